// fault_campaign: the controller under the faults a real robot cell sees (issue 23;
// docs/faults.md). Every shipped scene (the LWR 4 pair, the UR5e + Panda pair, three arms) holds
// its box on both plants (MuJoCo, rigid) under each fault cell (fault_cells.hpp: dropouts,
// latency, torque noise and limits, model error, a payload, optimistic friction, overloads), then
// a Monte Carlo of seeded random pushes per scene on MuJoCo. Writes the table (markdown, CSV),
// the Monte Carlo's pushes and figures, and gnuplot plots; runs the jobs on --jobs threads, each
// run in a world of its own.
//
// Its own program rather than a mode of dual_arm_box: the campaign's loop (jobs over scenes x
// plants x cells, threads, one table) shares nothing with the box program's per-scenario reports
// but the experiment loop, which both include (box_experiment.hpp); and the box program's
// translation unit stays as it was.
//
// Exit codes (examples/common/cli.hpp): 0 nothing dropped inside the envelope, every drop
// reported no later than it happened, every torque finite; 1 otherwise (or gnuplot failed);
// 2 bad command line; 3 invalid scene or scenario file; 4 a file that cannot be written.
#include "fault_report.hpp"

#include "box_scenario_loader.hpp"

#include "../common/cli.hpp"
#include "../common/files.hpp"

#include <CLI/CLI.hpp>

#include <atomic>
#include <chrono>
#include <exception>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <unistd.h>

#ifndef COOPDYN_BOX_DIR
#error "COOPDYN_BOX_DIR: the box example's folder (scenarios, scenes), set by examples/faults/CMakeLists.txt"
#endif

