// End-to-end tests of examples/box/dual_arm_box (docs/dual-arm-box.md): the program runs the
// shipped experiments on the plants each test needs, as a user would, and its CSV logs are checked against what
// the physics must show: the box is held by friction in MuJoCo (slip below 1 mm, no drop), the
// rigid plant's true contact wrenches stay inside the true friction cone, the squeeze rises when
// the box is pushed and never falls while mass is added, the circle is tracked outside the
// person's hold, the contact QP is never infeasible, and on the rigid plant the measured contact
// forces agree with the QP's prediction to the controller's model error (what it does not know of
// the box's mass and the person's force). Bad options and scenario files fail with their messages
// before anything runs.
#include "common/csv_table.hpp"
#include "program_runner.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using example_common::CsvTable;
using example_tests::contains;
using example_tests::ProgramRun;
using example_tests::quote;

const std::string program = DUAL_ARM_BOX_EXE;
const std::string box_dir = COOPDYN_BOX_DIR;
const fs::path output_root = DUAL_ARM_BOX_TEST_OUTPUT;
const std::vector<std::string> experiments{"hold", "push", "add_mass", "circle"};

/// Runs the program in a directory of the test's own: ctest runs each test in a process of its
/// own, several at a time.
class DualArmBox : public ::testing::Test {
protected:
    /// `extra`: more options; the minimum-squeeze measurement is off unless a test asks for it.
    void run(const std::string& selection, const std::string& plant, const std::string& extra = "--no-minimum-squeeze")
    {
        directory_ = example_tests::fresh_directory(
            output_root, ::testing::UnitTest::GetInstance()->current_test_info()->name());
        run_ = example_tests::run_program(program, directory_,
                                          "--experiment " + selection + " --plant " + plant +
                                              " --no-plots --quiet --output out " + extra);
        ASSERT_EQ(run_.exit_code, 0) << run_.output;
    }
    CsvTable log(const std::string& experiment, const std::string& plant) const
    {
        return CsvTable((directory_ / "out" / (experiment + "_" + plant + ".csv")).string());
    }
    fs::path directory_;
    ProgramRun run_;
};

double column_max(const CsvTable& table, const std::string& column)
{
    const std::vector<double> values = table.numbers(column);
    return *std::max_element(values.begin(), values.end());
}

double column_min(const CsvTable& table, const std::string& column)
{
    const std::vector<double> values = table.numbers(column);
    return *std::min_element(values.begin(), values.end());
}

TEST_F(DualArmBox, RunsEveryExperimentOnBothPlantsAndPrintsTheTable)
{
    ASSERT_NO_FATAL_FAILURE(run("all", "both", ""));
    EXPECT_TRUE(contains(run_.output, "holds N")) << run_.output;
    for (const std::string& experiment : experiments) {
        for (const char* plant : {"mujoco", "rigid"}) {
            EXPECT_TRUE(contains(run_.output, experiment)) << run_.output;
            EXPECT_TRUE(fs::exists(directory_ / "out" / (experiment + "_" + plant + ".csv")));
            EXPECT_TRUE(fs::exists(directory_ / "out" / (experiment + "_" + plant + ".gp")));
        }
    }
    EXPECT_FALSE(contains(run_.output, "DROPPED")) << run_.output;
    EXPECT_TRUE(contains(run_.output, "paper")) << run_.output;
}

TEST_F(DualArmBox, MujocoPlantHoldsTheBoxByFrictionInEveryExperiment)
{
    ASSERT_NO_FATAL_FAILURE(run("all", "mujoco"));
    for (const std::string& experiment : experiments) {
        const CsvTable table = log(experiment, "mujoco");
        const double slip = std::max(column_max(table, "left_slip"), column_max(table, "right_slip"));
        EXPECT_LT(slip, 1e-3) << experiment;
        // No drop: the whole scenario was simulated.
        EXPECT_GT(table.rows(), 3000u) << experiment;
    }
}

