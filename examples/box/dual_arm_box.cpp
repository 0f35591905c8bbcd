// dual_arm_box: the second paper's experiments (Lin et al., section IV, Figs. 5-8) in simulation.
// Two 7-joint arms squeeze a box with coopdyn's projected inverse-dynamics controller while a
// person pushes it down, loads it with masses or grabs it on a circular path; on the MuJoCo plant
// (friction only holds the box) or the exact rigid-grasp plant. Prints a table next to the paper's
// numbers and writes CSV logs, gnuplot scripts and PNG plots. docs/dual-arm-box.md.
//
// Relative paths (--scenario, --output) are taken from the working directory; the shipped MJCF and
// scenarios through the path compiled in (COOPDYN_BOX_DIR). Exit codes (examples/common/cli.hpp):
// 0 success, 1 run-time failure (the box dropped, gnuplot), 2 bad command line, 3 invalid
// scenario file, 4 a file that cannot be read or written.
#include "box_report.hpp"
#include "box_runs.hpp"  // the runs, compiled once (box_example_runs)
#include "box_scenario_loader.hpp"
#include "lwr4_run.hpp"
#include "minimum_squeeze.hpp"
#include "../scenes/scene.hpp"

#include "../common/cli.hpp"
#include "../common/files.hpp"
#include "../common/output_names.hpp"
#include "../common/plotting.hpp"
#include "../common/progress.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#ifndef COOPDYN_BOX_DIR
#error "COOPDYN_BOX_DIR: the shipped MJCF's and scenarios' folder, set by examples/box/CMakeLists.txt"
#endif

