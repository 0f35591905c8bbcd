/// \file
/// \brief ControllerData: everything a controller tick computes (its outputs) and the buffers it
/// needs, sized once from the model, and what the tick remembers between ticks for the faults
/// (the last valid measurement, the contacts' offsets, the safe-hold torque, the last sent
/// torque). Included by controller.hpp; docs/control.md, "Outputs and their signs" and "Faults:
/// dropout, safe hold, slip, torque limits".
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/control/controller_model.hpp"
#include "coopdyn/control/controller_status.hpp"
#include "coopdyn/control/projected_dynamics.hpp"
#include "coopdyn/numerics/fixed_llt.hpp"
#include "coopdyn/numerics/qp_solver.hpp"
#include "coopdyn/spatial/pose.hpp"
#include "coopdyn/spatial/spatial_vector.hpp"

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
    /// The refused or replaced input (invalid_input, safe_hold, degraded, and a tick whose prediction
    /// ran into friction_infeasible or qp_failed), otherwise none (to_string names it).
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

    // ---- faults (docs/control.md, "Faults: dropout, safe hold, slip, torque limits") ----------
    /// What replaced the object's measurement this tick (none: measured).
    ReplacedInput replaced_input = ReplacedInput::none;
    /// The object's state and acceleration this tick used: the measurement, or the prediction.
    RigidBodyState<Scalar> object{};
    Vector6<Scalar> object_acceleration = Vector6<Scalar>::Zero();
    /// Time (s) since the last valid object measurement: 0 when measured, the number of predicted
    /// ticks times FaultOptions::tick_period during a dropout.
    Scalar prediction_age = Scalar(0);
    /// h + J^T w of the last tick that computed the control (its bias and its predicted contact
    /// wrenches): what a safe hold sends (ControlStatus::safe_hold). Valid when hold_ready.
    JointVector hold_torque;
    StackVector hold_wrenches;  ///< that tick's w (a singular tick sends h + J^T w_hold)
    bool hold_ready = false;  ///< some tick computed the control: there is a grasp to hold
    /// Slip, when the input carries the contacts' poses and the object's pose is measured
    /// (slip_measured): column i of slip_displacement is contact i's measured origin minus where
    /// the measured object pose and ContactPoint::frame put it (m, {w}); slip_distance its norm
    /// (m), slip_angle the angle (rad) between the measured contact frame and the predicted one.
    /// Zero when !slip_measured.
    bool slip_measured = false;
    Eigen::Matrix<Scalar, 3, Arms> slip_displacement;
    ArmVector slip_distance;
    ArmVector slip_angle;
    /// Contacts beyond FaultOptions::slip_distance_threshold or slip_angle_threshold, and how many.
    Eigen::Array<bool, Arms, 1> slipping;
    Index slipping_contacts = 0;
    /// The torque before the torque limits (ControllerParameters::torque_limits,
    /// torque_rate_limits); `torque` is it clamped. The joints the limits changed, and how many.
    JointVector requested_torque;
    Eigen::Array<bool, Joints, 1> saturated_joints;
    Index saturated_count = 0;

    // ---- memory between ticks (faults) --------------------------------------------------------
    RigidBodyState<Scalar> last_measurement{};  ///< the last valid measured pose and twist
    Vector6<Scalar> last_acceleration = Vector6<Scalar>::Zero();  ///< the last valid measured acceleration
    bool has_measurement = false;
    Index predicted_ticks = 0;                  ///< consecutive ticks without a valid measurement
    /// Contact frame i in the object at the last valid measurement (columns: position; Eigen
    /// quaternion coeffs x, y, z, w), from the contacts' poses: the rigid grasp a dropout predicts
    /// the object's pose from.
    Eigen::Matrix<Scalar, 3, Arms> contact_offset_positions;
    Eigen::Matrix<Scalar, 4, Arms> contact_offset_orientations;
    bool has_contact_offsets = false;
    JointVector previous_torque;  ///< the torque sent last tick (for torque_rate_limits)
    bool has_previous_torque = false;

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
      hold_torque(JointVector::Zero(model.joints())),
      hold_wrenches(StackVector::Zero(6 * model.arms())),
      slip_displacement(Eigen::Matrix<Scalar, 3, Arms>::Zero(3, model.arms())),
      slip_distance(ArmVector::Zero(model.arms())),
      slip_angle(ArmVector::Zero(model.arms())),
      slipping(Eigen::Array<bool, Arms, 1>::Constant(model.arms(), false)),
      requested_torque(JointVector::Zero(model.joints())),
      saturated_joints(Eigen::Array<bool, Joints, 1>::Constant(model.joints(), false)),
      contact_offset_positions(Eigen::Matrix<Scalar, 3, Arms>::Zero(3, model.arms())),
      contact_offset_orientations(Eigen::Matrix<Scalar, 4, Arms>::Zero(4, model.arms())),
      previous_torque(JointVector::Zero(model.joints())),
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

}  // namespace coopdyn
