// End-to-end tests of the main job, examples/beam/two_arm_beam: the program is run as a user would run
// it (short durations), its CSV output is parsed, and the identified apparent impedance is checked
// against docs/analysis.md (the paper's (56), (59), (61)). Also: the CSV logs are complete and
// consistent (total = internal + external, internal wrenches do no work on the object), the
// identification can be repeated from the logged columns alone, the other shipped scenarios run,
// and command-line or scenario errors give a message and a non-zero exit code before anything
// runs.
#include "common/csv_table.hpp"
#include "program_runner.hpp"

#include <coopdyn/coopdyn.hpp>

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using example_common::CsvTable;

const std::string program = TWO_ARM_BEAM_EXE;
const std::string scenario_dir = COOPDYN_SCENARIO_DIR;
const fs::path output_root = TWO_ARM_BEAM_TEST_OUTPUT;

using example_tests::contains;
using example_tests::ProgramRun;
using example_tests::quote;

/// A fresh output directory for one test.
fs::path fresh_directory(const std::string& name) { return example_tests::fresh_directory(output_root, name); }

/// Runs the example with `arguments` in `directory`; `environment` is prefixed (e.g. "PATH=/x").
ProgramRun run_program(const fs::path& directory, const std::string& arguments, const std::string& environment = "")
{
    return example_tests::run_program(program, directory, arguments, environment);
}

// docs/analysis.md: nominal values (56), (59), (61) and the paper's identified ones (57), (60), (62).
struct Expected {
    double nominal;
    double paper_identified;
};
const std::map<std::string, std::array<Expected, 3>>& section9()
{
    // key: experiment/axis; values: inertia, damping, stiffness
    static const std::map<std::string, std::array<Expected, 3>> table{
        {"x/x", {{{21.75, 21.5}, {360.0, 384.0}, {600.0, 630.0}}}},
        {"rot_z/rot_z", {{{4.255, 4.652}, {77.6, 84.0}, {196.0, 170.0}}}},
        {"se3/x", {{{21.75, 25.8}, {360.0, 485.0}, {600.0, 820.0}}}},
        {"se3/y", {{{21.75, 25.8}, {360.0, 485.0}, {600.0, 820.0}}}},
        {"se3/z", {{{21.75, 25.8}, {360.0, 485.0}, {600.0, 820.0}}}},
        {"se3/rot_x", {{{4.255, 2.8}, {77.6, 73.0}, {196.0, 148.0}}}},
        {"se3/rot_y", {{{1.0, 0.45}, {20.0, 19.0}, {100.0, 78.0}}}},
        {"se3/rot_z", {{{4.255, 2.8}, {77.6, 73.0}, {196.0, 148.0}}}},
    };
    return table;
}

int parameter_index(const std::string& name) { return name == "inertia" ? 0 : name == "damping" ? 1 : 2; }

/// Checks every row of a beam identification summary against docs/analysis.md; returns the
/// largest relative error of the identified values, per block (translations, rotations).
std::array<double, 2> check_summary(const fs::path& path, std::size_t expected_rows)
{
    const CsvTable summary(path.string());
    EXPECT_EQ(summary.rows(), expected_rows);
    std::array<double, 2> worst{0.0, 0.0};
    for (std::size_t row = 0; row < summary.rows(); ++row) {
        const std::string key = summary.text(row, "experiment") + "/" + summary.text(row, "axis");
        SCOPED_TRACE(key + " " + summary.text(row, "parameter"));
        const auto entry = section9().find(key);
        if (entry == section9().end()) {
            ADD_FAILURE() << "unexpected row " << key;
            continue;
        }
        const Expected& expected = entry->second[static_cast<std::size_t>(parameter_index(summary.text(row, "parameter")))];
        EXPECT_DOUBLE_EQ(summary.number(row, "paper_nominal"), expected.nominal);
        EXPECT_DOUBLE_EQ(summary.number(row, "paper_identified"), expected.paper_identified);
        EXPECT_NEAR(summary.number(row, "nominal"), expected.nominal, 1e-12 * expected.nominal);  // Theorem 2
        const double error = std::abs(summary.number(row, "identified") / expected.nominal - 1.0);
        EXPECT_NEAR(summary.number(row, "relative_error"), summary.number(row, "identified") / expected.nominal - 1.0,
                    1e-9);
        EXPECT_EQ(summary.text(row, "converged"), "1");
        const std::size_t block = contains(summary.text(row, "axis"), "rot") ? 1 : 0;
        worst[block] = std::max(worst[block], error);
    }
    return worst;
}

std::vector<double> column(const CsvTable& table, const std::string& name) { return table.numbers(name); }

Eigen::VectorXd vector_of(const std::vector<double>& values)
{
    return Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
}

// ---------------------------------------------------------------------------------------------

