// The first paper's cooperative model (Erhart & Hirche 2016; docs/model.md, docs/dynamics.md):
// RigidObject, ImpedanceEndEffector, Arm, Model / Data with N chosen at run time, Setpoints,
// Disturbances, interaction_dynamics, check_inputs and the energies (the Simulator: simulator.cpp).
#include "common.hpp"

#include <coopdyn/core.hpp>

#include <vector>

namespace coopdyn::python {

namespace {

using ModelX = ImpedanceModelX;
using DataX = Data<ModelX>;
using EndEffector = ImpedanceEndEffector<double>;
using ArmX = Arm<EndEffector>;
using Object = RigidObject<double>;
using SetpointsX = Setpoints<double, Dynamic>;
using DisturbancesX = Disturbances<double, Dynamic>;
using State = RigidBodyState<double>;

void bind_parts(py::module_& module)
{
    py::class_<Object> object(module, "RigidObject",
                              "The held object (8)-(9): mass m_o > 0 [kg] and inertia_body J_o (3, 3) about its centre "
                              "of mass in its body frame, symmetric positive semi-definite (docs/model.md).");
    object
        .def(py::init([](double mass, py::object inertia_body) {
                 Object result;
                 result.mass = mass;
                 if (!inertia_body.is_none()) {
                     result.inertia_body = to_matrix(inertia_body, "RigidObject", "inertia_body", 3, 3, "(3, 3)");
                 }
                 return result;
             }),
             py::arg("mass") = 0.0, py::arg("inertia_body") = py::none())
        .def_readwrite("mass", &Object::mass, "m_o [kg]")
        .def("validate", &Object::validate, "raises InvalidModel naming the parameter");
    def_array(object, "RigidObject", "inertia_body", &Object::inertia_body, "(3, 3)", "J_o (3, 3), body frame [kg m^2]");

    py::class_<EndEffector> end_effector(module, "ImpedanceEndEffector",
                                         "An impedance-controlled end-effector (1): mass m_i, rotational_inertia J_i "
                                         "(3, 3) in {w}, translational/rotational damping d_i, delta_i and stiffness "
                                         "k_i, kappa_i (docs/model.md).");
    end_effector
        .def(py::init([](double mass, py::object rotational_inertia, double translational_damping,
                         double rotational_damping, double translational_stiffness, double rotational_stiffness) {
                 EndEffector result;
                 result.mass = mass;
                 if (!rotational_inertia.is_none()) {
                     result.rotational_inertia =
                         to_matrix(rotational_inertia, "ImpedanceEndEffector", "rotational_inertia", 3, 3, "(3, 3)");
                 }
                 result.translational_damping = translational_damping;
                 result.rotational_damping = rotational_damping;
                 result.translational_stiffness = translational_stiffness;
                 result.rotational_stiffness = rotational_stiffness;
                 return result;
             }),
             py::arg("mass") = 0.0, py::arg("rotational_inertia") = py::none(), py::arg("translational_damping") = 0.0,
             py::arg("rotational_damping") = 0.0, py::arg("translational_stiffness") = 0.0,
             py::arg("rotational_stiffness") = 0.0)
        .def_readwrite("mass", &EndEffector::mass, "m_i [kg]")
        .def_readwrite("translational_damping", &EndEffector::translational_damping, "d_i [N s/m]")
        .def_readwrite("rotational_damping", &EndEffector::rotational_damping, "delta_i [N m s/rad]")
        .def_readwrite("translational_stiffness", &EndEffector::translational_stiffness, "k_i [N/m]")
        .def_readwrite("rotational_stiffness", &EndEffector::rotational_stiffness, "kappa_i [N m/rad]")
        .def(
            "validate", [](const EndEffector& self, Index arm) { self.validate(arm); }, py::arg("arm") = 0,
            "raises InvalidModel naming the parameter and the arm");
    def_array(end_effector, "ImpedanceEndEffector", "rotational_inertia", &EndEffector::rotational_inertia, "(3, 3)",
              "J_i (3, 3) in {w}, SPD [kg m^2]");

    py::class_<ArmX>(module, "Arm",
                     "One arm: its end_effector (ImpedanceEndEffector) and grasp_body, the Pose of the end-effector "
                     "in the object's body frame (the rigid grasp (10)-(12)).")
        .def(py::init([](const EndEffector& ee, const Pose<double>& grasp) { return ArmX{ee, grasp}; }),
             py::arg("end_effector") = EndEffector(), py::arg("grasp_body") = Pose<double>())
        .def_readwrite("end_effector", &ArmX::end_effector)
        .def_readwrite("grasp_body", &ArmX::grasp_body);

    py::class_<SetpointsX> setpoints(module, "Setpoints",
                                     "Per-arm setpoints of (1): poses p_i^d (positions (3, N), orientations (4, N) as "
                                     "[x, y, z, w] columns), twists, accelerations and desired wrenches h_i^d (6N,), "
                                     "the wrench ON arm i.");
    setpoints.def(py::init<Index>(), py::arg("arms"))
        .def_property_readonly("arms", &SetpointsX::arms)
        .def("pose", &SetpointsX::pose, py::arg("arm"))
        .def("set_pose", [](SetpointsX& self, Index arm, const Pose<double>& pose) {
            if (arm < 0 || arm >= self.arms()) {
                fail_argument("Setpoints.set_pose", "arm", "must be in [0, " + std::to_string(self.arms()) + ")");
            }
            self.set_pose(arm, pose);
        }, py::arg("arm"), py::arg("pose"));
    def_array(setpoints, "Setpoints", "positions", &SetpointsX::positions, "(3, N)", "p_i^d, (3, N)");
    def_array(setpoints, "Setpoints", "orientations", &SetpointsX::orientations, "(4, N)", "q_i^d as [x, y, z, w], (4, N)");
    def_array(setpoints, "Setpoints", "twists", &SetpointsX::twists, "(6N,)", "xdot_i^d stacked (6N,)");
    def_array(setpoints, "Setpoints", "accelerations", &SetpointsX::accelerations, "(6N,)", "xdd_i^d stacked (6N,)");
    def_array(setpoints, "Setpoints", "wrenches", &SetpointsX::wrenches, "(6N,)", "h_i^d stacked (6N,), ON arm i");

    py::class_<DisturbancesX> disturbances(module, "Disturbances",
                                           "Disturbance wrenches: object (6,) on the object (8), end_effectors (6N,) "
                                           "on each end-effector (1).");
    disturbances.def(py::init<Index>(), py::arg("arms")).def_property_readonly("arms", &DisturbancesX::arms);
    def_array(disturbances, "Disturbances", "object", &DisturbancesX::object, "(6,)", "htilde_o (6,)");
    def_array(disturbances, "Disturbances", "end_effectors", &DisturbancesX::end_effectors, "(6N,)", "htilde_i stacked (6N,)");
}

void bind_input_check(py::module_& module)
{
    py::enum_<InputProblem> problem(module, "InputProblem", "What check_inputs found (docs/conventions.md, \"Errors\").");
    problem.value("none", InputProblem::none)
        .value("state_position", InputProblem::state_position)
        .value("state_orientation", InputProblem::state_orientation)
        .value("state_twist", InputProblem::state_twist)
        .value("setpoint_position", InputProblem::setpoint_position)
        .value("setpoint_orientation", InputProblem::setpoint_orientation)
        .value("setpoint_twist", InputProblem::setpoint_twist)
        .value("setpoint_acceleration", InputProblem::setpoint_acceleration)
        .value("setpoint_wrench", InputProblem::setpoint_wrench)
        .value("object_disturbance", InputProblem::object_disturbance)
        .value("arm_disturbance", InputProblem::arm_disturbance)
        .value("object_wrench", InputProblem::object_wrench);
    py::class_<InputCheck>(module, "InputCheck", "The first bad input (problem) and its arm (None for the object's).")
        .def_readonly("problem", &InputCheck::problem)
        .def_property_readonly("arm", [](const InputCheck& self) {
            return self.arm == no_arm ? py::object(py::none()) : py::object(py::int_(self.arm));
        })
        .def("ok", &InputCheck::ok)
        .def("__bool__", &InputCheck::ok)
        .def("input", &InputCheck::input, "the input's name");

}

template <typename Kind>
void bind_model_kind(py::module_& module, const char* model_name, const char* data_name, const char* model_doc)
{
    using KindData = Data<Kind>;
    using KindArm = Arm<typename Kind::EndEffectorModel>;
    py::class_<Kind>(module, model_name, model_doc)
        .def(py::init([model_name](const Object& object, const py::sequence& arm_list, py::object gravity) {
                 std::vector<KindArm> arms;
                 for (const py::handle arm : arm_list) {
                     arms.push_back(arm.cast<KindArm>());
                 }
                 const Vector3<double> g = gravity.is_none() ? standard_gravity<double>()
                                                             : Vector3<double>(to_vector(gravity, model_name, "gravity", 3, "(3,)"));
                 return Kind(object, arms, g);
             }),
             py::arg("object"), py::arg("arms"), py::arg("gravity") = py::none())
        .def_property_readonly("arms", &Kind::arms, "N")
        .def_property_readonly("object", &Kind::object, py::return_value_policy::copy,
                               "a copy: a model is constant once validated (set_end_effector changes an arm)")
        .def_property_readonly("gravity", [](const Kind& self) { return vector_copy(self.gravity(), true); })
        .def("end_effector", [](const Kind& self, Index arm) {
            if (arm < 0 || arm >= self.arms()) {
                fail_argument("end_effector", "arm", "must be in [0, " + std::to_string(self.arms()) + ")");
            }
            return self.end_effector(arm);
        }, py::arg("arm"))
        .def("set_end_effector", &Kind::set_end_effector, py::arg("arm"), py::arg("end_effector"),
             "replaces arm's end-effector (gain scheduling), validated; raises InvalidModel")
        .def_property_readonly("grasp_offsets_body",
                               [](const Kind& self) { return matrix_copy(self.grasp_offsets_body(), true); }, "(3, N)")
        .def_property_readonly("end_effector_inertias",
                               [](const Kind& self) { return matrix_copy(self.end_effector_inertias(), true); },
                               "the M_i side by side, (6, 6N)");

    py::class_<KindData> data(module, data_name,
                           "Buffers and results of interaction_dynamics for one Model (docs/dynamics.md). Array "
                           "fields are read-only copies made when read.");
    data.def(py::init<const Kind&>(), py::arg("model"))
        .def_property_readonly("arms", &KindData::arms)
        .def_property_readonly(
            "object_state", [](const KindData& self) { return self.object_state; }, "a copy of the state last used");
    def_output(data, "object_rotation", &KindData::object_rotation, "R(q_o) (3, 3)");
    def_output(data, "object_rotational_inertia", &KindData::object_rotational_inertia, "J_o in {w} (3, 3), (9)");
    def_output(data, "grasp_offsets", &KindData::grasp_offsets, "r_i in {w} (3, N)");
    def_output(data, "end_effector_positions", &KindData::end_effector_positions, "p_i (3, N)");
    def_output(data, "end_effector_orientations", &KindData::end_effector_orientations, "q_i [x, y, z, w] (4, N)");
    def_output(data, "end_effector_twists", &KindData::end_effector_twists, "xdot_i stacked (6N,)");
    def_output(data, "motion_wrenches", &KindData::motion_wrenches, "h_i^x of (6) stacked (6N,)");
    def_output(data, "h_sigma", &KindData::h_sigma, "[hSigma_o; hSigma_1; ...] (6(N+1),), (15)-(16)");
    def_output(data, "accelerations", &KindData::accelerations, "[xdd_o; xdd_1; ...] (6(N+1),)");
    def_output(data, "wrenches", &KindData::wrenches, "[h_o; h_1; ...] (6(N+1),), the wrench ON each body, (18)");
    data.def("object_acceleration", [](const KindData& self) { return vector_copy(self.object_acceleration()); })
        .def("object_wrench", [](const KindData& self) { return vector_copy(self.object_wrench()); },
             "h_o = -G h' (23), (6,)");
    data.def(
        "wrench_on_object_at_centre",
        [](const KindData& self, Index arm) {
            if (arm < 0 || arm >= self.arms()) {
                fail_argument("Data.wrench_on_object_at_centre", "arm", "out of range");
            }
            return vector_copy(self.wrench_on_object_at_centre(arm));
        },
        py::arg("arm"), "G_i (-h_i) (24): arm i's wrench on the object about its centre of mass (6,)");

    module.def(
        "check_inputs",
        [](const Kind& model, const State& state, const SetpointsX& setpoints, const DisturbancesX& disturbances) {
            require_arms(setpoints.arms(), model.arms(), "check_inputs", "setpoints");
            require_arms(disturbances.arms(), model.arms(), "check_inputs", "disturbances");
            return check_inputs(model, state, setpoints, disturbances);
        },
        py::arg("model"), py::arg("state"), py::arg("setpoints"), py::arg("disturbances"),
        "check_inputs(model, state, setpoints, disturbances) -> InputCheck: the first non-finite value or non-unit "
        "quaternion of a tick's inputs (cheap; docs/conventions.md, \"Errors\").");
    module.def(
        "interaction_dynamics",
        [](const Kind& model, KindData& data_, const State& state, const SetpointsX& setpoints,
           const DisturbancesX& disturbances) {
            require_arms(data_.arms(), model.arms(), "interaction_dynamics", "data");
            require_arms(setpoints.arms(), model.arms(), "interaction_dynamics", "setpoints");
            require_arms(disturbances.arms(), model.arms(), "interaction_dynamics", "disturbances");
            {
                py::gil_scoped_release unlocked;
                interaction_dynamics(model, data_, state, setpoints, disturbances);
            }
            return vector_copy(data_.wrenches);
        },
        py::arg("model"), py::arg("data"), py::arg("state"), py::arg("setpoints"), py::arg("disturbances"),
        R"doc(interaction_dynamics(model, data, state, setpoints, disturbances) -> wrenches (6(N+1),)

One evaluation of the cooperative dynamics (docs/dynamics.md): the grasp kinematics (10)-(12),
the motion wrenches (6), hSigma of (15)-(16) with gravity (errata E1), then the interaction
wrenches (18) in their structured O(N) form. Fills `data` and returns a copy of data.wrenches =
[h_o; h_1; ...; h_N]. Inputs are not checked (use check_inputs): a NaN gives NaN. Releases the GIL.)doc");

    module.def("kinetic_energy", [](const Kind& model, const KindData& data_) {
        require_arms(data_.arms(), model.arms(), "kinetic_energy", "data");
        return kinetic_energy(model, data_);
    }, py::arg("model"), py::arg("data"), "kinetic energy of the object and the end-effectors at data's state (7)");
    module.def("gravity_potential_energy", [](const Kind& model, const KindData& data_) {
        require_arms(data_.arms(), model.arms(), "gravity_potential_energy", "data");
        return gravity_potential_energy(model, data_);
    }, py::arg("model"), py::arg("data"), "gravitational potential energy (7), errata E7");
}

void bind_resolved_acceleration(py::module_& module)
{
    using Resolved = ResolvedAccelerationEndEffector<double>;
    using ResolvedArm = Arm<Resolved>;
    py::class_<Resolved> end_effector(module, "ResolvedAccelerationEndEffector",
                                      "An end-effector under resolved-acceleration control with PD tracking (20)-(21): "
                                      "apparent_inertia Lambda_i (6, 6) SPD in {w}, derivative_gain K_D,i and "
                                      "proportional_gain K_P,i (6, 6) (docs/model.md).");
    end_effector.def(py::init<>())
        .def(
            "validate", [](const Resolved& self, Index arm) { self.validate(arm); }, py::arg("arm") = 0,
            "raises InvalidModel naming the parameter and the arm");
    def_array(end_effector, "ResolvedAccelerationEndEffector", "apparent_inertia", &Resolved::apparent_inertia, "(6, 6)",
              "Lambda_i (6, 6), SPD");
    def_array(end_effector, "ResolvedAccelerationEndEffector", "derivative_gain", &Resolved::derivative_gain, "(6, 6)",
              "K_D,i (6, 6) [1/s]");
    def_array(end_effector, "ResolvedAccelerationEndEffector", "proportional_gain", &Resolved::proportional_gain,
              "(6, 6)", "K_P,i (6, 6) [1/s^2]");
    py::class_<ResolvedArm>(module, "ResolvedAccelerationArm",
                            "One arm of a ResolvedAccelerationModel: end_effector and grasp_body (as Arm).")
        .def(py::init([](const Resolved& ee, const Pose<double>& grasp) { return ResolvedArm{ee, grasp}; }),
             py::arg("end_effector") = Resolved(), py::arg("grasp_body") = Pose<double>())
        .def_readwrite("end_effector", &ResolvedArm::end_effector)
        .def_readwrite("grasp_body", &ResolvedArm::grasp_body);
    bind_model_kind<Model<double, Dynamic, ResolvedAccelerationEndEffector>>(
        module, "ResolvedAccelerationModel", "ResolvedAccelerationData",
        "The cooperative system with resolved-acceleration end-effectors (20)-(21) (C++ Model<double, Dynamic, "
        "ResolvedAccelerationEndEffector>): a RigidObject, N >= 1 ResolvedAccelerationArms, gravity (3,). The "
        "interaction solver takes its general (dense inertia) path.");
}

void bind_impedance_energy(py::module_& module)
{
    module.def("spring_potential_energy", [](const ModelX& model, const DataX& data_, const SetpointsX& setpoints) {
        require_arms(data_.arms(), model.arms(), "spring_potential_energy", "data");
        require_arms(setpoints.arms(), model.arms(), "spring_potential_energy", "setpoints");
        return spring_potential_energy(model, data_, setpoints);
    }, py::arg("model"), py::arg("data"), py::arg("setpoints"), "the end-effectors' spring energy (39)");
}

}  // namespace

void bind_spatial_model(py::module_& module)
{
    bind_parts(module);
    bind_input_check(module);
    bind_model_kind<ModelX>(module, "Model", "Data",
                            "The cooperative system's constant part (docs/model.md): a RigidObject, N >= 1 Arms of "
                            "ImpedanceEndEffector, gravity (3,). Validated at construction: raises InvalidModel naming "
                            "the parameter and the arm.");
    bind_impedance_energy(module);
    bind_resolved_acceleration(module);
}

}  // namespace coopdyn::python