TEST_F(DualArmBox, RigidPlantTrueWrenchesStayInsideTheTrueFrictionCone)
{
    ASSERT_NO_FATAL_FAILURE(run("all", "rigid"));
    for (const std::string& experiment : experiments) {
        const CsvTable table = log(experiment, "rigid");
        EXPECT_GE(std::min({column_min(table, "left_true_force_margin"), column_min(table, "right_true_force_margin"),
                            column_min(table, "left_true_moment_margin"), column_min(table, "right_true_moment_margin")}),
                  0.0)
            << experiment;
    }
}

TEST_F(DualArmBox, ContactQpIsNeverInfeasibleInTheShippedScenarios)
{
    ASSERT_NO_FATAL_FAILURE(run("all", "both", ""));
    EXPECT_TRUE(contains(run_.output, "holds N")) << run_.output;
    for (const std::string& experiment : experiments) {
        for (const char* plant : {"mujoco", "rigid"}) {
            const CsvTable table = log(experiment, plant);
            for (std::size_t row = 0; row < table.rows(); ++row) {
                ASSERT_EQ(table.text(row, "qp_status"), "solved") << experiment << " " << plant << " row " << row;
                ASSERT_EQ(table.text(row, "status"), "ok") << experiment << " " << plant << " row " << row;
            }
        }
    }
}

// Lin et al. Fig. 6 (top): about 70 N at rest, about 110 N while pushed with about 40 N, back after.
TEST_F(DualArmBox, SqueezeRisesWhenPushedAndFallsBackAfterwards)
{
    ASSERT_NO_FATAL_FAILURE(run("push", "both"));
    for (const char* plant : {"mujoco", "rigid"}) {
        const CsvTable table = log("push", plant);
        const std::vector<double> time = table.numbers("time");
        const std::vector<double> push = table.numbers("person_fz");
        double rest = 0.0, pushed = 0.0, after = 0.0;
        for (std::size_t row = 0; row < table.rows(); ++row) {
            const double normal = 0.5 * (table.number(row, "left_meas_fz") + table.number(row, "right_meas_fz"));
            if (time[row] < 0.9) {
                rest = std::max(rest, normal);
            }
            if (push[row] < -39.0) {
                pushed = std::max(pushed, normal);
            }
            if (time[row] > time.back() - 0.2) {
                after = std::max(after, normal);
            }
        }
        EXPECT_NEAR(rest, 70.0, 0.5) << plant;    // the scenario's minimum normal force
        EXPECT_GT(pushed, 100.0) << plant;        // (40 N + m g) / (2 mu) = 117 N with mu = 0.2
        EXPECT_NEAR(after, 70.0, 1.0) << plant;
    }
}

// Lin et al. Fig. 6 (bottom): the squeeze never falls while masses are added, and rises once the
// load needs more than the minimum normal force (with mu = 0.2 and 70 N: above 2.85 kg in all).
TEST_F(DualArmBox, SqueezeNeverFallsWhileMassIsAdded)
{
    ASSERT_NO_FATAL_FAILURE(run("add_mass", "both"));
    for (const char* plant : {"mujoco", "rigid"}) {
        const CsvTable table = log("add_mass", plant);
        const std::vector<double> mass = table.numbers("box_mass");
        // The settled squeeze of each mass step (the last 0.2 s before the next mass).
        std::vector<double> settled;
        double previous_mass = mass.front();
        double last = 0.0;
        for (std::size_t row = 0; row < table.rows(); ++row) {
            if (mass[row] != previous_mass) {
                settled.push_back(last);
                previous_mass = mass[row];
            }
            last = 0.5 * (table.number(row, "left_pred_fz") + table.number(row, "right_pred_fz"));
        }
        settled.push_back(last);
        ASSERT_EQ(settled.size(), 6u) << plant;
        // "Never falls" to 0.01 N: at the minimum the QP's answer carries the solver's rounding
        // and the moment weighting's trade (up to about 1e-3 N).
        for (std::size_t k = 1; k < settled.size(); ++k) {
            EXPECT_GE(settled[k], settled[k - 1] - 0.01) << plant << " mass step " << k;
        }
        EXPECT_NEAR(settled.front(), 70.0, 0.01) << plant;
        EXPECT_GT(settled.back(), 75.0) << plant;  // 3.2 kg: m g / (2 mu) = 78.5 N
        // Never below the minimum while the load grows.
        EXPECT_GE(std::min(column_min(table, "left_pred_fz"), column_min(table, "right_pred_fz")), 70.0 - 1e-6)
            << plant;
    }
}

