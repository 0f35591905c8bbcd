// The exact rigid-grasp plant of the dual-arm box (docs/dual-arm-box.md, "The rigid plant"): the
// two arms plus the box with its TRUE mass and inertia, each palm welded to the box. The
// accelerations and the true contact wrenches come from coopdyn's Udwadia-Kalaba solution (paper
// (18)-(19)) applied in joint space (by default in the first paper's structured form,
// coopdyn::interaction_wrenches; see WeldSolver), integrated with RK4 at the controller's rate.
//
// Coordinates: the arms' q (14), the box's centre p and orientation q_o; velocities qdot, the
// centre's velocity v and the angular velocity w, both in {w}. Unconstrained dynamics
//
//     M(q) qdd = tau - h(q, qdot)
//     m a = m g + F_e,        I_w alpha = T_e - w x I_w w           (the box, about its centre)
//
// and, per palm i, the weld: the palm's contact point moves with the box point r_i = R_o c_i and
// turns with the box,
//
//     J_i qdd + Jdot_i qdot = [a + alpha x r_i + w x (w x r_i); alpha]  - Baumgarte terms,
//
// i.e. A [qdd; a; alpha] = b with A_i = [J_i^lin, -I, S(r_i); J_i^ang, 0, -I]. The constraint
// force h = A^T lambda: lambda_i is the wrench the box applies to palm i, so palm i applies
// w_i = -lambda_i to the box (about its contact point, {w}). Integration drift of the weld is
// corrected by Baumgarte stabilisation (critically damped at `stabilisation_frequency`).
//
// The arms' M, h, J, Jdot qdot come from their own recursion (lwr4_dynamics.hpp, from lwr4.hpp's
// DH parameters), not from MuJoCo: this header needs no MuJoCo. It starts from any state, e.g.
// hold_state() (lwr4.hpp's hold configuration); mujoco_rigid_plant.hpp starts it from the MJCF's
// keyframe instead and checks that the MJCF's arms are lwr4.hpp's. WeldSolver::structured solves
// the weld arm by arm (coopdyn::JointSpaceGrasp). This header belongs to the examples, not to the
// library.
#pragma once

#include "box_model.hpp"
#include "lwr4.hpp"
#include "lwr4_dynamics.hpp"

#include <coopdyn/dynamics/joint_space_grasp.hpp>
#include <coopdyn/dynamics/udwadia_kalaba.hpp>
#include <coopdyn/spatial/inertia.hpp>
#include <coopdyn/spatial/quaternion.hpp>
#include <coopdyn/spatial/skew.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/QR>

#include <algorithm>
#include <array>

