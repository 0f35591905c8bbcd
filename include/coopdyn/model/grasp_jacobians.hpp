/// \file
/// \brief The grasp Jacobians of the second paper: the object Jacobian Jx = (G G^T)^-1 G J
/// (xdot_o = Jx qdot), the constraint Jacobian Jc = (I - G^+ G) J = J - G^T Jx of L(13), and their
/// rates Jxdot qdot, Jcdot qdot in closed form; docs/model.md, "Grasp Jacobians", and
/// docs/control.md.
///
/// Why in model/ and not in control/: they are the grasp's kinematics (G and its pseudo-inverse,
/// grasp.hpp and grasp_inverse.hpp) applied to the arms' stacked contact Jacobians J (6K x Q,
/// supplied by the user's kinematics library); nothing in them is dynamics or control. The
/// projection (control/projected_dynamics.hpp) builds on them.
///
/// `r` is 3 x K: column i is r_i, from the object's centre of mass to contact i, in {w}.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/model/grasp.hpp"
#include "coopdyn/model/grasp_inverse.hpp"
#include "coopdyn/spatial/spatial_vector.hpp"

namespace coopdyn {
namespace detail {

/// Jx = (G G^T)^-1 G J (6 x Q) into caller storage, column j the unit-weight solve of G J_j
/// (`unit_grasp` computed with UnitGraspWeights for these r; r with 3 rows at compile time).
template <typename Scalar, typename DerivedR, typename DerivedJ, typename DerivedOut>
void write_object_jacobian(const WeightedGrasp<Scalar>& unit_grasp, const Eigen::MatrixBase<DerivedR>& r,
                           const Eigen::MatrixBase<DerivedJ>& J, const Eigen::MatrixBase<DerivedOut>& jx_out) noexcept
{
    auto& jx = const_cast<Eigen::MatrixBase<DerivedOut>&>(jx_out);
    for (Index j = 0; j < J.cols(); ++j) {
        unit_grasp.solve(grasp_times(r, J.col(j))).write_to(jx.col(j));
    }
}

/// Jc = J - G^T Jx (6K x Q, L(13)) into caller storage: row block i of column j is contact i's
/// twist minus the twist the object's motion Jx_j gives point r_i (G_i^T, (10)).
template <typename DerivedR, typename DerivedJ, typename DerivedJx, typename DerivedOut>
void write_constraint_jacobian(const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedJ>& J,
                               const Eigen::MatrixBase<DerivedJx>& jx, const Eigen::MatrixBase<DerivedOut>& jc_out) noexcept
{
    using Scalar = typename DerivedJ::Scalar;
    auto& jc = const_cast<Eigen::MatrixBase<DerivedOut>&>(jc_out);
    for (Index j = 0; j < J.cols(); ++j) {
        const Motion<Scalar> object = Motion<Scalar>::from(jx.col(j));
        for (Index i = 0; i < r.cols(); ++i) {
            jc.template block<6, 1>(6 * i, j) = J.template block<6, 1>(6 * i, j) - object.at_point(r.col(i)).vector();
        }
    }
}

/// Jxdot qdot and Jcdot qdot in closed form (into caller storage, 6 and 6K), with the object's
/// twist y = Jx qdot (6) and `scratch` (6K). With v = J qdot, omega = y's angular part and
/// rdot_i = omega x r_i (the contacts turn with the object):
///   A Jx = G J, A = G G^T  =>  Jxdot qdot = A^-1 (G Jdot qdot + Gdot v - Adot y),  Adot = Gdot G^T + G Gdot^T
///   Jc = J - G^T Jx        =>  Jcdot qdot = Jdot qdot - Gdot^T y - G^T Jxdot qdot
template <typename Scalar, typename DerivedR, typename DerivedJ, typename DerivedJdotQdot, typename DerivedQdot,
          typename DerivedJx, typename DerivedJcRate, typename DerivedScratch>
void write_grasp_jacobian_rates(const WeightedGrasp<Scalar>& unit_grasp, const Eigen::MatrixBase<DerivedR>& r,
                                const Eigen::MatrixBase<DerivedJ>& J, const Eigen::MatrixBase<DerivedJdotQdot>& Jdot_qdot,
                                const Eigen::MatrixBase<DerivedQdot>& qdot, const Eigen::MatrixBase<DerivedJx>& jx,
                                Vector6<Scalar>& object_twist, Vector6<Scalar>& object_jacobian_rate_qdot,
                                const Eigen::MatrixBase<DerivedJcRate>& jc_rate_out,
                                const Eigen::MatrixBase<DerivedScratch>& scratch_out) noexcept
{
    auto& constraint_jacobian_rate_qdot = const_cast<Eigen::MatrixBase<DerivedJcRate>&>(jc_rate_out);
    auto& scratch = const_cast<Eigen::MatrixBase<DerivedScratch>&>(scratch_out);
    object_twist.noalias() = jx.lazyProduct(qdot);
    const Vector3<Scalar> omega = object_twist.template tail<3>();
    scratch.noalias() = J.lazyProduct(qdot);  // v
    Vector6<Scalar> rate = grasp_times(r, Jdot_qdot).vector() + grasp_rate_times(r, omega, scratch);
    // Adot y = Gdot (G^T y) + G (Gdot^T y)
    write_grasp_transpose_times(r, Motion<Scalar>::from(object_twist), scratch);
    rate -= grasp_rate_times(r, omega, scratch);
    grasp_rate_transpose_times(r, omega, object_twist, scratch);  // Gdot^T y
    rate -= grasp_times(r, scratch).vector();
    object_jacobian_rate_qdot = unit_grasp.solve(Force<Scalar>::from(rate)).vector();

    constraint_jacobian_rate_qdot = Jdot_qdot - scratch;
    const Motion<Scalar> object_rate = Motion<Scalar>::from(object_jacobian_rate_qdot);
    for (Index i = 0; i < r.cols(); ++i) {
        constraint_jacobian_rate_qdot.template segment<6>(6 * i) -= object_rate.at_point(r.col(i)).vector();
    }
}

}  // namespace detail

/// \brief Object Jacobian Jx = (G G^T)^-1 G J (6 x Q): the object's twist xdot_o = Jx qdot while
/// the grasp holds (the least-squares rigid motion of the contacts in general).
/// \param r 3 x K contact points relative to the object's centre, {w}.
/// \param J 6K x Q stacked contact Jacobians.
template <typename DerivedR, typename DerivedJ>
Eigen::Matrix<typename DerivedJ::Scalar, 6, DerivedJ::ColsAtCompileTime>
object_jacobian(const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedJ>& J)
{
    using Scalar = typename DerivedJ::Scalar;
    COOPDYN_ASSERT(r.rows() == 3 && J.rows() == 6 * r.cols(), "J must have 6K rows for r 3 x K");
    const Eigen::Matrix<Scalar, 3, DerivedR::ColsAtCompileTime> offsets = r;
    const detail::WeightedGrasp<Scalar> grasp(detail::UnitGraspWeights<Scalar>{r.cols()}, offsets);
    Eigen::Matrix<Scalar, 6, DerivedJ::ColsAtCompileTime> result(6, J.cols());
    detail::write_object_jacobian(grasp, offsets, J, result);
    return result;
}

/// \brief Constraint Jacobian Jc = (I - G^+ G) J = J - G^T Jx (6K x Q), L(13): Jc qdot = 0 says
/// the contacts move as one rigid body. Row block i is contact i's twist minus the twist the
/// object's motion Jx qdot gives point r_i. Rank 6K - 6 (errata E10).
template <typename DerivedR, typename DerivedJ>
Eigen::Matrix<typename DerivedJ::Scalar, DerivedJ::RowsAtCompileTime, DerivedJ::ColsAtCompileTime>
constraint_jacobian(const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedJ>& J)
{
    using Scalar = typename DerivedJ::Scalar;
    const Eigen::Matrix<Scalar, 3, DerivedR::ColsAtCompileTime> offsets = r;
    Eigen::Matrix<Scalar, DerivedJ::RowsAtCompileTime, DerivedJ::ColsAtCompileTime> result(J.rows(), J.cols());
    detail::write_constraint_jacobian(offsets, J, object_jacobian(offsets, J), result);
    return result;
}

}  // namespace coopdyn
