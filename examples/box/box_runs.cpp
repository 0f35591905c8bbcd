// The instances box_runs.hpp declares: the box experiment's runs and summaries, compiled once for
// dual_arm_box and the Python module (library box_example_runs).
#include "box_runs.hpp"

#include "lwr4_run.hpp"
#include "scene_box.hpp"

namespace box_example {

template ExperimentRun run_experiment_on<palms, joints, MujocoPlant>(MujocoPlant&, const BoxScenario&,
                                                                     const ExperimentSetup&, unsigned long long,
                                                                     const ExperimentProgress&);
template ExperimentRun run_experiment_on<palms, joints, RigidGraspPlant>(RigidGraspPlant&, const BoxScenario&,
                                                                         const ExperimentSetup&, unsigned long long,
                                                                         const ExperimentProgress&);
template DynamicRun run_experiment_on<Eigen::Dynamic, Eigen::Dynamic, SceneBoxPlant<scenes::RigidScenePlant>>(
    SceneBoxPlant<scenes::RigidScenePlant>&, const BoxScenario&, const ExperimentSetup&, unsigned long long,
    const ExperimentProgress&);
template DynamicRun run_experiment_on<Eigen::Dynamic, Eigen::Dynamic, SceneBoxPlant<scenes::MujocoScenePlant>>(
    SceneBoxPlant<scenes::MujocoScenePlant>&, const BoxScenario&, const ExperimentSetup&, unsigned long long,
    const ExperimentProgress&);
template BoxSummary summarise<palms, joints>(const BoxScenario&, const std::string&, const ExperimentRun&);
template BoxSummary summarise<Eigen::Dynamic, Eigen::Dynamic>(const BoxScenario&, const std::string&,
                                                              const DynamicRun&);

}  // namespace box_example
