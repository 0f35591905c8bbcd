// The main job: the paper's two-arm beam experiment (Erhart & Hirche 2016, Section V;
// docs/analysis.md, docs/two-arm-beam.md) in simulation, with identification, logs and plots.
//
// Two impedance-controlled arms hold a 1 m aluminium beam at 1 kHz. Three experiments, as in the
// paper: translation along x, rotation about z, and the full SE(3) case. Each applies a
// disturbance wrench to the object (a multisine or human-like pushes), logs the object's pose and
// every arm's wrench (total, internal, external), and identifies the apparent impedance from the
// logged wrench and pose alone by grey-box estimation (coopdyn::identify_diagonal_impedance). A
// table per experiment compares the paper's nominal values, the identified ones and the paper's
// values identified on the real robots. The set-up comes from a scenario file (JSON); see
// docs/two-arm-beam.md for the file format, the CSV columns and the plots.
//
// Every option is checked before anything runs (examples/common/cli.hpp): numbers must be finite
// and in range, the output folder usable, the scenarios valid (a name becomes a plain file-name
// prefix), and options that depend on a scenario (--duration, --lowpass) consistent with it.
// Several --scenario files run one after the other; relative paths are taken from the working
// directory.
//
// Exit codes (example_common, examples/common/cli.hpp): 0 success, 1 run-time failure
// (identification, gnuplot), 2 bad command line, 3 invalid scenario file, 4 a file that cannot be
// read or written.

#include "beam_experiment.hpp"
#include "beam_identify_log.hpp"
#include "beam_runs.hpp"  // the experiments, compiled once (beam_example_runs)
#include "beam_report.hpp"
#include "scenario.hpp"

#include "../common/cli.hpp"
#include "../common/files.hpp"
#include "../common/csv_table.hpp"
#include "../common/plotting.hpp"

#include <coopdyn/coopdyn.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#ifndef COOPDYN_SCENARIO_DIR
#error "COOPDYN_SCENARIO_DIR: the shipped scenarios' folder, set by examples/beam/CMakeLists.txt"
#endif

