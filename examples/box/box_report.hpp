// Output of the dual-arm box example (docs/dual-arm-box.md, "Output"): the summary numbers of a
// run, the printed table next to the paper's, the CSV log and the gnuplot scripts in the style of
// Lin et al. Figs. 6 and 8.
#pragma once

#include "box_experiment.hpp"

#include "../common/csv_table.hpp"
#include "../common/plotting.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace box_example {

/// What one run amounts to.
struct BoxSummary {
    std::string experiment;
    std::string plant;
    double simulated_seconds = 0.0;
    bool dropped = false;
    double rest_normal_predicted = 0.0;  ///< mean over palms and the first rest_window, N
    double rest_normal_measured = 0.0;
    double peak_normal_predicted = 0.0;  ///< largest normal force of either palm, N
    double peak_normal_measured = 0.0;
    double max_slip = 0.0;               ///< m
    double min_true_force_margin = 0.0;   ///< of the measured wrenches under the true friction: force rows, N
    double min_true_moment_margin = 0.0;  ///< and moment rows (torsion, centre of pressure), N m
    double max_force_error = 0.0;        ///< max |f_predicted - f_measured| over palms and ticks, N
    /// The normal force the plant needed: |f_t| / mu_true of the measured wrenches, largest over
    /// the run, against the Coulomb estimate W / (2 mu_true) of the heaviest static load
    /// (static_load: the box with its added mass, and a person's push held steady).
    double needed_normal = 0.0;
    double coulomb_estimate = 0.0;
    /// The measured minimum squeeze that still holds that load (MuJoCo plant,
    /// measure_minimum_squeeze); empty for the rigid plant or when not measured.
    std::optional<double> minimum_squeeze;
    int qp_not_solved = 0;               ///< ticks whose contact QP was not `solved`
    int fallback_ticks = 0;              ///< ticks that used the least-violating fallback
    double max_tracking_error = 0.0;     ///< m, outside the person's hold (circle); else the whole run
    double max_torque_use = 0.0;         ///< max |tau_j| / limit_j
    double real_time_factor = 0.0;       ///< simulated / wall time of the whole loop, the settle included
    double mean_tick_microseconds = 0.0; ///< the controller tick alone
};

/// The window at the start that counts as "at rest" (before any disturbance), s.
constexpr double rest_window = 0.8;

/// One run's summary (K palms, Q joints at run time: the LWR 4 pair's or a scene's).
template <int K, int Q>
BoxSummary summarise(const BoxScenario& scenario, const std::string& plant, const ExperimentRunOf<K, Q>& run)
{
    BoxSummary s;
    s.experiment = scenario.name;
    s.plant = plant;
    s.dropped = run.dropped;
    s.min_true_force_margin = s.min_true_moment_margin = std::numeric_limits<double>::infinity();
    int rest_samples = 0;
    for (const TickLogOf<K, Q>& row : run.log) {
        // A tick that computed no control (invalid_input, singular, safe_hold) has no prediction to compare:
        // its outputs are reset to zero (docs/control.md, "After a failed tick").
        const bool predicted = coopdyn::control_computed(row.status);
        const bool held_by_person = scenario.person_hold && row.time >= scenario.person_hold->start &&
                                    row.time < scenario.person_hold->start + scenario.person_hold->duration + 1.0;
        for (std::size_t i = 0; i < run.palm_count(); ++i) {
            if (row.time < rest_window && predicted) {
                s.rest_normal_predicted += row.predicted[i](2);
                s.rest_normal_measured += row.measured[i](2);
                ++rest_samples;
            }
            s.peak_normal_predicted = std::max(s.peak_normal_predicted, row.predicted[i](2));
            s.peak_normal_measured = std::max(s.peak_normal_measured, row.measured[i](2));
            s.max_slip = std::max(s.max_slip, row.slip[i]);
            s.min_true_force_margin = std::min(s.min_true_force_margin, row.measured_margins[i].force);
            s.min_true_moment_margin = std::min(s.min_true_moment_margin, row.measured_margins[i].moment);
            if (predicted) {
                const Eigen::Vector3d error = row.predicted[i].template head<3>() - row.measured[i].template head<3>();
                s.max_force_error = std::max(s.max_force_error, error.norm());
            }
            s.needed_normal =
                std::max(s.needed_normal, row.measured[i].template head<2>().norm() / scenario.plant_friction.sliding);
        }
        s.qp_not_solved += row.qp_ran && row.qp_status != coopdyn::QpStatus::solved ? 1 : 0;
        s.fallback_ticks += row.status == coopdyn::ControlStatus::friction_infeasible ? 1 : 0;
        if (!held_by_person) {
            s.max_tracking_error = std::max(s.max_tracking_error, (row.box_position - row.desired_position).norm());
        }
        s.max_torque_use = std::max(s.max_torque_use, row.torque_use);
    }
    if (rest_samples > 0) {
        s.rest_normal_predicted /= rest_samples;
        s.rest_normal_measured /= rest_samples;
    }
    s.simulated_seconds = run.log.empty() ? 0.0 : run.log.back().time + 0.001;
    // W / (K mu): the load shared equally by K palms (W / (2 mu) for a pair).
    s.coulomb_estimate =
        static_load(scenario) / (static_cast<double>(run.palm_count()) * scenario.plant_friction.sliding);
    // The whole loop's simulated time over its wall time: the settle before t = 0 is simulated and
    // timed too (bench_dual_arm_box counts it the same way).
    s.real_time_factor = run.wall_seconds > 0.0 ? run.simulated_seconds / run.wall_seconds : 0.0;
    s.mean_tick_microseconds = run.log.empty() ? 0.0 : 1e6 * run.tick_seconds / static_cast<double>(run.log.size());
    return s;
}

