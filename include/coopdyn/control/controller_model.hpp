/// \file
/// \brief The constant part of the projected inverse-dynamics controller of K arms holding an
/// object through flat contacts (Lin et al.): the grasp, each contact's friction, the desired
/// impedance, the posture gains, the squeeze objective and the QP's options, validated once at
/// construction; and, through controller_input.hpp, the per-tick input. docs/control.md, "The
/// controller".
///
/// Use:
///
///     coopdyn::ControllerParameters<double> parameters;
///     parameters.joints = 14;
///     parameters.contacts = {left_palm, right_palm};         // ContactPoint: frame in the object, friction
///     parameters.stiffness = ...; parameters.damping = ...;  // K_d, D_d (6 x 6)
///     parameters.posture_stiffness = Eigen::VectorXd::Constant(14, 20.0);
///     parameters.posture_damping = Eigen::VectorXd::Constant(14, 5.0);
///     coopdyn::ControllerModel<double, 2, 14> model(parameters);   // throws InvalidModel, naming what
///     coopdyn::ControllerData<double, 2, 14> data(model);          // controller.hpp
///     coopdyn::ControllerInput<double, 2, 14> input(model);        // fill M, h, J, ... every tick
///     const auto& tau = coopdyn::controller_tick(model, data, input);
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/control/friction.hpp"
#include "coopdyn/control/projected_dynamics.hpp"
#include "coopdyn/detail/validation.hpp"
#include "coopdyn/errors.hpp"
#include "coopdyn/model/contact_frames.hpp"
#include "coopdyn/spatial/pose.hpp"
#include "coopdyn/spatial/spatial_vector.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

