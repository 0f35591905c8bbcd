/// \file
/// \brief ArticulatedInertia: a general symmetric positive definite 6x6 inertia, such as an arm's
/// task-space inertia Lambda_i of (21), with the operations of SpatialInertia
/// (rigid_body_inertia.hpp): the shift of (31), sums, rotation into {w} (9), a structured solve.
/// Acts on motions [v; w] and gives forces [f; t] (docs/conventions.md). Fixed-size,
/// Scalar-generic, allocation-free.
#pragma once

#include "coopdyn/spatial/rigid_body_inertia.hpp"

namespace coopdyn {

/// \brief A general symmetric 6x6 inertia [[A, H^T], [H, C]] (A, C symmetric), the structure of
/// an articulated-body or task-space inertia such as Lambda_i of (21). Same operations as
/// SpatialInertia; the solve factorises the 6x6 matrix (L D L^T, written out).
template <typename ScalarType> class ArticulatedInertia {
public:
    using Scalar = ScalarType;

    ArticulatedInertia() : coupling_(Matrix3<Scalar>::Zero()) {}
    ArticulatedInertia(const Symmetric3<Scalar>& linear, const Matrix3<Scalar>& coupling,
                       const Symmetric3<Scalar>& angular)
        : linear_(linear), coupling_(coupling), angular_(angular)
    {
    }
    /// From a dense symmetric 6x6 matrix: its lower triangle is read.
    template <typename Derived> explicit ArticulatedInertia(const Eigen::MatrixBase<Derived>& matrix)
        : linear_(matrix.template topLeftCorner<3, 3>()),
          coupling_(matrix.template bottomLeftCorner<3, 3>()),
          angular_(matrix.template bottomRightCorner<3, 3>())
    {
        EIGEN_STATIC_ASSERT_MATRIX_SPECIFIC_SIZE(Derived, 6, 6);
    }
    /// A rigid-body inertia as a general one.
    explicit ArticulatedInertia(const SpatialInertia<Scalar>& inertia)
        : linear_(Symmetric3<Scalar>::scaled_identity(inertia.mass())),
          coupling_(skew(inertia.first_moment())),
          angular_(inertia.rotational())
    {
    }
    explicit ArticulatedInertia(const CentralInertia<Scalar>& inertia) : ArticulatedInertia(SpatialInertia<Scalar>(inertia)) {}
    static ArticulatedInertia Zero() { return ArticulatedInertia(); }

    /// A (top-left), H (bottom-left), C (bottom-right).
    const Symmetric3<Scalar>& linear() const noexcept { return linear_; }
    const Matrix3<Scalar>& coupling() const noexcept { return coupling_; }
    const Symmetric3<Scalar>& angular() const noexcept { return angular_; }

    Matrix6<Scalar> matrix() const
    {
        Matrix6<Scalar> result;
        result.template topLeftCorner<3, 3>() = linear_.matrix();
        result.template bottomLeftCorner<3, 3>() = coupling_;
        result.template topRightCorner<3, 3>() = coupling_.transpose();
        result.template bottomRightCorner<3, 3>() = angular_.matrix();
        return result;
    }

    /// X [v; w] = [A v + H^T w; H v + C w], in scalars (see detail::cross): g++ 12 kept the
    /// Eigen 3x3 products out of line and reloaded their results as straddling packets.
    COOPDYN_INLINE Force<Scalar> operator*(const Motion<Scalar>& motion) const noexcept
    {
        const Vector3<Scalar> a_v = linear_ * motion.linear;
        const Vector3<Scalar> c_w = angular_ * motion.angular;
        const Vector3<Scalar> h_v = coupling_times(motion.linear);
        const Vector3<Scalar> ht_w = coupling_transpose_times(motion.angular);
        return Force<Scalar>::make(Vector3<Scalar>(a_v(0) + ht_w(0), a_v(1) + ht_w(1), a_v(2) + ht_w(2)),
                                   Vector3<Scalar>(h_v(0) + c_w(0), h_v(1) + c_w(1), h_v(2) + c_w(2)));
    }

    /// X [a; 0] = [A a; H a].
    template <typename Derived>
    COOPDYN_INLINE Force<Scalar> apply_translation(const Eigen::MatrixBase<Derived>& a) const noexcept
    {
        EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(Derived, 3);
        return Force<Scalar>::make(linear_ * a, coupling_times(a));
    }

    /// G(r) X G(r)^T (see SpatialInertia::shifted): with S = S(r),
    /// A' = A, H' = H + S A, C' = C + S A S^T + S H^T + H S^T.
    template <typename Derived> ArticulatedInertia shifted(const Eigen::MatrixBase<Derived>& r) const
    {
        ArticulatedInertia result;
        result.add_shifted(*this, r);
        return result;
    }
    /// this += other.shifted(r), entry by entry in scalars (the composite inertia's accumulation
    /// on the per-tick path; dense Eigen 3x3 products here cost g++ 12 an out-of-line call and
    /// packet reloads per arm, docs/performance.md). With P = S A and K = H + P / 2:
    /// S A S^T + S H^T + H S^T = K S^T + S K^T, because P S^T = S A S^T = S P^T (A symmetric);
    /// row i of K S^T is r x k_i (k_i row i of K), so the increment of C is 3 cross products and
    /// its lower triangle, exactly symmetric. 36 products per arm instead of 81.
    template <typename Derived>
    COOPDYN_INLINE void add_shifted(const ArticulatedInertia& other, const Eigen::MatrixBase<Derived>& r_in) noexcept
    {
        EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(Derived, 3);
        // Copies: other may be *this.
        const Vector3<Scalar> r(r_in(0), r_in(1), r_in(2));
        const Symmetric3<Scalar> a = other.linear_;
        // P = S A, column j = r x (column j of A).
        const Vector3<Scalar> p0 = detail::cross(r, Vector3<Scalar>(a.xx, a.yx, a.zx));
        const Vector3<Scalar> p1 = detail::cross(r, Vector3<Scalar>(a.yx, a.yy, a.zy));
        const Vector3<Scalar> p2 = detail::cross(r, Vector3<Scalar>(a.zx, a.zy, a.zz));
        const Matrix3<Scalar>& h = other.coupling_;
        const Scalar half(0.5);
        // t_i = r x k_i, k_i = row i of K = H + P / 2.
        const Vector3<Scalar> t0 = detail::cross(
            r, Vector3<Scalar>(h(0, 0) + half * p0(0), h(0, 1) + half * p1(0), h(0, 2) + half * p2(0)));
        const Vector3<Scalar> t1 = detail::cross(
            r, Vector3<Scalar>(h(1, 0) + half * p0(1), h(1, 1) + half * p1(1), h(1, 2) + half * p2(1)));
        const Vector3<Scalar> t2 = detail::cross(
            r, Vector3<Scalar>(h(2, 0) + half * p0(2), h(2, 1) + half * p1(2), h(2, 2) + half * p2(2)));
        const Symmetric3<Scalar> increment(Scalar(2) * t0(0), t1(0) + t0(1), t2(0) + t0(2), Scalar(2) * t1(1),
                                           t2(1) + t1(2), Scalar(2) * t2(2));
        // Written out, not looped: g++ -O2 does not unroll 3-iteration loops (docs/performance.md).
        coupling_(0, 0) += h(0, 0) + p0(0), coupling_(0, 1) += h(0, 1) + p1(0), coupling_(0, 2) += h(0, 2) + p2(0);
        coupling_(1, 0) += h(1, 0) + p0(1), coupling_(1, 1) += h(1, 1) + p1(1), coupling_(1, 2) += h(1, 2) + p2(1);
        coupling_(2, 0) += h(2, 0) + p0(2), coupling_(2, 1) += h(2, 1) + p1(2), coupling_(2, 2) += h(2, 2) + p2(2);
        angular_ += other.angular_;
        angular_ += increment;
        linear_ += a;
    }
    template <typename Derived> void add_shifted(const SpatialInertia<Scalar>& other, const Eigen::MatrixBase<Derived>& r)
    {
        *this += ArticulatedInertia(other.shifted(r));
    }
    template <typename Derived> void add_shifted(const CentralInertia<Scalar>& other, const Eigen::MatrixBase<Derived>& r)
    {
        *this += ArticulatedInertia(other.shifted(r));
    }

    template <typename Derived> ArticulatedInertia rotated(const Eigen::MatrixBase<Derived>& rotation) const
    {
        return ArticulatedInertia(linear_.rotated(rotation), Matrix3<Scalar>(rotation * coupling_ * rotation.transpose()),
                                  angular_.rotated(rotation));
    }

    ArticulatedInertia& operator+=(const ArticulatedInertia& other) noexcept
    {
        linear_ += other.linear_;
        coupling_ += other.coupling_;
        angular_ += other.angular_;
        return *this;
    }
    ArticulatedInertia& operator+=(const SpatialInertia<Scalar>& other) noexcept
    {
        return *this += ArticulatedInertia(other);
    }
    friend ArticulatedInertia operator+(ArticulatedInertia a, const ArticulatedInertia& b) noexcept { return a += b; }

    /// Solves X a = force by an L D L^T factorisation of the 6x6 matrix (no explicit inverse).
    /// Precondition (asserted in debug builds): X positive definite. Always inlined, and only the
    /// lower triangle FixedLdlt reads is written (not matrix()): out of line, g++ 12 passed the
    /// factor and the 6-vectors through memory.
    COOPDYN_INLINE Motion<Scalar> solve(const Force<Scalar>& force) const noexcept
    {
        Matrix6<Scalar> lower;
        write_lower(lower);
        FixedLdlt<Scalar, 6> factor;
        const bool positive_definite = factor.compute(lower);
        COOPDYN_ASSERT(positive_definite, "ArticulatedInertia::solve needs a positive definite inertia");
        (void)positive_definite;
        Vector6<Scalar> solution;
        force.write_to(solution);
        factor.solve_in_place(solution);
        return Motion<Scalar>::from(solution);
    }

    Scalar kinetic_energy(const Motion<Scalar>& twist) const noexcept
    {
        return Scalar(0.5) * twist.dot((*this) * twist);
    }

    template <typename Other> ArticulatedInertia<Other> cast() const
    {
        return ArticulatedInertia<Other>(linear_.template cast<Other>(), coupling_.template cast<Other>(),
                                         angular_.template cast<Other>());
    }

private:
    /// H v and H^T w in scalars (see operator*).
    template <typename Derived> COOPDYN_INLINE Vector3<Scalar> coupling_times(const Eigen::MatrixBase<Derived>& v) const noexcept
    {
        const Scalar x = v(0), y = v(1), z = v(2);
        return Vector3<Scalar>(coupling_(0, 0) * x + coupling_(0, 1) * y + coupling_(0, 2) * z,
                               coupling_(1, 0) * x + coupling_(1, 1) * y + coupling_(1, 2) * z,
                               coupling_(2, 0) * x + coupling_(2, 1) * y + coupling_(2, 2) * z);
    }
    COOPDYN_INLINE Vector3<Scalar> coupling_transpose_times(const Vector3<Scalar>& w) const noexcept
    {
        const Scalar x = w(0), y = w(1), z = w(2);
        return Vector3<Scalar>(coupling_(0, 0) * x + coupling_(1, 0) * y + coupling_(2, 0) * z,
                               coupling_(0, 1) * x + coupling_(1, 1) * y + coupling_(2, 1) * z,
                               coupling_(0, 2) * x + coupling_(1, 2) * y + coupling_(2, 2) * z);
    }
    /// The lower triangle of matrix() (the upper one is left unwritten).
    COOPDYN_INLINE void write_lower(Matrix6<Scalar>& out) const noexcept
    {
        write_lower(linear_, 0, out);
        out(3, 0) = coupling_(0, 0), out(3, 1) = coupling_(0, 1), out(3, 2) = coupling_(0, 2);
        out(4, 0) = coupling_(1, 0), out(4, 1) = coupling_(1, 1), out(4, 2) = coupling_(1, 2);
        out(5, 0) = coupling_(2, 0), out(5, 1) = coupling_(2, 1), out(5, 2) = coupling_(2, 2);
        write_lower(angular_, 3, out);
    }
    /// The lower triangle of the diagonal block `block` at (corner, corner).
    static COOPDYN_INLINE void write_lower(const Symmetric3<Scalar>& block, int corner, Matrix6<Scalar>& out) noexcept
    {
        out(corner, corner) = block.xx;
        out(corner + 1, corner) = block.yx;
        out(corner + 2, corner) = block.zx;
        out(corner + 1, corner + 1) = block.yy;
        out(corner + 2, corner + 1) = block.zy;
        out(corner + 2, corner + 2) = block.zz;
    }

    Symmetric3<Scalar> linear_;
    Matrix3<Scalar> coupling_;
    Symmetric3<Scalar> angular_;
};

}  // namespace coopdyn
