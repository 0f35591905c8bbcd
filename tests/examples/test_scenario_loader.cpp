// Tests of the scenario loader of the two-arm beam example (examples/beam/scenario.hpp, on the shared
// examples/common/json_reader.hpp): every shipped scenario loads, and each kind of malformed or
// physically invalid file is refused with a message that names the JSON path of the field and what
// is wrong with it, nlohmann-json's own errors (e.g. a number too large for a double) included.
#include "scenario.hpp"

#include "common/json_reader.hpp"
#include "common/output_names.hpp"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using beam_example::Scenario;
using beam_example::ScenarioError;
using nlohmann::json;

const std::string scenario_dir = COOPDYN_SCENARIO_DIR;

std::string read_text(const std::string& path)
{
    std::ifstream file(path);
    std::ostringstream text;
    text << file.rdbuf();
    return text.str();
}

json beam_document() { return json::parse(read_text(scenario_dir + "/beam.json")); }

/// Parses `document` after `edit`, expecting a ScenarioError at `path` whose problem contains
/// `problem`; returns the message.
std::string expect_refused(const std::function<void(json&)>& edit, const std::string& path,
                           const std::string& problem)
{
    json document = beam_document();
    edit(document);
    try {
        const Scenario scenario = beam_example::parse_scenario(document.dump(2), "edited.json");
        ADD_FAILURE() << "accepted an invalid scenario (expected '" << path << ": " << problem << "')";
        return {};
    } catch (const ScenarioError& error) {
        const std::string message = error.what();
        EXPECT_EQ(error.path(), path) << message;
        EXPECT_NE(error.problem().find(problem), std::string::npos) << message;
        EXPECT_EQ(message.rfind("edited.json: " + path + ": ", 0), 0u) << message;
        std::printf("[ refused ] %s\n", message.c_str());
        return message;
    }
}

// ---------------------------------------------------------------------------------------------
// Shipped scenarios

TEST(ScenarioLoader, EveryShippedScenarioLoads)
{
    int count = 0;
    for (const auto& entry : std::filesystem::directory_iterator(scenario_dir)) {
        if (entry.path().extension() != ".json") {
            continue;
        }
        SCOPED_TRACE(entry.path().string());
        const Scenario scenario = beam_example::load_scenario(entry.path().string());
        EXPECT_FALSE(scenario.name.empty());
        EXPECT_FALSE(scenario.description.empty());
        EXPECT_GE(scenario.arm_count(), 2);
        // The loaded parameters build a coopdyn Model.
        const coopdyn::ImpedanceModelX model(scenario.object, scenario.arms, scenario.gravity);
        EXPECT_EQ(model.arms(), scenario.arm_count());
        ++count;
    }
    EXPECT_GE(count, 3) << "the beam, the three-arm plate and the asymmetric grasp";
}