namespace coopdyn {

/// \brief One contact of a hand (a palm) on the object.
template <typename ScalarType> struct ContactPoint {
    using Scalar = ScalarType;
    /// The contact frame {c_i} in the object's body frame: its position is the contact point
    /// relative to the object's centre, its z axis the object's inward surface normal there, x and y
    /// tangential (the patch's axes). Fixed while the grasp holds: r_i = R_o position,
    /// R_ci = R_o R(orientation) in {w}.
    Pose<Scalar> frame{};
    ContactFriction<Scalar> friction{};
};

/// \brief What the contact QP minimises over the squeeze z (w(z) = w_0 + B z, tau_c = J^T B z, B
/// the orthonormal basis of the internal wrenches, so B^T B = I and |B z| = |z|):
///
///     internal_weight |B^T w_0 + z|^2  +  moment_weight sum_i |t_i(z)|^2
///       +  torque_weight |J^T B z|^2  +  squeeze_weight |B z|^2
///
/// - internal_weight: the least squeeze. B^T w_0 + z = B^T w(z) are the coordinates of the
///   internal part B B^T w of the WHOLE contact wrench, so this term minimises how hard the hands
///   squeeze, including the internal wrench w_0 already holds (the arms' own weight and dynamics
///   that the projection leaves to the contacts). At rest each palm's normal force comes out as
///   max(f_min, what friction needs for the load) (errata E13; docs/control.md, "The least
///   squeeze"). In N^2.
/// - moment_weight: the contact moments t_i of w(z) about each contact point, which keeps the
///   centre of pressure central (docs/control.md, "Where the squeeze sits"). In N^2 m^2.
/// - torque_weight: the paper's L(20), tau_c^T tau_c, the least squeeze TORQUE. It is zero at
///   z = 0, so alone it keeps whatever internal wrench w_0 holds (the box example's LWR 4 pair at
///   rest, mu 0.5, f_min 2 N: 18.2 N per palm for 0.5 kg where 4.9 N suffices, 3.7x;
///   tests/examples/test_box_squeeze.cpp). In N^2 m^2.
/// - squeeze_weight: |B z|^2 = |z|^2, the squeeze added to w_0 (not the whole internal wrench):
///   a small ridge that keeps the Hessian positive definite when J^T B loses rank. In N^2.
///
/// The default is least_squeeze(); least_torque_centred() was the default until this release,
/// paper() is L(20) alone. Each weight >= 0, and internal_weight + torque_weight +
/// squeeze_weight > 0 (the Hessian must be positive definite); ControllerModel refuses anything
/// else, naming the weight.
template <typename ScalarType> struct SqueezeObjective {
    using Scalar = ScalarType;
    Scalar internal_weight = Scalar(1);    ///< >= 0, on |B^T w(z)|^2, the internal part of w (the least squeeze)
    Scalar moment_weight = Scalar(1e4);    ///< >= 0, on the contact moments (centre of pressure central)
    Scalar torque_weight = Scalar(0);      ///< >= 0, on |tau_c|^2 (L(20), the least squeeze torque)
    Scalar squeeze_weight = Scalar(0);     ///< >= 0, on |B z|^2 (a ridge)

    /// The default: the least internal wrench, the centre of pressure kept central (moment_weight
    /// 1e4 N^2 per (N m)^2: a 1 N m contact moment costs as much as a 100 N squeeze, so the moments
    /// stay as small as the load allows and the squeeze is what friction and f_min need).
    static SqueezeObjective least_squeeze() noexcept { return {Scalar(1), Scalar(1e4), Scalar(0), Scalar(0)}; }
    /// The default until this release: the paper's least squeeze torque L(20) plus the centring
    /// moment term (moment_weight 1e4, dimensionless here: both in N^2 m^2) and a 1e-6 ridge.
    static SqueezeObjective least_torque_centred() noexcept
    {
        return {Scalar(0), Scalar(1e4), Scalar(1), Scalar(1e-6)};
    }
    /// The paper's objective L(20), tau_c^T tau_c, with the 1e-6 ridge: the centre of pressure
    /// goes to the patch's edge and the internal wrench of w_0 stays (errata E13).
    static SqueezeObjective paper() noexcept { return {Scalar(0), Scalar(0), Scalar(1), Scalar(1e-6)}; }
};

/// \brief Options of the contact QP (docs/control.md, "When friction cannot hold the load").
template <typename ScalarType> struct ContactQpOptions {
    using Scalar = ScalarType;
    /// Start each tick from the previous tick's active set (QpSolver::solve_warm): the same answer
    /// in fewer steps when the active set does not change.
    bool warm_start = true;
    /// Cap on the QP's steps per tick; 0 takes QpSolver::default_iteration_limit.
    int iteration_limit = 0;
    /// The fallback when no squeeze satisfies every friction row: minimise the objective plus
    /// fallback_weight max_k(H_kk) s^2 subject to margin_k >= -s for every row k, s >= 0, i.e.
    /// violate the rows as little as possible (the largest violation s, in the margins' units),
    /// and among such squeezes prefer the objective's. > 0.
    Scalar fallback_weight = Scalar(1e6);
};

/// \brief What the controller does when an input fails or the grasp slips (docs/control.md,
/// "Faults: dropout, safe hold, slip, torque limits"). Times in s, distances in m, angles in rad.
template <typename ScalarType> struct FaultOptions {
    using Scalar = ScalarType;
    /// The controller's tick period (s), > 0: how far a predicted object state is propagated per
    /// tick, and how the prediction's age is counted.
    Scalar tick_period = Scalar(1e-3);
    /// How long (s), >= 0, the object's state may be predicted (ControlStatus::degraded) after its
    /// last valid measurement before the tick enters the safe hold (ControlStatus::safe_hold).
    Scalar prediction_limit = Scalar(0.1);
    /// A contact slips when the distance (m) between its measured contact point and the one the
    /// measured object pose and the model's contact frame put it at exceeds this, > 0 ...
    Scalar slip_distance_threshold = Scalar(5e-3);
    /// ... or the angle (rad) between the measured and the predicted contact frame exceeds this, > 0.
    Scalar slip_angle_threshold = Scalar(0.05);
    /// While a contact slips, its minimum normal force f_min is multiplied by this, >= 1 (1: off).
    Scalar slip_squeeze_factor = Scalar(1);
};

/// \brief Everything the controller model is built from (plain data; validated by ControllerModel).
template <typename ScalarType> struct ControllerParameters {
    using Scalar = ScalarType;
    using DynamicVector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;
    Index joints = 0;                         ///< Q, all joints of all arms (a shared torso counted once)
    std::vector<ContactPoint<Scalar>> contacts;   ///< K >= 2, one per hand, in the order of J's row blocks
    Matrix6<Scalar> stiffness = Matrix6<Scalar>::Zero();  ///< K_d, symmetric >= 0 (N/m, N m/rad)
    Matrix6<Scalar> damping = Matrix6<Scalar>::Zero();    ///< D_d, symmetric >= 0 (N s/m, N m s/rad)
    /// Posture (self-motion) gains, per joint, >= 0: tau_0 = h - K_n (q - q_n) - D_n qdot, applied
    /// through the dynamically consistent null space of J (docs/control.md, "Posture").
    DynamicVector posture_stiffness;          ///< K_n (Q), N m/rad
    DynamicVector posture_damping;            ///< D_n (Q), N m s/rad
    SqueezeObjective<Scalar> objective{};
    ContactQpOptions<Scalar> qp{};
    /// Per joint, the largest |torque| the tick may send (N m; Q entries, each > 0), applied after
    /// the QP to every torque the tick returns, safe hold included; empty: no limit.
    DynamicVector torque_limits;
    /// Per joint, the largest change of the sent torque from one tick to the next (N m per tick;
    /// Q entries, each > 0); empty: no limit.
    DynamicVector torque_rate_limits;
    FaultOptions<Scalar> faults{};
    /// Refuse a contact whose frame does not face into the object (contact_normal_cosine:
    /// z_i . r_i >= 0, model/contact_frames.hpp). Turn off only for a grasp where the inward normal
    /// need not face the object's centre (a non-convex object held inside a hollow or by a handle).
    bool check_contact_normals = true;
    /// Optional: the Q joints' names in q's order (MujocoArms::joint_names, a URDF's), used only to
    /// name a joint in the errors; empty: joints are named by index.
    std::vector<std::string> joint_names;
};

/// Rows of the contact QP for K contacts of n-edge pyramids: K (n + 7) (Dynamic passes through).
constexpr int contact_qp_rows(int arms, int edges) noexcept
{
    return arms == Eigen::Dynamic || edges == Eigen::Dynamic ? Eigen::Dynamic : arms * friction_rows(edges);
}

/// n + 1 (Dynamic passes through): the fallback QP's extra slack variable and row.
constexpr int plus_one(int n) noexcept { return n == Eigen::Dynamic ? Eigen::Dynamic : n + 1; }

/// \brief The controller's constant part for K arms (contacts), Q joints and n-edge friction
/// pyramids, each fixed or Dynamic. Built from ControllerParameters, which it validates: anything
/// wrong throws InvalidModel naming the parameter and the contact (as "arm i").
template <typename ScalarType, int ArmsAtCompileTime = Eigen::Dynamic, int JointsAtCompileTime = Eigen::Dynamic,
          int EdgesAtCompileTime = 8>
class ControllerModel {
public:
    using Scalar = ScalarType;
    static constexpr int Arms = ArmsAtCompileTime;
    static constexpr int Joints = JointsAtCompileTime;
    static constexpr int Edges = EdgesAtCompileTime;
    static constexpr int Stack = times_six(Arms);
    static constexpr int Internal = internal_wrench_dimension(Arms);
    static constexpr int Rows = contact_qp_rows(Arms, Edges);
    using JointVector = Eigen::Matrix<Scalar, Joints, 1>;
    using RowMatrix = Eigen::Matrix<Scalar, Rows, 6>;
    using RowVector = Eigen::Matrix<Scalar, Rows, 1>;

