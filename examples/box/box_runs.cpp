// The instances and functions box_runs.hpp declares: the box experiment's runs and summaries,
// compiled once for dual_arm_box and the Python module (library box_example_runs).
#include "box_runs.hpp"

#include "lwr4_run.hpp"
#include "minimum_squeeze.hpp"
#include "scene_box.hpp"

namespace box_example {

template ExperimentRun run_experiment_on<palms, joints, MujocoPlant, NoFaults>(MujocoPlant&, const BoxScenario&,
                                                                     const ExperimentSetup&, unsigned long long,
                                                                     const ExperimentProgress&, NoFaults&&);
template ExperimentRun run_experiment_on<palms, joints, RigidGraspPlant, NoFaults>(RigidGraspPlant&, const BoxScenario&,
                                                                         const ExperimentSetup&, unsigned long long,
                                                                         const ExperimentProgress&, NoFaults&&);
template DynamicRun run_experiment_on<Eigen::Dynamic, Eigen::Dynamic, SceneBoxPlant<scenes::RigidScenePlant>, NoFaults>(
    SceneBoxPlant<scenes::RigidScenePlant>&, const BoxScenario&, const ExperimentSetup&, unsigned long long,
    const ExperimentProgress&, NoFaults&&);
template DynamicRun run_experiment_on<Eigen::Dynamic, Eigen::Dynamic, SceneBoxPlant<scenes::MujocoScenePlant>, NoFaults>(
    SceneBoxPlant<scenes::MujocoScenePlant>&, const BoxScenario&, const ExperimentSetup&, unsigned long long,
    const ExperimentProgress&, NoFaults&&);
template BoxSummary summarise<palms, joints>(const BoxScenario&, const std::string&, const ExperimentRun&);
template BoxSummary summarise<Eigen::Dynamic, Eigen::Dynamic>(const BoxScenario&, const std::string&,
                                                              const DynamicRun&);

Lwr4Run run_lwr4_world(const std::string& mjcf, const BoxScenario& scenario, bool rigid, unsigned long long seed,
                       bool measure_squeeze)
{
    const DualArmBoxModel world(mjcf);
    const Grasp grasp = hold_grasp(world);
    Lwr4Run result{run_lwr4_experiment(world, scenario, grasp, rigid, seed), std::nullopt};
    if (measure_squeeze && !rigid) {
        if (const auto measured = measure_minimum_squeeze(world, grasp, scenario)) {
            result.minimum_squeeze = measured->squeeze;
        }
    }
    return result;
}

DynamicRun run_scene_world(const scenes::Scene& scene, const BoxScenario& scenario, bool rigid, unsigned long long seed,
                           const ExperimentProgress& progress, coopdyn::Integrator integrator)
{
    if (fixed_size_scene(scene)) {
        return run_scene_experiment<fixed_scene_palms, fixed_scene_joints>(scene, scenario, rigid, seed, progress,
                                                                           integrator);
    }
    return run_scene_experiment(scene, scenario, rigid, seed, progress, integrator);
}

}  // namespace box_example
