// The fault campaign (examples/faults, docs/faults.md) end to end, short: the program itself runs
// its --short campaign (four cells on the LWR 4 pair, both plants, 1.5 s, and five Monte Carlo
// pushes) as a user would, and its CSV is checked against what must happen: the undisturbed hold
// and a 100 ms dropout hold the box, the dropout is reported (degraded) and recovered from, a push
// five times what the controller's friction model holds at f_min is reported no later than it
// drops the box, and no torque is ever non-finite. Also the model-error cell's premise: scaling
// every body's mass, first moment and inertia by lambda scales MuJoCo's M and h by lambda.
#include "common/csv_table.hpp"
#include "program_runner.hpp"

#include <mujoco/mujoco.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using example_common::CsvTable;

const std::string program = FAULT_CAMPAIGN_EXE;
const fs::path output_root = FAULT_CAMPAIGN_TEST_OUTPUT;

/// The value of `column` in the row of `cell` on `plant`.
double cell_value(const CsvTable& table, const std::string& cell, const std::string& plant, const std::string& column)
{
    const std::vector<double> values = table.numbers(column);
    for (std::size_t r = 0; r < table.rows(); ++r) {
        if (table.text(r, "cell") == cell && table.text(r, "plant") == plant) {
            return values[r];
        }
    }
    ADD_FAILURE() << "no row " << cell << " " << plant;
    return std::nan("");
}

TEST(FaultCampaign, ShortCampaignHoldsInsideAndReportsOutside)
{
    const fs::path directory = example_tests::fresh_directory(output_root, "short");
    const example_tests::ProgramRun run = example_tests::run_program(
        program, directory, "--short --scene lwr4_pair --jobs 2 --no-plots --quiet --output out");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const CsvTable table((directory / "out" / "campaign.csv").string());
    for (const char* plant : {"mujoco", "rigid"}) {
        SCOPED_TRACE(plant);
        EXPECT_EQ(cell_value(table, "nominal", plant, "held"), 1.0);
        EXPECT_LT(cell_value(table, "nominal", plant, "largest_slip_mm"), 1.0);
        EXPECT_EQ(cell_value(table, "dropout_nan_100ms", plant, "held"), 1.0);
        // 100 ticks predicted (degraded), none held past the prediction limit.
        EXPECT_GE(cell_value(table, "dropout_nan_100ms", plant, "degraded"), 99.0);
        EXPECT_EQ(cell_value(table, "dropout_nan_100ms", plant, "safe_hold"), 0.0);
        EXPECT_EQ(cell_value(table, "latency_1tick", plant, "held"), 1.0);
        EXPECT_EQ(cell_value(table, "push_beyond_x20", plant, "reported"), 1.0);
    }
    // On MuJoCo the overload is reported before the box is lost, if it is.
    const double first_report = cell_value(table, "push_beyond_x20", "mujoco", "first_report_s");
    EXPECT_FALSE(std::isnan(first_report));
    const std::vector<double> finite = table.numbers("finite");
    EXPECT_TRUE(std::all_of(finite.begin(), finite.end(), [](double f) { return f == 1.0; }));
    const CsvTable pushes((directory / "out" / "monte_carlo.csv").string());
    const std::vector<double> held = pushes.numbers("held");
    EXPECT_EQ(held.size(), 5U);
    for (const double h : held) {
        EXPECT_EQ(h, 1.0);
    }
}

TEST(FaultCampaign, BadOptionsAreRefused)
{
    const fs::path directory = example_tests::fresh_directory(output_root, "bad");
    EXPECT_EQ(example_tests::run_program(program, directory, "--jobs 0").exit_code, 2);
    EXPECT_EQ(example_tests::run_program(program, directory, "--scene nowhere").exit_code, 2);
}

/// Every link's mass, first moment (the centre of mass kept) and inertia times lambda: MuJoCo's
/// M of the arms' joints (less the joints' armature, which is the motors', not the links'; zero in
/// the shipped models) and h = qfrc_bias times lambda, to rounding (both are linear in the
/// inertial parameters), on the LWR 4 pair at a posture with velocities.
TEST(FaultCampaign, ScalingEveryLinksInertiaScalesMAndH)
{
    char error[512] = "";
    mjModel* model = mj_loadXML(COOPDYN_BOX_MJCF, nullptr, error, sizeof error);
    ASSERT_NE(model, nullptr) << error;
    mjModel* scaled = mj_copyModel(nullptr, model);
    const double lambda = 1.2;
    for (int b = 1; b < model->nbody; ++b) {
        scaled->body_mass[b] *= lambda;
        for (int k = 0; k < 3; ++k) {
            scaled->body_inertia[3 * b + k] *= lambda;
        }
    }
    mjData* data = mj_makeData(model);
    mjData* scaled_data = mj_makeData(scaled);
    for (int i = 0; i < model->nq; ++i) {  // a posture away from qpos0, with velocities
        data->qpos[i] = scaled_data->qpos[i] = model->qpos0[i] + (i < 14 ? 0.1 * std::sin(1.0 + i) : 0.0);
    }
    for (int i = 0; i < model->nv; ++i) {
        data->qvel[i] = scaled_data->qvel[i] = 0.3 * std::cos(2.0 + i);
    }
    mj_forward(model, data);
    mj_forward(scaled, scaled_data);
    std::vector<mjtNum> full(static_cast<std::size_t>(model->nv * model->nv));
    std::vector<mjtNum> scaled_full(full.size());
    mj_fullM(model, full.data(), data->qM);
    mj_fullM(scaled, scaled_full.data(), scaled_data->qM);
    // The arms' 14 joints (the controller's M and h); the box's free joint is not the arms' model.
    const int arms = 14;
    ASSERT_GT(model->nv, arms);
    double worst_m = 0.0, worst_h = 0.0, largest = 0.0;
    for (int r = 0; r < arms; ++r) {
        for (int c = 0; c < arms; ++c) {
            const double armature = r == c ? model->dof_armature[r] : 0.0;
            const auto k = static_cast<std::size_t>(r * model->nv + c);
            worst_m = std::max(worst_m, std::abs((scaled_full[k] - armature) - lambda * (full[k] - armature)));
            largest = std::max(largest, std::abs(full[k]));
        }
        worst_h = std::max(worst_h, std::abs(scaled_data->qfrc_bias[r] - lambda * data->qfrc_bias[r]));
    }
    EXPECT_LT(worst_m, 1e-12 * std::max(1.0, largest));
    EXPECT_LT(worst_h, 1e-10);
    mj_deleteData(scaled_data);
    mj_deleteData(data);
    mj_deleteModel(scaled);
    mj_deleteModel(model);
}

}  // namespace
