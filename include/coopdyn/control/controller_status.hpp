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
/// are finite; which torque each status sends: docs/control.md, "Every status's torque". ok means
/// nothing went wrong: the measurement was used as given, the torque sent is the one computed, the
/// predicted contact wrenches satisfy every friction row and no contact was seen to slip. When
/// several conditions hold, the status is the first of: invalid_input, safe_hold, singular (these
/// compute no control), then slipping, torque_saturated, qp_failed, friction_infeasible,
/// degraded; each condition also has its own field (slipping_contacts, saturated_count,
/// qp_status, fallback_used, replaced_input), set whatever the status.
enum class ControlStatus {
    /// Every step succeeded, nothing was clipped, replaced or seen to slip.
    ok,
    /// No squeeze satisfies every friction row (the load cannot be held by friction as modelled):
    /// the fallback's least-violating squeeze is applied and ControllerData::fallback_violation
    /// says by how much the worst row is violated. The grasp may slip.
    friction_infeasible,
    /// The contact QP stopped at its iteration cap (or its Hessian was not positive definite): the
    /// fallback's squeeze is applied (or none if that failed too). Rare; see qp_status.
    qp_failed,
    /// The arms are at a singular configuration (J lost rank, or the object cannot be moved in
    /// some direction): no control can be computed; the torque is h + J^T w_hold (this tick's h
    /// and J, the contact wrenches of the last tick that computed the control: the last squeeze
    /// kept), or h before any such tick. ControllerData::dynamics.status says which projection
    /// failed.
    singular,
    /// An input is not finite, a quaternion is not unit, or M is not positive definite
    /// (ControllerData::input_problem names it) and no tick has computed the control yet, so there
    /// is nothing to hold: the torque is zero. After such a tick the same inputs give safe_hold.
    invalid_input,
    /// The object's measurement was missing (not finite) or flagged stale and a predicted state
    /// replaced it (ControllerData::replaced_input says which, input_problem what was wrong): the
    /// control ran on the prediction, the torque is computed as for ok. Friction_infeasible and
    /// qp_failed take precedence; replaced_input still says a prediction was used.
    degraded,
    /// The object's state has been predicted longer than FaultOptions::prediction_limit, or an
    /// input other than the object's measurement is unusable (input_problem names it) after a tick
    /// that computed the control: the torque is ControllerData::hold_torque, h + J^T w of the last
    /// tick that computed the control (its arms' bias and its predicted contact wrenches: the same
    /// squeeze, the object's last estimated load balanced, no motion). Never zero while held.
    safe_hold,
    /// The torque limits (ControllerParameters::torque_limits, torque_rate_limits) clipped the
    /// torque (ControllerData::saturated_joints, requested_torque): the arms do not apply the
    /// contact wrenches the tick computed, and the object may sag, slip or fall. The control was
    /// computed; the clipped torque is sent.
    torque_saturated,
    /// A contact slips (ControllerData::slipping): its measured frame is farther from where the
    /// measured object pose puts it than FaultOptions::slip_distance_threshold or
    /// slip_angle_threshold. Needs the contacts' poses in the input (ControllerInput::
    /// contact_poses_filled; the MuJoCo adapter fills them) and a measured object pose. The control
    /// was computed (with the squeeze raised when FaultOptions::slip_squeeze_factor > 1).
    slipping,
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
    case ControlStatus::degraded: return "degraded";
    case ControlStatus::safe_hold: return "safe_hold";
    case ControlStatus::torque_saturated: return "torque_saturated";
    case ControlStatus::slipping: return "slipping";
    }
    return "unknown";
}

/// Whether a tick with this status computed the control: every output of ControllerData is this
/// tick's (ok, degraded, friction_infeasible, qp_failed, torque_saturated, slipping). For
/// invalid_input, singular and safe_hold the tick computed only `torque`; every other output is
/// reset (docs/control.md, "After a failed tick").
inline bool control_computed(ControlStatus status) noexcept
{
    return status != ControlStatus::invalid_input && status != ControlStatus::singular &&
           status != ControlStatus::safe_hold;
}