TEST(TwoArmBeam, NoiseFreeIdentificationRecoversSection9ToFourDigits)
{
    const fs::path directory = fresh_directory("noise_free");
    // Translation along x and rotation about z at the scenario's amplitudes: 3 s are enough.
    const ProgramRun single = run_program(directory, "--experiment x,rot_z --duration 3 --no-plots --quiet --output out");
    ASSERT_EQ(single.exit_code, 0) << single.output;
    std::printf("%s", single.output.c_str());
    EXPECT_TRUE(contains(single.output, "Experiment 1 of 2: translation along x"));
    EXPECT_TRUE(contains(single.output, "2 arms hold a 1.75 kg object, scenario 'beam'")) << single.output;
    EXPECT_TRUE(contains(single.output, "-> 4 significant digits"));
    const std::array<double, 2> worst = check_summary(directory / "out" / "beam_identification.csv", 6);
    EXPECT_LT(worst[0], 5e-5);
    EXPECT_LT(worst[1], 5e-5);

    // The identification repeated from the logged columns alone gives the same values.
    const CsvTable x(directory / "out" / "beam_x.csv");
    const coopdyn::ImpedanceFit fit_x = coopdyn::identify_impedance(vector_of(column(x, "meas_disp_x")),
                                                                    vector_of(column(x, "meas_fx")), 1e-3);
    EXPECT_NEAR(fit_x.mass, 21.75, 5e-5 * 21.75);
    EXPECT_NEAR(fit_x.damping, 360.0, 5e-5 * 360.0);
    EXPECT_NEAR(fit_x.stiffness, 600.0, 5e-5 * 600.0);
    const CsvTable rz(directory / "out" / "beam_rot_z.csv");
    const coopdyn::ImpedanceFit fit_rz = coopdyn::identify_impedance(vector_of(column(rz, "meas_rot_z")),
                                                                     vector_of(column(rz, "meas_tz")), 1e-3);
    EXPECT_NEAR(fit_rz.mass, 4.255, 5e-5 * 4.255);
    EXPECT_NEAR(fit_rz.damping, 77.6, 5e-5 * 77.6);
    EXPECT_NEAR(fit_rz.stiffness, 196.0, 5e-5 * 196.0);
}

TEST(TwoArmBeam, NoiseFreeSe3)
{
    // Several simultaneous rotations couple at second and third order (gyroscopic terms,
    // rotation-vector kinematics, spring geometry), which the paper's diagonal linear model leaves
    // out. The default excitation runs (+u, -u, +2u, -2u: odd parts, extrapolated to zero
    // amplitude) cancel both, so every SE(3) value matches to 4 significant digits at the
    // default 2 N m, as at 0.01 N m.
    const fs::path directory = fresh_directory("se3");
    const ProgramRun small = run_program(directory, "--experiment se3 --duration 3 --torque 0.01 --no-plots --quiet --output small");
    ASSERT_EQ(small.exit_code, 0) << small.output;
    std::printf("%s", small.output.c_str());
    const std::array<double, 2> worst_small = check_summary(directory / "small" / "beam_identification.csv", 18);
    EXPECT_LT(worst_small[0], 5e-5);
    EXPECT_LT(worst_small[1], 5e-5);

    const ProgramRun large = run_program(directory, "--experiment se3 --duration 3 --no-plots --quiet --output large");
    ASSERT_EQ(large.exit_code, 0) << large.output;
    std::printf("%s", large.output.c_str());
    EXPECT_TRUE(contains(large.output, "runs +-u, +-2u"));
    EXPECT_TRUE(contains(large.output, "-> 4 significant digits"));
    const fs::path summary_path = directory / "large" / "beam_identification.csv";
    const std::array<double, 2> worst_large = check_summary(summary_path, 18);
    std::printf("[ se3 ] default torque, 3 s: largest error translations %.2g, rotations %.2g\n", worst_large[0],
                worst_large[1]);
    EXPECT_LT(worst_large[0], 5e-5);
    EXPECT_LT(worst_large[1], 5e-5);
    const CsvTable summary(summary_path.string());
    for (std::size_t row = 0; row < summary.rows(); ++row) {
        EXPECT_LT(std::abs(summary.number(row, "relative_error")), 5e-5)
            << summary.text(row, "axis") << " " << summary.text(row, "parameter");
    }

    // The identification repeated from the logged ident_* columns (the signals the program's
    // identification used) gives the program's values.
    const CsvTable log(directory / "large" / "beam_se3.csv");
    const coopdyn::ImpedanceFit rot_x = coopdyn::identify_impedance(vector_of(column(log, "ident_rot_x")),
                                                                    vector_of(column(log, "ident_tx")), 1e-3);
    EXPECT_NEAR(rot_x.mass, 4.255, 5e-5 * 4.255);
    EXPECT_NEAR(rot_x.damping, 77.6, 5e-5 * 77.6);
    EXPECT_NEAR(rot_x.stiffness, 196.0, 5e-5 * 196.0);

    // One run only (--single-run): the nonlinear coupling shows, in the rotations only.
    const ProgramRun single = run_program(directory, "--experiment se3 --duration 3 --single-run --no-plots --quiet --output single");
    ASSERT_EQ(single.exit_code, 0) << single.output;
    EXPECT_TRUE(contains(single.output, "single run"));
    const std::array<double, 2> worst_single = check_summary(directory / "single" / "beam_identification.csv", 18);
    std::printf("[ se3 ] default torque, 3 s, single run: largest error translations %.2g, rotations %.2g\n",
                worst_single[0], worst_single[1]);
    EXPECT_LT(worst_single[0], 5e-5);
    EXPECT_LT(worst_single[1], 5e-3);
    EXPECT_GT(worst_single[1], 10.0 * worst_large[1]);
    EXPECT_TRUE(contains(single.output, "couple at second and third order"));
}