// Lin et al. Fig. 8: outside the person's hold the box follows the circle, below it by about its
// uncompensated weight m g / K_z = 0.7 * 9.81 / 100 = 6.9 cm.
TEST_F(DualArmBox, CircleIsTrackedOutsideThePersonsHold)
{
    ASSERT_NO_FATAL_FAILURE(run("circle", "both"));
    for (const char* plant : {"mujoco", "rigid"}) {
        const CsvTable table = log("circle", plant);
        double outside = 0.0, during = 0.0;
        for (std::size_t row = 0; row < table.rows(); ++row) {
            const double t = table.number(row, "time");
            const double error = std::hypot(table.number(row, "y") - table.number(row, "y_d"),
                                            table.number(row, "z") - table.number(row, "z_d"));
            if (t >= 3.0 && t < 5.5) {  // the hold (3-4 s) and 1.5 s to return
                during = std::max(during, error);
            } else {
                outside = std::max(outside, error);
            }
        }
        EXPECT_LT(outside, 0.09) << plant;
        EXPECT_GT(during, outside) << plant;  // the person really held the box off its path
    }
}

// On the rigid plant the only difference between the QP's predicted contact forces and the true
// ones is what the controller's external-wrench estimate L(7) misses: the box's mass (unknown to
// it) times its acceleration, and the person's force, against the estimate from the filtered
// displacement. Model error per tick: |F_true - F_x| with F_true = F_person + m (g - a); each
// palm's force error stays within it.
TEST_F(DualArmBox, RigidPlantContactForcesAgreeWithThePredictionToTheModelError)
{
    ASSERT_NO_FATAL_FAILURE(run("all", "rigid"));
    double worst_ratio = 0.0;
    double worst_error = 0.0;
    for (const std::string& experiment : experiments) {
        const CsvTable table = log(experiment, "rigid");
        for (std::size_t row = 0; row < table.rows(); ++row) {
            const auto at = [&](const char* column) { return table.number(row, column); };
            const double m = at("box_mass");
            const double ex = at("person_fx") - m * at("ax") - at("est_fx");
            const double ey = at("person_fy") - m * at("ay") - at("est_fy");
            const double ez = at("person_fz") - m * (9.81 + at("az")) - at("est_fz");
            const double model_error = std::sqrt(ex * ex + ey * ey + ez * ez);
            for (const char* palm : {"left", "right"}) {
                const std::string p = palm;
                const double dx = table.number(row, p + "_pred_fx") - table.number(row, p + "_meas_fx");
                const double dy = table.number(row, p + "_pred_fy") - table.number(row, p + "_meas_fy");
                const double dz = table.number(row, p + "_pred_fz") - table.number(row, p + "_meas_fz");
                const double error = std::sqrt(dx * dx + dy * dy + dz * dz);
                worst_error = std::max(worst_error, error);
                worst_ratio = std::max(worst_ratio, error / (model_error + 1e-3));
                EXPECT_LE(error, model_error + 1e-3) << experiment << " row " << row;
                if (error > model_error + 1e-3) {
                    return;
                }
            }
        }
    }
    RecordProperty("worst_force_error_N", std::to_string(worst_error));
    RecordProperty("worst_error_over_model_error", std::to_string(worst_ratio));
}

// Every shipped scene (examples/box/scenarios/<scene>/, docs/dual-arm-box.md "Scenes"), every
// experiment, both plants, 2.5 s each (the pushes, masses and circle start by 2 s): the box is held
// (slip below 1 mm in every palm's plane, the whole run simulated: never dropped), every tick's
// contact QP solved and the tick ok, and at rest (the first 0.8 s) the least squeeze: every palm at
// least f_min and the least-pressed one at f_min (its bound: less squeeze would be infeasible),
// with the plant's normal forces the QP's (the measured wrench's frame and sign).
struct SceneCase {
    std::string scene;
    std::vector<std::string> palms;  ///< the CSV's palm names
    double minimum_normal_force;     ///< the scenarios' f_min (N)
};