/// The log's columns (docs/dual-arm-box.md, "The CSV columns"): per palm, named `palm_names`, and
/// per joint, 1 to `joint_count`.
inline std::vector<std::string> box_log_columns(const std::vector<std::string>& palm_names = {"left", "right"},
                                                Eigen::Index joint_count = joints)
{
    std::vector<std::string> columns{"time", "x", "y", "z", "x_d", "y_d", "z_d", "rotation_error",
                                     "est_fx", "est_fy", "est_fz", "est_tx", "est_ty", "est_tz",
                                     "person_fx", "person_fy", "person_fz", "ax", "ay", "az"};
    const char* axes[] = {"fx", "fy", "fz", "tx", "ty", "tz"};
    for (const std::string& palm : palm_names) {
        for (const char* kind : {"pred", "meas"}) {
            for (const char* axis : axes) {
                columns.push_back(std::string(palm) + "_" + kind + "_" + axis);
            }
            columns.push_back(std::string(palm) + "_" + kind + "_force_norm");
        }
        columns.push_back(std::string(palm) + "_true_force_margin");
        columns.push_back(std::string(palm) + "_true_moment_margin");
        columns.push_back(std::string(palm) + "_slip");
    }
    for (const char* name : {"predicted_force_margin", "predicted_moment_margin", "status", "qp_status", "qp_iterations"}) {
        columns.emplace_back(name);
    }
    for (const char* kind : {"tau_u", "tau_c"}) {
        for (Eigen::Index j = 1; j <= joint_count; ++j) {
            columns.push_back(std::string(kind) + "_" + std::to_string(j));
        }
    }
    columns.emplace_back("torque_use");
    columns.emplace_back("box_mass");
    return columns;
}

/// Writes every `every`-th tick of the run (--log-every; ticks 0, every, 2 every, ...) to `sink`, in
/// box_log_columns' order, one end_row() per tick: the file is thinned, the run (and the summary
/// computed from it) is not. `sink` has number(double), text(string) and end_row(): the CSV writer
/// here, numpy columns in the Python module (python/src/experiments/, docs/python.md).
template <int K, int Q, typename Sink>
void emit_box_log(Sink& sink, const ExperimentRunOf<K, Q>& run, std::size_t every = 1)
{
    const auto numbers = [&sink](const auto& vector) {
        for (Eigen::Index k = 0; k < vector.size(); ++k) {
            sink.number(vector(k));
        }
    };
    for (std::size_t tick = 0; tick < run.log.size(); tick += std::max<std::size_t>(every, 1)) {
        const TickLogOf<K, Q>& row = run.log[tick];
        sink.number(row.time);
        numbers(row.box_position);
        numbers(row.desired_position);
        sink.number(row.orientation_error);
        numbers(row.external_wrench);
        numbers(row.disturbance.template head<3>());
        numbers(row.box_acceleration);
        for (std::size_t i = 0; i < run.palm_count(); ++i) {
            numbers(row.predicted[i]);
            sink.number(row.predicted[i].template head<3>().norm());
            numbers(row.measured[i]);
            sink.number(row.measured[i].template head<3>().norm());
            sink.number(row.measured_margins[i].force);
            sink.number(row.measured_margins[i].moment);
            sink.number(row.slip[i]);
        }
        sink.number(row.predicted_force_margin);
        sink.number(row.predicted_moment_margin);
        sink.text(coopdyn::to_string(row.status));
        sink.text(row.qp_ran ? coopdyn::to_string(row.qp_status) : "not_run");  // no stale status
        sink.number(row.qp_iterations);
        numbers(row.motion_torque);
        numbers(row.squeeze_torque);
        sink.number(row.torque_use);
        sink.number(row.box_mass);
        sink.end_row();
    }
}

