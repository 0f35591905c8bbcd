// The hold experiment on any scene, in MuJoCo (docs/scenes.md, "Holding"): the arms keep the object
// at its start pose with coopdyn's projected inverse-dynamics controller (dynamic sizes), the object
// held by friction alone. The loop is the dual-arm box's MuJoCo plant (examples/box/mujoco_plant.hpp,
// box_experiment.hpp) for any K and Q: each 1 ms tick
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

namespace detail {

/// Each palm's normal force on the object and its number of contact points in the last step.
inline void palm_normal_forces(const SceneWorld& world, std::vector<double>& force, std::vector<int>& points)
{
    std::fill(force.begin(), force.end(), 0.0);
    std::fill(points.begin(), points.end(), 0);
    const mjData* data = world.data();
    for (int c = 0; c < data->ncon; ++c) {
        const mjContact& contact = data->contact[c];
        for (Eigen::Index i = 0; i < world.arms().arms(); ++i) {
            const bool ours = (contact.geom1 == world.palm_geom(i) && contact.geom2 == world.object_geom(i)) ||
                              (contact.geom2 == world.palm_geom(i) && contact.geom1 == world.object_geom(i));
            if (ours) {
                mjtNum local[6];
                mj_contactForce(world.model(), data, c, local);  // local[0]: the normal force, >= 0
                force[static_cast<std::size_t>(i)] += local[0];
                ++points[static_cast<std::size_t>(i)];
            }
        }
    }
}

}  // namespace detail

/// Runs the hold on `world` from its start (call world.start() first). Allocation-free per tick
/// (the controller's Dynamic-size data is allocated here, once).
inline HoldResult run_hold(SceneWorld& world, const HoldSettings& settings = {})
{
    mjModel* model = world.model();
    mjData* data = world.data();
    const Arms& arms = world.arms();
    const auto K = static_cast<std::size_t>(arms.arms());
    const coopdyn::ControllerModel<double> controller(world.controller_parameters(settings.controller));
    coopdyn::ControllerData<double> controller_data(controller);
    coopdyn::ControllerInput<double> input(controller);
    input.posture = world.posture();
    input.desired_pose = coopdyn::mujoco_object_pose(model, data, world.object_body());
    const coopdyn::Pose<double> start = input.desired_pose;

    const double period = model->opt.timestep;
    const double cutoff = settings.acceleration_cutoff;
    const double gain = cutoff > 0.0 ? 1.0 - std::exp(-2.0 * 3.141592653589793 * cutoff * period) : 1.0;
    coopdyn::Vector6<double> acceleration = coopdyn::Vector6<double>::Zero();

    HoldResult result;
    result.palms.assign(K, PalmHold{});
    for (PalmHold& palm : result.palms) {
        palm.min_contact_points = 1 << 30;
    }
    std::vector<Eigen::Vector3d> object_in_palm(K, Eigen::Vector3d::Zero());
    std::vector<double> force(K, 0.0);
    std::vector<int> points(K, 0);
    const auto measured = static_cast<long>(std::llround(settings.seconds / period));
    const auto settle = static_cast<long>(std::llround(settings.settle_seconds / period));
    std::vector<coopdyn::Pose<double>> palms_seen(K);  // the contact frames where the controller saw them
    double controller_seconds = 0.0;
    const auto wall_start = std::chrono::steady_clock::now();
    long tick = -settle;
    for (; tick < measured && !result.dropped; ++tick) {
        mj_step1(model, data);
        arms.read(model, data, input);
        input.object = coopdyn::mujoco_object_state(model, data, world.object_body());
        input.object_acceleration = acceleration;
        const auto tick_start = std::chrono::steady_clock::now();
        const auto& tau = coopdyn::controller_tick(controller, controller_data, input);
        controller_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - tick_start).count();
        for (Eigen::Index j = 0; j < arms.joints(); ++j) {
            data->qfrc_applied[arms.dof_address(j)] = tau(j);
        }
        for (std::size_t i = 0; i < K; ++i) {  // slip is measured in them
            palms_seen[i] = arms.contact_pose(data, static_cast<Eigen::Index>(i));
        }
        mj_step2(model, data);
        // The free joint's qacc: linear in {w}, angular in the body frame.
        const mjtNum* qacc = data->qacc + world.object_dof();
        const Eigen::Matrix3d rotation = input.object.pose.orientation.toRotationMatrix();
        coopdyn::Vector6<double> raw;
        raw << qacc[0], qacc[1], qacc[2], rotation * Eigen::Vector3d(qacc[3], qacc[4], qacc[5]);
        acceleration += gain * (raw - acceleration);
        if (tick < 0) {
            continue;
        }
        detail::palm_normal_forces(world, force, points);
        ++result.ticks;
        result.not_ok_ticks += controller_data.status != coopdyn::ControlStatus::ok ? 1 : 0;
        result.fallback_ticks += controller_data.fallback_used ? 1 : 0;
        result.max_torque = std::max(result.max_torque, tau.cwiseAbs().maxCoeff());
        const coopdyn::Pose<double>& object = input.object.pose;
        result.max_position_error = std::max(result.max_position_error, (object.position - start.position).norm());
        result.max_orientation_error =
            std::max(result.max_orientation_error, object.orientation.angularDistance(start.orientation));
        for (std::size_t i = 0; i < K; ++i) {
            const Eigen::Vector3d in_palm =
                palms_seen[i].orientation.conjugate() * (object.position - palms_seen[i].position);
            if (tick == 0) {
                object_in_palm[i] = in_palm;
            }
            PalmHold& palm = result.palms[i];
            palm.max_slip = std::max(palm.max_slip, (in_palm - object_in_palm[i]).head<2>().norm());
            palm.mean_normal_force += force[i];
            palm.final_normal_force = force[i];
            palm.predicted_normal_force = controller_data.contact_frame_wrenches(2, static_cast<Eigen::Index>(i));
            palm.min_contact_points = std::min(palm.min_contact_points, points[i]);
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

}  // namespace scenes
