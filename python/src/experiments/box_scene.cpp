// coopdyn.experiments.box on a scene's scenario (examples/box/scenarios/<scene>/; docs/scenes.md):
// scene_box.hpp's run_scene_experiment at dynamic sizes, as dual_arm_box's run_scene runs it. A
// translation unit of its own: the LWR 4 pair's fixed sizes (box_lwr4.cpp) compile in parallel.
#include "box_result.hpp"

#include "box/scene_box.hpp"

namespace coopdyn::python::experiments {

py::tuple run_scene_box(const box_example::BoxScenario& scenario, bool rigid, unsigned long long seed,
                        std::size_t log_every)
{
    const scenes::Scene scene = scenes::read_scene(*scenario.scene);
    std::optional<box_example::SceneRun> run;
    {
        py::gil_scoped_release release;
        run.emplace(box_example::run_scene_experiment(scene, scenario, rigid, seed));
    }
    // The minimum squeeze is measured on the LWR 4 pair only (as the program does).
    return box_result(*run, scenario, rigid ? "rigid" : "mujoco", log_every, std::nullopt);
}

}  // namespace coopdyn::python::experiments
