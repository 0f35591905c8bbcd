/// \file
/// \brief Pose x = (p, q) and rigid-body state (pose and twist), docs/conventions.md.
#pragma once

#include "coopdyn/config.hpp"

namespace coopdyn {

/// \brief Pose of a body: position p in {w} and unit quaternion q rotating body vectors into {w}.
template <typename Scalar> struct Pose {
    Vector3<Scalar> position;
    Quaternion<Scalar> orientation;

    /// Identity pose: origin, no rotation.
    Pose() : position(Vector3<Scalar>::Zero()), orientation(Quaternion<Scalar>::Identity()) {}

    /// Pose at `position_` with orientation `orientation_` (identity if omitted). Implicit, so a
    /// braced position `{p}` or `{p, q}` reads as a pose.
    template <typename Derived>
    Pose(const Eigen::MatrixBase<Derived>& position_,
         const Quaternion<Scalar>& orientation_ = Quaternion<Scalar>::Identity())
        : position(position_), orientation(orientation_)
    {
    }

    /// Rotation matrix R(q).
    Matrix3<Scalar> rotation() const noexcept { return orientation.toRotationMatrix(); }

    /// World-frame position of a point given in body coordinates: p + R(q) point_body.
    template <typename Derived>
    Vector3<Scalar> transform_point(const Eigen::MatrixBase<Derived>& point_body) const noexcept
    {
        return position + orientation * point_body;
    }

    /// The same pose with another scalar type (e.g. double -> float or -> autodiff).
    template <typename Other> Pose<Other> cast() const
    {
        return Pose<Other>{position.template cast<Other>(), orientation.template cast<Other>()};
    }
};

/// \brief State of a rigid body: pose and twist xdot = [v; omega], both in {w}.
template <typename Scalar> struct RigidBodyState {
    Pose<Scalar> pose{};
    Vector6<Scalar> twist = Vector6<Scalar>::Zero();

    auto linear_velocity() const noexcept { return twist.template head<3>(); }
    auto angular_velocity() const noexcept { return twist.template tail<3>(); }
};

}  // namespace coopdyn
