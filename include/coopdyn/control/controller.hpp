/// \file
/// \brief The projected inverse-dynamics controller of K arms holding an object (Lin et al.),
/// per tick: the impedance law L(16), the external-wrench estimate L(7), the contact-wrench bias
/// L(23)-(24) with errata E11, the contact QP L(20)-(25) in the internal-wrench coordinates z
/// (errata E10) with a least-violating fallback, and a posture torque for the arms' self-motion
/// (errata E12). docs/control.md, "The controller".
///
///     tau = tau_u + tau_c + tau_n
///     tau_u = P Jx^T F,   F = hc + Lambda_c xdd_d - D_d xtilde_dot - K_d xtilde            L(16)
///     F_x = Lambda_c xtilde_dd + D_d xtilde_dot + K_d xtilde                               L(7)
///     tau_c = J^T B z*,   z* = argmin objective(z) s.t. friction rows on w_0 + B z        L(20)-(25)
///     tau_n = (I - J^T (J M^-1 J^T)^-1 J M^-1) (h - K_n (q - q_n) - D_n qdot)            E12
///
/// xtilde = [p - p_d; 2 d_eta d_eps] with dq = q (x) q_d^-1 ((5): sin(theta) u, the first paper's
/// stiffness torque per unit stiffness), so the rotational stiffness is in N m/rad near the goal.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/control/contact_wrenches.hpp"
#include "coopdyn/control/controller_model.hpp"
#include "coopdyn/control/controller_status.hpp"
#include "coopdyn/control/projected_dynamics.hpp"
#include "coopdyn/detail/validation.hpp"
#include "coopdyn/numerics/fixed_llt.hpp"
#include "coopdyn/numerics/pivot_policy.hpp"
#include "coopdyn/numerics/qp_solver.hpp"
#include "coopdyn/spatial/quaternion.hpp"
#include "coopdyn/spatial/spatial_vector.hpp"

#include <limits>

namespace coopdyn {

/// \brief Everything a controller tick computes (outputs first) and the buffers it needs, sized
/// once from the model: controller_tick allocates nothing (fixed sizes, and Dynamic ones after
/// construction).
template <typename ScalarType, int ArmsAtCompileTime = Eigen::Dynamic, int JointsAtCompileTime = Eigen::Dynamic,
          int EdgesAtCompileTime = 8>
struct ControllerData {
    using Scalar = ScalarType;
    using Model = ControllerModel<Scalar, ArmsAtCompileTime, JointsAtCompileTime, EdgesAtCompileTime>;
    static constexpr int Arms = Model::Arms;
    static constexpr int Joints = Model::Joints;
    static constexpr int Stack = Model::Stack;
    static constexpr int Internal = Model::Internal;
    static constexpr int Rows = Model::Rows;
    using JointVector = Eigen::Matrix<Scalar, Joints, 1>;
    using JointMatrix = Eigen::Matrix<Scalar, Joints, Joints>;
    using StackVector = Eigen::Matrix<Scalar, Stack, 1>;
    using InternalVector = Eigen::Matrix<Scalar, Internal, 1>;
    using InternalMatrix = Eigen::Matrix<Scalar, Internal, Internal>;
    using ArmVector = Eigen::Matrix<Scalar, Arms, 1>;

    explicit ControllerData(const Model& model);

    Index arms() const noexcept { return friction_margins.size(); }
    Index joints() const noexcept { return torque.size(); }

