// The dual-arm box's runs, compiled once (box_runs.cpp, the library box_example_runs) for the
// program dual_arm_box and the Python module's coopdyn.experiments.box (python/src/experiments/):
// explicit instantiation declarations of run_experiment_on on the four plants (without faults:
// the fault campaign instantiates its own, examples/faults) and of summarise at
// both sizes, so that the files that include this header call those instances instead of
// compiling them again (docs/python.md, "Compile time"). The plants are only declared here: a file
// that includes this header parses the plants' headers it uses itself, and no others (their
// inline member functions instantiate Eigen's templates when parsed). A file that includes this
// header links box_example_runs.
#pragma once

#include "box_experiment.hpp"
#include "box_report.hpp"

#include <coopdyn/dynamics/integrator.hpp>

#include <functional>
#include <optional>
#include <string>

namespace scenes {
class RigidScenePlant;
class MujocoScenePlant;
struct Scene;
}  // namespace scenes

namespace box_example {

class MujocoPlant;
class RigidGraspPlant;
template <typename ScenePlant> class SceneBoxPlant;

using ExperimentProgress = std::function<void(double)>;
using DynamicRun = ExperimentRunOf<Eigen::Dynamic, Eigen::Dynamic>;  // scene_box.hpp's SceneRun

extern template ExperimentRun run_experiment_on<palms, joints, MujocoPlant, NoFaults>(
    MujocoPlant&, const BoxScenario&, const ExperimentSetup&, unsigned long long, const ExperimentProgress&, NoFaults&&);
extern template ExperimentRun run_experiment_on<palms, joints, RigidGraspPlant, NoFaults>(
    RigidGraspPlant&, const BoxScenario&, const ExperimentSetup&, unsigned long long, const ExperimentProgress&, NoFaults&&);
extern template DynamicRun run_experiment_on<Eigen::Dynamic, Eigen::Dynamic, SceneBoxPlant<scenes::RigidScenePlant>, NoFaults>(
    SceneBoxPlant<scenes::RigidScenePlant>&, const BoxScenario&, const ExperimentSetup&, unsigned long long,
    const ExperimentProgress&, NoFaults&&);
extern template DynamicRun run_experiment_on<Eigen::Dynamic, Eigen::Dynamic, SceneBoxPlant<scenes::MujocoScenePlant>, NoFaults>(
    SceneBoxPlant<scenes::MujocoScenePlant>&, const BoxScenario&, const ExperimentSetup&, unsigned long long,
    const ExperimentProgress&, NoFaults&&);
extern template BoxSummary summarise<palms, joints>(const BoxScenario&, const std::string&, const ExperimentRun&);
extern template BoxSummary summarise<Eigen::Dynamic, Eigen::Dynamic>(const BoxScenario&, const std::string&,
                                                                     const DynamicRun&);

/// A run on the LWR 4 pair and, when asked, its minimum squeeze (measure_minimum_squeeze).
struct Lwr4Run {
    ExperimentRun run;
    std::optional<double> minimum_squeeze;
};

/// The LWR 4 pair's world loaded from `mjcf` (DualArmBoxModel), `scenario` on one plant from its
/// hold grasp (run_lwr4_experiment, as dual_arm_box runs it) and, on the MuJoCo plant when
/// `measure_squeeze`, the least squeeze that holds the box. For callers that need none of the
/// plants' headers (the Python module): compiled in box_runs.cpp.
Lwr4Run run_lwr4_world(const std::string& mjcf, const BoxScenario& scenario, bool rigid, unsigned long long seed,
                       bool measure_squeeze);
/// scene_box.hpp's run_scene_experiment, compiled in box_runs.cpp: the controller at fixed sizes
/// for the three-arm scene's (box_experiment.hpp, fixed_scene_palms), at Dynamic sizes otherwise;
/// the rigid plant integrated by `integrator`.
DynamicRun run_scene_world(const scenes::Scene& scene, const BoxScenario& scenario, bool rigid, unsigned long long seed,
                           const ExperimentProgress& progress = {},
                           coopdyn::Integrator integrator = coopdyn::Integrator::semi_implicit_euler);

}  // namespace box_example
