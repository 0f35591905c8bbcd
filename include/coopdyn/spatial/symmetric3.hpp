/// \file
/// \brief Symmetric3: a symmetric 3x3 matrix stored as its six independent entries (the
/// rotational part of a spatial inertia, a rotational weight, a stiffness block).
///
/// Why not Matrix3: the rotational inertias on the 1 kHz path are summed, shifted and solved, and
/// every one of those operations needs only the lower triangle. Six named scalars halve the
/// arithmetic and, unlike a Matrix3, give the compilers' vectorisers nothing to pack into
/// 2- or 4-wide stores that later 3-vector loads straddle (a store-to-load forwarding stall that
/// cost g++ 12 a factor of about 1.6 on the interaction solve).
#pragma once

#include "coopdyn/config.hpp"

namespace coopdyn {

/// \brief Symmetric 3x3 matrix [[xx, yx, zx], [yx, yy, zy], [zx, zy, zz]], Scalar-generic,
/// fixed-size, allocation-free.
template <typename ScalarType> class Symmetric3 {
public:
    using Scalar = ScalarType;

    /// Entries of the lower triangle, column by column.
    Scalar xx, yx, zx, yy, zy, zz;

    /// Zero matrix.
    Symmetric3() : xx(0), yx(0), zx(0), yy(0), zy(0), zz(0) {}
    Symmetric3(const Scalar& xx_, const Scalar& yx_, const Scalar& zx_, const Scalar& yy_, const Scalar& zy_,
               const Scalar& zz_)
        : xx(xx_), yx(yx_), zx(zx_), yy(yy_), zy(zy_), zz(zz_)
    {
    }
    /// From the lower triangle of a 3x3 matrix (the upper triangle is not read).
    template <typename Derived> explicit Symmetric3(const Eigen::MatrixBase<Derived>& matrix)
        : xx(matrix(0, 0)), yx(matrix(1, 0)), zx(matrix(2, 0)), yy(matrix(1, 1)), zy(matrix(2, 1)), zz(matrix(2, 2))
    {
        static_assert(detail::sizes_agree(Derived::RowsAtCompileTime, 3) && detail::sizes_agree(Derived::ColsAtCompileTime, 3),
                      "a Symmetric3 is built from a 3x3 matrix");
        COOPDYN_ASSERT(matrix.rows() == 3 && matrix.cols() == 3, "a Symmetric3 is built from a 3x3 matrix");
    }

    static Symmetric3 Zero() { return Symmetric3(); }
    static Symmetric3 Identity() { return diagonal(Scalar(1), Scalar(1), Scalar(1)); }
    static Symmetric3 diagonal(const Scalar& x, const Scalar& y, const Scalar& z)
    {
        return Symmetric3(x, Scalar(0), Scalar(0), y, Scalar(0), z);
    }
    /// s I3.
    static Symmetric3 scaled_identity(const Scalar& s) { return diagonal(s, s, s); }

    /// S(a) S(a)^T = |a|^2 I3 - a a^T: the parallel-axis term of (25) and (31) per unit mass.
    template <typename Derived> static Symmetric3 skew_square(const Eigen::MatrixBase<Derived>& a)
    {
        EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(Derived, 3);
        const Scalar x = a(0), y = a(1), z = a(2);
        return Symmetric3(y * y + z * z, -y * x, -z * x, x * x + z * z, -z * y, x * x + y * y);
    }

    /// The dense 3x3 matrix.
    Matrix3<Scalar> matrix() const
    {
        Matrix3<Scalar> result;
        // clang-format off
        result << xx, yx, zx,
                  yx, yy, zy,
                  zx, zy, zz;
        // clang-format on
        return result;
    }

    /// S x.
    template <typename Derived> Vector3<Scalar> operator*(const Eigen::MatrixBase<Derived>& x) const noexcept
    {
        EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(Derived, 3);
        return Vector3<Scalar>(xx * x(0) + yx * x(1) + zx * x(2), yx * x(0) + yy * x(1) + zy * x(2),
                               zx * x(0) + zy * x(1) + zz * x(2));
    }

    Symmetric3& operator+=(const Symmetric3& other) noexcept
    {
        xx += other.xx, yx += other.yx, zx += other.zx, yy += other.yy, zy += other.zy, zz += other.zz;
        return *this;
    }
    Symmetric3& operator-=(const Symmetric3& other) noexcept
    {
        xx -= other.xx, yx -= other.yx, zx -= other.zx, yy -= other.yy, zy -= other.zy, zz -= other.zz;
        return *this;
    }
    Symmetric3& operator*=(const Scalar& s) noexcept
    {
        xx *= s, yx *= s, zx *= s, yy *= s, zy *= s, zz *= s;
        return *this;
    }
    friend Symmetric3 operator+(Symmetric3 a, const Symmetric3& b) noexcept { return a += b; }
    friend Symmetric3 operator-(Symmetric3 a, const Symmetric3& b) noexcept { return a -= b; }
    friend Symmetric3 operator*(const Scalar& s, Symmetric3 a) noexcept { return a *= s; }
    Symmetric3 operator-() const noexcept { return Symmetric3(-xx, -yx, -zx, -yy, -zy, -zz); }

    /// this += m S(a) S(a)^T = m (|a|^2 I3 - a a^T), the parallel-axis term, entry by entry.
    template <typename Derived> void add_skew_square(const Scalar& m, const Eigen::MatrixBase<Derived>& a) noexcept
    {
        EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(Derived, 3);
        const Scalar x = a(0), y = a(1), z = a(2);
        const Scalar mx = m * x, my = m * y, mz = m * z;
        xx += my * y + mz * z;
        yy += mx * x + mz * z;
        zz += mx * x + my * y;
        yx -= my * x;
        zx -= mz * x;
        zy -= mz * y;
    }

    /// R S R^T: the same matrix expressed in the frame that R rotates into (e.g. a body-frame
    /// inertia in {w}, (9)). Entry by entry: the rows of R S from the six entries (27
    /// multiply-adds), then only the six distinct (R S)_a . R_b (18), instead of the 54 of the
    /// dense product R S R^T, whose result would then be symmetric only up to rounding.
    template <typename Derived> COOPDYN_INLINE Symmetric3 rotated(const Eigen::MatrixBase<Derived>& rotation) const noexcept
    {
        EIGEN_STATIC_ASSERT_MATRIX_SPECIFIC_SIZE(Derived, 3, 3);
        const Scalar r00 = rotation(0, 0), r01 = rotation(0, 1), r02 = rotation(0, 2);
        const Scalar r10 = rotation(1, 0), r11 = rotation(1, 1), r12 = rotation(1, 2);
        const Scalar r20 = rotation(2, 0), r21 = rotation(2, 1), r22 = rotation(2, 2);
        return congruence(r00, r01, r02, r10, r11, r12, r20, r21, r22);
    }
    /// R^T S R: the inverse of rotated(R) for an orthonormal R (e.g. a {w} inertia into the body
    /// frame). The same six-entry product with R^T.
    template <typename Derived>
    COOPDYN_INLINE Symmetric3 rotated_back(const Eigen::MatrixBase<Derived>& rotation) const noexcept
    {
        EIGEN_STATIC_ASSERT_MATRIX_SPECIFIC_SIZE(Derived, 3, 3);
        const Scalar r00 = rotation(0, 0), r01 = rotation(0, 1), r02 = rotation(0, 2);
        const Scalar r10 = rotation(1, 0), r11 = rotation(1, 1), r12 = rotation(1, 2);
        const Scalar r20 = rotation(2, 0), r21 = rotation(2, 1), r22 = rotation(2, 2);
        return congruence(r00, r10, r20, r01, r11, r21, r02, r12, r22);
    }
    /// R diag(d) R^T, the rotated(R) of diagonal(d(0), d(1), d(2)) in 27 multiply-adds (R diag(d)
    /// is R with scaled columns): a principal-axes inertia in another frame.
    template <typename DerivedD, typename DerivedR>
    static COOPDYN_INLINE Symmetric3 rotated_diagonal(const Eigen::MatrixBase<DerivedD>& d,
                                                      const Eigen::MatrixBase<DerivedR>& rotation) noexcept
    {
        EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(DerivedD, 3);
        EIGEN_STATIC_ASSERT_MATRIX_SPECIFIC_SIZE(DerivedR, 3, 3);
        const Scalar d0 = d(0), d1 = d(1), d2 = d(2);
        const Scalar r00 = rotation(0, 0), r01 = rotation(0, 1), r02 = rotation(0, 2);
        const Scalar r10 = rotation(1, 0), r11 = rotation(1, 1), r12 = rotation(1, 2);
        const Scalar r20 = rotation(2, 0), r21 = rotation(2, 1), r22 = rotation(2, 2);
        // Row a of R diag(d).
        const Scalar a00 = r00 * d0, a01 = r01 * d1, a02 = r02 * d2;
        const Scalar a10 = r10 * d0, a11 = r11 * d1, a12 = r12 * d2;
        const Scalar a20 = r20 * d0, a21 = r21 * d1, a22 = r22 * d2;
        return Symmetric3(a00 * r00 + a01 * r01 + a02 * r02, a10 * r00 + a11 * r01 + a12 * r02,
                          a20 * r00 + a21 * r01 + a22 * r02, a10 * r10 + a11 * r11 + a12 * r12,
                          a20 * r10 + a21 * r11 + a22 * r12, a20 * r20 + a21 * r21 + a22 * r22);
    }

    Scalar trace() const noexcept { return xx + yy + zz; }
    Scalar determinant() const noexcept
    {
        return xx * (yy * zz - zy * zy) - yx * (yx * zz - zy * zx) + zx * (yx * zy - yy * zx);
    }

    /// Solves S x = b by the adjugate (Cramer's rule): x = adj(S) b / det(S).
    ///
    /// Why not a Cholesky factorisation: at 3x3 the factorisation is a serial chain of three
    /// divisions (each pivot waits for the previous column), while the six cofactors are
    /// independent and need one division; on the 1 kHz path this halves the latency of the
    /// block-diagonal interaction solve. Accuracy: the forward error is about
    /// cond(S) (lambda_max / lambda_mid) eps. For a rigid body's rotational inertia the triangle
    /// inequality lambda_max <= lambda_min + lambda_mid bounds the second factor by 2, so it is as
    /// accurate as the factorisation (~ cond(S) eps, tested up to cond 1e8). For a general SPD
    /// matrix with two small eigenvalues it degrades towards cond(S)^2 eps (and the determinant
    /// can lose its sign from cond ~ 1e8 on), where a Cholesky factorisation stays at cond(S) eps.
    /// Precondition (asserted in debug builds): S positive definite, by Sylvester's criterion on
    /// the leading minors the cofactors already hold.
    template <typename Derived>
    COOPDYN_INLINE Vector3<Scalar> solve(const Eigen::MatrixBase<Derived>& b) const noexcept
    {
        EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(Derived, 3);
        const Scalar c00 = yy * zz - zy * zy;
        const Scalar c10 = zx * zy - yx * zz;
        const Scalar c20 = yx * zy - zx * yy;
        const Scalar c11 = xx * zz - zx * zx;
        const Scalar c21 = zx * yx - xx * zy;
        const Scalar c22 = xx * yy - yx * yx;
        const Scalar det = xx * c00 + yx * c10 + zx * c20;
        COOPDYN_ASSERT(xx > Scalar(0) && c22 > Scalar(0) && det > Scalar(0),
                       "Symmetric3::solve needs a positive definite matrix");
        const Scalar inverse_det = Scalar(1) / det;
        const Scalar b0 = b(0), b1 = b(1), b2 = b(2);
        return Vector3<Scalar>((c00 * b0 + c10 * b1 + c20 * b2) * inverse_det,
                               (c10 * b0 + c11 * b1 + c21 * b2) * inverse_det,
                               (c20 * b0 + c21 * b1 + c22 * b2) * inverse_det);
    }

    /// S^-1 (Precondition as solve).
    Symmetric3 inverse() const noexcept
    {
        const Scalar c00 = yy * zz - zy * zy;
        const Scalar c10 = zx * zy - yx * zz;
        const Scalar c20 = yx * zy - zx * yy;
        const Scalar inverse_det = Scalar(1) / (xx * c00 + yx * c10 + zx * c20);
        return Symmetric3(c00 * inverse_det, c10 * inverse_det, c20 * inverse_det, (xx * zz - zx * zx) * inverse_det,
                          (zx * yx - xx * zy) * inverse_det, (xx * yy - yx * yx) * inverse_det);
    }

    /// Positive definite, by Sylvester's criterion (exact for exactly representable entries;
    /// a matrix that is singular up to rounding may pass or fail).
    bool is_positive_definite() const noexcept
    {
        return xx > Scalar(0) && xx * yy - yx * yx > Scalar(0) && determinant() > Scalar(0);
    }

    template <typename Other> Symmetric3<Other> cast() const
    {
        return Symmetric3<Other>(Other(xx), Other(yx), Other(zx), Other(yy), Other(zy), Other(zz));
    }
    bool operator==(const Symmetric3& other) const
    {
        return xx == other.xx && yx == other.yx && zx == other.zx && yy == other.yy && zy == other.zy &&
               zz == other.zz;
    }
    bool operator!=(const Symmetric3& other) const { return !(*this == other); }

private:
    /// A S A^T for A = [[a00, a01, a02], [a10, a11, a12], [a20, a21, a22]]: rows of A S, then the
    /// six distinct entries (A S)_a . A_b.
    COOPDYN_INLINE Symmetric3 congruence(const Scalar& a00, const Scalar& a01, const Scalar& a02, const Scalar& a10,
                                         const Scalar& a11, const Scalar& a12, const Scalar& a20, const Scalar& a21,
                                         const Scalar& a22) const noexcept
    {
        // Row a of A S (S's columns: (xx, yx, zx), (yx, yy, zy), (zx, zy, zz)).
        const Scalar p00 = a00 * xx + a01 * yx + a02 * zx, p01 = a00 * yx + a01 * yy + a02 * zy,
                     p02 = a00 * zx + a01 * zy + a02 * zz;
        const Scalar p10 = a10 * xx + a11 * yx + a12 * zx, p11 = a10 * yx + a11 * yy + a12 * zy,
                     p12 = a10 * zx + a11 * zy + a12 * zz;
        const Scalar p20 = a20 * xx + a21 * yx + a22 * zx, p21 = a20 * yx + a21 * yy + a22 * zy,
                     p22 = a20 * zx + a21 * zy + a22 * zz;
        return Symmetric3(p00 * a00 + p01 * a01 + p02 * a02, p10 * a00 + p11 * a01 + p12 * a02,
                          p20 * a00 + p21 * a01 + p22 * a02, p10 * a10 + p11 * a11 + p12 * a12,
                          p20 * a10 + p21 * a11 + p22 * a12, p20 * a20 + p21 * a21 + p22 * a22);
    }
};

}  // namespace coopdyn