namespace box_example {

constexpr int plant_velocities = joints + 6;  ///< qdot (14), v (3), w (3)
using PlantVector = Eigen::Matrix<double, plant_velocities, 1>;
using PlantMatrix = Eigen::Matrix<double, plant_velocities, plant_velocities>;
using WeldMatrix = Eigen::Matrix<double, 6 * palms, plant_velocities>;
/// Rate of the positions: qdot (14), the centre's velocity (3), the quaternion's rate (4, Eigen's
/// coeffs order x, y, z, w).
using PositionRate = Eigen::Matrix<double, joints + 7, 1>;
/// Both arms' terms arm by arm, as Lwr4Dynamics gives them: what the RK4 stages evaluate and the
/// weld solves read. ArmTerms is their block-diagonal 14-joint form.
using ArmPairTerms = std::array<Lwr4ArmTerms, palms>;

/// The arms and the box at one instant.
struct PlantState {
    JointVector q = JointVector::Zero();
    JointVector qdot = JointVector::Zero();
    Eigen::Vector3d box_position = Eigen::Vector3d::Zero();
    Eigen::Quaterniond box_orientation = Eigen::Quaterniond::Identity();
    Eigen::Vector3d box_velocity = Eigen::Vector3d::Zero();          ///< of the centre, {w}
    Eigen::Vector3d box_angular_velocity = Eigen::Vector3d::Zero();  ///< {w}
};

/// What the weld does at one state: accelerations and the palms' true wrenches on the box.
struct RigidGraspSolution {
    JointVector joint_acceleration = JointVector::Zero();
    Vector6d box_acceleration = Vector6d::Zero();  ///< [a; alpha] of the centre, {w}
    /// Palm i's wrench [f; t] on the box about its contact point, {w}.
    std::array<Vector6d, palms> contact_wrench{};
};

/// The box's true inertia (unknown to the controller).
struct BoxInertia {
    double mass = 0.7;
    Eigen::Matrix3d inertia = Eigen::Matrix3d::Identity();  ///< about the centre, box frame
};

/// The box of lwr4.hpp's box_spec() with `mass`: a uniform cuboid, principal axes along the box's.
inline BoxInertia box_inertia(double mass)
{
    const Eigen::Vector3d squared = box_spec().size.cwiseAbs2();
    BoxInertia box;
    box.mass = mass;
    box.inertia = (mass / 12.0) *
                  Eigen::Vector3d(squared.y() + squared.z(), squared.x() + squared.z(), squared.x() + squared.y()).asDiagonal();
    return box;
}

/// lwr4.hpp's hold configuration at rest: the arms in q_hold(), the box at box_hold_pose(), the
/// palms touching it (the MJCF's keyframe "hold" holds the same numbers).
inline PlantState hold_state()
{
    PlantState state;
    state.q = q_hold();
    state.box_position = box_hold_pose().translation();
    state.box_orientation = Eigen::Quaterniond(box_hold_pose().linear());
    return state;
}

class RigidGraspPlant {
public:
    /// Starts from `initial` (e.g. hold_state(); a unit box orientation) and welds each palm to the
    /// box where it is there.
    /// `gravity` in {w}; the weld's drift is corrected by Baumgarte terms critically damped at
    /// `stabilisation_frequency` (rad/s).
    RigidGraspPlant(const PlantState& initial, const BoxInertia& box,
                    const Eigen::Vector3d& gravity = Eigen::Vector3d(0.0, 0.0, -9.81),
                    double stabilisation_frequency = 50.0)
        : arms_{Lwr4Dynamics(Side::left, gravity), Lwr4Dynamics(Side::right, gravity)},
          box_(box),
          gravity_(gravity),
          period_(controller_period),
          stiffness_(stabilisation_frequency * stabilisation_frequency),
          damping_(2.0 * stabilisation_frequency),
          state_(initial)
    {
        const Eigen::Matrix3d box_rotation = state_.box_orientation.toRotationMatrix();
        evaluate_terms(state_, own_terms_);
        // The cross blocks stay zero (the arms share no joint): write_block_diagonal() writes
        // only the arms' own blocks.
        terms_.inertia.setZero();
        terms_.jacobian.setZero();
        write_block_diagonal(own_terms_, terms_);
        for (std::size_t i = 0; i < palms; ++i) {
            weld_point_[i] = box_rotation.transpose() * (own_terms_[i].palm_position - state_.box_position);
            weld_rotation_[i] = Eigen::Quaterniond(box_rotation.transpose() * own_terms_[i].palm_rotation).normalized();
        }
    }

    // The plant interface the experiment drives (the same as MujocoPlant's).
    double time() const noexcept { return time_; }
    void begin_tick() noexcept {}
    const Eigen::Vector3d& box_position() const noexcept { return state_.box_position; }
    const Eigen::Quaterniond& box_orientation() const noexcept { return state_.box_orientation; }
    Vector6d box_twist() const noexcept
    {
        Vector6d twist;
        twist << state_.box_velocity, state_.box_angular_velocity;
        return twist;
    }
    /// [a; alpha] of the box in the last step (zero before the first).
    const Vector6d& box_acceleration() const noexcept { return solution_.box_acceleration; }
    const JointVector& joint_positions() const noexcept { return state_.q; }
    const JointVector& joint_velocities() const noexcept { return state_.qdot; }
    /// One step of the controller's period under tau and the box wrench.
    void end_tick(const JointVector& tau, const Vector6d& box_wrench)
    {
        step(tau, box_wrench, period_);
        time_ += period_;
    }
    /// Palm i's true wrench on the box, about its contact point, {w}, at the state of the last
    /// tick's start (the state the controller saw).
    const Vector6d& measured_contact_wrench(int palm) const noexcept
    {
        return solution_.contact_wrench[static_cast<std::size_t>(palm)];
    }
    int contact_points(int) const noexcept { return 1; }
    double box_mass() const noexcept { return box_.mass; }

