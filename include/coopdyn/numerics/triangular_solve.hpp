/// \file
/// \brief Solves with a small upper-triangular R in place: x <- R^-1 x (back substitution) and
/// x <- R^-T x (forward substitution), one right-hand side; docs/numerics.md.
///
/// Why not Eigen's triangularView<...>().solveInPlace: for each expression type it is called with
/// (a fixed-size block, its transpose) it instantiates Eigen's blocked triangular solver (panels,
/// a GEMV on the remainder, the BLAS-style mappers), which at the 6(K-1) rows of the controller's
/// projection costs more to compile than the arithmetic it does (docs/performance.md, "Compile
/// time and CI"). These are the plain loops of Eigen's unblocked kernel (the column-oriented axpy
/// for R^-1, dot products over R's columns for R^-T): the same results to rounding.
#pragma once

#include "coopdyn/config.hpp"

#include <Eigen/Core>

namespace coopdyn {

/// x <- R^-1 x for the upper triangle of the n x n matrix R (the strict lower triangle is not
/// read; R regular). Back substitution by columns: once x_k is known, column k of R times x_k is
/// subtracted from the entries above it (contiguous in a column-major R).
template <typename DerivedR, typename DerivedX>
void solve_upper_in_place(const Eigen::MatrixBase<DerivedR>& R, const Eigen::MatrixBase<DerivedX>& x_out) noexcept
{
    auto& x = const_cast<Eigen::MatrixBase<DerivedX>&>(x_out);
    COOPDYN_ASSERT(R.rows() == R.cols() && x.size() == R.rows(), "solve_upper_in_place: R n x n, x n");
    for (Index k = R.rows() - 1; k >= 0; --k) {
        const typename DerivedX::Scalar value = x(k) / R(k, k);
        x(k) = value;
        for (Index i = 0; i < k; ++i) {
            x(i) -= value * R(i, k);
        }
    }
}

/// x <- R^-T x for the upper triangle of the n x n matrix R (the strict lower triangle is not
/// read; R regular). Forward substitution on R^T: x_k = (x_k - R(0:k, k) . x(0:k)) / R_kk, the
/// dot product over column k of R (contiguous in a column-major R).
template <typename DerivedR, typename DerivedX>
void solve_upper_transpose_in_place(const Eigen::MatrixBase<DerivedR>& R,
                                    const Eigen::MatrixBase<DerivedX>& x_out) noexcept
{
    auto& x = const_cast<Eigen::MatrixBase<DerivedX>&>(x_out);
    COOPDYN_ASSERT(R.rows() == R.cols() && x.size() == R.rows(), "solve_upper_transpose_in_place: R n x n, x n");
    for (Index k = 0; k < R.rows(); ++k) {
        typename DerivedX::Scalar value = x(k);
        for (Index i = 0; i < k; ++i) {
            value -= R(i, k) * x(i);
        }
        x(k) = value / R(k, k);
    }
}

}  // namespace coopdyn