    explicit ControllerModel(const ControllerParameters<Scalar>& parameters)
        : joints_(parameters.joints),
          arms_(static_cast<Index>(parameters.contacts.size())),
          contacts_(parameters.contacts),
          stiffness_(parameters.stiffness),
          damping_(parameters.damping),
          objective_(parameters.objective),
          qp_options_(parameters.qp),
          faults_(parameters.faults)
    {
        validate(parameters);
        posture_stiffness_ = parameters.posture_stiffness;
        posture_damping_ = parameters.posture_damping;
        has_torque_limits_ = parameters.torque_limits.size() > 0;
        has_torque_rate_limits_ = parameters.torque_rate_limits.size() > 0;
        torque_limits_ = has_torque_limits_ ? JointVector(parameters.torque_limits) : JointVector::Zero(joints_);
        torque_rate_limits_ =
            has_torque_rate_limits_ ? JointVector(parameters.torque_rate_limits) : JointVector::Zero(joints_);
        build_rows();
    }

    Index arms() const noexcept { return arms_; }
    Index joints() const noexcept { return joints_; }
    /// Rows of the contact QP, sum_i (n_i + 7).
    Index rows() const noexcept { return friction_rows_.rows(); }
    const std::vector<ContactPoint<Scalar>>& contacts() const noexcept { return contacts_; }
    const ContactPoint<Scalar>& contact(Index i) const noexcept { return contacts_[static_cast<std::size_t>(i)]; }
    /// R(q_i): contact frame i to the object's body frame.
    const Matrix3<Scalar>& contact_rotation(Index i) const noexcept
    {
        return contact_rotations_[static_cast<std::size_t>(i)];
    }
    const Matrix6<Scalar>& stiffness() const noexcept { return stiffness_; }
    const Matrix6<Scalar>& damping() const noexcept { return damping_; }
    const JointVector& posture_stiffness() const noexcept { return posture_stiffness_; }
    const JointVector& posture_damping() const noexcept { return posture_damping_; }
    const SqueezeObjective<Scalar>& objective() const noexcept { return objective_; }
    const ContactQpOptions<Scalar>& qp_options() const noexcept { return qp_options_; }
    const FaultOptions<Scalar>& faults() const noexcept { return faults_; }
    /// Whether ControllerParameters::torque_limits / torque_rate_limits were given, and their values
    /// (zero when not given).
    bool has_torque_limits() const noexcept { return has_torque_limits_; }
    bool has_torque_rate_limits() const noexcept { return has_torque_rate_limits_; }
    const JointVector& torque_limits() const noexcept { return torque_limits_; }
    const JointVector& torque_rate_limits() const noexcept { return torque_rate_limits_; }