    const PlantState& state() const noexcept { return state_; }
    /// M, h, J, Jdot qdot and the palm frames at state().
    const ArmTerms& arm_terms() const noexcept { return terms_; }
    /// The weld's solution at the start of the last step (the state the controller saw).
    const RigidGraspSolution& solution() const noexcept { return solution_; }
    /// Where palm i is welded to the box, in the box frame.
    const Eigen::Vector3d& weld_point(int palm) const noexcept { return weld_point_[static_cast<std::size_t>(palm)]; }
    const BoxInertia& box() const noexcept { return box_; }
    const Eigen::Vector3d& gravity() const noexcept { return gravity_; }
    /// A mass placed on the box (docs/dual-arm-box.md, "Add mass"): the box's mass and inertia
    /// about its centre grow in proportion.
    void set_box_mass(double mass) noexcept
    {
        box_.inertia *= mass / box_.mass;
        box_.mass = mass;
    }
    /// The weld's violation at state(): the largest palm position error (m) and rotation error
    /// (rad). Computed when asked, not every step: the tests ask, the experiment does not.
    std::array<double, 2> weld_error() const noexcept
    {
        std::array<double, 2> worst{0.0, 0.0};
        const Eigen::Matrix3d box_rotation = state_.box_orientation.toRotationMatrix();
        for (std::size_t i = 0; i < palms; ++i) {
            const Eigen::Vector3d r = box_rotation * weld_point_[i];
            worst[0] = std::max(worst[0], (own_terms_[i].palm_position - state_.box_position - r).norm());
            const Eigen::Quaterniond welded = state_.box_orientation * weld_rotation_[i];
            worst[1] = std::max(
                worst[1], coopdyn::quaternion_log(Eigen::Quaterniond(own_terms_[i].palm_rotation) * welded.conjugate()).norm());
        }
        return worst;
    }

    /// One RK4 step of `dt` under the joint torques `tau` and the wrench `box_wrench` = [F_e; T_e]
    /// on the box's centre ({w}), both held over the step.
    void step(const JointVector& tau, const Vector6d& box_wrench, double dt)
    {
        std::array<PlantVector, 4> acceleration{};
        std::array<PositionRate, 4> velocity{};
        const std::array<double, 4> fraction{0.0, 0.5, 0.5, 1.0};
        // The stages after the first evaluate the arms arm by arm (no 14-joint copies); the first
        // is the state the controller saw, whose solution is kept.
        PlantState stage;
        ArmPairTerms stage_terms;
        RigidGraspSolution stage_solution;
        for (std::size_t k = 0; k < 4; ++k) {
            if (k > 0) {
                stage = advanced(velocity[k - 1], acceleration[k - 1], fraction[k] * dt);
                evaluate_terms(stage, stage_terms);
            }
            const PlantState& at = k == 0 ? state_ : stage;
            RigidGraspSolution& solution = k == 0 ? solution_ : stage_solution;
            solve_arms(at, k == 0 ? own_terms_ : stage_terms, tau, box_wrench, solution, /*with_wrenches=*/k == 0,
                       WeldSolver::structured);
            velocity[k] << at.qdot, at.box_velocity,
                coopdyn::quaternion_derivative_world(at.box_orientation, at.box_angular_velocity).coeffs();
            acceleration[k] << solution.joint_acceleration, solution.box_acceleration;
        }
        const PositionRate mean_velocity = (velocity[0] + 2.0 * velocity[1] + 2.0 * velocity[2] + velocity[3]) / 6.0;
        const PlantVector mean_acceleration =
            (acceleration[0] + 2.0 * acceleration[1] + 2.0 * acceleration[2] + acceleration[3]) / 6.0;
        state_ = advanced(mean_velocity, mean_acceleration, dt);
        evaluate_terms(state_, own_terms_);
        write_block_diagonal(own_terms_, terms_);
    }

    /// How solve() applies (18):
    /// - `structured` (the per-tick path): per arm, the palm's operational-space inertia
    ///   Lambda_i = (J_i M_i^-1 J_i^T)^-1 and free acceleration turn the weld into the first
    ///   paper's N + 1 bodies, solved by coopdyn::JointSpaceGrasp (the structured form of
    ///   (18); docs/dual-arm-box.md, "The rigid plant"). Exact, because the arms share no joint:
    ///   M and J are block diagonal (checked at construction).
    /// - `constraint_space`: coopdyn::try_udwadia_kalaba_full_rank on the stacked 20-velocity
    ///   system (the constraint-space inertia A M^-1 A^T, multipliers directly).
    /// - `generic`: coopdyn::udwadia_kalaba, the pseudo-inverse form, with the multipliers from a
    ///   QR of A^T.
    /// The first two need full row rank; when an arm is singular they fall back to `generic`.
    /// The tests compare all three.
    enum class WeldSolver { structured, constraint_space, generic };