TEST(TwoArmBeam, WithSensorNoiseAndLowPassWithinFivePercent)
{
    const fs::path directory = fresh_directory("noisy");
    const ProgramRun noisy = run_program(directory, "--noise --duration 20 --no-plots --quiet --output out");
    ASSERT_EQ(noisy.exit_code, 0) << noisy.output;
    std::printf("%s", noisy.output.c_str());
    EXPECT_TRUE(contains(noisy.output, "500 Hz force low-pass"));
    const std::array<double, 2> worst = check_summary(directory / "out" / "beam_identification.csv", 24);
    EXPECT_LT(worst[0], 0.05);
    EXPECT_LT(worst[1], 0.05);
    // The output error is about the variance of the pose noise (0.1 mm, 1 mrad) in the signals
    // the identification uses: (2/3) (y(+u) - y(-u)) - (1/12) (y(+2u) - y(-2u)) of four runs
    // with independent noise, so the noise variance is 2 (2/3)^2 + 2 (1/12)^2 = 0.903 times one
    // run's.
    const double noise_gain = 2.0 * (2.0 / 3.0) * (2.0 / 3.0) + 2.0 * (1.0 / 12.0) * (1.0 / 12.0);
    const CsvTable summary((directory / "out" / "beam_identification.csv").string());
    for (std::size_t row = 0; row < summary.rows(); ++row) {
        const bool rotation = contains(summary.text(row, "axis"), "rot");
        const double variance = noise_gain * (rotation ? 1e-6 : 1e-8);
        EXPECT_NEAR(summary.number(row, "mean_squared_output_error") / variance, 1.0, 0.1) << summary.text(row, "axis");
        EXPECT_EQ(summary.text(row, "noise"), "1");
    }
    // The logged measurement differs from the truth by about the noise level.
    const CsvTable x(directory / "out" / "beam_x.csv");
    const std::vector<double> truth = column(x, "disp_x");
    const std::vector<double> measured = column(x, "meas_disp_x");
    double sum = 0.0;
    for (std::size_t n = 0; n < truth.size(); ++n) {
        sum += (measured[n] - truth[n]) * (measured[n] - truth[n]);
    }
    EXPECT_NEAR(std::sqrt(sum / static_cast<double>(truth.size())), 1e-4, 1e-5);
}

TEST(TwoArmBeam, LogsAreCompleteAndConsistent)
{
    const fs::path directory = fresh_directory("logs");
    const ProgramRun result = run_program(directory, "--experiment se3 --duration 2 --no-plots --quiet --output out");
    ASSERT_EQ(result.exit_code, 0) << result.output;
    const CsvTable log((directory / "out" / "beam_se3.csv").string());
    ASSERT_EQ(log.rows(), 2000u);
    ASSERT_EQ(log.header().size(), 92u);
    for (const char* name : {"time", "dist_fx", "meas_tz", "pos_x", "quat_w", "vel_y", "omega_z", "disp_x", "rot_z",
                             "meas_disp_y", "meas_rot_x", "model_disp_z", "model_rot_y", "ident_fx", "ident_tz",
                             "ident_disp_x", "ident_rot_z", "arm0_fx", "arm0_int_tz", "arm1_ext_fy"}) {
        EXPECT_TRUE(log.has(name)) << name;
    }
    // Noise-free, the combination of the runs' wrenches is the logged (+u) disturbance itself,
    // and the combined displacement differs from the +u run's only by the nonlinear terms (in the
    // rotations, of second order: about theta^2, theta up to 30 mrad here).
    const std::array<const char*, 6> ident_wrench{"ident_fx", "ident_fy", "ident_fz", "ident_tx", "ident_ty", "ident_tz"};
    const std::array<const char*, 6> dist_wrench{"dist_fx", "dist_fy", "dist_fz", "dist_tx", "dist_ty", "dist_tz"};
    const std::array<const char*, 6> ident_disp{"ident_disp_x", "ident_disp_y", "ident_disp_z",
                                                "ident_rot_x",  "ident_rot_y",  "ident_rot_z"};
    const std::array<const char*, 6> disp{"disp_x", "disp_y", "disp_z", "rot_x", "rot_y", "rot_z"};
    for (std::size_t row = 0; row < log.rows(); ++row) {
        for (std::size_t k = 0; k < 6; ++k) {
            EXPECT_NEAR(log.number(row, ident_wrench[k]), log.number(row, dist_wrench[k]), 1e-9) << ident_wrench[k];
            EXPECT_NEAR(log.number(row, ident_disp[k]), log.number(row, disp[k]), k < 3 ? 1e-8 : 1e-3) << ident_disp[k];
        }
    }
    const std::array<const char*, 6> parts{"fx", "fy", "fz", "tx", "ty", "tz"};
    double worst_split = 0.0, worst_force = 0.0, worst_torque = 0.0, largest = 0.0;
    for (std::size_t row = 0; row < log.rows(); ++row) {
        EXPECT_NEAR(log.number(row, "time"), 1e-3 * static_cast<double>(row), 1e-9);
        const Eigen::Quaterniond q(log.number(row, "quat_w"), log.number(row, "quat_x"), log.number(row, "quat_y"),
                                   log.number(row, "quat_z"));
        Eigen::Vector3d force = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
        for (int arm = 0; arm < 2; ++arm) {
            const std::string prefix = "arm" + std::to_string(arm) + "_";
            Eigen::Matrix<double, 6, 1> internal;
            for (std::size_t k = 0; k < 6; ++k) {
                const double total = log.number(row, prefix + parts[k]);
                internal(static_cast<Eigen::Index>(k)) = log.number(row, prefix + "int_" + parts[k]);
                const double external = log.number(row, prefix + "ext_" + parts[k]);
                worst_split = std::max(worst_split, std::abs(total - internal(static_cast<Eigen::Index>(k)) - external));
                largest = std::max(largest, std::abs(total));
            }
            // Internal wrenches do no work on the object: G h'_int = 0 (Definition 1).
            const Eigen::Vector3d r = q * Eigen::Vector3d(0.0, arm == 0 ? -0.4 : 0.4, 0.0);
            force += internal.head<3>();
            torque += r.cross(internal.head<3>()) + internal.tail<3>();
        }
        worst_force = std::max(worst_force, force.norm());
        worst_torque = std::max(worst_torque, torque.norm());
    }
    EXPECT_LT(worst_split, 1e-8 * largest);
    EXPECT_LT(worst_force, 1e-8 * largest);
    EXPECT_LT(worst_torque, 1e-8 * largest);
    // Gravity compensation: each arm carries half the beam's weight (h_i = -hbar_i, pointing down).
    EXPECT_NEAR(log.number(0, "arm0_fz") + log.number(0, "arm1_fz"), -1.75 * 9.81, 0.5);
}

