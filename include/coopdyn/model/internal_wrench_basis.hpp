/// \file
/// \brief The internal wrenches of a rigid grasp, the null space of the grasp matrix G (24): their
/// dimension 6(K - 1), a closed-form basis of null(G), and the orthonormal basis B (G B = 0,
/// B^T B = I) in which the second paper's projection and contact QP take their coordinates z of
/// w = B z (errata E10; docs/model.md, "Internal wrenches", and docs/control.md).
///
/// `r` is 3 x K: column i is r_i, from the object's centre of mass to contact i, in {w}.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/numerics/householder_qr.hpp"
#include "coopdyn/spatial/spatial_vector.hpp"

#include <cmath>

namespace coopdyn {

/// 6(K - 1), the dimension of the internal wrenches of K contacts (Dynamic passes through).
constexpr int internal_wrench_dimension(int arms) noexcept
{
    return arms == Eigen::Dynamic ? Eigen::Dynamic : 6 * (arms - 1);
}

namespace detail {

/// Whether B is orthonormal and G(r) B = 0, to 1e-8 (a debug check; allocates nothing).
template <typename DerivedR, typename DerivedB>
bool is_internal_basis(const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedB>& B) noexcept
{
    using Scalar = typename DerivedB::Scalar;
    using std::abs;
    const Scalar tolerance(1e-8);
    for (Index j = 0; j < B.cols(); ++j) {
        for (Index k = 0; k <= j; ++k) {
            const Scalar expected = j == k ? Scalar(1) : Scalar(0);
            if (!(abs(B.col(j).dot(B.col(k)) - expected) < tolerance)) {
                return false;
            }
        }
        // G B_j = sum_i [f_i; t_i + r_i x f_i] (24), with r_i as a fixed 3-vector whatever r's type.
        Vector6<Scalar> net = Vector6<Scalar>::Zero();
        for (Index i = 0; i < r.cols(); ++i) {
            const Vector3<Scalar> force = B.col(j).template segment<3>(6 * i);
            net.template head<3>() += force;
            net.template tail<3>() += B.col(j).template segment<3>(6 * i + 3) + Vector3<Scalar>(r.col(i)).cross(force);
        }
        if (!(net.norm() < tolerance * (Scalar(1) + r.norm()))) {
            return false;
        }
    }
    return true;
}

/// The closed-form basis of null(G), 6K x 6(K-1), not orthonormal: column 6(i-1)+a is the unit
/// wrench e_a at contact i balanced by the same wrench moved to contact 1 and reversed,
/// w_1 = -G(r_i - r_1) e_a, w_i = e_a, so that G_1 w_1 + G_i w_i = 0.
template <typename DerivedR, typename DerivedOut>
void closed_form_internal_basis(const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedOut>& basis_out) noexcept
{
    using Scalar = typename DerivedR::Scalar;
    auto& basis = const_cast<Eigen::MatrixBase<DerivedOut>&>(basis_out);
    basis.setZero();
    for (Index i = 1; i < r.cols(); ++i) {
        const Vector3<Scalar> offset = r.col(i) - r.col(0);
        for (int axis = 0; axis < 6; ++axis) {
            const Index column = 6 * (i - 1) + axis;
            basis(6 * i + axis, column) = Scalar(1);
            basis.template block<6, 1>(0, column) = -(Force<Scalar>::from(Vector6<Scalar>::Unit(axis)).shifted(offset).vector());
        }
    }
}

/// B into caller storage, allocation-free (the per-tick form of internal_wrench_basis; the
/// workspace sized as there): the closed-form basis, overwritten by its Householder QR, then the QR's
/// leading 6(K-1) columns of Q.
template <typename DerivedR, typename DerivedW, typename DerivedV, typename DerivedTau, typename DerivedWork,
          typename DerivedOut>
void write_internal_wrench_basis(const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedW>& closed_form,
                                 const Eigen::MatrixBase<DerivedV>& reflectors, const Eigen::MatrixBase<DerivedTau>& tau,
                                 const Eigen::MatrixBase<DerivedWork>& workspace,
                                 const Eigen::MatrixBase<DerivedOut>& basis) noexcept
{
    closed_form_internal_basis(r, closed_form);
    householder_qr_in_place(closed_form, reflectors, tau);
    householder_q(reflectors, tau, basis, workspace);
}

}  // namespace detail

/// \brief Orthonormal basis B (6K x 6(K-1), B^T B = I) of the internal wrenches, the null space of
/// G: G B = 0. Orthonormal columns give weights and tolerances on the coordinates z of w = B z a
/// physical scale (|B z| = |z|). Built from the closed-form basis (a wrench u at contact i
/// balanced by -u moved to contact 1: w_1 = -G(r_i - r_1) u, w_i = u) by a Householder QR.
/// \param r 3 x K contact points, K >= 2.
template <typename DerivedR>
Eigen::Matrix<typename DerivedR::Scalar, times_six(DerivedR::ColsAtCompileTime),
              internal_wrench_dimension(DerivedR::ColsAtCompileTime)>
internal_wrench_basis(const Eigen::MatrixBase<DerivedR>& r)
{
    using Scalar = typename DerivedR::Scalar;
    constexpr int Arms = DerivedR::ColsAtCompileTime;
    using Basis = Eigen::Matrix<Scalar, times_six(Arms), internal_wrench_dimension(Arms)>;
    using Reduced = Eigen::Matrix<Scalar, internal_wrench_dimension(Arms), 1>;
    COOPDYN_ASSERT(r.cols() >= 2, "internal wrenches need at least two contacts");
    const Index arms = r.cols();
    Basis closed_form = Basis::Zero(6 * arms, 6 * (arms - 1));
    Basis reflectors = Basis::Zero(6 * arms, 6 * (arms - 1));
    Reduced tau = Reduced::Zero(6 * (arms - 1));
    Eigen::Matrix<Scalar, 1, internal_wrench_dimension(Arms)> workspace = tau.transpose();
    Basis basis(6 * arms, 6 * (arms - 1));
    detail::write_internal_wrench_basis(r, closed_form, reflectors, tau, workspace, basis);
    return basis;
}

}  // namespace coopdyn
