/// \file
/// \brief Projected inverse dynamics of K arms holding one object (the second paper, Lin et al.):
/// the grasp's constraint and object Jacobians, an orthonormal basis of the internal wrenches, and
/// the projected dynamics L(4)-(6), (13), (15) with their exact derivative terms; docs/control.md.
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
///     Mc = P M + I - P                         L(5)
///     Lambda_c = (Jx Mc^-1 P Jx^T)^-1          L(6)
///     hc = Lambda_c (Jx Mc^-1 (P h - Pdot qdot) - Jxdot qdot)       L(15): Lambda_c xdd_o + hc = F + F_x
///
/// Errata E10: Jc has rank 6K - 6, not 6K. The library never inverts Jc Jc^T: with B (6K x 6(K-1))
/// an orthonormal basis of null(G), N = B B^T and Jc = B Jr with Jr = B^T J of full row rank (when
/// J has), so Jc^+ = Jr^T (Jr Jr^T)^-1 B^T, a Cholesky factorisation of a 6(K-1) square matrix.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/model/grasp.hpp"
#include "coopdyn/spatial/skew.hpp"
#include "coopdyn/spatial/spatial_vector.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Householder>
#include <Eigen/LU>
#include <Eigen/QR>

namespace coopdyn {

/// 6(K - 1), the dimension of the internal wrenches of K contacts (Dynamic passes through).
constexpr int internal_wrench_dimension(int arms) noexcept
{
    return arms == Eigen::Dynamic ? Eigen::Dynamic : 6 * (arms - 1);
}

namespace detail {

/// G G^T (6 x 6, symmetric positive definite for any grasp: its lower-right block contains K I3).
template <typename DerivedG> Matrix6<typename DerivedG::Scalar> grasp_gram(const Eigen::MatrixBase<DerivedG>& grasp)
{
    return grasp * grasp.transpose();
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

/// A Cholesky factor of a matrix that is regular to rounding: min L_jj^2 > 1000 eps max L_jj^2
/// (the squared pivot ratio bounds the condition number from below). A rank-deficient Gram matrix
/// factors "successfully" in floating point with a pivot of rounding size; this catches it.
template <typename Factor> bool regular_cholesky(const Factor& factor) noexcept
{
    using Real = typename Eigen::NumTraits<typename Factor::Scalar>::Real;
    if (factor.info() != Eigen::Success) {
        return false;
    }
    const auto pivots = factor.matrixLLT().diagonal().cwiseAbs2();
    return pivots.minCoeff() > Real(1000) * Eigen::NumTraits<Real>::epsilon() * pivots.maxCoeff();
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

}  // namespace detail

/// \brief Object Jacobian Jx = (G G^T)^-1 G J (6 x Q): the object's twist xdot_o = Jx qdot while
/// the grasp holds (the least-squares rigid motion of the contacts in general).
/// \param r 3 x K contact points relative to the object's centre, {w}.
/// \param J 6K x Q stacked contact Jacobians.
template <typename DerivedR, typename DerivedJ>
Eigen::Matrix<typename DerivedJ::Scalar, 6, DerivedJ::ColsAtCompileTime>
object_jacobian(const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedJ>& J)
{
    COOPDYN_ASSERT(J.rows() == 6 * r.cols(), "J must have 6K rows");
    const auto grasp = grasp_matrix(r);
    return detail::grasp_gram(grasp).llt().solve(grasp * J);
}

/// \brief Constraint Jacobian Jc = (I - G^+ G) J = J - G^T Jx (6K x Q), L(13): Jc qdot = 0 says
/// the contacts move as one rigid body. Row block i is contact i's twist minus the twist the
/// object's motion Jx qdot gives point r_i. Rank 6K - 6 (errata E10).
template <typename DerivedR, typename DerivedJ>
Eigen::Matrix<typename DerivedJ::Scalar, DerivedJ::RowsAtCompileTime, DerivedJ::ColsAtCompileTime>
constraint_jacobian(const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedJ>& J)
{
    const auto grasp = grasp_matrix(r);
    const Eigen::Matrix<typename DerivedJ::Scalar, 6, DerivedJ::ColsAtCompileTime> jx =
        detail::grasp_gram(grasp).llt().solve(grasp * J);
    Eigen::Matrix<typename DerivedJ::Scalar, DerivedJ::RowsAtCompileTime, DerivedJ::ColsAtCompileTime> result = J;
    result.noalias() -= grasp.transpose() * jx;
    return result;
}

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
    COOPDYN_ASSERT(r.cols() >= 2, "internal wrenches need at least two contacts");
    const Index arms = r.cols();
    Basis closed_form = Basis::Zero(6 * arms, 6 * (arms - 1));
    detail::closed_form_internal_basis(r, closed_form);
    const Eigen::HouseholderQR<Basis> qr(closed_form);
    Basis basis = Basis::Identity(6 * arms, 6 * (arms - 1));
    qr.householderQ().applyThisOnTheLeft(basis);
    return basis;
}

/// Outcome of a projected-dynamics evaluation. Not ok means a singular configuration: the
/// results are not to be used (they are finite but meaningless).
enum class ProjectionStatus {
    ok,
    singular_constraint,  ///< Jr Jr^T not positive definite: J lost rank (an arm at a singularity)
    singular_task,        ///< Jx Mc^-1 P Jx^T not invertible: the object cannot be moved in some direction
};

/// \brief Workspace and results of the projected dynamics for K arms and Q joints (fixed or
/// Dynamic). Sized once at construction; compute() is noexcept and allocates nothing.
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
                             const Eigen::MatrixBase<DerivedQdot>& qdot, const Eigen::MatrixBase<DerivedR>& r) noexcept;

