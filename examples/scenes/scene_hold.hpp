// The hold experiment on any scene (docs/scenes.md, "Holding"): the arms keep the object at its start
// pose with coopdyn's projected inverse-dynamics controller (dynamic sizes). run_hold_on() runs it
// on a plant: MujocoScenePlant here (the object held by friction alone), RigidScenePlant
// (scene_rigid.hpp, the palms welded to the object). The MuJoCo plant is the dual-arm box's
// (examples/box/mujoco_plant.hpp, box_experiment.hpp) for any K and Q: each 1 ms tick
//
//     mj_step1  ->  MujocoArms::read (M, h, J, Jdot qdot, q, qdot), mujoco_object_state (the
//     object's centre: pose, twist), its last acceleration low-passed  ->  controller_tick  ->
//     qfrc_applied = tau  ->  mj_step2  ->  each palm's contact force (mj_contactForce)
//
// The palms first press into the object for settle_seconds (not measured): the start's palms touch
// it without force, and the soft contact takes a few ticks to build up the commanded squeeze.
//
// This header belongs to the examples (it depends on MuJoCo), not to the library.
#pragma once

#include "scene_world.hpp"

#include <coopdyn/spatial/spatial_vector.hpp>

#include <array>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

namespace scenes {

struct HoldSettings {
    double seconds = 2.0;           ///< measured time (s), after the settling
    double settle_seconds = 0.2;    ///< the palms press in first (s)
    double acceleration_cutoff = 20.0;  ///< Hz, the object's measured acceleration low-pass (0: none)
    double drop_slip = 0.05;        ///< slip (m) above which the object counts as dropped; the run stops
    ControllerSettings controller{};
};

struct PalmHold {
    double max_slip = 0.0;             ///< m: the object's centre moved in the palm's contact plane
    double mean_normal_force = 0.0;    ///< N, MuJoCo's, over the measured time
    double final_normal_force = 0.0;   ///< N, MuJoCo's, last tick
    double predicted_normal_force = 0.0;  ///< N, the controller's QP, last tick
    int min_contact_points = 0;        ///< fewest MuJoCo contact points with the object in a tick
};

struct HoldResult {
    std::vector<PalmHold> palms;
    bool dropped = false;
    double max_slip = 0.0;              ///< over the palms
    double max_position_error = 0.0;    ///< m, the object's centre from its start
    double max_orientation_error = 0.0; ///< rad
    long ticks = 0;                     ///< measured ticks run
    long not_ok_ticks = 0;              ///< ticks whose ControlStatus was not ok (friction_infeasible, ...)
    long fallback_ticks = 0;            ///< ticks on the QP's fallback (no squeeze satisfied every row)
    double max_torque = 0.0;            ///< N m, the largest |tau_j| sent
    double real_time_factor = 0.0;      ///< simulated / wall time, settling included
    double tick_microseconds = 0.0;     ///< the controller ticks' mean wall time
};

/// The MuJoCo plant of a scene (examples/box/mujoco_plant.hpp for any K, Q): the world's model and
/// data step by step, the controller between mj_step1 and mj_step2.
class MujocoScenePlant {
public:
    explicit MujocoScenePlant(SceneWorld& world)
        : world_(world),
          contacts_(world.arms().arms()),
          measured_(static_cast<std::size_t>(world.arms().arms()), coopdyn::Vector6<double>::Zero())
    {
    }

