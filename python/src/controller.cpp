// The second paper's controller (Lin et al.; docs/control.md): its parameters (with the fault
// options), ControllerModel, ControllerData, ControllerInput and controller_tick. Its kernels (the
// projected dynamics, the grasp Jacobians, the internal-wrench basis, the friction margin) are in
// control_kernels.cpp. Sizes K (contacts), Q (joints) and the pyramids' edges are chosen at run time
// (Eigen::Dynamic). The spatial types Pose and
// RigidBodyState are bound here too (the controller's inputs are the first to need them).
#include "common.hpp"

#include <coopdyn/control.hpp>

#include <string>
#include <vector>

namespace coopdyn::python {

namespace {

constexpr int X = Eigen::Dynamic;
using Friction = ContactFriction<double>;
using Contact = ContactPoint<double>;
using Parameters = ControllerParameters<double>;
using Objective = SqueezeObjective<double>;
using QpOptions = ContactQpOptions<double>;
using Faults = FaultOptions<double>;
using ModelX = ControllerModel<double, X, X, X>;
using DataX = ControllerData<double, X, X, X>;
using InputX = ControllerInput<double, X, X>;
using Projection = ProjectedDynamics<double, X, X>;
using PoseX = Pose<double>;
using State = RigidBodyState<double>;

void bind_spatial(py::module_& module)
{
    py::class_<PoseX> pose(module, "Pose",
                           "A pose: position (3,) and orientation, a unit quaternion given as [x, y, z, w] (Eigen's "
                           "coeffs() order, scipy's from_quat order; docs/conventions.md, \"Quaternions\").");
    pose.def(py::init([](py::object position, py::object orientation) {
                 PoseX result;
                 if (!position.is_none()) {
                     result.position = to_vector(position, "Pose", "position", 3, "(3,)");
                 }
                 if (!orientation.is_none()) {
                     result.orientation = quaternion_from(orientation, "Pose", "orientation");
                 }
                 return result;
             }),
             py::arg("position") = py::none(), py::arg("orientation") = py::none(),
             "Pose(position=[0, 0, 0], orientation=[0, 0, 0, 1])");
    def_array(pose, "Pose", "position", &PoseX::position, "(3,)", "position (3,)");
    pose.def_property(
        "orientation", [](const PoseX& self) { return quaternion_array(self.orientation, true); },
        [](PoseX& self, ArrayLike value) { self.orientation = quaternion_from(value, "Pose", "orientation"); },
        "unit quaternion [x, y, z, w] (not normalised here: the models refuse a non-unit one)");
    pose.def("rotation", [](const PoseX& self) { return matrix_copy(self.orientation.toRotationMatrix()); },
             "the rotation matrix (3, 3) of the orientation");

    py::class_<State> state(module, "RigidBodyState", "Pose and twist [v; w] (6,) of a body's centre, in {w}.");
    state.def(py::init<>())
        .def_readwrite("pose", &State::pose, "Pose (a reference into this state: writes go through)");
    def_array(state, "RigidBodyState", "twist", &State::twist, "(6,)", "twist [v; w] (6,), {w}");
}

void bind_parameters(py::module_& module)
{
    py::class_<Friction>(module, "ContactFriction",
                         "Friction parameters of one flat contact, Lin et al. L(17)-(19) with errata E9 "
                         "(docs/control.md): |f_t| <= mu f_z in an n-edge pyramid, |t_z| <= gamma f_z, the centre "
                         "of pressure in the patch, f_z >= f_min.")
        .def(py::init<>())
        .def_readwrite("friction_coefficient", &Friction::friction_coefficient, "mu > 0 (Coulomb)")
        .def_readwrite("torsional_coefficient", &Friction::torsional_coefficient, "gamma >= 0 [m]")
        .def_readwrite("patch_half_length_x", &Friction::patch_half_length_x, "delta_x > 0 [m]")
        .def_readwrite("patch_half_length_y", &Friction::patch_half_length_y, "delta_y > 0 [m]")
        .def_readwrite("minimum_normal_force", &Friction::minimum_normal_force, "f_min >= 0 [N]")
        .def_readwrite("pyramid_edges", &Friction::pyramid_edges, "n, 3..64")
        .def(
            "validate", [](const Friction& self, Index contact) { self.validate(contact); }, py::arg("contact") = 0,
            "raises InvalidModel naming the parameter (and the contact as .arm)");

    py::class_<Contact>(module, "ContactPoint",
                        "One contact of a hand on the object: frame (Pose of the contact frame {c_i} in the object's "
                        "body frame, z the inward normal) and friction (ContactFriction).")
        .def(py::init<>())
        .def_readwrite("frame", &Contact::frame, "Pose in the object's frame (a reference: writes go through)")
        .def_readwrite("friction", &Contact::friction, "ContactFriction (a reference: writes go through)");

    py::class_<Objective>(module, "SqueezeObjective",
                          "What the contact QP minimises (docs/control.md, \"The least squeeze\"; errata E13): "
                          "internal_weight |B^T w(z)|^2 + moment_weight sum |t_i|^2 + torque_weight |J^T B z|^2 "
                          "(L(20)) + squeeze_weight |B z|^2.")
        .def(py::init<>())
        .def_readwrite("internal_weight", &Objective::internal_weight)
        .def_readwrite("moment_weight", &Objective::moment_weight)
        .def_readwrite("torque_weight", &Objective::torque_weight)
        .def_readwrite("squeeze_weight", &Objective::squeeze_weight)
        .def_static("least_squeeze", &Objective::least_squeeze, "the default: the least internal wrench (E13)")
        .def_static("least_torque_centred", &Objective::least_torque_centred, "L(20) plus the centring moment term")
        .def_static("paper", &Objective::paper, "the paper's L(20) alone, tau_c^T tau_c (with a 1e-6 ridge)");

    py::class_<QpOptions>(module, "ContactQpOptions",
                          "Options of the contact QP (docs/control.md, \"When friction cannot hold the load\").")
        .def(py::init<>())
        .def_readwrite("warm_start", &QpOptions::warm_start)
        .def_readwrite("iteration_limit", &QpOptions::iteration_limit, "0: the solver's default")
        .def_readwrite("fallback_weight", &QpOptions::fallback_weight, "> 0");

    py::class_<Faults>(module, "FaultOptions",
                       "What the controller does when an input fails or the grasp slips (docs/control.md, "
                       "\"Faults: dropout, safe hold, slip, torque limits\"). Times in s, distances in m, angles in rad.")
        .def(py::init<>())
        .def_readwrite("tick_period", &Faults::tick_period, "the tick's period (s) > 0: how far a prediction is propagated")
        .def_readwrite("prediction_limit", &Faults::prediction_limit,
                       "how long (s) >= 0 the object's state may be predicted (degraded) before the safe hold")
        .def_readwrite("slip_distance_threshold", &Faults::slip_distance_threshold, "m > 0: a contact slips beyond it")
        .def_readwrite("slip_angle_threshold", &Faults::slip_angle_threshold, "rad > 0: or beyond this angle")
        .def_readwrite("slip_squeeze_factor", &Faults::slip_squeeze_factor,
                       ">= 1: f_min is multiplied by it while a contact slips (1: off)");

    py::class_<Parameters> parameters(module, "ControllerParameters",
                                      "Everything a ControllerModel is built from (plain data, validated by "
                                      "ControllerModel; docs/control.md, \"The controller\").");
    parameters.def(py::init<>())
        .def_readwrite("joints", &Parameters::joints, "Q, all joints of all arms")
        .def_property(
            "contacts",
            [](const Parameters& self) {
                py::list contacts;
                for (const Contact& contact : self.contacts) {
                    contacts.append(contact);
                }
                return contacts;
            },
            [](Parameters& self, const py::sequence& contacts) {
                std::vector<Contact> values;
                for (const py::handle contact : contacts) {
                    values.push_back(contact.cast<Contact>());
                }
                self.contacts = values;
            },
            "list of ContactPoint, K >= 2, in the order of J's row blocks (a copy: assign the whole list)")
        .def_readwrite("objective", &Parameters::objective, "SqueezeObjective")
        .def_readwrite("qp", &Parameters::qp, "ContactQpOptions")
        .def_readwrite("faults", &Parameters::faults, "FaultOptions")
        .def_readwrite("check_contact_normals", &Parameters::check_contact_normals,
                       "refuse a contact frame whose z does not face into the object, z . r >= 0 (default True)")
        .def_property(
            "joint_names",
            [](const Parameters& self) {
                py::list names;
                for (const std::string& name : self.joint_names) {
                    names.append(name);
                }
                return names;
            },
            [](Parameters& self, const py::sequence& names) {
                std::vector<std::string> values;
                for (const py::handle name : names) {
                    values.push_back(name.cast<std::string>());
                }
                self.joint_names = values;
            },
            "optional list of the Q joints' names, used only to name a joint in errors (a copy: assign the whole list)");
    def_array(parameters, "ControllerParameters", "stiffness", &Parameters::stiffness, "(6, 6)",
              "K_d (6, 6), symmetric >= 0 [N/m, N m/rad], L(16)");
    def_array(parameters, "ControllerParameters", "damping", &Parameters::damping, "(6, 6)",
              "D_d (6, 6), symmetric >= 0, L(16)");
    def_array(parameters, "ControllerParameters", "posture_stiffness", &Parameters::posture_stiffness, "(Q,)",
              "K_n (Q,) >= 0, the posture gains (E12)", true);
    def_array(parameters, "ControllerParameters", "posture_damping", &Parameters::posture_damping, "(Q,)",
              "D_n (Q,) >= 0 (E12)", true);
    def_array(parameters, "ControllerParameters", "torque_limits", &Parameters::torque_limits, "(Q,) or (0,)",
              "|tau_j| <= limit_j (Q,) > 0 applied after the QP, saturation reported; empty: none", true);
    def_array(parameters, "ControllerParameters", "torque_rate_limits", &Parameters::torque_rate_limits,
              "(Q,) or (0,)", "|tau_j - tau_j,previous| <= limit_j (Q,) > 0 per tick; empty: none", true);
}

void check_sizes(const ModelX& model, const DataX& data, const InputX& input)
{
    const Index arms = model.arms();
    const Index joints = model.joints();
    if (data.arms() != arms || data.joints() != joints) {
        fail_argument("controller_tick", "data",
                      "was made for another model (K = " + std::to_string(data.arms()) + ", Q = " +
                          std::to_string(data.joints()) + "; the model has K = " + std::to_string(arms) +
                          ", Q = " + std::to_string(joints) + ")");
    }
    if (input.jacobian.rows() != 6 * arms || input.inertia.rows() != joints) {
        fail_argument("controller_tick", "input",
                      "was made for another model (K = " + std::to_string(input.jacobian.rows() / 6) + ", Q = " +
                          std::to_string(input.inertia.rows()) + ")");
    }
}

/// A read-only numpy bool array copying an Eigen bool array (slipping, saturated_joints).
template <typename Derived> py::array bool_copy(const Eigen::ArrayBase<Derived>& flags)
{
    py::array_t<bool> result(flags.size());
    auto view = result.mutable_unchecked<1>();
    for (Index i = 0; i < flags.size(); ++i) {
        view(i) = flags(i);
    }
    result.attr("flags").attr("writeable") = false;
    return std::move(result);
}

void bind_controller_types(py::module_& module)
{
    py::enum_<ControlStatus>(module, "ControlStatus", "Outcome of a controller tick (docs/control.md).")
        .value("ok", ControlStatus::ok)
        .value("friction_infeasible", ControlStatus::friction_infeasible)
        .value("qp_failed", ControlStatus::qp_failed)
        .value("singular", ControlStatus::singular)
        .value("invalid_input", ControlStatus::invalid_input)
        .value("degraded", ControlStatus::degraded, "the object's measurement was replaced by a prediction")
        .value("safe_hold", ControlStatus::safe_hold, "h + J^T w of the last computed tick (docs/control.md)")
        .value("torque_saturated", ControlStatus::torque_saturated,
               "the torque limits clipped the torque: the contact wrenches are not the ones computed")
        .value("slipping", ControlStatus::slipping, "a contact slips (data.slipping)");
    py::enum_<ReplacedInput>(module, "ReplacedInput", "What replaced the object's measurement (ControllerData.replaced_input).")
        .value("none", ReplacedInput::none)
        .value("object_acceleration", ReplacedInput::object_acceleration)
        .value("object_state_from_contacts", ReplacedInput::object_state_from_contacts)
        .value("object_state_from_twist", ReplacedInput::object_state_from_twist);
    py::enum_<ControllerInputProblem> problem(module, "ControllerInputProblem",
                                              "The input a tick refused (ControllerData.input_problem).");
    for (int k = 0; k <= static_cast<int>(ControllerInputProblem::object_stale); ++k) {
        const auto value = static_cast<ControllerInputProblem>(k);
        // the enumerators' C++ names (to_string gives the input's name and the problem)
        static const char* const names[] = {
            "none", "inertia_not_finite", "bias_not_finite", "jacobian_not_finite", "jacobian_rate_qdot_not_finite",
            "positions_not_finite", "velocities_not_finite", "object_position_not_finite", "object_orientation_not_unit",
            "object_twist_not_finite", "object_acceleration_not_finite", "desired_position_not_finite",
            "desired_orientation_not_unit", "desired_twist_not_finite", "desired_acceleration_not_finite",
            "posture_not_finite", "inertia_not_positive_definite", "object_stale"};
        static_assert(sizeof(names) / sizeof(names[0]) == static_cast<std::size_t>(ControllerInputProblem::object_stale) + 1,
                      "one name per enumerator");
        problem.value(names[k], value, to_string(value));
    }

    py::class_<ModelX> model(module, "ControllerModel",
                             "The controller's constant part (Lin et al.; docs/control.md), built from "
                             "ControllerParameters, which it validates: raises InvalidModel naming the parameter "
                             "and the contact (.arm). K, Q and the pyramids' edges are taken from the parameters.");
    model.def(py::init<const Parameters&>(), py::arg("parameters"))
        .def_property_readonly("arms", &ModelX::arms, "K")
        .def_property_readonly("joints", &ModelX::joints, "Q")
        .def_property_readonly("rows", &ModelX::rows, "rows of the contact QP, sum_i (n_i + 7)")
        .def_property_readonly("contacts",
                               [](const ModelX& self) {
                                   py::list contacts;
                                   for (const Contact& contact : self.contacts()) {
                                       contacts.append(contact);
                                   }
                                   return contacts;
                               })
        .def_property_readonly("objective", &ModelX::objective, py::return_value_policy::copy,
                               "a copy: a model is constant once validated")
        .def_property_readonly("qp_options", &ModelX::qp_options, py::return_value_policy::copy, "a copy")
        .def_property_readonly("faults", &ModelX::faults, py::return_value_policy::copy, "a copy")
        .def_property_readonly("has_torque_limits", &ModelX::has_torque_limits)
        .def_property_readonly("has_torque_rate_limits", &ModelX::has_torque_rate_limits)
        .def_property_readonly("torque_limits", [](const ModelX& self) { return vector_copy(self.torque_limits(), true); },
                               "(Q,), zero when none")
        .def_property_readonly("torque_rate_limits",
                               [](const ModelX& self) { return vector_copy(self.torque_rate_limits(), true); },
                               "(Q,), zero when none")
        .def_property_readonly("stiffness", [](const ModelX& self) { return matrix_copy(self.stiffness(), true); })
        .def_property_readonly("damping", [](const ModelX& self) { return matrix_copy(self.damping(), true); })
        .def_property_readonly("posture_stiffness",
                               [](const ModelX& self) { return vector_copy(self.posture_stiffness(), true); })
        .def_property_readonly("posture_damping",
                               [](const ModelX& self) { return vector_copy(self.posture_damping(), true); })
        .def_property_readonly("contact_frame_rows",
                               [](const ModelX& self) { return matrix_copy(self.contact_frame_rows(), true); })
        .def_property_readonly("contact_frame_bounds",
                               [](const ModelX& self) { return vector_copy(self.contact_frame_bounds(), true); })
        .def_property_readonly("body_internal_basis",
                               [](const ModelX& self) { return matrix_copy(self.body_internal_basis(), true); })
        .def_property_readonly("contact_qp_constraints",
                               [](const ModelX& self) { return matrix_copy(self.contact_qp_constraints(), true); });

    py::class_<InputX> input(module, "ControllerInput",
                             "What the robot model and the state estimate give the controller each tick "
                             "(docs/control.md, \"Inputs and sign conventions\"), sized by the model. Assign whole "
                             "arrays (the getters return read-only copies); shapes are checked.");
    input.def(py::init([](const ModelX& m) { return InputX(m); }), py::arg("model"))
        .def_readwrite("object", &InputX::object, "RigidBodyState of the object's centre, {w} (a reference)")
        .def_readwrite("desired_pose", &InputX::desired_pose, "Pose x_d (a reference)");
    def_array(input, "ControllerInput", "inertia", &InputX::inertia, "(Q, Q)", "M(q) (Q, Q), SPD");
    def_array(input, "ControllerInput", "bias", &InputX::bias, "(Q,)", "h(q, qdot) (Q,): Coriolis, centrifugal, gravity");
    def_array(input, "ControllerInput", "jacobian", &InputX::jacobian, "(6K, Q)",
              "J (6K, Q): the contact points' twists [v; w] in {w}");
    def_array(input, "ControllerInput", "jacobian_rate_qdot", &InputX::jacobian_rate_qdot, "(6K,)", "Jdot qdot (6K,)");
    def_array(input, "ControllerInput", "positions", &InputX::positions, "(Q,)", "q (Q,)");
    def_array(input, "ControllerInput", "velocities", &InputX::velocities, "(Q,)", "qdot (Q,)");
    def_array(input, "ControllerInput", "object_acceleration", &InputX::object_acceleration, "(6,)",
              "measured [a; alpha] of the object's centre (6,), {w}, for the estimate L(7)");
    def_array(input, "ControllerInput", "desired_twist", &InputX::desired_twist, "(6,)", "xdot_d (6,)");
    def_array(input, "ControllerInput", "desired_acceleration", &InputX::desired_acceleration, "(6,)", "xdd_d (6,)");
    def_array(input, "ControllerInput", "posture", &InputX::posture, "(Q,)", "q_n (Q,), the posture (E12)");
    input.def_readwrite("object_stale", &InputX::object_stale,
                        "the caller's flag that object and object_acceleration are an old measurement")
        .def_readwrite("contact_poses_filled", &InputX::contact_poses_filled,
                       "contact_positions / contact_orientations hold this tick's contact frames");
    def_array(input, "ControllerInput", "contact_positions", &InputX::contact_positions, "(3, K)",
              "column i: contact frame i's origin in {w} (m)");
    def_array(input, "ControllerInput", "contact_orientations", &InputX::contact_orientations, "(4, K)",
              "column i: contact frame i's orientation in {w}, unit quaternion (x, y, z, w)");

    // The enumerations are returned as copies: pybind11's def_readonly would hand out a reference
    // into the data, which the next tick overwrites (a list of statuses would read the last one).
    py::class_<DataX> data(module, "ControllerData",
                           "Everything a controller tick computes, sized once from the model. Every array field is a "
                           "read-only copy made when read (docs/python.md, \"Arrays\").");
    data.def(py::init([](const ModelX& m) { return DataX(m); }), py::arg("model"))
        .def_property_readonly("arms", &DataX::arms)
        .def_property_readonly("joints", &DataX::joints)
        .def_property_readonly("status", [](const DataX& self) { return self.status; }, "ControlStatus (a copy)")
        .def_property_readonly("input_problem", [](const DataX& self) { return self.input_problem; }, "ControllerInputProblem (a copy)")
        .def_readonly("tightest_force_margin", &DataX::tightest_force_margin, "N")
        .def_readonly("tightest_moment_margin", &DataX::tightest_moment_margin, "N m")
        .def_readonly("tightest_margin", &DataX::tightest_margin)
        .def_readonly("tightest_contact", &DataX::tightest_contact)
        .def_readonly("qp_ran", &DataX::qp_ran)
        .def_property_readonly("qp_status", [](const DataX& self) { return self.qp_status; }, "QpStatus (a copy)")
        .def_readonly("qp_iterations", &DataX::qp_iterations)
        .def_readonly("fallback_used", &DataX::fallback_used)
        .def_readonly("fallback_violation", &DataX::fallback_violation)
        .def_property_readonly(
            "dynamics", [](const DataX& self) -> const Projection& { return self.dynamics; },
            py::return_value_policy::reference_internal,
            "ProjectedDynamics of this tick (a view that keeps the data alive; its fields are copies)");
    def_output(data, "torque", &DataX::torque, "tau = tau_u + tau_c + tau_n (Q,)");
    def_output(data, "motion_torque", &DataX::motion_torque, "tau_u = P Jx^T F (Q,), L(16)");
    def_output(data, "squeeze_torque", &DataX::squeeze_torque, "tau_c = J^T B z* (Q,)");
    def_output(data, "posture_torque", &DataX::posture_torque, "tau_n (Q,), E12");
    def_output(data, "pose_error", &DataX::pose_error, "xtilde (6,)");
    def_output(data, "twist_error", &DataX::twist_error, "xtilde_dot (6,)");
    def_output(data, "motion_wrench", &DataX::motion_wrench, "F of L(16) (6,)");
    def_output(data, "external_wrench", &DataX::external_wrench, "F_x of L(7) (6,)");
    def_output(data, "contact_wrench_bias", &DataX::contact_wrench_bias, "w_0 (6K,), E11");
    def_output(data, "contact_wrenches", &DataX::contact_wrenches,
               "w = w_0 + B z* (6K,): hand i on the object about contact i, {w}");
    def_output(data, "contact_frame_wrenches", &DataX::contact_frame_wrenches,
               "(6, K): column i is contact i's wrench [f; t] in its contact frame (f_z the normal force)");
    def_output(data, "force_margins", &DataX::force_margins, "(K,) N");
    def_output(data, "moment_margins", &DataX::moment_margins, "(K,) N m");
    def_output(data, "friction_margins", &DataX::friction_margins, "(K,)");
    def_output(data, "squeeze", &DataX::squeeze, "z* (6K - 6,)");
    def_output(data, "joint_acceleration", &DataX::joint_acceleration, "qdd (Q,)");
    def_output(data, "contact_rotations", &DataX::contact_rotations, "[R_c1 ... R_cK] (3, 3K)");
    // Faults (docs/control.md, "Faults: dropout, safe hold, slip, torque limits").
    data.def_property_readonly("replaced_input", [](const DataX& self) { return self.replaced_input; }, "ReplacedInput (a copy)")
        .def_property_readonly("object", [](const DataX& self) { return self.object; },
                               "RigidBodyState the tick used (the measurement or the prediction; a copy)")
        .def_readonly("prediction_age", &DataX::prediction_age, "s since the last valid object measurement")
        .def_readonly("hold_ready", &DataX::hold_ready, "some tick computed the control (there is a grasp to hold)")
        .def_readonly("slip_measured", &DataX::slip_measured)
        .def_readonly("slipping_contacts", &DataX::slipping_contacts)
        .def_readonly("saturated_count", &DataX::saturated_count)
        .def_property_readonly("slipping", [](const DataX& self) { return bool_copy(self.slipping); }, "(K,) bool")
        .def_property_readonly("saturated_joints", [](const DataX& self) { return bool_copy(self.saturated_joints); },
                               "(Q,) bool");
    def_output(data, "object_acceleration", &DataX::object_acceleration, "[a; alpha] the tick used (6,)");
    def_output(data, "hold_torque", &DataX::hold_torque, "h + J^T w of the last computed tick (Q,): the safe hold's");
    def_output(data, "hold_wrenches", &DataX::hold_wrenches, "that tick's w (6K,)");
    def_output(data, "slip_displacement", &DataX::slip_displacement, "(3, K) m, {w}");
    def_output(data, "slip_distance", &DataX::slip_distance, "(K,) m");
    def_output(data, "slip_angle", &DataX::slip_angle, "(K,) rad");
    def_output(data, "requested_torque", &DataX::requested_torque, "the torque before the limits (Q,)");

    module.def(
        "controller_tick",
        [](const ModelX& model_, DataX& data_, const InputX& input_) {
            check_sizes(model_, data_, input_);
            {
                py::gil_scoped_release unlocked;
                controller_tick(model_, data_, input_);
            }
            return vector_copy(data_.torque);
        },
        py::arg("model"), py::arg("data"), py::arg("input"),
        R"doc(controller_tick(model, data, input) -> torques (Q,)

One tick of the projected inverse-dynamics controller of Lin et al. (docs/control.md):
tau = tau_u + tau_c + tau_n with the impedance law L(16), the external-wrench estimate L(7), the
contact-wrench bias L(23)-(24) (errata E11), the contact QP L(20)-(25) for the least squeeze
friction allows (errata E10, E13; a least-violating fallback when none exists) and the posture
torque (errata E12). Fills `data` (status, wrenches, margins, ...) and returns a copy of
data.torque. Check data.status: the torques are finite whatever it is. Releases the GIL while it
computes (do not use the same data from two threads at once).)doc");
}

}  // namespace

void bind_controller(py::module_& module)
{
    bind_spatial(module);
    bind_parameters(module);
    bind_control_kernels(module);  // control_kernels.cpp: their types (ContactFriction) are bound above
    bind_controller_types(module);
}

}  // namespace coopdyn::python
