// A scenario on the LWR 4 pair (dual_arm_box.xml, no scene) on one plant: the MuJoCo plant
// (friction only holds the box) or the exact rigid-grasp plant, from the MJCF's hold keyframe
// (docs/dual-arm-box.md). One place for the program (dual_arm_box.cpp) and the Python module's
// coopdyn.experiments.box (python/src/experiments/); the scenes' counterpart is
// scene_box.hpp's run_scene_experiment.
#pragma once

#include "box_experiment.hpp"
#include "mujoco_plant.hpp"
#include "mujoco_rigid_plant.hpp"

#include <functional>

namespace box_example {

/// Runs `scenario` on `world`'s LWR 4 pair on the MuJoCo plant, or the rigid plant when `rigid`,
/// holding `grasp` (hold_grasp(world)).
inline ExperimentRun run_lwr4_experiment(const DualArmBoxModel& world, const BoxScenario& scenario, const Grasp& grasp,
                                         bool rigid, unsigned long long seed = 1,
                                         const std::function<void(double)>& progress = {})
{
    if (!rigid) {
        MujocoPlant plant(world, scenario.plant_friction);
        plant.set_box_mass(scenario.box_mass);
        return run_experiment(plant, scenario, grasp, seed, progress);
    }
    const DataPointer start = world.make_data_at_hold();
    RigidGraspPlant plant = make_rigid_plant(world, *start, box_inertia(world, scenario.box_mass));
    return run_experiment(plant, scenario, grasp, seed, progress);
}

}  // namespace box_example