    /// x -> Jc^+ x (6K -> Q), the minimum-norm solution of Jc y = N x.
    template <typename DerivedIn, typename DerivedOut>
    void constraint_pseudo_inverse_times(const Eigen::MatrixBase<DerivedIn>& x,
                                         const Eigen::MatrixBase<DerivedOut>& out) const noexcept;
    /// y -> (Jc^T)^+ y (Q -> 6K), the minimum-norm least-squares solution of Jc^T lambda = y; it
    /// lies in null(G).
    template <typename DerivedIn, typename DerivedOut>
    void constraint_transpose_pseudo_inverse_times(const Eigen::MatrixBase<DerivedIn>& y,
                                                   const Eigen::MatrixBase<DerivedOut>& out) const noexcept;
    /// out -= G^+ F, G^+ F = G^T (G G^T)^-1 F (6 -> 6K): the least-norm contact wrenches whose net
    /// wrench on the object is F.
    template <typename DerivedIn, typename DerivedOut>
    void subtract_grasp_pseudo_inverse_times(const Eigen::MatrixBase<DerivedIn>& wrench,
                                             const Eigen::MatrixBase<DerivedOut>& out) const noexcept
    {
        const Vector6<Scalar> solved = grasp_gram_factor_.solve(wrench);
        const_cast<Eigen::MatrixBase<DerivedOut>&>(out).noalias() -= grasp.transpose() * solved;
    }
    /// x -> Mc^-1 x (Q, into out; out may be x itself: x is copied first, because PartialPivLU
    /// permutes an aliased right-hand side through a heap-allocated mask).
    template <typename DerivedIn, typename DerivedOut>
    void constrained_inertia_solve(const Eigen::MatrixBase<DerivedIn>& x, const Eigen::MatrixBase<DerivedOut>& out) const noexcept
    {
        solve_scratch_ = x;
        const_cast<Eigen::MatrixBase<DerivedOut>&>(out) = constrained_inertia_factor_.solve(solve_scratch_);
    }

    Index arms() const noexcept { return constraint_jacobian.rows() / 6; }
    Index joints() const noexcept { return projector.rows(); }

    Eigen::Matrix<Scalar, 3, Arms> contact_offsets;        ///< r, 3 x K, {w}
    Eigen::Matrix<Scalar, 6, Stack> grasp;                  ///< G (24), 6 x 6K
    Eigen::Matrix<Scalar, 6, Joints> object_jacobian;       ///< Jx, 6 x Q
    Eigen::Matrix<Scalar, Stack, Joints> constraint_jacobian;  ///< Jc, 6K x Q, L(13)
    Eigen::Matrix<Scalar, Stack, Internal> internal_basis;  ///< B, 6K x 6(K-1), orthonormal, G B = 0
    JointMatrix projector;                                  ///< P, L(4)
    JointMatrix constrained_inertia;                        ///< Mc = P M + I - P, L(5)
    Matrix6<Scalar> task_inertia;                           ///< Lambda_c, L(6)
    Vector6<Scalar> task_bias;                              ///< hc, L(15)
    Vector6<Scalar> object_twist;                           ///< Jx qdot
    Vector6<Scalar> object_jacobian_rate_qdot;              ///< Jxdot qdot
    StackVector constraint_jacobian_rate_qdot;              ///< Jcdot qdot
    JointVector projector_rate_qdot;                        ///< Pdot qdot = -Jc^+ Jcdot qdot
    ProjectionStatus status = ProjectionStatus::ok;

private:
    using ReducedJacobian = Eigen::Matrix<Scalar, Internal, Joints>;
    using ReducedMatrix = Eigen::Matrix<Scalar, Internal, Internal>;
    using Basis = Eigen::Matrix<Scalar, Stack, Internal>;