class DualArmBoxScene : public DualArmBox {
protected:
    void check_scene(const SceneCase& c)
    {
        ASSERT_NO_FATAL_FAILURE(run("all", "both", "--no-minimum-squeeze --scene " + c.scene + " --duration 2.5"));
        EXPECT_TRUE(contains(run_.output, "scene ")) << run_.output;
        for (const std::string& experiment : experiments) {
            for (const char* plant : {"mujoco", "rigid"}) {
                SCOPED_TRACE(c.scene + " " + experiment + " " + plant);
                const CsvTable table = log(experiment, plant);
                ASSERT_EQ(table.rows(), 2500u);  // not dropped: every tick of 2.5 s ran
                for (std::size_t row = 0; row < table.rows(); ++row) {
                    ASSERT_EQ(table.text(row, "qp_status"), "solved") << "row " << row;
                    ASSERT_EQ(table.text(row, "status"), "ok") << "row " << row;
                }
                check_rest(c, table);
            }
        }
    }

    static void check_rest(const SceneCase& c, const CsvTable& table)
    {
        double least = 1e9;
        for (const std::string& palm : c.palms) {
            EXPECT_LT(column_max(table, palm + "_slip"), 1e-3) << palm;
            double predicted = 0.0, measured = 0.0;
            int samples = 0;
            for (std::size_t row = 0; row < table.rows(); ++row) {
                const double t = table.number(row, "time");
                if (t < 0.8) {
                    EXPECT_GE(table.number(row, palm + "_pred_fz"), c.minimum_normal_force - 1e-6)
                        << palm << " t " << t;
                }
                if (t >= 0.4 && t < 0.8) {  // settled
                    predicted += table.number(row, palm + "_pred_fz");
                    measured += table.number(row, palm + "_meas_fz");
                    ++samples;
                }
            }
            predicted /= samples;
            measured /= samples;
            EXPECT_NEAR(measured, predicted, 0.03 * predicted) << palm;
            least = std::min(least, predicted);
        }
        EXPECT_NEAR(least, c.minimum_normal_force, 0.5);
    }
};

TEST_F(DualArmBoxScene, Ur5ePandaHoldsTheBoxInEveryExperimentOnBothPlants)
{
    check_scene({"ur5e_panda", {"ur5e", "panda"}, 30.0});
    // Pushed down with 20 N (held from 2 s), the pair squeezes enough for the controller's
    // friction model: per palm (F + m g) / (2 mu) = (20 + 0.8 * 9.81) / 0.4 = 69.6 N, where the
    // 30 N at rest would hold only 2 mu f_min = 12 N.
    const CsvTable table = log("push", "rigid");
    double pushed = 0.0;
    for (std::size_t row = 0; row < table.rows(); ++row) {
        if (table.number(row, "person_fz") < -19.5) {
            pushed = std::max(pushed, 0.5 * (table.number(row, "ur5e_meas_fz") + table.number(row, "panda_meas_fz")));
        }
    }
    EXPECT_GT(pushed, 0.9 * 69.6);
}

TEST_F(DualArmBoxScene, ThreeArmsHoldTheBoxInEveryExperimentOnBothPlants)
{
    check_scene({"three_arms", {"ur5e", "panda", "b_panda"}, 30.0});
}

