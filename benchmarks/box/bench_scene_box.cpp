// The box experiments on the shipped scenes of any arms (docs/dual-arm-box.md, "Scenes";
// docs/performance.md, "Scenes of any arms"): the four shipped scenarios of the UR5e + Panda and of
// three arms (examples/box/scenarios/<scene>/), each for its full duration and the 0.2 s settle,
// on each plant, through the program's own path (box_runs.cpp's run_scene_world, compiled into
// this benchmark with the benchmark's flags: the three-arm controller at its fixed sizes, the rigid
// plant on its own recursion and semi-implicit Euler). One run per benchmark; counters:
// real_time_factor (the run's simulated time over its loop's wall time, the table's RTF column:
// the settle counted, the log in memory) and us_per_tick. A run that drops the box is an error.
#include "box_runs.hpp"
#include "box_scenario_loader.hpp"

#include "../scenes/scene.hpp"

#include <benchmark/benchmark.h>

#include <string>

namespace {

using namespace box_example;

void BM_SceneExperiment(benchmark::State& state, const std::string& scene, const std::string& experiment, bool rigid)
{
    const BoxScenario scenario =
        load_box_scenario(std::string(COOPDYN_BOX_SCENARIOS) + "/" + scene + "/" + experiment + ".json");
    if (!scenario.scene) {
        state.SkipWithError("the scenario names no scene");
        return;
    }
    const scenes::Scene arms = scenes::read_scene(*scenario.scene);
    double simulated = 0.0, wall = 0.0;
    for (auto _ : state) {
        const DynamicRun run = run_scene_world(arms, scenario, rigid, 1);
        if (run.dropped) {
            state.SkipWithError("the box was dropped");
            break;
        }
        simulated += run.simulated_seconds;
        wall += run.wall_seconds;
        benchmark::DoNotOptimize(run.log.data());
    }
    state.counters["real_time_factor"] = wall > 0.0 ? simulated / wall : 0.0;
    state.counters["us_per_tick"] = simulated > 0.0 ? 1e6 * wall / (simulated / 0.001) : 0.0;
}

int register_benchmarks()
{
    for (const char* scene : {"ur5e_panda", "three_arms"}) {
        for (const char* experiment : {"hold", "push", "add_mass", "circle"}) {
            for (const bool rigid : {false, true}) {
                const std::string name =
                    std::string("SceneExperiment/") + scene + "/" + experiment + (rigid ? "/rigid" : "/mujoco");
                benchmark::RegisterBenchmark(name.c_str(), BM_SceneExperiment, std::string(scene), std::string(experiment),
                                             rigid)
                    ->Unit(benchmark::kSecond)
                    ->Iterations(1);
            }
        }
    }
    return 0;
}
[[maybe_unused]] const int registered = register_benchmarks();

}  // namespace