TEST(ScenarioLoader, BeamHoldsModelSection9Numbers)
{
    const Scenario beam = beam_example::load_scenario(scenario_dir + "/beam.json");
    EXPECT_EQ(beam.name, "beam");
    EXPECT_DOUBLE_EQ(beam.time_step, 1e-3);
    EXPECT_DOUBLE_EQ(beam.object.mass, 1.75);
    EXPECT_TRUE(beam.object.inertia_body.isApprox(Eigen::Vector3d(0.055, 0.0, 0.055).asDiagonal().toDenseMatrix()));
    ASSERT_EQ(beam.arm_count(), 2);
    for (int i = 0; i < 2; ++i) {
        const auto& arm = beam.arms[static_cast<std::size_t>(i)];
        EXPECT_DOUBLE_EQ(arm.end_effector.mass, 10.0);
        EXPECT_TRUE(arm.end_effector.rotational_inertia.isApprox(0.5 * Eigen::Matrix3d::Identity()));
        EXPECT_DOUBLE_EQ(arm.end_effector.translational_damping, 180.0);
        EXPECT_DOUBLE_EQ(arm.end_effector.rotational_damping, 10.0);
        EXPECT_DOUBLE_EQ(arm.end_effector.translational_stiffness, 300.0);
        EXPECT_DOUBLE_EQ(arm.end_effector.rotational_stiffness, 50.0);
        EXPECT_TRUE(arm.grasp_body.position.isApprox(Eigen::Vector3d(0.0, i == 0 ? -0.4 : 0.4, 0.0)));
    }
    ASSERT_TRUE(beam.paper.has_value());
    ASSERT_TRUE(beam.paper->translation_x && beam.paper->rotation_z && beam.paper->se3);
    EXPECT_DOUBLE_EQ(beam.paper->translation_x->identified->stiffness.at(0), 630.0);
    EXPECT_DOUBLE_EQ(*beam.paper->translation_x->mean_squared_output_error, 3.86e-6);
    EXPECT_DOUBLE_EQ(*beam.paper->rotation_z->mean_squared_output_error, 2.46e-5);
    EXPECT_DOUBLE_EQ(beam.paper->se3->identified->inertia.at(4), 0.45);

    // Theorem 2 at the equilibrium gives the paper's nominal (56), (59), (61).
    const coopdyn::ImpedanceModelX model(beam.object, beam.arms, beam.gravity);
    coopdyn::Data<coopdyn::ImpedanceModelX> data(model);
    coopdyn::RigidBodyState<double> state;
    state.pose = beam.equilibrium;
    coopdyn::grasp_kinematics(model, data, state);
    const auto impedance = coopdyn::apparent_impedance(model, data);
    coopdyn::Vector6<double> m, d, k;
    m << 21.75, 21.75, 21.75, 4.255, 1.0, 4.255;
    d << 360, 360, 360, 77.6, 20, 77.6;
    k << 600, 600, 600, 196, 100, 196;
    EXPECT_TRUE(impedance.inertia.isApprox(coopdyn::Matrix6<double>(m.asDiagonal()), 1e-12));
    EXPECT_TRUE(impedance.damping.isApprox(coopdyn::Matrix6<double>(d.asDiagonal()), 1e-12));
    EXPECT_TRUE(impedance.stiffness.isApprox(coopdyn::Matrix6<double>(k.asDiagonal()), 1e-12));
}

TEST(ScenarioLoader, OptionalFieldsTakeTheirDefaults)
{
    json document = beam_document();
    document.erase("time_step");
    document.erase("gravity");
    document.erase("excitation");
    document.erase("paper");
    document.erase("description");
    document["object"].erase("position");
    document["object"].erase("orientation");
    document["arms"][0]["grasp_body"].erase("orientation");
    const Scenario scenario = beam_example::parse_scenario(document.dump(), "minimal.json");
    EXPECT_DOUBLE_EQ(scenario.time_step, 1e-3);
    EXPECT_TRUE(scenario.gravity.isApprox(Eigen::Vector3d(0, 0, -9.81)));
    EXPECT_TRUE(scenario.equilibrium.position.isZero());
    EXPECT_FALSE(scenario.paper.has_value());
    EXPECT_FALSE(scenario.has_custom_weights());
    EXPECT_DOUBLE_EQ(scenario.excitation.force, 5.0);
}

TEST(ScenarioLoader, InertiaAsFullMatrixEqualsDiagonalShorthand)
{
    json document = beam_document();
    document["object"]["inertia_body"] = json::parse("[[0.055, 0, 0], [0, 0, 0], [0, 0, 0.055]]");
    const Scenario full = beam_example::parse_scenario(document.dump(), "full.json");
    const Scenario shorthand = beam_example::load_scenario(scenario_dir + "/beam.json");
    EXPECT_TRUE(full.object.inertia_body.isApprox(shorthand.object.inertia_body));
}

// ---------------------------------------------------------------------------------------------
// Malformed files: every kind of error names the field and the problem.