TEST(TwoArmBeam, OtherScenarios)
{
    const fs::path directory = fresh_directory("scenarios");
    // Three arms on a plate: Corollary 1 holds, so the diagonal model is exact to first order.
    const ProgramRun plate = run_program(directory, "--scenario " + quote(scenario_dir + "/plate_three_arms.json") +
                                         " --duration 3 --torque 0.01 --no-plots --quiet --output out");
    ASSERT_EQ(plate.exit_code, 0) << plate.output;
    EXPECT_TRUE(contains(plate.output, "3 arms hold a 4.58 kg object, scenario 'plate'")) << plate.output;
    EXPECT_FALSE(contains(plate.output, "two-arm beam")) << plate.output;  // the banner said so
    EXPECT_TRUE(contains(plate.output, "axes decoupled"));
    const CsvTable summary((directory / "out" / "plate_identification.csv").string());
    ASSERT_EQ(summary.rows(), 24u);
    for (std::size_t row = 0; row < summary.rows(); ++row) {
        EXPECT_LT(std::abs(summary.number(row, "relative_error")), 5e-5)
            << summary.text(row, "experiment") << " " << summary.text(row, "axis") << " "
            << summary.text(row, "parameter");
        EXPECT_EQ(summary.text(row, "paper_nominal"), "");  // no paper reference for this set-up
    }
    // The asymmetric grasp: translation and rotation couple, and the program says so.
    const ProgramRun asymmetric = run_program(directory, "--scenario " + quote(scenario_dir + "/asymmetric_two_arms.json") +
                                              " --experiment x --duration 2 --no-plots --quiet --output out");
    ASSERT_EQ(asymmetric.exit_code, 0) << asymmetric.output;
    std::printf("%s", asymmetric.output.c_str());
    EXPECT_TRUE(contains(asymmetric.output, "axes COUPLED"));
    EXPECT_TRUE(fs::exists(directory / "out" / "asymmetric_x.csv"));
    // Pushes instead of a multisine.
    const ProgramRun push = run_program(directory, "--experiment x --excitation push --duration 5 --no-plots --quiet --output push");
    ASSERT_EQ(push.exit_code, 0) << push.output;
    EXPECT_TRUE(contains(push.output, "pushes"));
    EXPECT_TRUE(contains(push.output, "-> 4 significant digits"));
}

