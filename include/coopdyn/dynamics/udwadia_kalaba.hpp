/// \file
/// \brief Generic Udwadia-Kalaba constrained dynamics (docs/dynamics.md, paper (18)-(19)).
///
/// For unconstrained dynamics M xdd = hSigma and constraints A xdd = b, the constrained
/// accelerations minimise Gauss's function (xdd - M^-1 hSigma)^T M (xdd - M^-1 hSigma) over
/// A xdd = b (19). The minimiser is xdd = M^-1 (hSigma + h) with the constraint wrench (18)
///
///     h = M^(1/2) (A M^(-1/2))^+ (b - A M^-1 hSigma).
///
/// Any square-root factor of M gives the same h; this uses the Cholesky factor M = L L^T, so
/// h = L (A L^-T)^+ (b - A M^-1 hSigma). The pseudo-inverse is applied through a complete
/// orthogonal decomposition (minimum-norm least squares), so redundant, rank-deficient constraint
/// rows are handled: they give the same accelerations as the independent rows alone.
///
/// This is the reference solver for any SPD M and any consistent A, b: O(n^3), and it allocates
/// (for fixed sizes only Eigen 3.4's one temporary in CompleteOrthogonalDecomposition::solve); the
/// per-tick path of the paper's rigid grasp is interaction_wrenches.
#pragma once

#include "coopdyn/config.hpp"

#include <Eigen/Cholesky>
#include <Eigen/QR>

namespace coopdyn {

/// \brief Constraint wrench h of paper (18) for M xdd = hSigma + h subject to A xdd = b.
/// \param M n x n symmetric positive definite inertia.
/// \param A m x n constraint matrix (any rank; rows may be redundant).
/// \param b m constraint right-hand side; must be consistent (b in the range of A).
/// \param h_sigma n, the wrench of the unconstrained dynamics.
/// \return h, n entries; the constrained accelerations are M^-1 (hSigma + h). Sized like M's
/// columns: fixed-size arguments give fixed-size work (e.g. the dual-arm box's rigid plant,
/// 20 x 20 and 12 x 20).
template <typename DerivedM, typename DerivedA, typename DerivedB, typename DerivedSigma>
Eigen::Matrix<typename DerivedM::Scalar, DerivedM::ColsAtCompileTime, 1>
udwadia_kalaba(const Eigen::MatrixBase<DerivedM>& M, const Eigen::MatrixBase<DerivedA>& A,
               const Eigen::MatrixBase<DerivedB>& b, const Eigen::MatrixBase<DerivedSigma>& h_sigma)
{
    using Scalar = typename DerivedM::Scalar;
    constexpr int Size = DerivedM::ColsAtCompileTime;
    constexpr int Rows = DerivedA::RowsAtCompileTime;
    using Square = Eigen::Matrix<Scalar, Size, Size>;
    using Vector = Eigen::Matrix<Scalar, Size, 1>;
    using Constraints = Eigen::Matrix<Scalar, Rows, Size>;
    using ConstraintsTransposed = Eigen::Matrix<Scalar, Size, Rows>;
    using RowVector = Eigen::Matrix<Scalar, Rows, 1>;
    COOPDYN_ASSERT(M.rows() == M.cols(), "M must be square");
    COOPDYN_ASSERT(A.cols() == M.rows(), "A must have as many columns as M");
    COOPDYN_ASSERT(b.size() == A.rows(), "b must have as many entries as A has rows");
    COOPDYN_ASSERT(h_sigma.size() == M.rows(), "h_sigma must have as many entries as M has rows");

    const Eigen::LLT<Square> cholesky(M);
    COOPDYN_ASSERT(cholesky.info() == Eigen::Success, "M must be symmetric positive definite");

    // A L^-T, computed as (L^-1 A^T)^T.
    const Constraints scaled_constraints =
        cholesky.matrixL().solve(ConstraintsTransposed(A.transpose())).transpose();
    const Vector unconstrained_acceleration = cholesky.solve(Vector(h_sigma));
    const RowVector constraint_violation = b - A * unconstrained_acceleration;

    // (A L^-T)^+ e: the minimum-norm least-squares solution of (A L^-T) y = e.
    const Eigen::CompleteOrthogonalDecomposition<Constraints> decomposition(scaled_constraints);
    return cholesky.matrixL() * Vector(decomposition.solve(constraint_violation));
}

/// \brief Constrained accelerations xdd = M^-1 (hSigma + h) with h from udwadia_kalaba.
template <typename DerivedM, typename DerivedA, typename DerivedB, typename DerivedSigma>
Eigen::Matrix<typename DerivedM::Scalar, DerivedM::ColsAtCompileTime, 1>
udwadia_kalaba_accelerations(const Eigen::MatrixBase<DerivedM>& M, const Eigen::MatrixBase<DerivedA>& A,
                             const Eigen::MatrixBase<DerivedB>& b,
                             const Eigen::MatrixBase<DerivedSigma>& h_sigma)
{
    using Square = Eigen::Matrix<typename DerivedM::Scalar, DerivedM::ColsAtCompileTime, DerivedM::ColsAtCompileTime>;
    const Eigen::LLT<Square> cholesky(M);
    return cholesky.solve(h_sigma + udwadia_kalaba(M, A, b, h_sigma));
}

}  // namespace coopdyn
