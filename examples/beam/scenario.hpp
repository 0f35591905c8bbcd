// Scenario files of the two-arm beam example: one JSON file describes one cooperative set-up
// (object, arms, grasp, equilibrium, excitation defaults and, optionally, the paper's reference
// values). The format is documented in docs/two-arm-beam.md ("Scenario files").
//
// This header belongs to the examples, not to the library: it depends on nlohmann-json, while
// include/coopdyn/ depends on Eigen only. The example and its tests share it.
//
// Loading is all-or-nothing: load_scenario() reads and checks the whole file (syntax, every
// field's presence and type, unknown fields, physical validity through coopdyn's own Model
// construction) and either returns a complete Scenario or throws ScenarioError, whose message
// names the file, the JSON path of the offending field and what is wrong, e.g.
//
//   scenarios/beam.json: arms[1].end_effector.mass: expected a number, got string
//   scenarios/beam.json: arms[0].end_effector.mass: must be positive and finite, got -10
#pragma once

#include "../common/json_reader.hpp"

#include <coopdyn/coopdyn.hpp>

#include <nlohmann/json.hpp>

#include <array>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace beam_example {

/// A scenario file is malformed or describes an invalid set-up: "<source>: <json path>:
/// <problem>" (the shared loader's error type, examples/common/json_reader.hpp).
using example_common::ScenarioError;

/// Reference values of one experiment from the paper (one entry per identified axis: 1 for the
/// single-axis experiments, 6 for SE(3) in the order x, y, z, rot x, rot y, rot z).
struct ImpedanceValues {
    std::vector<double> inertia, damping, stiffness;
};
struct PaperExperiment {
    std::optional<ImpedanceValues> nominal;     ///< the paper's nominal values, e.g. (56)
    std::optional<ImpedanceValues> identified;  ///< identified on the real robots, e.g. (57)
    std::optional<double> mean_squared_output_error;  ///< of the paper's identified model (m^2 or rad^2)
};
struct PaperReference {
    std::string source;
    std::optional<PaperExperiment> translation_x, rotation_z, se3;
};

/// Amplitudes of the disturbance wrench when the command line does not override them.
struct ExcitationDefaults {
    double force = 5.0;   ///< N: RMS of each multisine force channel, or peak of a push
    double torque = 1.0;  ///< N m: the same for torques
};

/// The excitation's amplitudes: the range of the scenario's "excitation.force" / "excitation.torque"
/// and of --force / --torque (which also take 0: the scenario's), one definition for both.
inline constexpr example_common::NumberRange excitation_force_range{1e-3, 1e3};   ///< N
inline constexpr example_common::NumberRange excitation_torque_range{1e-3, 1e3};  ///< N m

using Arm = coopdyn::Arm<coopdyn::ImpedanceEndEffector<double>>;

/// A complete, validated set-up.
struct Scenario {
    std::string source;  ///< file name (or label) it was read from
    std::string name;
    std::string description;
    double time_step = 1e-3;  ///< s
    Eigen::Vector3d gravity = coopdyn::standard_gravity<double>();
    coopdyn::RigidObject<double> object;
    coopdyn::Pose<double> equilibrium;  ///< object pose the arms hold (setpoints at its grasp poses)
    std::vector<Arm> arms;
    /// Load-distribution weights m*_i (N) and J*_i (3 x 3N); empty = the end-effector inertias.
    Eigen::VectorXd mass_weights;
    Eigen::Matrix3Xd inertia_weights;
    ExcitationDefaults excitation;
    std::optional<PaperReference> paper;

    coopdyn::Index arm_count() const { return static_cast<coopdyn::Index>(arms.size()); }
    bool has_custom_weights() const { return mass_weights.size() > 0; }
};