// The excitation's amplitudes have the range of --force and --torque (one definition,
// beam_example::excitation_force_range / excitation_torque_range), and the message names it.
TEST(ScenarioLoader, ExcitationAmplitudesHaveTheCommandLinesRange)
{
    EXPECT_EQ(beam_example::excitation_force_range.low, 1e-3);
    EXPECT_EQ(beam_example::excitation_force_range.high, 1e3);
    expect_refused([](json& d) { d["excitation"]["force"] = 1e9; }, "excitation.force",
                   "must be between 0.001 and 1000, got 1e+09");
    expect_refused([](json& d) { d["excitation"]["torque"] = 0.0; }, "excitation.torque",
                   "must be between 0.001 and 1000, got 0");
    json document = beam_document();
    document["excitation"]["force"] = 1000.0;  // the limit itself is accepted
    document["excitation"]["torque"] = 1e-3;
    const Scenario scenario = beam_example::parse_scenario(document.dump(), "limits.json");
    EXPECT_DOUBLE_EQ(scenario.excitation.force, 1000.0);
    EXPECT_DOUBLE_EQ(scenario.excitation.torque, 1e-3);
}

TEST(ScenarioLoader, MissingField)
{
    expect_refused([](json& d) { d["arms"][0]["end_effector"].erase("mass"); }, "arms[0].end_effector.mass",
                   "missing required field");
    expect_refused([](json& d) { d.erase("object"); }, "object", "missing required field");
    expect_refused([](json& d) { d["object"].erase("inertia_body"); }, "object.inertia_body",
                   "missing required field");
    expect_refused([](json& d) { d["arms"][1]["grasp_body"].erase("position"); }, "arms[1].grasp_body.position",
                   "missing required field");
    expect_refused([](json& d) { d.erase("arm_count"); }, "arm_count", "missing required field");
}

TEST(ScenarioLoader, WrongType)
{
    expect_refused([](json& d) { d["arms"][1]["end_effector"]["mass"] = "ten"; }, "arms[1].end_effector.mass",
                   "expected a number, got string");
    expect_refused([](json& d) { d["object"]["position"] = json::parse("[0, \"a\", 1]"); }, "object.position[1]",
                   "expected a number, got string");
    expect_refused([](json& d) { d["object"]["position"] = json::parse("[0, 1]"); }, "object.position",
                   "expected 3 entries, got 2");
    expect_refused([](json& d) { d["arms"] = json::object(); }, "arms", "expected an array, got object");
    expect_refused([](json& d) { d["arms"][0]["end_effector"] = 3; }, "arms[0].end_effector",
                   "expected an object, got number");
    expect_refused([](json& d) { d["arm_count"] = 2.5; }, "arm_count", "expected an integer");
    expect_refused([](json& d) { d["name"] = true; }, "name", "expected a string, got boolean");
    expect_refused([](json& d) { d["paper"]["se3"]["identified"]["damping"] = json::parse("[1, 2]"); },
                   "paper.se3.identified.damping", "expected 6 entries, got 2");
}

TEST(ScenarioLoader, NegativeMass)
{
    expect_refused([](json& d) { d["object"]["mass"] = -1.75; }, "object.mass",
                   "must be positive and finite, got -1.75");
    expect_refused([](json& d) { d["arms"][1]["end_effector"]["mass"] = -10.0; }, "arms[1].end_effector.mass",
                   "must be positive and finite, got -10");
    expect_refused([](json& d) { d["arms"][0]["end_effector"]["translational_damping"] = -1.0; },
                   "arms[0].end_effector.translational_damping", "must be non-negative");
}

TEST(ScenarioLoader, NonPositiveDefiniteInertia)
{
    expect_refused(
        [](json& d) { d["arms"][1]["end_effector"]["rotational_inertia"] = json::parse("[[1, 2, 0], [2, 1, 0], [0, 0, 1]]"); },
        "arms[1].end_effector.rotational_inertia", "must be symmetric positive definite");
    expect_refused([](json& d) { d["object"]["inertia_body"] = json::parse("[0.055, -0.01, 0.055]"); },
                   "object.inertia_body", "must be symmetric positive semi-definite");
    expect_refused(
        [](json& d) { d["object"]["inertia_body"] = json::parse("[[0.055, 0.01, 0], [0, 0.03, 0], [0, 0, 0.055]]"); },
        "object.inertia_body", "must be symmetric");
    expect_refused([](json& d) { d["load_distribution"] = json::parse(R"({"mass_weights": [1, 1],
                      "inertia_weights": [[0.1, 0.1, 0.1], [[1, 2, 0], [2, 1, 0], [0, 0, 1]]]})"); },
                   "load_distribution.inertia_weights[1]", "must be symmetric positive semi-definite");
}