    double period() const noexcept { return world_.model()->opt.timestep; }
    /// mj_step1, then the controller's input: the arms (adapter), the object's centre (pose, twist)
    /// and its acceleration in the last step.
    void begin_tick(coopdyn::ControllerInput<double>& input) noexcept
    {
        mj_step1(world_.model(), world_.data());
        world_.arms().read(world_.model(), world_.data(), input);
        input.object = coopdyn::mujoco_object_state(world_.model(), world_.data(), world_.object_body());
        input.object_acceleration = acceleration_;
        orientation_ = input.object.pose.orientation;
    }
    /// Contact i's frame at the tick's start (the state the controller saw).
    coopdyn::Pose<double> contact_pose(Eigen::Index i) const { return world_.arms().contact_pose(world_.data(), i); }
    /// qfrc_applied = tau, mj_step2, then the object's acceleration and the palms' contact forces.
    void end_tick(const Eigen::VectorXd& tau) noexcept { end_tick(tau, coopdyn::Vector6<double>::Zero()); }
    /// The same with a wrench [F; T] ({w}) on the object's centre of mass (a person's push; the
    /// box experiments, examples/box/scene_box.hpp).
    void end_tick(const Eigen::VectorXd& tau, const coopdyn::Vector6<double>& object_wrench) noexcept
    {
        mjData* data = world_.data();
        for (Eigen::Index j = 0; j < world_.arms().joints(); ++j) {
            data->qfrc_applied[world_.arms().dof_address(j)] = tau(j);
        }
        coopdyn::mujoco_set_applied_wrench(world_.model(), data, world_.object_body(), object_wrench);
        mj_step2(world_.model(), data);
        // The free joint's qacc: linear in {w}, angular in the body frame.
        const mjtNum* qacc = data->qacc + world_.object_dof();
        acceleration_ << qacc[0], qacc[1], qacc[2], orientation_ * Eigen::Vector3d(qacc[3], qacc[4], qacc[5]);
        measure_contacts();
    }
    /// Palm i's normal force on the object (N, along MuJoCo's contact normals) and its MuJoCo contact
    /// points, in the last step.
    double normal_force(Eigen::Index i) const noexcept { return contacts_.normal_forces(i); }
    int contact_points(Eigen::Index i) const noexcept { return contacts_.points(i); }
    /// Palm i's whole wrench [f; t] on the object about its contact site (where the controller saw
    /// it), {w}, summed over its MuJoCo contacts in the last step.
    const coopdyn::Vector6<double>& measured_contact_wrench(Eigen::Index i) const noexcept
    {
        return measured_[static_cast<std::size_t>(i)];
    }
    /// [a; alpha] of the object's centre in the last step, {w}.
    const coopdyn::Vector6<double>& object_acceleration() const noexcept { return acceleration_; }
    double object_mass() const noexcept { return world_.model()->body_mass[world_.object_body()]; }
    /// Puts mass on the object (the box's "add mass"): its mass and rotational inertia grow in
    /// proportion, in the world's model (a world per run: examples/box/scene_box.hpp). mj_setConst
    /// overwrites the mjData it is given, so it gets a scratch one.
    void set_object_mass(double mass)
    {
        mjModel* model = world_.model();
        const int body = world_.object_body();
        const double ratio = mass / model->body_mass[body];
        model->body_mass[body] = mass;
        for (int k = 0; k < 3; ++k) {
            model->body_inertia[3 * body + k] *= ratio;
        }
        DataPointer scratch(mj_makeData(model));
        mj_setConst(model, scratch.get());
    }

private:
    /// The library's measurement (MujocoArms::read_contact_wrenches: each palm's MuJoCo contacts
    /// with the object in either geom order, mj_contactForce turned to {w} and to the palm's force
    /// on the object, the moments about the palm's contact site where the controller saw it; the
    /// step leaves the sites' poses as they were).
    void measure_contacts() noexcept
    {
        world_.arms().read_contact_wrenches(world_.model(), world_.data(), world_.object_body(), contacts_);
        for (std::size_t i = 0; i < measured_.size(); ++i) {
            measured_[i] = contacts_.world.col(static_cast<Eigen::Index>(i));
        }
    }

