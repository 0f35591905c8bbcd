// One dual-arm box experiment (docs/dual-arm-box.md): coopdyn's projected inverse-dynamics
// controller (Lin et al.) drives two 7-joint arms squeezing a box, on the MuJoCo plant or the
// rigid-grasp plant, while a person pushes, loads or grabs the box. Every tick is logged.
//
// The controller gets M, h, J, Jdot qdot of the arms alone, the box's measured pose, twist and
// (one tick late) acceleration, and the desired pose; it knows neither the box's mass nor the
// person's force (it estimates both as F_x, L(7)) and uses its own, conservative friction model.
#pragma once

#include "box_model.hpp"
#include "box_person.hpp"
#include "box_scenario.hpp"
#include "lwr4.hpp"

#include <coopdyn/control.hpp>
#include <coopdyn/spatial/quaternion.hpp>
#include <coopdyn/spatial/spatial_vector.hpp>

#include <algorithm>
#include <chrono>
#include <array>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace box_example {

using Controller = coopdyn::ControllerModel<double, palms, joints>;
using ControllerData = coopdyn::ControllerData<double, palms, joints>;
using ControllerInput = coopdyn::ControllerInput<double, palms, joints>;

/// The controller's parameters for a scenario: each palm's contact frame in the box (z: the box's
/// inward normal = the palm's outward normal), its friction model, the impedance and posture gains.
inline coopdyn::ControllerParameters<double> controller_parameters(const ControllerSettings& settings,
                                                                   const Grasp& grasp)
{
    coopdyn::ControllerParameters<double> parameters;
    parameters.joints = joints;
    const Eigen::Matrix3d box_rotation = grasp.box.orientation.toRotationMatrix();
    for (std::size_t i = 0; i < palms; ++i) {
        coopdyn::ContactPoint<double> contact;
        contact.frame.position = box_rotation.transpose() * (grasp.palm_position[i] - grasp.box.position);
        contact.frame.orientation = Eigen::Quaterniond(box_rotation.transpose() * grasp.palm_rotation[i]).normalized();
        contact.friction.friction_coefficient = settings.friction;
        contact.friction.torsional_coefficient = settings.torsional_friction;
        contact.friction.patch_half_length_x = settings.patch_half_size;
        contact.friction.patch_half_length_y = settings.patch_half_size;
        contact.friction.minimum_normal_force = settings.minimum_normal_force;
        parameters.contacts.push_back(contact);
    }
    parameters.stiffness.diagonal() << Eigen::Vector3d::Constant(settings.translational_stiffness),
        Eigen::Vector3d::Constant(settings.rotational_stiffness);
    parameters.damping.diagonal() << Eigen::Vector3d::Constant(settings.translational_damping),
        Eigen::Vector3d::Constant(settings.rotational_damping);
    parameters.posture_stiffness = Eigen::VectorXd::Constant(joints, settings.posture_stiffness);
    parameters.posture_damping = Eigen::VectorXd::Constant(joints, settings.posture_damping);
    parameters.objective = settings.objective;
    return parameters;
}

/// The palms' true friction as a coopdyn friction model, for the margin of the measured wrenches:
/// the plant's coefficients, the palm's patch, no minimum force, a 64-edge pyramid (within 0.12 %
/// of the cone).
inline coopdyn::ContactFriction<double> true_friction(const PlantFriction& plant, double patch_half_size)
{
    coopdyn::ContactFriction<double> friction;
    friction.friction_coefficient = plant.sliding;
    friction.torsional_coefficient = plant.torsional;
    friction.patch_half_length_x = patch_half_size;
    friction.patch_half_length_y = patch_half_size;
    friction.minimum_normal_force = 0.0;
    friction.pyramid_edges = coopdyn::max_pyramid_edges;
    return friction;
}

/// A friction model's constraint rows, built once for the margins of many wrenches (the true
/// friction's 64-facet pyramid would cost 128 sines and cosines per margin otherwise), and scaled
/// once to unit rows: coopdyn::friction_margin's min_k (b_k - a_k^T w) / |a_k| is then
/// min_k (b_k / |a_k| - (a_k / |a_k|)^T w), without its 71 square roots and divisions per call
/// (twice a tick). The same value up to rounding (a few ulps of each term; the test
/// UnitRowsGiveTheLibrarysMargin in test_box_plants.cpp compares the two).
struct FrictionRows {
    static constexpr int most = coopdyn::friction_rows(coopdyn::max_pyramid_edges);
    Eigen::Matrix<double, Eigen::Dynamic, 6, 0, most, 6> unit_rows;  ///< a_k / |a_k|
    Eigen::Matrix<double, Eigen::Dynamic, 1, 0, most, 1> scaled_bounds;  ///< b_k / |a_k|