TEST(ScenarioLoader, ArmCountMismatch)
{
    expect_refused([](json& d) { d["arm_count"] = 3; }, "arms", "holds 2 arm(s) but arm_count is 3 (N mismatch)");
    expect_refused([](json& d) { d["arms"].erase(1); }, "arms", "holds 1 arm(s) but arm_count is 2 (N mismatch)");
    expect_refused([](json& d) { d["load_distribution"] = json::parse(R"({"mass_weights": [1, 1, 1],
                      "inertia_weights": [[0.1, 0.1, 0.1], [0.1, 0.1, 0.1]]})"); },
                   "load_distribution.mass_weights", "expected one weight per arm (2), got 3 (N mismatch)");
    expect_refused([](json& d) { d["load_distribution"] = json::parse(R"({"mass_weights": [1, 1],
                      "inertia_weights": [[0.1, 0.1, 0.1]]})"); },
                   "load_distribution.inertia_weights", "(N mismatch)");
    expect_refused([](json& d) { d["arm_count"] = 0; }, "arm_count", "must be at least 1, got 0");
}

TEST(ScenarioLoader, OtherInvalidContent)
{
    expect_refused([](json& d) { d["arms"][0]["end_effector"]["stifness"] = 1.0; }, "arms[0].end_effector.stifness",
                   "unknown field");
    expect_refused([](json& d) { d["object"]["orientation"] = json::parse("[1, 0, 0, 0.5]"); }, "object.orientation",
                   "must be a unit quaternion");
    expect_refused([](json& d) { d["time_step"] = 0.0; }, "time_step", "must be positive, got 0");
    // Physically invalid as a whole: no stiffness at all leaves the object without an equilibrium.
    expect_refused(
        [](json& d) {
            for (auto& arm : d["arms"]) {
                arm["end_effector"]["translational_stiffness"] = 0.0;
                arm["end_effector"]["rotational_stiffness"] = 0.0;
            }
        },
        "arms", "apparent stiffness K (Theorem 2) that is not positive definite");
    // Grasp points on one line with no rotational weights: the torque about the line cannot be distributed.
    expect_refused([](json& d) { d["load_distribution"] = json::parse(R"({"mass_weights": [1, 1],
                      "inertia_weights": [[0, 0, 0], [0, 0, 0]]})"); },
                   "load_distribution.inertia_weights", "degenerate");
}

TEST(ScenarioLoader, SyntaxErrorAndMissingFile)
{
    try {
        beam_example::parse_scenario("{\"name\": \"beam\",, }", "broken.json");
        ADD_FAILURE() << "accepted invalid JSON";
    } catch (const ScenarioError& error) {
        const std::string message = error.what();
        std::printf("[ refused ] %s\n", message.c_str());
        EXPECT_NE(message.find("broken.json: (top level): not valid JSON: parse error at line 1"), std::string::npos)
            << message;
    }
    // A file that cannot be read is no invalid scenario: a FileError (the programs' exit_file).
    try {
        beam_example::load_scenario(scenario_dir + "/no_such_file.json");
        ADD_FAILURE() << "loaded a file that does not exist";
    } catch (const example_common::FileError& error) {
        EXPECT_EQ(std::string(error.what()),
                  "cannot read " + scenario_dir + "/no_such_file.json: No such file or directory");
        EXPECT_EQ(error.access(), example_common::FileError::Access::read);
    }
    try {
        beam_example::load_scenario(scenario_dir);
        ADD_FAILURE() << "loaded a directory";
    } catch (const example_common::FileError& error) {
        EXPECT_EQ(std::string(error.what()), "cannot read " + scenario_dir + ": is a directory, not a file");
    }
    EXPECT_THROW(beam_example::parse_scenario("[1, 2, 3]", "array.json"), ScenarioError);
}

