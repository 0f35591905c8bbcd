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

/// R a written out in scalars (see cross): a 3-vector in the frame that R rotates into (R's
/// columns are the rotated frame's axes in the target frame, as Pose::rotation() rotates body
/// vectors into {w}).
template <typename DerivedR, typename DerivedA>
COOPDYN_INLINE Vector3<typename DerivedA::Scalar> rotate(const Eigen::MatrixBase<DerivedR>& rotation,
                                                         const Eigen::MatrixBase<DerivedA>& a) noexcept
{
    using Scalar = typename DerivedA::Scalar;
    const Scalar x = a(0), y = a(1), z = a(2);
    return Vector3<Scalar>(rotation(0, 0) * x + rotation(0, 1) * y + rotation(0, 2) * z,
                           rotation(1, 0) * x + rotation(1, 1) * y + rotation(1, 2) * z,
                           rotation(2, 0) * x + rotation(2, 1) * y + rotation(2, 2) * z);
}

/// R^T a written out in scalars (see cross): the inverse of rotate for an orthonormal R.
template <typename DerivedR, typename DerivedA>
COOPDYN_INLINE Vector3<typename DerivedA::Scalar> rotate_back(const Eigen::MatrixBase<DerivedR>& rotation,
                                                              const Eigen::MatrixBase<DerivedA>& a) noexcept
{
    using Scalar = typename DerivedA::Scalar;
    const Scalar x = a(0), y = a(1), z = a(2);
    return Vector3<Scalar>(rotation(0, 0) * x + rotation(1, 0) * y + rotation(2, 0) * z,
                           rotation(0, 1) * x + rotation(1, 1) * y + rotation(2, 1) * z,
                           rotation(0, 2) * x + rotation(1, 2) * y + rotation(2, 2) * z);
}

/// out(row + 0..2, j) = R in(row + 0..2, j) (R^T when Back) for every column j. Each column's
/// three entries are read before any is written, so out may be in itself.
template <bool Back, typename DerivedR, typename DerivedIn, typename DerivedOut>
COOPDYN_INLINE void rotate_three_rows(const Eigen::MatrixBase<DerivedR>& rotation, const Eigen::MatrixBase<DerivedIn>& in,
                                      Eigen::MatrixBase<DerivedOut>& out, Index row) noexcept
{
    using Scalar = typename DerivedOut::Scalar;
    // R's entries once, as locals: otherwise the compiler must assume each store to out may change
    // them and reload all nine per column.
    const Scalar r00 = rotation(0, 0), r01 = rotation(0, 1), r02 = rotation(0, 2);
    const Scalar r10 = rotation(1, 0), r11 = rotation(1, 1), r12 = rotation(1, 2);
    const Scalar r20 = rotation(2, 0), r21 = rotation(2, 1), r22 = rotation(2, 2);
    for (Index j = 0; j < in.cols(); ++j) {
        const Scalar x = in(row, j), y = in(row + 1, j), z = in(row + 2, j);
        if constexpr (Back) {
            out(row, j) = r00 * x + r10 * y + r20 * z;
            out(row + 1, j) = r01 * x + r11 * y + r21 * z;
            out(row + 2, j) = r02 * x + r12 * y + r22 * z;
        } else {
            out(row, j) = r00 * x + r01 * y + r02 * z;
            out(row + 1, j) = r10 * x + r11 * y + r12 * z;
            out(row + 2, j) = r20 * x + r21 * y + r22 * z;
        }
    }
}

template <bool Back, typename DerivedR, typename DerivedIn, typename DerivedOut>
COOPDYN_INLINE void rotate_stack_impl(const Eigen::MatrixBase<DerivedR>& rotation, const Eigen::MatrixBase<DerivedIn>& in,
                                 const Eigen::MatrixBase<DerivedOut>& out_) noexcept
{
    EIGEN_STATIC_ASSERT_MATRIX_SPECIFIC_SIZE(DerivedR, 3, 3);
    static_assert(DerivedIn::RowsAtCompileTime == Eigen::Dynamic || DerivedIn::RowsAtCompileTime % 6 == 0,
                  "a stack of spatial vectors has 6K rows");
    static_assert(sizes_agree(DerivedIn::RowsAtCompileTime, DerivedOut::RowsAtCompileTime) &&
                      sizes_agree(DerivedIn::ColsAtCompileTime, DerivedOut::ColsAtCompileTime),
                  "rotate_stack: in and out differ in size");
    auto& out = const_cast<Eigen::MatrixBase<DerivedOut>&>(out_);  // Eigen's idiom for writable expressions
    COOPDYN_ASSERT(in.rows() % 6 == 0 && out.rows() == in.rows() && out.cols() == in.cols(),
                   "rotate_stack: in must have 6K rows and out its size");
    for (Index block = 0; block < in.rows() / 3; ++block) {
        rotate_three_rows<Back>(rotation, in, out, 3 * block);
    }
}