namespace {

using namespace beam_example;
namespace fs = std::filesystem;

using example_common::CsvTable;
using example_common::exit_failure;
using example_common::exit_file;
using example_common::exit_scenario;
using example_common::exit_usage;
using example_common::FileError;

/// The default --scenario as --help shows it (relative to the repository root).
const char* const shipped_scenario = "examples/beam/scenarios/beam.json";

/// The file of the default --scenario: the shipped beam in the source tree the program was built
/// from (COOPDYN_SCENARIO_DIR, compiled in), wherever the program is run from; never looked up
/// relative to the working directory (if that tree is gone, it is a file that cannot be read).
std::string default_scenario_file() { return std::string(COOPDYN_SCENARIO_DIR) + "/beam.json"; }

struct CommandLine {
    std::vector<std::string> scenarios;  ///< empty before finish_command_line(): the default
    bool scenario_given = false;
    std::vector<std::string> experiments{"all"};
    std::string excitation = "multisine";
    std::string output = "out";
    std::string identify_log;
    bool plots = true;
    bool list_scenarios = false;
    bool lowpass_given = false;
    unsigned long long log_every = 1;  ///< the CSV logs hold every log_every-th step
    RunOptions run;
};

/// What the scenario is, for the banner: "3 arms hold a 4.58 kg object".
std::string setup_summary(const Scenario& scenario)
{
    const long long arms = static_cast<long long>(scenario.arm_count());
    return std::to_string(arms) + (arms == 1 ? " arm holds a " : " arms hold a ") +
           format("%.4g", scenario.object.mass) + " kg object";
}

/// Checks the options that depend on the scenario; prints the problem and returns false.
bool options_fit_scenario(const CommandLine& command, const Scenario& scenario)
{
    if (command.run.duration / scenario.time_step < 100.0) {
        std::fprintf(stderr, "two_arm_beam: --duration %g s gives fewer than 100 samples at the scenario's "
                             "time step %g s\n",
                     command.run.duration, scenario.time_step);
        return false;
    }
    // The low-pass filters the logged wrench, sampled at the control loop's rate: a cut-off
    // above the Nyquist frequency 1 / (2 T_s) cannot be represented (the default, 500 Hz, is
    // the limit of the 1 kHz loop).
    const double nyquist = 0.5 / scenario.time_step;
    if (command.lowpass_given && command.run.sensors.lowpass_hz > nyquist * (1.0 + 1e-12)) {
        std::fprintf(stderr, "two_arm_beam: --lowpass %g Hz is above the Nyquist limit %g Hz of the scenario's "
                             "%g Hz loop (time step %g s); use at most %g Hz (0: no low-pass)\n",
                     command.run.sensors.lowpass_hz, nyquist, 1.0 / scenario.time_step, scenario.time_step, nyquist);
        return false;
    }
    return true;
}

/// Runs the selected experiments on a Model with N arms fixed at compile time (2, 3) or not.
template <typename ModelType>
int run_experiments(const Scenario& scenario, const CommandLine& command, const std::vector<ExperimentSpec>& specs)
{
    const ModelType model(scenario.object, scenario.arms, scenario.gravity);
    const fs::path output = command.output;  // created and checked before anything ran

    std::printf("coopdyn cooperative manipulation: %s, scenario '%s' (%s)\n", setup_summary(scenario).c_str(),
                scenario.name.c_str(), scenario.source.c_str());
    if (!scenario.description.empty()) {
        std::printf("  %s\n", scenario.description.c_str());
    }
    std::printf("  RK4 at %.4g Hz, %.4g s per experiment, seed %llu\n", 1.0 / scenario.time_step,
                command.run.duration, command.run.seed);

    Progress progress(command.run.progress);
    std::vector<ExperimentResult> results;
    std::vector<fs::path> written;
    std::vector<example_common::Plot> plots;
    double simulated = 0.0, wall = 0.0;
    int number = 0;
    for (const ExperimentSpec& spec : specs) {
        ++number;
        const auto index = static_cast<unsigned long long>(
            std::find_if(experiment_specs().begin(), experiment_specs().end(),
                         [&](const ExperimentSpec& s) { return s.id == spec.id; }) -
            experiment_specs().begin());
        ExperimentResult result = run_experiment(scenario, model, spec, command.run, progress, index);
        print_table(scenario, result, command.run, number, static_cast<int>(specs.size()));
        simulated += result.simulated_seconds;
        wall += result.simulation_seconds;

        // Output files lie directly in --output: the scenario's name was checked when it was
        // loaded, and confined_path() refuses any file name that could leave the folder.
        const std::string stem = scenario.name + "_" + spec.id;
        const fs::path csv = example_common::confined_path(output, stem + ".csv");
        write_log_csv(csv, result.log, static_cast<Eigen::Index>(command.log_every));
        written.push_back(csv);
        const fs::path script = example_common::confined_path(output, stem + ".gp");
        example_common::write_text_file(
            script, gnuplot_script(stem + ".csv", stem + ".png", scenario, result, command.run.sensors.enabled));
        plots.push_back({script, example_common::confined_path(output, stem + ".png")});
        result.log = ExperimentLog{};  // the log is on disk; keep the fit only
        results.push_back(std::move(result));
    }
    const fs::path summary = example_common::confined_path(output, scenario.name + "_identification.csv");
    write_summary_csv(summary, scenario, results, command.run);
    written.push_back(summary);

    std::printf("\nsimulated %.4g s (warm-up included) in %.3g s wall clock (%.0fx real time, %s)\n", simulated, wall,
                simulated / wall,
                command.log_every == 1 ? "logging every step"
                                       : ("the CSV logs hold 1 step in " + std::to_string(command.log_every) +
                                          ", the identification used every step")
                                             .c_str());
    std::printf("logs (CSV, SI units, columns in docs/two-arm-beam.md):\n");
    for (const fs::path& path : written) {
        std::printf("  %s\n", path.string().c_str());
    }

    if (!command.plots) {
        std::printf("plots: skipped (--no-plots); gnuplot scripts written next to the logs\n");
        return 0;
    }
    return example_common::render_plots("two_arm_beam", plots) ? 0 : exit_failure;
}

int list_scenarios()
{
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(COOPDYN_SCENARIO_DIR)) {
        if (entry.path().extension() == ".json") {
            files.push_back(entry.path());
        }
    }
    std::sort(files.begin(), files.end());
    for (const fs::path& file : files) {
        try {
            const Scenario scenario = load_scenario(file.string());
            std::printf("%-50s %s\n", file.string().c_str(), scenario.description.c_str());
        } catch (const ScenarioError& error) {
            std::printf("%-50s INVALID: %s\n", file.string().c_str(), error.what());
        }
    }
    return 0;
}

/// The command line's options and flags that are read after parsing.
struct ParsedFlags {
    CLI::Option* scenario = nullptr;
    CLI::Option* lowpass = nullptr;
    bool single_run = false;
    bool no_plots = false;
    bool quiet = false;
};

