/// \file
/// \brief Eigenvalues of a small real symmetric matrix by the cyclic Jacobi method
/// (docs/numerics.md). The library's input checks use it to test that an inertia or a gain is
/// positive (semi-)definite and to read a body's principal moments.
///
/// Why not Eigen's SelfAdjointEigenSolver: it reduces to tridiagonal form with blocked Householder
/// reflections, whose templates cost about 3 s of compile time per matrix size in every file that
/// validates a model (docs/performance.md, "Compile time"); these checks run once, at construction,
/// on 3 x 3 and 6 x 6 matrices, where a few Jacobi sweeps are as accurate and as fast as anything.
///
/// Each rotation J(p, q, theta) zeroes a_pq of A' = J^T A J (Golub & Van Loan, Matrix
/// Computations, 4th ed., Algorithm 8.5.2 with the stable choice of t = tan(theta)); a cyclic sweep
/// visits every pair p < q, and the off-diagonal mass converges quadratically. The eigenvalues are
/// accurate to a few units of rounding times ||A||_F.
#pragma once

#include "coopdyn/config.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace coopdyn::numerics {

/// \brief Eigenvalues of the symmetric matrix `matrix` (n x n, fixed or dynamic size; only
/// double), in ascending order. Only the symmetric part (A + A^T) / 2 is used. Allocates only for
/// dynamic sizes; a NaN or infinite entry gives NaN eigenvalues.
template <typename Derived>
Eigen::Matrix<double, Derived::RowsAtCompileTime, 1> symmetric_eigenvalues(const Eigen::MatrixBase<Derived>& matrix)
{
    static_assert(std::is_same<typename Derived::Scalar, double>::value, "symmetric_eigenvalues takes doubles");
    using Square = Eigen::Matrix<double, Derived::RowsAtCompileTime, Derived::RowsAtCompileTime>;
    COOPDYN_ASSERT(matrix.rows() == matrix.cols(), "symmetric_eigenvalues needs a square matrix");
    const Index n = matrix.rows();
    Square a = (matrix + matrix.transpose()) / 2.0;
    const double frobenius_squared = a.squaredNorm();
    if (!std::isfinite(frobenius_squared)) {
        return Eigen::Matrix<double, Derived::RowsAtCompileTime, 1>::Constant(
            n, std::numeric_limits<double>::quiet_NaN());
    }
    const double eps = std::numeric_limits<double>::epsilon();
    constexpr int sweep_limit = 64;  // quadratic convergence needs fewer than 10 at these sizes
    for (int sweep = 0; sweep < sweep_limit; ++sweep) {
        double off_diagonal_squared = 0.0;
        for (Index q = 1; q < n; ++q) {
            for (Index p = 0; p < q; ++p) {
                off_diagonal_squared += 2.0 * a(p, q) * a(p, q);
            }
        }
        if (!(off_diagonal_squared > eps * eps * frobenius_squared)) {
            break;  // converged (or the zero matrix)
        }
        for (Index p = 0; p + 1 < n; ++p) {
            for (Index q = p + 1; q < n; ++q) {
                const double apq = a(p, q);
                if (apq == 0.0) {
                    continue;
                }
                // t = tan(theta) of the smaller rotation, from cot(2 theta) = (a_qq - a_pp) / (2 a_pq).
                const double cot_two_theta = (a(q, q) - a(p, p)) / (2.0 * apq);
                const double t = std::copysign(1.0, cot_two_theta) /
                                 (std::abs(cot_two_theta) + std::hypot(cot_two_theta, 1.0));
                const double c = 1.0 / std::sqrt(t * t + 1.0);
                const double s = t * c;
                for (Index k = 0; k < n; ++k) {  // A <- A J
                    const double akp = a(k, p);
                    const double akq = a(k, q);
                    a(k, p) = c * akp - s * akq;
                    a(k, q) = s * akp + c * akq;
                }
                for (Index k = 0; k < n; ++k) {  // A <- J^T A
                    const double apk = a(p, k);
                    const double aqk = a(q, k);
                    a(p, k) = c * apk - s * aqk;
                    a(q, k) = s * apk + c * aqk;
                }
                a(p, q) = a(q, p) = 0.0;  // zero by construction; drop the rounding residue
            }
        }
    }
    Eigen::Matrix<double, Derived::RowsAtCompileTime, 1> eigenvalues = a.diagonal();
    std::sort(eigenvalues.data(), eigenvalues.data() + n);
    return eigenvalues;
}

}  // namespace coopdyn::numerics
