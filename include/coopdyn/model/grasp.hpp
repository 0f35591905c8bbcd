/// \file
/// \brief Rigid-grasp kinematics: grasp matrix (24), constraint matrix (14) and constraint bias
/// (13), and the per-arm maps G_i and G_i^T they are built from (docs/model.md).
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

}  // namespace coopdyn