    /// The weld's accelerations and (with_wrenches) the palms' wrenches at `state` (terms
    /// evaluated there) under tau and the box wrench: the Udwadia-Kalaba solution of the stacked
    /// system.
    void solve(const PlantState& state, const ArmTerms& terms, const JointVector& tau, const Vector6d& box_wrench,
               RigidGraspSolution& out, bool with_wrenches = true, WeldSolver solver = WeldSolver::structured) const
    {
        ArmPairTerms arm_terms;
        for (std::size_t i = 0; i < palms; ++i) {
            const Eigen::Index joint = arm_joints * static_cast<Eigen::Index>(i), row = 6 * static_cast<Eigen::Index>(i);
            arm_terms[i].inertia = terms.inertia.block<arm_joints, arm_joints>(joint, joint);
            arm_terms[i].bias = terms.bias.segment<arm_joints>(joint);
            arm_terms[i].jacobian = terms.jacobian.block<6, arm_joints>(row, joint);
            arm_terms[i].jacobian_rate_qdot = terms.jacobian_rate_qdot.segment<6>(row);
            arm_terms[i].palm_position = terms.palm_position[i];
            arm_terms[i].palm_rotation = terms.palm_rotation[i];
        }
        solve_arms(state, arm_terms, tau, box_wrench, out, with_wrenches, solver);
    }

private:
    /// What every weld solver needs at one state, computed once: per palm, the weld point
    /// r_i = R_o c_i ({w}) and the Baumgarte term beta_i of the weld's acceleration
    /// J_i qdd + Jdot_i qdot = [a + alpha x r_i + w x (w x r_i); alpha] + beta_i,
    /// beta_i = -2 omega_s (velocity error) - omega_s^2 (pose error); and the box's inertia in {w}.
    struct WeldGeometry {
        Eigen::Matrix<double, 3, palms> offset;
        std::array<Vector6d, palms> stabilisation{};
        Eigen::Matrix3d box_inertia_world;  ///< R_o I R_o^T, about the centre
    };

    /// solve() on the arms' terms arm by arm.
    void solve_arms(const PlantState& state, const ArmPairTerms& terms, const JointVector& tau, const Vector6d& box_wrench,
                    RigidGraspSolution& out, bool with_wrenches, WeldSolver solver) const
    {
        const WeldGeometry weld = weld_geometry(state, terms);
        const bool solved = (solver == WeldSolver::structured && solve_structured(state, terms, weld, tau, box_wrench, out)) ||
                            (solver == WeldSolver::constraint_space &&
                             solve_stacked(state, terms, weld, tau, box_wrench, out, with_wrenches, /*generic=*/false));
        if (!solved) {
            solve_stacked(state, terms, weld, tau, box_wrench, out, with_wrenches, /*generic=*/true);
        }
    }

    WeldGeometry weld_geometry(const PlantState& state, const ArmPairTerms& terms) const
    {
        WeldGeometry weld;
        const Eigen::Matrix3d box_rotation = state.box_orientation.toRotationMatrix();
        weld.box_inertia_world = coopdyn::Symmetric3<double>(box_.inertia).rotated(box_rotation).matrix();
        const Eigen::Vector3d& w = state.box_angular_velocity;
        for (std::size_t i = 0; i < palms; ++i) {
            const Eigen::Vector3d r = box_rotation * weld_point_[i];
            weld.offset.col(static_cast<Eigen::Index>(i)) = r;
            const Eigen::Vector3d position_error = terms[i].palm_position - (state.box_position + r);
            const Eigen::Quaterniond welded_orientation = state.box_orientation * weld_rotation_[i];
            const Eigen::Vector3d rotation_error = coopdyn::quaternion_log(
                Eigen::Quaterniond(terms[i].palm_rotation) * welded_orientation.conjugate());
            const Vector6d palm_twist =
                terms[i].jacobian * state.qdot.segment<arm_joints>(arm_joints * static_cast<Eigen::Index>(i));
            Vector6d velocity_error;
            velocity_error << palm_twist.head<3>() - (state.box_velocity + w.cross(r)), palm_twist.tail<3>() - w;
            Vector6d pose_error;
            pose_error << position_error, rotation_error;
            weld.stabilisation[i] = -damping_ * velocity_error - stiffness_ * pose_error;
        }
        return weld;
    }

