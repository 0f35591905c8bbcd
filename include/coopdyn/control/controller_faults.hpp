/// \file
/// \brief The controller tick's fault handling (docs/control.md, "Faults: dropout, safe hold,
/// slip, torque limits"): the object's state when its measurement drops out (predicted from the
/// contacts' poses or from the last measurement's twist), each contact's slip, the squeeze raised
/// while a contact slips, the safe-hold torque, and the torque limits. Per-tick, noexcept,
/// allocation-free; called by controller_tick (controller.hpp).
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/control/controller_data.hpp"
#include "coopdyn/control/controller_model.hpp"
#include "coopdyn/control/controller_status.hpp"
#include "coopdyn/detail/validation.hpp"
#include "coopdyn/model/contact_frames.hpp"
#include "coopdyn/spatial/pose.hpp"
#include "coopdyn/spatial/quaternion.hpp"

namespace coopdyn {
namespace detail {

/// Contact frame i's pose in {w} from the input's columns.
template <typename Input> Pose<typename Input::Scalar> input_contact_pose(const Input& input, Index i) noexcept
{
    using Scalar = typename Input::Scalar;
    return Pose<Scalar>{input.contact_positions.col(i), Quaternion<Scalar>(input.contact_orientations.col(i))};
}

/// The input carries usable contact poses: flagged filled, finite, unit quaternions.
template <typename Input> bool contact_poses_usable(const Input& input) noexcept
{
    if (!input.contact_poses_filled || !all_finite(input.contact_positions)) {
        return false;
    }
    for (Index i = 0; i < input.contact_orientations.cols(); ++i) {
        if (!is_unit_quaternion(input.contact_orientations.col(i))) {
            return false;
        }
    }
    return true;
}

/// Whether the object's measured pose and twist are usable (only the acceleration may be bad).
inline bool object_pose_measured(ControllerInputProblem problem) noexcept
{
    return problem == ControllerInputProblem::none || problem == ControllerInputProblem::object_acceleration_not_finite;
}

/// Keeps what a dropout needs: on a measured tick the measurement (pose, twist, and the
/// acceleration when it is finite) and, with usable
/// contact poses, each contact frame in the object (contact_frame_in_object), the prediction's age
/// reset; on a tick without one, the age advanced by a tick period.
template <typename Model, typename Data, typename Input>
void controller_remember_measurement(const Model& model, Data& data, const Input& input, ControllerInputProblem problem) noexcept
{
    if (!object_pose_measured(problem)) {
        data.predicted_ticks += data.has_measurement ? 1 : 0;
        data.prediction_age = static_cast<typename Model::Scalar>(data.predicted_ticks) * model.faults().tick_period;
        return;
    }
    data.last_measurement = input.object;
    data.has_measurement = true;
    if (problem == ControllerInputProblem::none) {
        data.last_acceleration = input.object_acceleration;
    }
    data.predicted_ticks = 0;
    data.prediction_age = 0;
    if (contact_poses_usable(input)) {
        for (Index i = 0; i < model.arms(); ++i) {
            const auto offset = contact_frame_in_object(input.object.pose, input_contact_pose(input, i));
            data.contact_offset_positions.col(i) = offset.position;
            data.contact_offset_orientations.col(i) = offset.orientation.coeffs();
        }
        data.has_contact_offsets = true;
    }
}

/// The object's pose predicted by the contacts (object_pose_from_contact with the offsets recorded
/// at the last valid measurement): positions averaged, quaternions averaged on one hemisphere and
/// normalised (for a rigid grasp all contacts predict the same pose; the mean averages their noise).
template <typename Data, typename Input> Pose<typename Data::Scalar> pose_from_contacts(const Data& data, const Input& input) noexcept
{
    using Scalar = typename Data::Scalar;
    const Index arms = data.contact_offset_positions.cols();
    Pose<Scalar> mean;
    mean.position.setZero();
    Eigen::Matrix<Scalar, 4, 1> quaternion_sum = Eigen::Matrix<Scalar, 4, 1>::Zero();
    for (Index i = 0; i < arms; ++i) {
        const Pose<Scalar> offset{data.contact_offset_positions.col(i),
                                  Quaternion<Scalar>(data.contact_offset_orientations.col(i))};
        const Pose<Scalar> predicted = object_pose_from_contact(input_contact_pose(input, i), offset);
        mean.position += predicted.position / Scalar(arms);
        const Scalar sign = i > 0 && predicted.orientation.coeffs().dot(quaternion_sum) < Scalar(0) ? Scalar(-1) : Scalar(1);
        quaternion_sum += sign * predicted.orientation.coeffs();
    }
    mean.orientation = Quaternion<Scalar>(quaternion_sum.normalized());
    return mean;
}

/// The object's state this tick (data.object, data.object_acceleration, data.replaced_input):
/// the measurement; the last valid acceleration for a non-finite acceleration alone; else, within
/// FaultOptions::prediction_limit of the last valid measurement, a prediction: from the contacts'
/// poses when the input carries them (the twist is set from Jx qdot after the projection, by
/// controller_tick), otherwise the last measurement with its twist held constant, integrated
/// exactly: p = p_0 + v t, q = exp(omega t) q_0 (quaternion_exp; omega in {w}); the acceleration
/// in both is the last valid one. Returns false when
/// there is no usable state (no valid measurement yet, or the prediction is older than the limit).
template <typename Model, typename Data, typename Input>
bool controller_object_state(const Model& model, Data& data, const Input& input, ControllerInputProblem problem) noexcept
{
    using Scalar = typename Model::Scalar;
    data.replaced_input = ReplacedInput::none;
    if (problem == ControllerInputProblem::none) {
        data.object = input.object;
        data.object_acceleration = input.object_acceleration;
        return true;
    }
    // The last valid acceleration, held: zero (the constant-twist model's) would make the estimate
    // F_x of L(7) jump by Lambda_c xdd at the dropout's first tick, and the squeeze with it.
    data.object_acceleration = data.last_acceleration;
    if (problem == ControllerInputProblem::object_acceleration_not_finite) {
        data.object = input.object;
        data.replaced_input = ReplacedInput::object_acceleration;
        return true;
    }
    // A relative slack of 1e-9 of a tick keeps limit / period ticks (e.g. 100 of 1 ms for 0.1 s)
    // from failing on rounding.
    const FaultOptions<Scalar>& faults = model.faults();
    if (!data.has_measurement || data.prediction_age > faults.prediction_limit + Scalar(1e-9) * faults.tick_period) {
        return false;
    }
    if (data.has_contact_offsets && contact_poses_usable(input)) {
        data.object.pose = pose_from_contacts(data, input);
        data.object.twist = data.last_measurement.twist;  // replaced by Jx qdot once projected
        data.replaced_input = ReplacedInput::object_state_from_contacts;
        return true;
    }
    const RigidBodyState<Scalar>& last = data.last_measurement;
    data.object.twist = last.twist;
    data.object.pose.position = last.pose.position + data.prediction_age * last.linear_velocity();
    const Vector3<Scalar> rotation = data.prediction_age * last.angular_velocity();
    data.object.pose.orientation = (quaternion_exp(rotation) * last.pose.orientation).normalized();
    data.replaced_input = ReplacedInput::object_state_from_twist;
    return true;
}

/// Each contact's slip (data.slip_*): with the contacts' poses in the input and the object's pose
/// measured, contact i's measured origin minus the one the measured object pose puts it at,
/// p_o + R_o p_i (m, {w}), and the angle of q_c,measured (q_o q_i)^-1 (rad); q_i, p_i:
/// ContactPoint::frame. Contacts beyond a threshold (FaultOptions) are marked slipping.
template <typename Model, typename Data, typename Input>
void controller_slip(const Model& model, Data& data, const Input& input) noexcept
{
    using Scalar = typename Model::Scalar;
    data.slip_measured = data.replaced_input != ReplacedInput::object_state_from_contacts &&
                         data.replaced_input != ReplacedInput::object_state_from_twist && contact_poses_usable(input);
    data.slipping_contacts = 0;
    if (!data.slip_measured) {
        data.slip_displacement.setZero();
        data.slip_distance.setZero();
        data.slip_angle.setZero();
        data.slipping.setConstant(false);
        return;
    }
    const Pose<Scalar>& object = data.object.pose;
    for (Index i = 0; i < model.arms(); ++i) {
        const Pose<Scalar> measured = input_contact_pose(input, i);
        const Pose<Scalar>& frame = model.contact(i).frame;
        data.slip_displacement.col(i) = measured.position - object.transform_point(frame.position);
        data.slip_distance(i) = data.slip_displacement.col(i).norm();
        const Quaternion<Scalar> predicted = object.orientation * frame.orientation;
        data.slip_angle(i) = quaternion_log(Quaternion<Scalar>((measured.orientation * predicted.conjugate()).normalized())).norm();
        data.slipping(i) = data.slip_distance(i) > model.faults().slip_distance_threshold ||
                           data.slip_angle(i) > model.faults().slip_angle_threshold;
        data.slipping_contacts += data.slipping(i) ? 1 : 0;
    }
}

/// While contact i slips, its minimum normal force is f_min times FaultOptions::slip_squeeze_factor:
/// the bound of its unilateral row (the first of its rows, -f_z <= -f_min; friction.hpp) moves by
/// (factor - 1) f_min. Call after controller_contact_qp has written the bounds.
template <typename Model, typename Data> void controller_raise_squeeze(const Model& model, Data& data) noexcept
{
    using Scalar = typename Model::Scalar;
    const Scalar factor = model.faults().slip_squeeze_factor;
    if (data.slipping_contacts == 0 || factor == Scalar(1)) {
        return;
    }
    for (Index i = 0; i < model.arms(); ++i) {
        if (data.slipping(i)) {
            data.bounds(model.row_offset(i)) -= (factor - Scalar(1)) * model.contact(i).friction.minimum_normal_force;
        }
    }
}

/// The safe hold's torque for the next ticks, from a tick that computed the control:
/// tau_hold = h + J^T w with this tick's bias and predicted contact wrenches w. The arms' dynamics
/// with the hands applying w on the object are M qdd + h = tau - J^T w, so at rest tau_hold keeps
/// qdd = 0 with the same contact wrenches: the same squeeze (w's internal part), the object's
/// estimated load balanced (G w = -F_x), the arms' weight compensated.
template <typename Data, typename Input> void controller_record_hold(Data& data, const Input& input) noexcept
{
    data.hold_wrenches = data.contact_wrenches;
    data.hold_torque = input.bias;
    data.hold_torque.noalias() += input.jacobian.transpose().lazyProduct(data.hold_wrenches);
    data.hold_ready = true;
}

/// The torque limits, after everything else: the change from the last sent torque clamped to
/// +-torque_rate_limits, then the torque to +-torque_limits; data.requested_torque keeps the
/// torque before, data.saturated_joints / saturated_count the joints the limits changed.
template <typename Model, typename Data>
const typename Data::JointVector& controller_limit_torque(const Model& model, Data& data) noexcept
{
    data.requested_torque = data.torque;
    if (model.has_torque_rate_limits() && data.has_previous_torque) {
        data.torque = data.torque.cwiseMax(data.previous_torque - model.torque_rate_limits())
                          .cwiseMin(data.previous_torque + model.torque_rate_limits());
    }
    if (model.has_torque_limits()) {
        data.torque = data.torque.cwiseMax(-model.torque_limits()).cwiseMin(model.torque_limits());
    }
    data.saturated_joints = data.torque.array() != data.requested_torque.array();
    data.saturated_count = data.saturated_joints.count();
    data.previous_torque = data.torque;
    data.has_previous_torque = true;
    return data.torque;
}

}  // namespace detail
}  // namespace coopdyn