namespace {

using namespace fault_campaign;
namespace fs = std::filesystem;

struct CommandLine {
    std::vector<std::string> scenes{"lwr4_pair", "ur5e_panda", "three_arms"};
    std::string plant = "both";
    unsigned jobs = 0;  ///< 0: the hardware's threads
    bool short_run = false;
    double duration = 3.0;
    std::size_t pushes = 1000;
    unsigned long long seed = 1;
    std::string output = "out/faults";
    bool plots = true;
    bool progress = true;
};

/// The scene's hold scenario (the box experiments' shipped one) with its scene: the LWR 4 pair's
/// scenario names none (the box program runs it at fixed sizes), so its scene file is set here.
SceneCase load_scene_case(const std::string& name)
{
    const std::string box = COOPDYN_BOX_DIR;
    SceneCase scene_case;
    scene_case.name = name;
    scene_case.hold = box_example::load_box_scenario(box + "/scenarios/" + (name == "lwr4_pair" ? "" : name + "/") +
                                                     "hold.json");
    const std::string scene_file = name == "lwr4_pair" ? box + "/../scenes/lwr4_pair.json" : *scene_case.hold.scene;
    scene_case.hold.scene = scene_file;
    scene_case.scene = scenes::read_scene(scene_file);
    return scene_case;
}

/// One job: a cell on a scene and plant, or a Monte Carlo push (cell < 0) on a scene.
struct Job {
    std::size_t scene = 0;
    int cell = -1;
    bool rigid = false;
    std::size_t push = 0;
};

/// Runs every job on `threads` threads (each job its own world); a progress line on stderr.
std::vector<CellResult> run_jobs(const std::vector<Job>& jobs, const std::vector<SceneCase>& cases,
                                 const std::vector<Cell>& cells, const CommandLine& command, unsigned threads)
{
    std::vector<CellResult> results(jobs.size());
    std::atomic<std::size_t> next{0};
    std::atomic<std::size_t> done{0};
    std::mutex load_mutex, print_mutex;
    std::exception_ptr failure;  // the first job's exception, rethrown once every thread is joined
    const bool show = command.progress && isatty(fileno(stderr)) != 0;
    const auto work = [&]() {
        for (std::size_t k = next++; k < jobs.size(); k = next++) {
            const Job& job = jobs[k];
            try {
                results[k] = job.cell >= 0 ? run_cell(cases[job.scene], cells[static_cast<std::size_t>(job.cell)],
                                                      job.rigid, command.duration, command.seed, load_mutex)
                                           : run_push(cases[job.scene], job.push, command.seed, load_mutex);
            } catch (...) {
                const std::lock_guard<std::mutex> lock(print_mutex);
                if (!failure) {
                    failure = std::current_exception();
                }
                next = jobs.size();
                return;
            }
            const std::size_t finished = ++done;
            if (show) {
                const std::lock_guard<std::mutex> lock(print_mutex);
                std::fprintf(stderr, "\rfault_campaign: %zu / %zu runs  %-40s", finished, jobs.size(),
                             (results[k].scene + " " + results[k].plant + " " + results[k].cell.name).c_str());
                std::fflush(stderr);
            }
        }
    };
    std::vector<std::thread> pool;
    for (unsigned t = 1; t < threads; ++t) {
        pool.emplace_back(work);
    }
    work();
    for (std::thread& thread : pool) {
        thread.join();
    }
    if (show) {
        std::fprintf(stderr, "\r%-90s\r", "");
    }
    if (failure) {
        std::rethrow_exception(failure);
    }
    return results;
}

int run(const CommandLine& command)
{
    std::vector<SceneCase> cases;
    for (const std::string& name : command.scenes) {
        cases.push_back(load_scene_case(name));
    }
    example_common::prepare_output_folder(command.output);
    const std::vector<Cell> cells = command.short_run ? short_cells() : campaign_cells();
    std::vector<Job> jobs;
    for (std::size_t s = 0; s < cases.size(); ++s) {
        for (std::size_t c = 0; c < cells.size(); ++c) {
            for (const bool rigid : {false, true}) {
                if (command.plant == "both" || (command.plant == "rigid") == rigid) {
                    jobs.push_back({s, static_cast<int>(c), rigid, 0});
                }
            }
        }
    }
    const std::size_t cell_jobs = jobs.size();
    for (std::size_t s = 0; s < cases.size(); ++s) {
        for (std::size_t p = 0; p < command.pushes; ++p) {
            jobs.push_back({s, -1, false, p});
        }
    }
    const unsigned threads = command.jobs > 0 ? command.jobs : std::max(1U, std::thread::hardware_concurrency());
    const auto start = std::chrono::steady_clock::now();
    std::vector<CellResult> results = run_jobs(jobs, cases, cells, command, threads);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::vector<CellResult> table(results.begin(), results.begin() + static_cast<std::ptrdiff_t>(cell_jobs));
    const std::vector<CellResult> pushes(results.begin() + static_cast<std::ptrdiff_t>(cell_jobs), results.end());

    const std::string cell_table = markdown_table(table);
    const std::string push_table = monte_carlo_table(pushes, command.scenes);
    const fs::path folder = command.output;
    write_results_csv(folder / "campaign.csv", table);
    write_results_csv(folder / "monte_carlo.csv", pushes);
    example_common::write_text_file(folder / "campaign.md", "# Fault campaign\n\n" + cell_table +
                                                                 "\n## Monte Carlo of random pushes (MuJoCo)\n\n" +
                                                                 push_table);
    std::printf("fault_campaign: %zu runs on %u threads in %.0f s (seed %llu%s)\n\n%s\nMonte Carlo of random pushes "
                "(MuJoCo, %.1f s each):\n\n%s\n",
                jobs.size(), threads, wall, command.seed, command.short_run ? ", --short" : "", cell_table.c_str(),
                push_run_seconds, push_table.c_str());
    std::printf("slip: the box relative to the palms (plant); F/M mrg: smallest true-friction margins of the measured "
                "wrenches;\nctrl slip: the largest the controller measured; first report: first tick not ok, slipping "
                "or saturated.\ntables: %s, %s, %s\n",
                (folder / "campaign.md").string().c_str(), (folder / "campaign.csv").string().c_str(),
                (folder / "monte_carlo.csv").string().c_str());
    std::vector<example_common::Plot> plots;
    for (const std::string& scene : command.scenes) {
        plots.push_back(write_scene_plot(folder, scene, table, pushes));
    }
    bool failed = false;
    for (const CellResult& r : results) {
        const bool finding = (r.dropped && (r.cell.in_envelope || !r.reported())) || !r.stats.finite;
        if (finding) {
            std::fprintf(stderr, "fault_campaign: %s %s %s: %s\n", r.scene.c_str(), r.plant.c_str(), r.cell.name.c_str(),
                         !r.stats.finite ? "a torque was not finite"
                         : r.reported()  ? "dropped inside the envelope"
                                         : "dropped without a report");
        }
        failed = failed || finding;
    }
    if (command.plots && !example_common::render_plots("fault_campaign", plots)) {
        return example_common::exit_failure;
    }
    return failed ? example_common::exit_failure : example_common::exit_success;
}

void add_options(CLI::App& app, CommandLine& command, bool& no_plots, bool& quiet)
{
    app.option_defaults()->always_capture_default();
    app.add_option("--scene", command.scenes, "Scenes: lwr4_pair, ur5e_panda, three_arms (default: all)")
        ->delimiter(',')
        ->check(CLI::IsMember({"lwr4_pair", "ur5e_panda", "three_arms"}))
        ->type_name("LIST");
    app.add_option("--plant", command.plant, "mujoco, rigid or both (the Monte Carlo runs on MuJoCo)")
        ->check(CLI::IsMember({"mujoco", "rigid", "both"}))
        ->type_name("PLANT");
    app.add_option("--jobs", command.jobs, "Runs in parallel (threads; default: the hardware's)")
        ->check(example_common::decimal_positive())
        ->default_str("hardware threads")
        ->type_name("N");
    app.add_flag("--short", command.short_run,
                 "A short campaign (the tests'): four cells, 1.5 s runs, 5 pushes per scene unless --pushes");
    app.add_option("--duration", command.duration, "Simulated seconds per cell (faults start at a third)")
        ->check(example_common::number_in_range(1.0, 60.0))
        ->type_name("SECONDS");
    app.add_option("--pushes", command.pushes, "Monte Carlo pushes per scene")
        ->check(example_common::decimal_unsigned())
        ->type_name("N");
    app.add_option("--seed", command.seed, "Seed of the noise and the pushes")
        ->check(example_common::decimal_unsigned())
        ->type_name("N");
    app.add_option("--output", command.output,
                   "Directory for the tables and plots (created if missing; relative to the working directory)")
        ->check(example_common::output_folder())
        ->type_name("DIR");
    app.add_flag("--no-plots", no_plots, "Do not run gnuplot (the scripts are still written)");
    app.add_flag("--quiet", quiet, "No progress line");
}

}  // namespace