namespace {

using namespace box_example;
namespace fs = std::filesystem;
using example_common::exit_failure;
using example_common::exit_file;
using example_common::exit_scenario;
using example_common::exit_usage;
using example_common::FileError;

/// The shipped folder in the source tree the program was built from (compiled in), wherever it is
/// run from; never looked up relative to the working directory.
std::string box_dir() { return COOPDYN_BOX_DIR; }

struct CommandLine {
    std::vector<std::string> experiments{"all"};
    std::vector<std::string> scenarios;  ///< files; empty: the shipped ones of `experiments`
    std::string plant = "mujoco";
    std::string rigid_integrator = "euler";
    std::string scene = "lwr4_pair";  ///< whose shipped scenarios --experiment picks
    double duration = 0.0;  ///< 0: each scenario's
    double friction = 0.0;  ///< 0: each scenario's controller friction
    unsigned long long seed = 1;
    std::string output = "out/box";
    bool plots = true;
    bool progress = true;
    bool minimum_squeeze = true;  ///< measure it on the MuJoCo plant (minimum_squeeze.hpp)
    std::size_t log_every = 1;    ///< the CSV logs hold every log_every-th tick
};

std::vector<std::string> scenario_files(const CommandLine& command)
{
    if (!command.scenarios.empty()) {
        return command.scenarios;
    }
    std::vector<std::string> files;
    const bool all = std::find(command.experiments.begin(), command.experiments.end(), "all") != command.experiments.end();
    // The LWR 4 pair's scenarios are scenarios/*.json (no scene: the fixed-size path); every other
    // scene's are scenarios/<scene>/*.json.
    const std::string folder = box_dir() + "/scenarios/" + (command.scene == "lwr4_pair" ? "" : command.scene + "/");
    for (const char* name : {"hold", "push", "add_mass", "circle"}) {
        if (all || std::find(command.experiments.begin(), command.experiments.end(), name) != command.experiments.end()) {
            files.push_back(folder + name + ".json");
        }
    }
    return files;
}

/// Writes one run's log and plot script; returns its summary.
template <int K, int Q>
BoxSummary report_one(const ExperimentRunOf<K, Q>& run, const BoxScenario& scenario, const std::string& plant_name,
                      const CommandLine& command, std::vector<example_common::Plot>& plots)
{
    const std::string stem = scenario.name + "_" + plant_name;
    const fs::path csv = example_common::confined_path(command.output, stem + ".csv");
    write_box_log(csv, run, command.log_every);
    const fs::path script = example_common::confined_path(command.output, stem + ".gp");
    const fs::path image = example_common::confined_path(command.output, stem + ".png");
    example_common::write_text_file(script, box_plot_script(scenario, plant_name, csv.filename().string(),
                                                            image.filename().string(), run.palm_names));
    plots.push_back({script, image});
    return summarise(scenario, plant_name, run);
}

/// The runs' bookkeeping: the progress line, the plot scripts, the table's rows.
struct Runs {
    example_common::Progress progress;
    std::vector<example_common::Plot> plots;
    std::vector<std::pair<BoxScenario, BoxSummary>> summaries;
};

/// A scenario on the LWR 4 pair (no scene), on the plants asked for; `world` is loaded on first use.
void run_lwr4(const BoxScenario& scenario, const CommandLine& command, std::unique_ptr<DualArmBoxModel>& world,
              Runs& runs)
{
    if (!world) {
        world = std::make_unique<DualArmBoxModel>(box_dir() + "/dual_arm_box.xml");
    }
    const Grasp grasp = hold_grasp(*world);
    for (const char* plant_name : {"mujoco", "rigid"}) {
        if (command.plant != "both" && command.plant != plant_name) {
            continue;
        }
        const std::string label = scenario.name + " (" + plant_name + ")";
        const auto update = [&](double fraction) { runs.progress.update(label, fraction); };
        const ExperimentRun run =
            run_lwr4_experiment(*world, scenario, grasp, std::string(plant_name) == "rigid", command.seed, update);
        runs.progress.finish();
        BoxSummary summary = report_one(run, scenario, plant_name, command, runs.plots);
        if (command.minimum_squeeze && std::string(plant_name) == "mujoco") {
            runs.progress.update(scenario.name + " (minimum squeeze)", 0.0);
            if (const auto measured = measure_minimum_squeeze(*world, grasp, scenario)) {
                summary.minimum_squeeze = measured->squeeze;
            }
            runs.progress.finish();
        }
        runs.summaries.emplace_back(scenario, summary);
    }
}

/// A scenario on its scene (scene_box.hpp's run, compiled in box_runs.cpp: run_scene_world), on the
/// plants asked for. The minimum squeeze is measured on the LWR 4 pair only.
void run_scene(const BoxScenario& scenario, const scenes::Scene& scene, const CommandLine& command, Runs& runs)
{
    for (const char* plant_name : {"mujoco", "rigid"}) {
        if (command.plant != "both" && command.plant != plant_name) {
            continue;
        }
        const std::string label = scenario.name + " (" + plant_name + ")";
        const DynamicRun run = run_scene_world(
            scene, scenario, std::string(plant_name) == "rigid", command.seed,
            [&](double fraction) { runs.progress.update(label, fraction); },
            command.rigid_integrator == "rk4" ? coopdyn::Integrator::runge_kutta_4 : coopdyn::Integrator::semi_implicit_euler);
        runs.progress.finish();
        runs.summaries.emplace_back(scenario, report_one(run, scenario, plant_name, command, runs.plots));
    }
}

void print_legend(const std::vector<BoxScenario>& scenarios, const std::vector<std::optional<scenes::Scene>>& scene_of)
{
    if (!scene_of.front()) {
        std::printf("dual_arm_box: two 7-joint arms squeeze a %.1f kg box (unknown to the controller), Lin et al. "
                    "section IV\n",
                    scenarios.front().box_mass);
    } else {
        const scenes::Scene& scene = *scene_of.front();
        std::printf("dual_arm_box: scene %s: %ld arms, %ld joints squeeze a %.1f kg object (unknown to the "
                    "controller), Lin et al. section IV\n",
                    fs::path(scene.source).filename().string().c_str(), static_cast<long>(scene.arms()),
                    static_cast<long>(scene.joints()),
                    scenarios.front().box_mass);
    }
}

/// Each scenario's scene, read before anything runs (or is written): a bad scene file fails at once.
std::vector<std::optional<scenes::Scene>> read_scenes(const std::vector<BoxScenario>& scenarios)
{
    std::vector<std::optional<scenes::Scene>> scene_of;
    for (const BoxScenario& scenario : scenarios) {
        scene_of.push_back(scenario.scene ? std::optional<scenes::Scene>(scenes::read_scene(*scenario.scene))
                                          : std::nullopt);
    }
    return scene_of;
}

int run(const CommandLine& command, std::vector<BoxScenario> scenarios,
        const std::vector<std::optional<scenes::Scene>>& scene_of)
{
    std::unique_ptr<DualArmBoxModel> world;  // --output was created and checked by main()
    Runs runs{example_common::Progress(command.progress), {}, {}};
    for (std::size_t k = 0; k < scenarios.size(); ++k) {
        BoxScenario& scenario = scenarios[k];
        if (command.duration > 0.0) {
            scenario.duration = command.duration;
        }
        if (command.friction > 0.0) {
            scenario.controller.friction = command.friction;
        }
        if (scene_of[k]) {
            run_scene(scenario, *scene_of[k], command, runs);
        } else {
            run_lwr4(scenario, command, world, runs);
        }
    }
    print_legend(scenarios, scene_of);
    print_box_table(runs.summaries);
    std::printf("  rest/peak N: normal force per palm, the QP's (expected) and the plant's (measured); slip: the box "
                "relative to the palms;\n  F mrg N, M mrg Nm: tightest friction margins of the measured wrenches under the "
                "true friction, force rows (N) and moment rows (N m); needed N: |f_t| / mu_true;\n  holds N: the smallest squeeze that still holds the heaviest static "
                "load in MuJoCo (measured; LWR 4 pair only); W/(K mu): its Coulomb estimate, K palms;\n  track: largest |x - x_d| (m) outside a "
                "person's hold; QP: ticks whose contact QP was not solved; RTF: real-time factor.\n");
    std::printf("logs and plot scripts: %s%s\n", command.output.c_str(),
                command.log_every == 1 ? ""
                                       : (" (the CSV logs hold 1 tick in " + std::to_string(command.log_every) +
                                          "; the table used every tick)")
                                             .c_str());
    bool dropped = false;
    for (const auto& entry : runs.summaries) {
        dropped = dropped || entry.second.dropped;
    }
    if (command.plots && !example_common::render_plots("dual_arm_box", runs.plots)) {
        return exit_failure;
    }
    if (dropped) {
        std::fprintf(stderr, "dual_arm_box: the box was dropped (see the table)\n");
        return exit_failure;
    }
    return 0;
}

/// The flags that switch something off, bound by add_options and turned into CommandLine's switches.
struct NegativeFlags {
    bool no_plots = false;
    bool quiet = false;
    bool no_minimum_squeeze = false;
};

/// Every option and flag of the command line (docs/dual-arm-box.md, "Options"), bound to `command`
/// and `flags`.
void add_options(CLI::App& app, CommandLine& command, NegativeFlags& flags)
{
    app.option_defaults()->always_capture_default();
    app.add_option("--experiment", command.experiments, "Shipped experiments to run: hold, push, add_mass, circle or all")
        ->delimiter(',')
        ->check(CLI::IsMember({"hold", "push", "add_mass", "circle", "all"}))
        ->type_name("LIST");
    app.add_option("--scene", command.scene,
                   "Whose shipped scenarios --experiment runs: lwr4_pair (examples/box/scenarios/), ur5e_panda or "
                   "three_arms (examples/box/scenarios/<scene>/; docs/scenes.md)")
        ->check(CLI::IsMember({"lwr4_pair", "ur5e_panda", "three_arms"}))
        ->type_name("SCENE");
    app.add_option("--scenario", command.scenarios,
                   "Scenario files (JSON) instead of the shipped ones (examples/box/scenarios/), run one after the "
                   "other (repeat the option); relative to the working directory")
        ->type_name("FILE");
    app.add_option("--plant", command.plant, "mujoco (friction contact), rigid (welded palms) or both")
        ->check(CLI::IsMember({"mujoco", "rigid", "both"}))
        ->type_name("PLANT");
    app.add_option("--rigid-integrator", command.rigid_integrator,
                   "A scene's rigid plant: euler (semi-implicit, one evaluation per step) or rk4 (four; docs/scenes.md, "
                   "\"The rigid plant\"); the LWR 4 pair's own rigid plant integrates by RK4")
        ->check(CLI::IsMember({"euler", "rk4"}))
        ->capture_default_str()
        ->type_name("INTEGRATOR");
    app.add_option("--duration", command.duration,
                   "Simulated seconds per experiment (default: the scenario's; at least 1 s, the table's rest window "
                   "is 0.8 s)")
        ->check(example_common::number_in_range(example_common::experiment_duration_range))
        ->default_str("scenario")
        ->type_name("SECONDS");
    app.add_option("--friction", command.friction,
                   "The controller's friction coefficient (default: the scenario's, 0.2; the plant's is 0.5)")
        ->check(example_common::number_in_range(friction_range))  // the scenario's range too
        ->default_str("scenario")
        ->type_name("MU");
    app.add_option("--seed", command.seed, "Seed of the person's trembling hand")
        ->check(example_common::decimal_unsigned())
        ->type_name("N");
    app.add_option("--output", command.output,
                   "Directory for the CSV logs and plots (created if missing; relative to the working directory)")
        ->check(example_common::output_folder())
        ->type_name("DIR");
    app.add_option("--log-every", command.log_every,
                   "Write every N-th tick to the CSV logs (and so to the plots); the table still uses every tick")
        ->check(example_common::decimal_positive())
        ->type_name("N");
    app.add_flag("--no-plots", flags.no_plots, "Do not run gnuplot (the scripts are still written)");
    app.add_flag("--quiet", flags.quiet, "No progress line");
    app.add_flag("--no-minimum-squeeze", flags.no_minimum_squeeze,
                 "Do not measure the smallest squeeze that holds the box in MuJoCo (a bisection of short holds, "
                 "about 1 s per experiment)");
}

}  // namespace