// The LWR 4 pair as a scene (examples/scenes/lwr4_pair.json, the same MJCF and start posture):
// the scenario naming it runs at dynamic sizes through the MuJoCo adapter (MujocoArms) and, on
// the rigid plant, the scene's weld on MuJoCo's arm dynamics instead of lwr4_dynamics.hpp's
// recursion. Both are the same physics and, with the scene's rigid plant on RK4 as the LWR 4
// pair's (--rigid-integrator rk4), the same integrator, so the logs agree with the fixed-size
// run's to the solvers' rounding (the CSV's 10 digits: measured within 1e-7 N).
TEST(DualArmBoxInput, TheLwr4PairSceneGivesTheFixedSizeRun)
{
    const fs::path directory = example_tests::fresh_directory(output_root, "lwr4_pair_scene");
    for (const char* name : {"push", "add_mass"}) {
        const std::string text = example_tests::read_file(box_dir + "/scenarios/" + name + ".json");
        const std::string edited =
            "\"scene\": \"" + box_dir + "/../scenes/lwr4_pair.json\", \"name\": \"" + name + "_scene\"";
        ASSERT_TRUE(example_tests::write_edited(text, "\"name\": \"" + std::string(name) + "\"", edited,
                                                directory / (std::string(name) + "_scene.json")));
    }
    const std::string common =
        " --plant both --rigid-integrator rk4 --duration 2.5 --no-plots --quiet --no-minimum-squeeze --output out";
    const ProgramRun scene = example_tests::run_program(
        program, directory, "--scenario push_scene.json --scenario add_mass_scene.json" + common);
    ASSERT_EQ(scene.exit_code, 0) << scene.output;
    const ProgramRun fixed = example_tests::run_program(program, directory, "--experiment push,add_mass" + common);
    ASSERT_EQ(fixed.exit_code, 0) << fixed.output;
    for (const std::string name : {"push", "add_mass"}) {
        for (const std::string plant : {"mujoco", "rigid"}) {
            const CsvTable a((directory / "out" / (name + "_" + plant + ".csv")).string());
            const CsvTable b((directory / "out" / (name + "_scene_" + plant + ".csv")).string());
            ASSERT_EQ(a.rows(), b.rows()) << name << " " << plant;
            for (const std::string column : {"z", "left_pred_fz", "right_pred_fz", "left_meas_fz", "right_meas_fz",
                                              "left_meas_tx", "right_meas_ty", "tau_c_3", "box_mass"}) {
                double worst = 0.0;
                for (std::size_t row = 0; row < a.rows(); ++row) {
                    worst = std::max(worst, std::abs(a.number(row, column) - b.number(row, column)));
                }
                EXPECT_LT(worst, 1e-5) << name << " " << plant << " " << column;
            }
        }
    }
}

TEST(DualArmBoxInput, MalformedScenariosFailWithFileJsonPathAndProblem)
{
    const fs::path directory = example_tests::fresh_directory(output_root, "malformed");
    std::ifstream shipped(box_dir + "/scenarios/push.json");
    const std::string push((std::istreambuf_iterator<char>(shipped)), std::istreambuf_iterator<char>());
    ASSERT_FALSE(push.empty());
    const auto replaced = [&](const std::string& from, const std::string& to) {
        std::string text = push;
        const std::size_t at = text.find(from);
        EXPECT_NE(at, std::string::npos) << from;
        return text.replace(at, from.size(), to);
    };
    struct Case {
        std::string file, text, expected;
    };
    const std::vector<Case> cases{
        {"syntax.json", "{ \"name\": ", "syntax.json: (top level):"},
        {"negative.json", replaced("\"force\": 40.0", "\"force\": -40"), "negative.json: push.force: must be positive"},
        {"huge.json", replaced("\"duration\": 13.0", "\"duration\": 1e400"), "huge.json: duration:"},
        {"unknown.json", replaced("\"ramp\": 1.0", "\"rampe\": 1.0"), "unknown.json: push.rampe: unknown field"},
        {"misspelt.json", replaced("\"push\": {", "\"pushed\": {"), "misspelt.json: pushed: unknown field"},
        {"name.json", replaced("\"name\": \"push\"", "\"name\": \"../escaped\""), "name.json: name:"},
        {"type.json", replaced("\"box_mass\": 0.7", "\"box_mass\": \"heavy\""), "type.json: box_mass: expected a number"},
        {"objective.json", replaced("\"moment_weight\": 10000.0", "\"internal_weight\": 0, \"squeeze_weight\": 0"),
         "objective.json: controller.squeeze_weight: must be positive when torque_weight is 0"},
        // The ranges of --friction and --duration hold for the scenario's values too.
        {"friction.json", replaced("\"friction\": 0.2", "\"friction\": 100"),
         "dual_arm_box: invalid scenario: friction.json: controller.friction: must be between 0.01 and 2, got 100"},
        {"plant.json", replaced("\"sliding\": 0.5", "\"sliding\": 1e9"),
         "dual_arm_box: invalid scenario: plant.json: plant_friction.sliding: must be between 0.01 and 2, got 1e+09"},
        {"short.json", replaced("\"duration\": 13.0", "\"duration\": 0.5"),
         "dual_arm_box: invalid scenario: short.json: duration: must be between 1 and 3600, got 0.5"},
    };
    for (const Case& c : cases) {
        std::ofstream(directory / c.file) << c.text;
        const ProgramRun result =
            example_tests::run_program(program, directory, "--scenario " + c.file + " --no-plots --quiet --output out");
        EXPECT_EQ(result.exit_code, 3) << c.file << ": " << result.output;
        EXPECT_TRUE(contains(result.output, c.expected)) << c.file << ": " << result.output;
        EXPECT_FALSE(fs::exists(directory / "out")) << c.file;
    }
}

