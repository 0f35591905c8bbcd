/// \file
/// \brief Kinematic coordination (27) and the tracking feed-forward of Theorem 1
/// (docs/coordination.md).
///
/// From a desired object motion (pose, twist, acceleration), every end-effector's desired motion
/// follows from the rigid grasp: x_i^d from (38), xdot_i^d = G_i^T xdot_o^d (27) and
/// xdd_i^d = G_i^T xdd_o^d + b_i(w_o^d). With the object wrench
/// h_o^d = M_o xdd_o^d + C_o(x_o^d, xdot_o^d) xdot_o^d + h_g distributed by (26), ideal conditions
/// give exact tracking and no internal wrench (Theorem 1).
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/dynamics/input_check.hpp"
#include "coopdyn/model/cooperative_model.hpp"
#include "coopdyn/model/grasp.hpp"

namespace coopdyn {

/// \brief Desired end-effector poses, twists and accelerations (27) for a desired object state
/// and acceleration, written into `setpoints` (wrenches untouched). noexcept; allocation-free.
template <typename ModelType, typename DerivedAcceleration>
void coordinate_setpoints(const ModelType& model, const RigidBodyState<typename ModelType::Scalar>& desired_object,
                          const Eigen::MatrixBase<DerivedAcceleration>& desired_object_acceleration,
                          Setpoints<typename ModelType::Scalar, ModelType::arms_at_compile_time>& setpoints) noexcept
{
    using Scalar = typename ModelType::Scalar;
    COOPDYN_REQUIRE_SHAPE(setpoints.arms() == model.arms(), "setpoints sized for another number of arms");
    COOPDYN_ASSERT_INPUTS(check_state(desired_object));
    COOPDYN_ASSERT(detail::all_finite(desired_object_acceleration), "desired_object_acceleration must be finite");
    const Matrix3<Scalar> rotation = desired_object.pose.orientation.toRotationMatrix();
    const Vector3<Scalar> omega = desired_object.twist.template tail<3>();
    for (Index i = 0; i < model.arms(); ++i) {
        const GraspPoint<Scalar> point = grasp_point(model, i, rotation, desired_object);
        setpoints.set_pose(i, point.pose);
        setpoints.twist(i) = point.twist;
        // xdd_i^d = G_i^T xdd_o^d + b_i(w_o^d) (27)
        Vector6<Scalar> acceleration = grasp_map_twist(point.offset, desired_object_acceleration);
        acceleration.template head<3>() += centripetal_acceleration(point.offset, omega);
        setpoints.acceleration(i) = acceleration;
    }
}

/// \brief Object wrench that makes the object follow the desired motion (Theorem 1, with
/// gravity): h_o^d = M_o xdd_o^d + C_o(x_o^d, xdot_o^d) xdot_o^d + h_g.
template <typename ModelType, typename DerivedAcceleration>
Vector6<typename ModelType::Scalar> tracking_object_wrench(
    const ModelType& model, const RigidBodyState<typename ModelType::Scalar>& desired_object,
    const Eigen::MatrixBase<DerivedAcceleration>& desired_object_acceleration) noexcept
{
    using Scalar = typename ModelType::Scalar;
    const auto& object = model.object();
    const Matrix3<Scalar> rotation = desired_object.pose.orientation.toRotationMatrix();
    const CentralInertia<Scalar> inertia = object.inertia(rotation);  // M_o (9), in {w}
    const Vector6<Scalar> inertial = (inertia * Motion<Scalar>::from(desired_object_acceleration)).vector();
    return inertial + object.coriolis_wrench(inertia.rotational().matrix(), desired_object.twist) +
           object.gravity_wrench(model.gravity());
}

}  // namespace coopdyn
