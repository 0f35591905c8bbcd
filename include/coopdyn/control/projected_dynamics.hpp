/// \file
/// \brief Projected inverse dynamics of K arms holding one object (the second paper, Lin et al.):
/// the projected dynamics L(4), (15), (26) with their exact derivative terms; docs/control.md. The
/// grasp kinematics it builds on are in model/ and included here: the grasp operators G, G^T, Gdot
/// (model/grasp.hpp), the pseudo-inverse G^+ (model/grasp_inverse.hpp), the object and constraint
/// Jacobians Jx, Jc of L(13) and their rates (model/grasp_jacobians.hpp), the internal-wrench
/// basis B (model/internal_wrench_basis.hpp).
///
/// Inputs come from the user's kinematics/dynamics library: the joint inertia M (Q x Q, SPD), the
/// bias h (Q; Coriolis, centrifugal, gravity), the stacked contact Jacobians J (6K x Q; rows
/// 6i..6i+5 map qdot to the twist [v; w] of contact point i in {w}; arms may share joints),
/// Jdot qdot (6K), qdot (Q), and the contact points relative to the object's centre r (3 x K, {w}).
///
///     G = [G_1 ... G_K] (24),  G^+ = G^T (G G^T)^-1,  N = I - G^+ G
///     Jc = N J = J - G^T Jx                    constraint Jacobian L(13), rank 6K - 6
///     Jx = (G G^T)^-1 G J                      object Jacobian, xdot_o = Jx qdot
///     P  = I - Jc^+ Jc                         projector L(4)
///     Mc = P M + I - P                         L(26), Appendix A
///     Lambda_c = (Jx Mc^-1 P Jx^T)^-1          below L(15)
///     hc = Lambda_c (Jx Mc^-1 (P h - Pdot qdot) - Jxdot qdot)       L(15): Lambda_c xdd_o + hc = F + F_x
///
/// Errata E10: Jc has rank 6K - 6, not 6K. The library never inverts Jc Jc^T: with B (6K x 6(K-1))
/// an orthonormal basis of null(G), N = B B^T and Jc = B Jr with Jr = B^T J of full row rank (when
/// J has), so Jc^+ = Jr^T (Jr Jr^T)^-1 B^T. Jr Jr^T is never formed either: a Householder QR
/// Jr^T = Q1 R gives Jr Jr^T = R^T R, Jc^+ = Q1 R^-T B^T and P = I - Q1 Q1^T, and the rest of Q
/// (a basis Q2 of the motions the grasp allows) turns Mc^-1 and Lambda_c into a Cholesky factorisation
/// of the (Q - 6K + 6) square matrix Q2^T M Q2 (ProjectedDynamics; docs/control.md).
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/model/grasp.hpp"
#include "coopdyn/model/grasp_inverse.hpp"
#include "coopdyn/model/grasp_jacobians.hpp"
#include "coopdyn/model/internal_wrench_basis.hpp"
#include "coopdyn/numerics/fixed_llt.hpp"
#include "coopdyn/numerics/householder_qr.hpp"
#include "coopdyn/numerics/pivot_policy.hpp"
#include "coopdyn/numerics/triangular_solve.hpp"
#include "coopdyn/spatial/spatial_vector.hpp"

#include <algorithm>