TEST(TwoArmBeam, ErrorsGiveMessagesAndExitCodes)
{
    const fs::path directory = fresh_directory("errors");
    const ProgramRun help = run_program(directory, "--help");
    EXPECT_EQ(help.exit_code, 0);
    for (const char* option : {"--scenario", "--experiment", "--duration", "--excitation", "--force", "--torque",
                               "--seed", "--noise", "--lowpass", "--output", "--no-plots", "--identify-log"}) {
        EXPECT_TRUE(contains(help.output, option)) << option;
    }
    // The default scenario is shown relative to the repository, not as the build machine's path
    // (it is still found at run time: the other tests run without --scenario).
    EXPECT_TRUE(contains(help.output, "--scenario FILE=examples/beam/scenarios/beam.json")) << help.output;
    EXPECT_FALSE(contains(help.output, scenario_dir)) << help.output;

    const ProgramRun unknown = run_program(directory, "--frobnicate");
    EXPECT_EQ(unknown.exit_code, 2) << unknown.output;
    EXPECT_TRUE(contains(unknown.output, "frobnicate")) << unknown.output;

    const ProgramRun negative = run_program(directory, "--duration -3");
    EXPECT_EQ(negative.exit_code, 2) << negative.output;

    const ProgramRun experiment = run_program(directory, "--experiment rot_q");
    EXPECT_EQ(experiment.exit_code, 2) << experiment.output;

    // A file that cannot be read is exit code 4 (not an invalid scenario), one line.
    const ProgramRun missing = run_program(directory, "--scenario no_such.json");
    EXPECT_EQ(missing.exit_code, 4) << missing.output;
    EXPECT_TRUE(example_tests::is_one_line(missing.output, "two_arm_beam: cannot read no_such.json: No such file or directory"))
        << missing.output;

    // A malformed file: nothing is simulated, no output is written.
    std::string text;
    {
        std::ifstream file(scenario_dir + "/beam.json");
        std::ostringstream buffer;
        buffer << file.rdbuf();
        text = buffer.str();
    }
    const std::string needle = "\"mass\": 10.0";
    const auto last = text.rfind(needle);
    ASSERT_NE(last, std::string::npos);
    text.replace(last, needle.size(), "\"mass\": \"ten\"");
    {
        std::ofstream file(directory / "bad.json");
        file << text;
    }
    const ProgramRun bad = run_program(directory, "--scenario bad.json --output bad_out");
    EXPECT_EQ(bad.exit_code, 3) << bad.output;
    EXPECT_TRUE(contains(bad.output, "bad.json: arms[1].end_effector.mass: expected a number, got string"))
        << bad.output;
    EXPECT_FALSE(fs::exists(directory / "bad_out"));
}

TEST(TwoArmBeam, PlotsOrAClearMessageWithoutGnuplot)
{
    const fs::path directory = fresh_directory("plots");
    // Without gnuplot on PATH the program still succeeds and says what it skipped.
    const ProgramRun without = run_program(directory, "--experiment x --duration 1 --quiet --output out", "PATH=/nonexistent");
    ASSERT_EQ(without.exit_code, 0) << without.output;
    EXPECT_TRUE(contains(without.output, "gnuplot was not found on PATH")) << without.output;
    EXPECT_TRUE(fs::exists(directory / "out" / "beam_x.gp"));
    EXPECT_FALSE(fs::exists(directory / "out" / "beam_x.png"));

    if (std::system("command -v gnuplot > /dev/null 2>&1") != 0) {
        GTEST_SKIP() << "gnuplot is not installed (Debian: gnuplot-nox); the PNG output is not checked";
    }
    const ProgramRun with = run_program(directory, "--experiment x --duration 1 --quiet --output out");
    ASSERT_EQ(with.exit_code, 0) << with.output;
    std::ifstream png(directory / "out" / "beam_x.png", std::ios::binary);
    std::array<char, 8> signature{};
    png.read(signature.data(), 8);
    EXPECT_EQ(std::string(signature.data() + 1, 3), "PNG");
}

TEST(TwoArmBeam, IdentifyAnExistingLog)
{
    const fs::path directory = fresh_directory("identify_log");
    const ProgramRun simulation = run_program(directory, "--experiment rot_z --duration 3 --no-plots --quiet --output out");
    ASSERT_EQ(simulation.exit_code, 0) << simulation.output;
    // Keep only the columns a real experiment would have.
    const CsvTable log((directory / "out" / "beam_rot_z.csv").string());
    {
        std::ofstream real(directory / "real.csv");
        real << "time,meas_tz,meas_rot_z\n";
        real.precision(12);
        for (std::size_t row = 0; row < log.rows(); ++row) {
            real << log.text(row, "time") << ',' << log.text(row, "meas_tz") << ',' << log.text(row, "meas_rot_z")
                 << '\n';
        }
    }
    const ProgramRun identified = run_program(directory, "--identify-log real.csv --scenario " + quote(scenario_dir + "/beam.json"));
    ASSERT_EQ(identified.exit_code, 0) << identified.output;
    std::printf("%s", identified.output.c_str());
    EXPECT_TRUE(contains(identified.output, "3000 samples at 1000 Hz"));
    EXPECT_TRUE(contains(identified.output, "4.255")) << identified.output;
    EXPECT_TRUE(contains(identified.output, "196")) << identified.output;

    const ProgramRun missing_columns = run_program(directory, "--identify-log out/beam_identification.csv");
    EXPECT_EQ(missing_columns.exit_code, 1) << missing_columns.output;
    EXPECT_TRUE(contains(missing_columns.output, "'time'")) << missing_columns.output;
}

/// Runs the program with options that must be refused: exit code `code`, quickly, a message that
/// contains `message`, nothing simulated and no file written (the directory holds only the
/// captured output).
void expect_refused_up_front(const std::string& arguments, int code, const std::string& message)
{
    SCOPED_TRACE(arguments);
    const fs::path directory = fresh_directory("refused");
    const auto start = std::chrono::steady_clock::now();
    const ProgramRun run = run_program(directory, arguments);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("[ refused ] %s -> %d: %s", arguments.c_str(), run.exit_code, run.output.c_str());
    EXPECT_EQ(run.exit_code, code) << run.output;
    EXPECT_TRUE(contains(run.output, message)) << run.output;
    EXPECT_LT(seconds, 5.0) << "a refused option must not run anything";
    EXPECT_FALSE(contains(run.output, "Experiment")) << run.output;
    EXPECT_FALSE(contains(run.output, "bad_alloc")) << run.output;
    EXPECT_LT(run.output.size(), 400u) << "a short message";
    std::vector<std::string> files;
    for (const auto& entry : fs::directory_iterator(directory)) {
        if (entry.path().filename() != "program_output.txt") {
            files.push_back(entry.path().filename().string());
        }
    }
    EXPECT_TRUE(files.empty()) << files.size() << " file(s) written, e.g. " << (files.empty() ? "" : files.front());
}