// ---------------------------------------------------------------------------------------------
// Numbers nlohmann-json cannot hold, and names that would leave the output folder.

/// Parses the beam with the JSON text `literal` in place of the value that `edit` sets to a
/// marker, expecting a ScenarioError at `path` whose problem contains `problem`.
void expect_literal_refused(const std::function<void(json&)>& edit, const std::string& literal,
                            const std::string& path, const std::string& problem)
{
    json document = beam_document();
    edit(document);
    std::string text = document.dump(2);
    const std::string marker = "\"@@marker@@\"";
    const auto at = text.find(marker);
    ASSERT_NE(at, std::string::npos);
    text.replace(at, marker.size(), literal);
    try {
        beam_example::parse_scenario(text, "edited.json");
        ADD_FAILURE() << "accepted " << literal << " at " << path;
    } catch (const ScenarioError& error) {
        std::printf("[ refused ] %s\n", error.what());
        EXPECT_EQ(error.path(), path) << error.what();
        EXPECT_NE(error.problem().find(problem), std::string::npos) << error.what();
        EXPECT_EQ(std::string(error.what()).rfind("edited.json: " + path + ": ", 0), 0u) << error.what();
    }
}

TEST(ScenarioLoader, NumberTooLargeForADoubleNamesFileAndPath)
{
    // nlohmann-json refuses 1e400 (it would be inf) with an out_of_range exception that names
    // neither the file nor the field; the loader reports both.
    const auto marker = [](json& value) { value = "@@marker@@"; };
    expect_literal_refused([&](json& d) { marker(d["object"]["mass"]); }, "1e400", "object.mass",
                           "not a finite number");
    expect_literal_refused([&](json& d) { marker(d["arms"][1]["end_effector"]["rotational_inertia"][2]); }, "-1e400",
                           "arms[1].end_effector.rotational_inertia[2]", "not a finite number");
    // After a whole object in an array (arms[0]) the index moves on.
    expect_literal_refused([&](json& d) { marker(d["arms"][1]["grasp_body"]["position"][0]); }, "1e999",
                           "arms[1].grasp_body.position[0]", "number overflow parsing '1e999'");
    expect_literal_refused([&](json& d) { marker(d["paper"]["se3"]["identified"]["damping"][4]); }, "2e308",
                           "paper.se3.identified.damping[4]", "not a finite number");
    expect_literal_refused([&](json& d) { marker(d["time_step"]); }, "1e400", "time_step", "not a finite number");
    // Integers: too large for the loader's integer type, or written as a whole float.
    expect_literal_refused([&](json& d) { marker(d["arm_count"]); }, "18446744073709551615", "arm_count",
                           "integer too large");
    expect_literal_refused([&](json& d) { marker(d["arm_count"]); }, "1e20", "arm_count",
                           "expected an integer, got 1e+20");
    // Numbers that are finite but out of range for the field stay the loader's usual errors.
    expect_literal_refused([&](json& d) { marker(d["object"]["mass"]); }, "-1e300", "object.mass",
                           "must be positive and finite");
}

TEST(ScenarioLoader, NameMustBeAPlainFileName)
{
    // The name prefixes every output file (<output>/<name>_x.csv): it is checked at load time.
    expect_refused([](json& d) { d["name"] = "../escaped"; }, "name", "must not contain a path separator");
    expect_refused([](json& d) { d["name"] = "/tmp/escaped"; }, "name", "must not contain a path separator");
    expect_refused([](json& d) { d["name"] = "a\\b"; }, "name", "must not contain a path separator");
    expect_refused([](json& d) { d["name"] = ""; }, "name", "must not be empty");
    expect_refused([](json& d) { d["name"] = ".hidden"; }, "name", "must not start with a dot");
    expect_refused([](json& d) { d["name"] = ".."; }, "name", "must not start with a dot");
    expect_refused([](json& d) { d["name"] = "two words"; }, "name", "must be a plain file name");
    expect_refused([](json& d) { d["name"] = "quote'"; }, "name", "must be a plain file name");
    expect_refused([](json& d) { d["name"] = "line\nbreak"; }, "name", "\\x0a");
    expect_refused([](json& d) { d["name"] = std::string(65, 'a'); }, "name", "is too long, 65 characters");

    json document = beam_document();
    document["name"] = "Beam_v2.1-test";
    EXPECT_EQ(beam_example::parse_scenario(document.dump(), "ok.json").name, "Beam_v2.1-test");
}

