// The first paper's analysis on a Model and its Data (Erhart & Hirche 2016, Section IV;
// docs/analysis.md): the grasp kinematics (10)-(12) alone, the apparent impedance (31)-(32) of a
// model at data's configuration, the restoring wrench, the apparent Coriolis wrench and the
// reduced model (30), the storage function of Lemma 1, the internal / external split (53)-(54),
// and the synthesis of per-arm gains for a target object impedance with the model it gives.
// The kernel forms on arrays are in kernels.cpp; these take the model, as the C++ functions do.
#include "common.hpp"

#include <coopdyn/analysis/apparent_impedance.hpp>
#include <coopdyn/analysis/impedance_synthesis.hpp>
#include <coopdyn/analysis/internal_wrenches.hpp>
#include <coopdyn/core.hpp>

#include <vector>

namespace coopdyn::python {

namespace {

using ModelX = ImpedanceModelX;
using DataX = Data<ModelX>;
using SetpointsX = Setpoints<double, Dynamic>;
using State = RigidBodyState<double>;

py::list arm_list(const std::vector<ModelX::ArmType>& arms)
{
    py::list result;
    for (const ModelX::ArmType& arm : arms) {
        result.append(py::cast(arm));
    }
    return result;
}

void bind_impedance_of_model(py::module_& module)
{
    module.def(
        "grasp_kinematics",
        [](const ModelX& model, DataX& data, const State& state) {
            require_arms(data.arms(), model.arms(), "grasp_kinematics", "data");
            grasp_kinematics(model, data, state);
        },
        py::arg("model"), py::arg("data"), py::arg("state"),
        "grasp_kinematics(model, data, state): the configuration part of interaction_dynamics alone: R(q_o), J_o "
        "in {w} (9), the grasp offsets r_i and the end-effectors' poses and twists (10)-(12), into data.");
    module.def(
        "apparent_impedance",
        [](const ModelX& model, const DataX& data) {
            require_arms(data.arms(), model.arms(), "apparent_impedance", "data");
            return apparent_impedance(model, data);
        },
        py::arg("model"), py::arg("data"),
        "apparent_impedance(model, data) -> ApparentImpedance: M, D, K of the object (31)-(32) with errata E3 at the "
        "grasp configuration in data (after grasp_kinematics or interaction_dynamics). K is the restoring wrench's "
        "Jacobian where the springs are unloaded (docs/analysis.md).");
    module.def(
        "restoring_wrench",
        [](const ModelX& model, const DataX& data, const SetpointsX& setpoints) {
            require_arms(data.arms(), model.arms(), "restoring_wrench", "data");
            require_arms(setpoints.arms(), model.arms(), "restoring_wrench", "setpoints");
            return vector_copy(restoring_wrench(model, data, setpoints));
        },
        py::arg("model"), py::arg("data"), py::arg("setpoints"),
        "restoring_wrench(model, data, setpoints) -> (6,): the exact nonlinear h_o^K = sum_i G_i h_i^K(x_i, x_i^d) "
        "of the end-effectors' springs at data's configuration, about the object's centre of mass in {w}.");
    module.def(
        "apparent_coriolis_wrench",
        [](const ModelX& model, const DataX& data) {
            require_arms(data.arms(), model.arms(), "apparent_coriolis_wrench", "data");
            return vector_copy(apparent_coriolis_wrench(model, data));
        },
        py::arg("model"), py::arg("data"),
        "apparent_coriolis_wrench(model, data) -> (6,): C_o xdot_o + sum_i G_i M_i b_i of (30) at data's "
        "configuration and twist.");
    module.def(
        "reduced_model_acceleration",
        [](const ModelX& model, DataX& data, const State& state, const SetpointsX& setpoints, py::handle disturbance) {
            require_arms(data.arms(), model.arms(), "reduced_model_acceleration", "data");
            require_arms(setpoints.arms(), model.arms(), "reduced_model_acceleration", "setpoints");
            const Vector6<double> object_disturbance =
                disturbance.is_none()
                    ? Vector6<double>::Zero().eval()
                    : Vector6<double>(to_vector(disturbance, "reduced_model_acceleration", "object_disturbance", 6, "(6,)"));
            return vector_copy(reduced_model_acceleration(model, data, state, setpoints, object_disturbance));
        },
        py::arg("model"), py::arg("data"), py::arg("state"), py::arg("setpoints"),
        py::arg("object_disturbance") = py::none(),
        "reduced_model_acceleration(model, data, state, setpoints, object_disturbance=0) -> (6,): the object's "
        "acceleration of the reduced 6-DOF model (30), M^-1 (h~_o - C - D xdot_o - h_o^K); fills data's grasp "
        "kinematics. Exact without gravity and desired wrenches, constant setpoints (Theorem 2).");
    module.def(
        "storage_function",
        [](const ModelX& model, const DataX& data, const SetpointsX& setpoints) {
            require_arms(data.arms(), model.arms(), "storage_function", "data");
            require_arms(setpoints.arms(), model.arms(), "storage_function", "setpoints");
            return storage_function(model, data, setpoints);
        },
        py::arg("model"), py::arg("data"), py::arg("setpoints"),
        "storage_function(model, data, setpoints) -> float: V of Lemma 1 ((47), gravity compensated): "
        "1/2 xdot_o^T M xdot_o + the springs' energy, at data's state.");
}

void bind_decomposition(py::module_& module)
{
    module.def(
        "decompose_wrenches",
        [](const ModelX& model, const DataX& data) {
            require_arms(data.arms(), model.arms(), "decompose_wrenches", "data");
            WrenchDecomposition<ModelX> decomposition(model);
            decompose_wrenches(model, data, decomposition);
            py::dict result;
            result["internal"] = vector_copy(decomposition.internal);
            result["external"] = vector_copy(decomposition.external);
            return result;
        },
        py::arg("model"), py::arg("data"),
        "decompose_wrenches(model, data) -> {'internal': (6N,), 'external': (6N,)}: the end-effector wrenches h' "
        "of data (after interaction_dynamics) split into internal (53) and external (54) parts; internal sums to "
        "zero through G (no motion of the object), internal + external = h'.");
}

void bind_synthesis_of_model(py::module_& module)
{
    using Result = SynthesisResult<double>;
    module.def(
        "synthesize_stiffness",
        [](const ModelX& model, const DataX& data, py::handle target, double tolerance) {
            require_arms(data.arms(), model.arms(), "synthesize_stiffness", "data");
            const Matrix6<double> goal = to_matrix(target, "synthesize_stiffness", "target", 6, 6, "(6, 6)");
            return synthesize_stiffness(model, data, goal, tolerance);
        },
        py::arg("model"), py::arg("data"), py::arg("target"), py::arg("tolerance") = 1e-9,
        "synthesize_stiffness(model, data, target, tolerance=1e-9) -> SynthesisResult: per-arm stiffness gains "
        "k_i, kappa_i >= 0 that give the object the apparent stiffness target (K of Theorem 2 with E3) at data's "
        "grasp configuration; .achievable says whether they do (docs/analysis.md).");
    module.def(
        "synthesize_damping",
        [](const ModelX& model, const DataX& data, py::handle target, double tolerance) {
            require_arms(data.arms(), model.arms(), "synthesize_damping", "data");
            const Matrix6<double> goal = to_matrix(target, "synthesize_damping", "target", 6, 6, "(6, 6)");
            return synthesize_damping(model, data, goal, tolerance);
        },
        py::arg("model"), py::arg("data"), py::arg("target"), py::arg("tolerance") = 1e-9,
        "synthesize_damping(model, data, target, tolerance=1e-9) -> SynthesisResult: per-arm damping gains d_i, "
        "delta_i >= 0 for the apparent damping target (D of (32)).");
    module.def(
        "with_stiffness", [](const ModelX& model, const Result& gains) { return with_stiffness(model, gains); },
        py::arg("model"), py::arg("gains"),
        "with_stiffness(model, gains) -> Model: a copy of model whose arms have gains' stiffnesses; raises "
        "InvalidArgument when the gains are not achievable or sized for another N.");
    module.def(
        "with_damping", [](const ModelX& model, const Result& gains) { return with_damping(model, gains); },
        py::arg("model"), py::arg("gains"), "with_damping(model, gains) -> Model: as with_stiffness, the dampings.");
    module.def(
        "arms_with_stiffness", [](const ModelX& model, const Result& gains) { return arm_list(arms_with_stiffness(model, gains)); },
        py::arg("model"), py::arg("gains"),
        "arms_with_stiffness(model, gains) -> [Arm]: the model's arms with gains' stiffnesses, achievable or not (the "
        "closest fit applied deliberately), to build a Model from.");
    module.def(
        "arms_with_damping", [](const ModelX& model, const Result& gains) { return arm_list(arms_with_damping(model, gains)); },
        py::arg("model"), py::arg("gains"), "arms_with_damping(model, gains) -> [Arm]: as arms_with_stiffness.");
}

}  // namespace

void bind_model_analysis(py::module_& module)
{
    bind_impedance_of_model(module);
    bind_decomposition(module);
    bind_synthesis_of_model(module);
}

}  // namespace coopdyn::python
