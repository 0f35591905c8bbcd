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

/// The LWR 4 pair's controller at its fixed sizes (scenes run at Eigen::Dynamic: scene_box.hpp).
using Controller = coopdyn::ControllerModel<double, palms, joints>;
using ControllerData = coopdyn::ControllerData<double, palms, joints>;
using ControllerInput = coopdyn::ControllerInput<double, palms, joints>;

/// The scenario's controller settings on parameters whose contact frames and joint count are set:
/// each contact's friction model, the impedance and posture gains, the QP's objective. One place
/// for the LWR 4 pair (controller_parameters) and every scene (scene_box.hpp).
inline void apply_controller_settings(const ControllerSettings& settings,
                                      coopdyn::ControllerParameters<double>& parameters)
{
    for (coopdyn::ContactPoint<double>& contact : parameters.contacts) {
        contact.friction.friction_coefficient = settings.friction;
        contact.friction.torsional_coefficient = settings.torsional_friction;
        contact.friction.patch_half_length_x = settings.patch_half_size;
        contact.friction.patch_half_length_y = settings.patch_half_size;
        contact.friction.minimum_normal_force = settings.minimum_normal_force;
    }
    parameters.stiffness.diagonal() << Eigen::Vector3d::Constant(settings.translational_stiffness),
        Eigen::Vector3d::Constant(settings.rotational_stiffness);
    parameters.damping.diagonal() << Eigen::Vector3d::Constant(settings.translational_damping),
        Eigen::Vector3d::Constant(settings.rotational_damping);
    parameters.posture_stiffness = Eigen::VectorXd::Constant(parameters.joints, settings.posture_stiffness);
    parameters.posture_damping = Eigen::VectorXd::Constant(parameters.joints, settings.posture_damping);
    parameters.objective = settings.objective;
}

/// The controller's parameters for a scenario on the LWR 4 pair: each palm's contact frame in the
/// box (z: the box's inward normal = the palm's outward normal), then apply_controller_settings.
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
        parameters.contacts.push_back(contact);
    }
    apply_controller_settings(settings, parameters);
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

/// Most palms (K) and joints (Q) a scene's run can log: the Dynamic-size runs (scene_box.hpp)
/// keep their per-palm and per-joint columns in fixed-capacity storage, so that logging a tick
/// allocates nothing, as with the LWR 4 pair's fixed sizes. The shipped scenes have K <= 3, Q <= 20.
constexpr int max_scene_palms = 4;
constexpr int max_scene_joints = 32;
/// The one scene size whose experiments run the controller at fixed sizes (box_runs.cpp,
/// run_scene_world): three arms (K = 3, Q = 20), whose Dynamic-size tick (14.5-17 us) held the rigid
/// plant's experiments under 50x real time; at fixed sizes it costs 10.7-11.4 us
/// (docs/performance.md, "Scenes of any arms"). Every other scene runs it at Dynamic sizes; another
/// size costs its own controller_tick and two experiment loops in box_runs.cpp (about 70 s of g++
/// -O3 CPU: docs/performance.md).
constexpr int fixed_scene_palms = 3;
constexpr int fixed_scene_joints = 20;
/// Palm slots of a run with K palms (K, or max_scene_palms for Eigen::Dynamic).
template <int K>
constexpr std::size_t palm_capacity = K == Eigen::Dynamic ? std::size_t{max_scene_palms} : std::size_t(K);
/// A joint vector of a run with Q joints: JointVector for the LWR 4 pair, bounded Dynamic for scenes.
template <int Q>
using JointVectorOf = Eigen::Matrix<double, Q, 1, 0, (Q == Eigen::Dynamic ? max_scene_joints : Q), 1>;
template <typename T, int K> using PalmArray = std::array<T, palm_capacity<K>>;