TEST(DualArmBoxInput, InvalidOptionsAreRefusedBeforeAnythingRuns)
{
    const fs::path directory = example_tests::fresh_directory(output_root, "options");
    for (const std::string options :
         {"--duration nan", "--duration -1", "--duration inf", "--friction nan", "--friction 0", "--friction 1e400",
          "--plant foo", "--experiment juggle", "--seed -1", "--output ''", "--no-such-option", "--duration 0.5",
          "--friction 50", "--log-every 0", "--log-every 2.5", "--scene octopus"}) {
        const std::string output = contains(options, "--output") ? "" : " --output out";
        const ProgramRun result = example_tests::run_program(program, directory, options + output + " --no-plots");
        EXPECT_EQ(result.exit_code, 2) << options << ": " << result.output;
        EXPECT_LT(result.output.size(), 600u) << options << ": " << result.output;
        EXPECT_FALSE(fs::exists(directory / "out")) << options;
    }
}

TEST(DualArmBoxInput, HelpNamesTheShippedFilesRelativeToTheRepository)
{
    const fs::path directory = example_tests::fresh_directory(output_root, "help");
    const ProgramRun help = example_tests::run_program(program, directory, "--help");
    EXPECT_EQ(help.exit_code, 0) << help.output;
    EXPECT_TRUE(contains(help.output, "examples/box/scenarios")) << help.output;
    EXPECT_FALSE(contains(help.output, box_dir)) << help.output;
    for (const char* option :
         {"--plant", "--experiment", "--scene", "--duration", "--friction", "--seed", "--output"}) {
        EXPECT_TRUE(contains(help.output, option)) << option;
    }
}

TEST(DualArmBoxInput, MissingOrUnwritableFilesAreExitCodeFour)
{
    const fs::path directory = example_tests::fresh_directory(output_root, "files");
    const ProgramRun missing = example_tests::run_program(program, directory, "--scenario nope.json --no-plots --quiet");
    EXPECT_EQ(missing.exit_code, 4) << missing.output;
    EXPECT_TRUE(example_tests::is_one_line(missing.output, "dual_arm_box: cannot read nope.json: No such file or directory"))
        << missing.output;
    // A scenario naming a scene file that is not there: the same, before anything runs.
    const std::string hold = example_tests::read_file(box_dir + "/scenarios/hold.json");
    ASSERT_TRUE(example_tests::write_edited(hold, "\"name\": \"hold\"",
                                            "\"name\": \"hold\", \"scene\": \"nope_scene.json\"",
                                            directory / "on_nothing.json"));
    const ProgramRun scene =
        example_tests::run_program(program, directory, "--scenario on_nothing.json --no-plots --quiet");
    EXPECT_EQ(scene.exit_code, 4) << scene.output;
    EXPECT_TRUE(contains(scene.output, "cannot read nope_scene.json")) << scene.output;
    EXPECT_FALSE(fs::exists(directory / "out")) << scene.output;
    const ProgramRun output = example_tests::run_program(
        program, directory, "--experiment hold --plant rigid --no-plots --quiet --output /proc/nope");
    EXPECT_EQ(output.exit_code, 4) << output.output;
    EXPECT_EQ(output.output.rfind("dual_arm_box: cannot write /proc/nope: ", 0), 0u) << output.output;
    EXPECT_EQ(std::count(output.output.begin(), output.output.end(), '\n'), 1) << output.output;
}

