// One run of the fault campaign (docs/faults.md): a cell (fault_cells.hpp) or a Monte Carlo push
// on one scene (examples/scenes) and one plant, in a world of its own, through the box
// experiments' loop (box_experiment.hpp) with the cell's FaultHook; summarised as a CellResult.
// Runs of different jobs share nothing but the scene's description, so they run in parallel.
#pragma once

#include "fault_cells.hpp"

#include "scene_box.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <random>
#include <string>

namespace fault_campaign {

/// One shipped scene and its hold scenario (the box experiments', with the scene set).
struct SceneCase {
    std::string name;
    scenes::Scene scene;
    box_example::BoxScenario hold;
};

/// One row of the table (or one Monte Carlo push).
struct CellResult {
    std::string scene;
    std::string plant;
    Cell cell;
    bool dropped = false;
    double dropped_at = std::numeric_limits<double>::quiet_NaN();  ///< s
    double largest_slip = 0.0;   ///< m, the box relative to the palms (the plant's truth)
    double force_margin = 0.0;   ///< N, smallest force-row margin of the measured wrenches, true friction
    double moment_margin = 0.0;  ///< N m, same for the moment rows
    CellStats stats;
    double push_force = 0.0;     ///< N (Monte Carlo)
    double push_hold = 0.0;      ///< s (Monte Carlo)
    double wall_seconds = 0.0;
    /// A failure (a drop) that the controller reported no later than it happened: a tick not ok,
    /// a slipping contact or a saturated joint at or before the drop.
    bool reported() const { return !dropped || (!std::isnan(stats.first_report) && stats.first_report <= dropped_at); }
};

/// The scene's world, loaded under `load_mutex` (MuJoCo's XML parser is not documented as
/// thread-safe; the runs themselves are independent), at its start.
inline std::unique_ptr<scenes::SceneWorld> start_world(const scenes::Scene& scene, std::mutex& load_mutex)
{
    std::unique_ptr<scenes::SceneWorld> world;
    {
        const std::lock_guard<std::mutex> lock(load_mutex);
        world = std::make_unique<scenes::SceneWorld>(scene);
    }
    world->start();
    return world;
}

/// Runs `scenario` on the scene with the library's torque limits `limits` and `hook`.
inline box_example::SceneRun run_with_hook(const scenes::Scene& scene, const box_example::BoxScenario& scenario,
                                           bool rigid, const Eigen::VectorXd& limits, FaultHook& hook,
                                           std::mutex& load_mutex)
{
    const std::unique_ptr<scenes::SceneWorld> world = start_world(scene, load_mutex);
    box_example::ExperimentSetup setup = box_example::make_scene_setup(*world, scenario);
    setup.parameters.torque_limits = limits;
    setup.parameters.faults.tick_period = box_example::controller_period;
    if (rigid) {
        // RK4, not the plant's default semi-implicit Euler: the cells drive the arms into their
        // torque limits and the welds to reactions of kilonewtons, where Euler's weld drift is no
        // longer negligible (45 mm in torque_limits_90pct on the LWR 4 pair; docs/scenes.md, "The
        // rigid plant"); RK4 keeps the weld to rounding.
        scenes::RigidScenePlant plant(*world, coopdyn::Integrator::runge_kutta_4);
        plant.set_object_mass(scenario.box_mass);
        box_example::SceneBoxPlant<scenes::RigidScenePlant> box_plant(*world, plant);
        return box_example::run_experiment_on<Eigen::Dynamic, Eigen::Dynamic>(box_plant, scenario, setup, 1, {}, hook);
    }
    box_example::set_palm_friction(*world, scenario.plant_friction);
    scenes::MujocoScenePlant plant(*world);
    plant.set_object_mass(scenario.box_mass);
    box_example::SceneBoxPlant<scenes::MujocoScenePlant> box_plant(*world, plant);
    return box_example::run_experiment_on<Eigen::Dynamic, Eigen::Dynamic>(box_plant, scenario, setup, 1, {}, hook);
}

/// The run's truth: dropped, the largest slip, the smallest true-friction margins.
inline void summarise_run(const box_example::SceneRun& run, CellResult& result)
{
    result.dropped = run.dropped;
    result.dropped_at = run.dropped ? run.dropped_at : std::numeric_limits<double>::quiet_NaN();
    result.force_margin = std::numeric_limits<double>::infinity();
    result.moment_margin = std::numeric_limits<double>::infinity();
    const std::size_t palms = run.palm_count();
    for (const auto& row : run.log) {
        for (std::size_t i = 0; i < palms; ++i) {
            result.largest_slip = std::max(result.largest_slip, row.slip[i]);
            result.force_margin = std::min(result.force_margin, row.measured_margins[i].force);
            result.moment_margin = std::min(result.moment_margin, row.measured_margins[i].moment);
        }
    }
}

/// The scene's robot limits (|tau_j|), infinite where it gives none.
inline Eigen::VectorXd robot_limits(const SceneCase& scene_case)
{
    const Eigen::Index joints = static_cast<Eigen::Index>(scene_case.scene.joint_names.size());
    return scene_case.scene.torque_limits ? *scene_case.scene.torque_limits
                                          : Eigen::VectorXd::Constant(joints, std::numeric_limits<double>::infinity());
}

/// The library's torque limits of a run: the robot's (so that the controller reports the
/// saturation the robot's clamp would do silently; none where the scene has none), or for the
/// binding cell `value` times the peak |tau_j| of an undisturbed hold of `duration`.
inline Eigen::VectorXd library_limits(const SceneCase& scene_case, const Cell& cell, bool rigid, double duration,
                                      std::mutex& load_mutex)
{
    const Eigen::VectorXd robot = robot_limits(scene_case);
    if (cell.kind != FaultKind::torque_limits) {
        return robot.allFinite() ? robot : Eigen::VectorXd();
    }
    box_example::BoxScenario scenario = scene_case.hold;
    const Cell nominal{"nominal", "none", FaultKind::none, 0.0, true};
    apply_cell(nominal, duration, scene_case.scene.contact_sites.size(), scenario);
    FaultHook hook(nominal, duration, robot, 1);
    run_with_hook(scene_case.scene, scenario, rigid, Eigen::VectorXd(), hook, load_mutex);
    return (cell.value * hook.stats().peak_torque).cwiseMax(1e-3);
}

/// One cell on one scene and plant.
inline CellResult run_cell(const SceneCase& scene_case, const Cell& cell, bool rigid, double duration,
                           unsigned long long seed, std::mutex& load_mutex)
{
    const auto wall_start = std::chrono::steady_clock::now();
    CellResult result;
    result.scene = scene_case.name;
    result.plant = rigid ? "rigid" : "mujoco";
    result.cell = cell;
    box_example::BoxScenario scenario = scene_case.hold;
    apply_cell(cell, duration, scene_case.scene.contact_sites.size(), scenario);
    if (scenario.push) {
        result.push_force = scenario.push->force;
    }
    const Eigen::VectorXd limits = library_limits(scene_case, cell, rigid, duration, load_mutex);
    FaultHook hook(cell, duration, robot_limits(scene_case), seed);
    summarise_run(run_with_hook(scene_case.scene, scenario, rigid, limits, hook, load_mutex), result);
    result.stats = hook.stats();
    result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    return result;
}

/// The Monte Carlo's run length (s) and its pushes' start and ramp (s).
inline constexpr double push_run_seconds = 1.2;
inline constexpr double push_start = 0.2;
inline constexpr double push_ramp = 0.1;

/// Monte Carlo push `index` on the scene (MuJoCo): direction uniform on the sphere, magnitude
/// uniform up to friction_load (the load the controller's friction model holds at f_min), held
/// 0.1 to 0.6 s after a 0.1 s ramp, from push_start; seeded by (seed, index).
inline CellResult run_push(const SceneCase& scene_case, std::size_t index, unsigned long long seed,
                           std::mutex& load_mutex)
{
    std::mt19937_64 generator(seed * 1000003ULL + index);
    std::normal_distribution<double> normal(0.0, 1.0);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    Eigen::Vector3d direction(normal(generator), normal(generator), normal(generator));
    direction.normalize();
    box_example::BoxScenario scenario = scene_case.hold;
    const std::size_t palms = scene_case.scene.contact_sites.size();
    Cell cell{"push_" + std::to_string(index), "monte_carlo", FaultKind::random_push, 0.0, true};
    apply_cell(cell, push_run_seconds, palms, scenario);
    box_example::Push push;
    push.start = push_start;
    push.force = uniform(generator) * friction_load(scenario, palms);
    push.ramp = push_ramp;
    push.hold = 0.1 + 0.5 * uniform(generator);
    push.period = 2.0 * push_run_seconds;
    push.repeats = 1;
    push.direction = direction;
    scenario.push = push;
    const auto wall_start = std::chrono::steady_clock::now();
    CellResult result;
    result.scene = scene_case.name;
    result.plant = "mujoco";
    result.cell = cell;
    result.push_force = push.force;
    result.push_hold = push.hold;
    const Eigen::VectorXd robot = robot_limits(scene_case);
    FaultHook hook(cell, push_run_seconds, robot, seed);
    summarise_run(run_with_hook(scene_case.scene, scenario, false, robot.allFinite() ? robot : Eigen::VectorXd(), hook,
                                load_mutex),
                  result);
    result.stats = hook.stats();
    result.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    return result;
}

}  // namespace fault_campaign
