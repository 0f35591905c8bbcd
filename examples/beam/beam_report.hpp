// Output of the two-arm beam example: the printed tables, the CSV logs and the gnuplot plots
// (paper Figs. 5-7 style). Column names and units are documented in docs/two-arm-beam.md.
#pragma once

#include "beam_experiment.hpp"
#include "scenario.hpp"

#include "../common/csv_table.hpp"
#include "../common/plotting.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace beam_example {

/// Relative error (identified - reference) / reference.
inline double relative_error(double value, double reference) { return (value - reference) / reference; }

/// Noise-free identification must match to 4 significant digits: relative error below 5e-5.
inline constexpr double four_digit_tolerance = 5e-5;

/// Parameter rows of a table: name and unit per axis.
struct ParameterRow {
    const char* name;
    const char* unit;
};
inline ParameterRow parameter_row(int parameter, std::size_t axis)
{
    const bool rotation = axis >= 3;
    switch (parameter) {
    case 0: return rotation ? ParameterRow{"J", "kg m^2"} : ParameterRow{"m", "kg"};
    case 1: return rotation ? ParameterRow{"delta", "N m s/rad"} : ParameterRow{"d", "N s/m"};
    default: return rotation ? ParameterRow{"kappa", "N m/rad"} : ParameterRow{"k", "N/m"};
    }
}
inline const char* parameter_key(int parameter)
{
    return parameter == 0 ? "inertia" : parameter == 1 ? "damping" : "stiffness";
}

/// The paper's reference block for an experiment, if the scenario has one.
inline const PaperExperiment* paper_reference(const Scenario& scenario, const std::string& id)
{
    if (!scenario.paper) {
        return nullptr;
    }
    const std::optional<PaperExperiment>& entry = id == "x"       ? scenario.paper->translation_x
                                                  : id == "rot_z" ? scenario.paper->rotation_z
                                                                  : scenario.paper->se3;
    return entry ? &*entry : nullptr;
}

/// Value of parameter `parameter` (0 inertia, 1 damping, 2 stiffness) for the `slot`-th
/// identified axis of an experiment from reference values.
inline std::optional<double> reference_value(const std::optional<ImpedanceValues>& values, int parameter,
                                             std::size_t slot)
{
    if (!values) {
        return std::nullopt;
    }
    const std::vector<double>& list =
        parameter == 0 ? values->inertia : parameter == 1 ? values->damping : values->stiffness;
    if (slot >= list.size()) {
        return std::nullopt;
    }
    return list[slot];
}

/// One line of the comparison: everything the table and the summary CSV show.
struct ComparisonRow {
    std::size_t axis = 0;
    int parameter = 0;
    std::optional<double> paper_nominal;
    double nominal = 0.0;  ///< Theorem 2
    double identified = 0.0;
    std::optional<double> paper_identified;
    double mean_squared_output_error = 0.0;
};

inline std::vector<ComparisonRow> comparison_rows(const Scenario& scenario, const ExperimentResult& result)
{
    const PaperExperiment* paper = paper_reference(scenario, result.spec.id);
    std::vector<ComparisonRow> rows;
    std::size_t slot = 0;
    for (std::size_t axis = 0; axis < 6; ++axis) {
        if (!result.spec.axes[axis]) {
            continue;
        }
        const auto index = static_cast<Eigen::Index>(axis);
        const coopdyn::ImpedanceFit& fit = result.fit.axes[axis];
        for (int parameter = 0; parameter < 3; ++parameter) {
            ComparisonRow row;
            row.axis = axis;
            row.parameter = parameter;
            const coopdyn::Matrix6<double>& nominal = parameter == 0   ? result.nominal.inertia
                                                      : parameter == 1 ? result.nominal.damping
                                                                       : result.nominal.stiffness;
            row.nominal = nominal(index, index);
            row.identified = parameter == 0 ? fit.mass : parameter == 1 ? fit.damping : fit.stiffness;
            if (paper != nullptr) {
                row.paper_nominal = reference_value(paper->nominal, parameter, slot);
                row.paper_identified = reference_value(paper->identified, parameter, slot);
            }
            row.mean_squared_output_error = fit.mean_squared_output_error;
            rows.push_back(row);
        }
        ++slot;
    }
    return rows;
}