/// One tick of the log (docs/dual-arm-box.md, "The CSV columns"); slots [0, K) of the palm arrays.
template <int K, int Q> struct TickLogOf {
    double time = 0.0;
    Eigen::Vector3d box_position = Eigen::Vector3d::Zero();
    Eigen::Vector3d desired_position = Eigen::Vector3d::Zero();
    double orientation_error = 0.0;  ///< rad, box against desired
    Vector6d external_wrench = Vector6d::Zero();  ///< F_x, the controller's estimate
    Vector6d disturbance = Vector6d::Zero();      ///< what the person applied, [F; T] at the centre
    Eigen::Vector3d box_acceleration = Eigen::Vector3d::Zero();  ///< the plant's, in this tick's step
    PalmArray<Vector6d, K> predicted{};      ///< QP's contact wrench, contact frame [f; t]
    PalmArray<Vector6d, K> measured{};       ///< plant's, contact frame
    PalmArray<Vector6d, K> measured_world{}; ///< plant's, about the contact point, {w}
    /// Friction margins of the measured wrench under the true friction: force rows (N), moment rows (N m).
    PalmArray<coopdyn::FrictionMargins<double>, K> measured_margins{};
    double predicted_force_margin = 0.0;   ///< tightest force-row margin of the QP's wrenches, controller's friction (N)
    double predicted_moment_margin = 0.0;  ///< tightest moment-row margin of the QP's wrenches (N m)
    PalmArray<double, K> slip{};             ///< m, the box relative to each palm since the start
    coopdyn::ControlStatus status = coopdyn::ControlStatus::ok;
    bool qp_ran = false;  ///< the contact QP ran this tick (not after an invalid_input, singular or safe_hold tick)
    coopdyn::QpStatus qp_status = coopdyn::QpStatus::solved;
    int qp_iterations = 0;
    JointVectorOf<Q> motion_torque{};   ///< tau_u
    JointVectorOf<Q> squeeze_torque{};  ///< tau_c
    double torque_use = 0.0;  ///< max_j |tau_j| / limit_j of the torque sent (after saturation)
    double box_mass = 0.0;    ///< the plant's current box mass (kg)
};
using TickLog = TickLogOf<palms, joints>;

template <int K, int Q> struct ExperimentRunOf {
    std::vector<TickLogOf<K, Q>> log;
    bool dropped = false;         ///< the box left the palms (slip above drop_slip)
    double dropped_at = 0.0;
    double tick_seconds = 0.0;    ///< wall time of the controller ticks, total
    double wall_seconds = 0.0;    ///< wall time of the whole run
    double simulated_seconds = 0.0;  ///< simulated time of the whole run, the settle included
    /// The palms' names in the log's columns ("left", "right" on the LWR 4 pair; "palm1".. in a
    /// scene), one per palm: K at run time.
    std::vector<std::string> palm_names{"left", "right"};
    Eigen::Index joint_count = Q;  ///< Q at run time
    std::size_t palm_count() const noexcept { return palm_names.size(); }
};
using ExperimentRun = ExperimentRunOf<palms, joints>;

/// Slip above which a run counts as a drop and stops (m).
constexpr double drop_slip = 0.05;
/// How long the palms press into the box before t = 0 (s).
constexpr double settle_seconds = 0.2;

/// What a run needs besides the plant and the scenario: the controller's parameters (contact
/// frames and the scenario's settings), q_n, the hold pose the desired motion starts from, the
/// joints' torque limits and the palms' names.
struct ExperimentSetup {
    coopdyn::ControllerParameters<double> parameters;
    Eigen::VectorXd posture;
    coopdyn::Pose<double> hold{};
    Eigen::VectorXd torque_limit;
    std::vector<std::string> palm_names;
};