TEST(TwoArmBeam, InvalidOptionsAreRefusedBeforeAnythingRuns)
{
    const std::string rest = " --no-plots --quiet --output out";
    // NaN and infinities: CLI11's own range checks let NaN through.
    expect_refused_up_front("--duration nan" + rest, 2, "--duration: must be a finite number in [1, 3600], got nan");
    expect_refused_up_front("--duration inf" + rest, 2, "--duration: must be a finite number in [1, 3600], got inf");
    expect_refused_up_front("--duration 1e999" + rest, 2, "--duration: must be a finite number");
    expect_refused_up_front("--force nan" + rest, 2, "--force: must be a finite number, 0 or in [0.001, 1000], got nan");
    expect_refused_up_front("--torque=-inf" + rest, 2, "--torque: must be a finite number, 0 or in [0.001, 1000], got -inf");
    expect_refused_up_front("--force-noise nan --noise" + rest, 2, "--force-noise: must be a non-negative finite number");
    expect_refused_up_front("--angle-noise nan" + rest, 2, "--angle-noise: must be a non-negative finite number");
    // Readable limits (CLI11 printed DBL_MAX with all its digits).
    expect_refused_up_front("--force -1" + rest, 2, "--force: must be a finite number, 0 or in [0.001, 1000], got -1");
    // The scenario's excitation.force has the same range (beam_example::excitation_force_range).
    expect_refused_up_front("--force 1e9" + rest, 2, "--force: must be a finite number, 0 or in [0.001, 1000], got 1e9");
    expect_refused_up_front("--log-every 0" + rest, 2, "--log-every: must be a positive decimal integer");
    expect_refused_up_front("--log-every 1.5" + rest, 2, "--log-every: must be a positive decimal integer");
    expect_refused_up_front("--duration 0.5" + rest, 2, "--duration: must be a finite number in [1, 3600], got 0.5");
    expect_refused_up_front("--lowpass abc" + rest, 2, "--lowpass: must be a non-negative finite number, got abc");
    // The low-pass filters the 1 kHz log: above the 500 Hz Nyquist limit it is refused (whether
    // or not --noise is given), after the scenario is read and before anything runs.
    expect_refused_up_front("--lowpass 600 --noise" + rest, 2, "--lowpass 600 Hz is above the Nyquist limit 500 Hz");
    expect_refused_up_front("--lowpass 500.5" + rest, 2, "Nyquist limit 500 Hz");
    // A negative seed would wrap around; a leading zero would be read as octal.
    expect_refused_up_front("--seed -1" + rest, 2, "--seed: must be a non-negative decimal integer, got -1");
    expect_refused_up_front("--seed 010" + rest, 2, "--seed: must be a non-negative decimal integer, got 010");
    // The output folder.
    expect_refused_up_front("--no-plots --quiet --output ''", 2, "--output: must not be empty");
    expect_refused_up_front("--duration 1 --runs 3" + rest, 2, "--runs");
    expect_refused_up_front("--duration 1 --experiment x,rot_q" + rest, 2, "--experiment");

    // At the limits the options are accepted.
    const fs::path directory = fresh_directory("limits");
    const ProgramRun limits = run_program(directory, "--experiment x --duration 1 --runs 1 --noise --lowpass 500 "
                                                     "--force-noise 0 --seed 0 --no-plots --quiet --output out");
    ASSERT_EQ(limits.exit_code, 0) << limits.output;
    EXPECT_TRUE(contains(limits.output, "500 Hz force low-pass")) << limits.output;
    EXPECT_TRUE(fs::exists(directory / "out" / "beam_x.csv"));
}

/// The shipped beam with `from` (found once) replaced by `to`, written to `directory / file`.
void write_edited_beam(const fs::path& directory, const std::string& file, const std::string& from,
                       const std::string& to)
{
    std::ifstream in(scenario_dir + "/beam.json");
    std::ostringstream buffer;
    buffer << in.rdbuf();
    std::string text = buffer.str();
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    std::ofstream out(directory / file);
    out << text;
}