inline std::string format(const char* pattern, double value)
{
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, pattern, value);
    return buffer;
}

inline std::string format_optional(const char* pattern, const std::optional<double>& value)
{
    return value ? format(pattern, *value) : std::string("-");
}

inline std::string percent(double fraction) { return format("%+.2g %%", 100.0 * fraction); }

/// The table's heading: the experiment, the excitation and the sensors.
inline void print_heading(const Scenario& scenario, const ExperimentResult& result, const RunOptions& options,
                          int number, int count)
{
    std::printf("\nExperiment %d of %d: %s  [scenario %s]\n", number, count, result.spec.title.c_str(),
                scenario.name.c_str());
    std::printf("  excitation: %s%s, force %.3g N, torque %.3g N m; log %.4g s at %.4g Hz%s; sensors: %s\n",
                options.excitation == ExcitationKind::multisine ? "multisine (amplitudes RMS)" : "pushes (amplitudes peak)",
                result.runs == 4   ? ", runs +-u, +-2u (identified: odd parts extrapolated to zero amplitude)"
                : result.runs == 2 ? ", runs +-u (identified: odd part)"
                                   : ", single run",
                result.excitation_force, result.excitation_torque, options.duration, 1.0 / scenario.time_step,
                result.warmup_seconds > 0.0 ? format(" after %.4g s of warm-up", result.warmup_seconds).c_str() : "",
                options.sensors.enabled
                    ? (format("noise %.3g N", options.sensors.force_rms) + format(" / %.3g N m", options.sensors.torque_rms) +
                       format(" / %.3g m", options.sensors.position_rms) +
                       format(" / %.3g rad RMS", options.sensors.angle_rms) +
                       (options.sensors.lowpass_hz > 0.0 ? format(", %.4g Hz force low-pass", options.sensors.lowpass_hz)
                                                         : std::string(", no low-pass")))
                          .c_str()
                    : "ideal (noise-free)");
}

/// The table's rows, each parameter against Theorem 2 (and the paper's values), and the fit's
/// output errors. Returns the largest relative error against Theorem 2.
inline double print_rows(const std::vector<ComparisonRow>& rows, const ExperimentResult& result,
                         const PaperExperiment* paper)
{
    const bool has_paper = paper != nullptr;
    std::printf("  %-6s %-18s %13s %13s %15s %11s %13s %11s\n", "axis", "parameter",
                has_paper ? "paper nominal" : "", "nominal", "identified", "error", has_paper ? "paper ident." : "",
                has_paper ? "paper error" : "");
    std::printf("  %-6s %-18s %13s %13s %15s %11s %13s %11s\n", "", "",
                has_paper ? result.spec.paper_nominal_equation.c_str() : "", "(Theorem 2)", "(this sim.)", "",
                has_paper ? (result.spec.paper_identified_equation + " robots").c_str() : "", "");
    double worst = 0.0;
    for (const ComparisonRow& row : rows) {
        const ParameterRow names = parameter_row(row.parameter, row.axis);
        const std::string label = std::string(names.name) + " [" + names.unit + "]";
        const double error = relative_error(row.identified, row.nominal);
        worst = std::max(worst, std::abs(error));
        std::printf("  %-6s %-18s %13s %13.6g %15.7g %11s %13s %11s\n", axis_names[row.axis], label.c_str(),
                    format_optional("%.4g", row.paper_nominal).c_str(), row.nominal, row.identified,
                    percent(error).c_str(), format_optional("%.4g", row.paper_identified).c_str(),
                    row.paper_identified ? percent(relative_error(*row.paper_identified, row.nominal)).c_str() : "-");
    }
    std::printf("  mean squared output error of the identified model:");
    for (std::size_t axis = 0; axis < 6; ++axis) {
        if (result.spec.axes[axis]) {
            std::printf(" %s %.3g %s;", axis_names[axis], result.fit.axes[axis].mean_squared_output_error,
                        axis < 3 ? "m^2" : "rad^2");
        }
    }
    if (paper != nullptr && paper->mean_squared_output_error) {
        std::printf(" paper (real robots): %.3g %s", *paper->mean_squared_output_error,
                    result.spec.id == "rot_z" ? "rad^2" : "m^2");
    }
    std::printf("\n");
    return worst;
}

