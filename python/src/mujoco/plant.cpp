// What MujocoArms does to and measures of its MuJoCo world besides the arms' terms (docs/python.md,
// "The MuJoCo adapter"): a wrench applied to a body (set_applied_wrench: MuJoCo's xfrc_applied,
// coopdyn::mujoco_set_applied_wrench), each hand's contact wrench on a body (contact_wrenches:
// coopdyn::MujocoArms::read_contact_wrenches, recorded by arms.hpp's OwnedArms after each constraint
// solve), and the inverse kinematics of start postures (place_hands: MujocoArms::place_hands). The
// formulas are the C++ adapter's (include/coopdyn/adapters/mujoco.hpp, mujoco_forces.hpp); this file
// converts and checks the arguments.
#include "arms.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <string>
#include <vector>

namespace coopdyn::python::mujoco {
namespace {

using Numbers = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Wrenches = MujocoContactWrenches<>;
using Options = InverseKinematicsOptions;
using Result = InverseKinematicsResult;

/// `value` as `size` finite numbers (a 1-D array of any dtype numpy converts to float); else
/// coopdyn.InvalidArgument naming the function and the argument.
Eigen::VectorXd finite_vector(const py::handle& value, const char* function, const char* name, Index size)
{
    Numbers array = Numbers::ensure(value);
    if (!array || array.ndim() != 1 || array.shape(0) != size) {
        PyErr_Clear();
        throw InvalidArgument(function, name, no_arm,
                              "must be an array of shape (" + std::to_string(size) + ",), got " +
                                  py::repr(value).cast<std::string>().substr(0, 80));
    }
    const Eigen::VectorXd vector = Eigen::Map<const Eigen::VectorXd>(array.data(), size);
    if (!vector.allFinite()) {
        throw InvalidArgument(function, name, no_arm, "must be finite, got " + py::repr(value).cast<std::string>().substr(0, 80));
    }
    return vector;
}

/// The body called `name`, or coopdyn.InvalidArgument naming `parameter`.
int body_named(const OwnedArms& self, const std::string& name, const char* function, const char* parameter)
{
    const int body = mj_name2id(self.model(), mjOBJ_BODY, name.c_str());
    if (body < 0) {
        throw InvalidArgument(function, parameter, no_arm, "names no body of the model: '" + name + "'");
    }
    return body;
}

py::array copy_matrix(const Eigen::MatrixXd& m)
{
    py::array_t<double> out({m.rows(), m.cols()});
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(out.mutable_data(), m.rows(),
                                                                                        m.cols()) = m;
    return std::move(out);
}
template <typename Scalar> py::array copy_vector(const Eigen::Matrix<Scalar, Eigen::Dynamic, 1>& v)
{
    py::array_t<Scalar> out(v.size());
    std::copy(v.data(), v.data() + v.size(), out.mutable_data());
    return std::move(out);
}

void set_applied_wrench(OwnedArms& self, const std::string& name, const py::handle& wrench, const py::handle& point)
{
    const char* function = "MujocoArms.set_applied_wrench";
    const int body = body_named(self, name, function, "body");
    if (self.model()->body_weldid[body] == 0) {
        throw InvalidArgument(function, "body", no_arm,
                              "'" + name + "' is fixed to the world (no joint between them): a wrench on it moves nothing");
    }
    const Vector6<double> value = finite_vector(wrench, function, "wrench", 6);
    if (point.is_none()) {
        mujoco_set_applied_wrench(self.model(), self.data(), body, value);
    } else {
        const Eigen::Vector3d at = finite_vector(point, function, "point", 3);
        mujoco_set_applied_wrench(self.model(), self.data(), body, value, at);
    }
}

/// A target of place_hands: a coopdyn.Pose, or a (position (3,), orientation (4,) = [x, y, z, w])
/// pair made into one by coopdyn.Pose (which checks the shapes).
Pose<double> target_pose(const py::handle& item, std::size_t i)
{
    const std::string parameter = "targets[" + std::to_string(i) + "]";
    if (py::isinstance<Pose<double>>(item)) {
        return item.cast<Pose<double>>();
    }
    try {
        const py::sequence pair = item.cast<py::sequence>();
        if (pair.size() == 2) {
            const py::object pose = py::module_::import("coopdyn._coopdyn").attr("Pose")(pair[0], pair[1]);
            return pose.cast<Pose<double>>();
        }
    } catch (const py::error_already_set& error) {
        throw InvalidArgument("MujocoArms.place_hands", parameter, static_cast<Index>(i), error.what());
    } catch (const py::cast_error&) {
    }
    throw InvalidArgument("MujocoArms.place_hands", parameter, static_cast<Index>(i),
                          "must be a coopdyn.Pose or a pair (position (3,), orientation (4,) = [x, y, z, w]), got " +
                              py::repr(item).cast<std::string>().substr(0, 80));
}

Result place_hands(OwnedArms& self, const py::sequence& targets, const Options& options)
{
    std::vector<Pose<double>> poses;
    for (std::size_t i = 0; i < targets.size(); ++i) {
        poses.push_back(target_pose(targets[i], i));
    }
    py::gil_scoped_release release;
    const Result result = self.arms().place_hands(self.model(), self.data(), poses, options);
    self.forward();
    return result;
}

void bind_inverse_kinematics_types(py::module_& module)
{
    py::enum_<numerics::DampedLeastSquaresStatus>(module, "InverseKinematicsStatus",
                                                  "How place_hands ended (C++ numerics::DampedLeastSquaresStatus).")
        .value("converged", numerics::DampedLeastSquaresStatus::converged, "|e| <= tolerance")
        .value("stalled", numerics::DampedLeastSquaresStatus::stalled,
               "no more progress: an unreachable target or a joint limit")
        .value("iteration_limit", numerics::DampedLeastSquaresStatus::iteration_limit, "iteration_limit steps taken");
    py::class_<Options>(module, "InverseKinematicsOptions",
                        "place_hands' options (C++ coopdyn::InverseKinematicsOptions = "
                        "numerics::DampedLeastSquaresOptions; docs/adapters.md, \"Inverse kinematics for start "
                        "postures\"). Checked when place_hands runs.")
        .def(py::init([](double damping, double tolerance, int iteration_limit, double max_step, double stall_step) {
                 return Options{damping, tolerance, iteration_limit, max_step, stall_step};
             }),
             py::arg("damping") = Options{}.damping, py::arg("tolerance") = Options{}.tolerance,
             py::arg("iteration_limit") = Options{}.iteration_limit, py::arg("max_step") = Options{}.max_step,
             py::arg("stall_step") = Options{}.stall_step)
        .def_readwrite("damping", &Options::damping, "lambda of dq = J^T (J J^T + lambda^2 I)^-1 e")
        .def_readwrite("tolerance", &Options::tolerance, "on |e| = |[p_target - p; log(R_target R^T)]| (m and rad)")
        .def_readwrite("iteration_limit", &Options::iteration_limit)
        .def_readwrite("max_step", &Options::max_step, "largest |dq| of one step (rad or m)")
        .def_readwrite("stall_step", &Options::stall_step, "stalled when |dq| <= stall_step (1 + |q|)")
        .def("__repr__", [](const Options& o) {
            return "InverseKinematicsOptions(damping=" + py::repr(py::float_(o.damping)).cast<std::string>() +
                   ", tolerance=" + py::repr(py::float_(o.tolerance)).cast<std::string>() +
                   ", iteration_limit=" + std::to_string(o.iteration_limit) +
                   ", max_step=" + py::repr(py::float_(o.max_step)).cast<std::string>() +
                   ", stall_step=" + py::repr(py::float_(o.stall_step)).cast<std::string>() + ")";
        });
    py::class_<Result>(module, "InverseKinematicsResult", "How place_hands ended (C++ coopdyn::InverseKinematicsResult).")
        .def_readonly("status", &Result::status)
        .def_readonly("residual", &Result::residual, "|e| at the returned posture (m and rad)")
        .def_readonly("iterations", &Result::iterations, "steps taken")
        .def("converged", &Result::converged)
        .def("__repr__", [](const Result& r) {
            return std::string("InverseKinematicsResult(status=") + numerics::to_string(r.status) +
                   ", residual=" + py::repr(py::float_(r.residual)).cast<std::string>() +
                   ", iterations=" + std::to_string(r.iterations) + ")";
        });
}

void bind_contact_wrenches_type(py::module_& module)
{
    py::class_<Wrenches>(module, "MujocoContactWrenches",
                         "Each hand's wrench on one body from MuJoCo's contacts in the last constraint solve (C++ "
                         "coopdyn::MujocoContactWrenches; docs/adapters.md, \"Applied wrenches and contact forces\"). "
                         "Arrays are read-only copies.")
        .def_property_readonly("world", [](const Wrenches& w) { return copy_matrix(w.world); },
                               "(6, K): hand i's wrench [f; t] on the body in {w}, t about contact point i")
        .def_property_readonly("contact_frame", [](const Wrenches& w) { return copy_matrix(w.contact_frame); },
                               "(6, K): the same in contact i's frame [R_i^T f; R_i^T t]; row 2 the normal force (z: "
                               "the inward normal), as ControllerData.contact_frame_wrenches")
        .def_property_readonly("normal_forces", [](const Wrenches& w) { return copy_vector<double>(w.normal_forces); },
                               "(K,): each hand's contacts' normal forces along MuJoCo's contact normals (N)")
        .def_property_readonly("points", [](const Wrenches& w) { return copy_vector<int>(w.points); },
                               "(K,): each hand's MuJoCo contacts with the body");
}

}  // namespace

void bind_plant(py::module_& module)
{
    bind_inverse_kinematics_types(module);
    bind_contact_wrenches_type(module);
    auto arms = py::reinterpret_borrow<py::class_<OwnedArms>>(module.attr("MujocoArms"));
    arms.def_property_readonly("qacc", [](const OwnedArms& self) {
        return copy_vector<double>(Eigen::Map<const Eigen::VectorXd>(self.data()->qacc, self.model()->nv));
    }, "The whole model's qacc (nv,), a copy: the accelerations of the last step (or mj_forward).");
    arms.def("set_applied_wrench", &set_applied_wrench, py::arg("body"), py::arg("wrench"), py::arg("point") = py::none(),
             "Sets the wrench [F; T] (6,) in {w} that MuJoCo applies to the body (xfrc_applied) from the next step on, "
             "until it is set again: at its centre of mass, or F at `point` (3,) in {w} (the torque at the centre is "
             "then T + (point - c) x F). C++ coopdyn::mujoco_set_applied_wrench.");
    arms.def("applied_wrench",
             [](const OwnedArms& self, const std::string& body) {
                 const Vector6<double> wrench = mujoco_applied_wrench(
                     self.model(), self.data(), body_named(self, body, "MujocoArms.applied_wrench", "body"));
                 return copy_vector<double>(Eigen::VectorXd(wrench));
             },
             py::arg("body"), "The wrench [F; T] (6,) MuJoCo applies to the body, at its centre of mass, {w}.");
    arms.def("clear_applied_wrenches", [](OwnedArms& self) { mujoco_clear_applied_wrenches(self.model(), self.data()); },
             "Every body's applied wrench back to zero.");
    arms.def(
        "contact_wrenches",
        [](const OwnedArms& self, const std::string& body) {
            const Wrenches* recorded =
                self.contact_wrenches(body_named(self, body, "MujocoArms.contact_wrenches", "object_body"));
            return recorded != nullptr ? *recorded : Wrenches(self.arms().arms());
        },
        py::arg("object_body"),
        "Each hand's wrench on the body (and the bodies fixed to it) from MuJoCo's contacts: those of the last "
        "step (after step()), or of the state set (after set_state, reset, place_hands). A MujocoContactWrenches; "
        "zero when no hand touches it. C++ MujocoArms::read_contact_wrenches.");
    arms.def("place_hands", &place_hands, py::arg("targets"), py::arg("options") = Options{},
             "Moves the chosen joints so that each contact frame reaches its target in {w} (a coopdyn.Pose or a pair "
             "(position, [x, y, z, w]) per contact), by damped least squares from the current posture within the "
             "joints' ranges, then mj_forward (velocities unchanged). Returns an InverseKinematicsResult. C++ "
             "MujocoArms::place_hands (docs/adapters.md).");
}

}  // namespace coopdyn::python::mujoco