/// The run's CSV log (docs/dual-arm-box.md, "The CSV columns"): the header, then emit_box_log.
template <int K, int Q>
void write_box_log(const std::filesystem::path& path, const ExperimentRunOf<K, Q>& run, std::size_t every = 1)
{
    example_common::CsvWriter csv(path);
    for (const std::string& column : box_log_columns(run.palm_names, run.joint_count)) {
        csv.text(column);
    }
    csv.end_row();
    emit_box_log(csv, run, every);
    csv.close();
}

/// The box's height against the desired one and, since the controller does not compensate the
/// box's weight (its mass is unknown to it), the height the impedance settles at: z_d - m g / K_z,
/// the static sag under the scenario's box mass and the controller's translational stiffness.
inline std::string box_height_plot(const BoxScenario& scenario, const std::string& csv_name)
{
    const auto column = [](const char* name) { return std::string("(column('") + name + "'))"; };
    const double stiffness = scenario.controller.translational_stiffness;
    // The offsets keep the desired and the sag line off the frame, the key off the lines.
    std::string s = "set ylabel 'z [m]'\nset offsets 0, 0, graph 0.05, graph 0.05\nset key right center\n";
    std::string sag_line;
    if (stiffness > 0.0) {
        const double sag = scenario.box_mass * 9.81 / stiffness;
        char text[160];
        std::snprintf(text, sizeof text, "weight not compensated: expected static sag m g / K_z = %.3g kg * 9.81 / %.4g "
                      "N/m = %.1f mm", scenario.box_mass, stiffness, 1e3 * sag);
        s += std::string("set title '") + text + "'\n";
        char offset[64];
        std::snprintf(offset, sizeof offset, "%.10g", sag);
        sag_line = ", '' using " + column("time") + ":(" + column("z_d") + " - " + offset +
                   ") with lines ls 5 dt 3 title 'desired - m g / K_z (expected sag)'";
    } else {
        s += "set title 'weight not compensated (K_z = 0: no stiffness to hold it)'\n";
    }
    s += "plot '" + csv_name + "' using " + column("time") + ":" + column("z") +
         " with lines ls 1 title 'box height', '' using " + column("time") + ":" + column("z_d") +
         " with lines ls 4 title 'desired'" + sag_line + "\n";
    s += "unset title\nunset offsets\nset key top right\n";
    return s;
}

/// Fig. 6's plot for any K: each palm's expected (blue) and measured (red) contact-force norm; the
/// first two palms solid and dashed (ls 1-4), further ones in dash types of their own.
inline std::string force_norm_plot(const std::string& csv_name, const std::vector<std::string>& palm_names)
{
    const auto column = [](const std::string& name) { return "(column('" + name + "'))"; };
    std::string s = "plot '" + csv_name + "'";
    for (std::size_t i = 0; i < palm_names.size(); ++i) {
        const std::string& name = palm_names[i];
        const std::string label = i == 0 ? name + " palm" : name;
        const std::string expected = i < 2 ? "ls " + std::to_string(2 * i + 1)
                                           : "lc rgb '#1f77b4' lw 1.5 dt " + std::to_string(i + 1);
        const std::string measured = i < 2 ? "ls " + std::to_string(2 * i + 2)
                                           : "lc rgb '#d62728' lw 1.2 dt " + std::to_string(i + 1);
        s += std::string(i == 0 ? "" : ", ''") + " using " + column("time") + ":" + column(name + "_pred_force_norm") +
             " with lines " + expected + " title 'expected (" + label + ")', '' using " + column("time") + ":" +
             column(name + "_meas_force_norm") + " with lines " + measured + " title 'measured (" + label + ")'";
    }
    return s + "\n";
}