/// The verdict against Theorem 2, per block (translations, rotations) when it fails.
inline void print_verdict(const std::vector<ComparisonRow>& rows, const ExperimentResult& result, const RunOptions& options,
                          double worst)
{
    double worst_block[2] = {0.0, 0.0};
    int rotation_axes = 0;
    for (const ComparisonRow& row : rows) {
        const double error = std::abs(relative_error(row.identified, row.nominal));
        worst_block[row.axis < 3 ? 0 : 1] = std::max(worst_block[row.axis < 3 ? 0 : 1], error);
        rotation_axes += row.axis >= 3 && row.parameter == 0 ? 1 : 0;
    }
    const double tolerance = options.sensors.enabled ? 0.05 : four_digit_tolerance;
    const char* criterion = options.sensors.enabled ? "within 5 %" : "4 significant digits (relative error < 5e-5)";
    std::printf("  largest relative error against Theorem 2: %.2g", worst);
    if (worst < tolerance) {
        std::printf(" -> %s\n", criterion);
    } else {
        std::printf(" -> NOT %s", criterion);
        if (rows.front().axis < 3 && rows.back().axis >= 3) {
            std::printf(" (translations %.2g, rotations %.2g)", worst_block[0], worst_block[1]);
        }
        std::printf("\n");
        if (!options.sensors.enabled && rotation_axes > 1 && worst_block[0] < tolerance &&
            result.nominal_coupling < 1e-12) {
            std::printf("  note: rotations about several axes at once couple at second and third order (gyroscopic\n"
                        "  terms, the rotation-vector kinematics, the springs' geometry), which a diagonal linear model\n"
                        "  cannot represent; the error grows with the rotation amplitude (--torque)%s\n",
                        result.runs == 4 ? "" : ";\n  the default excitation runs (--runs 4) cancel it");
        }
    }
}

/// Whether the axes are decoupled (Corollary 1), and the motion in the axes not excited.
inline void print_coupling(const ExperimentResult& result)
{
    if (result.nominal_coupling < 1e-12) {
        std::printf("  axes decoupled: largest off-diagonal of M, D, K (Theorem 2, normalised) %.1g (Corollary 1)",
                    result.nominal_coupling);
    } else {
        std::printf("  axes COUPLED: largest off-diagonal of M, D, K (Theorem 2, normalised) %.3g; the diagonal\n"
                    "  model of the paper does not hold for this set-up, so its fit differs from the diagonal of Theorem 2",
                    result.nominal_coupling);
    }
    if (std::isfinite(result.cross_axis_motion)) {
        std::printf("; motion in the other axes %.2g of the excited one (energy ratio)", result.cross_axis_motion);
    }
    std::printf("\n");
}

/// Prints the table of one experiment to stdout.
inline void print_table(const Scenario& scenario, const ExperimentResult& result, const RunOptions& options,
                        int number, int count)
{
    const std::vector<ComparisonRow> rows = comparison_rows(scenario, result);
    const PaperExperiment* paper = paper_reference(scenario, result.spec.id);
    print_heading(scenario, result, options, number, count);
    const double worst = print_rows(rows, result, paper);
    print_verdict(rows, result, options, worst);
    print_coupling(result);
}

// ---------------------------------------------------------------------------------------------
// CSV

