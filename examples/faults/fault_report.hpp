// The fault campaign's outputs (docs/faults.md): the table (markdown on stdout and in
// campaign.md, CSV in campaign.csv), the Monte Carlo's pushes (monte_carlo.csv) and figures, and
// the gnuplot scripts of the plots (each scene's largest slip per cell; each scene's slip against
// the push's force).
#pragma once

#include "fault_runs.hpp"

#include "../common/csv_table.hpp"
#include "../common/plotting.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace fault_campaign {

/// The statuses seen, "name count" for each count > 0.
inline std::string statuses_seen(const CellStats& stats)
{
    std::string text;
    for (std::size_t k = 0; k < all_statuses.size(); ++k) {
        if (stats.statuses[k] > 0) {
            text += (text.empty() ? "" : ", ") + std::string(coopdyn::to_string(all_statuses[k])) + " " +
                    std::to_string(stats.statuses[k]);
        }
    }
    if (stats.saturated_ticks > 0) {
        text += ", saturated " + std::to_string(stats.saturated_ticks);
    }
    if (stats.slipping_ticks > 0) {
        text += ", slipping " + std::to_string(stats.slipping_ticks);
    }
    return text;
}

inline std::string number(double value, const char* format = "%.2f")
{
    char buffer[48];
    std::snprintf(buffer, sizeof buffer, format, value);
    return buffer;
}

/// The markdown table of the cells.
inline std::string markdown_table(const std::vector<CellResult>& results)
{
    std::string text = "| scene | plant | cell | envelope | outcome | slip mm | F mrg N | M mrg Nm | ctrl slip mm | "
                       "first report s | statuses (ticks) |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const CellResult& r : results) {
        const std::string outcome = r.dropped ? ("dropped at " + number(r.dropped_at, "%.3f") + " s" +
                                                 (r.reported() ? ", reported" : ", NOT reported"))
                                              : "held";
        text += "| " + r.scene + " | " + r.plant + " | " + r.cell.name + " | " + (r.cell.in_envelope ? "in" : "out") +
                " | " + outcome + (r.stats.finite ? "" : ", NON-FINITE torque") + " | " +
                number(1e3 * r.largest_slip) + " | " + number(r.force_margin, "%.1f") + " | " +
                number(r.moment_margin, "%.3f") + " | " + number(1e3 * r.stats.controller_slip) + " | " +
                (std::isnan(r.stats.first_report) ? std::string("-") : number(r.stats.first_report, "%.3f")) + " | " +
                statuses_seen(r.stats) + " |\n";
    }
    return text;
}

/// campaign.csv / monte_carlo.csv: one row per run.
inline void write_results_csv(const std::filesystem::path& path, const std::vector<CellResult>& results)
{
    example_common::CsvWriter csv(path);
    for (const char* column : {"scene", "plant", "cell", "class", "envelope", "held", "dropped_at_s", "reported",
                               "finite", "largest_slip_mm", "force_margin_N", "moment_margin_Nm",
                               "controller_slip_mm", "first_report_s", "saturated_ticks", "slipping_ticks",
                               "push_force_N", "push_hold_s"}) {
        csv.text(column);
    }
    for (const coopdyn::ControlStatus status : all_statuses) {
        csv.text(coopdyn::to_string(status));
    }
    csv.end_row();
    for (const CellResult& r : results) {
        csv.text(r.scene);
        csv.text(r.plant);
        csv.text(r.cell.name);
        csv.text(r.cell.fault_class);
        csv.text(r.cell.in_envelope ? "in" : "out");
        csv.number(r.dropped ? 0.0 : 1.0);
        csv.number(r.dropped_at);
        csv.number(r.reported() ? 1.0 : 0.0);
        csv.number(r.stats.finite ? 1.0 : 0.0);
        csv.number(1e3 * r.largest_slip);
        csv.number(r.force_margin);
        csv.number(r.moment_margin);
        csv.number(1e3 * r.stats.controller_slip);
        csv.number(r.stats.first_report);
        csv.number(static_cast<double>(r.stats.saturated_ticks));
        csv.number(static_cast<double>(r.stats.slipping_ticks));
        csv.number(r.push_force);
        csv.number(r.push_hold);
        for (const long count : r.stats.statuses) {
            csv.number(static_cast<double>(count));
        }
        csv.end_row();
    }
    csv.close();
}

/// The q-quantile of sorted values (nearest rank).
inline double quantile(const std::vector<double>& sorted, double q)
{
    if (sorted.empty()) {
        return std::numeric_limits<double>::quiet_NaN();
    }
    const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(sorted.size())));
    return sorted[std::min(sorted.size() - 1, rank == 0 ? 0 : rank - 1)];
}