/// The controller's input from the plant's state: the arms' terms, the box's measured pose and
/// twist, and its acceleration for L(7), the plant's last one low-passed as on a robot (a
/// soft-contact simulation's raw acceleration is as spiky as a real accelerometer's).
template <typename Plant, typename Terms, typename Input>
void read_plant(const Plant& plant, const Terms& terms, double filter_gain, Vector6d& filtered_acceleration,
                Input& input)
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
    // The contacts' poses from the arms' forward kinematics, as the library's adapters fill them
    // (docs/control.md, "Faults"): the controller predicts the box from them during a dropout and
    // measures each palm's slip. They change no torque while the box is measured.
    for (std::size_t i = 0; i < terms.palm_position.size(); ++i) {
        const auto column = static_cast<Eigen::Index>(i);
        input.contact_positions.col(column) = terms.palm_position[i];
        input.contact_orientations.col(column) = Eigen::Quaterniond(terms.palm_rotation[i]).coeffs();
    }
    input.contact_poses_filled = true;
}

/// The experiment's fault hook (the fault campaign, docs/faults.md): corrupt_input after the plant
/// is read, corrupt_torque after the torque is saturated (noise on it, forces the model misses);
/// both also see the tick. This one changes nothing and compiles to nothing.
struct NoFaults {
    template <typename Input> void corrupt_input(long, double, Input&) noexcept {}
    template <typename Torque, typename Input, typename Data>
    void corrupt_torque(long, double, Torque&, const Input&, const Data&) noexcept
    {
    }
};

/// The controller's parameters with the joints' torque limits as its own when they are finite and
/// the parameters have none (the fault campaign's limit cells set their own): the controller clips
/// the torque it computes, so the tick's status says so on the tick it clips (torque_saturated,
/// docs/control.md, "Check data.status first"), and the plant-side clamp (saturate) then changes
/// nothing.
inline coopdyn::ControllerParameters<double> limited_parameters(const ExperimentSetup& setup)
{
    coopdyn::ControllerParameters<double> parameters = setup.parameters;
    if (parameters.torque_limits.size() == 0 && setup.torque_limit.size() > 0 && setup.torque_limit.allFinite()) {
        parameters.torque_limits = setup.torque_limit;
    }
    return parameters;
}

/// Clamps tau to the joints' torque limits; returns max_j |tau_j| / limit_j.
template <typename Torque, typename Limit> double saturate(Torque& tau, const Limit& limit) noexcept
{
    double use = 0.0;
    for (Eigen::Index j = 0; j < tau.size(); ++j) {
        tau(j) = std::clamp(tau(j), -limit(j), limit(j));
        use = std::max(use, std::abs(tau(j)) / limit(j));
    }
    return use;
}

/// The palms' frames ({w}) at one tick's start.
template <int K> struct PalmFramesOf {
    PalmArray<Eigen::Vector3d, K> position{};
    PalmArray<Eigen::Matrix3d, K> rotation{};
    template <typename Terms> void copy(const Terms& terms, std::size_t count) noexcept
    {
        for (std::size_t i = 0; i < count; ++i) {
            position[i] = terms.palm_position[i];
            rotation[i] = terms.palm_rotation[i];
        }
    }
};
using PalmFrames = PalmFramesOf<palms>;

/// Each palm's predicted and measured wrench (contact frame), the measured one's true friction
/// margin, and the slip: how far the box's centre moved in the palm's contact plane (the palm's
/// x-y; along the normal the soft contact's penetration changes with the squeeze) since
/// `box_in_palm` was taken.
template <typename Plant, typename Data, int K, int Q>
void log_palms(const Plant& plant, const PalmFramesOf<K>& palms_seen, const Data& data, const FrictionRows& friction,
               const PalmArray<Eigen::Vector3d, K>& box_in_palm, const Eigen::Vector3d& box_position,
               std::size_t count, TickLogOf<K, Q>& row)
{
    for (std::size_t i = 0; i < count; ++i) {
        const auto palm = static_cast<int>(i);
        row.predicted[i] = data.contact_frame_wrenches.col(palm);
        const Eigen::Matrix3d& rotation = palms_seen.rotation[i];
        const Vector6d& world = plant.measured_contact_wrench(palm);
        row.measured_world[i] = world;
        coopdyn::rotate_stack_back(rotation, world, row.measured[i]);  // [R^T f; R^T t], {w} to the palm frame
        row.measured_margins[i] = friction.margins(row.measured[i]);
        const Eigen::Vector3d now = rotation.transpose() * (box_position - palms_seen.position[i]);
        row.slip[i] = (now - box_in_palm[i]).template head<2>().norm();
    }
}