/// Column names of an experiment log, in file order.
inline std::vector<std::string> log_columns(Eigen::Index arms)
{
    std::vector<std::string> columns{"time"};
    const std::array<const char*, 6> wrench{"fx", "fy", "fz", "tx", "ty", "tz"};
    const std::array<const char*, 6> displacement{"disp_x", "disp_y", "disp_z", "rot_x", "rot_y", "rot_z"};
    for (const char* name : wrench) {
        columns.push_back(std::string("dist_") + name);
    }
    for (const char* name : wrench) {
        columns.push_back(std::string("meas_") + name);
    }
    for (const char* name : {"pos_x", "pos_y", "pos_z", "quat_x", "quat_y", "quat_z", "quat_w"}) {
        columns.push_back(name);
    }
    for (const char* name : {"vel_x", "vel_y", "vel_z", "omega_x", "omega_y", "omega_z"}) {
        columns.push_back(name);
    }
    for (const char* name : displacement) {
        columns.push_back(name);
    }
    for (const char* name : displacement) {
        columns.push_back(std::string("meas_") + name);
    }
    for (const char* name : displacement) {
        columns.push_back(std::string("model_") + name);
    }
    for (const char* name : wrench) {
        columns.push_back(std::string("ident_") + name);
    }
    for (const char* name : displacement) {
        columns.push_back(std::string("ident_") + name);
    }
    for (Eigen::Index i = 0; i < arms; ++i) {
        const std::string arm = "arm" + std::to_string(i) + "_";
        for (const char* part : {"", "int_", "ext_"}) {
            for (const char* name : wrench) {
                columns.push_back(arm + part + name);
            }
        }
    }
    return columns;
}

using example_common::CsvWriter;

/// Writes the log's steps 0, every, 2 every, ... (every >= 1; --log-every) to `sink`, in
/// log_columns' order, one end_row() per step: the file is thinned, the log itself (and all that was
/// computed from it) is not. `sink` has number(double) and end_row(): the CSV writer here, numpy
/// columns in the Python module (python/src/experiments/, docs/python.md).
template <typename Sink> void emit_log(Sink& sink, const ExperimentLog& log, Eigen::Index every = 1)
{
    every = std::max<Eigen::Index>(every, 1);
    for (Eigen::Index n = 0; n < log.samples(); n += every) {
        sink.number(log.time(n));
        const auto block = [&](const auto& matrix) {
            for (Eigen::Index row = 0; row < matrix.rows(); ++row) {
                sink.number(matrix(row, n));
            }
        };
        block(log.applied);
        block(log.measured_wrench);
        block(log.pose);
        block(log.twist);
        block(log.displacement);
        block(log.measured_displacement);
        block(log.model_displacement);
        block(log.identification_wrench);
        block(log.identification_displacement);
        block(log.arm_wrenches);
        sink.end_row();
    }
}

/// The log's CSV file (docs/two-arm-beam.md): the header, then emit_log.
inline void write_log_csv(const std::filesystem::path& path, const ExperimentLog& log, Eigen::Index every = 1)
{
    CsvWriter csv(path);
    for (const std::string& column : log_columns(log.arm_wrenches.rows() / 18)) {
        csv.text(column);
    }
    csv.end_row();
    emit_log(csv, log, every);
    csv.close();
}

/// Columns of the identification summary file.
inline const std::vector<std::string>& summary_columns()
{
    static const std::vector<std::string> columns{
        "scenario", "experiment", "axis", "parameter", "unit", "paper_nominal", "nominal", "identified",
        "relative_error", "paper_identified", "paper_relative_error", "mean_squared_output_error",
        "paper_mean_squared_output_error", "noise", "duration", "converged"};
    return columns;
}

/// The identification summary's rows (summary_columns' order, one end_row() per row) to `sink`
/// (number, optional, text, end_row: the CSV writer, or the Python module's numpy columns).
template <typename Sink>
void emit_summary(Sink& sink, const Scenario& scenario, const std::vector<ExperimentResult>& results,
                  const RunOptions& options)
{
    const std::array<const char*, 6> axis_keys{"x", "y", "z", "rot_x", "rot_y", "rot_z"};
    for (const ExperimentResult& result : results) {
        const PaperExperiment* paper = paper_reference(scenario, result.spec.id);
        for (const ComparisonRow& row : comparison_rows(scenario, result)) {
            sink.text(scenario.name);
            sink.text(result.spec.id);
            sink.text(axis_keys[row.axis]);
            sink.text(parameter_key(row.parameter));
            sink.text(parameter_row(row.parameter, row.axis).unit);
            sink.optional(row.paper_nominal);
            sink.number(row.nominal);
            sink.number(row.identified);
            sink.number(relative_error(row.identified, row.nominal));
            sink.optional(row.paper_identified);
            sink.optional(row.paper_identified ? std::optional<double>(relative_error(*row.paper_identified, row.nominal))
                                               : std::nullopt);
            sink.number(row.mean_squared_output_error);
            sink.optional(paper != nullptr && result.spec.id != "se3" ? paper->mean_squared_output_error
                                                                      : std::nullopt);
            sink.text(options.sensors.enabled ? "1" : "0");
            sink.number(options.duration);
            sink.text(result.fit.axes[row.axis].converged ? "1" : "0");
            sink.end_row();
        }
    }
}