int main(int argc, char** argv)
{
    CommandLine command;
    CLI::App app{"dual_arm_box: the dual-arm box experiments of Lin et al. (section IV, Figs. 5-8) in simulation.\n"
                 "Two 7-joint arms (or any scene's arms: --scene, a scenario's \"scene\") hold a box by friction\n"
                 "with coopdyn's projected inverse-dynamics controller while a person pushes it, loads it or grabs\n"
                 "it. Writes CSV logs, gnuplot scripts and PNG plots to --output. Docs: docs/dual-arm-box.md",
                 "dual_arm_box"};
    NegativeFlags flags;
    add_options(app, command, flags);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& error) {
        const int code = app.exit(error);
        return code == 0 ? 0 : exit_usage;
    }
    command.plots = !flags.no_plots;
    command.progress = !flags.quiet;
    command.minimum_squeeze = !flags.no_minimum_squeeze;

    std::vector<BoxScenario> scenarios;
    try {
        for (const std::string& file : scenario_files(command)) {
            scenarios.push_back(load_box_scenario(file));
            for (std::size_t k = 0; k + 1 < scenarios.size(); ++k) {
                if (scenarios[k].name == scenarios.back().name) {
                    std::fprintf(stderr, "dual_arm_box: the scenarios %s and %s have the same name '%s' and would "
                                         "write the same files\n",
                                 scenarios[k].source.c_str(), file.c_str(), scenarios.back().name.c_str());
                    return exit_usage;
                }
            }
        }
        const std::vector<std::optional<scenes::Scene>> scene_of = read_scenes(scenarios);
        example_common::prepare_output_folder(command.output);
        return run(command, std::move(scenarios), scene_of);
    } catch (const FileError& error) {
        std::fprintf(stderr, "dual_arm_box: %s\n", error.what());
        return exit_file;
    } catch (const ScenarioError& error) {
        std::fprintf(stderr, "dual_arm_box: invalid scenario: %s\n", error.what());
        return exit_scenario;
    } catch (const std::exception& error) {
        std::fprintf(stderr, "dual_arm_box: %s\n", error.what());
        return exit_failure;
    }
}
