// coopdyn._experiments.box_run: the dual-arm box experiment (Lin et al. section IV;
// docs/dual-arm-box.md) as the program dual_arm_box runs it, returning the log's columns and the
// run's summary (box_result.hpp) instead of writing files. The runs are the ones compiled in
// box_example_runs (box_runs.hpp: the LWR 4 pair's run_lwr4_world, a scene's run_scene_world), so
// this file needs none of the plants' headers. The GIL is released while the experiment runs.
#include "box_result.hpp"

#include "box/box_scenario_loader.hpp"
#include "scenes/scene.hpp"

#include <optional>
#include <string>

#ifndef COOPDYN_BOX_DIR
#error "COOPDYN_BOX_DIR: the shipped MJCF's and scenarios' folder, set by python/CMakeLists.txt"
#endif

namespace coopdyn::python::experiments {
namespace {

using namespace box_example;

/// dual_arm_box's run_lwr4 / run_scene for one scenario file and one plant, without the files.
py::tuple box_run(const std::string& file, const std::string& plant, std::optional<double> duration,
                  unsigned long long seed, std::optional<double> friction, bool minimum_squeeze,
                  std::size_t log_every)
{
    if (plant != "mujoco" && plant != "rigid") {
        throw py::value_error("plant: 'mujoco' or 'rigid', got '" + plant + "'");
    }
    BoxScenario scenario = load_box_scenario(file);
    if (duration) {
        scenario.duration = *duration;
    }
    if (friction) {
        scenario.controller.friction = *friction;
    }
    const bool rigid = plant == "rigid";
    if (scenario.scene) {
        const scenes::Scene scene = scenes::read_scene(*scenario.scene);
        std::optional<DynamicRun> run;
        {
            py::gil_scoped_release release;
            run.emplace(run_scene_world(scene, scenario, rigid, seed));
        }
        return box_result(*run, scenario, plant, log_every, std::nullopt);  // measured on the LWR 4 pair only
    }
    std::optional<Lwr4Run> run;
    {
        py::gil_scoped_release release;
        run.emplace(run_lwr4_world(std::string(COOPDYN_BOX_DIR) + "/dual_arm_box.xml", scenario, rigid, seed,
                                   minimum_squeeze));
    }
    return box_result(run->run, scenario, plant, log_every, run->minimum_squeeze);
}

}  // namespace

void bind_box(py::module_& module)
{
    module.attr("box_dir") = COOPDYN_BOX_DIR;
    module.def("box_run", &box_run, py::arg("file"), py::arg("plant"), py::arg("duration"), py::arg("seed"),
               py::arg("friction"), py::arg("minimum_squeeze"), py::arg("log_every"),
               "One dual-arm box scenario file on one plant, as dual_arm_box runs it: (log columns, summary). "
               "Use coopdyn.experiments.box.");
}

}  // namespace coopdyn::python::experiments