    // ---- outputs of the last tick -------------------------------------------------------------
    ControlStatus status = ControlStatus::ok;
    /// The refused input when status is invalid_input, otherwise none (to_string names it).
    ControllerInputProblem input_problem = ControllerInputProblem::none;
    JointVector torque;                  ///< tau = tau_u + tau_c + tau_n, what to send to the arms
    JointVector motion_torque;           ///< tau_u = P Jx^T F, L(16)
    JointVector squeeze_torque;          ///< tau_c = J^T B z*
    JointVector posture_torque;          ///< tau_n (E12)
    Vector6<Scalar> pose_error;          ///< xtilde = [p - p_d; 2 d_eta d_eps]
    Vector6<Scalar> twist_error;         ///< xtilde_dot = xdot - xdot_d
    Vector6<Scalar> motion_wrench;       ///< F of L(16), on the object at its centre, {w}
    Vector6<Scalar> external_wrench;     ///< F_x of L(7), on the object at its centre, {w}
    StackVector contact_wrench_bias;     ///< w_0 = -G^+ F_x - eta (E11), the wrenches without squeeze
    StackVector contact_wrenches;        ///< w = w_0 + B z*: hand i on the object, about contact i, {w}
    /// Column i: contact i's predicted wrench [f; t] in its contact frame {c_i}: f_z is the normal
    /// force, (f_x, f_y) the tangential force, t the moments about the contact point.
    Eigen::Matrix<Scalar, 6, Arms> contact_frame_wrenches;
    /// Per contact, the margins of its predicted wrench split by the rows' units (friction_margins
    /// of friction.hpp): force_margins over the unilateral and pyramid rows (N), moment_margins
    /// over the torsion and centre-of-pressure rows (N m); < 0: that row is violated.
    ArmVector force_margins;
    ArmVector moment_margins;
    Scalar tightest_force_margin = Scalar(0);   ///< the smallest of force_margins (N)
    Scalar tightest_moment_margin = Scalar(0);  ///< the smallest of moment_margins (N m)
    /// Per contact, friction_margin of its predicted wrench: the smaller of its force and moment
    /// margins, which mixes N and N m (kept for compatibility; the split margins above say which).
    ArmVector friction_margins;
    Scalar tightest_margin = Scalar(0);  ///< the smallest of friction_margins (< 0: a row is violated)
    Index tightest_contact = 0;          ///< the contact it belongs to
    InternalVector squeeze;              ///< z*, the internal-wrench coordinates (N, N m; B orthonormal)
    bool qp_ran = false;                 ///< the contact QP ran this tick (false after a failed tick)
    QpStatus qp_status = QpStatus::solved;  ///< of the contact QP proper when qp_ran; solved (none failed) otherwise
    int qp_iterations = 0;               ///< its steps (plus the fallback's when it ran); 0 when !qp_ran
    bool fallback_used = false;          ///< the least-violating fallback supplied z*
    Scalar fallback_violation = Scalar(0);  ///< s, the worst row's violation under the fallback (>= 0)
    /// qdd under tau_u + tau_c (tau_c changes none) with the estimated F_x; the posture torque adds
    /// the self-motion M^-1 tau_n, which moves neither the object nor the contacts.
    JointVector joint_acceleration;
    Eigen::Matrix<Scalar, 3, times_three(Arms)> contact_rotations;  ///< [R_c1 ... R_cK], {c_i} to {w} (zero after invalid_input)
    /// Jx, Lambda_c, hc, Jr^T, ... of this tick, and the grasp it was computed for: the contact
    /// offsets r_i = R_o p_i (dynamics.contact_offsets, {w}) and the internal-wrench basis
    /// B = blkdiag(R6, ..., R6) B_body (dynamics.internal_basis), which the tick writes there
    /// directly (one owner). The tick does not form P and Mc (dynamics.form_projection_matrices
    /// is false: set it to read dynamics.projector and dynamics.constrained_inertia). After
    /// invalid_input the projection did not run (status marks it): its outputs are the last
    /// computed ones.
    ProjectedDynamics<Scalar, Arms, Joints> dynamics;

