/// \file
/// \brief Cholesky factorisation for small fixed-size SPD matrices, in its square-root-free form
/// A = L D L^T (L unit lower triangular, D diagonal positive), written out so that the compiler
/// unrolls it completely.
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

// Ask for complete unrolling of the fixed-trip-count loops below (the inner bounds depend on the
// outer index, which compilers do not always unroll on their own).
#if defined(__clang__)
#define COOPDYN_DETAIL_UNROLL _Pragma("unroll")
#elif defined(__GNUC__)
#define COOPDYN_DETAIL_UNROLL _Pragma("GCC unroll 8")
#else
#define COOPDYN_DETAIL_UNROLL
#endif

namespace coopdyn::detail {

template <typename Scalar, int Size> class FixedCholesky {
public:
    using Matrix = Eigen::Matrix<Scalar, Size, Size>;
    using Vector = Eigen::Matrix<Scalar, Size, 1>;

    /// Factorise the lower triangle of `matrix`. Returns false when a pivot is not positive
    /// (matrix not positive definite, or NaN); the factor is then unusable.
    template <typename Derived> bool compute(const Eigen::MatrixBase<Derived>& matrix) noexcept
    {
        // Column by column: d_j = a_jj - sum_k l_jk^2 d_k, l_ij = (a_ij - sum_k l_ik l_jk d_k) / d_j.
        // scaled_(i, k) = l_ik d_k is kept alongside l_ik so that each update is one product.
        bool positive_definite = true;
        COOPDYN_DETAIL_UNROLL
        for (int column = 0; column < Size; ++column) {
            Scalar pivot = matrix(column, column);
            COOPDYN_DETAIL_UNROLL
            for (int k = 0; k < column; ++k) {
                pivot -= lower_(column, k) * scaled_(column, k);
            }
            // No early return: every entry is written on every path (so nothing needs zeroing),
            // and the result of an indefinite matrix is reported, not used.
            positive_definite = positive_definite && pivot > Scalar(0);
            inverse_diagonal_(column) = Scalar(1) / pivot;
            COOPDYN_DETAIL_UNROLL
            for (int row = column + 1; row < Size; ++row) {
                Scalar value = matrix(row, column);
                COOPDYN_DETAIL_UNROLL
                for (int k = 0; k < column; ++k) {
                    value -= lower_(row, k) * scaled_(column, k);
                }
                scaled_(row, column) = value;  // l_ij d_j
                lower_(row, column) = value * inverse_diagonal_(column);
            }
        }
        return positive_definite;
    }

    /// Solve A x = rhs with the stored factor: L y = rhs, then L^T x = D^-1 y.
    template <typename Derived> Vector solve(const Eigen::MatrixBase<Derived>& rhs) const noexcept
    {
        Vector solution;
        COOPDYN_DETAIL_UNROLL
        for (int row = 0; row < Size; ++row) {
            Scalar value = rhs(row);
            COOPDYN_DETAIL_UNROLL
            for (int k = 0; k < row; ++k) {
                value -= lower_(row, k) * solution(k);
            }
            solution(row) = value;
        }
        COOPDYN_DETAIL_UNROLL
        for (int row = Size - 1; row >= 0; --row) {
            Scalar value = solution(row) * inverse_diagonal_(row);
            COOPDYN_DETAIL_UNROLL
            for (int k = row + 1; k < Size; ++k) {
                value -= lower_(k, row) * solution(k);
            }
            solution(row) = value;
        }
        return solution;
    }

private:
    // Only the strictly lower parts are written and read; left uninitialised on purpose (zeroing
    // them costs stores on every tick and buys nothing).
    Matrix lower_;             // l_ij, i > j (unit diagonal implied)
    Matrix scaled_;            // l_ij d_j, i > j
    Vector inverse_diagonal_;  // 1 / d_j
};

}  // namespace coopdyn::detail

#undef COOPDYN_DETAIL_UNROLL