    /// The box's unconstrained wrench about its centre, {w}: [m g + F_e; T_e - w x I_w w].
    Vector6d box_free_wrench(const Eigen::Matrix3d& inertia_world, const Eigen::Vector3d& w, const Vector6d& box_wrench) const
    {
        Vector6d wrench;
        wrench << box_.mass * gravity_ + box_wrench.head<3>(), box_wrench.tail<3>() - w.cross(inertia_world * w);
        return wrench;
    }

    /// WeldSolver::structured: coopdyn::JointSpaceGrasp (docs/dynamics.md, "Arms in joint space").
    /// Arm i alone, with a wrench f_i on its palm, has the palm acceleration a_i + Lambda_i^-1 f_i,
    /// a_i = J_i M_i^-1 (tau_i - h_i) + Jdot_i qdot_i: the palm is a body of inertia Lambda_i =
    /// (J_i M_i^-1 J_i^T)^-1 pushed by hSigma_i = Lambda_i a_i, and the first paper's structured
    /// kernel solves the weld; the weld's Baumgarte term beta_i is its stabilisation. Returns
    /// false, writing nothing, when an arm's M_i or J_i M_i^-1 J_i^T is not safely positive
    /// definite.
    bool solve_structured(const PlantState& state, const ArmPairTerms& terms, const WeldGeometry& weld,
                          const JointVector& tau, const Vector6d& box_wrench, RigidGraspSolution& out) const
    {
        for (std::size_t i = 0; i < palms; ++i) {
            const Eigen::Index joint = arm_joints * static_cast<Eigen::Index>(i);
            if (!grasp_.set_arm(static_cast<Eigen::Index>(i), terms[i].inertia, terms[i].jacobian,
                                tau.segment<arm_joints>(joint) - terms[i].bias, terms[i].jacobian_rate_qdot,
                                weld.stabilisation[i])) {
                return false;
            }
        }
        const Eigen::Matrix3d& inertia_world = weld.box_inertia_world;
        const Eigen::Vector3d& w = state.box_angular_velocity;
        // solve() writes qdd only when it succeeds.
        if (!grasp_.solve(coopdyn::CentralInertia<double>(box_.mass, inertia_world), weld.offset, w,
                          box_free_wrench(inertia_world, w, box_wrench), out.joint_acceleration)) {
            return false;  // a palm cannot move in every direction: the arm is singular
        }
        out.box_acceleration = grasp_.object_acceleration();
        for (std::size_t i = 0; i < palms; ++i) {
            out.contact_wrench[i] = -grasp_.palm_wrench(static_cast<Eigen::Index>(i));  // h_i: the box's wrench on palm i
        }
        return true;
    }

    /// WeldSolver::constraint_space (returns false on rank loss) and WeldSolver::generic on the
    /// stacked system A [qdd; a; alpha] = b of the file comment.
    bool solve_stacked(const PlantState& state, const ArmPairTerms& arm_terms, const WeldGeometry& weld,
                       const JointVector& tau, const Vector6d& box_wrench, RigidGraspSolution& out, bool with_wrenches,
                       bool generic) const
    {
        ArmTerms terms;
        write_block_diagonal(arm_terms, terms);  // ArmTerms' cross blocks start zero
        const Eigen::Matrix3d& inertia_world = weld.box_inertia_world;
        const Eigen::Vector3d& w = state.box_angular_velocity;
        PlantMatrix inertia = PlantMatrix::Zero();
        inertia.topLeftCorner<joints, joints>() = terms.inertia;
        inertia.block<3, 3>(joints, joints) = box_.mass * Eigen::Matrix3d::Identity();
        inertia.block<3, 3>(joints + 3, joints + 3) = inertia_world;
        PlantVector unconstrained;
        unconstrained << tau - terms.bias, box_free_wrench(inertia_world, w, box_wrench);

        WeldMatrix constraint = WeldMatrix::Zero();
        StackVector rate;
        for (std::size_t i = 0; i < palms; ++i) {
            const Eigen::Index row = static_cast<Eigen::Index>(6 * i);
            const Eigen::Vector3d r = weld.offset.col(static_cast<Eigen::Index>(i));
            constraint.block<6, joints>(row, 0) = terms.jacobian.middleRows<6>(row);
            constraint.block<3, 3>(row, joints) = -Eigen::Matrix3d::Identity();
            constraint.block<3, 3>(row, joints + 3) = coopdyn::skew(r);
            constraint.block<3, 3>(row + 3, joints + 3) = -Eigen::Matrix3d::Identity();
            Vector6d weld_rate = weld.stabilisation[i] - terms.jacobian_rate_qdot.segment<6>(row);
            weld_rate.head<3>() += w.cross(w.cross(r));
            rate.segment<6>(row) = weld_rate;
        }
        PlantVector acceleration = PlantVector::Zero();
        StackVector lambda = StackVector::Zero();
        if (generic) {
            const PlantVector constraint_force = coopdyn::udwadia_kalaba(inertia, constraint, rate, unconstrained);
            acceleration = inertia.llt().solve(unconstrained + constraint_force);
            // h = A^T lambda: the least-squares multipliers (unique while A has full row rank).
            lambda = Eigen::ColPivHouseholderQR<Eigen::Matrix<double, plant_velocities, 6 * palms>>(constraint.transpose())
                         .solve(constraint_force);
        } else if (!coopdyn::try_udwadia_kalaba_full_rank(inertia, constraint, rate, unconstrained, lambda, acceleration)) {
            return false;
        }
        out.joint_acceleration = acceleration.head<joints>();
        out.box_acceleration = acceleration.tail<6>();
        if (with_wrenches) {
            for (std::size_t i = 0; i < palms; ++i) {
                out.contact_wrench[i] = -lambda.segment<6>(static_cast<Eigen::Index>(6 * i));
            }
        }
        return true;
    }

