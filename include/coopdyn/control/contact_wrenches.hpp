/// \file
/// \brief The contact wrenches a projected inverse-dynamics controller produces, Lin et al.
/// L(7), L(16), L(22)-(24) with errata E11; docs/control.md.
///
/// Sign conventions: w (6K) stacks the wrenches the hands apply ON the object, each about its
/// contact point, in {w}. F_x is the external wrench on the (massless, as the controller models it)
/// object: its weight, its inertia and any push, so G w = -F_x. The joint-space dynamics are
///
///     M qdd + h = tau + Jc^T lambda + Jx^T F_x,      Jc qdd = -Jcdot qdot
///
/// and the contacts apply w = -G^+ F_x - lambda_c to the object, with lambda_c the part of lambda
/// in null(G) (L(23)-(24)):
///
///     lambda_c = eta - rho,   rho = (Jc^T)^+ tau_c,
///     eta = (Jc^T)^+ (I - P)(M qdd + h - Jx^T F_x),   qdd = Mc^-1 (tau_u + P Jx^T F_x - P h + Pdot qdot)   (E11)
///
/// Errata E11: the printed qdd in eta omits P Jx^T F_x: the external wrench moves the object too.
/// A squeeze tau_c = J^T B z adds exactly B z to w and changes no acceleration (P J^T B = 0), so
/// w(z) = w_0 + B z with the bias w_0 = -G^+ F_x - eta.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/control/projected_dynamics.hpp"

namespace coopdyn {

/// \brief The contact-wrench bias w_0 = -G^+ F_x - eta (6K) of L(23)-(24) with errata E11: the
/// wrenches the hands apply to the object under tau = tau_u (no squeeze) for the external wrench
/// F_x, and the joint acceleration qdd that goes with it.
/// \param dynamics computed at this configuration (status ok) from the same M and h (non-const:
/// its products use its workspace).
/// \param tau_u Q, the motion torque (L(16): P Jx^T F; anything with P tau_u = tau_u).
/// \param external_wrench F_x (6), on the object at its centre, {w}.
/// \param joint_acceleration_out Q, qdd; \param bias_out 6K, w_0; \param joint_scratch Q, caller
/// storage so that nothing allocates. noexcept.
template <typename Scalar, int Arms, int Joints, typename DerivedM, typename DerivedH, typename DerivedTau,
          typename DerivedWrench, typename DerivedAcceleration, typename DerivedBias, typename DerivedScratch>
void contact_wrench_bias(ProjectedDynamics<Scalar, Arms, Joints>& dynamics, const Eigen::MatrixBase<DerivedM>& M,
                         const Eigen::MatrixBase<DerivedH>& h, const Eigen::MatrixBase<DerivedTau>& tau_u,
                         const Eigen::MatrixBase<DerivedWrench>& external_wrench,
                         const Eigen::MatrixBase<DerivedAcceleration>& joint_acceleration_out,
                         const Eigen::MatrixBase<DerivedBias>& bias_out,
                         const Eigen::MatrixBase<DerivedScratch>& joint_scratch_out) noexcept
{
    auto& qdd = const_cast<Eigen::MatrixBase<DerivedAcceleration>&>(joint_acceleration_out);
    auto& bias = const_cast<Eigen::MatrixBase<DerivedBias>&>(bias_out);
    auto& scratch = const_cast<Eigen::MatrixBase<DerivedScratch>&>(joint_scratch_out);
    COOPDYN_ASSERT(dynamics.status == ProjectionStatus::ok, "contact_wrench_bias needs a regular projection");
    COOPDYN_REQUIRE_SHAPE(bias.size() == 6 * dynamics.arms() && scratch.size() == dynamics.joints() &&
                              qdd.size() == dynamics.joints() && tau_u.size() == dynamics.joints() &&
                              external_wrench.size() == 6,
                          "contact_wrench_bias: inputs or outputs sized for another controller");
    const Vector6<Scalar> F_x = external_wrench;
    // qdd = Mc^-1 (tau_u + P (Jx^T F_x - h) + Pdot qdot)   (E11: P Jx^T F_x included)
    scratch.noalias() = dynamics.object_jacobian.transpose().lazyProduct(F_x);
    scratch -= h;
    dynamics.project(scratch, qdd);
    qdd += tau_u;
    qdd += dynamics.projector_rate_qdot;
    dynamics.constrained_inertia_solve(qdd, qdd);
    // eta = (Jc^T)^+ (I - P) y with y = M qdd + h - Jx^T F_x. (Jc^T)^+ = B (Jr Jr^T)^-1 Jr and
    // Jr P = 0, so (Jc^T)^+ (I - P) y = (Jc^T)^+ y.
    scratch = -scratch;
    scratch.noalias() += M.lazyProduct(qdd);
    dynamics.constraint_transpose_pseudo_inverse_times(scratch, bias);
    // w_0 = -G^+ F_x - eta
    bias = -bias;
    dynamics.subtract_grasp_pseudo_inverse_times(F_x, bias);
}

}  // namespace coopdyn
