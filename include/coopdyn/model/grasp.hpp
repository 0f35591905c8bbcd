/// \file
/// \brief Rigid-grasp kinematics: grasp matrix (24), constraint matrix (14) and constraint bias
/// (13), the per-arm maps G_i and G_i^T they are built from, and the grasp operators applied per
/// contact without forming G (G w, G^T y, Gdot v, Gdot^T y, G G^T; docs/model.md, "Rigid grasp
/// kinematics"). The grasp's pseudo-inverses are in grasp_inverse.hpp, the internal-wrench basis
/// (null(G)) in internal_wrench_basis.hpp.
///
/// `r` is 3 x N: column i is r_i, from the object's centre of mass to grasp point i, in {w}.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/spatial/skew.hpp"
#include "coopdyn/spatial/spatial_vector.hpp"

namespace coopdyn {

/// \brief Wrench map of one arm, G_i h = [f; r_i x f + t]: a wrench at grasp point i expressed
/// at the object's centre of mass, G_i = [[I3, 0], [S(r_i), I3]] (paper (24)); Force::shifted.
template <typename DerivedR, typename DerivedW>
Vector6<typename DerivedW::Scalar> grasp_map_wrench(const Eigen::MatrixBase<DerivedR>& r_i,
                                                    const Eigen::MatrixBase<DerivedW>& wrench) noexcept
{
    return Force<typename DerivedW::Scalar>::from(wrench).shifted(r_i).vector();
}

/// \brief Twist map of one arm, G_i^T xdot_o = [v_o + w_o x r_i; w_o]: the twist of grasp point
/// i on a rigid object (paper (10)); Motion::at_point.
template <typename DerivedR, typename DerivedT>
Vector6<typename DerivedT::Scalar> grasp_map_twist(const Eigen::MatrixBase<DerivedR>& r_i,
                                                   const Eigen::MatrixBase<DerivedT>& object_twist) noexcept
{
    return Motion<typename DerivedT::Scalar>::from(object_twist).at_point(r_i).vector();
}

/// \brief G of (24) written into caller storage (6 x 6N, already sized): the allocation-free form
/// of grasp_matrix for workspaces that rebuild G every tick.
template <typename DerivedR, typename DerivedOut>
void write_grasp_matrix(const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedOut>& grasp_out) noexcept
{
    auto& grasp = const_cast<Eigen::MatrixBase<DerivedOut>&>(grasp_out);
    COOPDYN_ASSERT(r.rows() == 3 && grasp.rows() == 6 && grasp.cols() == 6 * r.cols(), "G is 6 x 6N for r 3 x N");
    grasp.setZero();
    for (Index i = 0; i < r.cols(); ++i) {
        grasp.template block<3, 3>(0, 6 * i).setIdentity();
        grasp.template block<3, 3>(3, 6 * i) = skew(r.col(i).template head<3>());
        grasp.template block<3, 3>(3, 6 * i + 3).setIdentity();
    }
}

/// \brief Grasp matrix G = [G_1 ... G_N] of paper (24), 6 x 6N, with h_o = G hbar (23).
/// \param r 3 x N grasp offsets in {w}.
template <typename DerivedR>
Eigen::Matrix<typename DerivedR::Scalar, 6, times_six(DerivedR::ColsAtCompileTime)>
grasp_matrix(const Eigen::MatrixBase<DerivedR>& r)
{
    static_assert(DerivedR::RowsAtCompileTime == 3 || DerivedR::RowsAtCompileTime == Eigen::Dynamic,
                  "r must be 3 x N");
    using Scalar = typename DerivedR::Scalar;
    COOPDYN_ASSERT(r.rows() == 3, "r must be 3 x N");
    Eigen::Matrix<Scalar, 6, times_six(DerivedR::ColsAtCompileTime)> result(6, 6 * r.cols());
    write_grasp_matrix(r, result);
    return result;
}

/// \brief Constraint matrix A of paper (14), 6N x 6(N+1), for the rigid grasp: A xdd = b.
/// Block row i: [[-I3, S(r_i)], [0, -I3]] in the object's columns, I6 in end-effector i's.
/// \param r 3 x N grasp offsets in {w}.
template <typename DerivedR>
Eigen::Matrix<typename DerivedR::Scalar, times_six(DerivedR::ColsAtCompileTime),
              full_stack_size(DerivedR::ColsAtCompileTime)>
constraint_matrix(const Eigen::MatrixBase<DerivedR>& r)
{
    static_assert(DerivedR::RowsAtCompileTime == 3 || DerivedR::RowsAtCompileTime == Eigen::Dynamic,
                  "r must be 3 x N");
    using Scalar = typename DerivedR::Scalar;
    COOPDYN_ASSERT(r.rows() == 3, "r must be 3 x N");
    const Index arms = r.cols();
    Eigen::Matrix<Scalar, times_six(DerivedR::ColsAtCompileTime),
                  full_stack_size(DerivedR::ColsAtCompileTime)>
        result(6 * arms, 6 * (arms + 1));
    result.setZero();
    for (Index i = 0; i < arms; ++i) {
        result.template block<3, 3>(6 * i, 0) = -Matrix3<Scalar>::Identity();
        result.template block<3, 3>(6 * i, 3) = skew(r.col(i).template head<3>());
        result.template block<3, 3>(6 * i + 3, 3) = -Matrix3<Scalar>::Identity();
        result.template block<6, 6>(6 * i, 6 * (i + 1)).setIdentity();
    }
    return result;
}

/// \brief Constraint bias b of paper (13), 6N: b_i = [S(w_o)^2 r_i; 0].
/// \param r 3 x N grasp offsets in {w}.
/// \param omega_o object angular velocity in {w}.
template <typename DerivedR, typename DerivedOmega>
Eigen::Matrix<typename DerivedR::Scalar, times_six(DerivedR::ColsAtCompileTime), 1>
constraint_bias(const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedOmega>& omega_o)
{
    static_assert(DerivedR::RowsAtCompileTime == 3 || DerivedR::RowsAtCompileTime == Eigen::Dynamic,
                  "r must be 3 x N");
    using Scalar = typename DerivedR::Scalar;
    COOPDYN_ASSERT(r.rows() == 3, "r must be 3 x N");
    const Index arms = r.cols();
    Eigen::Matrix<Scalar, times_six(DerivedR::ColsAtCompileTime), 1> result(6 * arms);
    for (Index i = 0; i < arms; ++i) {
        result.template segment<3>(6 * i) = centripetal_acceleration(r.col(i).template head<3>(), omega_o);
        result.template segment<3>(6 * i + 3).setZero();
    }
    return result;
}

namespace detail {

// The grasp operators of the per-tick path (ProjectedDynamics, the squeeze): G and its rate applied
// per contact, G_i = [[I, 0], [S(r_i), I]] (24), 18 nonzeros of 36 per block, never formed.

/// G G^T (6 x 6, symmetric positive definite for any grasp: its lower-right block contains K I3).
template <typename DerivedG> Matrix6<typename DerivedG::Scalar> grasp_gram(const Eigen::MatrixBase<DerivedG>& grasp)
{
    return grasp * grasp.transpose();
}

/// G w = sum_i G_i w_i = sum_i [f_i; t_i + r_i x f_i] (24), per contact: G has 18 nonzeros of 36
/// per block. The net wrench at the object's centre of the contact wrenches w (any r, 3 x K).
template <typename DerivedR, typename DerivedW>
Force<typename DerivedW::Scalar> grasp_times(const Eigen::MatrixBase<DerivedR>& r,
                                             const Eigen::MatrixBase<DerivedW>& stacked) noexcept
{
    using Scalar = typename DerivedW::Scalar;
    Force<Scalar> result;
    for (Index i = 0; i < r.cols(); ++i) {
        result += Force<Scalar>::from(stacked.template segment<6>(6 * i)).shifted(r.col(i).template head<3>());
    }
    return result;
}

/// G^T y: block i is G_i^T y = [v + w x r_i; w], the twist of contact i (10).
template <typename DerivedR, typename DerivedOut>
void write_grasp_transpose_times(const Eigen::MatrixBase<DerivedR>& r, const Motion<typename DerivedR::Scalar>& twist,
                                 const Eigen::MatrixBase<DerivedOut>& result_out) noexcept
{
    auto& result = const_cast<Eigen::MatrixBase<DerivedOut>&>(result_out);
    for (Index i = 0; i < r.cols(); ++i) {
        twist.at_point(r.col(i)).write_to(result.template segment<6>(6 * i));
    }
}

/// Gdot v = sum_i [0; rdot_i x v_i,linear] with rdot_i = omega x r_i (the contacts turn with the
/// object; G_i = [[I, 0], [S(r_i), I]] so Gdot_i = [[0, 0], [S(rdot_i), 0]]).
template <typename DerivedR, typename DerivedV>
Vector6<typename DerivedV::Scalar> grasp_rate_times(const Eigen::MatrixBase<DerivedR>& r,
                                                    const Vector3<typename DerivedV::Scalar>& omega,
                                                    const Eigen::MatrixBase<DerivedV>& stacked) noexcept
{
    using Scalar = typename DerivedV::Scalar;
    Vector6<Scalar> result = Vector6<Scalar>::Zero();
    for (Index i = 0; i < r.cols(); ++i) {
        const Vector3<Scalar> rate = omega.cross(Vector3<Scalar>(r.col(i)));
        result.template tail<3>() += rate.cross(Vector3<Scalar>(stacked.template segment<3>(6 * i)));
    }
    return result;
}

/// Gdot^T y: block i = [S(rdot_i)^T y_angular; 0] = [y_angular x rdot_i; 0].
template <typename DerivedR, typename DerivedOut>
void grasp_rate_transpose_times(const Eigen::MatrixBase<DerivedR>& r, const Vector3<typename DerivedR::Scalar>& omega,
                                const Vector6<typename DerivedR::Scalar>& y,
                                const Eigen::MatrixBase<DerivedOut>& result_out) noexcept
{
    using Scalar = typename DerivedR::Scalar;
    auto& result = const_cast<Eigen::MatrixBase<DerivedOut>&>(result_out);
    for (Index i = 0; i < r.cols(); ++i) {
        const Vector3<Scalar> rate = omega.cross(Vector3<Scalar>(r.col(i)));
        result.template segment<3>(6 * i) = Vector3<Scalar>(y.template tail<3>()).cross(rate);
        result.template segment<3>(6 * i + 3).setZero();
    }
}

}  // namespace detail

}  // namespace coopdyn