/// The gnuplot script of one run: Fig. 6's expected (blue) and measured (red) contact-force norm
/// of each palm over time, plus what disturbed the box; for the circle, Fig. 8's y and z tracking
/// (solid: the box, dashed: desired) above the force norms.
inline std::string box_plot_script(const BoxScenario& scenario, const std::string& plant, const std::string& csv_name,
                                   const std::string& png_name,
                                   const std::vector<std::string>& palm_names = {"left", "right"})
{
    const bool circle = scenario.experiment == Experiment::circle;
    std::string s;
    s += "# Generated by dual_arm_box. Rerun with: gnuplot " + png_name.substr(0, png_name.size() - 4) + ".gp\n";
    s += "set terminal pngcairo size 1000," + std::string(circle ? "1000" : "750") + " font 'sans,10'\n";
    s += "set output '" + png_name + "'\n";
    s += "set termoption noenhanced\n";  // "add_mass" is a name, not a subscript
    s += "set datafile separator ','\nset grid\nset key top right\nset xlabel 'time [s]'\n";
    s += "set style line 1 lc rgb '#1f77b4' lw 1.5\nset style line 2 lc rgb '#d62728' lw 1.2\n";
    s += "set style line 3 lc rgb '#1f77b4' lw 1.5 dt 2\nset style line 4 lc rgb '#d62728' lw 1.2 dt 2\n";
    s += "set style line 5 lc rgb '#2ca02c' lw 1.5\n";
    s += "set multiplot layout " + std::string(circle ? "3" : "2") + ",1 title 'coopdyn dual-arm box, " +
         scenario.name + " (" + plant + " plant)'\n";
    const auto column = [](const char* name) { return std::string("(column('") + name + "'))"; };
    if (circle) {
        for (const char* axis : {"y", "z"}) {
            const std::string desired = std::string(axis) + "_d";
            s += std::string("set ylabel '") + axis + " [m]'\n";
            s += "plot '" + csv_name + "' using " + column("time") + ":" + column(axis) +
                 " with lines ls 1 title 'box', '' using " + column("time") + ":" + column(desired.c_str()) +
                 " with lines ls 4 title 'desired'\n";
        }
    }
    s += "set ylabel 'contact force norm [N]'\n";
    s += force_norm_plot(csv_name, palm_names);
    if (!circle) {
        if (scenario.experiment == Experiment::add_mass) {
            s += "set ylabel 'box mass [kg]'\n";
            s += "plot '" + csv_name + "' using " + column("time") + ":" + column("box_mass") +
                 " with lines ls 5 title 'box mass (unknown to the controller)'\n";
        } else {
            s += box_height_plot(scenario, csv_name);
        }
    }
    s += "unset multiplot\n";
    return s;
}

inline std::string format_optional(const char* pattern, const std::optional<double>& value)
{
    if (!value) {
        return "-";
    }
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, pattern, *value);
    return buffer;
}

/// The printed table: one row per run, the paper's numbers alongside.
inline void print_box_table(const std::vector<std::pair<BoxScenario, BoxSummary>>& runs)
{
    std::printf("\n%-9s %-7s %9s %9s %6s %9s %9s %6s %8s %8s %8s %9s %8s %9s %6s %4s %6s\n", "", "", "rest N", "meas", "paper",
                "peak N", "meas", "paper", "slip mm", "F mrg N", "M mrg Nm", "needed N", "holds N", "W/(K mu)", "track",
                "QP", "RTF");
    for (const auto& [scenario, s] : runs) {
        std::printf("%-9s %-7s %9.1f %9.1f %6s %9.1f %9.1f %6s %8.3f %8.2f %8.3f %9.1f %8s %9.1f %6.3f %4d %6.0f%s\n",
                    s.experiment.c_str(), s.plant.c_str(), s.rest_normal_predicted, s.rest_normal_measured,
                    format_optional("%.0f", scenario.paper.squeeze_at_rest).c_str(), s.peak_normal_predicted,
                    s.peak_normal_measured, format_optional("%.0f", scenario.paper.squeeze_pushed).c_str(),
                    1e3 * s.max_slip, s.min_true_force_margin, s.min_true_moment_margin, s.needed_normal,
                    format_optional("%.1f", s.minimum_squeeze).c_str(), s.coulomb_estimate, s.max_tracking_error,
                    s.qp_not_solved + s.fallback_ticks, s.real_time_factor, s.dropped ? "  DROPPED" : "");
    }
}

}  // namespace box_example
