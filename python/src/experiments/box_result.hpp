// What coopdyn.experiments.box returns of one dual-arm box run (docs/python.md, "The
// experiments"): the log's columns (box_report.hpp's emit_box_log into a ColumnSink) and the
// summary (summarise, compiled in box_example_runs) as a dict.
#pragma once

#include "columns.hpp"

#include "box/box_report.hpp"
#include "box/box_runs.hpp"  // the runs and summaries, compiled once (box_example_runs)

#include <cstddef>
#include <optional>
#include <string>

namespace coopdyn::python::experiments {

inline py::dict summary_dict(const box_example::BoxSummary& s)
{
    py::dict d;
    d["experiment"] = s.experiment;
    d["plant"] = s.plant;
    d["simulated_seconds"] = s.simulated_seconds;
    d["dropped"] = s.dropped;
    d["rest_normal_predicted"] = s.rest_normal_predicted;
    d["rest_normal_measured"] = s.rest_normal_measured;
    d["peak_normal_predicted"] = s.peak_normal_predicted;
    d["peak_normal_measured"] = s.peak_normal_measured;
    d["max_slip"] = s.max_slip;
    d["min_true_force_margin"] = s.min_true_force_margin;
    d["min_true_moment_margin"] = s.min_true_moment_margin;
    d["max_force_error"] = s.max_force_error;
    d["needed_normal"] = s.needed_normal;
    d["coulomb_estimate"] = s.coulomb_estimate;
    d["minimum_squeeze"] = s.minimum_squeeze ? py::object(py::float_(*s.minimum_squeeze)) : py::none();
    d["qp_not_solved"] = s.qp_not_solved;
    d["fallback_ticks"] = s.fallback_ticks;
    d["max_tracking_error"] = s.max_tracking_error;
    d["max_torque_use"] = s.max_torque_use;
    d["real_time_factor"] = s.real_time_factor;
    d["mean_tick_microseconds"] = s.mean_tick_microseconds;
    return d;
}

/// (log columns, summary) of one run (K, Q: the LWR 4 pair's or a scene's).
template <int K, int Q>
py::tuple box_result(const box_example::ExperimentRunOf<K, Q>& run, const box_example::BoxScenario& scenario,
                     const std::string& plant, std::size_t log_every, const std::optional<double>& minimum_squeeze)
{
    ColumnSink sink(box_example::box_log_columns(run.palm_names, run.joint_count));
    box_example::emit_box_log(sink, run, log_every);
    box_example::BoxSummary summary = box_example::summarise(scenario, plant, run);
    summary.minimum_squeeze = minimum_squeeze;
    return py::make_tuple(sink.to_dict(), summary_dict(summary));
}

}  // namespace coopdyn::python::experiments
