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
#include "coopdyn/control/controller_data.hpp"
#include "coopdyn/control/controller_faults.hpp"
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

/// L(16) and L(7): the pose and twist errors, F, tau_u = P Jx^T F and the estimate F_x, from the
/// object's state this tick uses (data.object: measured or predicted, controller_object_state).
template <typename Model, typename Data, typename Input>
void controller_impedance(const Model& model, Data& data, const Input& input) noexcept
{
    using Scalar = typename Model::Scalar;
    auto& dynamics = data.dynamics;  // non-const: project() uses its workspace
    data.pose_error.template head<3>() = data.object.pose.position - input.desired_pose.position;
    data.pose_error.template tail<3>() = rotational_stiffness_torque(
        orientation_error(data.object.pose.orientation, input.desired_pose.orientation), Scalar(1));
    data.twist_error = data.object.twist - input.desired_twist;
    const Vector6<Scalar> spring_damper = model.damping() * data.twist_error + model.stiffness() * data.pose_error;
    data.motion_wrench = dynamics.task_bias + dynamics.task_inertia * input.desired_acceleration - spring_damper;
    data.joint_scratch.noalias() = dynamics.object_jacobian.transpose().lazyProduct(data.motion_wrench);
    dynamics.project(data.joint_scratch, data.motion_torque);
    data.external_wrench = dynamics.task_inertia * (data.object_acceleration - input.desired_acceleration) + spring_damper;
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

/// Every output of a tick that computes no control (invalid_input, singular, safe_hold): `torque`
/// (zero, h or the hold torque) and the status; everything the later steps compute is reset to zero (NaN-free), the QP
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
    data.replaced_input = ReplacedInput::none;
    data.slip_measured = false;
    data.slip_displacement.setZero();
    data.slip_distance.setZero();
    data.slip_angle.setZero();
    data.slipping.setConstant(false);
    data.slipping_contacts = 0;
    if (status != ControlStatus::singular) {  // the grasp (step 2) did not run either
        data.contact_rotations.setZero();
    }
}

/// A tick that cannot compute the control (an unusable input, or the object's state predicted
/// past FaultOptions::prediction_limit): the safe hold, data.hold_torque, once a tick has computed
/// the control (a grasp to hold); before that invalid_input with zero torque (nothing held yet).
template <typename Model, typename Data> const typename Data::JointVector& controller_hold_or_refuse(const Model& model, Data& data) noexcept
{
    if (data.hold_ready) {
        controller_no_control(data, ControlStatus::safe_hold, data.hold_torque);
    } else {
        controller_no_control(data, ControlStatus::invalid_input, Data::JointVector::Zero(model.joints()));
    }
    return controller_limit_torque(model, data);
}

/// A singular configuration (the projection failed): h, the arms' bias, and once a tick has
/// computed the control also J^T w_hold, that tick's contact wrenches through this tick's J (h and
/// J are finite here, only their projection failed): the arms' weight compensated and the last
/// squeeze kept instead of dropping the object (ControllerData::hold_wrenches).
template <typename Model, typename Data, typename Input>
const typename Data::JointVector& controller_singular(const Model& model, Data& data, const Input& input) noexcept
{
    controller_no_control(data, ControlStatus::singular, input.bias);
    if (data.hold_ready) {
        data.torque.noalias() += input.jacobian.transpose().lazyProduct(data.hold_wrenches);
    }
    return controller_limit_torque(model, data);
}

/// A tick that computed the control, once its torque is limited: a slipping contact, then a
/// clipped torque, take precedence over the solver's statuses and degraded (ControlStatus), for
/// they say the contact wrenches are not the ones computed.
template <typename Data> void controller_grasp_status(Data& data) noexcept
{
    if (data.slipping_contacts > 0) {
        data.status = ControlStatus::slipping;
    } else if (data.saturated_count > 0) {
        data.status = ControlStatus::torque_saturated;
    }
}

}  // namespace detail

/// \brief One controller tick: fills `data` from `input` and returns the joint torques
/// tau = tau_u + tau_c + tau_n (data.torque), clamped by the torque limits when the model has them.
/// noexcept; allocates nothing. Check data.status: the torques are finite whatever it is; a missing
/// object measurement is predicted (degraded), an unusable input after a computed tick holds the
/// grasp (safe_hold); docs/control.md, "Every status's torque".
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
                              input.jacobian_rate_qdot.size() == 6 * model.arms() &&
                              input.contact_positions.cols() == model.arms() &&
                              input.contact_orientations.cols() == model.arms(),
                          "controller_tick: data or input sized for another controller model");
    const ControllerInputProblem object_problem = detail::object_measurement_problem(input);
    detail::controller_remember_measurement(model, data, input, object_problem);
    data.input_problem = detail::arm_input_problem(input);
    if (data.input_problem == ControllerInputProblem::none) {
        data.inertia_factor.compute(input.inertia);
        if (!regular_llt(data.inertia_factor)) {  // the pivot policy, numerics/pivot_policy.hpp
            data.input_problem = ControllerInputProblem::inertia_not_positive_definite;
        }
    }
    if (data.input_problem != ControllerInputProblem::none) {
        return detail::controller_hold_or_refuse(model, data);
    }
    data.input_problem = object_problem;
    if (!detail::controller_object_state(model, data, input, object_problem)) {
        return detail::controller_hold_or_refuse(model, data);
    }
    detail::controller_grasp(model, data, data.object.pose.orientation.toRotationMatrix());
    // r and B are already the projection's own (controller_grasp wrote them there): passing them
    // back makes compute_with_basis's copies self-assignments, harmless and cheaper than a second
    // owner kept in sync.
    if (data.dynamics.compute_with_basis(input.inertia, input.bias, input.jacobian, input.jacobian_rate_qdot,
                                         input.velocities, data.dynamics.contact_offsets,
                                         data.dynamics.internal_basis) != ProjectionStatus::ok) {
        return detail::controller_singular(model, data, input);
    }
    if (data.replaced_input == ReplacedInput::object_state_from_contacts) {  // the object's twist Jx qdot
        data.object.twist.noalias() = data.dynamics.object_jacobian.lazyProduct(input.velocities);
    }
    detail::controller_slip(model, data, input);
    detail::controller_impedance(model, data, input);
    contact_wrench_bias(data.dynamics, input.inertia, input.bias, data.motion_torque, data.external_wrench,
                        data.joint_acceleration, data.contact_wrench_bias, data.joint_scratch);
    detail::controller_contact_qp(model, data);
    detail::controller_raise_squeeze(model, data);
    detail::controller_solve_squeeze(model, data);
    detail::controller_contact_outputs(model, data);
    detail::controller_posture(model, data, input);
    data.torque = data.motion_torque + data.squeeze_torque + data.posture_torque;
    if (data.replaced_input != ReplacedInput::none && data.status == ControlStatus::ok) {
        data.status = ControlStatus::degraded;
    }
    detail::controller_record_hold(data, input);
    const auto& torque = detail::controller_limit_torque(model, data);
    detail::controller_grasp_status(data);
    return torque;
}

}  // namespace coopdyn
