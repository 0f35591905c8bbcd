// coopdyn._experiments.beam_run: the first paper's two-arm beam experiment (Erhart & Hirche 2016,
// Section V; docs/two-arm-beam.md) as the program two_arm_beam runs it (beam_experiment.hpp's
// run_experiment on the Model of the scenario's arm count, compiled in beam_example_runs:
// run_beam_experiment), returning the log's columns (emit_log) and the identification table's rows
// (emit_summary) instead of writing files. The GIL is released while the experiment runs.
#include "columns.hpp"

#include "beam/beam_experiment.hpp"
#include "beam/beam_report.hpp"
#include "beam/beam_runs.hpp"  // the experiments, compiled once (beam_example_runs)
#include "beam/scenario.hpp"

#include <algorithm>
#include <optional>
#include <string>

#ifndef COOPDYN_BEAM_SCENARIO_DIR
#error "COOPDYN_BEAM_SCENARIO_DIR: the shipped beam scenarios' folder, set by python/CMakeLists.txt"
#endif

namespace coopdyn::python::experiments {
namespace {

using namespace beam_example;

/// (log columns, identification summary) of one experiment: the run compiled in beam_example_runs.
py::tuple run_on(const Scenario& scenario, const ExperimentSpec& spec, const RunOptions& options,
                 unsigned long long index)
{
    std::optional<ExperimentResult> result;
    {
        py::gil_scoped_release release;
        result.emplace(run_beam_experiment(scenario, spec, options, index));
    }
    ColumnSink log(log_columns(scenario.arm_count()));
    emit_log(log, result->log);
    ColumnSink table(summary_columns());
    const std::vector<ExperimentResult> results{*result};
    emit_summary(table, scenario, results, options);
    py::dict summary = table.to_dict();
    summary["simulated_seconds"] = result->simulated_seconds;
    summary["warmup_seconds"] = result->warmup_seconds;
    summary["cross_axis_motion"] = result->cross_axis_motion;
    summary["nominal_coupling"] = result->nominal_coupling;
    return py::make_tuple(log.to_dict(), summary);
}

/// two_arm_beam's run_scenario for one scenario file and one experiment, without the files.
py::tuple beam_run(const std::string& file, const std::string& experiment, double duration,
                   const std::string& excitation, double force, double torque, unsigned long long seed, int runs,
                   bool noise)
{
    const auto& specs = experiment_specs();
    const auto spec = std::find_if(specs.begin(), specs.end(), [&](const ExperimentSpec& s) { return s.id == experiment; });
    if (spec == specs.end()) {
        throw py::value_error("experiment: 'x', 'rot_z' or 'se3', got '" + experiment + "'");
    }
    if (excitation != "multisine" && excitation != "push") {
        throw py::value_error("excitation: 'multisine' or 'push', got '" + excitation + "'");
    }
    if (runs != 1 && runs != 2 && runs != 4) {
        throw py::value_error("runs: 1, 2 or 4, got " + std::to_string(runs));
    }
    RunOptions options;
    options.duration = duration;
    options.excitation = excitation == "push" ? ExcitationKind::push : ExcitationKind::multisine;
    options.force = force;
    options.torque = torque;
    options.seed = seed;
    options.runs = runs;
    options.sensors.enabled = noise;
    options.progress = false;
    const Scenario scenario = load_scenario(file);
    if (duration / scenario.time_step < 100.0) {  // two_arm_beam's options_fit_scenario
        throw py::value_error("duration: " + std::to_string(duration) + " s gives fewer than 100 samples at the "
                              "scenario's time step");
    }
    const auto index = static_cast<unsigned long long>(spec - specs.begin());  // the program's seed offset
    return run_on(scenario, *spec, options, index);
}

}  // namespace

void bind_beam(py::module_& module)
{
    module.attr("beam_scenario_dir") = COOPDYN_BEAM_SCENARIO_DIR;
    module.def("beam_run", &beam_run, py::arg("file"), py::arg("experiment"), py::arg("duration"),
               py::arg("excitation"), py::arg("force"), py::arg("torque"), py::arg("seed"), py::arg("runs"),
               py::arg("noise"),
               "One two-arm beam experiment of one scenario file, as two_arm_beam runs it: (log columns, "
               "identification summary). Use coopdyn.experiments.beam.");
}

}  // namespace coopdyn::python::experiments