// From a directory of the user's: relative --scenario and --output are that directory's, several
// scenarios run one after the other, --log-every thins the CSV only (the table is from every
// tick), and the hold plot shows the expected sag of the uncompensated weight.
TEST(DualArmBoxInput, RelativePathsSeveralScenariosAndLogEvery)
{
    const fs::path directory = example_tests::fresh_directory(output_root, "relative_paths");
    const fs::path cwd = directory / "a" / "b";
    fs::create_directories(cwd);
    fs::create_directories(directory / "scenarios");
    const std::string hold = example_tests::read_file(box_dir + "/scenarios/hold.json");
    ASSERT_TRUE(example_tests::write_edited(hold, "\"name\": \"hold\"", "\"name\": \"first\"",
                                            directory / "scenarios" / "first.json"));
    ASSERT_TRUE(example_tests::write_edited(hold, "\"name\": \"hold\"", "\"name\": \"second\"",
                                            directory / "scenarios" / "second.json"));
    const std::string common = " --plant rigid --duration 1 --no-plots --quiet --output ../out";
    const ProgramRun run = example_tests::run_program(
        program, cwd, "--scenario ../../scenarios/first.json --scenario ../../scenarios/second.json --log-every 10" + common);
    ASSERT_EQ(run.exit_code, 0) << run.output;
    EXPECT_TRUE(contains(run.output, "1 tick in 10")) << run.output;
    for (const char* name : {"first", "second"}) {
        const CsvTable table((directory / "a" / "out" / (std::string(name) + "_rigid.csv")).string());
        ASSERT_EQ(table.rows(), 100u) << name;  // ticks 0, 10, ..., 990 of 1000
        EXPECT_NEAR(table.number(1, "time") - table.number(0, "time"), 0.01, 1e-12) << name;
    }
    // The table is the same as without --log-every.
    const ProgramRun full = example_tests::run_program(program, cwd, "--scenario ../../scenarios/first.json" + common);
    ASSERT_EQ(full.exit_code, 0) << full.output;
    const auto table_row = [](const std::string& output) {
        const std::size_t at = output.find("\nfirst ");
        return at == std::string::npos ? std::string() : output.substr(at, output.find('\n', at + 1) - at);
    };
    ASSERT_FALSE(table_row(full.output).empty()) << full.output;
    const auto without_rtf = [](const std::string& row) {  // the last column, the real-time factor, varies
        const std::string trimmed = row.substr(0, row.find_last_not_of(' ') + 1);
        return trimmed.substr(0, trimmed.find_last_of(' '));
    };
    EXPECT_EQ(without_rtf(table_row(run.output)), without_rtf(table_row(full.output)));
    EXPECT_EQ(CsvTable((directory / "a" / "out" / "first_rigid.csv").string()).rows(), 1000u);

    // The hold plot: the expected sag m g / K_z = 0.7 * 9.81 / 100 = 68.7 mm, weight not compensated.
    const std::string script = example_tests::read_file(directory / "a" / "out" / "first_rigid.gp");
    EXPECT_TRUE(contains(script, "weight not compensated")) << script;
    EXPECT_TRUE(contains(script, "= 68.7 mm")) << script;
    EXPECT_TRUE(contains(script, "(column('z_d')) - 0.06867)")) << script;

    // Defaults: the shipped scenario from anywhere, out/box/ in the working directory.
    const ProgramRun defaults = example_tests::run_program(
        program, cwd, "--experiment hold --plant rigid --duration 1 --no-plots --quiet");
    ASSERT_EQ(defaults.exit_code, 0) << defaults.output;
    EXPECT_TRUE(fs::exists(cwd / "out" / "box" / "hold_rigid.csv"));
}

}  // namespace