    void compute_basis() noexcept;
    template <typename DerivedJ, typename DerivedJdotQdot, typename DerivedQdot>
    void compute_rates(const Eigen::MatrixBase<DerivedJ>& J, const Eigen::MatrixBase<DerivedJdotQdot>& Jdot_qdot,
                       const Eigen::MatrixBase<DerivedQdot>& qdot) noexcept;

    Eigen::LLT<Matrix6<Scalar>> grasp_gram_factor_;
    Basis closed_form_basis_;
    Eigen::HouseholderQR<Basis> basis_qr_;
    Eigen::Matrix<Scalar, 1, Internal> householder_workspace_;
    ReducedJacobian reduced_jacobian_;  // Jr = B^T J
    ReducedMatrix reduced_gram_;        // Jr Jr^T
    Eigen::LLT<ReducedMatrix> reduced_gram_factor_;
    ReducedJacobian reduced_solved_;    // (Jr Jr^T)^-1 Jr
    Eigen::PartialPivLU<JointMatrix> constrained_inertia_factor_;
    Eigen::Matrix<Scalar, Joints, 6> object_jacobian_scratch_;              // P Jx^T
    Eigen::Matrix<Scalar, Joints, 6> projected_object_jacobian_transpose_;  // Mc^-1 P Jx^T
    Eigen::LLT<Matrix6<Scalar>> task_factor_;
    mutable Eigen::Matrix<Scalar, Internal, 1> reduced_;  // scratch of the pseudo-inverse products
    StackVector stack_scratch_;
    JointVector joint_scratch_;
    mutable JointVector solve_scratch_;
};

// ---------------------------------------------------------------------------------------------

template <typename Scalar, int Arms, int Joints>
ProjectedDynamics<Scalar, Arms, Joints>::ProjectedDynamics(Index arms, Index joints)
    : contact_offsets(Eigen::Matrix<Scalar, 3, Arms>::Zero(3, arms)),
      grasp(Eigen::Matrix<Scalar, 6, Stack>::Zero(6, 6 * arms)),
      object_jacobian(Eigen::Matrix<Scalar, 6, Joints>::Zero(6, joints)),
      constraint_jacobian(Eigen::Matrix<Scalar, Stack, Joints>::Zero(6 * arms, joints)),
      internal_basis(Basis::Zero(6 * arms, 6 * (arms - 1))),
      projector(JointMatrix::Identity(joints, joints)),
      constrained_inertia(JointMatrix::Identity(joints, joints)),
      task_inertia(Matrix6<Scalar>::Identity()),
      task_bias(Vector6<Scalar>::Zero()),
      object_twist(Vector6<Scalar>::Zero()),
      object_jacobian_rate_qdot(Vector6<Scalar>::Zero()),
      constraint_jacobian_rate_qdot(StackVector::Zero(6 * arms)),
      projector_rate_qdot(JointVector::Zero(joints)),
      grasp_gram_factor_(6),
      closed_form_basis_(Basis::Zero(6 * arms, 6 * (arms - 1))),
      basis_qr_(6 * arms, 6 * (arms - 1)),
      householder_workspace_(Eigen::Matrix<Scalar, 1, Internal>::Zero(1, 6 * (arms - 1))),
      reduced_jacobian_(ReducedJacobian::Zero(6 * (arms - 1), joints)),
      reduced_gram_(ReducedMatrix::Zero(6 * (arms - 1), 6 * (arms - 1))),
      reduced_gram_factor_(6 * (arms - 1)),
      reduced_solved_(ReducedJacobian::Zero(6 * (arms - 1), joints)),
      constrained_inertia_factor_(joints),
      object_jacobian_scratch_(Eigen::Matrix<Scalar, Joints, 6>::Zero(joints, 6)),
      projected_object_jacobian_transpose_(Eigen::Matrix<Scalar, Joints, 6>::Zero(joints, 6)),
      task_factor_(6),
      reduced_(Eigen::Matrix<Scalar, Internal, 1>::Zero(6 * (arms - 1))),
      stack_scratch_(StackVector::Zero(6 * arms)),
      joint_scratch_(JointVector::Zero(joints)),
      solve_scratch_(JointVector::Zero(joints))
{
    COOPDYN_ASSERT(arms >= 2, "projected dynamics need at least two arms");
    COOPDYN_ASSERT(Arms == Eigen::Dynamic || arms == Arms, "arms must equal the fixed K");
    COOPDYN_ASSERT(Joints == Eigen::Dynamic || joints == Joints, "joints must equal the fixed Q");
}

