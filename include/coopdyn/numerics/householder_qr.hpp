/// \file
/// \brief Householder QR of a tall matrix (rows >= cols) for fixed or dynamic sizes, in place and
/// allocation-free: householder_qr_in_place (A = H_0 ... H_{n-1} [R; 0]) and householder_q (the
/// leading columns of Q = H_0 ... H_{n-1}); docs/numerics.md. The projected dynamics use it twice
/// per tick: for an orthonormal basis of the internal wrenches (6K x 6(K-1)) and for Jr^T = Q1 R
/// (Q x 6(K-1); errata E10, docs/control.md).
///
/// The convention is Eigen's HouseholderQR's (Householder vectors with a unit first entry,
/// makeHouseholder's R_kk = -sign(a_kk) |a_k|), so R and Q equal Eigen's to rounding.
#pragma once

#include "coopdyn/config.hpp"

#include <Eigen/Core>

#include <cmath>
#include <limits>

namespace coopdyn {

/// Householder QR of A (rows >= cols) in place: A becomes R (upper triangle; zeros below),
/// reflector k is H_k = I - tau_k v_k v_k^T with v_k stored full-length in reflectors.col(k)
/// (zeros above row k, 1 at row k), so that A_in = H_0 ... H_{cols-1} [R; 0]. The convention is
/// Eigen's (makeHouseholder: R_kk = -sign(a_kk) |a_k|), written over whole columns so that every
/// operation is a fixed-length, vectorised dot or axpy; Eigen's HouseholderQR works on shrinking
/// dynamic blocks, which cost more than the arithmetic at these sizes.
///
/// Shapes: A m x n with m >= n; reflectors m x n (overwritten); tau n (overwritten; tau_k = 0 when
/// column k is already triangular, H_k = I). A column that is zero below the diagonal is left as
/// it is, so R_kk may then have either sign (as Eigen's).
template <typename DerivedA, typename DerivedV, typename DerivedTau>
void householder_qr_in_place(const Eigen::MatrixBase<DerivedA>& A_out, const Eigen::MatrixBase<DerivedV>& reflectors_out,
                             const Eigen::MatrixBase<DerivedTau>& tau_out) noexcept
{
    using Scalar = typename DerivedA::Scalar;
    auto& A = const_cast<Eigen::MatrixBase<DerivedA>&>(A_out);
    auto& reflectors = const_cast<Eigen::MatrixBase<DerivedV>&>(reflectors_out);
    auto& tau = const_cast<Eigen::MatrixBase<DerivedTau>&>(tau_out);
    const Index rows = A.rows();
    for (Index k = 0; k < A.cols(); ++k) {
        auto v = reflectors.col(k);
        v = A.col(k);
        v.head(k).setZero();
        const Scalar c0 = v(k);
        v(k) = Scalar(0);
        const Scalar tail_squared_norm = v.squaredNorm();
        Scalar beta = c0;
        if (tail_squared_norm <= (std::numeric_limits<Scalar>::min)()) {
            tau(k) = Scalar(0);  // already triangular in this column: H_k = I
        } else {
            beta = std::sqrt(c0 * c0 + tail_squared_norm);
            if (c0 >= Scalar(0)) {
                beta = -beta;
            }
            v /= c0 - beta;
            tau(k) = (beta - c0) / beta;
        }
        v(k) = Scalar(1);
        for (Index j = k + 1; j < A.cols(); ++j) {
            A.col(j) -= (tau(k) * v.dot(A.col(j))) * v;
        }
        A.col(k).tail(rows - k - 1).setZero();
        A(k, k) = beta;
    }
}

/// The leading Q.cols() columns of H_0 ... H_{m-1} (householder_qr_in_place), accumulated from
/// the last reflector: Q <- H_k Q = Q - v_k (tau_k v_k^T Q). H_k changes rows k.. only, so the
/// columns j < k of H_{k+1} ... H_{m-1} [I; 0] are still e_j and v_k^T e_j = 0: only columns k..
/// are updated, each by one axpy (a lazy outer product is evaluated coefficient by coefficient).
/// Shapes: reflectors and tau from householder_qr_in_place (m x n, n); Q m x p for any p <= m (p =
/// n: the thin Q1 whose columns span range(A) when R is regular; p = m: the whole orthogonal Q);
/// workspace: 1 x p.
template <typename DerivedV, typename DerivedTau, typename DerivedQ, typename DerivedWork>
void householder_q(const Eigen::MatrixBase<DerivedV>& reflectors, const Eigen::MatrixBase<DerivedTau>& tau,
                   const Eigen::MatrixBase<DerivedQ>& Q_out, const Eigen::MatrixBase<DerivedWork>& workspace_out) noexcept
{
    auto& Q = const_cast<Eigen::MatrixBase<DerivedQ>&>(Q_out);
    auto& workspace = const_cast<Eigen::MatrixBase<DerivedWork>&>(workspace_out);
    Q.setIdentity();
    for (Index k = reflectors.cols() - 1; k >= 0; --k) {
        const auto v = reflectors.col(k);
        for (Index j = k; j < Q.cols(); ++j) {
            workspace(j) = tau(k) * v.dot(Q.col(j));
        }
        for (Index j = k; j < Q.cols(); ++j) {
            Q.col(j) -= workspace(j) * v;
        }
    }
}

}  // namespace coopdyn