TEST(TwoArmBeam, ScenarioNumbersAndNamesAreCheckedBeforeAnythingRuns)
{
    const fs::path directory = fresh_directory("scenario_checks");
    // A number too large for a double: nlohmann-json's own error becomes file + JSON path.
    write_edited_beam(directory, "huge.json", "\"mass\": 1.75", "\"mass\": 1e400");
    const ProgramRun huge = run_program(directory, "--scenario huge.json --duration 1 --no-plots --quiet --output out");
    EXPECT_EQ(huge.exit_code, 3) << huge.output;
    EXPECT_TRUE(contains(huge.output, "huge.json: object.mass: not a finite number")) << huge.output;
    EXPECT_FALSE(contains(huge.output, "[json.exception")) << huge.output;

    // A name that would write outside --output, and an empty one (which gave "_x.csv").
    write_edited_beam(directory, "escaped.json", "\"name\": \"beam\"", "\"name\": \"../escaped\"");
    const ProgramRun escaped =
        run_program(directory, "--scenario escaped.json --experiment x --duration 1 --no-plots --quiet --output out");
    EXPECT_EQ(escaped.exit_code, 3) << escaped.output;
    EXPECT_TRUE(contains(escaped.output, "escaped.json: name: must not contain a path separator")) << escaped.output;
    write_edited_beam(directory, "unnamed.json", "\"name\": \"beam\"", "\"name\": \"\"");
    const ProgramRun unnamed =
        run_program(directory, "--scenario unnamed.json --experiment x --duration 1 --no-plots --quiet --output out");
    EXPECT_EQ(unnamed.exit_code, 3) << unnamed.output;
    EXPECT_TRUE(contains(unnamed.output, "unnamed.json: name: must not be empty")) << unnamed.output;

    // Nothing was written, neither in nor next to the output folder.
    EXPECT_FALSE(fs::exists(directory / "out"));
    EXPECT_FALSE(fs::exists(directory / "escaped_x.csv"));
    EXPECT_FALSE(fs::exists(directory / "escaped_identification.csv"));

    // A valid name with dots and dashes writes its files inside --output only.
    write_edited_beam(directory, "dotted.json", "\"name\": \"beam\"", "\"name\": \"beam.v2-test\"");
    const ProgramRun dotted =
        run_program(directory, "--scenario dotted.json --experiment x --duration 1 --runs 1 --no-plots --quiet --output out");
    ASSERT_EQ(dotted.exit_code, 0) << dotted.output;
    EXPECT_TRUE(fs::exists(directory / "out" / "beam.v2-test_x.csv"));
    EXPECT_TRUE(fs::exists(directory / "out" / "beam.v2-test_identification.csv"));
}

// Relative paths are the working directory's (scripts/beam runs the program from the caller's
// directory too); the default scenario is found through the compiled-in path from anywhere, and
// the default output folder out/ is the working directory's.
TEST(TwoArmBeam, RelativePathsAreTakenFromTheWorkingDirectory)
{
    const fs::path directory = fresh_directory("relative_paths");
    const fs::path cwd = directory / "a" / "b";
    fs::create_directories(cwd);
    fs::create_directories(directory / "scenarios");
    ASSERT_TRUE(example_tests::write_edited(example_tests::read_file(scenario_dir + "/beam.json"), "\"name\": \"beam\"",
                                            "\"name\": \"mine\"", directory / "scenarios" / "mine.json"));
    const ProgramRun relative = example_tests::run_program(
        program, cwd, "--scenario ../../scenarios/mine.json --experiment x --duration 1 --runs 1 --no-plots --quiet "
                      "--output ../out");
    ASSERT_EQ(relative.exit_code, 0) << relative.output;
    EXPECT_TRUE(fs::exists(directory / "a" / "out" / "mine_x.csv"));
    EXPECT_TRUE(fs::exists(directory / "a" / "out" / "mine_identification.csv"));

    // --identify-log on a relative path, from the same directory.
    const ProgramRun identified = example_tests::run_program(program, cwd, "--identify-log ../out/mine_x.csv");
    ASSERT_EQ(identified.exit_code, 0) << identified.output;
    EXPECT_TRUE(contains(identified.output, "identification of ../out/mine_x.csv: 1000 samples")) << identified.output;

    // Defaults: the shipped scenario from anywhere, out/ in the working directory.
    const ProgramRun defaults =
        example_tests::run_program(program, cwd, "--experiment x --duration 1 --runs 1 --no-plots --quiet");
    ASSERT_EQ(defaults.exit_code, 0) << defaults.output;
    EXPECT_TRUE(contains(defaults.output, "scenario 'beam'")) << defaults.output;
    EXPECT_TRUE(fs::exists(cwd / "out" / "beam_x.csv"));
}

// Several --scenario files run one after the other, each writing its own files; two with the same
// name (same output files) are refused before anything runs.
TEST(TwoArmBeam, SeveralScenariosRunOneAfterTheOther)
{
    const fs::path directory = fresh_directory("several");
    const std::string both = "--scenario " + quote(scenario_dir + "/beam.json") + " --scenario " +
                             quote(scenario_dir + "/plate_three_arms.json");
    const ProgramRun run = run_program(directory, both + " --experiment x --duration 1 --runs 1 --no-plots --quiet --output out");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_TRUE(contains(run.output, "2 arms hold a 1.75 kg object, scenario 'beam'")) << run.output;
    EXPECT_TRUE(contains(run.output, "3 arms hold a 4.58 kg object, scenario 'plate'")) << run.output;
    EXPECT_EQ(CsvTable((directory / "out" / "beam_identification.csv").string()).rows(), 3u);
    EXPECT_EQ(CsvTable((directory / "out" / "plate_identification.csv").string()).rows(), 3u);

    const ProgramRun twice = run_program(directory, "--scenario " + quote(scenario_dir + "/beam.json") +
                                                        " --scenario " + quote(scenario_dir + "/beam.json") +
                                                        " --duration 1 --no-plots --quiet --output twice");
    EXPECT_EQ(twice.exit_code, 2) << twice.output;
    EXPECT_TRUE(contains(twice.output, "have the same name 'beam'")) << twice.output;
    EXPECT_FALSE(fs::exists(directory / "twice"));

    // A bad second scenario stops everything before the first one runs.
    std::ofstream(directory / "broken.json") << "{";
    const ProgramRun broken = run_program(directory, "--scenario " + quote(scenario_dir + "/beam.json") +
                                                         " --scenario broken.json --duration 1 --no-plots --quiet --output broken");
    EXPECT_EQ(broken.exit_code, 3) << broken.output;
    EXPECT_FALSE(fs::exists(directory / "broken"));
}