/// The scenario's and the experiments' options: --scenario .. --runs.
void add_experiment_options(CLI::App& app, CommandLine& command, ParsedFlags& flags)
{
    app.option_defaults()->always_capture_default();
    flags.scenario =
        app.add_option("--scenario", command.scenarios,
                       "Scenario files (JSON), run one after the other (repeat the option), see "
                       "examples/beam/scenarios/; relative to the working directory; default: the shipped beam "
                       "scenario")
            ->type_name("FILE")
            ->default_str(shipped_scenario);
    app.add_option("--experiment", command.experiments, "Experiments to run: x, rot_z, se3 or all")
        ->delimiter(',')
        ->check(CLI::IsMember({"x", "rot_z", "se3", "all"}))
        ->type_name("LIST");
    app.add_option("--duration", command.run.duration,
                   "Simulated seconds per experiment (at least 1 s: the multisine needs three lines in 0.1-5 Hz)")
        ->check(example_common::number_in_range(example_common::experiment_duration_range))
        ->type_name("SECONDS");
    app.add_option("--excitation", command.excitation,
                   "Disturbance wrench: multisine (random-phase, 0.1-5 Hz) or push (human-like pushes)")
        ->check(CLI::IsMember({"multisine", "push"}))
        ->type_name("KIND");
    app.add_option("--force", command.run.force,
                   "Force amplitude per axis [N]: RMS of the multisine, peak of a push (0: the scenario's)")
        ->check(example_common::zero_or_in_range(excitation_force_range))
        ->type_name("NEWTONS");
    app.add_option("--torque", command.run.torque, "Torque amplitude per axis [N m] (0: the scenario's)")
        ->check(example_common::zero_or_in_range(excitation_torque_range))
        ->type_name("NEWTON_METRES");
    app.add_option("--seed", command.run.seed, "Seed of the excitation phases/pushes and of the sensor noise")
        ->check(example_common::decimal_unsigned());
    app.add_option("--runs", command.run.runs,
                   "Excitation runs per experiment: 4 = +u, -u, +2u, -2u, identified on the odd parts extrapolated "
                   "to zero amplitude (cancels the even- and third-order nonlinear distortion); 2 = +u, -u, odd "
                   "part (even orders); 1 = a single run. The CSV logs hold the +u run")
        ->check(CLI::IsMember({1, 2, 4}))
        ->type_name("N");
}

/// The sensors', output's and other modes' options: --single-run .. --list-scenarios.
void add_output_options(CLI::App& app, CommandLine& command, ParsedFlags& flags)
{
    app.add_flag("--single-run", flags.single_run, "Same as --runs 1");
    app.add_flag("--noise", command.run.sensors.enabled,
                 "Realistic sensors: white noise on wrench and pose, and the force low-pass");
    app.add_option("--force-noise", command.run.sensors.force_rms, "Force noise with --noise [N RMS]")
        ->check(example_common::non_negative_number());
    app.add_option("--torque-noise", command.run.sensors.torque_rms, "Torque noise with --noise [N m RMS]")
        ->check(example_common::non_negative_number());
    app.add_option("--position-noise", command.run.sensors.position_rms, "Position noise with --noise [m RMS]")
        ->check(example_common::non_negative_number());
    app.add_option("--angle-noise", command.run.sensors.angle_rms, "Angle noise with --noise [rad RMS]")
        ->check(example_common::non_negative_number());
    flags.lowpass = app.add_option(
        "--lowpass", command.run.sensors.lowpass_hz,
        "Cut-off of the first-order force low-pass with --noise [Hz] (0: none), at most the Nyquist limit "
        "1 / (2 time step): 500 Hz at 1 kHz")
        ->check(example_common::non_negative_number())
        ->type_name("HZ");
    app.add_option("--output", command.output,
                   "Directory for the CSV logs and plots (created if missing; relative to the working directory)")
        ->check(example_common::output_folder())
        ->type_name("DIR");
    app.add_option("--log-every", command.log_every,
                   "Write every N-th step to the CSV logs (and so to the plots); the identification and the "
                   "tables still use every step")
        ->check(example_common::decimal_positive())
        ->type_name("N");
    app.add_flag("--no-plots", flags.no_plots, "Do not run gnuplot (the scripts are still written)");
    app.add_flag("--quiet", flags.quiet, "No progress line");
    app.add_option("--identify-log", command.identify_log,
                   "Only identify the impedance from an existing log (e.g. from real robots), no simulation; "
                   "columns: time, meas_fx..meas_tz, meas_disp_x..meas_rot_z (or ident_* when present)")
        ->type_name("CSV");
    app.add_flag("--list-scenarios", command.list_scenarios, "List the shipped scenario files and exit");

}