    explicit FrictionRows(const coopdyn::ContactFriction<double>& friction)
        : unit_rows(coopdyn::friction_rows(friction.pyramid_edges), 6),
          scaled_bounds(coopdyn::friction_rows(friction.pyramid_edges))
    {
        coopdyn::contact_frame_friction_rows(friction, unit_rows, scaled_bounds);
        for (Eigen::Index k = 0; k < unit_rows.rows(); ++k) {
            const double norm = unit_rows.row(k).norm();
            unit_rows.row(k) /= norm;
            scaled_bounds(k) /= norm;
        }
    }
    /// coopdyn::friction_margin of a contact-frame wrench (to rounding).
    double margin(const Vector6d& wrench) const noexcept { return (scaled_bounds - unit_rows * wrench).minCoeff(); }
    /// coopdyn::friction_margins: the force rows' (unilateral, pyramid: N) and the moment rows'
    /// (torsion, centre of pressure: N m) margins apart; the moment rows are the last
    /// coopdyn::friction_moment_rows (friction.hpp's row order).
    coopdyn::FrictionMargins<double> margins(const Vector6d& wrench) const noexcept
    {
        const Eigen::Index moment_rows = coopdyn::friction_moment_rows;
        const Eigen::Index force_rows = unit_rows.rows() - moment_rows;
        return {(scaled_bounds.head(force_rows) - unit_rows.topRows(force_rows) * wrench).minCoeff(),
                (scaled_bounds.tail(moment_rows) - unit_rows.bottomRows(moment_rows) * wrench).minCoeff()};
    }
};

/// One tick of the log (docs/dual-arm-box.md, "The CSV columns").
struct TickLog {
    double time = 0.0;
    Eigen::Vector3d box_position = Eigen::Vector3d::Zero();
    Eigen::Vector3d desired_position = Eigen::Vector3d::Zero();
    double orientation_error = 0.0;  ///< rad, box against desired
    Vector6d external_wrench = Vector6d::Zero();  ///< F_x, the controller's estimate
    Vector6d disturbance = Vector6d::Zero();      ///< what the person applied, [F; T] at the centre
    Eigen::Vector3d box_acceleration = Eigen::Vector3d::Zero();  ///< the plant's, in this tick's step
    std::array<Vector6d, palms> predicted{};      ///< QP's contact wrench, contact frame [f; t]
    std::array<Vector6d, palms> measured{};       ///< plant's, contact frame
    std::array<Vector6d, palms> measured_world{}; ///< plant's, about the contact point, {w}
    /// Friction margins of the measured wrench under the true friction: force rows (N), moment rows (N m).
    std::array<coopdyn::FrictionMargins<double>, palms> measured_margins{};
    double predicted_force_margin = 0.0;   ///< tightest force-row margin of the QP's wrenches, controller's friction (N)
    double predicted_moment_margin = 0.0;  ///< tightest moment-row margin of the QP's wrenches (N m)
    std::array<double, palms> slip{};             ///< m, the box relative to each palm since the start
    coopdyn::ControlStatus status = coopdyn::ControlStatus::ok;
    bool qp_ran = false;  ///< the contact QP ran this tick (not after an invalid_input or singular tick)
    coopdyn::QpStatus qp_status = coopdyn::QpStatus::solved;
    int qp_iterations = 0;
    JointVector motion_torque = JointVector::Zero();   ///< tau_u
    JointVector squeeze_torque = JointVector::Zero();  ///< tau_c
    double torque_use = 0.0;  ///< max_j |tau_j| / limit_j of the torque sent (after saturation)
    double box_mass = 0.0;    ///< the plant's current box mass (kg)
};

struct ExperimentRun {
    std::vector<TickLog> log;
    bool dropped = false;         ///< the box left the palms (slip above drop_slip)
    double dropped_at = 0.0;
    double tick_seconds = 0.0;    ///< wall time of the controller ticks, total
    double wall_seconds = 0.0;    ///< wall time of the whole run
};