inline void write_summary_csv(const std::filesystem::path& path, const Scenario& scenario,
                              const std::vector<ExperimentResult>& results, const RunOptions& options)
{
    CsvWriter csv(path);
    for (const std::string& column : summary_columns()) {
        csv.text(column);
    }
    csv.end_row();
    emit_summary(csv, scenario, results, options);
    csv.close();
}

// ---------------------------------------------------------------------------------------------
// Plots (gnuplot)

// Finding and running gnuplot: examples/common/plotting.hpp.

/// gnuplot script for one experiment: for each excited axis, the applied (measured) wrench and
/// the measured and model-predicted displacement (mm or mrad), in the style of Figs. 5-7.
inline std::string gnuplot_script(const std::string& csv_name, const std::string& png_name, const Scenario& scenario,
                                  const ExperimentResult& result, bool noise)
{
    const std::array<const char*, 6> wrench{"fx", "fy", "fz", "tx", "ty", "tz"};
    const std::array<const char*, 6> displacement{"disp_x", "disp_y", "disp_z", "rot_x", "rot_y", "rot_z"};
    const std::array<const char*, 6> wrench_labels{"f_x [N]", "f_y [N]", "f_z [N]", "t_x [N m]", "t_y [N m]", "t_z [N m]"};
    const std::array<const char*, 6> pose_labels{"x [mm]", "y [mm]", "z [mm]", "rot_x [mrad]", "rot_y [mrad]", "rot_z [mrad]"};
    std::vector<std::size_t> axes;
    for (std::size_t axis = 0; axis < 6; ++axis) {
        if (result.spec.axes[axis]) {
            axes.push_back(axis);
        }
    }
    const bool single = axes.size() == 1;
    std::string s;
    s += "# Generated by two_arm_beam. Rerun with: gnuplot " + png_name.substr(0, png_name.size() - 4) + ".gp\n";
    s += "set terminal pngcairo size " + std::string(single ? "1000,700" : "1400,1800") + " font 'sans,10'\n";
    s += "set output '" + png_name + "'\n";
    s += "set datafile separator ','\n";
    s += "set grid\nset key top right\n";
    s += "set style line 1 lc rgb '#1f77b4' lw 1.2\n";
    s += "set style line 2 lc rgb '#d62728' lw 2 dt 2\n";
    s += "set style line 3 lc rgb '#2ca02c' lw 1.2\n";
    const std::string title = "coopdyn, scenario " + scenario.name + ": " + result.spec.title + " (" +
                              (noise ? "with sensor noise and low-pass" : "noise-free") + ")";
    s += "set multiplot layout " + std::to_string(single ? 2 : axes.size()) + "," + (single ? "1" : "2") +
         " title '" + title + "'\n";
    for (const std::size_t axis : axes) {
        const std::string w = std::string("meas_") + wrench[axis];
        const std::string measured = std::string("meas_") + displacement[axis];
        const std::string model = std::string("model_") + displacement[axis];
        s += "set xlabel 'time [s]'\n";
        s += std::string("set ylabel '") + wrench_labels[axis] + "'\n";
        s += "plot '" + csv_name + "' using (column('time')):(column('" + w +
             "')) with lines ls 3 title 'applied wrench (measured)'\n";
        s += std::string("set ylabel '") + pose_labels[axis] + "'\n";
        s += "plot '" + csv_name + "' using (column('time')):(1e3*column('" + measured +
             "')) with lines ls 1 title 'measured', '' using (column('time')):(1e3*column('" + model +
             "')) with lines ls 2 title 'identified model'\n";
    }
    s += "unset multiplot\n";
    return s;
}

}  // namespace beam_example
