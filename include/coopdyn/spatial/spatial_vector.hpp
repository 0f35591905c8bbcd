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
/// a x b written out in scalars. Why not Eigen's cross(): on the per-tick path the operands are
/// short-lived locals; Eigen's packet cross product (and GCC's SLP vectoriser on the expression
/// form) stores them as 2- or 4-wide packets that the next scalar loads straddle, a
/// store-to-load forwarding stall that cost g++ 12 about a factor of 2 on the interaction solve.
template <typename DerivedA, typename DerivedB>
COOPDYN_INLINE Vector3<typename DerivedA::Scalar> cross(const Eigen::MatrixBase<DerivedA>& a, const Eigen::MatrixBase<DerivedB>& b) noexcept
{
    using Scalar = typename DerivedA::Scalar;
    const Scalar ax = a(0), ay = a(1), az = a(2), bx = b(0), by = b(1), bz = b(2);
    return Vector3<Scalar>(ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx);
}

/// s a written out in scalars (see cross).
template <typename Derived>
COOPDYN_INLINE Vector3<typename Derived::Scalar> scaled(const typename Derived::Scalar& s, const Eigen::MatrixBase<Derived>& a) noexcept
{
    return Vector3<typename Derived::Scalar>(s * a(0), s * a(1), s * a(2));
}

/// What Motion and Force share: two 3-vectors, conversion from and to stacked 6-vectors, and the
/// vector-space operations. Derived is Motion<Scalar> or Force<Scalar> (the two never mix).
template <typename Derived, typename ScalarType> struct SpatialVectorBase {
    using Scalar = ScalarType;
    Vector3<Scalar> linear;
    Vector3<Scalar> angular;

    SpatialVectorBase() : linear(Scalar(0), Scalar(0), Scalar(0)), angular(Scalar(0), Scalar(0), Scalar(0)) {}
    /// From a stacked 6-vector [linear; angular].
    template <typename Six> static Derived from(const Eigen::MatrixBase<Six>& six) noexcept
    {
        EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(Six, 6);
        return make(six.template head<3>(), six.template tail<3>());
    }
    static Derived Zero() noexcept { return Derived{}; }
    /// The stacked 6-vector [linear; angular].
    Vector6<Scalar> vector() const noexcept
    {
        Vector6<Scalar> result;
        write_to(result);
        return result;
    }
    /// Writes [linear; angular] into a 6-vector expression (a segment of a stack, a Map).
    template <typename Six> void write_to(const Eigen::MatrixBase<Six>& six_out) const noexcept
    {
        EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(Six, 6);
        auto& six = const_cast<Eigen::MatrixBase<Six>&>(six_out);  // Eigen's idiom for writable expressions
        six(0) = linear(0);
        six(3) = angular(0);
        six(1) = linear(1);
        six(4) = angular(1);
        six(2) = linear(2);
        six(5) = angular(2);
    }

    // Element by element in scalars (see detail::cross for why not Eigen's expressions), and
    // written out rather than looped over k: g++ at -O2 (CMake's RelWithDebInfo, most distribution
    // builds) does not unroll a 3-iteration loop, so the 3-vectors stay in memory, indexed; with
    // the loops the N = 2 interaction solve took 217 ns at -O2 against 80 ns at -O3, written out
    // 83 ns at both (docs/performance.md).
    Derived& operator+=(const Derived& other) noexcept
    {
        linear(0) += other.linear(0);
        angular(0) += other.angular(0);
        linear(1) += other.linear(1);
        angular(1) += other.angular(1);
        linear(2) += other.linear(2);
        angular(2) += other.angular(2);
        return self();
    }
    Derived& operator-=(const Derived& other) noexcept
    {
        linear(0) -= other.linear(0);
        angular(0) -= other.angular(0);
        linear(1) -= other.linear(1);
        angular(1) -= other.angular(1);
        linear(2) -= other.linear(2);
        angular(2) -= other.angular(2);
        return self();
    }
    friend Derived operator+(Derived a, const Derived& b) noexcept { return a += b; }
    friend Derived operator-(Derived a, const Derived& b) noexcept { return a -= b; }
    friend Derived operator*(const Scalar& s, Derived a) noexcept
    {
        a.linear(0) *= s;
        a.angular(0) *= s;
        a.linear(1) *= s;
        a.angular(1) *= s;
        a.linear(2) *= s;
        a.angular(2) *= s;
        return a;
    }
    Derived operator-() const noexcept { return Scalar(-1) * static_cast<const Derived&>(*this); }

    template <typename DerivedLinear, typename DerivedAngular>
    static Derived make(const Eigen::MatrixBase<DerivedLinear>& linear_, const Eigen::MatrixBase<DerivedAngular>& angular_) noexcept
    {
        Derived result;
        result.linear(0) = linear_(0);
        result.angular(0) = angular_(0);
        result.linear(1) = linear_(1);
        result.angular(1) = angular_(1);
        result.linear(2) = linear_(2);
        result.angular(2) = angular_(2);
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
    template <typename Derived> COOPDYN_INLINE Motion at_point(const Eigen::MatrixBase<Derived>& r) const noexcept
    {
        EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(Derived, 3);
        const Vector3<Scalar> moment = detail::cross(this->angular, r);
        Motion result = *this;
        result.linear(0) += moment(0);
        result.linear(1) += moment(1);
        result.linear(2) += moment(2);
        return result;
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
    template <typename Derived> COOPDYN_INLINE Force shifted(const Eigen::MatrixBase<Derived>& r) const noexcept
    {
        EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(Derived, 3);
        const Vector3<Scalar> moment = detail::cross(r, this->linear);
        Force result = *this;
        result.angular(0) += moment(0);
        result.angular(1) += moment(1);
        result.angular(2) += moment(2);
        return result;
    }
};

/// The acceleration of a point displaced by r on a body rotating at omega, beyond what its
/// angular and linear acceleration give: omega x (omega x r) = S(omega)^2 r, the translational
/// part of the constraint bias b_i of (13) (its rotational part is zero).
template <typename DerivedR, typename DerivedOmega>
COOPDYN_INLINE Vector3<typename DerivedR::Scalar> centripetal_acceleration(const Eigen::MatrixBase<DerivedR>& r,
                                                            const Eigen::MatrixBase<DerivedOmega>& omega) noexcept
{
    EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(DerivedR, 3);
    EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(DerivedOmega, 3);
    return detail::cross(omega, detail::cross(omega, r));
}

}  // namespace coopdyn