/// Slip above which a run counts as a drop and stops (m).
constexpr double drop_slip = 0.05;
/// How long the palms press into the box before t = 0 (s).
constexpr double settle_seconds = 0.2;

/// The controller's input from the plant's state: the arms' terms, the box's measured pose and
/// twist, and its acceleration for L(7), the plant's last one low-passed as on a robot (a
/// soft-contact simulation's raw acceleration is as spiky as a real accelerometer's).
template <typename Plant>
void read_plant(const Plant& plant, const ArmTerms& terms, double filter_gain, Vector6d& filtered_acceleration,
                ControllerInput& input)
{
    input.inertia = terms.inertia;
    input.bias = terms.bias;
    input.jacobian = terms.jacobian;
    input.jacobian_rate_qdot = terms.jacobian_rate_qdot;
    input.positions = plant.joint_positions();
    input.velocities = plant.joint_velocities();
    input.object.pose.position = plant.box_position();
    input.object.pose.orientation = plant.box_orientation();
    input.object.twist = plant.box_twist();
    filtered_acceleration += filter_gain * (plant.box_acceleration() - filtered_acceleration);
    input.object_acceleration = filtered_acceleration;
}

/// Clamps tau to the joints' torque limits; returns max_j |tau_j| / limit_j.
inline double saturate(JointVector& tau, const JointVector& limit) noexcept
{
    double use = 0.0;
    for (int j = 0; j < joints; ++j) {
        tau(j) = std::clamp(tau(j), -limit(j), limit(j));
        use = std::max(use, std::abs(tau(j)) / limit(j));
    }
    return use;
}

/// The palms' frames ({w}) at one tick's start.
struct PalmFrames {
    std::array<Eigen::Vector3d, palms> position{};
    std::array<Eigen::Matrix3d, palms> rotation{};
};

/// Each palm's predicted and measured wrench (contact frame), the measured one's true friction
/// margin, and the slip: how far the box's centre moved in the palm's contact plane (the palm's
/// x-y; along the normal the soft contact's penetration changes with the squeeze) since
/// `box_in_palm` was taken.
template <typename Plant>
void log_palms(const Plant& plant, const PalmFrames& palms_seen, const ControllerData& data,
               const FrictionRows& friction, const std::array<Eigen::Vector3d, palms>& box_in_palm,
               const Eigen::Vector3d& box_position, TickLog& row)
{
    for (std::size_t i = 0; i < palms; ++i) {
        const auto palm = static_cast<int>(i);
        row.predicted[i] = data.contact_frame_wrenches.col(palm);
        const Eigen::Matrix3d& rotation = palms_seen.rotation[i];
        const Vector6d& world = plant.measured_contact_wrench(palm);
        row.measured_world[i] = world;
        coopdyn::rotate_stack_back(rotation, world, row.measured[i]);  // [R^T f; R^T t], {w} to the palm frame
        row.measured_margins[i] = friction.margins(row.measured[i]);
        const Eigen::Vector3d now = rotation.transpose() * (box_position - palms_seen.position[i]);
        row.slip[i] = (now - box_in_palm[i]).head<2>().norm();
    }
}

/// The tick's log row (the palms' columns are log_palms'): the box against the desired motion,
/// the controller's estimate, QP and torques, the person's wrench and the plant's box.
template <typename Plant>
TickLog tick_log(const Plant& plant, const ControllerInput& input, const Desired& desired, const ControllerData& data,
                 double t, const Vector6d& disturbance, double torque_use)
{
    TickLog row;
    row.time = t;
    row.box_position = input.object.pose.position;
    row.desired_position = desired.pose.position;
    row.orientation_error = coopdyn::quaternion_log(Eigen::Quaterniond(input.object.pose.orientation *
                                                                       desired.pose.orientation.conjugate()))
                                .norm();
    row.external_wrench = data.external_wrench;
    row.disturbance = disturbance;
    row.box_acceleration = plant.box_acceleration().template head<3>();
    row.predicted_force_margin = data.tightest_force_margin;
    row.predicted_moment_margin = data.tightest_moment_margin;
    row.status = data.status;
    row.qp_ran = data.qp_ran;
    row.qp_status = data.qp_status;
    row.qp_iterations = data.qp_iterations;
    row.motion_torque = data.motion_torque;
    row.squeeze_torque = data.squeeze_torque;
    row.torque_use = torque_use;
    row.box_mass = plant.box_mass();
    return row;
}

