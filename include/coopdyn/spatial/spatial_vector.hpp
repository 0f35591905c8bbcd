/// \file
/// \brief Motion (twist, acceleration) and Force (wrench) 6-vectors held as two 3-vectors, and
/// their change of reference point: the per-arm maps G_i^T and G_i of (10) and (24).
///
/// Conventions (docs/conventions.md): a motion is [v; w] (linear first), a force [f; t] (force
/// first, torque about the reference point), both in {w}.
///
/// Why two 3-vectors instead of a Vector6: the per-arm arithmetic is 3-vector algebra (cross
/// products, 3x3 blocks). On a Vector6, Eigen stores with 2- or 4-wide packets and the 3-vector
/// halves are then reloaded with loads that straddle those stores, which defeats store-to-load
/// forwarding; measured, the N = 2 interaction solve ran about 4x slower with Vector6.
#pragma once

#include "coopdyn/config.hpp"

namespace coopdyn {

namespace detail {
/// What Motion and Force share: two 3-vectors, conversion from and to stacked 6-vectors, and the
/// vector-space operations. Derived is Motion<Scalar> or Force<Scalar> (the two never mix).
template <typename Derived, typename ScalarType> struct SpatialVectorBase {
    using Scalar = ScalarType;
    Vector3<Scalar> linear = Vector3<Scalar>::Zero();
    Vector3<Scalar> angular = Vector3<Scalar>::Zero();

    /// From a stacked 6-vector [linear; angular].
    template <typename Six> static Derived from(const Eigen::MatrixBase<Six>& six) noexcept
    {
        EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(Six, 6);
        Derived result;
        result.linear = six.template head<3>();
        result.angular = six.template tail<3>();
        return result;
    }
    static Derived Zero() noexcept { return Derived{}; }
    /// The stacked 6-vector [linear; angular].
    Vector6<Scalar> vector() const noexcept
    {
        Vector6<Scalar> result;
        result << linear, angular;
        return result;
    }
    /// Writes [linear; angular] into a 6-vector expression (a segment of a stack, a Map).
    template <typename Six> void write_to(const Eigen::MatrixBase<Six>& six_out) const noexcept
    {
        EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(Six, 6);
        auto& six = const_cast<Eigen::MatrixBase<Six>&>(six_out);  // Eigen's idiom for writable expressions
        six.template head<3>() = linear;
        six.template tail<3>() = angular;
    }

    Derived& operator+=(const Derived& other) noexcept
    {
        linear += other.linear;
        angular += other.angular;
        return self();
    }
    Derived& operator-=(const Derived& other) noexcept
    {
        linear -= other.linear;
        angular -= other.angular;
        return self();
    }
    friend Derived operator+(Derived a, const Derived& b) noexcept { return a += b; }
    friend Derived operator-(Derived a, const Derived& b) noexcept { return a -= b; }
    friend Derived operator*(const Scalar& s, const Derived& a) noexcept { return make(s * a.linear, s * a.angular); }
    Derived operator-() const noexcept { return make(-linear, -angular); }

    static Derived make(const Vector3<Scalar>& linear_, const Vector3<Scalar>& angular_) noexcept
    {
        Derived result;
        result.linear = linear_;
        result.angular = angular_;
        return result;
    }

private:
    Derived& self() noexcept { return static_cast<Derived&>(*this); }
};
}  // namespace detail

/// \brief A motion vector [v; w]: a twist xdot or an acceleration xdd, in {w}.
template <typename Scalar> struct Motion : detail::SpatialVectorBase<Motion<Scalar>, Scalar> {
    /// The same rigid motion seen at the point displaced by r from the reference point:
    /// [v + w x r; w] = G(r)^T xdot, the twist of grasp point i for r = r_i (10).
    template <typename Derived> Motion at_point(const Eigen::MatrixBase<Derived>& r) const noexcept
    {
        EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(Derived, 3);
        return Motion::make(this->linear + this->angular.cross(r), this->angular);
    }
    /// Power of `force` on this motion, f . v + t . w (both about the same reference point).
    template <typename ForceType> Scalar dot(const ForceType& force) const noexcept
    {
        return this->linear.dot(force.linear) + this->angular.dot(force.angular);
    }
};

/// \brief A force vector [f; t]: a wrench, torque about the reference point, in {w}.
template <typename Scalar> struct Force : detail::SpatialVectorBase<Force<Scalar>, Scalar> {
    /// The same wrench, applied at the point displaced by r from the reference point, expressed
    /// about the reference point: [f; t + r x f] = G(r) h, the grasp map G_i of (24) for r = r_i.
    template <typename Derived> Force shifted(const Eigen::MatrixBase<Derived>& r) const noexcept
    {
        EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(Derived, 3);
        return Force::make(this->linear, this->angular + r.cross(this->linear));
    }
};

/// The acceleration of a point displaced by r on a body rotating at omega, beyond what its
/// angular and linear acceleration give: omega x (omega x r) = S(omega)^2 r, the translational
/// part of the constraint bias b_i of (13) (its rotational part is zero).
template <typename DerivedR, typename DerivedOmega>
Vector3<typename DerivedR::Scalar> centripetal_acceleration(const Eigen::MatrixBase<DerivedR>& r,
                                                            const Eigen::MatrixBase<DerivedOmega>& omega) noexcept
{
    EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(DerivedR, 3);
    EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(DerivedOmega, 3);
    return omega.cross(omega.cross(r));
}

}  // namespace coopdyn
