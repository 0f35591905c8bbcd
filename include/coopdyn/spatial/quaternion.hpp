/// \file
/// \brief Quaternion kinematics, exponential map and orientation error, docs/spatial.md,
/// paper (2)-(5) and errata E6.
///
/// Quaternions are Eigen::Quaternion (Hamilton product, rotating body vectors into the world
/// frame). Where a 4-vector is written out, its order is (eta, eps) = (w, x, y, z), as in the paper;
/// note that Eigen's `coeffs()` stores (x, y, z, w).
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/spatial/skew.hpp"

#include <cmath>

namespace coopdyn {

/// \brief Left-multiplication matrix Q(q) of paper (4): for quaternions in (eta, eps) order,
/// Q(q) p = q (x) p.
/// \return 4x4 matrix [[eta, -eps^T], [eps, eta I3 + S(eps)]].
template <typename Scalar>
Eigen::Matrix<Scalar, 4, 4> quaternion_left_matrix(const Quaternion<Scalar>& q) noexcept
{
    Eigen::Matrix<Scalar, 4, 4> result;
    result(0, 0) = q.w();
    result.template block<1, 3>(0, 1) = -q.vec().transpose();
    result.template block<3, 1>(1, 0) = q.vec();
    result.template block<3, 3>(1, 1) = q.w() * Matrix3<Scalar>::Identity() + skew(q.vec());
    return result;
}

/// \brief Time derivative of q for an angular velocity expressed in the world frame:
/// qdot = 1/2 [0; omega] (x) q (docs/spatial.md; the printed (3) is the body-frame form, E6).
/// \param orientation unit quaternion q.
/// \param omega angular velocity in {w}.
/// \return qdot, stored in a Quaternion (not unit).
template <typename Scalar, typename Derived>
Quaternion<Scalar> quaternion_derivative_world(const Quaternion<Scalar>& orientation,
                                               const Eigen::MatrixBase<Derived>& omega) noexcept
{
    EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(Derived, 3);
    const Scalar half(0.5);
    // [0; w] (x) q = [-w . eps; eta w + w x eps]
    Quaternion<Scalar> derivative;
    derivative.w() = -half * omega.dot(orientation.vec());
    derivative.vec() = half * (orientation.w() * omega + omega.cross(orientation.vec()));
    return derivative;
}

/// \brief Time derivative of q for an angular velocity expressed in the body frame:
/// qdot = 1/2 q (x) [0; omega_body] = 1/2 Q(q) [0; omega_body], the printed paper (3).
/// \param orientation unit quaternion q.
/// \param omega_body angular velocity in the body frame, omega_body = R(q)^T omega.
template <typename Scalar, typename Derived>
Quaternion<Scalar> quaternion_derivative_body(const Quaternion<Scalar>& orientation,
                                              const Eigen::MatrixBase<Derived>& omega_body) noexcept
{
    EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(Derived, 3);
    const Scalar half(0.5);
    // q (x) [0; w] = [-eps . w; eta w + eps x w]
    Quaternion<Scalar> derivative;
    derivative.w() = -half * orientation.vec().dot(omega_body);
    derivative.vec() =
        half * (orientation.w() * omega_body + orientation.vec().cross(omega_body));
    return derivative;
}

/// \brief Exponential map: the unit quaternion of the rotation by |v| about v / |v|.
/// \param rotation_vector v = theta u (axis times angle, radians).
/// \return [cos(theta/2); sin(theta/2) u]; exact (Taylor series near zero, so it is smooth and
/// differentiable at v = 0, which autodiff scalars need).
template <typename Derived>
Quaternion<typename Derived::Scalar>
quaternion_exp(const Eigen::MatrixBase<Derived>& rotation_vector) noexcept
{
    EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(Derived, 3);
    using Scalar = typename Derived::Scalar;
    using std::cos;
    using std::sin;
    using std::sqrt;
    const Scalar angle_squared = rotation_vector.squaredNorm();
    Scalar real_part;
    Scalar sinc_half;  // sin(theta / 2) / theta
    // For theta < 1e-4 the truncated series is exact to double rounding (next term ~ theta^6);
    // the closed form would divide 0 by 0 at v = 0 and lose the derivative there.
    if (angle_squared < Scalar(1e-8)) {
        real_part = Scalar(1) - angle_squared / Scalar(8) + angle_squared * angle_squared / Scalar(384);
        sinc_half = Scalar(0.5) - angle_squared / Scalar(48) +
                    angle_squared * angle_squared / Scalar(3840);
    } else {
        const Scalar angle = sqrt(angle_squared);
        real_part = cos(angle / Scalar(2));
        sinc_half = sin(angle / Scalar(2)) / angle;
    }
    Quaternion<Scalar> result;
    result.w() = real_part;
    result.vec() = sinc_half * rotation_vector;
    return result;
}

/// \brief Logarithm map, the inverse of quaternion_exp: the rotation vector theta u (|theta| <= pi)
/// of the rotation q represents. q and -q give the same result (the shorter rotation is chosen).
/// \param q unit quaternion (not normalised here; asserted unit in debug builds).
/// \return theta u, radians; exact near the identity (series for sin(theta/2) / theta), so it is
/// smooth at q = 1, which autodiff scalars need.
template <typename Scalar> Vector3<Scalar> quaternion_log(const Quaternion<Scalar>& q) noexcept
{
    using std::abs;
    using std::atan2;
    using std::sqrt;
    COOPDYN_ASSERT(abs(q.squaredNorm() - Scalar(1)) < Scalar(1e-4), "quaternion_log needs a unit quaternion");
    // The representative with w >= 0 is the rotation by theta in [0, pi].
    const Scalar sign = q.w() < Scalar(0) ? Scalar(-1) : Scalar(1);
    const Scalar w = sign * q.w();
    const Vector3<Scalar> v = sign * q.vec();
    const Scalar sine_squared = v.squaredNorm();  // sin^2(theta / 2)
    // theta / sin(theta / 2) = 2 asin(s) / s; for s < 1e-4 its series 2 (1 + s^2 / 6 + 3 s^4 / 40) is
    // exact to double rounding.
    if (sine_squared < Scalar(1e-8)) {
        return (Scalar(2) * (Scalar(1) + sine_squared / Scalar(6) + Scalar(3) * sine_squared * sine_squared / Scalar(40))) * v;
    }
    const Scalar sine = sqrt(sine_squared);
    return (Scalar(2) * atan2(sine, w) / sine) * v;
}

/// \brief Orientation error dq = q (x) qd^-1 of paper (5), returned as (d_eta, d_eps).
/// \param orientation current unit quaternion q.
/// \param desired desired unit quaternion qd (its conjugate is used as the inverse).
template <typename Scalar>
Quaternion<Scalar> orientation_error(const Quaternion<Scalar>& orientation,
                                     const Quaternion<Scalar>& desired) noexcept
{
    return orientation * desired.conjugate();
}

/// \brief Rotational stiffness torque t_K = 2 d_eta kappa d_eps of paper (5).
/// Equal to kappa sin(theta) u for an error rotation of angle theta about u; invariant under
/// dq -> -dq, so no hemisphere correction is needed.
template <typename Scalar>
Vector3<Scalar> rotational_stiffness_torque(const Quaternion<Scalar>& error,
                                            const Scalar& stiffness) noexcept
{
    return (Scalar(2) * error.w() * stiffness) * error.vec();
}

/// \brief Potential of the rotational spring, U_rot = 2 kappa |d_eps|^2 = kappa (1 - cos theta),
/// paper (39). Its gradient on SO(3) (world-frame rotation) is rotational_stiffness_torque.
template <typename Scalar>
Scalar rotational_potential(const Quaternion<Scalar>& error, const Scalar& stiffness) noexcept
{
    return Scalar(2) * stiffness * error.vec().squaredNorm();
}

}  // namespace coopdyn