int main(int argc, char** argv)
{
    CommandLine command;
    CLI::App app{"fault_campaign: every shipped scene holds its box on both plants under each fault (dropout, "
                 "latency,\ntorque noise and limits, model error, payload, optimistic friction, overloads) and a "
                 "Monte Carlo\nof random pushes; a table (markdown, CSV) and plots. Docs: docs/faults.md",
                 "fault_campaign"};
    bool no_plots = false, quiet = false;
    add_options(app, command, no_plots, quiet);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& error) {
        const int code = app.exit(error);
        return code == 0 ? 0 : example_common::exit_usage;
    }
    command.plots = !no_plots;
    command.progress = !quiet;
    if (command.short_run) {
        if (app.count("--duration") == 0) {
            command.duration = 1.5;
        }
        if (app.count("--pushes") == 0) {
            command.pushes = 5;
        }
    }
    try {
        return run(command);
    } catch (const example_common::FileError& error) {
        std::fprintf(stderr, "fault_campaign: %s\n", error.what());
        return example_common::exit_file;
    } catch (const box_example::ScenarioError& error) {
        std::fprintf(stderr, "fault_campaign: invalid scenario: %s\n", error.what());
        return example_common::exit_scenario;
    } catch (const scenes::SceneError& error) {
        std::fprintf(stderr, "fault_campaign: invalid scene: %s\n", error.what());
        return example_common::exit_scenario;
    } catch (const std::exception& error) {
        std::fprintf(stderr, "fault_campaign: %s\n", error.what());
        return example_common::exit_failure;
    }
}