    SceneWorld& world_;
    coopdyn::MujocoContactWrenches<> contacts_;          ///< the palms' MuJoCo contacts in the last step
    std::vector<coopdyn::Vector6<double>> measured_;     ///< palms' wrenches on the object
    coopdyn::Vector6<double> acceleration_ = coopdyn::Vector6<double>::Zero();
    Eigen::Quaterniond orientation_ = Eigen::Quaterniond::Identity();
};

/// Runs the hold on `plant` (MujocoScenePlant, RigidScenePlant) of `world`, from its start (call
/// world.start() first; the controller's contact points are taken there). Allocation-free per tick
/// (the controller's Dynamic-size data is allocated here, once).
template <typename Plant>
HoldResult run_hold_on(const SceneWorld& world, Plant& plant, const HoldSettings& settings = {})
{
    const auto K = static_cast<std::size_t>(world.arms().arms());
    const coopdyn::ControllerModel<double> controller(world.controller_parameters(settings.controller));
    coopdyn::ControllerData<double> controller_data(controller);
    coopdyn::ControllerInput<double> input(controller);
    input.posture = world.posture();
    input.desired_pose = coopdyn::mujoco_object_pose(world.model(), world.data(), world.object_body());
    const coopdyn::Pose<double> start = input.desired_pose;

    const double period = plant.period();
    const double cutoff = settings.acceleration_cutoff;
    const double gain = cutoff > 0.0 ? 1.0 - std::exp(-2.0 * 3.141592653589793 * cutoff * period) : 1.0;
    coopdyn::Vector6<double> acceleration = coopdyn::Vector6<double>::Zero();

    HoldResult result;
    result.palms.assign(K, PalmHold{});
    for (PalmHold& palm : result.palms) {
        palm.min_contact_points = 1 << 30;
    }
    std::vector<Eigen::Vector3d> object_in_palm(K, Eigen::Vector3d::Zero());
    std::vector<coopdyn::Pose<double>> palms_seen(K);  // the contact frames where the controller saw them
    const auto measured = static_cast<long>(std::llround(settings.seconds / period));
    const auto settle = static_cast<long>(std::llround(settings.settle_seconds / period));
    double controller_seconds = 0.0;
    const auto wall_start = std::chrono::steady_clock::now();
    long tick = -settle;
    for (; tick < measured && !result.dropped; ++tick) {
        plant.begin_tick(input);
        acceleration += gain * (input.object_acceleration - acceleration);  // low-passed, as on a robot
        input.object_acceleration = acceleration;
        const auto tick_start = std::chrono::steady_clock::now();
        const auto& tau = coopdyn::controller_tick(controller, controller_data, input);
        controller_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - tick_start).count();
        for (std::size_t i = 0; i < K; ++i) {  // slip is measured in them
            palms_seen[i] = plant.contact_pose(static_cast<Eigen::Index>(i));
        }
        plant.end_tick(tau);
        if (tick < 0) {
            continue;
        }
        ++result.ticks;
        result.not_ok_ticks += controller_data.status != coopdyn::ControlStatus::ok ? 1 : 0;
        result.fallback_ticks += controller_data.fallback_used ? 1 : 0;
        result.max_torque = std::max(result.max_torque, tau.cwiseAbs().maxCoeff());
        const coopdyn::Pose<double>& object = input.object.pose;
        result.max_position_error = std::max(result.max_position_error, (object.position - start.position).norm());
        result.max_orientation_error =
            std::max(result.max_orientation_error, object.orientation.angularDistance(start.orientation));
        for (std::size_t i = 0; i < K; ++i) {
            const auto index = static_cast<Eigen::Index>(i);
            const Eigen::Vector3d in_palm =
                palms_seen[i].orientation.conjugate() * (object.position - palms_seen[i].position);
            if (tick == 0) {
                object_in_palm[i] = in_palm;
            }
            PalmHold& palm = result.palms[i];
            palm.max_slip = std::max(palm.max_slip, (in_palm - object_in_palm[i]).head<2>().norm());
            palm.mean_normal_force += plant.normal_force(index);
            palm.final_normal_force = plant.normal_force(index);
            palm.predicted_normal_force = controller_data.contact_frame_wrenches(2, index);
            palm.min_contact_points = std::min(palm.min_contact_points, plant.contact_points(index));
            result.max_slip = std::max(result.max_slip, palm.max_slip);
        }
        result.dropped = result.max_slip > settings.drop_slip;
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    const auto ticks_run = static_cast<double>(tick + settle);
    result.real_time_factor = wall > 0.0 ? ticks_run * period / wall : 0.0;
    result.tick_microseconds = ticks_run > 0.0 ? 1e6 * controller_seconds / ticks_run : 0.0;
    for (PalmHold& palm : result.palms) {
        palm.mean_normal_force /= static_cast<double>(std::max(result.ticks, 1L));
    }
    return result;
}

/// The hold in MuJoCo (MujocoScenePlant) from the world's current state.
inline HoldResult run_hold(SceneWorld& world, const HoldSettings& settings = {})
{
    MujocoScenePlant plant(world);
    return run_hold_on(world, plant, settings);
}

}  // namespace scenes