// --log-every N thins the CSV logs only: every N-th step, while the identification (from every
// step) is the same as without it.
TEST(TwoArmBeam, LogEveryThinsTheCsvOnly)
{
    const fs::path directory = fresh_directory("log_every");
    const std::string common = "--experiment x --duration 2 --runs 1 --no-plots --quiet";
    const ProgramRun full = run_program(directory, common + " --output full");
    ASSERT_EQ(full.exit_code, 0) << full.output;
    const ProgramRun thinned = run_program(directory, common + " --log-every 7 --output thinned");
    ASSERT_EQ(thinned.exit_code, 0) << thinned.output;
    EXPECT_TRUE(contains(thinned.output, "the CSV logs hold 1 step in 7")) << thinned.output;

    const CsvTable all((directory / "full" / "beam_x.csv").string());
    const CsvTable some((directory / "thinned" / "beam_x.csv").string());
    ASSERT_EQ(all.rows(), 2000u);
    ASSERT_EQ(some.rows(), 286u);  // steps 0, 7, ..., 1995: ceil(2000 / 7)
    EXPECT_EQ(some.header(), all.header());
    for (std::size_t row = 0; row < some.rows(); ++row) {
        EXPECT_EQ(some.text(row, "time"), all.text(7 * row, "time"));
        EXPECT_EQ(some.text(row, "meas_disp_x"), all.text(7 * row, "meas_disp_x"));
    }
    const CsvTable summary_all((directory / "full" / "beam_identification.csv").string());
    const CsvTable summary_some((directory / "thinned" / "beam_identification.csv").string());
    ASSERT_EQ(summary_all.rows(), summary_some.rows());
    for (std::size_t row = 0; row < summary_all.rows(); ++row) {
        EXPECT_EQ(summary_some.text(row, "identified"), summary_all.text(row, "identified"));
    }
}

// Files that cannot be read or written: exit code 4 and one line "two_arm_beam: cannot read|write
// <path>: <reason>", nothing simulated.
TEST(TwoArmBeam, MissingOrUnwritableFilesAreExitCodeFour)
{
    const fs::path directory = fresh_directory("files");
    const ProgramRun scenario = run_program(directory, "--scenario nope.json --no-plots --quiet");
    EXPECT_EQ(scenario.exit_code, 4) << scenario.output;
    EXPECT_TRUE(example_tests::is_one_line(scenario.output, "two_arm_beam: cannot read nope.json: No such file or directory"))
        << scenario.output;

    const ProgramRun folder = run_program(directory, "--scenario . --no-plots --quiet");
    EXPECT_EQ(folder.exit_code, 4) << folder.output;
    EXPECT_TRUE(example_tests::is_one_line(folder.output, "two_arm_beam: cannot read .: is a directory, not a file"))
        << folder.output;

    const ProgramRun log = run_program(directory, "--identify-log nope.csv");
    EXPECT_EQ(log.exit_code, 4) << log.output;
    EXPECT_TRUE(example_tests::is_one_line(log.output, "two_arm_beam: cannot read nope.csv: No such file or directory"))
        << log.output;

    const auto start = std::chrono::steady_clock::now();
    const ProgramRun output = run_program(directory, "--duration 20 --no-plots --quiet --output /proc/nope");
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0)
        << "refused before anything runs";
    EXPECT_EQ(output.exit_code, 4) << output.output;
    EXPECT_EQ(output.output.rfind("two_arm_beam: cannot write /proc/nope: ", 0), 0u) << output.output;
    EXPECT_EQ(std::count(output.output.begin(), output.output.end(), '\n'), 1) << output.output;
}

// A scenario value out of the range its option has is refused as an invalid scenario (exit 3),
// naming the field and the range.
TEST(TwoArmBeam, ScenarioValuesHaveTheOptionsRanges)
{
    const fs::path directory = fresh_directory("scenario_ranges");
    write_edited_beam(directory, "strong.json", "\"force\": 5.0", "\"force\": 1e9");
    const ProgramRun strong = run_program(directory, "--scenario strong.json --duration 1 --no-plots --quiet --output out");
    EXPECT_EQ(strong.exit_code, 3) << strong.output;
    EXPECT_TRUE(example_tests::is_one_line(
        strong.output, "two_arm_beam: invalid scenario: strong.json: excitation.force: must be between 0.001 and 1000, got 1e+09"))
        << strong.output;
    EXPECT_FALSE(fs::exists(directory / "out"));
}

}  // namespace
