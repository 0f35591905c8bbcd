/// \file
/// \brief End-effector under resolved-acceleration control with PD tracking (docs/model.md,
/// paper (20)-(21)).
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/detail/validation.hpp"
#include "coopdyn/spatial/inertia.hpp"
#include "coopdyn/spatial/pose.hpp"
#include "coopdyn/spatial/quaternion.hpp"

#include <string>

namespace coopdyn {

/// \brief Lambda_i xdd_i = h_i^Pi + h_i (21) with
/// h_i^Pi = Lambda_i [xdd_i^d - K_D,i (xdot_i - xdot_i^d) - K_P,i dx_i] (20),
/// dx_i = [p_i - p_i^d; d_eps_i] with dq_i = q_i (x) (q_i^d)^-1 as in (5).
///
/// Lambda_i is the arm's apparent (physical) task-space inertia, a general SPD 6x6 matrix, so the
/// interaction solver takes its general path. Its motion wrench h_i^Pi plays the role of h_i^x.
template <typename ScalarType> struct ResolvedAccelerationEndEffector {
    using Scalar = ScalarType;
    /// The inertia type of inertia(): a general SPD 6x6 (the solver's general path).
    using Inertia = ArticulatedInertia<Scalar>;
    static constexpr bool has_block_diagonal_inertia = false;

    Matrix6<Scalar> apparent_inertia = Matrix6<Scalar>::Zero();   ///< Lambda_i in {w}, SPD
    Matrix6<Scalar> derivative_gain = Matrix6<Scalar>::Zero();    ///< K_D,i, 1/s
    Matrix6<Scalar> proportional_gain = Matrix6<Scalar>::Zero();  ///< K_P,i, 1/s^2

    /// Lambda_i.
    Inertia inertia() const { return Inertia(apparent_inertia); }

    /// dx_i = [p_i - p_i^d; d_eps_i] of (20).
    Vector6<Scalar> pose_error(const Pose<Scalar>& pose, const Pose<Scalar>& desired) const noexcept
    {
        Vector6<Scalar> result;
        result.template head<3>() = pose.position - desired.position;
        result.template tail<3>() = orientation_error(pose.orientation, desired.orientation).vec();
        return result;
    }

    /// h_i^Pi of (20).
    template <typename DerivedTwist, typename DerivedDesiredTwist, typename DerivedDesiredAcceleration>
    Vector6<Scalar> motion_wrench(const Pose<Scalar>& pose, const Eigen::MatrixBase<DerivedTwist>& twist,
                                  const Pose<Scalar>& desired,
                                  const Eigen::MatrixBase<DerivedDesiredTwist>& desired_twist,
                                  const Eigen::MatrixBase<DerivedDesiredAcceleration>& desired_acceleration)
        const noexcept
    {
        return apparent_inertia * (desired_acceleration - derivative_gain * (twist - desired_twist) -
                                   proportional_gain * pose_error(pose, desired));
    }

    /// Throws InvalidModel naming the arm and the parameter: Lambda_i SPD, gains finite and not
    /// negative (no eigenvalue with a negative real part; they need not be symmetric).
    void validate(Index arm) const
    {
        const detail::ErrorContext context = detail::arm_context(arm);
        detail::require_symmetric_positive(apparent_inertia, context, "apparent_inertia");
        detail::require_non_negative_gain(derivative_gain, context, "derivative_gain");
        detail::require_non_negative_gain(proportional_gain, context, "proportional_gain");
    }
};

}  // namespace coopdyn
