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
/// per-tick path of the paper's rigid grasp is interaction_wrenches. For full row rank A,
/// try_udwadia_kalaba_full_rank is the same solution through the constraint-space inertia
/// A M^-1 A^T: faster, allocation-free with fixed sizes, and it returns the multipliers.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/numerics/pivot_policy.hpp"

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

/// \brief Full-row-rank form of (18): the multipliers lambda of h = A^T lambda and the constrained
/// accelerations xdd, from the constraint-space inertia S = A M^-1 A^T (the Schur complement of
/// the KKT system [[M, A^T], [A, 0]]):
///
///     S lambda = b - A M^-1 hSigma,        xdd = M^-1 (hSigma + A^T lambda).
///
/// With full row rank A this is (18) exactly (h = A^T lambda is the same wrench); it costs two
/// Cholesky factorisations (n x n and m x m) instead of a complete orthogonal decomposition, gives
/// lambda directly (the wrench each constraint row carries, e.g. a welded palm's contact wrench),
/// and with fixed sizes allocates nothing. A rank test replaces the pseudo-inverse: when M is not
/// positive definite, or S is singular by the pivot policy (a squared Cholesky pivot at or below
/// 1000 eps times S's largest diagonal entry, numerics/pivot_policy.hpp: A rank-deficient or
/// nearly so, e.g. an arm at a singularity), it returns false and leaves both
/// outputs untouched: use udwadia_kalaba, which handles any rank, then.
/// \param lambda_out m, the multipliers (h = A^T lambda).
/// \param acceleration_out n, the constrained accelerations.
template <typename DerivedM, typename DerivedA, typename DerivedB, typename DerivedSigma, typename DerivedLambda,
          typename DerivedAcceleration>
bool try_udwadia_kalaba_full_rank(const Eigen::MatrixBase<DerivedM>& M, const Eigen::MatrixBase<DerivedA>& A,
                                  const Eigen::MatrixBase<DerivedB>& b, const Eigen::MatrixBase<DerivedSigma>& h_sigma,
                                  const Eigen::MatrixBase<DerivedLambda>& lambda_out,
                                  const Eigen::MatrixBase<DerivedAcceleration>& acceleration_out) noexcept
{
    using Scalar = typename DerivedM::Scalar;
    constexpr int Size = DerivedM::ColsAtCompileTime;
    constexpr int Rows = DerivedA::RowsAtCompileTime;
    using Square = Eigen::Matrix<Scalar, Size, Size>;
    using Vector = Eigen::Matrix<Scalar, Size, 1>;
    using ConstraintsTransposed = Eigen::Matrix<Scalar, Size, Rows>;
    using ConstraintSpace = Eigen::Matrix<Scalar, Rows, Rows>;
    using RowVector = Eigen::Matrix<Scalar, Rows, 1>;
    COOPDYN_ASSERT(M.rows() == M.cols() && A.cols() == M.rows() && b.size() == A.rows() && h_sigma.size() == M.rows(),
                   "try_udwadia_kalaba_full_rank: M n x n, A m x n, b m, h_sigma n");
    COOPDYN_ASSERT(lambda_out.size() == A.rows() && acceleration_out.size() == M.rows(),
                   "try_udwadia_kalaba_full_rank: lambda m, acceleration n");

    const Eigen::LLT<Square> cholesky(M);
    if (cholesky.info() != Eigen::Success) {
        return false;
    }
    // In the Cholesky factor's coordinates: Y = L^-1 A^T and u = L^-1 hSigma, so that
    // S = A M^-1 A^T = Y^T Y, A M^-1 hSigma = Y^T u and xdd = L^-T (u + Y lambda): two triangular
    // solves of vectors instead of two full solves with M.
    ConstraintsTransposed scaled_transposed = A.transpose();
    cholesky.matrixL().solveInPlace(scaled_transposed);
    const ConstraintSpace constraint_space = scaled_transposed.transpose().lazyProduct(scaled_transposed);
    // S must be regular by the pivot policy (numerics/pivot_policy.hpp): a redundant constraint
    // leaves S singular up to rounding, with a pivot of rounding size that LLT accepts.
    const Eigen::LLT<ConstraintSpace> constraint_cholesky(constraint_space);
    if (constraint_cholesky.info() != Eigen::Success ||
        !regular_pivots(constraint_cholesky.matrixLLT().diagonal().cwiseAbs2(), constraint_space.diagonal().maxCoeff())) {
        return false;
    }
    Vector scaled = h_sigma;
    cholesky.matrixL().solveInPlace(scaled);
    const RowVector lambda = constraint_cholesky.solve(RowVector(b - scaled_transposed.transpose() * scaled));
    scaled.noalias() += scaled_transposed * lambda;
    cholesky.matrixU().solveInPlace(scaled);
    const_cast<Eigen::MatrixBase<DerivedLambda>&>(lambda_out) = lambda;
    const_cast<Eigen::MatrixBase<DerivedAcceleration>&>(acceleration_out) = scaled;
    return true;
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