    /// The friction rows of all contacts in their contact frames, stacked (rows() x 6; contact i's
    /// block starts at row_offset(i) and has n_i + 7 rows, in contact_frame_friction_rows' order),
    /// their bounds and their norms (the margins' denominators).
    const RowMatrix& contact_frame_rows() const noexcept { return friction_rows_; }
    const RowVector& contact_frame_bounds() const noexcept { return friction_bounds_; }
    const RowVector& row_norms() const noexcept { return friction_row_norms_; }
    Index row_offset(Index i) const noexcept { return row_offsets_[static_cast<std::size_t>(i)]; }
    /// The orthonormal internal-wrench basis of the contacts in the object's frame
    /// (internal_wrench_basis of the contact positions p_i): each tick only rotates it into {w}
    /// (ProjectedDynamics::compute_with_basis).
    const Eigen::Matrix<Scalar, Stack, Internal>& body_internal_basis() const noexcept { return body_internal_basis_; }
    /// The contact QP's constraint matrix C = A_i blkdiag(R_i^T, R_i^T) B_body,i per contact
    /// (rows() x 6(K - 1)). Constant: the basis turns with the object, B_i = blkdiag(R_o, R_o)
    /// B_body,i, and contact frame i with it, R_ci = R_o R_i, so the contact-frame rows acting on
    /// the {w} wrench B_i z give A_i blkdiag(R_ci^T, R_ci^T) B_i = A_i blkdiag(R_i^T, R_i^T) B_body,i.
    const Eigen::Matrix<Scalar, Rows, Internal>& contact_qp_constraints() const noexcept { return contact_qp_constraints_; }
    /// sum_i B_m,i^T B_m,i over the basis' moment rows (the objective's moment term), constant for
    /// the same reason (B_m,i = R_o B_body,m,i).
    const Eigen::Matrix<Scalar, Internal, Internal>& moment_gram() const noexcept { return moment_gram_; }
    Index row_count(Index i) const noexcept { return coopdyn::friction_rows(contact(i).friction.pyramid_edges); }

private:
    void validate(const ControllerParameters<Scalar>& parameters) const;
    void validate_joint_count(const ControllerParameters<Scalar>& parameters) const;
    void validate_faults(const ControllerParameters<Scalar>& parameters) const;
    /// "joint j (name)" with ControllerParameters::joint_names, else "joint j".
    static std::string joint_label(const ControllerParameters<Scalar>& parameters, Index j)
    {
        std::string label = "joint " + std::to_string(j);
        if (static_cast<std::size_t>(j) < parameters.joint_names.size()) {
            label += " (" + parameters.joint_names[static_cast<std::size_t>(j)] + ")";
        }
        return label;
    }
    void build_rows();