TEST(JsonReader, EveryNlohmannExceptionBecomesAScenarioError)
{
    using example_common::JsonReader;
    // A schema that trips over nlohmann-json itself (at() on a missing key throws out_of_range):
    // read_document reports it at the path read last.
    const auto schema = [](const JsonReader& reader, const json& document) {
        const json& object = reader.required(document, "", "object");
        reader.expect_object(object, "object");
        return object.at("no_such_key").get<double>();
    };
    try {
        example_common::read_document(R"({"object": {"mass": 1}})", "schema.json", schema);
        ADD_FAILURE() << "no error";
    } catch (const ScenarioError& error) {
        std::printf("[ refused ] %s\n", error.what());
        EXPECT_EQ(error.source(), "schema.json");
        EXPECT_EQ(error.path(), "object");
        EXPECT_NE(error.problem().find("no_such_key"), std::string::npos) << error.what();
        EXPECT_EQ(error.problem().find("[json.exception"), std::string::npos) << error.what();
    }
    // Top-level errors and a number overflow in a top-level array.
    EXPECT_THROW(example_common::parse_json("", "empty.json"), ScenarioError);
    try {
        example_common::parse_json("[1, {\"a\": [2]}, 1e400]", "array.json");
        ADD_FAILURE() << "no error";
    } catch (const ScenarioError& error) {
        EXPECT_EQ(error.path(), "[2]") << error.what();
    }
}

TEST(JsonReader, ValueChecks)
{
    const example_common::JsonReader reader("checks.json");
    EXPECT_DOUBLE_EQ(reader.in_range(json(0.5), "a", 0.0, 1.0), 0.5);
    const auto problem = [](const std::function<void()>& read) {
        try {
            read();
        } catch (const ScenarioError& error) {
            return error.problem();
        }
        return std::string("(accepted)");
    };
    EXPECT_EQ(problem([&] { reader.in_range(json(2.0), "a", 0.0, 1.0); }), "must be between 0 and 1, got 2");
    EXPECT_EQ(problem([&] { reader.in_range(json(-2.0), "a", 0.0, 1e300); }), "must be between 0 and 1e+300, got -2");
    EXPECT_EQ(problem([&] { reader.non_negative(json(-1.0), "a"); }), "must be non-negative, got -1");
    EXPECT_EQ(problem([&] { reader.positive(json(0.0), "a"); }), "must be positive, got 0");
    EXPECT_EQ(problem([&] { reader.number(json(std::numeric_limits<double>::infinity()), "a"); }),
              "must be finite, got inf");
    EXPECT_EQ(problem([&] { reader.number(json("1"), "a"); }), "expected a number, got string");
    EXPECT_EQ(problem([&] { reader.only_keys(json::parse(R"({"b": 1})"), "a", {"c"}); }),
              "unknown field (allowed here: c)");
    EXPECT_EQ(problem([&] { reader.required(json::parse(R"({"b": 1})"), "a", "c"); }), "missing required field");

    // Output files are built only from plain names.
    EXPECT_EQ(example_common::confined_path("out", "beam_x.csv"), std::filesystem::path("out") / "beam_x.csv");
    EXPECT_THROW(example_common::confined_path("out", "../beam_x.csv"), std::runtime_error);
    EXPECT_THROW(example_common::confined_path("out", ""), std::runtime_error);
    EXPECT_THROW(example_common::confined_path("out", ".."), std::runtime_error);
}

}  // namespace
