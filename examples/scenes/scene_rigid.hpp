// The rigid-grasp plant of any scene (docs/scenes.md, "The rigid plant"): the scene's arms with each
// palm welded to the object where it touches it at the start, the object with its true mass and
// inertia (the MJCF's), solved exactly by coopdyn::JointSpaceGrasp (Gauss's principle through the
// structured kernel, docs/dynamics.md "Arms in joint space") and integrated at the model's
// timestep by semi-implicit Euler (the default, MuJoCo's own integrator) or RK4. The dual-arm
// box's rigid plant (examples/box/rigid_plant.hpp) for any K and arms of any joint counts; the
// arms' M, h, J, Jdot qdot come from the plant's own recursion (chain_dynamics.hpp, built from the
// MJCF's constants; MuJoCo's to rounding), or, for arms it does not model (ArmTermsSource), from
// MuJoCo's smooth stages through the adapter (MujocoArms::read on a scratch mjData).
//
// Coordinates: the arms' q (Q), the object's centre of mass p and orientation (its body frame),
// qdot, the centre's velocity v and the angular velocity w ({w}). Unconstrained dynamics
// M(q) qdd = tau - h(q, qdot), m a = m g, I_w alpha = -w x I_w w; per palm the weld
// J_i qdd_i + Jdot_i qdot_i = [a + alpha x r_i + w x (w x r_i); alpha] + beta_i, r_i = R_o c_i,
// with Baumgarte's beta_i = -2 omega_s (velocity error) - omega_s^2 (pose error) against drift.
//
// Needs arms that share no joint, their joints contiguous in q and in the contacts' order (checked
// at construction): JointSpaceGrasp works arm by arm. The RK4 stages' vectors are sized at
// construction (the simulated world is not a per-tick path: only the controller's tick is proven
// not to allocate, docs/conventions.md). Semi-implicit Euler evaluates the arms once per step, at
// the step's start, which is the evaluation begin_tick made for the controller's input: the hold
// runs at 93-102x real time on the pairs and 51-54x with three arms, the controller at Dynamic sizes
// (CPU time, docs/performance.md, "Scenes of any arms"); RK4 evaluates four times. Euler's
// error is first order (the object's excursion differs from RK4's by 4-34 um over 0.5 s at 1 ms,
// halving with the step; its weld error is under 1 um where RK4's is 1e-15 m: test_scenes). This
// header belongs to the examples.
#pragma once

#include "chain_dynamics.hpp"
#include "scene_world.hpp"