/// The Monte Carlo's figures per scene: pushes, drops (reported), slip median / 99th percentile /
/// maximum (mm), the smallest margins.
inline std::string monte_carlo_table(const std::vector<CellResult>& pushes, const std::vector<std::string>& scene_names)
{
    std::string text = "| scene | pushes | largest force N | dropped | dropped, reported | slip median mm | slip p99 mm "
                       "| slip max mm | F mrg N | M mrg Nm |\n|---|---|---|---|---|---|---|---|---|---|\n";
    for (const std::string& scene : scene_names) {
        std::vector<double> slips;
        long dropped = 0, reported = 0;
        double force = 0.0, force_margin = std::numeric_limits<double>::infinity(), moment_margin = force_margin;
        for (const CellResult& r : pushes) {
            if (r.scene != scene) {
                continue;
            }
            slips.push_back(1e3 * r.largest_slip);
            dropped += r.dropped ? 1 : 0;
            reported += r.dropped && r.reported() ? 1 : 0;
            force = std::max(force, r.push_force);
            force_margin = std::min(force_margin, r.force_margin);
            moment_margin = std::min(moment_margin, r.moment_margin);
        }
        if (slips.empty()) {
            continue;
        }
        std::sort(slips.begin(), slips.end());
        text += "| " + scene + " | " + std::to_string(slips.size()) + " | " + number(force, "%.1f") + " | " +
                std::to_string(dropped) + " | " + std::to_string(reported) + " | " + number(quantile(slips, 0.5), "%.3f") +
                " | " + number(quantile(slips, 0.99), "%.3f") + " | " + number(slips.back(), "%.3f") + " | " +
                number(force_margin, "%.1f") + " | " + number(moment_margin, "%.3f") + " |\n";
    }
    return text;
}

/// A scene's plot data and gnuplot script: the largest slip (mm) per cell on each plant, and the
/// Monte Carlo's slip against the push's force. Returns the plot.
inline example_common::Plot write_scene_plot(const std::filesystem::path& folder, const std::string& scene,
                                             const std::vector<CellResult>& cells,
                                             const std::vector<CellResult>& pushes)
{
    const std::string stem = "faults_" + scene;
    std::string table = "# index cell mujoco_slip_mm rigid_slip_mm\n";
    std::string push_table = "# force_N slip_mm dropped\n";
    int index = 0;
    for (const CellResult& r : cells) {
        if (r.scene != scene || r.plant != "mujoco") {
            continue;
        }
        double rigid = std::numeric_limits<double>::quiet_NaN();
        for (const CellResult& other : cells) {
            if (other.scene == scene && other.plant == "rigid" && other.cell.name == r.cell.name) {
                rigid = 1e3 * other.largest_slip;
            }
        }
        table += std::to_string(index++) + " " + r.cell.name + " " + number(1e3 * r.largest_slip, "%.6f") + " " +
                 number(rigid, "%.6f") + "\n";
    }
    for (const CellResult& r : pushes) {
        if (r.scene == scene) {
            push_table += number(r.push_force, "%.4f") + " " + number(1e3 * r.largest_slip, "%.6f") + " " +
                          (r.dropped ? "1" : "0") + "\n";
        }
    }
    example_common::write_text_file(folder / (stem + "_cells.dat"), table);
    example_common::write_text_file(folder / (stem + "_pushes.dat"), push_table);
    const std::string script =
        "set terminal pngcairo size 1200,900 noenhanced\nset output '" + stem + ".png'\nset multiplot layout 2,1 title 'fault "
        "campaign: " + scene + " (docs/faults.md)'\nset style data histograms\nset style fill solid 0.6\nset logscale y"
        "\nset yrange [0.001:*]\nset ylabel 'largest slip (mm)'\nset xtics rotate by -45 font ',8'\nplot '" + stem +
        "_cells.dat' using ($3+0.001):xtic(2) title 'MuJoCo', '' using ($4+0.001) title 'rigid (welded)'\n"
        "unset style\nset style data points\nunset xtics\nset xtics\nset xlabel 'push force (N), Monte Carlo'\n"
        "plot '" + stem + "_pushes.dat' using 1:($2+0.001):($3 > 0 ? 1 : 3) pt 7 ps 0.5 lc variable title 'slip (red: dropped)'\n"
        "unset multiplot\n";
    const std::filesystem::path script_path = folder / (stem + ".gp");
    example_common::write_text_file(script_path, script);
    return {script_path, folder / (stem + ".png")};
}

}  // namespace fault_campaign