namespace detail {

using example_common::index_path;
using example_common::join_path;
using example_common::json;
using Reader = example_common::JsonReader;

inline coopdyn::Pose<double> pose(const Reader& reader, const json& object, const std::string& path)
{
    coopdyn::Pose<double> result;
    if (const json* position = reader.optional(object, "position")) {
        result.position = reader.vector3(*position, join_path(path, "position"));
    }
    if (const json* orientation = reader.optional(object, "orientation")) {
        result.orientation = reader.quaternion(*orientation, join_path(path, "orientation"));
    }
    return result;
}

inline ImpedanceValues impedance_values(const Reader& reader, const json& value, const std::string& path,
                                        std::size_t axes)
{
    reader.only_keys(value, path, {"inertia", "damping", "stiffness"});
    ImpedanceValues result;
    result.inertia = reader.numbers(reader.required(value, path, "inertia"), join_path(path, "inertia"), axes);
    result.damping = reader.numbers(reader.required(value, path, "damping"), join_path(path, "damping"), axes);
    result.stiffness = reader.numbers(reader.required(value, path, "stiffness"), join_path(path, "stiffness"), axes);
    return result;
}

inline PaperExperiment paper_experiment(const Reader& reader, const json& value, const std::string& path,
                                        std::size_t axes)
{
    reader.only_keys(value, path, {"nominal", "identified", "mean_squared_output_error"});
    PaperExperiment result;
    if (const json* nominal = reader.optional(value, "nominal")) {
        result.nominal = impedance_values(reader, *nominal, join_path(path, "nominal"), axes);
    }
    if (const json* identified = reader.optional(value, "identified")) {
        result.identified = impedance_values(reader, *identified, join_path(path, "identified"), axes);
    }
    if (const json* error = reader.optional(value, "mean_squared_output_error")) {
        result.mean_squared_output_error = reader.positive(*error, join_path(path, "mean_squared_output_error"));
    }
    return result;
}

/// Runs a coopdyn validation and turns its coopdyn::Error into a ScenarioError at the JSON path
/// of the refused parameter, read from the error's fields. The file's field names are coopdyn's
/// parameter names, so the mapping is mechanical: component "object" -> object.<p>; an arm's
/// parameter -> arms[i].end_effector.<p> (arms[i].<p> for grasp_body.*,
/// load_distribution.<p>[i] for the weights); "load distribution" -> load_distribution.<p>;
/// anything else (the model's own parameters) -> <p>.
template <typename Check> void physical(const Reader& reader, Check&& check)
{
    try {
        check();
    } catch (const coopdyn::Error& error) {
        const std::string& parameter = error.parameter();
        std::string path = parameter;
        if (error.has_arm()) {
            const std::string index = std::to_string(error.arm());
            if (error.component() == "load distribution") {
                path = "load_distribution." + parameter + "[" + index + "]";
            } else if (parameter.compare(0, 10, "grasp_body") == 0) {
                path = join_path("arms[" + index + "]", parameter);
            } else {
                path = join_path("arms[" + index + "].end_effector", parameter);
            }
        } else if (error.component() == "object") {
            path = join_path("object", parameter);
        } else if (error.component() == "load distribution") {
            path = join_path("load_distribution", parameter);
        }
        reader.fail(path, error.problem());
    }
}

inline coopdyn::ImpedanceEndEffector<double> end_effector(const Reader& reader, const json& value,
                                                          const std::string& path)
{
    reader.expect_object(value, path);
    reader.only_keys(value, path,
                     {"mass", "rotational_inertia", "translational_damping", "rotational_damping",
                      "translational_stiffness", "rotational_stiffness"});
    coopdyn::ImpedanceEndEffector<double> result;
    result.mass = reader.number(reader.required(value, path, "mass"), join_path(path, "mass"));
    result.rotational_inertia =
        reader.matrix3(reader.required(value, path, "rotational_inertia"), join_path(path, "rotational_inertia"));
    result.translational_damping = reader.number(reader.required(value, path, "translational_damping"),
                                                 join_path(path, "translational_damping"));
    result.rotational_damping =
        reader.number(reader.required(value, path, "rotational_damping"), join_path(path, "rotational_damping"));
    result.translational_stiffness = reader.number(reader.required(value, path, "translational_stiffness"),
                                                   join_path(path, "translational_stiffness"));
    result.rotational_stiffness = reader.number(reader.required(value, path, "rotational_stiffness"),
                                                join_path(path, "rotational_stiffness"));
    return result;
}

/// "object": the object's mass and inertia, and its pose, the equilibrium.
inline void read_object(const Reader& reader, const json& document, Scenario& scenario)
{
    const json& object = reader.required(document, "", "object");
    reader.expect_object(object, "object");
    reader.only_keys(object, "object", {"mass", "inertia_body", "position", "orientation"});
    scenario.object.mass = reader.number(reader.required(object, "object", "mass"), "object.mass");
    scenario.object.inertia_body = reader.matrix3(reader.required(object, "object", "inertia_body"), "object.inertia_body");
    scenario.equilibrium = pose(reader, object, "object");
    physical(reader, [&] { scenario.object.validate(); });
}

/// "arm_count" and "arms": each arm's grasp pose on the object and its end-effector.
inline void read_arms(const Reader& reader, const json& document, Scenario& scenario)
{
    const long long arm_count = reader.integer(reader.required(document, "", "arm_count"), "arm_count");
    if (arm_count < 1) {
        reader.fail("arm_count", "must be at least 1, got " + std::to_string(arm_count));
    }
    const json& arms = reader.array(reader.required(document, "", "arms"), "arms");
    if (arms.size() != static_cast<std::size_t>(arm_count)) {
        reader.fail("arms", "holds " + std::to_string(arms.size()) + " arm(s) but arm_count is " +
                                std::to_string(arm_count) + " (N mismatch)");
    }
    for (std::size_t i = 0; i < arms.size(); ++i) {
        const std::string path = index_path("arms", i);
        const json& arm = arms[i];
        reader.expect_object(arm, path);
        reader.only_keys(arm, path, {"grasp_body", "end_effector"});
        const json& grasp = reader.required(arm, path, "grasp_body");
        reader.expect_object(grasp, join_path(path, "grasp_body"));
        reader.only_keys(grasp, join_path(path, "grasp_body"), {"position", "orientation"});
        reader.required(grasp, join_path(path, "grasp_body"), "position");
        Arm result;
        result.grasp_body = pose(reader, grasp, join_path(path, "grasp_body"));
        result.end_effector =
            end_effector(reader, reader.required(arm, path, "end_effector"), join_path(path, "end_effector"));
        physical(reader, [&] { result.end_effector.validate(static_cast<coopdyn::Index>(i)); });
        scenario.arms.push_back(result);
    }
}

/// "load_distribution" (optional): the weights of (25)-(26), one mass and one 3x3 inertia weight per arm.
inline void read_load_distribution(const Reader& reader, const json& document, Scenario& scenario)
{
    const std::size_t count = scenario.arms.size();
    if (const json* weights = reader.optional(document, "load_distribution")) {
        const std::string path = "load_distribution";
        reader.expect_object(*weights, path);
        reader.only_keys(*weights, path, {"mass_weights", "inertia_weights"});
        const std::vector<double> masses =
            reader.numbers(reader.required(*weights, path, "mass_weights"), join_path(path, "mass_weights"));
        if (masses.size() != count) {
            reader.fail(join_path(path, "mass_weights"), "expected one weight per arm (" + std::to_string(count) +
                                                             "), got " + std::to_string(masses.size()) +
                                                             " (N mismatch)");
        }
        const json& inertias =
            reader.array(reader.required(*weights, path, "inertia_weights"), join_path(path, "inertia_weights"));
        if (inertias.size() != count) {
            reader.fail(join_path(path, "inertia_weights"), "expected one 3x3 weight per arm (" +
                                                                std::to_string(count) + "), got " +
                                                                std::to_string(inertias.size()) + " (N mismatch)");
        }
        scenario.mass_weights = Eigen::Map<const Eigen::VectorXd>(masses.data(), static_cast<Eigen::Index>(count));
        scenario.inertia_weights.resize(3, 3 * static_cast<Eigen::Index>(count));
        for (std::size_t i = 0; i < count; ++i) {
            scenario.inertia_weights.block<3, 3>(0, 3 * static_cast<Eigen::Index>(i)) =
                reader.matrix3(inertias[i], index_path(join_path(path, "inertia_weights"), i));
        }
    }
}

/// "excitation" (optional): the default amplitudes.
inline void read_excitation(const Reader& reader, const json& document, Scenario& scenario)
{
    if (const json* excitation = reader.optional(document, "excitation")) {
        reader.expect_object(*excitation, "excitation");
        reader.only_keys(*excitation, "excitation", {"force", "torque"});
        if (const json* force = reader.optional(*excitation, "force")) {
            scenario.excitation.force = reader.in_range(*force, "excitation.force", excitation_force_range);
        }
        if (const json* torque = reader.optional(*excitation, "torque")) {
            scenario.excitation.torque = reader.in_range(*torque, "excitation.torque", excitation_torque_range);
        }
    }
}

/// "paper" (optional): the paper's reference values.
inline void read_paper(const Reader& reader, const json& document, Scenario& scenario)
{
    if (const json* paper = reader.optional(document, "paper")) {
        reader.expect_object(*paper, "paper");
        reader.only_keys(*paper, "paper", {"source", "translation_x", "rotation_z", "se3"});
        PaperReference reference;
        if (const json* source_text = reader.optional(*paper, "source")) {
            reference.source = reader.string(*source_text, "paper.source");
        }
        if (const json* x = reader.optional(*paper, "translation_x")) {
            reference.translation_x = paper_experiment(reader, *x, "paper.translation_x", 1);
        }
        if (const json* z = reader.optional(*paper, "rotation_z")) {
            reference.rotation_z = paper_experiment(reader, *z, "paper.rotation_z", 1);
        }
        if (const json* se3 = reader.optional(*paper, "se3")) {
            reference.se3 = paper_experiment(reader, *se3, "paper.se3", 6);
        }
        scenario.paper = reference;
    }
}

/// The whole set-up, through coopdyn's own validation (the Model and LoadDistribution
/// constructors), and a stable equilibrium: Theorem 2's K and D positive definite.
inline void check_setup(const Reader& reader, const Scenario& scenario)
{
    physical(reader, [&] {
        const coopdyn::ImpedanceModelX model(scenario.object, scenario.arms, scenario.gravity);
        const auto distribution =
            scenario.has_custom_weights()
                ? coopdyn::LoadDistribution<coopdyn::ImpedanceModelX>(model, scenario.mass_weights,
                                                                      scenario.inertia_weights)
                : coopdyn::LoadDistribution<coopdyn::ImpedanceModelX>(model);
        (void)distribution;
        // The experiments need a stable equilibrium: the apparent stiffness and damping at the
        // equilibrium (Theorem 2) must be positive definite.
        coopdyn::Data<coopdyn::ImpedanceModelX> data(model);
        coopdyn::RigidBodyState<double> state;
        state.pose = scenario.equilibrium;
        coopdyn::grasp_kinematics(model, data, state);
        const coopdyn::ApparentImpedance<double> impedance = coopdyn::apparent_impedance(model, data);
        const auto smallest = [](const coopdyn::Matrix6<double>& matrix) {
            return Eigen::SelfAdjointEigenSolver<coopdyn::Matrix6<double>>(matrix, Eigen::EigenvaluesOnly)
                .eigenvalues()
                .minCoeff();
        };
        const double stiffness = smallest(impedance.stiffness);
        const double damping = smallest(impedance.damping);
        std::ostringstream value;
        if (!(stiffness > 0.0)) {
            value << stiffness;
            reader.fail("arms", "together give an apparent stiffness K (Theorem 2) that is not positive definite "
                                "(smallest eigenvalue " + value.str() +
                                    "): the object has no isolated equilibrium; raise the arms' stiffnesses");
        }
        if (!(damping > 0.0)) {
            value << damping;
            reader.fail("arms", "together give an apparent damping D (Theorem 2) that is not positive definite "
                                "(smallest eigenvalue " + value.str() +
                                    "): the object's motion is undamped; raise the arms' damping");
        }
    });
}

/// The beam's schema, on a parsed document.
inline Scenario read_scenario(const Reader& reader, const json& document)
{
    Scenario scenario;
    scenario.source = reader.source();
    reader.expect_object(document, "");
    reader.only_keys(document, "",
                     {"name", "description", "time_step", "gravity", "object", "arm_count", "arms",
                      "load_distribution", "excitation", "paper"});
    // The name prefixes the output files: a plain file name, checked here, not when writing.
    scenario.name = reader.name(reader.required(document, "", "name"), "name");
    if (const json* description = reader.optional(document, "description")) {
        scenario.description = reader.string(*description, "description");
    }
    if (const json* time_step = reader.optional(document, "time_step")) {
        scenario.time_step = reader.positive(*time_step, "time_step");
        if (scenario.time_step > 0.1) {
            reader.fail("time_step", "must be at most 0.1 s (the experiments log every step), got " +
                                         std::to_string(scenario.time_step));
        }
    }
    if (const json* gravity = reader.optional(document, "gravity")) {
        scenario.gravity = reader.vector3(*gravity, "gravity");
    }

    read_object(reader, document, scenario);
    read_arms(reader, document, scenario);
    read_load_distribution(reader, document, scenario);
    read_excitation(reader, document, scenario);
    read_paper(reader, document, scenario);
    check_setup(reader, scenario);
    return scenario;
}

}  // namespace detail

/// Parses and validates a scenario from JSON text. `source` names it in error messages.
/// Throws ScenarioError only (nlohmann-json's exceptions included); never returns a partly
/// filled Scenario.
inline Scenario parse_scenario(const std::string& text, const std::string& source)
{
    return example_common::read_document(text, source, detail::read_scenario);
}

/// Reads and validates a scenario file. Throws example_common::FileError when the file cannot be
/// read, ScenarioError (naming the file) when it is invalid.
inline Scenario load_scenario(const std::string& path)
{
    return parse_scenario(example_common::read_text_file(path), path);
}

}  // namespace beam_example