/// \brief What replaced the object's measurement in a tick (ControllerData::replaced_input);
/// docs/control.md, "Faults: dropout, safe hold, slip, torque limits".
enum class ReplacedInput {
    /// The measurement was used as given.
    none,
    /// Only object_acceleration was not finite: the last valid one replaced it, the measured pose
    /// and twist were used.
    object_acceleration,
    /// The object's pose from the contacts' poses (ControllerInput::contact_poses_filled) composed
    /// with the contact-to-object offsets recorded at the last valid measurement; its twist
    /// Jx qdot; its acceleration the last valid one.
    object_state_from_contacts,
    /// The last valid measurement propagated with its twist held constant: p = p_0 + v t,
    /// q = exp(omega t) q_0; its acceleration the last valid one.
    object_state_from_twist,
};

/// The enumerator's name.
inline const char* to_string(ReplacedInput replaced) noexcept
{
    switch (replaced) {
    case ReplacedInput::none: return "none";
    case ReplacedInput::object_acceleration: return "object_acceleration";
    case ReplacedInput::object_state_from_contacts: return "object_state_from_contacts";
    case ReplacedInput::object_state_from_twist: return "object_state_from_twist";
    }
    return "unknown";
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
    /// ControllerInput::object_stale was set: the object's measurement is old.
    object_stale,
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
    case ControllerInputProblem::object_stale: return "object (flagged stale)";
    }
    return "unknown";
}

namespace detail {

/// The first per-tick input, other than the object's measurement, that is not finite (or a
/// quaternion that is not unit); none. A failure here leaves nothing to control with: safe hold.
template <typename Scalar, int Arms, int Joints>
ControllerInputProblem arm_input_problem(const ControllerInput<Scalar, Arms, Joints>& input) noexcept
{
    using Problem = ControllerInputProblem;
    if (!all_finite(input.inertia)) return Problem::inertia_not_finite;
    if (!all_finite(input.bias)) return Problem::bias_not_finite;
    if (!all_finite(input.jacobian)) return Problem::jacobian_not_finite;
    if (!all_finite(input.jacobian_rate_qdot)) return Problem::jacobian_rate_qdot_not_finite;
    if (!all_finite(input.positions)) return Problem::positions_not_finite;
    if (!all_finite(input.velocities)) return Problem::velocities_not_finite;
    if (!all_finite(input.desired_pose.position)) return Problem::desired_position_not_finite;
    if (!is_unit_quaternion(input.desired_pose.orientation.coeffs())) return Problem::desired_orientation_not_unit;
    if (!all_finite(input.desired_twist)) return Problem::desired_twist_not_finite;
    if (!all_finite(input.desired_acceleration)) return Problem::desired_acceleration_not_finite;
    if (!all_finite(input.posture)) return Problem::posture_not_finite;
    return Problem::none;
}

/// What is wrong with the object's measurement (the stale flag first, then the pose, the twist,
/// the acceleration); none. A failure here is replaced by a prediction (ControlStatus::degraded).
template <typename Scalar, int Arms, int Joints>
ControllerInputProblem object_measurement_problem(const ControllerInput<Scalar, Arms, Joints>& input) noexcept
{
    using Problem = ControllerInputProblem;
    if (input.object_stale) return Problem::object_stale;
    if (!all_finite(input.object.pose.position)) return Problem::object_position_not_finite;
    if (!is_unit_quaternion(input.object.pose.orientation.coeffs())) return Problem::object_orientation_not_unit;
    if (!all_finite(input.object.twist)) return Problem::object_twist_not_finite;
    if (!all_finite(input.object_acceleration)) return Problem::object_acceleration_not_finite;
    return Problem::none;
}

}  // namespace detail

}  // namespace coopdyn