    /// Each arm's terms by its own recursion (lwr4_dynamics.hpp).
    void evaluate_terms(const PlantState& state, ArmPairTerms& terms) const noexcept
    {
        for (std::size_t i = 0; i < palms; ++i) {
            const Eigen::Index joint = arm_joints * static_cast<Eigen::Index>(i);
            arms_[i].evaluate(state.q.segment<arm_joints>(joint), state.qdot.segment<arm_joints>(joint), terms[i]);
        }
    }

    /// The arms' own blocks of `terms` (the arms share no joint: the cross blocks are left as
    /// they are, zero).
    static void write_block_diagonal(const ArmPairTerms& arm_terms, ArmTerms& terms) noexcept
    {
        for (std::size_t i = 0; i < palms; ++i) {
            const Eigen::Index joint = arm_joints * static_cast<Eigen::Index>(i), row = 6 * static_cast<Eigen::Index>(i);
            terms.inertia.block<arm_joints, arm_joints>(joint, joint) = arm_terms[i].inertia;
            terms.bias.segment<arm_joints>(joint) = arm_terms[i].bias;
            terms.jacobian.block<6, arm_joints>(row, joint) = arm_terms[i].jacobian;
            terms.jacobian_rate_qdot.segment<6>(row) = arm_terms[i].jacobian_rate_qdot;
            terms.palm_position[i] = arm_terms[i].palm_position;
            terms.palm_rotation[i] = arm_terms[i].palm_rotation;
        }
    }

    PlantState advanced(const PositionRate& velocity, const PlantVector& acceleration, double dt) const
    {
        PlantState next = state_;
        next.q += dt * velocity.head<joints>();
        next.qdot += dt * acceleration.head<joints>();
        next.box_position += dt * velocity.segment<3>(joints);
        next.box_orientation.coeffs() += dt * velocity.tail<4>();
        next.box_orientation.normalize();
        next.box_velocity += dt * acceleration.segment<3>(joints);
        next.box_angular_velocity += dt * acceleration.tail<3>();
        return next;
    }

    std::array<Lwr4Dynamics, palms> arms_;
    BoxInertia box_;
    Eigen::Vector3d gravity_;
    double period_;
    double time_ = 0.0;
    double stiffness_;
    double damping_;
    PlantState state_;
    ArmPairTerms own_terms_;  ///< at state_, arm by arm
    ArmTerms terms_;          ///< the same, block diagonal (arm_terms())
    RigidGraspSolution solution_;
    std::array<Eigen::Vector3d, palms> weld_point_{};
    std::array<Eigen::Quaterniond, palms> weld_rotation_{};
    /// WeldSolver::structured's workspace (sized once; scratch, hence mutable in the const solves).
    mutable coopdyn::JointSpaceGrasp<double, palms, arm_joints> grasp_;
};

}  // namespace box_example