    // ---- workspace -----------------------------------------------------------------------------
    Llt<JointMatrix> inertia_factor;                       ///< M = L L^T: the input check that M is SPD
    InternalMatrix hessian;
    InternalVector gradient;
    Eigen::Matrix<Scalar, Rows, 1> bounds;
    /// The contact QP and its least-violating fallback are solved by one QpSolver type, (n + 1)
    /// variables and (m + 1) rows, so that it is compiled once, not for two sizes (it was a tenth
    /// of the controller's compile time; docs/performance.md, "Compile time and CI"). The contact
    /// QP in z is posed there in (z, t): H' = blkdiag(H, eta), g' = (g, 0), rows [C, 0; 0, -1],
    /// d' = (d, 0) (padded_problem). t = 0 at the unconstrained minimum and no row moves it
    /// (none has a t entry but -t <= 0, which t = 0 satisfies), so the iterates are the contact
    /// QP's own; the fallback's rows are [C, -|c|; 0, -1] (controller_fallback).
    using PaddedSolver = QpSolver<Scalar, plus_one(Internal), plus_one(Rows)>;
    Eigen::Matrix<Scalar, plus_one(Internal), plus_one(Internal)> padded_hessian;
    Eigen::Matrix<Scalar, plus_one(Internal), 1> padded_gradient;
    Eigen::Matrix<Scalar, plus_one(Rows), plus_one(Internal)> padded_constraints;  // the fallback's (construction only)
    Eigen::Matrix<Scalar, plus_one(Rows), 1> padded_bounds;
    PaddedSolver qp;           ///< the contact QP, padded
    PaddedSolver fallback_qp;  ///< the least-violating fallback
    JointVector joint_scratch;
    bool warm = false;  ///< the QP solved last tick (its active set starts this one)
};

template <typename Scalar, int Arms, int Joints, int Edges>
ControllerData<Scalar, Arms, Joints, Edges>::ControllerData(const Model& model)
    : torque(JointVector::Zero(model.joints())),
      motion_torque(JointVector::Zero(model.joints())),
      squeeze_torque(JointVector::Zero(model.joints())),
      posture_torque(JointVector::Zero(model.joints())),
      pose_error(Vector6<Scalar>::Zero()),
      twist_error(Vector6<Scalar>::Zero()),
      motion_wrench(Vector6<Scalar>::Zero()),
      external_wrench(Vector6<Scalar>::Zero()),
      contact_wrench_bias(StackVector::Zero(6 * model.arms())),
      contact_wrenches(StackVector::Zero(6 * model.arms())),
      contact_frame_wrenches(Eigen::Matrix<Scalar, 6, Arms>::Zero(6, model.arms())),
      force_margins(ArmVector::Zero(model.arms())),
      moment_margins(ArmVector::Zero(model.arms())),
      friction_margins(ArmVector::Zero(model.arms())),
      squeeze(InternalVector::Zero(6 * (model.arms() - 1))),
      joint_acceleration(JointVector::Zero(model.joints())),
      contact_rotations(Eigen::Matrix<Scalar, 3, times_three(Arms)>::Zero(3, 3 * model.arms())),
      dynamics(model.arms(), model.joints()),
      inertia_factor(model.joints()),
      hessian(InternalMatrix::Zero(6 * (model.arms() - 1), 6 * (model.arms() - 1))),
      gradient(InternalVector::Zero(6 * (model.arms() - 1))),
      bounds(Eigen::Matrix<Scalar, Rows, 1>::Zero(model.rows())),
      padded_hessian(Eigen::Matrix<Scalar, plus_one(Internal), plus_one(Internal)>::Zero(6 * model.arms() - 5,
                                                                                         6 * model.arms() - 5)),
      padded_gradient(Eigen::Matrix<Scalar, plus_one(Internal), 1>::Zero(6 * model.arms() - 5)),
      padded_constraints(
          Eigen::Matrix<Scalar, plus_one(Rows), plus_one(Internal)>::Zero(model.rows() + 1, 6 * model.arms() - 5)),
      padded_bounds(Eigen::Matrix<Scalar, plus_one(Rows), 1>::Zero(model.rows() + 1)),
      qp(6 * model.arms() - 5, model.rows() + 1),
      fallback_qp(6 * model.arms() - 5, model.rows() + 1),
      joint_scratch(JointVector::Zero(model.joints()))
{
    dynamics.form_projection_matrices = false;
    // Both QPs' rows depend on the model only: set once, each tick solves with H', g', d'. The
    // contact QP's [C, 0; 0, -1] first, then the fallback's [C, -|c|; 0, -1].
    const Index n = hessian.rows();
    const Index m = bounds.size();
    padded_constraints.topLeftCorner(m, n) = model.contact_qp_constraints();
    padded_constraints(m, n) = Scalar(-1);
    qp.set_constraints(padded_constraints);
    padded_constraints.col(n).head(m) = -model.row_norms();
    fallback_qp.set_constraints(padded_constraints);
    // The contact QP keeps the step cap of its own size, 10 (n + m), not the padded one's.
    const int limit = model.qp_options().iteration_limit;
    qp.set_iteration_limit(limit > 0 ? limit : PaddedSolver::default_iteration_limit(n, m));
    if (limit > 0) {
        fallback_qp.set_iteration_limit(limit);
    }
}

namespace detail {

/// The grasp in {w} from the object's orientation: r_i = R_o p_i, R_ci = R_o R_i and the internal
/// wrench basis B = blkdiag(R6, ..., R6) B_body, R6 = blkdiag(R_o, R_o)
/// (ProjectedDynamics::compute_with_basis). r and B go straight into data.dynamics, their one
/// owner.
template <typename Model, typename Data>
void controller_grasp(const Model& model, Data& data, const Matrix3<typename Model::Scalar>& object_rotation) noexcept
{
    using Scalar = typename Model::Scalar;
    rotate_stack(object_rotation, model.body_internal_basis(), data.dynamics.internal_basis);
    for (Index i = 0; i < model.arms(); ++i) {
        data.dynamics.contact_offsets.col(i).noalias() = object_rotation * model.contact(i).frame.position;
        const Matrix3<Scalar> rotation = object_rotation * model.contact_rotation(i);
        data.contact_rotations.template middleCols<3>(3 * i) = rotation;
    }
}

/// L(16) and L(7): the pose and twist errors, F, tau_u = P Jx^T F and the estimate F_x.
template <typename Model, typename Data, typename Input>
void controller_impedance(const Model& model, Data& data, const Input& input) noexcept
{
    using Scalar = typename Model::Scalar;
    auto& dynamics = data.dynamics;  // non-const: project() uses its workspace
    data.pose_error.template head<3>() = input.object.pose.position - input.desired_pose.position;
    data.pose_error.template tail<3>() = rotational_stiffness_torque(
        orientation_error(input.object.pose.orientation, input.desired_pose.orientation), Scalar(1));
    data.twist_error = input.object.twist - input.desired_twist;
    const Vector6<Scalar> spring_damper = model.damping() * data.twist_error + model.stiffness() * data.pose_error;
    data.motion_wrench = dynamics.task_bias + dynamics.task_inertia * input.desired_acceleration - spring_damper;
    data.joint_scratch.noalias() = dynamics.object_jacobian.transpose().lazyProduct(data.motion_wrench);
    dynamics.project(data.joint_scratch, data.motion_torque);
    data.external_wrench = dynamics.task_inertia * (input.object_acceleration - input.desired_acceleration) + spring_damper;
}

/// The contact QP in z (L(20)-(25), E10): per contact the rows C = A_w B_i (constant,
/// ControllerModel::contact_qp_constraints, set at construction) and the bounds
/// d = b - A_w w_0,i = b - A_i [R_ci^T f_0,i; R_ci^T t_0,i], and the objective's H and g
/// (SqueezeObjective; its moment term's B_m^T B_m is constant too, ControllerModel::moment_gram).
/// The least-squeeze term internal_weight |B^T w_0 + z|^2 adds internal_weight I to H and
/// internal_weight B^T w_0 to g: B is orthonormal (B^T B = I, ControllerModel checks the body
/// basis once; a rotation per contact keeps it so), so B^T w_0 + z = B^T w(z) are the coordinates
/// of the internal part B B^T w(z) of the whole contact wrench, errata E13.
template <typename Model, typename Data> void controller_contact_qp(const Model& model, Data& data) noexcept
{
    using Scalar = typename Model::Scalar;
    const auto& basis = data.dynamics.internal_basis;
    const SqueezeObjective<Scalar>& objective = model.objective();
    // Coefficient-based products: at these sizes Eigen's GEMM path costs more in packing than in
    // arithmetic (as in ProjectedDynamics::compute).
    const auto& jacobian_basis = data.dynamics.reduced_jacobian_transpose;  // J^T B
    if (objective.torque_weight != Scalar(0)) {
        data.hessian.noalias() = objective.torque_weight * jacobian_basis.transpose().lazyProduct(jacobian_basis);
    } else {
        data.hessian.setZero();
    }
    data.hessian.diagonal().array() += objective.squeeze_weight + objective.internal_weight;
    data.hessian.noalias() += objective.moment_weight * model.moment_gram();
    data.gradient.noalias() = objective.internal_weight * basis.transpose().lazyProduct(data.contact_wrench_bias);
    for (Index i = 0; i < model.arms(); ++i) {
        const auto moment_rows = basis.template middleRows<3>(6 * i + 3);
        const auto bias = data.contact_wrench_bias.template segment<6>(6 * i);
        data.gradient.noalias() += objective.moment_weight * moment_rows.transpose().lazyProduct(bias.template tail<3>());
        Vector6<Scalar> bias_in_contact_frame;
        rotate_stack_back(data.contact_rotations.template middleCols<3>(3 * i), bias, bias_in_contact_frame);
        data.bounds.segment(model.row_offset(i), model.row_count(i)) =
            model.contact_frame_bounds().segment(model.row_offset(i), model.row_count(i));
        data.bounds.segment(model.row_offset(i), model.row_count(i)).noalias() -=
            model.contact_frame_rows().middleRows(model.row_offset(i), model.row_count(i)).lazyProduct(bias_in_contact_frame);
    }
}

/// H' = blkdiag(H, eta), g' = (g, 0), d' = (d, 0): the contact QP's H, g, d padded to the (n + 1)
/// x (m + 1) problems of both QPs (ControllerData::PaddedSolver).
template <typename Data> void padded_problem(Data& data, typename Data::Scalar eta) noexcept
{
    using Scalar = typename Data::Scalar;
    const Index n = data.hessian.rows();
    const Index m = data.bounds.size();
    data.padded_hessian.setZero();
    data.padded_hessian.topLeftCorner(n, n) = data.hessian;
    data.padded_hessian(n, n) = eta;
    data.padded_gradient.head(n) = data.gradient;
    data.padded_gradient(n) = Scalar(0);
    data.padded_bounds.head(m) = data.bounds;
    data.padded_bounds(m) = Scalar(0);
}

/// The least-violating squeeze: min objective + rho s^2 s.t. C z - |a_k| s <= d, -s <= 0, with
/// rho = fallback_weight max_k H_kk. Always feasible (a large s satisfies every row). Returns
/// whether it solved; writes z into data.squeeze and s into data.fallback_violation.
template <typename Model, typename Data> bool controller_fallback(const Model& model, Data& data) noexcept
{
    const Index n = data.hessian.rows();
    // [C, -|c|; 0, -1] is constant: set once when the data was made (ControllerData's constructor).
    padded_problem(data, model.qp_options().fallback_weight * data.hessian.diagonal().maxCoeff());
    const auto& result = data.fallback_qp.solve(data.padded_hessian, data.padded_gradient, data.padded_bounds);
    data.qp_iterations += result.iterations;
    if (result.status != QpStatus::solved) {
        return false;
    }
    data.squeeze = result.x.head(n);
    data.fallback_violation = result.x(n);
    return true;
}

/// Solves the contact QP (warm from last tick's active set when allowed), falling back to the
/// least-violating squeeze when it has no solution; sets data.status.
template <typename Model, typename Data> void controller_solve_squeeze(const Model& model, Data& data) noexcept
{
    using Scalar = typename Model::Scalar;
    const bool warm = data.warm && model.qp_options().warm_start;
    // eta = max_k H_kk: t's pivot passes the pivot policy and leaves its scale, max_k H_kk, as it
    // is, so H' is refused exactly when H is.
    padded_problem(data, data.hessian.diagonal().maxCoeff());
    const auto& result = warm ? data.qp.solve_warm(data.padded_hessian, data.padded_gradient, data.padded_bounds)
                              : data.qp.solve(data.padded_hessian, data.padded_gradient, data.padded_bounds);
    data.qp_ran = true;
    data.qp_status = result.status;
    data.qp_iterations = result.iterations;
    data.fallback_used = false;
    data.fallback_violation = Scalar(0);
    data.warm = result.status == QpStatus::solved;
    if (data.warm) {
        data.squeeze = result.x.head(data.hessian.rows());
        data.status = ControlStatus::ok;
        return;
    }
    data.status = result.status == QpStatus::infeasible ? ControlStatus::friction_infeasible : ControlStatus::qp_failed;
    data.fallback_used = controller_fallback(model, data);
    if (!data.fallback_used) {
        data.squeeze.setZero();
        data.status = ControlStatus::qp_failed;
    }
}

/// tau_c = J^T B z, w = w_0 + B z, each contact's wrench in its frame, and the friction margins
/// (the rows' slacks d - C z = b - A_w w, over the rows' norms), split into the force rows (the
/// first friction_force_rows(n) of a contact, N) and the moment rows (the rest, N m).
template <typename Model, typename Data> void controller_contact_outputs(const Model& model, Data& data) noexcept
{
    using Scalar = typename Model::Scalar;
    const Scalar infinity = std::numeric_limits<Scalar>::infinity();
    data.squeeze_torque.noalias() = data.dynamics.reduced_jacobian_transpose.lazyProduct(data.squeeze);
    data.contact_wrenches = data.contact_wrench_bias;
    data.contact_wrenches.noalias() += data.dynamics.internal_basis.lazyProduct(data.squeeze);
    data.tightest_margin = data.tightest_force_margin = data.tightest_moment_margin = infinity;
    for (Index i = 0; i < model.arms(); ++i) {
        rotate_stack_back(data.contact_rotations.template middleCols<3>(3 * i), data.contact_wrenches.template segment<6>(6 * i),
                          data.contact_frame_wrenches.col(i));
        const Index first_moment_row = model.row_offset(i) + friction_force_rows(model.contact(i).friction.pyramid_edges);
        Scalar force = infinity, moment = infinity;
        for (Index k = model.row_offset(i); k < model.row_offset(i) + model.row_count(i); ++k) {
            const Scalar slack = data.bounds(k) - model.contact_qp_constraints().row(k).dot(data.squeeze);
            Scalar& margin = k < first_moment_row ? force : moment;
            margin = std::min(margin, slack / model.row_norms()(k));
        }
        data.force_margins(i) = force;
        data.moment_margins(i) = moment;
        data.friction_margins(i) = std::min(force, moment);
        data.tightest_force_margin = std::min(data.tightest_force_margin, force);
        data.tightest_moment_margin = std::min(data.tightest_moment_margin, moment);
        if (data.friction_margins(i) < data.tightest_margin) {
            data.tightest_margin = data.friction_margins(i);
            data.tightest_contact = i;
        }
    }
}

/// E12: tau_n = N^T tau_0 with tau_0 = h - K_n (q - q_n) - D_n qdot and the dynamically consistent
/// projector N^T = I - J^T (J M^-1 J^T)^-1 J M^-1: J M^-1 tau_n = 0, so tau_n accelerates no
/// contact point; since [Jx; Jc] and J have the same row space, it moves neither the object nor
/// the grasp and leaves every contact wrench as it is. The h term compensates the self-motion's
/// own gravity and Coriolis forces, which tau_u and tau_c do not reach. N^T comes from the
/// projection's own factors (ProjectedDynamics::self_motion_projection), never J M^-1 J^T.
template <typename Model, typename Data, typename Input>
void controller_posture(const Model& model, Data& data, const Input& input) noexcept
{
    auto& tau_0 = data.joint_scratch;
    tau_0 = input.bias;
    tau_0.array() -= model.posture_stiffness().array() * (input.positions - input.posture).array() +
                     model.posture_damping().array() * input.velocities.array();
    data.dynamics.self_motion_projection(tau_0, data.posture_torque);
}

/// Every output of a tick that computes no control (invalid_input, singular): `torque` (zero or
/// h) and the status; everything the later steps compute is reset to zero (NaN-free), the QP
/// marked as not run (qp_ran false, qp_iterations 0, qp_status solved: none failed), so that no
/// output holds a previous tick's value (docs/control.md, "After a failed tick").
template <typename Data, typename Torque>
void controller_no_control(Data& data, ControlStatus status, const Torque& torque) noexcept
{
    using Scalar = typename Data::Scalar;
    data.status = status;
    data.torque = torque;
    data.motion_torque.setZero();
    data.squeeze_torque.setZero();
    data.posture_torque.setZero();
    data.pose_error.setZero();
    data.twist_error.setZero();
    data.motion_wrench.setZero();
    data.external_wrench.setZero();
    data.contact_wrench_bias.setZero();
    data.squeeze.setZero();
    data.contact_wrenches.setZero();
    data.contact_frame_wrenches.setZero();
    data.force_margins.setZero();
    data.moment_margins.setZero();
    data.friction_margins.setZero();
    data.tightest_force_margin = Scalar(0);
    data.tightest_moment_margin = Scalar(0);
    data.tightest_margin = Scalar(0);
    data.tightest_contact = 0;
    data.qp_ran = false;
    data.qp_status = QpStatus::solved;
    data.qp_iterations = 0;
    data.fallback_used = false;
    data.fallback_violation = Scalar(0);
    data.joint_acceleration.setZero();
    data.warm = false;
    if (status == ControlStatus::invalid_input) {  // the grasp (step 2) did not run either
        data.contact_rotations.setZero();
    }
}

}  // namespace detail

/// \brief One controller tick: fills `data` from `input` and returns the joint torques
/// tau = tau_u + tau_c + tau_n (data.torque). noexcept; allocates nothing. Check data.status: the
/// torques are finite whatever it is (zero for an invalid input, h at a singular configuration,
/// the least-violating squeeze when friction cannot hold the load).
template <typename Scalar, int Arms, int Joints, int Edges>
const typename ControllerData<Scalar, Arms, Joints, Edges>::JointVector&
controller_tick(const ControllerModel<Scalar, Arms, Joints, Edges>& model, ControllerData<Scalar, Arms, Joints, Edges>& data,
                const ControllerInput<Scalar, Arms, Joints>& input) noexcept
{
    COOPDYN_REQUIRE_SHAPE(data.arms() == model.arms() && data.joints() == model.joints() &&
                              input.jacobian.rows() == 6 * model.arms() && input.inertia.rows() == model.joints() &&
                              input.inertia.cols() == model.joints() && input.bias.size() == model.joints() &&
                              input.jacobian.cols() == model.joints() && input.positions.size() == model.joints() &&
                              input.velocities.size() == model.joints() && input.posture.size() == model.joints() &&
                              input.jacobian_rate_qdot.size() == 6 * model.arms(),
                          "controller_tick: data or input sized for another controller model");
    data.input_problem = detail::controller_input_problem(input);
    if (data.input_problem != ControllerInputProblem::none) {
        detail::controller_no_control(data, ControlStatus::invalid_input, Eigen::Matrix<Scalar, Joints, 1>::Zero(model.joints()));
        return data.torque;
    }
    data.inertia_factor.compute(input.inertia);
    if (!regular_llt(data.inertia_factor)) {  // the pivot policy, numerics/pivot_policy.hpp
        data.input_problem = ControllerInputProblem::inertia_not_positive_definite;
        detail::controller_no_control(data, ControlStatus::invalid_input, Eigen::Matrix<Scalar, Joints, 1>::Zero(model.joints()));
        return data.torque;
    }
    detail::controller_grasp(model, data, input.object.pose.orientation.toRotationMatrix());
    // r and B are already the projection's own (controller_grasp wrote them there): passing them
    // back makes compute_with_basis's copies self-assignments, harmless and cheaper than a second
    // owner kept in sync.
    if (data.dynamics.compute_with_basis(input.inertia, input.bias, input.jacobian, input.jacobian_rate_qdot,
                                         input.velocities, data.dynamics.contact_offsets,
                                         data.dynamics.internal_basis) != ProjectionStatus::ok) {
        detail::controller_no_control(data, ControlStatus::singular, input.bias);
        return data.torque;
    }
    detail::controller_impedance(model, data, input);
    contact_wrench_bias(data.dynamics, input.inertia, input.bias, data.motion_torque, data.external_wrench,
                        data.joint_acceleration, data.contact_wrench_bias, data.joint_scratch);
    detail::controller_contact_qp(model, data);
    detail::controller_solve_squeeze(model, data);
    detail::controller_contact_outputs(model, data);
    detail::controller_posture(model, data, input);
    data.torque = data.motion_torque + data.squeeze_torque + data.posture_torque;
    return data.torque;
}

}  // namespace coopdyn
