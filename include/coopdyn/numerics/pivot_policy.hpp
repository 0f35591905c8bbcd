/// \file
/// \brief The one rank policy of coopdyn: when a pivot of a factorised symmetric positive
/// (semi-)definite matrix counts as zero. Every solver that must refuse a singular matrix asks it
/// (the projected dynamics' Jr Jr^T and task matrix, the controller's check of the joint inertia,
/// the QP's Hessian, the Udwadia-Kalaba constraint-space matrix, the load distribution's J*_o,
/// the rigid plant's arm mobility); docs/numerics.md, "Pivot policy".
///
/// The rule. A is n x n symmetric, factorised without pivoting as L D L^T, L L^T (d_j = L_jj^2) or
/// through a QR of a factor, A = X^T X = R^T R (d_j = R_jj^2). A is regular when every squared
/// pivot exceeds the tolerance times A's largest diagonal entry:
///
///     d_j > tau max_i A_ii  for every j,      tau = pivot_tolerance = 1000 eps.
///
/// Why this scale: max_i A_ii lies between lambda_max(A) / n and lambda_max(A), and every pivot of
/// an SPD matrix lies between lambda_min(A) and max_i A_ii. So a matrix with cond(A) < 1 / tau
/// always passes, and a refused one has cond(A) >= 1 / tau: the rule never refuses a
/// well-conditioned matrix, whatever the unit of A, and it does not depend on the row order or
/// on how large the other pivots happen to be. (An unpivoted factor is not rank revealing, so it
/// can pass a matrix whose cond(A) exceeds 1 / tau; the load distribution, which must catch every
/// exactly singular J*_o, pivots its 3 x 3 factorisation for that reason.)
///
/// Why 1000 eps (2.2e-13 in double, 1.2e-4 in float): the rounding noise in the pivots of an n x n
/// factorisation (and in forming a Gram matrix) is about n eps max_i A_ii, so a matrix that is
/// singular up to rounding has a pivot of that size or below: 1000 eps stays above it for every
/// size coopdyn factorises (n <= 30 per tick) with a wide margin. Above the tolerance the solve's
/// relative error bound eps cond(A) is at most 1e-3, so a matrix the rule lets through still gives
/// three correct digits. One value serves every use: no solver needs another scale.
///
/// NaN: every comparison is written so that a NaN pivot or scale refuses the matrix.
#pragma once

#include "coopdyn/config.hpp"

#include <Eigen/Core>

#include <type_traits>

namespace coopdyn {

/// The number of units of roundoff in the pivot tolerance (docs/numerics.md, "Pivot policy").
inline constexpr int pivot_tolerance_ulps = 1000;

/// tau = 1000 eps of Scalar's precision: squared pivots at or below tau max_i A_ii count as zero.
template <typename Scalar> Scalar pivot_tolerance() noexcept
{
    return Scalar(pivot_tolerance_ulps) * Scalar(Eigen::NumTraits<Scalar>::epsilon());
}

/// One squared pivot against the policy: d > tau scale (false for NaN d or scale).
/// \param scale max_i A_ii of the factorised matrix (or 1 when d is already divided by it).
template <typename Scalar> bool regular_pivot(const Scalar& squared_pivot, const Scalar& scale) noexcept
{
    return squared_pivot > pivot_tolerance<Scalar>() * scale;
}

/// Every squared pivot d_j against the policy: d_j > tau scale (false if any is NaN, or the scale).
/// \param squared_pivots D's diagonal of L D L^T, or the squares of L's (L L^T) or R's (QR) diagonal.
/// \param scale max_i A_ii of the factorised matrix A.
template <typename DerivedPivots>
bool regular_pivots(const Eigen::MatrixBase<DerivedPivots>& squared_pivots,
                    const typename DerivedPivots::Scalar& scale) noexcept
{
    using Scalar = typename DerivedPivots::Scalar;
    const Scalar floor = pivot_tolerance<Scalar>() * scale;
    for (Index j = 0; j < squared_pivots.size(); ++j) {
        if (!(squared_pivots(j) > floor)) {
            return false;
        }
    }
    return true;
}

/// An L L^T factorisation (Eigen::LLT, FixedLlt, DynamicLlt) of a regular matrix: info() is
/// Success and regular_pivots(diag(L)^2, max_i A_ii), with A_ii = |row i of L|^2 read from the
/// factor itself (the factorised matrix need not be kept).
template <typename Factor> bool regular_llt(const Factor& factor) noexcept
{
    if (factor.info() != Eigen::Success) {
        return false;
    }
    const auto& lower = factor.matrixLLT();  // L in the lower triangle
    using Scalar = typename std::decay_t<decltype(lower)>::Scalar;
    Scalar scale(0);
    for (Index i = 0; i < lower.rows(); ++i) {
        const Scalar diagonal = lower.row(i).head(i + 1).squaredNorm();
        if (diagonal > scale || diagonal != diagonal) {
            scale = diagonal;  // the largest; a NaN is kept (nothing compares greater than it)
        }
    }
    return regular_pivots(lower.diagonal().cwiseAbs2(), scale);
}

/// The R of a QR X = Q R (n x n upper triangle, the top rows of householder_qr_in_place's result)
/// of a regular A = X^T X = R^T R: regular_pivots(diag(R)^2, max_j |column j of R|^2), since
/// A_jj = |column j of X|^2 = |column j of R|^2.
template <typename DerivedR> bool regular_triangular_factor(const Eigen::MatrixBase<DerivedR>& r) noexcept
{
    using Scalar = typename DerivedR::Scalar;
    Scalar scale(0);
    for (Index j = 0; j < r.cols(); ++j) {
        const Scalar diagonal = r.col(j).head(j + 1).squaredNorm();
        if (diagonal > scale || diagonal != diagonal) {
            scale = diagonal;  // the largest; a NaN is kept (nothing compares greater than it)
        }
    }
    return regular_pivots(r.diagonal().cwiseAbs2(), scale);
}

}  // namespace coopdyn