/// The tick's log row (the palms' columns are log_palms'): the box (as the plant measured it,
/// before any fault) against the desired motion, the controller's estimate, QP and torques, the
/// person's wrench and the plant's box.
template <int K, int Q, typename Plant, typename Data>
TickLogOf<K, Q> tick_log(const Plant& plant, const coopdyn::RigidBodyState<double>& box, const Desired& desired,
                         const Data& data, double t, const Vector6d& disturbance, double torque_use)
{
    TickLogOf<K, Q> row;
    row.time = t;
    row.box_position = box.pose.position;
    row.desired_position = desired.pose.position;
    row.orientation_error = coopdyn::quaternion_log(Eigen::Quaterniond(box.pose.orientation *
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

/// The box's mass at time t (the scenario's masses put on it), set on the plant when it changes.
template <typename Plant> void apply_added_mass(Plant& plant, const BoxScenario& scenario, double t)
{
    if (scenario.added_mass) {
        const double mass = scenario.box_mass + added_mass(*scenario.added_mass, t);
        if (mass != plant.box_mass()) {
            plant.set_box_mass(mass);
        }
    }
}

/// Runs `scenario` on `plant` from its current state with K palms and Q joints (the LWR 4 pair:
/// 2, 14; a scene: Eigen::Dynamic, Eigen::Dynamic), one plant step per 1 ms controller tick.
/// `progress(fraction)` is called every simulated tenth of a second. The palms first press into
/// the box for settle_seconds (not logged, no disturbance): in MuJoCo the start's palms touch the
/// box without force, and the soft contact takes a few ticks to build up the commanded squeeze.
///
/// The plant: begin_tick(); arm_terms() (inertia, bias, jacobian, jacobian_rate_qdot,
/// palm_position[i], palm_rotation[i]); joint_positions(), joint_velocities(), box_position(),
/// box_orientation(), box_twist(), box_acceleration(); end_tick(tau, wrench on the box's centre);
/// measured_contact_wrench(i); box_mass(), set_box_mass(m).
/// `faults` (NoFaults by default; docs/faults.md) corrupts each tick's input and torque.
/// `ControllerK`, `ControllerQ`: the controller's sizes, K and Q by default; a scene's run (K, Q
/// Dynamic) may run it at the scene's fixed sizes (box_runs.cpp, run_scene_world), the log staying
/// Dynamic.
template <int K, int Q, typename Plant, typename Faults = NoFaults, int ControllerK = K, int ControllerQ = Q>
ExperimentRunOf<K, Q> run_experiment_on(Plant& plant, const BoxScenario& scenario, const ExperimentSetup& setup,
                                        unsigned long long seed = 1, const std::function<void(double)>& progress = {},
                                        Faults&& faults = Faults{})
{
    const coopdyn::ControllerModel<double, ControllerK, ControllerQ> controller(limited_parameters(setup));
    coopdyn::ControllerData<double, ControllerK, ControllerQ> data(controller);
    coopdyn::ControllerInput<double, ControllerK, ControllerQ> input(controller);
    input.posture = setup.posture;
    const FrictionRows friction(true_friction(scenario.plant_friction, scenario.controller.patch_half_size));
    const Eigen::Matrix<double, Q, 1> limit = setup.torque_limit;
    Eigen::Matrix<double, Q, 1> tau = limit;  // sized once: the tick's assignment allocates nothing
    const double cutoff = scenario.controller.acceleration_cutoff;
    const double filter_gain = cutoff > 0.0 ? 1.0 - std::exp(-2.0 * lwr4_pi * cutoff * controller_period) : 0.0;
    Vector6d filtered_acceleration = Vector6d::Zero();
    Person person(scenario, seed, controller_period);
    PalmArray<Eigen::Vector3d, K> box_in_palm{};  // the box's centre in each palm's frame at t = 0
    PalmFramesOf<K> palms_seen;

    ExperimentRunOf<K, Q> run;
    run.palm_names = setup.palm_names;
    run.joint_count = setup.posture.size();
    const std::size_t count = run.palm_count();
    const auto ticks = static_cast<long>(std::llround(scenario.duration / controller_period));
    const auto settle_ticks = static_cast<long>(std::llround(settle_seconds / controller_period));
    // The log's rows are allocated and touched before the clock starts, as a real-time logger's
    // buffer is: the kernel's zeroing of fresh pages (1.4 kB a row at a scene's Dynamic sizes,
    // about 2 us a tick in the VM measured) is not the simulation's cost. Rows after a drop are
    // cut off below.
    run.log.resize(static_cast<std::size_t>(ticks));
    std::size_t logged = 0;
    const auto wall_start = std::chrono::steady_clock::now();
    for (long tick = -settle_ticks; tick < ticks && !run.dropped; ++tick) {
        const double t = static_cast<double>(tick) * controller_period;
        apply_added_mass(plant, scenario, t);
        plant.begin_tick();
        // The controller's input is read from the plant's terms directly; only the palm frames are
        // copied: the rigid plant re-evaluates its terms at the next state in end_tick, and the
        // log needs the palms where the controller saw them.
        const auto& terms = plant.arm_terms();
        palms_seen.copy(terms, count);
        read_plant(plant, terms, filter_gain, filtered_acceleration, input);
        const Desired desired = desired_motion(scenario, setup.hold, t);
        input.desired_pose = desired.pose;
        input.desired_twist = desired.twist;
        input.desired_acceleration = desired.acceleration;
        const coopdyn::RigidBodyState<double> box = input.object;  // the plant's, for the log and the person
        faults.corrupt_input(tick, t, input);

        const auto tick_start = std::chrono::steady_clock::now();
        tau = coopdyn::controller_tick(controller, data, input);
        run.tick_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - tick_start).count();
        const double torque_use = saturate(tau, limit);
        faults.corrupt_torque(tick, t, tau, input, data);
        const Vector6d disturbance =
            person.wrench(t, box.pose.position, box.twist.template head<3>());
        plant.end_tick(tau, disturbance);
        run.simulated_seconds += controller_period;
        if (tick < 0) {
            continue;
        }
        if (tick == 0) {
            for (std::size_t i = 0; i < count; ++i) {
                box_in_palm[i] =
                    palms_seen.rotation[i].transpose() * (box.pose.position - palms_seen.position[i]);
            }
        }

        TickLogOf<K, Q>& row = run.log[logged++];
        row = tick_log<K, Q>(plant, box, desired, data, t, disturbance, torque_use);
        log_palms(plant, palms_seen, data, friction, box_in_palm, box.pose.position, count, row);

        if (*std::max_element(row.slip.begin(), row.slip.begin() + static_cast<std::ptrdiff_t>(count)) > drop_slip) {
            run.dropped = true;
            run.dropped_at = t;
        }
        if (progress && tick % 100 == 0) {
            progress(static_cast<double>(tick) / static_cast<double>(ticks));
        }
    }
    run.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    run.log.resize(logged);
    return run;
}

/// Runs `scenario` on the LWR 4 pair's `plant` (MujocoPlant or RigidGraspPlant) from the grasp at
/// its current state (run_experiment_on at K = 2, Q = 14).
template <typename Plant>
ExperimentRun run_experiment(Plant& plant, const BoxScenario& scenario, const Grasp& grasp, unsigned long long seed = 1,
                             const std::function<void(double)>& progress = {})
{
    ExperimentSetup setup;
    setup.parameters = controller_parameters(scenario.controller, grasp);
    setup.posture = grasp.q;
    setup.hold = grasp.box;
    JointVector limit;
    limit << torque_limits(), torque_limits();
    setup.torque_limit = limit;
    setup.palm_names = {"left", "right"};
    return run_experiment_on<palms, joints>(plant, scenario, setup, seed, progress);
}

}  // namespace box_example