template <bool Back, typename DerivedR, typename DerivedIn, typename DerivedOut>
COOPDYN_INLINE void rotate_stack_per_block_impl(const Eigen::MatrixBase<DerivedR>& rotations, const Eigen::MatrixBase<DerivedIn>& in,
                                           const Eigen::MatrixBase<DerivedOut>& out_) noexcept
{
    static_assert(DerivedR::RowsAtCompileTime == 3 || DerivedR::RowsAtCompileTime == Eigen::Dynamic,
                  "rotate_stack_per_block: the rotations are 3 x 3K, [R_1 ... R_K]");
    static_assert(sizes_agree(DerivedIn::RowsAtCompileTime, DerivedOut::RowsAtCompileTime) &&
                      sizes_agree(DerivedIn::ColsAtCompileTime, DerivedOut::ColsAtCompileTime),
                  "rotate_stack_per_block: in and out differ in size");
    static_assert(DerivedR::ColsAtCompileTime == Eigen::Dynamic || DerivedIn::RowsAtCompileTime == Eigen::Dynamic ||
                      2 * DerivedR::ColsAtCompileTime == DerivedIn::RowsAtCompileTime,
                  "rotate_stack_per_block: K rotations (3 x 3K) for a stack of 6K rows");
    auto& out = const_cast<Eigen::MatrixBase<DerivedOut>&>(out_);
    COOPDYN_ASSERT(rotations.rows() == 3 && 2 * rotations.cols() == in.rows() && out.rows() == in.rows() &&
                       out.cols() == in.cols(),
                   "rotate_stack_per_block: K rotations (3 x 3K) for in of 6K rows, out of in's size");
    for (Index block = 0; block < in.rows() / 6; ++block) {
        const auto rotation = rotations.template middleCols<3>(3 * block);
        rotate_three_rows<Back>(rotation, in, out, 6 * block);
        rotate_three_rows<Back>(rotation, in, out, 6 * block + 3);
    }
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

    /// diag(R, R) x = [R linear; R angular]: the same vector expressed in the frame R rotates into
    /// (for R = R_o, the object's orientation, from the object frame into {w}). The reference
    /// point does not move, so both halves turn alike (docs/spatial.md, "Rotation").
    template <typename DerivedR> COOPDYN_INLINE Derived rotated(const Eigen::MatrixBase<DerivedR>& rotation) const noexcept
    {
        EIGEN_STATIC_ASSERT_MATRIX_SPECIFIC_SIZE(DerivedR, 3, 3);
        return make(detail::rotate(rotation, linear), detail::rotate(rotation, angular));
    }
    /// diag(R^T, R^T) x = [R^T linear; R^T angular]: the inverse of rotated(R) for an orthonormal R
    /// (for R = R_ci, a wrench in {w} into contact frame {c_i}).
    template <typename DerivedR> COOPDYN_INLINE Derived rotated_back(const Eigen::MatrixBase<DerivedR>& rotation) const noexcept
    {
        EIGEN_STATIC_ASSERT_MATRIX_SPECIFIC_SIZE(DerivedR, 3, 3);
        return make(detail::rotate_back(rotation, linear), detail::rotate_back(rotation, angular));
    }

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

/// \brief out = blkdiag(R, R, ..., R) in: every 6-vector [linear; angular] of a stack of K turned
/// by R, as Motion::rotated and Force::rotated do for one.
///
/// `in` has 6K rows (K fixed or dynamic) and any number of columns: a stack of K motions or
/// forces, or a 6K x m matrix whose columns are such stacks (for the internal-wrench basis,
/// B(R_o p) = blkdiag(R6, ..., R6) B(p) with R6 = blkdiag(R_o, R_o); docs/control.md). `out` has
/// `in`'s size and may be `in` itself. noexcept, allocation-free, written out in scalars (see
/// detail::cross).
template <typename DerivedR, typename DerivedIn, typename DerivedOut>
void rotate_stack(const Eigen::MatrixBase<DerivedR>& rotation, const Eigen::MatrixBase<DerivedIn>& in,
                  const Eigen::MatrixBase<DerivedOut>& out) noexcept
{
    detail::rotate_stack_impl<false>(rotation, in, out);
}

/// out = blkdiag(R^T, R^T, ..., R^T) in: the inverse of rotate_stack for an orthonormal R (same
/// sizes; out may be in).
template <typename DerivedR, typename DerivedIn, typename DerivedOut>
void rotate_stack_back(const Eigen::MatrixBase<DerivedR>& rotation, const Eigen::MatrixBase<DerivedIn>& in,
                       const Eigen::MatrixBase<DerivedOut>& out) noexcept
{
    detail::rotate_stack_impl<true>(rotation, in, out);
}

/// \brief out = blkdiag(R_1, R_1, R_2, R_2, ..., R_K, R_K) in: block i (rows 6i..6i+5) turned by
/// its own R_i, `rotations` = [R_1 ... R_K] (3 x 3K, the layout of ControllerData::contact_rotations,
/// docs/conventions.md "Stacking"). Sizes and aliasing as rotate_stack.
template <typename DerivedR, typename DerivedIn, typename DerivedOut>
void rotate_stack_per_block(const Eigen::MatrixBase<DerivedR>& rotations, const Eigen::MatrixBase<DerivedIn>& in,
                            const Eigen::MatrixBase<DerivedOut>& out) noexcept
{
    detail::rotate_stack_per_block_impl<false>(rotations, in, out);
}

/// out = blkdiag(R_1^T, R_1^T, ..., R_K^T, R_K^T) in: the inverse of rotate_stack_per_block (e.g.
/// the contact wrenches from {w} into their contact frames {c_i}).
template <typename DerivedR, typename DerivedIn, typename DerivedOut>
void rotate_stack_per_block_back(const Eigen::MatrixBase<DerivedR>& rotations, const Eigen::MatrixBase<DerivedIn>& in,
                                 const Eigen::MatrixBase<DerivedOut>& out) noexcept
{
    detail::rotate_stack_per_block_impl<true>(rotations, in, out);
}

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
