// --identify-log of the two-arm beam program (docs/two-arm-beam.md, "Identifying real logs"): the
// apparent impedance identified from a CSV log alone (this program's or a real experiment's),
// next to the scenario's nominal values when a scenario is given. Split from two_arm_beam.cpp,
// which runs the experiments.
#pragma once

#include "beam_report.hpp"
#include "scenario.hpp"

#include "../common/csv_table.hpp"

#include <coopdyn/coopdyn.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace beam_example {

using example_common::CsvTable;

/// The signals of a log for --identify-log: the sample period, the wrench h and displacement x
/// (6 x samples) and the axes that have both, and the columns' prefix (ident_ or meas_).
struct LogSignals {
    double period = 0.0;
    Eigen::Index samples = 0;
    std::string prefix;
    Eigen::Matrix<double, 6, Eigen::Dynamic> h, x;
    std::array<bool, 6> axes{};
};

/// Reads and checks the log of --identify-log (uniform time stamps, at least one usable axis).
inline LogSignals read_log(const std::string& log_path)
{
    const CsvTable table(log_path);
    if (!table.has("time")) {
        throw std::runtime_error(log_path + ": needs a 'time' column (seconds)");
    }
    const std::vector<double> time = table.numbers("time");
    if (time.size() < 10) {
        throw std::runtime_error(log_path + ": needs at least 10 samples");
    }
    const double period = (time.back() - time.front()) / static_cast<double>(time.size() - 1);
    for (std::size_t n = 1; n < time.size(); ++n) {
        if (!(std::abs(time[n] - time[n - 1] - period) <= 1e-3 * period)) {
            throw std::runtime_error(log_path + ": the time stamps are not uniform (row " +
                                     std::to_string(n + 1) + "); resample the log to a fixed period first");
        }
    }
    // A log written by this program has the signals its identification used (ident_*: the
    // combination of its excitation runs); a real log has the measurements (meas_*).
    const bool own_log = table.has("ident_fx");
    const std::string prefix = own_log ? "ident_" : "meas_";
    std::array<std::string, 6> wrench, displacement;
    const std::array<const char*, 6> wrench_names{"fx", "fy", "fz", "tx", "ty", "tz"};
    const std::array<const char*, 6> displacement_names{"disp_x", "disp_y", "disp_z", "rot_x", "rot_y", "rot_z"};
    for (std::size_t axis = 0; axis < 6; ++axis) {
        wrench[axis] = prefix + wrench_names[axis];
        displacement[axis] = prefix + displacement_names[axis];
    }
    const auto samples = static_cast<Eigen::Index>(time.size());
    LogSignals signals;
    signals.period = period;
    signals.samples = samples;
    signals.prefix = prefix;
    Eigen::Matrix<double, 6, Eigen::Dynamic>& h = signals.h;
    Eigen::Matrix<double, 6, Eigen::Dynamic>& x = signals.x;
    h.setZero(6, samples);
    x.setZero(6, samples);
    std::array<bool, 6>& axes = signals.axes;
    for (std::size_t axis = 0; axis < 6; ++axis) {
        if (!table.has(wrench[axis]) || !table.has(displacement[axis])) {
            continue;
        }
        const std::vector<double> f = table.numbers(wrench[axis]);
        const std::vector<double> p = table.numbers(displacement[axis]);
        const bool usable = std::all_of(f.begin(), f.end(), [](double v) { return std::isfinite(v); }) &&
                            std::all_of(p.begin(), p.end(), [](double v) { return std::isfinite(v); }) &&
                            std::any_of(f.begin(), f.end(), [](double v) { return v != 0.0; });
        if (!usable) {
            continue;
        }
        for (Eigen::Index n = 0; n < samples; ++n) {
            h(static_cast<Eigen::Index>(axis), n) = f[static_cast<std::size_t>(n)];
            x(static_cast<Eigen::Index>(axis), n) = p[static_cast<std::size_t>(n)];
        }
        axes[axis] = true;
    }
    if (std::none_of(axes.begin(), axes.end(), [](bool a) { return a; })) {
        throw std::runtime_error(log_path + ": no axis has both a non-zero wrench column (" + prefix +
                                 "fx .. " + prefix + "tz) and a displacement column (" + prefix + "disp_x .. " +
                                 prefix + "rot_z) with finite values");
    }
    return signals;
}

/// Theorem 2's impedance at the scenario's equilibrium.
inline coopdyn::ApparentImpedance<double> nominal_impedance(const Scenario& scenario)
{
    const coopdyn::ImpedanceModelX model(scenario.object, scenario.arms, scenario.gravity);
    coopdyn::Data<coopdyn::ImpedanceModelX> data(model);
    coopdyn::RigidBodyState<double> state;
    state.pose = scenario.equilibrium;
    coopdyn::grasp_kinematics(model, data, state);
    return coopdyn::apparent_impedance(model, data);
}

/// --identify-log: the identification alone, on a log written by this program or by a real
/// experiment (docs/two-arm-beam.md, "Identifying real logs").
inline int identify_log(const std::string& log_path, const Scenario* scenario)
{
    const LogSignals signals = read_log(log_path);
    const double period = signals.period;
    const Eigen::Index samples = signals.samples;
    const std::string& prefix = signals.prefix;
    const std::array<bool, 6>& axes = signals.axes;
    const coopdyn::DiagonalImpedanceFit fit = coopdyn::identify_diagonal_impedance(signals.x, signals.h, period, {}, axes);

    coopdyn::ApparentImpedance<double> nominal;
    if (scenario != nullptr) {
        nominal = nominal_impedance(*scenario);
    }
    std::printf("identification of %s: %lld samples at %.6g Hz, columns %s*\n", log_path.c_str(),
                static_cast<long long>(samples), 1.0 / period, prefix.c_str());
    std::printf("  %-6s %-18s %15s %13s %11s %14s\n", "axis", "parameter", "identified",
                scenario != nullptr ? "nominal" : "", scenario != nullptr ? "error" : "", "output MSE");
    for (std::size_t axis = 0; axis < 6; ++axis) {
        if (!axes[axis]) {
            continue;
        }
        const coopdyn::ImpedanceFit& axis_fit = fit.axes[axis];
        for (int parameter = 0; parameter < 3; ++parameter) {
            const ParameterRow names = parameter_row(parameter, axis);
            const double value = parameter == 0 ? axis_fit.mass : parameter == 1 ? axis_fit.damping : axis_fit.stiffness;
            const auto i = static_cast<Eigen::Index>(axis);
            const double reference = parameter == 0   ? nominal.inertia(i, i)
                                     : parameter == 1 ? nominal.damping(i, i)
                                                      : nominal.stiffness(i, i);
            const std::string label = std::string(names.name) + " [" + names.unit + "]";
            std::printf("  %-6s %-18s %15.7g %13s %11s %14s\n", axis_names[axis], label.c_str(), value,
                        scenario != nullptr ? format("%.6g", reference).c_str() : "",
                        scenario != nullptr ? percent(relative_error(value, reference)).c_str() : "",
                        parameter == 0 ? format("%.3g", axis_fit.mean_squared_output_error).c_str() : "");
        }
    }
    return 0;
}

}  // namespace beam_example