/// Runs `scenario` on `plant` (MujocoPlant or RigidGraspPlant) from the grasp at its current
/// state, one plant step per 1 ms controller tick. `progress(fraction)` is called every simulated
/// tenth of a second. The palms first press into the box for settle_seconds (not logged, no
/// disturbance): in MuJoCo the keyframe's palms touch the box without force, and the soft contact
/// takes a few ticks to build up the commanded squeeze.
template <typename Plant>
ExperimentRun run_experiment(Plant& plant, const BoxScenario& scenario, const Grasp& grasp, unsigned long long seed = 1,
                             const std::function<void(double)>& progress = {})
{
    const Controller controller(controller_parameters(scenario.controller, grasp));
    ControllerData data(controller);
    ControllerInput input(controller);
    input.posture = grasp.q;
    const FrictionRows friction(true_friction(scenario.plant_friction, scenario.controller.patch_half_size));
    JointVector limit;
    limit << torque_limits(), torque_limits();
    const double cutoff = scenario.controller.acceleration_cutoff;
    const double filter_gain = cutoff > 0.0 ? 1.0 - std::exp(-2.0 * lwr4_pi * cutoff * controller_period) : 0.0;
    Vector6d filtered_acceleration = Vector6d::Zero();
    Person person(scenario, seed, controller_period);
    std::array<Eigen::Vector3d, palms> box_in_palm{};  // the box's centre in each palm's frame at t = 0

    ExperimentRun run;
    const auto ticks = static_cast<long>(std::llround(scenario.duration / controller_period));
    const auto settle_ticks = static_cast<long>(std::llround(settle_seconds / controller_period));
    run.log.reserve(static_cast<std::size_t>(ticks));
    const auto wall_start = std::chrono::steady_clock::now();
    for (long tick = -settle_ticks; tick < ticks && !run.dropped; ++tick) {
        const double t = static_cast<double>(tick) * controller_period;
        if (scenario.added_mass) {
            const double mass = scenario.box_mass + added_mass(*scenario.added_mass, t);
            if (mass != plant.box_mass()) {
                plant.set_box_mass(mass);
            }
        }
        plant.begin_tick();
        // The controller's input is read from the plant's terms directly; only the palm frames are
        // copied: the rigid plant re-evaluates its terms at the next state in end_tick, and the
        // log needs the palms where the controller saw them.
        const ArmTerms& terms = plant.arm_terms();
        const PalmFrames palms_seen{terms.palm_position, terms.palm_rotation};
        read_plant(plant, terms, filter_gain, filtered_acceleration, input);
        const Desired desired = desired_motion(scenario, grasp.box, t);
        input.desired_pose = desired.pose;
        input.desired_twist = desired.twist;
        input.desired_acceleration = desired.acceleration;

        const auto tick_start = std::chrono::steady_clock::now();
        JointVector tau = coopdyn::controller_tick(controller, data, input);
        run.tick_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - tick_start).count();
        const double torque_use = saturate(tau, limit);
        const Vector6d disturbance =
            person.wrench(t, input.object.pose.position, input.object.twist.template head<3>());
        plant.end_tick(tau, disturbance);
        if (tick < 0) {
            continue;
        }
        if (tick == 0) {
            for (std::size_t i = 0; i < palms; ++i) {
                box_in_palm[i] =
                    palms_seen.rotation[i].transpose() * (input.object.pose.position - palms_seen.position[i]);
            }
        }

        TickLog row = tick_log(plant, input, desired, data, t, disturbance, torque_use);
        log_palms(plant, palms_seen, data, friction, box_in_palm, input.object.pose.position, row);
        run.log.push_back(row);

        if (std::max(row.slip[0], row.slip[1]) > drop_slip) {
            run.dropped = true;
            run.dropped_at = t;
        }
        if (progress && tick % 100 == 0) {
            progress(static_cast<double>(tick) / static_cast<double>(ticks));
        }
    }
    run.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    return run;
}

}  // namespace box_example