#include <coopdyn/dynamics/integrator.hpp>
#include <coopdyn/dynamics/joint_space_grasp.hpp>
#include <coopdyn/spatial/quaternion.hpp>

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace scenes {

/// Each arm's joint count, checking that arm i's joints are the i-th contiguous block of q (the
/// rigid plant's weld solve and own recursion work arm by arm).
inline std::vector<Eigen::Index> arm_joint_counts(const SceneWorld& world)
{
    const mjModel* model = world.model();
    const Arms& arms = world.arms();
    std::vector<Eigen::Index> counts(static_cast<std::size_t>(arms.arms()), 0);
    Eigen::Index arm = 0;
    for (Eigen::Index j = 0; j < arms.joints(); ++j) {
        const int root = model->body_rootid[model->jnt_bodyid[arms.joint_id(j)]];
        while (arm < arms.arms() && model->body_rootid[arms.contact(arm).body] != root) {
            ++arm;
        }
        if (arm == arms.arms()) {
            throw SceneError(world.scene().source +
                             ": the rigid plant needs the joints arm by arm, in the contacts' order (joints[" +
                             std::to_string(j) + "])");
        }
        ++counts[static_cast<std::size_t>(arm)];
    }
    for (std::size_t i = 0; i < counts.size(); ++i) {
        if (counts[i] == 0) {
            throw SceneError(world.scene().source + ": the rigid plant finds no joint of contact " + std::to_string(i));
        }
    }
    return counts;
}

/// The arms' joints at (q, qdot) (their first Q entries) in `data`, then only the MuJoCo stages the
/// adapter's read needs (docs/adapters.md, "What read reads"): positions, the composite inertias
/// and M, velocities and cdof_dot, h. Not mj_forward: a scratch mjData keeps the object at its
/// start pose, so MuJoCo would also detect the palms' contacts and run its constraint solver, 84 %
/// of the rigid plant's instructions when it did (docs/performance.md, "Scenes of any arms").
template <typename Positions, typename Velocities>
void run_arm_stages(const mjModel* model, mjData* data, const Arms& arms, const Positions& q, const Velocities& qdot) noexcept
{
    for (Eigen::Index j = 0; j < arms.joints(); ++j) {
        data->qpos[arms.qpos_address(j)] = q(j);
        data->qvel[arms.dof_address(j)] = qdot(j);
    }
    mj_kinematics(model, data);
    mj_comPos(model, data);
    mj_crb(model, data);
    mj_comVel(model, data);
    mj_rne(model, data, 0, data->qfrc_bias);
}

/// Every arm's own recursion (ChainDynamics, chain_dynamics.hpp), in the contacts' order; none,
/// with `why` naming the arm and what is not modelled, when one arm is not a chain it models.
inline std::vector<ChainDynamics> arm_chains(const SceneWorld& world, std::string& why)
{
    const std::vector<Eigen::Index> counts = arm_joint_counts(world);
    std::vector<ChainDynamics> chains;
    Eigen::Index first = 0;
    for (Eigen::Index i = 0; i < world.arms().arms(); ++i) {
        const Eigen::Index count = counts[static_cast<std::size_t>(i)];
        std::optional<ChainDynamics> chain = ChainDynamics::from_mujoco(world.model(), world.arms(), i, first, count, why);
        if (!chain) {
            return {};
        }
        chains.push_back(*chain);
        first += count;
    }
    return chains;
}

/// The arms' M, h, J, Jdot qdot at (q, qdot) (their first Q entries, arm by arm) into `input`'s
/// blocks, arm by arm (the blocks between two arms are left alone: zero), and each contact's frame
/// into contacts[i] (sized K). Allocates nothing.
template <typename Positions, typename Velocities>
void evaluate_chains(const std::vector<ChainDynamics>& chains, const Positions& q, const Velocities& qdot,
                     coopdyn::ControllerInput<double>& input, std::vector<coopdyn::Pose<double>>& contacts) noexcept
{
    Eigen::Index first = 0;
    for (std::size_t i = 0; i < chains.size(); ++i) {
        const Eigen::Index n = chains[i].joints();
        const Eigen::Index rows = 6 * static_cast<Eigen::Index>(i);
        chains[i].evaluate(q.segment(first, n), qdot.segment(first, n), input.inertia.block(first, first, n, n),
                           input.bias.segment(first, n), input.jacobian.block(rows, first, 6, n),
                           input.jacobian_rate_qdot.template segment<6>(rows), contacts[i]);
        first += n;
    }
}

/// How the rigid plant evaluates the arms' M, h, J, Jdot qdot and contact frames: by its own
/// recursion (ChainDynamics, chain_dynamics.hpp; the arms must be serial chains of hinge joints,
/// else the plant falls back to MuJoCo) or by MuJoCo's stages and the adapter's read. The same
/// quantities to rounding (test_scenes).
enum class ArmTermsSource { own_recursion, mujoco };

class RigidScenePlant {
public:
    using Index = Eigen::Index;
    using Vector6 = coopdyn::Vector6<double>;
    using RigidBodyState = coopdyn::RigidBodyState<double>;

    /// Welds each palm to the object where the world's current state (after world.start()) has
    /// them. `stabilisation_frequency` (rad/s): the Baumgarte terms, critically damped.
    explicit RigidScenePlant(const SceneWorld& world,
                             coopdyn::Integrator integrator = coopdyn::Integrator::semi_implicit_euler,
                             double stabilisation_frequency = 50.0, ArmTermsSource source = ArmTermsSource::own_recursion)
        : world_(world),
          integrator_(integrator),
          scratch_(mj_makeData(world.model())),
          grasp_(arm_joint_counts(world)),
          stiffness_(stabilisation_frequency * stabilisation_frequency),
          damping_(2.0 * stabilisation_frequency),
          input_(world.arms().arms(), world.arms().joints())
    {
        if (!scratch_) {
            throw SceneError(world.scene().source + ": MuJoCo cannot allocate the rigid plant's mjData");
        }
        const mjModel* model = world.model();
        const int body = world.object_body();
        mass_ = model->body_mass[body];
        const mjtNum* frame = model->body_iquat + 4 * body;  // principal axes in the body frame
        const Eigen::Matrix3d axes = Eigen::Quaterniond(frame[0], frame[1], frame[2], frame[3]).normalized().toRotationMatrix();
        inertia_ = axes * Eigen::Map<const Eigen::Vector3d>(model->body_inertia + 3 * body).asDiagonal() * axes.transpose();
        gravity_ = Eigen::Map<const Eigen::Vector3d>(model->opt.gravity);
        const Index joints = world.arms().joints();
        const Index arms = world.arms().arms();
        state_.resize(joints + 7);
        velocity_.resize(joints + 6);
        if (source == ArmTermsSource::own_recursion) {
            chains_ = arm_chains(world, why_not_own_recursion_);
            contact_poses_.resize(chains_.size());
        }
        world.arms().read_positions(world.data(), state_.head(joints));
        world.arms().read_velocities(world.data(), velocity_.head(joints));
        const RigidBodyState object = coopdyn::mujoco_object_state(model, world.data(), body);
        state_.segment<3>(joints) = object.pose.position;
        state_.segment<4>(joints + 3) = object.pose.orientation.normalized().coeffs();
        velocity_.tail<6>() = object.twist;
        evaluate(state_, velocity_);
        const Eigen::Matrix3d rotation = object.pose.orientation.toRotationMatrix();
        for (Index i = 0; i < arms; ++i) {
            const coopdyn::Pose<double> palm = contact_pose(i);
            weld_point_.push_back(rotation.transpose() * (palm.position - object.pose.position));
            weld_rotation_.push_back((object.pose.orientation.conjugate() * palm.orientation).normalized());
        }
        offsets_.resize(3, arms);
        stabilisation_.assign(static_cast<std::size_t>(arms), Vector6::Zero());
        acceleration_ = Vector6::Zero();
        stage_acceleration_.resize(joints + 6);
        stage_position_.resize(joints + 7);
        stage_velocity_.resize(joints + 6);
        for (std::size_t k = 0; k < 4; ++k) {
            position_rate_[k].resize(joints + 7);
            velocity_rate_[k].resize(joints + 6);
        }
        joint_acceleration_.resize(joints);
        free_torque_.resize(joints);
    }

    double period() const noexcept { return world_.model()->opt.timestep; }

    /// The controller's input at the current state: the arms' terms and the object's state and last
    /// acceleration.
    void begin_tick(coopdyn::ControllerInput<double>& input) noexcept
    {
        evaluate(state_, velocity_);
        const Index joints = world_.arms().joints();
        input.inertia = input_.inertia;
        input.bias = input_.bias;
        input.jacobian = input_.jacobian;
        input.jacobian_rate_qdot = input_.jacobian_rate_qdot;
        input.positions = state_.head(joints);
        input.velocities = velocity_.head(joints);
        input.object.pose.position = state_.segment<3>(joints);
        input.object.pose.orientation = Eigen::Quaterniond(state_.segment<4>(joints + 3));
        input.object.twist = velocity_.tail<6>();
        input.object_acceleration = acceleration_;
    }
    /// Contact i's frame in {w} at the last evaluation (begin_tick's: the current state).
    coopdyn::Pose<double> contact_pose(Index i) const
    {
        return chains_.empty() ? world_.arms().contact_pose(scratch_.get(), i) : contact_poses_[static_cast<std::size_t>(i)];
    }
    /// Whether the arms' terms come from the own recursion; if not, why (empty when MuJoCo was
    /// asked for).
    bool own_recursion() const noexcept { return !chains_.empty(); }
    const std::string& why_not_own_recursion() const noexcept { return why_not_own_recursion_; }

    /// One step under tau (held over the step), by the plant's integrator; the palms' wrenches are
    /// those at the step's start (the state the controller saw). Needs begin_tick() at the current
    /// state first (its evaluation of the arms' terms is the step's first).
    void end_tick(const Eigen::VectorXd& tau) { end_tick(tau, Vector6::Zero()); }
    /// The same with a wrench [F; T] ({w}) on the object's centre of mass, held over the step (a
    /// person's push; the box experiments, examples/box/scene_box.hpp).
    void end_tick(const Eigen::VectorXd& tau, const Vector6& object_wrench)
    {
        object_wrench_ = object_wrench;
        if (integrator_ == coopdyn::Integrator::semi_implicit_euler) {
            euler_step(tau);
            return;
        }
        const double dt = period();
        const std::array<double, 4> fraction{0.0, 0.5, 0.5, 1.0};
        stage_position_ = state_;
        stage_velocity_ = velocity_;
        for (std::size_t k = 0; k < 4; ++k) {
            if (k > 0) {
                advance(state_, velocity_, position_rate_[k - 1], velocity_rate_[k - 1], fraction[k] * dt,
                        stage_position_, stage_velocity_);
                evaluate(stage_position_, stage_velocity_);
            }
            solve(stage_position_, stage_velocity_, tau, /*keep=*/k == 0);
            rate_of_position(stage_position_, stage_velocity_, position_rate_[k]);
            velocity_rate_[k] = stage_acceleration_;
        }
        // RK4's weighted mean of the four rates, into the first stage's (coefficient-wise: no alias).
        position_rate_[0] = (position_rate_[0] + 2.0 * position_rate_[1] + 2.0 * position_rate_[2] + position_rate_[3]) / 6.0;
        velocity_rate_[0] = (velocity_rate_[0] + 2.0 * velocity_rate_[1] + 2.0 * velocity_rate_[2] + velocity_rate_[3]) / 6.0;
        advance(state_, velocity_, position_rate_[0], velocity_rate_[0], dt, stage_position_, stage_velocity_);
        state_ = stage_position_;
        velocity_ = stage_velocity_;
    }

    /// Palm i's normal force on the object (N) at the last step's start: the weld's wrench along the
    /// contact normal (negative: the weld pulls).
    double normal_force(Index i) const noexcept { return normal_force_[static_cast<std::size_t>(i)]; }
    int contact_points(Index) const noexcept { return 1; }
    /// Palm i's whole wrench [f; t] on the object about its contact point, {w}, at the last step's
    /// start: the weld's constraint wrench -h_i (JointSpaceGrasp::palm_wrench is the object's on the palm).
    const Vector6& measured_contact_wrench(Index i) const noexcept { return measured_[static_cast<std::size_t>(i)]; }
    /// [a; alpha] of the object's centre at the last step's start, {w}.
    const Vector6& object_acceleration() const noexcept { return acceleration_; }
    double object_mass() const noexcept { return mass_; }
    /// Puts mass on the object: its mass and rotational inertia grow in proportion.
    void set_object_mass(double mass) noexcept
    {
        inertia_ *= mass / mass_;
        mass_ = mass;
    }
    /// The weld's worst position (m) and rotation (rad) error at the current state.
    std::array<double, 2> weld_error()
    {
        evaluate(state_, velocity_);
        std::array<double, 2> worst{0.0, 0.0};
        const Index joints = world_.arms().joints();
        const Eigen::Quaterniond orientation(state_.segment<4>(joints + 3));
        for (Index i = 0; i < world_.arms().arms(); ++i) {
            const auto index = static_cast<std::size_t>(i);
            const coopdyn::Pose<double> palm = contact_pose(i);
            worst[0] = std::max(worst[0], (palm.position - state_.segment<3>(joints) - orientation * weld_point_[index]).norm());
            worst[1] = std::max(worst[1], palm.orientation.angularDistance(orientation * weld_rotation_[index]));
        }
        return worst;
    }

private:
    /// The arms' terms at (position, velocity), into input_: by the own recursion, or by MuJoCo on
    /// scratch_ (which then holds the state after).
    void evaluate(const Eigen::VectorXd& position, const Eigen::VectorXd& velocity) noexcept
    {
        if (!chains_.empty()) {
            evaluate_chains(chains_, position, velocity, input_, contact_poses_);
            return;
        }
        run_arm_stages(world_.model(), scratch_.get(), world_.arms(), position, velocity);
        world_.arms().read(world_.model(), scratch_.get(), input_);
    }

    /// The weld at (position, velocity) with the terms in input_: stage_acceleration_ = [qdd; a;
    /// alpha]; `keep`: also the object's acceleration and the palms' normal forces.
    void solve(const Eigen::VectorXd& position, const Eigen::VectorXd& velocity, const Eigen::VectorXd& tau, bool keep)
    {
        const Arms& arms = world_.arms();
        const Index joints = arms.joints();
        const Eigen::Vector3d centre = position.segment<3>(joints);
        const Eigen::Quaterniond orientation(position.segment<4>(joints + 3));
        const Eigen::Matrix3d rotation = orientation.toRotationMatrix();
        const Eigen::Vector3d v = velocity.segment<3>(joints);
        const Eigen::Vector3d w = velocity.tail<3>();
        free_torque_ = tau - input_.bias;
        Index first = 0;
        for (Index i = 0; i < arms.arms(); ++i) {
            const auto index = static_cast<std::size_t>(i);
            const Index n = grasp_.joints(i);
            const Eigen::Vector3d r = rotation * weld_point_[index];
            offsets_.col(i) = r;
            const coopdyn::Pose<double> palm = contact_pose(i);
            const Vector6 twist = input_.jacobian.block(6 * i, first, 6, n) * velocity.segment(first, n);
            Vector6 error;
            error << palm.position - centre - r,
                coopdyn::quaternion_log(Eigen::Quaterniond(palm.orientation * (orientation * weld_rotation_[index]).conjugate()));
            Vector6 rate;
            rate << twist.head<3>() - v - w.cross(r), twist.tail<3>() - w;
            stabilisation_[index] = -damping_ * rate - stiffness_ * error;
            if (!grasp_.set_arm(i, input_.inertia.block(first, first, n, n), input_.jacobian.block(6 * i, first, 6, n),
                                free_torque_.segment(first, n), input_.jacobian_rate_qdot.segment<6>(6 * i),
                                stabilisation_[index])) {
                throw SceneError("rigid plant: arm " + std::to_string(i) + "'s M is not positive definite");
            }
            first += n;
        }
        const Eigen::Matrix3d inertia_world = rotation * inertia_ * rotation.transpose();
        Vector6 free_wrench;
        free_wrench << mass_ * gravity_, -w.cross(inertia_world * w);
        free_wrench += object_wrench_;
        if (!grasp_.solve(coopdyn::CentralInertia<double>(mass_, inertia_world), offsets_, w, free_wrench,
                          joint_acceleration_)) {
            throw SceneError("rigid plant: an arm is singular (a palm cannot move in every direction)");
        }
        stage_acceleration_.head(joints) = joint_acceleration_;
        stage_acceleration_.tail<6>() = grasp_.object_acceleration();
        if (keep) {
            acceleration_ = grasp_.object_acceleration();
            normal_force_.resize(static_cast<std::size_t>(arms.arms()));
            measured_.resize(static_cast<std::size_t>(arms.arms()));
            for (Index i = 0; i < arms.arms(); ++i) {
                measured_[static_cast<std::size_t>(i)] = -grasp_.palm_wrench(i);
                const coopdyn::Pose<double> palm = contact_pose(i);
                // The palm's wrench on the object is -h_i; its normal: the contact frame's z.
                normal_force_[static_cast<std::size_t>(i)] =
                    -(palm.orientation * Eigen::Vector3d::UnitZ()).dot(grasp_.palm_wrench(i).head<3>());
            }
        }
    }

    /// Semi-implicit Euler: qdot, v, w from the accelerations at the step's start (the terms
    /// begin_tick evaluated), then q, p from the new velocities and the orientation by the exact
    /// rotation of the new w over the step.
    void euler_step(const Eigen::VectorXd& tau)
    {
        const double dt = period();
        const Index joints = world_.arms().joints();
        solve(state_, velocity_, tau, /*keep=*/true);
        velocity_ += dt * stage_acceleration_;
        state_.head(joints + 3) += dt * velocity_.head(joints + 3);
        const Eigen::Quaterniond orientation(state_.segment<4>(joints + 3));
        const Eigen::Vector3d rotation = dt * velocity_.tail<3>();
        state_.segment<4>(joints + 3) = (coopdyn::quaternion_exp(rotation) * orientation).normalized().coeffs();
    }

    /// d/dt of [q; p; quaternion coeffs (x, y, z, w)], into rate (sized joints + 7).
    void rate_of_position(const Eigen::VectorXd& position, const Eigen::VectorXd& velocity, Eigen::VectorXd& rate) const noexcept
    {
        const Index joints = world_.arms().joints();
        rate.head(joints + 3) = velocity.head(joints + 3);
        const Eigen::Quaterniond orientation(position.segment<4>(joints + 3));
        rate.tail<4>() = coopdyn::quaternion_derivative_world(orientation, Eigen::Vector3d(velocity.tail<3>())).coeffs();
    }

    void advance(const Eigen::VectorXd& position, const Eigen::VectorXd& velocity, const Eigen::VectorXd& position_rate,
                 const Eigen::VectorXd& velocity_rate, double dt, Eigen::VectorXd& position_out,
                 Eigen::VectorXd& velocity_out) const
    {
        const Index joints = world_.arms().joints();
        position_out = position + dt * position_rate;
        position_out.segment<4>(joints + 3).normalize();
        velocity_out = velocity + dt * velocity_rate;
    }

    const SceneWorld& world_;
    coopdyn::Integrator integrator_;
    DataPointer scratch_;
    coopdyn::JointSpaceGrasp<double> grasp_;
    double stiffness_;
    double damping_;
    double mass_ = 0.0;
    Eigen::Matrix3d inertia_ = Eigen::Matrix3d::Identity();  ///< about the centre, body frame
    Eigen::Vector3d gravity_ = Eigen::Vector3d::Zero();
    coopdyn::ControllerInput<double> input_;  ///< the arms' terms at the last evaluate()
    Eigen::VectorXd state_;     ///< [q; p; quaternion coeffs]
    Eigen::VectorXd velocity_;  ///< [qdot; v; w]
    std::vector<Eigen::Vector3d> weld_point_;
    std::vector<Eigen::Quaterniond> weld_rotation_;
    Eigen::Matrix3Xd offsets_;
    std::vector<Vector6> stabilisation_;
    Vector6 acceleration_;
    std::vector<double> normal_force_;
    std::vector<Vector6> measured_;  ///< the palms' wrenches on the object, {w}
    Vector6 object_wrench_ = Vector6::Zero();  ///< a push on the object's centre, this step
    Eigen::VectorXd stage_acceleration_;
    // RK4's stage state and the four stages' rates, sized at construction (a step allocates none
    // of them).
    Eigen::VectorXd stage_position_;
    Eigen::VectorXd stage_velocity_;
    std::array<Eigen::VectorXd, 4> position_rate_;
    std::array<Eigen::VectorXd, 4> velocity_rate_;
    Eigen::VectorXd joint_acceleration_;
    Eigen::VectorXd free_torque_;
    std::vector<ChainDynamics> chains_;  ///< one per arm, or none (MuJoCo's stages)
    std::vector<coopdyn::Pose<double>> contact_poses_;  ///< the chains' contact frames at the last evaluation
    std::string why_not_own_recursion_;
};

}  // namespace scenes
