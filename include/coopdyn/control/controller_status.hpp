/// \file
/// \brief What a controller tick reports besides its torques: its outcome (ControlStatus), the
/// input it refused (ControllerInputProblem) and the input check that finds it, run before
/// anything is computed. Included by controller.hpp, whose ControllerData holds both;
/// docs/control.md, "The controller".
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/control/controller_model.hpp"
#include "coopdyn/detail/validation.hpp"

namespace coopdyn {

/// \brief Outcome of a controller tick (ControllerData::status). Whatever the status, the torques
/// are finite.
enum class ControlStatus {
    /// Every step succeeded; the predicted contact wrenches satisfy every friction row.
    ok,
    /// No squeeze satisfies every friction row (the load cannot be held by friction as modelled):
    /// the fallback's least-violating squeeze is applied and ControllerData::fallback_violation
    /// says by how much the worst row is violated. The grasp may slip.
    friction_infeasible,
    /// The contact QP stopped at its iteration cap (or its Hessian was not positive definite): the
    /// fallback's squeeze is applied (or none if that failed too). Rare; see qp_status.
    qp_failed,
    /// The arms are at a singular configuration (J lost rank, or the object cannot be moved in
    /// some direction): no torques can be computed; the torque is h (the arms' bias compensated,
    /// no squeeze). ControllerData::dynamics.status says which projection failed.
    singular,
    /// An input is not finite, a quaternion is not unit, or M is not positive definite
    /// (ControllerData::input_problem names it): the torque is zero.
    invalid_input,
};

/// The enumerator's name.
inline const char* to_string(ControlStatus status) noexcept
{
    switch (status) {
    case ControlStatus::ok: return "ok";
    case ControlStatus::friction_infeasible: return "friction_infeasible";
    case ControlStatus::qp_failed: return "qp_failed";
    case ControlStatus::singular: return "singular";
    case ControlStatus::invalid_input: return "invalid_input";
    }
    return "unknown";
}

/// Whether a tick with this status computed the control: every output of ControllerData is this
/// tick's (ok, friction_infeasible, qp_failed). For invalid_input and singular the tick computed
/// only `torque`; every other output is reset (docs/control.md, "After a failed tick").
inline bool control_computed(ControlStatus status) noexcept
{
    return status == ControlStatus::ok || status == ControlStatus::friction_infeasible ||
           status == ControlStatus::qp_failed;
}

/// \brief The input a tick refused (ControllerData::input_problem): the first one found, in this
/// order; `none` when every input passed. Checked before anything is computed.
enum class ControllerInputProblem {
    none,
    inertia_not_finite,
    bias_not_finite,
    jacobian_not_finite,
    jacobian_rate_qdot_not_finite,
    positions_not_finite,
    velocities_not_finite,
    object_position_not_finite,
    object_orientation_not_unit,
    object_twist_not_finite,
    object_acceleration_not_finite,
    desired_position_not_finite,
    desired_orientation_not_unit,
    desired_twist_not_finite,
    desired_acceleration_not_finite,
    posture_not_finite,
    /// M is finite but its Cholesky factorisation failed (not symmetric positive definite).
    inertia_not_positive_definite,
};

/// The refused input by its ControllerInput name and what is wrong with it, e.g.
/// "object_acceleration (not finite)", "inertia (not positive definite)"; "none".
inline const char* to_string(ControllerInputProblem problem) noexcept
{
    switch (problem) {
    case ControllerInputProblem::none: return "none";
    case ControllerInputProblem::inertia_not_finite: return "inertia (not finite)";
    case ControllerInputProblem::bias_not_finite: return "bias (not finite)";
    case ControllerInputProblem::jacobian_not_finite: return "jacobian (not finite)";
    case ControllerInputProblem::jacobian_rate_qdot_not_finite: return "jacobian_rate_qdot (not finite)";
    case ControllerInputProblem::positions_not_finite: return "positions (not finite)";
    case ControllerInputProblem::velocities_not_finite: return "velocities (not finite)";
    case ControllerInputProblem::object_position_not_finite: return "object.pose.position (not finite)";
    case ControllerInputProblem::object_orientation_not_unit: return "object.pose.orientation (not unit)";
    case ControllerInputProblem::object_twist_not_finite: return "object.twist (not finite)";
    case ControllerInputProblem::object_acceleration_not_finite: return "object_acceleration (not finite)";
    case ControllerInputProblem::desired_position_not_finite: return "desired_pose.position (not finite)";
    case ControllerInputProblem::desired_orientation_not_unit: return "desired_pose.orientation (not unit)";
    case ControllerInputProblem::desired_twist_not_finite: return "desired_twist (not finite)";
    case ControllerInputProblem::desired_acceleration_not_finite: return "desired_acceleration (not finite)";
    case ControllerInputProblem::posture_not_finite: return "posture (not finite)";
    case ControllerInputProblem::inertia_not_positive_definite: return "inertia (not positive definite)";
    }
    return "unknown";
}

namespace detail {

/// The first per-tick input that is not finite (or a quaternion that is not unit); none.
template <typename Scalar, int Arms, int Joints>
ControllerInputProblem controller_input_problem(const ControllerInput<Scalar, Arms, Joints>& input) noexcept
{
    using Problem = ControllerInputProblem;
    if (!all_finite(input.inertia)) return Problem::inertia_not_finite;
    if (!all_finite(input.bias)) return Problem::bias_not_finite;
    if (!all_finite(input.jacobian)) return Problem::jacobian_not_finite;
    if (!all_finite(input.jacobian_rate_qdot)) return Problem::jacobian_rate_qdot_not_finite;
    if (!all_finite(input.positions)) return Problem::positions_not_finite;
    if (!all_finite(input.velocities)) return Problem::velocities_not_finite;
    if (!all_finite(input.object.pose.position)) return Problem::object_position_not_finite;
    if (!is_unit_quaternion(input.object.pose.orientation.coeffs())) return Problem::object_orientation_not_unit;
    if (!all_finite(input.object.twist)) return Problem::object_twist_not_finite;
    if (!all_finite(input.object_acceleration)) return Problem::object_acceleration_not_finite;
    if (!all_finite(input.desired_pose.position)) return Problem::desired_position_not_finite;
    if (!is_unit_quaternion(input.desired_pose.orientation.coeffs())) return Problem::desired_orientation_not_unit;
    if (!all_finite(input.desired_twist)) return Problem::desired_twist_not_finite;
    if (!all_finite(input.desired_acceleration)) return Problem::desired_acceleration_not_finite;
    if (!all_finite(input.posture)) return Problem::posture_not_finite;
    return Problem::none;
}

}  // namespace detail

}  // namespace coopdyn
