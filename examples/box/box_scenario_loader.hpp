// Scenario files of the dual-arm box example (docs/dual-arm-box.md, "Scenario files"), read with
// the examples' shared all-or-nothing loader (examples/common/json_reader.hpp): the whole file is
// checked (syntax, every field's presence, type and range, unknown fields) and either a complete
// BoxScenario comes back or a ScenarioError "<file>: <json path>: <problem>", e.g.
//
//   examples/box/scenarios/push.json: push.force: must be positive, got -40
#pragma once

#include "box_scenario.hpp"

#include "../common/json_reader.hpp"

#include <filesystem>
#include <string>

namespace box_example {

using example_common::JsonReader;
using example_common::ScenarioError;
using json = nlohmann::json;

namespace detail {

/// `object[key]` read by `read` when present, else `fallback`.
template <typename Read>
double optional_number(const JsonReader& reader, const json& object, const std::string& path, const char* key,
                       double fallback, Read&& read)
{
    const json* value = reader.optional(object, key);
    return value == nullptr ? fallback : read(*value, example_common::join_path(path, key));
}

inline Experiment experiment(const JsonReader& reader, const json& value, const std::string& path)
{
    const std::string text = reader.string(value, path);
    for (const Experiment candidate : {Experiment::hold, Experiment::push, Experiment::add_mass, Experiment::circle}) {
        if (text == to_string(candidate)) {
            return candidate;
        }
    }
    reader.fail(path, "must be one of hold, push, add_mass, circle, got \"" + text + "\"");
    return Experiment::hold;
}

/// The contact QP's objective by name (SqueezeObjective's presets, docs/control.md).
inline coopdyn::SqueezeObjective<double> objective_preset(const JsonReader& reader, const json& value,
                                                          const std::string& path)
{
    using Objective = coopdyn::SqueezeObjective<double>;
    const std::string text = reader.string(value, path);
    if (text == "least_squeeze") {
        return Objective::least_squeeze();
    }
    if (text == "least_torque_centred") {
        return Objective::least_torque_centred();
    }
    if (text == "paper") {
        return Objective::paper();
    }
    reader.fail(path, "must be one of least_squeeze, least_torque_centred, paper, got \"" + text + "\"");
    return Objective::least_squeeze();
}

/// The objective: the preset `objective` (default the library's, least_squeeze: ControllerSettings), then
/// each weight given.
inline void read_objective(const JsonReader& reader, const json& object, const std::string& path, ControllerSettings& c)
{
    if (const json* preset = reader.optional(object, "objective")) {
        c.objective = objective_preset(reader, *preset, example_common::join_path(path, "objective"));
    }
    const auto non_negative = [&](const json& v, const std::string& p) { return reader.non_negative(v, p); };
    coopdyn::SqueezeObjective<double>& o = c.objective;
    o.internal_weight = optional_number(reader, object, path, "internal_weight", o.internal_weight, non_negative);
    o.torque_weight = optional_number(reader, object, path, "torque_weight", o.torque_weight, non_negative);
    o.moment_weight = optional_number(reader, object, path, "moment_weight", o.moment_weight, non_negative);
    o.squeeze_weight = optional_number(reader, object, path, "squeeze_weight", o.squeeze_weight, non_negative);
    if (!(o.internal_weight + o.torque_weight + o.squeeze_weight > 0.0)) {
        reader.fail(example_common::join_path(path, "squeeze_weight"),
                    "must be positive when torque_weight is 0 and internal_weight is 0 (the QP needs a positive "
                    "definite objective)");
    }
}

inline ControllerSettings controller(const JsonReader& reader, const json& object, const std::string& path)
{
    reader.expect_object(object, path);
    reader.only_keys(object, path,
                     {"friction", "torsional_friction", "patch_half_size", "minimum_normal_force",
                      "translational_stiffness", "rotational_stiffness", "translational_damping",
                      "rotational_damping", "posture_stiffness", "posture_damping", "objective",
                      "internal_weight", "torque_weight", "moment_weight", "squeeze_weight", "acceleration_cutoff"});
    ControllerSettings c;
    const auto positive = [&](const json& v, const std::string& p) { return reader.positive(v, p); };
    const auto non_negative = [&](const json& v, const std::string& p) { return reader.non_negative(v, p); };
    c.friction = optional_number(reader, object, path, "friction", c.friction,
                                 [&](const json& v, const std::string& p) { return reader.in_range(v, p, friction_range); });
    c.torsional_friction = optional_number(reader, object, path, "torsional_friction", c.torsional_friction, non_negative);
    c.patch_half_size = optional_number(reader, object, path, "patch_half_size", c.patch_half_size, positive);
    c.minimum_normal_force =
        optional_number(reader, object, path, "minimum_normal_force", c.minimum_normal_force, non_negative);
    c.translational_stiffness =
        optional_number(reader, object, path, "translational_stiffness", c.translational_stiffness, non_negative);
    c.rotational_stiffness =
        optional_number(reader, object, path, "rotational_stiffness", c.rotational_stiffness, non_negative);
    c.translational_damping =
        optional_number(reader, object, path, "translational_damping", c.translational_damping, non_negative);
    c.rotational_damping = optional_number(reader, object, path, "rotational_damping", c.rotational_damping, non_negative);
    c.posture_stiffness = optional_number(reader, object, path, "posture_stiffness", c.posture_stiffness, non_negative);
    c.posture_damping = optional_number(reader, object, path, "posture_damping", c.posture_damping, non_negative);
    read_objective(reader, object, path, c);
    c.acceleration_cutoff = optional_number(reader, object, path, "acceleration_cutoff", c.acceleration_cutoff,
                                            [&](const json& v, const std::string& p) {
                                                return reader.in_range(v, p, 0.0, 500.0);  // Nyquist at 1 kHz
                                            });
    return c;
}

inline Push push(const JsonReader& reader, const json& object, const std::string& path)
{
    reader.expect_object(object, path);
    reader.only_keys(object, path, {"start", "force", "ramp", "hold", "period", "repeats", "direction"});
    Push p;
    const auto at = [&](const char* key) { return example_common::join_path(path, key); };
    p.start = reader.non_negative(reader.required(object, path, "start"), at("start"));
    p.force = reader.positive(reader.required(object, path, "force"), at("force"));
    p.ramp = reader.positive(reader.required(object, path, "ramp"), at("ramp"));
    p.hold = reader.non_negative(reader.required(object, path, "hold"), at("hold"));
    p.period = reader.positive(reader.required(object, path, "period"), at("period"));
    const long long repeats = reader.integer(reader.required(object, path, "repeats"), at("repeats"));
    if (repeats < 1 || repeats > 1000) {
        reader.fail(at("repeats"), "must be between 1 and 1000, got " + std::to_string(repeats));
    }
    p.repeats = static_cast<int>(repeats);
    if (p.period < 2.0 * p.ramp + p.hold) {
        reader.fail(at("period"), "must be at least 2 ramp + hold (the pushes must not overlap)");
    }
    if (const json* direction = reader.optional(object, "direction")) {
        p.direction = reader.vector3(*direction, at("direction"));
        if (!(p.direction.norm() > 1e-9)) {
            reader.fail(at("direction"), "must not be zero");
        }
        p.direction.normalize();
    }
    return p;
}

inline AddedMass added_mass(const JsonReader& reader, const json& object, const std::string& path)
{
    reader.expect_object(object, path);
    reader.only_keys(object, path, {"start", "step", "interval", "total"});
    const auto at = [&](const char* key) { return example_common::join_path(path, key); };
    AddedMass a;
    a.start = reader.non_negative(reader.required(object, path, "start"), at("start"));
    a.step = reader.positive(reader.required(object, path, "step"), at("step"));
    a.interval = reader.positive(reader.required(object, path, "interval"), at("interval"));
    a.total = reader.positive(reader.required(object, path, "total"), at("total"));
    if (a.total > 100.0) {
        reader.fail(at("total"), "must be at most 100 kg");
    }
    return a;
}

inline PersonHold person_hold(const JsonReader& reader, const json& object, const std::string& path)
{
    reader.expect_object(object, path);
    reader.only_keys(object, path, {"start", "duration", "stiffness", "damping"});
    const auto at = [&](const char* key) { return example_common::join_path(path, key); };
    PersonHold h;
    h.start = reader.non_negative(reader.required(object, path, "start"), at("start"));
    h.duration = reader.positive(reader.required(object, path, "duration"), at("duration"));
    h.stiffness = reader.positive(reader.required(object, path, "stiffness"), at("stiffness"));
    h.damping = reader.non_negative(reader.required(object, path, "damping"), at("damping"));
    return h;
}

inline Circle circle(const JsonReader& reader, const json& object, const std::string& path)
{
    reader.expect_object(object, path);
    reader.only_keys(object, path, {"start", "radius", "angular_speed", "ramp"});
    const auto at = [&](const char* key) { return example_common::join_path(path, key); };
    Circle c;
    c.start = reader.non_negative(reader.required(object, path, "start"), at("start"));
    c.radius = reader.in_range(reader.required(object, path, "radius"), at("radius"), 1e-3, 0.3);
    c.angular_speed = reader.in_range(reader.required(object, path, "angular_speed"), at("angular_speed"), 1e-3, 20.0);
    c.ramp = reader.positive(reader.required(object, path, "ramp"), at("ramp"));
    return c;
}

inline PaperNumbers paper(const JsonReader& reader, const json& object, const std::string& path)
{
    reader.expect_object(object, path);
    reader.only_keys(object, path, {"source", "squeeze_at_rest", "squeeze_pushed"});
    PaperNumbers p;
    if (const json* source = reader.optional(object, "source")) {
        reader.string(*source, example_common::join_path(path, "source"));
    }
    if (const json* value = reader.optional(object, "squeeze_at_rest")) {
        p.squeeze_at_rest = reader.positive(*value, example_common::join_path(path, "squeeze_at_rest"));
    }
    if (const json* value = reader.optional(object, "squeeze_pushed")) {
        p.squeeze_pushed = reader.positive(*value, example_common::join_path(path, "squeeze_pushed"));
    }
    return p;
}

inline BoxScenario box_scenario(const JsonReader& reader, const json& document)
{
    reader.expect_object(document, "");
    reader.only_keys(document, "",
                     {"name", "description", "scene", "experiment", "duration", "box_mass", "plant_friction",
                      "controller", "push", "added_mass", "person_hold", "circle", "person_tremor", "paper"});
    BoxScenario s;
    s.source = reader.source();
    s.name = reader.name(reader.required(document, "", "name"), "name");
    if (const json* description = reader.optional(document, "description")) {
        reader.string(*description, "description");
    }
    if (const json* scene = reader.optional(document, "scene")) {
        const std::string file = reader.string(*scene, "scene");
        if (file.empty()) {
            reader.fail("scene", "must name a scene file (examples/scenes/*.json)");
        }
        // Relative to the scenario file, wherever the program runs.
        s.scene = (std::filesystem::path(s.source).parent_path() / file).lexically_normal().string();
    }
    s.experiment = experiment(reader, reader.required(document, "", "experiment"), "experiment");
    s.duration = reader.in_range(reader.required(document, "", "duration"), "duration",
                                 example_common::experiment_duration_range);  // --duration's too
    s.box_mass = reader.in_range(reader.required(document, "", "box_mass"), "box_mass", 0.01, 100.0);
    const json& friction = reader.required(document, "", "plant_friction");
    reader.expect_object(friction, "plant_friction");
    reader.only_keys(friction, "plant_friction", {"sliding", "torsional"});
    s.plant_friction.sliding =
        reader.in_range(reader.required(friction, "plant_friction", "sliding"), "plant_friction.sliding", friction_range);
    s.plant_friction.torsional =
        reader.non_negative(reader.required(friction, "plant_friction", "torsional"), "plant_friction.torsional");
    if (const json* settings = reader.optional(document, "controller")) {
        s.controller = controller(reader, *settings, "controller");
    }
    if (const json* value = reader.optional(document, "push")) {
        s.push = push(reader, *value, "push");
    }
    if (const json* value = reader.optional(document, "added_mass")) {
        s.added_mass = added_mass(reader, *value, "added_mass");
    }
    if (const json* value = reader.optional(document, "person_hold")) {
        s.person_hold = person_hold(reader, *value, "person_hold");
    }
    if (const json* value = reader.optional(document, "circle")) {
        s.circle = circle(reader, *value, "circle");
    }
    if (const json* value = reader.optional(document, "person_tremor")) {
        s.person_tremor = reader.in_range(*value, "person_tremor", 0.0, 100.0);
    }
    if (const json* value = reader.optional(document, "paper")) {
        s.paper = paper(reader, *value, "paper");
    }
    // Each experiment needs its disturbance or motion.
    const auto require_section = [&](bool present, const char* section) {
        if (!present) {
            reader.fail(section, std::string("is required when experiment is \"") + to_string(s.experiment) + "\"");
        }
    };
    switch (s.experiment) {
    case Experiment::hold: break;
    case Experiment::push: require_section(s.push.has_value(), "push"); break;
    case Experiment::add_mass: require_section(s.added_mass.has_value(), "added_mass"); break;
    case Experiment::circle: require_section(s.circle.has_value(), "circle"); break;
    }
    return s;
}

}  // namespace detail

/// Parses a box scenario from JSON text; `source` names it in messages. Throws ScenarioError.
inline BoxScenario parse_box_scenario(const std::string& text, const std::string& source)
{
    return example_common::read_document(text, source, detail::box_scenario);
}

/// Reads and parses a box scenario file. Throws example_common::FileError when it cannot be read,
/// ScenarioError naming the file when it is invalid.
inline BoxScenario load_box_scenario(const std::string& path)
{
    return parse_box_scenario(example_common::read_text_file(path), path);
}

}  // namespace box_example