namespace coopdyn {

/// Outcome of a projected-dynamics evaluation. Not ok means a singular configuration: the
/// results are not to be used (they are finite but meaningless).
enum class ProjectionStatus {
    ok,
    singular_constraint,  ///< Jr Jr^T not positive definite: J lost rank (an arm at a singularity)
    singular_task,        ///< Jx Mc^-1 P Jx^T not invertible: the object cannot be moved in some direction
};

/// Q - 6(K - 1), the dimension of the motions the grasp allows (null(Jr) = range(P)); Dynamic
/// passes through, and fewer joints than internal wrenches give 0 (the grasp is then singular).
constexpr int free_joint_dimension(int joints, int arms) noexcept
{
    return joints == Eigen::Dynamic || arms == Eigen::Dynamic
               ? Eigen::Dynamic
               : (joints > internal_wrench_dimension(arms) ? joints - internal_wrench_dimension(arms) : 0);
}

/// \brief Workspace and results of the projected dynamics for K arms and Q joints (fixed or
/// Dynamic). Sized once at construction; compute() is noexcept and allocates nothing.
///
/// Method (the members keep the meaning of the formulas in the file comment): a Householder QR
/// Jr^T = [Q1 Q2] [R; 0] (Q1: Q x 6(K-1), Q2: Q x (Q - 6(K-1)), [Q1 Q2] orthogonal) gives
/// Jr Jr^T = R^T R, P = I - Q1 Q1^T = Q2 Q2^T and, because Q^T P = [0; Q2^T],
///
///     [Q1 Q2]^T Mc [Q1 Q2] = [[I, 0], [Q2^T M Q1, M22]],   M22 = Q2^T M Q2 (SPD),
///
/// block lower triangular: Mc^-1 needs only the Cholesky factor M22 = L22 L22^T, and
/// Jx Mc^-1 P Jx^T = E^T E with E = L22^-1 Q2^T Jx^T (Lambda_c^-1 as a Gram matrix, symmetric positive
/// semi-definite by construction).
template <typename ScalarType, int ArmsAtCompileTime, int JointsAtCompileTime> class ProjectedDynamics {
public:
    using Scalar = ScalarType;
    static constexpr int Arms = ArmsAtCompileTime;
    static constexpr int Joints = JointsAtCompileTime;
    static constexpr int Stack = times_six(Arms);
    static constexpr int Internal = internal_wrench_dimension(Arms);
    using JointVector = Eigen::Matrix<Scalar, Joints, 1>;
    using JointMatrix = Eigen::Matrix<Scalar, Joints, Joints>;
    using StackVector = Eigen::Matrix<Scalar, Stack, 1>;

    /// \param arms K >= 2 (must equal Arms when fixed); \param joints Q (must equal Joints when fixed).
    ProjectedDynamics(Index arms = (Arms == Eigen::Dynamic ? 2 : Arms),
                      Index joints = (Joints == Eigen::Dynamic ? 1 : Joints));

    /// Evaluate everything at one configuration. qdot must satisfy the grasp, Jc qdot = 0 (the
    /// closed forms of Pdot qdot use it). Returns status.
    template <typename DerivedM, typename DerivedH, typename DerivedJ, typename DerivedJdotQdot, typename DerivedQdot,
              typename DerivedR>
    ProjectionStatus compute(const Eigen::MatrixBase<DerivedM>& M, const Eigen::MatrixBase<DerivedH>& h,
                             const Eigen::MatrixBase<DerivedJ>& J, const Eigen::MatrixBase<DerivedJdotQdot>& Jdot_qdot,
                             const Eigen::MatrixBase<DerivedQdot>& qdot, const Eigen::MatrixBase<DerivedR>& r) noexcept
    {
        compute_basis(r);
        return evaluate(M, h, J, Jdot_qdot, qdot, r);
    }

    /// compute() with the internal-wrench basis B given (6K x 6(K-1), orthonormal, G(r) B = 0;
    /// asserted in debug builds) instead of built from r by a Householder QR. For an object whose
    /// contacts are fixed in its frame, r_i = R_o p_i and G(R_o p) = R6 G(p) blkdiag(R6^T, ...),
    /// R6 = blkdiag(R_o, R_o), so B = blkdiag(R6, ..., R6) B(p): the basis of the body-frame
    /// offsets, built once, rotated each tick (the controller does this). Any orthonormal basis of
    /// null(G) gives the same P, Jx, Lambda_c and hc; B only fixes the coordinates z of w = B z.
    template <typename DerivedM, typename DerivedH, typename DerivedJ, typename DerivedJdotQdot, typename DerivedQdot,
              typename DerivedR, typename DerivedB>
    ProjectionStatus compute_with_basis(const Eigen::MatrixBase<DerivedM>& M, const Eigen::MatrixBase<DerivedH>& h,
                                        const Eigen::MatrixBase<DerivedJ>& J,
                                        const Eigen::MatrixBase<DerivedJdotQdot>& Jdot_qdot,
                                        const Eigen::MatrixBase<DerivedQdot>& qdot, const Eigen::MatrixBase<DerivedR>& r,
                                        const Eigen::MatrixBase<DerivedB>& basis) noexcept
    {
        COOPDYN_REQUIRE_SHAPE(basis.rows() == 6 * arms() && basis.cols() == 6 * (arms() - 1),
                              "projected dynamics: the basis must be 6K x 6(K - 1)");
        internal_basis = basis;
        COOPDYN_ASSERT(detail::is_internal_basis(r, internal_basis),
                       "compute_with_basis: the basis must be orthonormal and span null(G(r))");
        return evaluate(M, h, J, Jdot_qdot, qdot, r);
    }

    /// Whether compute() forms the Q x Q matrices P (projector) and Mc (constrained_inertia). The
    /// computations never read them (they apply P as x - Q1 Q1^T x, project(), and Mc through
    /// its block form, constrained_inertia_solve); they are outputs for the user. The controller
    /// turns them off: forming them for two 7-joint arms costs about 10 % of its tick.
    bool form_projection_matrices = true;

    /// x -> P x = x - Q1 (Q1^T x) (Q, into out; out may be x itself), L(4) without forming P.
    template <typename DerivedIn, typename DerivedOut>
    void project(const Eigen::MatrixBase<DerivedIn>& x, const Eigen::MatrixBase<DerivedOut>& out_) noexcept
    {
        auto& out = const_cast<Eigen::MatrixBase<DerivedOut>&>(out_);
        const auto q1 = reduced_q_.template leftCols<Internal>(reduced_.size());
        reduced_.noalias() = q1.transpose().lazyProduct(x);
        out = x;
        out.noalias() -= q1.lazyProduct(reduced_);
    }

    /// x -> Jc^+ x (6K -> Q), the minimum-norm solution of Jc y = N x.
    template <typename DerivedIn, typename DerivedOut>
    void constraint_pseudo_inverse_times(const Eigen::MatrixBase<DerivedIn>& x,
                                         const Eigen::MatrixBase<DerivedOut>& out) noexcept;
    /// y -> (Jc^T)^+ y (Q -> 6K), the minimum-norm least-squares solution of Jc^T lambda = y; it
    /// lies in null(G).
    template <typename DerivedIn, typename DerivedOut>
    void constraint_transpose_pseudo_inverse_times(const Eigen::MatrixBase<DerivedIn>& y,
                                                   const Eigen::MatrixBase<DerivedOut>& out) noexcept;
    /// out -= G^+ F, G^+ F = G^T (G G^T)^-1 F (6 -> 6K): the least-norm contact wrenches whose net
    /// wrench on the object is F.
    template <typename DerivedIn, typename DerivedOut>
    void subtract_grasp_pseudo_inverse_times(const Eigen::MatrixBase<DerivedIn>& wrench,
                                             const Eigen::MatrixBase<DerivedOut>& out_) const noexcept
    {
        // The unit-weight inverse of (25) (model/grasp_inverse.hpp), factored in this tick's evaluate.
        grasp_inverse_.subtract_inverse_times(detail::UnitGraspWeights<Scalar>{arms()}, contact_offsets,
                                              Force<Scalar>::from(wrench), out_);
    }
    /// tau -> N^T tau = tau - J^T (J M^-1 J^T)^-1 J M^-1 tau (Q, into out; out must not be tau): the
    /// dynamically consistent projection onto the torques that move only the arms' self-motion
    /// null(J) (errata E12's posture torque), without forming or factorising J M^-1 J^T. null(J)
    /// is spanned by V = Q2 L22^-T U, U (free x (free - 6)) an orthonormal basis of null(E^T):
    /// J = G^T Jx + B Jr, Jr Q2 = 0 and Jx Q2 L22^-T = E^T. Then V^T M V = U^T U = I, so
    /// N^T = M V (V^T M V)^-1 V^T = M V V^T, and U U^T = I - E Lambda_c E^T:
    ///
    ///     N^T tau = (Q2^T M)^T L22^-T (I - E Lambda_c E^T) L22^-1 Q2^T tau.
    ///
    /// Needs status ok (then J has full row rank: rank J = rank Jr + rank(Jx Q2)).
    template <typename DerivedIn, typename DerivedOut>
    void self_motion_projection(const Eigen::MatrixBase<DerivedIn>& tau, const Eigen::MatrixBase<DerivedOut>& out_) noexcept
    {
        auto& out = const_cast<Eigen::MatrixBase<DerivedOut>&>(out_);
        COOPDYN_ASSERT(status == ProjectionStatus::ok, "self_motion_projection needs a regular projection");
        auto& reduced = free_scratch_;
        reduced.noalias() = reduced_q_.template rightCols<Free>(free_joints()).transpose().lazyProduct(tau);  // Q2^T
        free_inertia_factor_.solve_lower_in_place(reduced);                                          // L22^-1
        task_scratch_.noalias() = task_reduced_.transpose().lazyProduct(reduced);                    // E^T
        const Vector6<Scalar> task_part = task_inertia.lazyProduct(task_scratch_);                   // Lambda_c
        reduced.noalias() -= task_reduced_.lazyProduct(task_part);                                   // I - E Lambda_c E^T
        free_inertia_factor_.solve_upper_in_place(reduced);                                          // L22^-T
        out.noalias() = free_rows_inertia_.transpose().lazyProduct(reduced);                         // M Q2
    }

    /// x -> Mc^-1 x (Q, into out; out may be x itself). With v = [Q1 Q2]^T x (see the class
    /// comment): Mc^-1 x = Q1 v1 + Q2 M22^-1 (v2 - Q2^T M Q1 v1).
    template <typename DerivedIn, typename DerivedOut>
    void constrained_inertia_solve(const Eigen::MatrixBase<DerivedIn>& x, const Eigen::MatrixBase<DerivedOut>& out_) noexcept
    {
        auto& out = const_cast<Eigen::MatrixBase<DerivedOut>&>(out_);
        const Index internal = 6 * (arms() - 1);
        const Index free = free_joints();
        solve_scratch_.noalias() = reduced_q_.transpose().lazyProduct(x);  // x is not read after this line
        solve_internal_.noalias() =
            reduced_q_.template leftCols<Internal>(internal).lazyProduct(solve_scratch_.template head<Internal>(internal));  // Q1 v1
        auto free_part = solve_scratch_.template segment<Free>(internal, free);  // (tail<N>(n) ignores n)
        free_part.noalias() -= free_rows_inertia_.lazyProduct(solve_internal_);  // Q2^T M Q1 v1
        free_inertia_factor_.solveInPlace(free_part);
        out = solve_internal_;
        out.noalias() += reduced_q_.template rightCols<Free>(free).lazyProduct(free_part);
    }

    Index arms() const noexcept { return constraint_jacobian.rows() / 6; }
    Index joints() const noexcept { return projector.rows(); }

    Eigen::Matrix<Scalar, 3, Arms> contact_offsets;        ///< r, 3 x K, {w}
    Eigen::Matrix<Scalar, 6, Stack> grasp;                  ///< G (24), 6 x 6K
    Eigen::Matrix<Scalar, 6, Joints> object_jacobian;       ///< Jx, 6 x Q
    Eigen::Matrix<Scalar, Stack, Joints> constraint_jacobian;  ///< Jc, 6K x Q, L(13)
    Eigen::Matrix<Scalar, Stack, Internal> internal_basis;  ///< B, 6K x 6(K-1), orthonormal, G B = 0
    /// Jr^T = J^T B (Q x 6(K-1)): the torques of the internal wrenches, tau_c = Jr^T z for w = B z
    Eigen::Matrix<Scalar, Joints, Internal> reduced_jacobian_transpose;
    JointMatrix projector;                                  ///< P, L(4) (formed when form_projection_matrices)
    JointMatrix constrained_inertia;                        ///< Mc = P M + I - P, L(26) (when form_projection_matrices)
    Matrix6<Scalar> task_inertia;                           ///< Lambda_c, L(15)
    Vector6<Scalar> task_bias;                              ///< hc, L(15)
    Vector6<Scalar> object_twist;                           ///< Jx qdot
    Vector6<Scalar> object_jacobian_rate_qdot;              ///< Jxdot qdot
    StackVector constraint_jacobian_rate_qdot;              ///< Jcdot qdot
    JointVector projector_rate_qdot;                        ///< Pdot qdot = -Jc^+ Jcdot qdot
    ProjectionStatus status = ProjectionStatus::ok;

private:
    static constexpr int Free = free_joint_dimension(Joints, Arms);
    using Basis = Eigen::Matrix<Scalar, Stack, Internal>;
    using ReducedJacobianTranspose = Eigen::Matrix<Scalar, Joints, Internal>;
    using FreeMatrix = Eigen::Matrix<Scalar, Free, Free>;

    Index free_joints() const noexcept { return reduced_q_.cols() - 6 * (arms() - 1); }
    /// compute() and compute_with_basis() after B is set: the stages below, in order.
    template <typename DerivedM, typename DerivedH, typename DerivedJ, typename DerivedJdotQdot, typename DerivedQdot,
              typename DerivedR>
    ProjectionStatus evaluate(const Eigen::MatrixBase<DerivedM>& M, const Eigen::MatrixBase<DerivedH>& h,
                              const Eigen::MatrixBase<DerivedJ>& J, const Eigen::MatrixBase<DerivedJdotQdot>& Jdot_qdot,
                              const Eigen::MatrixBase<DerivedQdot>& qdot, const Eigen::MatrixBase<DerivedR>& r) noexcept
    {
        const Index joints = this->joints();
        COOPDYN_REQUIRE_SHAPE(r.cols() == arms() && J.rows() == 6 * arms() && J.cols() == joints && M.rows() == joints &&
                                  M.cols() == joints && h.size() == joints && qdot.size() == joints &&
                                  Jdot_qdot.size() == 6 * arms(),
                              "projected dynamics: inputs sized for another number of arms or joints");
        // A stage that meets a singular factor ends the evaluation (its status says which).
        compute_grasp_jacobians(J, r);
        status = factor_constraint(J);
        if (status == ProjectionStatus::ok) status = factor_free_inertia(M);
        if (status == ProjectionStatus::ok) status = factor_task_inertia();
        if (status != ProjectionStatus::ok) return status;
        compute_rates(J, Jdot_qdot, qdot);  // the exact rates, on the constraint manifold
        compute_task_bias(h);
        return status;
    }

    /// B from the closed-form basis by a Householder QR (as internal_wrench_basis; no allocation: the
    /// reflectors and the workspace were sized at construction).
    template <typename DerivedR>
    void compute_basis(const Eigen::MatrixBase<DerivedR>& r) noexcept
    {
        COOPDYN_REQUIRE_SHAPE(r.cols() == arms(), "projected dynamics: r sized for another number of arms");
        detail::write_internal_wrench_basis(r, closed_form_basis_, basis_reflectors_, basis_tau_, basis_workspace_,
                                            internal_basis);
    }

    // The stages of evaluate, in order; each needs the ones before it.
    /// Grasp geometry: G (24), Jx = (G G^T)^-1 G J and Jc = J - G^T Jx (L(13)). G G^T is the composite
    /// inertia of unit masses with unit rotational inertia at the r_i (G_i diag(I, I) G_i^T), factored
    /// once about their centroid (the unit-weight inverse of (25), model/grasp_inverse.hpp); G and G^T
    /// are applied per contact (G_i = [[I, 0], [S(r_i), I]], (24)).
    template <typename DerivedJ, typename DerivedR>
    void compute_grasp_jacobians(const Eigen::MatrixBase<DerivedJ>& J, const Eigen::MatrixBase<DerivedR>& r) noexcept
    {
        contact_offsets = r;
        write_grasp_matrix(contact_offsets, grasp);
        grasp_inverse_.compute(detail::UnitGraspWeights<Scalar>{arms()}, contact_offsets);  // valid: J*_o >= K I3
        detail::write_object_jacobian(grasp_inverse_, contact_offsets, J, object_jacobian);
        detail::write_constraint_jacobian(contact_offsets, J, object_jacobian, constraint_jacobian);
    }

    /// Jc^+ through Jr = B^T J (errata E10), by a Householder QR Jr^T = Q1 R: Jr Jr^T = R^T R, and
    /// R's diagonal is its Cholesky factor's up to signs, so the pivot policy of a Cholesky
    /// factorisation of Jr Jr^T applies unchanged (numerics/pivot_policy.hpp). Jc^+ Jc =
    /// Jr^T (Jr Jr^T)^-1 Jr = Q1 Q1^T, so P = I - Q1 Q1^T (L(4)) without squaring Jr's condition
    /// number.
    template <typename DerivedJ>
    ProjectionStatus factor_constraint(const Eigen::MatrixBase<DerivedJ>& J) noexcept
    {
        const Index internal = 6 * (arms() - 1);
        if (joints() < internal) {
            return ProjectionStatus::singular_constraint;  // Jr has more rows than columns
        }
        const Index free = joints() - internal;
        reduced_jacobian_transpose.noalias() = J.transpose().lazyProduct(internal_basis);
        reduced_factor_ = reduced_jacobian_transpose;
        householder_qr_in_place(reduced_factor_, reduced_reflectors_, reduced_tau_);
        if (!regular_triangular_factor(reduced_r())) {
            return ProjectionStatus::singular_constraint;
        }
        householder_q(reduced_reflectors_, reduced_tau_, reduced_q_, reduced_workspace_);
        // P = I - Q1 Q1^T = Q2 Q2^T, from the thinner of the two (an output only). Coefficient-based
        // products throughout: at these sizes Eigen's GEMM path costs more in packing than in
        // arithmetic.
        if (form_projection_matrices) {
            if (free < internal) {
                const auto q2 = reduced_q_.template rightCols<Free>(free);
                projector.noalias() = q2.lazyProduct(q2.transpose());
            } else {
                const auto q1 = reduced_q_.template leftCols<Internal>(internal);
                projector.setIdentity();
                projector.noalias() -= q1.lazyProduct(q1.transpose());
            }
        }
        return ProjectionStatus::ok;
    }

    /// Mc = P M + I - P = Q2 (Q2^T M) + I - P (L(26)); M22 = (Q2^T M) Q2 and its Cholesky factor (the
    /// class comment): Mc^-1 needs only that.
    template <typename DerivedM>
    ProjectionStatus factor_free_inertia(const Eigen::MatrixBase<DerivedM>& M) noexcept
    {
        const auto q2 = reduced_q_.template rightCols<Free>(free_joints());
        free_rows_inertia_.noalias() = q2.transpose().lazyProduct(M);
        if (form_projection_matrices) {
            constrained_inertia = -projector;
            constrained_inertia.diagonal().array() += Scalar(1);
            constrained_inertia.noalias() += q2.lazyProduct(free_rows_inertia_);
        }
        free_inertia_.noalias() = free_rows_inertia_.lazyProduct(q2);
        free_inertia_factor_.compute(free_inertia_);
        if (free_inertia_factor_.info() != Eigen::Success) {
            return ProjectionStatus::singular_task;  // M not positive definite on the grasp's motions
        }
        return ProjectionStatus::ok;
    }

    /// Lambda_c^-1 = Jx Mc^-1 P Jx^T = E^T E, E = L22^-1 Q2^T Jx^T (L(15)), and Lambda_c = L^-T L^-1
    /// (task_factor_ = L L^T), symmetric by construction.
    ProjectionStatus factor_task_inertia() noexcept
    {
        task_reduced_.noalias() = reduced_q_.template rightCols<Free>(free_joints()).transpose().lazyProduct(
            object_jacobian.transpose());
        free_inertia_factor_.solve_lower_in_place(task_reduced_);
        task_factor_.compute(task_reduced_.transpose().lazyProduct(task_reduced_));
        if (!regular_llt(task_factor_)) {
            return ProjectionStatus::singular_task;
        }
        Matrix6<Scalar> task_factor_inverse = Matrix6<Scalar>::Identity();
        task_factor_.solve_lower_in_place(task_factor_inverse);
        task_inertia.noalias() = task_factor_inverse.transpose().lazyProduct(task_factor_inverse);
        return ProjectionStatus::ok;
    }

    /// Jxdot qdot, Jcdot qdot (model/grasp_jacobians.hpp) and Pdot qdot in closed form:
    ///   P = I - Jc^+ Jc  =>  Pdot qdot = -Jc^+ Jcdot qdot   (the other term carries Jc qdot = 0)
    template <typename DerivedJ, typename DerivedJdotQdot, typename DerivedQdot>
    void compute_rates(const Eigen::MatrixBase<DerivedJ>& J, const Eigen::MatrixBase<DerivedJdotQdot>& Jdot_qdot,
                       const Eigen::MatrixBase<DerivedQdot>& qdot) noexcept
    {
        detail::write_grasp_jacobian_rates(grasp_inverse_, contact_offsets, J, Jdot_qdot, qdot, object_jacobian,
                                           object_twist, object_jacobian_rate_qdot, constraint_jacobian_rate_qdot,
                                           stack_scratch_);
        constraint_pseudo_inverse_times(constraint_jacobian_rate_qdot, projector_rate_qdot);
        projector_rate_qdot = -projector_rate_qdot;
    }

    /// hc = Lambda_c (Jx Mc^-1 (P h - Pdot qdot) - Jxdot qdot) (L(15)), after compute_rates.
    template <typename DerivedH>
    void compute_task_bias(const Eigen::MatrixBase<DerivedH>& h) noexcept
    {
        project(h, joint_scratch_);
        joint_scratch_ -= projector_rate_qdot;
        constrained_inertia_solve(joint_scratch_, joint_scratch_);
        object_twist_rate_ = object_jacobian.lazyProduct(joint_scratch_) - object_jacobian_rate_qdot;
        task_bias.noalias() = task_inertia.lazyProduct(object_twist_rate_);
    }

    /// R of Jr^T = Q1 R (Jr Jr^T = R^T R) in its upper triangle.
    auto reduced_r() const noexcept
    {
        const Index internal = 6 * (arms() - 1);
        return reduced_factor_.template topLeftCorner<Internal, Internal>(internal, internal);
    }

    detail::WeightedGrasp<Scalar> grasp_inverse_;  // G G^T about the contacts' centroid, factored (unit weights)
    Basis closed_form_basis_;  // then its R
    Basis basis_reflectors_;
    Eigen::Matrix<Scalar, Internal, 1> basis_tau_;
    Eigen::Matrix<Scalar, 1, Internal> basis_workspace_;
    ReducedJacobianTranspose reduced_factor_;  // Jr^T, then R of Jr^T = Q1 R in its upper triangle
    ReducedJacobianTranspose reduced_reflectors_;
    Eigen::Matrix<Scalar, Internal, 1> reduced_tau_;
    JointMatrix reduced_q_;        // [Q1 Q2]
    Eigen::Matrix<Scalar, Free, Joints> free_rows_inertia_;  // Q2^T M
    FreeMatrix free_inertia_;      // M22 = Q2^T M Q2
    Llt<FreeMatrix> free_inertia_factor_;
    Eigen::Matrix<Scalar, Free, 6> task_reduced_;  // E = L22^-1 Q2^T Jx^T
    Llt<Matrix6<Scalar>> task_factor_;
    // Scratch of the products above (project, the pseudo-inverses, self_motion_projection,
    // constrained_inertia_solve): those methods write it, so they are non-const rather than the
    // scratch mutable (a const ProjectedDynamics shared between threads would race on it).
    Eigen::Matrix<Scalar, Internal, 1> reduced_;
    StackVector stack_scratch_;
    Vector6<Scalar> object_twist_rate_;  // Jx Mc^-1 (P h - Pdot qdot) - Jxdot qdot
    JointVector joint_scratch_;
    Eigen::Matrix<Scalar, 1, Joints> reduced_workspace_;
    JointVector solve_scratch_;
    JointVector solve_internal_;
    Eigen::Matrix<Scalar, Free, 1> free_scratch_;
    Vector6<Scalar> task_scratch_;
};

template <typename Scalar, int Arms, int Joints>
ProjectedDynamics<Scalar, Arms, Joints>::ProjectedDynamics(Index arms, Index joints)
    : contact_offsets(Eigen::Matrix<Scalar, 3, Arms>::Zero(3, arms)),
      grasp(Eigen::Matrix<Scalar, 6, Stack>::Zero(6, 6 * arms)),
      object_jacobian(Eigen::Matrix<Scalar, 6, Joints>::Zero(6, joints)),
      constraint_jacobian(Eigen::Matrix<Scalar, Stack, Joints>::Zero(6 * arms, joints)),
      internal_basis(Basis::Zero(6 * arms, 6 * (arms - 1))),
      reduced_jacobian_transpose(Eigen::Matrix<Scalar, Joints, Internal>::Zero(joints, 6 * (arms - 1))),
      projector(JointMatrix::Identity(joints, joints)),
      constrained_inertia(JointMatrix::Identity(joints, joints)),
      task_inertia(Matrix6<Scalar>::Identity()),
      task_bias(Vector6<Scalar>::Zero()),
      object_twist(Vector6<Scalar>::Zero()),
      object_jacobian_rate_qdot(Vector6<Scalar>::Zero()),
      constraint_jacobian_rate_qdot(StackVector::Zero(6 * arms)),
      projector_rate_qdot(JointVector::Zero(joints)),
      closed_form_basis_(Basis::Zero(6 * arms, 6 * (arms - 1))),
      basis_reflectors_(Basis::Zero(6 * arms, 6 * (arms - 1))),
      basis_tau_(Eigen::Matrix<Scalar, Internal, 1>::Zero(6 * (arms - 1))),
      basis_workspace_(Eigen::Matrix<Scalar, 1, Internal>::Zero(1, 6 * (arms - 1))),
      reduced_factor_(ReducedJacobianTranspose::Zero(joints, 6 * (arms - 1))),
      reduced_reflectors_(ReducedJacobianTranspose::Zero(joints, 6 * (arms - 1))),
      reduced_tau_(Eigen::Matrix<Scalar, Internal, 1>::Zero(6 * (arms - 1))),
      reduced_q_(JointMatrix::Identity(joints, joints)),
      free_rows_inertia_(Eigen::Matrix<Scalar, Free, Joints>::Zero(std::max<Index>(joints - 6 * (arms - 1), 0), joints)),
      free_inertia_(FreeMatrix::Identity(std::max<Index>(joints - 6 * (arms - 1), 0),
                                         std::max<Index>(joints - 6 * (arms - 1), 0))),
      free_inertia_factor_(std::max<Index>(joints - 6 * (arms - 1), 0)),
      task_reduced_(Eigen::Matrix<Scalar, Free, 6>::Zero(std::max<Index>(joints - 6 * (arms - 1), 0), 6)),
      task_factor_(6),
      reduced_(Eigen::Matrix<Scalar, Internal, 1>::Zero(6 * (arms - 1))),
      stack_scratch_(StackVector::Zero(6 * arms)),
      object_twist_rate_(Vector6<Scalar>::Zero()),
      joint_scratch_(JointVector::Zero(joints)),
      reduced_workspace_(Eigen::Matrix<Scalar, 1, Joints>::Zero(1, joints)),
      solve_scratch_(JointVector::Zero(joints)),
      solve_internal_(JointVector::Zero(joints)),
      free_scratch_(Eigen::Matrix<Scalar, Free, 1>::Zero(std::max<Index>(joints - 6 * (arms - 1), 0))),
      task_scratch_(Vector6<Scalar>::Zero())
{
    COOPDYN_ASSERT(arms >= 2, "projected dynamics need at least two arms");
    COOPDYN_ASSERT(Arms == Eigen::Dynamic || arms == Arms, "arms must equal the fixed K");
    COOPDYN_ASSERT(Joints == Eigen::Dynamic || joints == Joints, "joints must equal the fixed Q");
}

/// Jc^+ x = Jr^T (Jr Jr^T)^-1 B^T x = Q1 R^-T B^T x (Jc = B Jr, B orthonormal, Jr^T = Q1 R of
/// full column rank; errata E10).
template <typename Scalar, int Arms, int Joints>
template <typename DerivedIn, typename DerivedOut>
void ProjectedDynamics<Scalar, Arms, Joints>::constraint_pseudo_inverse_times(
    const Eigen::MatrixBase<DerivedIn>& x, const Eigen::MatrixBase<DerivedOut>& out_) noexcept
{
    auto& out = const_cast<Eigen::MatrixBase<DerivedOut>&>(out_);
    auto& reduced = reduced_;
    reduced.noalias() = internal_basis.transpose().lazyProduct(x);
    solve_upper_transpose_in_place(reduced_r(), reduced);  // R^-T: plain loops, numerics/triangular_solve.hpp
    out.noalias() = reduced_q_.template leftCols<Internal>(reduced.size()).lazyProduct(reduced);
}

/// (Jc^T)^+ y = B (Jr Jr^T)^-1 Jr y = B R^-1 Q1^T y: the minimum-norm lambda with Jc^T lambda =
/// P-free part of y.
template <typename Scalar, int Arms, int Joints>
template <typename DerivedIn, typename DerivedOut>
void ProjectedDynamics<Scalar, Arms, Joints>::constraint_transpose_pseudo_inverse_times(
    const Eigen::MatrixBase<DerivedIn>& y, const Eigen::MatrixBase<DerivedOut>& out_) noexcept
{
    auto& out = const_cast<Eigen::MatrixBase<DerivedOut>&>(out_);
    auto& reduced = reduced_;
    reduced.noalias() = reduced_q_.template leftCols<Internal>(reduced.size()).transpose().lazyProduct(y);
    solve_upper_in_place(reduced_r(), reduced);  // R^-1
    out.noalias() = internal_basis.lazyProduct(reduced);
}

/// \brief Projected dynamics L(4), (15), (26) at one configuration, by value (allocates for dynamic
/// sizes; use a ProjectedDynamics workspace in a control loop). Arguments as in
/// ProjectedDynamics::compute; check `.status`.
template <typename DerivedM, typename DerivedH, typename DerivedJ, typename DerivedJdotQdot, typename DerivedQdot,
          typename DerivedR>
ProjectedDynamics<typename DerivedM::Scalar, DerivedR::ColsAtCompileTime, DerivedJ::ColsAtCompileTime>
projected_dynamics(const Eigen::MatrixBase<DerivedM>& M, const Eigen::MatrixBase<DerivedH>& h,
                   const Eigen::MatrixBase<DerivedJ>& J, const Eigen::MatrixBase<DerivedJdotQdot>& Jdot_qdot,
                   const Eigen::MatrixBase<DerivedQdot>& qdot, const Eigen::MatrixBase<DerivedR>& r)
{
    ProjectedDynamics<typename DerivedM::Scalar, DerivedR::ColsAtCompileTime, DerivedJ::ColsAtCompileTime> result(
        r.cols(), J.cols());
    result.compute(M, h, J, Jdot_qdot, qdot, r);
    return result;
}

}  // namespace coopdyn
