/// \file
/// \brief FixedLdlt: the square-root-free Cholesky factorisation A = L D L^T (L unit lower
/// triangular, D diagonal positive) of a small fixed-size SPD matrix, written out so that every loop
/// has a compile-time trip count (the spatial layer's 3x3 and 6x6 solves, the load distribution's
/// 3x3 J*_o, the rigid plant's weld solve); docs/numerics.md. Its L L^T sibling is FixedLlt
/// (numerics/fixed_llt.hpp).
///
/// Why not Eigen::LLT / Eigen::LDLT: for 3x3 and 6x6 they run general blocked (LDLT: pivoting)
/// algorithms with run-time loop bounds; at these sizes the loop overhead dominates the arithmetic.
///
/// Why L D L^T rather than L L^T: the factorisation is a serial chain, each column waiting for
/// the previous column's pivot. L L^T puts a square root and a division on that chain per column,
/// L D L^T only a division (about half the latency), and needs no sqrt at all (no errno call-out,
/// and friendlier to autodiff scalars). Only the lower triangle of the input is read.
#pragma once

#include "coopdyn/config.hpp"

#include <Eigen/Core>

// Ask for complete unrolling of the fixed-trip-count loops below (the inner bounds depend on the
// outer index, which compilers do not always unroll on their own).
#if defined(__clang__)
#define COOPDYN_LDLT_UNROLL _Pragma("unroll")
#elif defined(__GNUC__)
#define COOPDYN_LDLT_UNROLL _Pragma("GCC unroll 8")
#else
#define COOPDYN_LDLT_UNROLL
#endif

namespace coopdyn {

/// A = L D L^T of a Size x Size SPD matrix (lower triangle read), with in-place solves of any
/// number of right-hand sides.
template <typename Scalar, int Size> class FixedLdlt {
public:
    using Matrix = Eigen::Matrix<Scalar, Size, Size>;
    using Vector = Eigen::Matrix<Scalar, Size, 1>;

    /// Factorise the lower triangle of `matrix`. Returns false when a pivot is not positive
    /// (matrix not positive definite, or NaN); the factor is then unusable.
    ///
    /// Always inlined, like solve_in_place(): a caller that factorises several independent
    /// matrices in turn (the rigid plant's two arms) gets their serial pivot chains interleaved
    /// only when both calls are inlined into it, and an out-of-line call would also have to
    /// store and reload the factor through memory.
    template <typename Derived> COOPDYN_INLINE bool compute(const Eigen::MatrixBase<Derived>& matrix) noexcept
    {
        // Column by column: d_j = a_jj - sum_k l_jk^2 d_k, l_ij = (a_ij - sum_k l_ik l_jk d_k) / d_j.
        // scaled_(i, k) = l_ik d_k is kept alongside l_ik so that each update is one product.
        bool positive_definite = true;
        COOPDYN_LDLT_UNROLL
        for (int column = 0; column < Size; ++column) {
            Scalar pivot = matrix(column, column);
            COOPDYN_LDLT_UNROLL
            for (int k = 0; k < column; ++k) {
                pivot -= lower_(column, k) * scaled_(column, k);
            }
            // No early return: every entry is written on every path (so nothing needs zeroing),
            // and the result of an indefinite matrix is reported, not used.
            positive_definite = positive_definite && pivot > Scalar(0);
            pivots_(column) = pivot;
            inverse_diagonal_(column) = Scalar(1) / pivot;
            COOPDYN_LDLT_UNROLL
            for (int row = column + 1; row < Size; ++row) {
                Scalar value = matrix(row, column);
                COOPDYN_LDLT_UNROLL
                for (int k = 0; k < column; ++k) {
                    value -= lower_(row, k) * scaled_(column, k);
                }
                scaled_(row, column) = value;  // l_ij d_j
                lower_(row, column) = value * inverse_diagonal_(column);
            }
        }
        return positive_definite;
    }

    /// The pivots d_j of the last compute() (D's diagonal; the squares of L L^T's diagonal). Their
    /// smallest, relative to the matrix's diagonal, tells how close to singular the matrix is
    /// (regular_pivots, numerics/pivot_policy.hpp).
    const Vector& pivots() const noexcept { return pivots_; }

    /// Solve A x = rhs with the stored factor (solve_in_place on a copy of rhs).
    template <typename Derived> Vector solve(const Eigen::MatrixBase<Derived>& rhs) const noexcept
    {
        Vector solution = rhs;
        solve_in_place(solution);
        return solution;
    }

    /// X <- A^-1 X for Size-row X with any number of columns: L Y = X, then L^T X = D^-1 Y, a
    /// whole row of X per step. With a row-major X each step is then one multiply-add across
    /// all right-hand sides, which vectorises; a vector X gets the scalar substitution.
    template <typename Derived> COOPDYN_INLINE void solve_in_place(const Eigen::MatrixBase<Derived>& X_out) const noexcept
    {
        static_assert(Derived::RowsAtCompileTime == Size || Derived::RowsAtCompileTime == Eigen::Dynamic,
                      "FixedLdlt::solve_in_place: X must have Size rows");
        // Eigen's idiom for writing through an expression argument (a block, a map).
        auto& X = const_cast<Eigen::MatrixBase<Derived>&>(X_out);
        COOPDYN_ASSERT(X.rows() == Size, "FixedLdlt::solve_in_place: X must have Size rows");
        COOPDYN_LDLT_UNROLL
        for (int row = 1; row < Size; ++row) {
            COOPDYN_LDLT_UNROLL
            for (int k = 0; k < row; ++k) {
                X.row(row) -= lower_(row, k) * X.row(k);
            }
        }
        COOPDYN_LDLT_UNROLL
        for (int row = Size - 1; row >= 0; --row) {
            X.row(row) *= inverse_diagonal_(row);
            COOPDYN_LDLT_UNROLL
            for (int k = row + 1; k < Size; ++k) {
                X.row(row) -= lower_(k, row) * X.row(k);
            }
        }
    }

private:
    // Only the strictly lower parts are written and read; left uninitialised on purpose (zeroing
    // them costs stores on every tick and buys nothing).
    Matrix lower_;             // l_ij, i > j (unit diagonal implied)
    Matrix scaled_;            // l_ij d_j, i > j
    Vector pivots_;            // d_j
    Vector inverse_diagonal_;  // 1 / d_j
};

}  // namespace coopdyn

#undef COOPDYN_LDLT_UNROLL