/// B from the closed-form basis, orthonormalised in place (no allocation: the QR and its
/// Householder workspace were sized at construction).
template <typename Scalar, int Arms, int Joints>
void ProjectedDynamics<Scalar, Arms, Joints>::compute_basis() noexcept
{
    detail::closed_form_internal_basis(contact_offsets, closed_form_basis_);
    basis_qr_.compute(closed_form_basis_);
    internal_basis.setIdentity();
    basis_qr_.householderQ().applyThisOnTheLeft(internal_basis, householder_workspace_);
}

template <typename Scalar, int Arms, int Joints>
template <typename DerivedM, typename DerivedH, typename DerivedJ, typename DerivedJdotQdot, typename DerivedQdot,
          typename DerivedR>
ProjectionStatus ProjectedDynamics<Scalar, Arms, Joints>::compute(
    const Eigen::MatrixBase<DerivedM>& M, const Eigen::MatrixBase<DerivedH>& h, const Eigen::MatrixBase<DerivedJ>& J,
    const Eigen::MatrixBase<DerivedJdotQdot>& Jdot_qdot, const Eigen::MatrixBase<DerivedQdot>& qdot,
    const Eigen::MatrixBase<DerivedR>& r) noexcept
{
    const Index joints = this->joints();
    COOPDYN_REQUIRE_SHAPE(r.cols() == arms() && J.rows() == 6 * arms() && J.cols() == joints && M.rows() == joints &&
                              M.cols() == joints && h.size() == joints && qdot.size() == joints &&
                              Jdot_qdot.size() == 6 * arms(),
                          "projected dynamics: inputs sized for another number of arms or joints");
    // Grasp geometry: G, Jx = (G G^T)^-1 G J, Jc = J - G^T Jx, B.
    contact_offsets = r;
    write_grasp_matrix(contact_offsets, grasp);
    grasp_gram_factor_.compute(detail::grasp_gram(grasp));
    object_jacobian.noalias() = grasp * J;
    grasp_gram_factor_.solveInPlace(object_jacobian);
    constraint_jacobian = J;
    constraint_jacobian.noalias() -= grasp.transpose() * object_jacobian;
    compute_basis();

    // Jc^+ through Jr = B^T J (errata E10): P = I - Jr^T (Jr Jr^T)^-1 Jr.
    reduced_jacobian_.noalias() = internal_basis.transpose() * J;
    reduced_gram_.noalias() = reduced_jacobian_ * reduced_jacobian_.transpose();
    reduced_gram_factor_.compute(reduced_gram_);
    if (!detail::regular_cholesky(reduced_gram_factor_)) {
        status = ProjectionStatus::singular_constraint;
        return status;
    }
    reduced_solved_ = reduced_jacobian_;
    reduced_gram_factor_.solveInPlace(reduced_solved_);  // (Jr Jr^T)^-1 Jr
    projector.setIdentity();
    projector.noalias() -= reduced_jacobian_.transpose() * reduced_solved_;

    // Mc = P M + I - P (L(5)) and Lambda_c = (Jx Mc^-1 P Jx^T)^-1 (L(6)).
    constrained_inertia.noalias() = projector * M;
    constrained_inertia += JointMatrix::Identity(joints, joints) - projector;
    constrained_inertia_factor_.compute(constrained_inertia);
    // Out of place: PartialPivLU permutes an aliased right-hand side through a heap-allocated mask.
    object_jacobian_scratch_.noalias() = projector * object_jacobian.transpose();
    projected_object_jacobian_transpose_ = constrained_inertia_factor_.solve(object_jacobian_scratch_);
    const Matrix6<Scalar> task_inverse = object_jacobian * projected_object_jacobian_transpose_;
    task_factor_.compute(Scalar(0.5) * (task_inverse + task_inverse.transpose()));
    if (!detail::regular_cholesky(task_factor_)) {
        status = ProjectionStatus::singular_task;
        return status;
    }
    task_inertia = task_factor_.solve(Matrix6<Scalar>::Identity());

    // The exact rates, on the constraint manifold.
    compute_rates(J, Jdot_qdot, qdot);

    // hc = Lambda_c (Jx Mc^-1 (P h - Pdot qdot) - Jxdot qdot) (L(15)).
    joint_scratch_.noalias() = projector * h;
    joint_scratch_ -= projector_rate_qdot;
    constrained_inertia_solve(joint_scratch_, joint_scratch_);
    task_bias.noalias() = task_inertia * (object_jacobian * joint_scratch_ - object_jacobian_rate_qdot);
    status = ProjectionStatus::ok;
    return status;
}