/// What the flags imply, once parsed.
void finish_command_line(const ParsedFlags& flags, CommandLine& command)
{
    command.plots = !flags.no_plots;
    if (flags.single_run) {
        command.run.runs = 1;
    }
    command.run.progress = !flags.quiet;
    command.scenario_given = flags.scenario->count() > 0;
    if (!command.scenario_given) {
        command.scenarios = {default_scenario_file()};
    }
    command.lowpass_given = flags.lowpass->count() > 0;
    command.run.excitation = command.excitation == "push" ? ExcitationKind::push : ExcitationKind::multisine;

}

/// The experiments --experiment selects, in the paper's order.
std::vector<ExperimentSpec> selected_experiments(const CommandLine& command)
{
    std::vector<ExperimentSpec> specs;
    for (const ExperimentSpec& spec : experiment_specs()) {
        const bool selected =
            std::find(command.experiments.begin(), command.experiments.end(), "all") != command.experiments.end() ||
            std::find(command.experiments.begin(), command.experiments.end(), spec.id) != command.experiments.end();
        if (selected) {
            specs.push_back(spec);
        }
    }
    return specs;
}

/// The selected experiments on one scenario, on a Model with N arms fixed at compile time (2, 3)
/// or not.
int run_scenario(const Scenario& scenario, const CommandLine& command, const std::vector<ExperimentSpec>& specs)
{
    switch (scenario.arm_count()) {
    case 2: return run_experiments<coopdyn::ImpedanceModel<2>>(scenario, command, specs);
    case 3: return run_experiments<coopdyn::ImpedanceModel<3>>(scenario, command, specs);
    default: return run_experiments<coopdyn::ImpedanceModelX>(scenario, command, specs);
    }
}

/// The parsed command: lists the scenarios, identifies a log or runs the experiments of each
/// scenario. Every scenario is read and checked against the options before the first one runs.
int run_command(const CommandLine& command)
{
    if (command.list_scenarios) {
        return list_scenarios();
    }
    if (!command.identify_log.empty() && command.scenarios.size() > 1) {
        std::fprintf(stderr, "two_arm_beam: --identify-log compares with one scenario, got %zu --scenario files\n",
                     command.scenarios.size());
        return exit_usage;
    }
    std::vector<Scenario> scenarios;
    for (const std::string& file : command.scenarios) {
        scenarios.push_back(load_scenario(file));  // FileError, ScenarioError: main()
        for (std::size_t k = 0; k + 1 < scenarios.size(); ++k) {
            if (scenarios[k].name == scenarios.back().name) {
                std::fprintf(stderr, "two_arm_beam: the scenarios %s and %s have the same name '%s' and would write the "
                                     "same files\n",
                             scenarios[k].source.c_str(), file.c_str(), scenarios.back().name.c_str());
                return exit_usage;
            }
        }
    }
    if (!command.identify_log.empty()) {
        return identify_log(command.identify_log, command.scenario_given ? &scenarios.front() : nullptr);
    }
    for (const Scenario& scenario : scenarios) {
        if (!options_fit_scenario(command, scenario)) {
            return exit_usage;
        }
    }
    example_common::prepare_output_folder(command.output);
    const std::vector<ExperimentSpec> specs = selected_experiments(command);
    int status = 0;
    for (std::size_t k = 0; k < scenarios.size(); ++k) {
        if (k > 0) {
            std::printf("\n");
        }
        const int code = run_scenario(scenarios[k], command, specs);
        status = status == 0 ? code : status;
    }
    return status;
}

}  // namespace

int main(int argc, char** argv)
{
    CommandLine command;
    CLI::App app{"two_arm_beam: the paper's two-arm beam experiment (Erhart & Hirche 2016, Section V) in "
                 "simulation.\nTwo impedance-controlled arms hold a beam at 1 kHz; a disturbance wrench excites "
                 "it; the apparent\nimpedance is identified from the logged wrench and pose and compared with the "
                 "paper's values.\nWrites CSV logs, gnuplot scripts and PNG plots to --output. Docs: "
                 "docs/two-arm-beam.md",
                 "two_arm_beam"};
    ParsedFlags flags;
    add_experiment_options(app, command, flags);
    add_output_options(app, command, flags);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& error) {
        const int code = app.exit(error);
        return code == 0 ? 0 : exit_usage;
    }
    finish_command_line(flags, command);
    try {
        return run_command(command);
    } catch (const FileError& error) {
        std::fprintf(stderr, "two_arm_beam: %s\n", error.what());
        return exit_file;
    } catch (const ScenarioError& error) {
        std::fprintf(stderr, "two_arm_beam: invalid scenario: %s\n", error.what());
        return exit_scenario;
    } catch (const std::exception& error) {
        std::fprintf(stderr, "two_arm_beam: %s\n", error.what());
        return exit_failure;
    }
}