    Index joints_;
    Index arms_;
    std::vector<ContactPoint<Scalar>> contacts_;
    std::vector<Matrix3<Scalar>> contact_rotations_;
    std::vector<Index> row_offsets_;
    Matrix6<Scalar> stiffness_;
    Matrix6<Scalar> damping_;
    JointVector posture_stiffness_;
    JointVector posture_damping_;
    SqueezeObjective<Scalar> objective_;
    ContactQpOptions<Scalar> qp_options_;
    FaultOptions<Scalar> faults_;
    bool has_torque_limits_ = false;
    bool has_torque_rate_limits_ = false;
    JointVector torque_limits_;
    JointVector torque_rate_limits_;
    RowMatrix friction_rows_;
    RowVector friction_bounds_;
    RowVector friction_row_norms_;
    Eigen::Matrix<Scalar, Stack, Internal> body_internal_basis_;
    Eigen::Matrix<Scalar, Rows, Internal> contact_qp_constraints_;
    Eigen::Matrix<Scalar, Internal, Internal> moment_gram_;
};

template <typename Scalar, int Arms, int Joints, int Edges>
void ControllerModel<Scalar, Arms, Joints, Edges>::validate(const ControllerParameters<Scalar>& parameters) const
{
    const detail::ErrorContext model{detail::ErrorKind::model, "controller"};
    if (arms_ < 2 || (Arms != Eigen::Dynamic && arms_ != Arms)) {
        detail::fail(model, "contacts",
                     "must hold " + (Arms == Eigen::Dynamic ? std::string("at least 2") : std::to_string(Arms)) +
                         " contacts, got " + std::to_string(arms_));
    }
    if (joints_ < 6 * arms_ || (Joints != Eigen::Dynamic && joints_ != Joints)) {
        detail::fail(model, "joints",
                     "must be " + (Joints == Eigen::Dynamic ? "at least 6K = " + std::to_string(6 * arms_)
                                                           : std::to_string(Joints)) +
                         ", got " + std::to_string(joints_));
    }
    for (Index i = 0; i < arms_; ++i) {
        const ContactPoint<Scalar>& point = contact(i);
        const detail::ErrorContext context{detail::ErrorKind::model, "contact", i};
        detail::require_finite(point.frame.position, context, "frame.position");
        detail::require_unit_quaternion(point.frame.orientation, context, "frame.orientation");
        if (parameters.check_contact_normals) {
            const std::string problem = contact_normal_problem(point.frame);
            if (!problem.empty()) {
                detail::fail(context, "frame.orientation", problem);
            }
        }
        point.friction.validate(i);
        if (Edges != Eigen::Dynamic && point.friction.pyramid_edges != Edges) {
            detail::fail(context, "friction.pyramid_edges",
                         "must equal the controller's compile-time Edges = " + std::to_string(Edges) + ", got " +
                             std::to_string(point.friction.pyramid_edges));
        }
    }
    detail::require_symmetric_positive(parameters.stiffness, model, "stiffness", /*allow_semidefinite=*/true);
    detail::require_symmetric_positive(parameters.damping, model, "damping", /*allow_semidefinite=*/true);
    validate_joint_count(parameters);
    const auto require_joint_gains = [&](const auto& gains, const char* name) {
        if (gains.size() != joints_) {
            detail::fail(model, name,
                         "must have one entry per joint (joints = " + std::to_string(joints_) + "), got " +
                             std::to_string(gains.size()));
        }
        for (Index j = 0; j < joints_; ++j) {
            const double value = detail::value_of(gains(j));
            if (!(value >= 0.0) || !std::isfinite(value)) {
                detail::fail(model, name,
                             joint_label(parameters, j) + ": must be non-negative and finite, got " + std::to_string(value));
            }
        }
    };
    require_joint_gains(parameters.posture_stiffness, "posture_stiffness");
    require_joint_gains(parameters.posture_damping, "posture_damping");
    const SqueezeObjective<Scalar>& objective = parameters.objective;
    detail::require_non_negative(objective.internal_weight, model, "objective.internal_weight");
    detail::require_non_negative(objective.torque_weight, model, "objective.torque_weight");
    detail::require_non_negative(objective.moment_weight, model, "objective.moment_weight");
    detail::require_non_negative(objective.squeeze_weight, model, "objective.squeeze_weight");
    if (!(objective.internal_weight + objective.torque_weight + objective.squeeze_weight > Scalar(0))) {
        detail::fail(model, "objective.squeeze_weight",
                     "must be positive when objective.internal_weight and objective.torque_weight are zero "
                     "(the QP's Hessian must be positive definite)");
    }
    if (parameters.qp.iteration_limit < 0) {
        detail::fail(model, "qp.iteration_limit",
                     "must be non-negative (0 = the default), got " + std::to_string(parameters.qp.iteration_limit));
    }
    detail::require_positive(parameters.qp.fallback_weight, model, "qp.fallback_weight");
    validate_faults(parameters);
}

/// `joints` against the per-joint inputs: when every per-joint vector given (the posture gains,
/// joint_names, the torque limits) has the same size and it is not `joints`, `joints` is what is
/// wrong (a 13-joint cell with joints = 12 names `joints`, not posture_stiffness); joint_names
/// must be empty or have `joints` entries.
template <typename Scalar, int Arms, int Joints, int Edges>
void ControllerModel<Scalar, Arms, Joints, Edges>::validate_joint_count(const ControllerParameters<Scalar>& parameters) const
{
    const detail::ErrorContext model{detail::ErrorKind::model, "controller"};
    const Index gains = parameters.posture_stiffness.size();
    bool all_agree = gains != joints_ && parameters.posture_damping.size() == gains;
    std::string given = "posture_stiffness, posture_damping";
    const auto also = [&](Index size, const char* name) {
        if (size > 0) {
            all_agree = all_agree && size == gains;
            given += std::string(", ") + name;
        }
    };
    also(static_cast<Index>(parameters.joint_names.size()), "joint_names");
    also(parameters.torque_limits.size(), "torque_limits");
    also(parameters.torque_rate_limits.size(), "torque_rate_limits");
    if (all_agree && gains > 0) {
        detail::fail(model, "joints",
                     "is " + std::to_string(joints_) + ", but " + given + " all have " + std::to_string(gains) +
                         " entries (one per joint): set joints to the arms' joint count");
    }
    if (!parameters.joint_names.empty() && static_cast<Index>(parameters.joint_names.size()) != joints_) {
        detail::fail(model, "joint_names",
                     "must be empty or have one name per joint (joints = " + std::to_string(joints_) + "), got " +
                         std::to_string(parameters.joint_names.size()));
    }
}

/// The torque limits (each entry > 0 and finite, Q entries, or none) and the fault options.
template <typename Scalar, int Arms, int Joints, int Edges>
void ControllerModel<Scalar, Arms, Joints, Edges>::validate_faults(const ControllerParameters<Scalar>& parameters) const
{
    const detail::ErrorContext model{detail::ErrorKind::model, "controller"};
    const auto require_optional_limits = [&](const auto& limits, const char* name) {
        if (limits.size() == 0) {
            return;
        }
        if (limits.size() != joints_) {
            detail::fail(model, name,
                         "must be empty (no limit) or have one entry per joint (" + std::to_string(joints_) +
                             "), got " + std::to_string(limits.size()));
        }
        for (Index j = 0; j < joints_; ++j) {
            const double value = detail::value_of(limits(j));
            if (!std::isfinite(value) || !(value > 0.0)) {
                detail::fail(model, name,
                             joint_label(parameters, j) + ": must be positive and finite, got " + std::to_string(value));
            }
        }
    };
    require_optional_limits(parameters.torque_limits, "torque_limits");
    require_optional_limits(parameters.torque_rate_limits, "torque_rate_limits");
    const FaultOptions<Scalar>& faults = parameters.faults;
    detail::require_positive(faults.tick_period, model, "faults.tick_period");
    detail::require_non_negative(faults.prediction_limit, model, "faults.prediction_limit");
    detail::require_positive(faults.slip_distance_threshold, model, "faults.slip_distance_threshold");
    detail::require_positive(faults.slip_angle_threshold, model, "faults.slip_angle_threshold");
    detail::require_positive(faults.slip_squeeze_factor, model, "faults.slip_squeeze_factor");
    if (!(faults.slip_squeeze_factor >= Scalar(1))) {
        detail::fail(model, "faults.slip_squeeze_factor",
                     "must be at least 1 (1: off), got " + std::to_string(detail::value_of(faults.slip_squeeze_factor)));
    }
}

/// The contact-frame friction rows of every contact, stacked once: per tick they are only rotated
/// into {w} (no trigonometry on the hot path).
template <typename Scalar, int Arms, int Joints, int Edges>
void ControllerModel<Scalar, Arms, Joints, Edges>::build_rows()
{
    Index total = 0;
    for (const ContactPoint<Scalar>& point : contacts_) {
        row_offsets_.push_back(total);
        total += coopdyn::friction_rows(point.friction.pyramid_edges);
        contact_rotations_.push_back(point.frame.orientation.toRotationMatrix());
    }
    friction_rows_ = RowMatrix::Zero(total, 6);
    friction_bounds_ = RowVector::Zero(total);
    for (Index i = 0; i < arms_; ++i) {
        contact_frame_friction_rows(contact(i).friction, friction_rows_.middleRows(row_offset(i), row_count(i)),
                                    friction_bounds_.segment(row_offset(i), row_count(i)));
    }
    friction_row_norms_ = friction_rows_.rowwise().norm();
    Eigen::Matrix<Scalar, 3, Arms> positions(3, arms_);
    for (Index i = 0; i < arms_; ++i) {
        positions.col(i) = contact(i).frame.position;
    }
    body_internal_basis_ = internal_wrench_basis(positions);
    const Index internal = body_internal_basis_.cols();
    // B^T B = I is what the objective's units rest on (|B z| = |z| in N and N m, and B^T w_0 + z
    // the coordinates of w's internal part: SqueezeObjective); each tick only rotates B per
    // contact, which keeps it. Checked once here, to rounding.
    using std::abs;
    // Coefficient-based products here and below: operator* at these sizes instantiates Eigen's
    // GEMM kernels, a third of this constructor's compile time, for one-off setup arithmetic
    // (docs/performance.md, "Compile time and CI").
    const Eigen::Matrix<Scalar, Internal, Internal> gram = body_internal_basis_.transpose().lazyProduct(body_internal_basis_);
    Scalar departure(0);
    for (Index j = 0; j < internal; ++j) {
        for (Index k = 0; k < internal; ++k) {
            departure = std::max(departure, Scalar(abs(gram(j, k) - (j == k ? Scalar(1) : Scalar(0)))));
        }
    }
    if (!(departure <= Scalar(1000) * std::numeric_limits<Scalar>::epsilon())) {
        detail::fail(detail::ErrorContext{detail::ErrorKind::model, "controller"}, "contacts",
                     "the internal-wrench basis of these contact positions is not orthonormal (departure " +
                         std::to_string(static_cast<double>(departure)) + ")");
    }
    contact_qp_constraints_ = Eigen::Matrix<Scalar, Rows, Internal>::Zero(total, internal);
    moment_gram_ = Eigen::Matrix<Scalar, Internal, Internal>::Zero(internal, internal);
    for (Index i = 0; i < arms_; ++i) {
        Eigen::Matrix<Scalar, 6, Internal> in_contact_frame(6, internal);
        rotate_stack_back(contact_rotation(i), body_internal_basis_.template middleRows<6>(6 * i), in_contact_frame);
        contact_qp_constraints_.middleRows(row_offset(i), row_count(i)) =
            friction_rows_.middleRows(row_offset(i), row_count(i)).lazyProduct(in_contact_frame);
        const auto moment_rows = body_internal_basis_.template middleRows<3>(6 * i + 3);
        moment_gram_ += moment_rows.transpose().lazyProduct(moment_rows);
    }
}

}  // namespace coopdyn

// ControllerInput, the per-tick input, sized by the model (after the model: its constructor takes one).
#include "coopdyn/control/controller_input.hpp"