/// Jxdot qdot, Jcdot qdot and Pdot qdot in closed form. With v = J qdot, y = Jx qdot (the object's
/// twist), omega = y's angular part and rdot_i = omega x r_i (the contacts turn with the object):
///   A Jx = G J, A = G G^T  =>  Jxdot qdot = A^-1 (G Jdot qdot + Gdot v - Adot y),  Adot = Gdot G^T + G Gdot^T
///   Jc = J - G^T Jx        =>  Jcdot qdot = Jdot qdot - Gdot^T y - G^T Jxdot qdot
///   P = I - Jc^+ Jc        =>  Pdot qdot = -Jc^+ Jcdot qdot   (the other term carries Jc qdot = 0)
template <typename Scalar, int Arms, int Joints>
template <typename DerivedJ, typename DerivedJdotQdot, typename DerivedQdot>
void ProjectedDynamics<Scalar, Arms, Joints>::compute_rates(const Eigen::MatrixBase<DerivedJ>& J,
                                                             const Eigen::MatrixBase<DerivedJdotQdot>& Jdot_qdot,
                                                             const Eigen::MatrixBase<DerivedQdot>& qdot) noexcept
{
    object_twist.noalias() = object_jacobian * qdot;
    const Vector3<Scalar> omega = object_twist.template tail<3>();
    stack_scratch_.noalias() = J * qdot;  // v
    Vector6<Scalar> rate = grasp * Jdot_qdot + detail::grasp_rate_times(contact_offsets, omega, stack_scratch_);
    // Adot y = Gdot (G^T y) + G (Gdot^T y)
    stack_scratch_.noalias() = grasp.transpose() * object_twist;
    rate -= detail::grasp_rate_times(contact_offsets, omega, stack_scratch_);
    detail::grasp_rate_transpose_times(contact_offsets, omega, object_twist, stack_scratch_);  // Gdot^T y
    rate.noalias() -= grasp * stack_scratch_;
    object_jacobian_rate_qdot = grasp_gram_factor_.solve(rate);

    constraint_jacobian_rate_qdot = Jdot_qdot - stack_scratch_;
    constraint_jacobian_rate_qdot.noalias() -= grasp.transpose() * object_jacobian_rate_qdot;
    constraint_pseudo_inverse_times(constraint_jacobian_rate_qdot, projector_rate_qdot);
    projector_rate_qdot = -projector_rate_qdot;
}

/// Jc^+ x = Jr^T (Jr Jr^T)^-1 B^T x (Jc = B Jr, B orthonormal, Jr full row rank; errata E10).
template <typename Scalar, int Arms, int Joints>
template <typename DerivedIn, typename DerivedOut>
void ProjectedDynamics<Scalar, Arms, Joints>::constraint_pseudo_inverse_times(
    const Eigen::MatrixBase<DerivedIn>& x, const Eigen::MatrixBase<DerivedOut>& out_) const noexcept
{
    auto& out = const_cast<Eigen::MatrixBase<DerivedOut>&>(out_);
    auto& reduced = reduced_;
    reduced.noalias() = internal_basis.transpose() * x;
    reduced_gram_factor_.solveInPlace(reduced);
    out.noalias() = reduced_jacobian_.transpose() * reduced;
}

/// (Jc^T)^+ y = B (Jr Jr^T)^-1 Jr y: the minimum-norm lambda with Jc^T lambda = P-free part of y.
template <typename Scalar, int Arms, int Joints>
template <typename DerivedIn, typename DerivedOut>
void ProjectedDynamics<Scalar, Arms, Joints>::constraint_transpose_pseudo_inverse_times(
    const Eigen::MatrixBase<DerivedIn>& y, const Eigen::MatrixBase<DerivedOut>& out_) const noexcept
{
    auto& out = const_cast<Eigen::MatrixBase<DerivedOut>&>(out_);
    auto& reduced = reduced_;
    reduced.noalias() = reduced_jacobian_ * y;
    reduced_gram_factor_.solveInPlace(reduced);
    out.noalias() = internal_basis * reduced;
}

/// \brief Projected dynamics L(4)-(6), (15) at one configuration, by value (allocates for dynamic
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
