// A scene: which arms hold which object, and how they start (docs/scenes.md). Plain data and its
// JSON reader; no MuJoCo here (scene_world.hpp builds the MuJoCo world and the controller from it).
//
//   {
//     "model": "ur5e_panda.xml",                  MJCF, relative to the scene file
//     "joints": ["ur5e_joint1", ..., "panda_joint7"],   Q names, in q's order
//     "contact_sites": ["ur5e_palm_contact", "panda_palm_contact"],   K sites (or bodies), J's order
//     "object": {"body": "box", "pose": {"position": [x, y, z], "orientation": [w, x, y, z]}},
//     "start": {"positions": [Q numbers]}                               a given posture, or
//     "start": {"contacts": [{"position": [..], "orientation": [..]}, ...], "seed": [Q numbers]}
//                                                   each contact frame in the object (IK targets)
//     "posture": [Q numbers]                        optional: q_n, default the start posture
//     "torque_limits": [Q numbers]                  optional: |tau_j| limits (N m), default none
//     "check_contact_normals": false                optional: accept contact frames whose z does not
//                                                   face into the object (default true; docs/control.md)
//   }
//
// Errors are example_common::ScenarioError naming the file and the field's JSON path
// (examples/common/json_reader.hpp).
#pragma once

#include "../common/json_reader.hpp"

#include <coopdyn/model/contact_frames.hpp>
#include <coopdyn/spatial/pose.hpp>

#include <Eigen/Core>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace scenes {

/// The start posture: given joint positions, or where each contact frame sits on the object (its
/// pose in the object's body frame: origin the contact point on the surface, z the inward normal),
/// reached by the arms' inverse kinematics (MujocoArms::place_hands) from `seed`.
struct SceneStart {
    std::optional<Eigen::VectorXd> positions;        ///< Q, when given
    std::vector<coopdyn::Pose<double>> contacts;     ///< K, when the IK finds the posture
    std::optional<Eigen::VectorXd> seed;             ///< Q, the IK's first guess (default: the model's qpos0)
};

struct Scene {
    std::string source;                      ///< the scene file (for messages)
    std::filesystem::path model_path;        ///< the MJCF, resolved against the scene file's folder
    std::vector<std::string> joint_names;    ///< Q
    std::vector<std::string> contact_sites;  ///< K
    std::string object_body;
    coopdyn::Pose<double> object_pose{};     ///< the object body's frame in {w} at the start
    SceneStart start;
    std::optional<Eigen::VectorXd> posture;  ///< q_n (default: the start posture)
    /// The joints' torque limits (N m; the URDFs' effort limits): the box experiments clamp the
    /// controller's torques to them. The MJCFs generated from URDF carry no actuators, so the
    /// limits are the scene's; without them the torques are not clamped.
    std::optional<Eigen::VectorXd> torque_limits;
    /// Refuse contact frames whose z does not face into the object (the start contacts here, the
    /// measured grasp in the controller: ControllerParameters::check_contact_normals).
    bool check_contact_normals = true;

    Eigen::Index joints() const noexcept { return static_cast<Eigen::Index>(joint_names.size()); }
    Eigen::Index arms() const noexcept { return static_cast<Eigen::Index>(contact_sites.size()); }
};

namespace detail {

using example_common::JsonReader;
using example_common::json;
using example_common::join_path;
using example_common::index_path;

inline std::vector<std::string> names(const JsonReader& reader, const json& value, const std::string& path)
{
    const json& list = reader.array(value, path);
    if (list.empty()) {
        reader.fail(path, "must name at least one");
    }
    std::vector<std::string> result;
    for (std::size_t i = 0; i < list.size(); ++i) {
        const std::string name = reader.string(list[i], index_path(path, i));
        for (const std::string& earlier : result) {
            if (earlier == name) {
                reader.fail(index_path(path, i), "names \"" + name + "\" twice");
            }
        }
        result.push_back(name);
    }
    return result;
}

inline Eigen::VectorXd joint_vector(const JsonReader& reader, const json& value, const std::string& path,
                                    std::size_t joints)
{
    const std::vector<double> numbers = reader.numbers(value, path, joints);
    return Eigen::Map<const Eigen::VectorXd>(numbers.data(), static_cast<Eigen::Index>(numbers.size()));
}

inline coopdyn::Pose<double> pose(const JsonReader& reader, const json& value, const std::string& path)
{
    reader.only_keys(value, path, {"position", "orientation"});
    coopdyn::Pose<double> result;
    result.position = reader.vector3(reader.required(value, path, "position"), join_path(path, "position"));
    result.orientation = reader.quaternion(reader.required(value, path, "orientation"), join_path(path, "orientation"));
    return result;
}

inline SceneStart start(const JsonReader& reader, const json& value, std::size_t joints, std::size_t arms)
{
    const std::string path = "start";
    reader.only_keys(value, path, {"positions", "contacts", "seed"});
    SceneStart result;
    const json* positions = reader.optional(value, "positions");
    const json* contacts = reader.optional(value, "contacts");
    if ((positions == nullptr) == (contacts == nullptr)) {
        reader.fail(path, "needs exactly one of \"positions\" (the joints) and \"contacts\" (IK targets)");
    }
    if (positions != nullptr) {
        if (reader.optional(value, "seed") != nullptr) {
            reader.fail(join_path(path, "seed"), "is for \"contacts\" (the IK's first guess), not \"positions\"");
        }
        result.positions = joint_vector(reader, *positions, join_path(path, "positions"), joints);
        return result;
    }
    const std::string contacts_path = join_path(path, "contacts");
    const json& list = reader.array(*contacts, contacts_path, arms);
    for (std::size_t i = 0; i < list.size(); ++i) {
        result.contacts.push_back(pose(reader, list[i], index_path(contacts_path, i)));
    }
    if (const json* seed = reader.optional(value, "seed")) {
        result.seed = joint_vector(reader, *seed, join_path(path, "seed"), joints);
    }
    return result;
}

}  // namespace detail

/// Reads a scene from JSON text; `source` names it in messages and `folder` resolves "model".
inline Scene parse_scene(const std::string& text, const std::string& source, const std::filesystem::path& folder)
{
    return example_common::read_document(text, source, [&](const detail::JsonReader& reader, const detail::json& document) {
        using detail::join_path;
        reader.only_keys(document, "",
                         {"model", "joints", "contact_sites", "object", "start", "posture", "torque_limits",
                          "check_contact_normals"});
        Scene scene;
        scene.source = source;
        const std::string model = reader.string(reader.required(document, "", "model"), "model");
        if (model.empty()) {
            reader.fail("model", "must name the MJCF file");
        }
        scene.model_path = folder / model;
        scene.joint_names = detail::names(reader, reader.required(document, "", "joints"), "joints");
        scene.contact_sites = detail::names(reader, reader.required(document, "", "contact_sites"), "contact_sites");
        if (scene.contact_sites.size() < 2) {
            reader.fail("contact_sites", "must name at least two contacts (K >= 2)");
        }
        if (scene.joint_names.size() < 6 * scene.contact_sites.size()) {
            reader.fail("joints", "must name at least 6K = " + std::to_string(6 * scene.contact_sites.size()) +
                                      " joints (the controller needs J's rows independent), got " +
                                      std::to_string(scene.joint_names.size()));
        }
        const detail::json& object = reader.required(document, "", "object");
        reader.only_keys(object, "object", {"body", "pose"});
        scene.object_body = reader.string(reader.required(object, "object", "body"), "object.body");
        scene.object_pose = detail::pose(reader, reader.required(object, "object", "pose"), "object.pose");
        scene.start = detail::start(reader, reader.required(document, "", "start"), scene.joint_names.size(),
                                    scene.contact_sites.size());
        if (const detail::json* check = reader.optional(document, "check_contact_normals")) {
            if (!check->is_boolean()) {
                reader.fail("check_contact_normals", "must be true or false");
            }
            scene.check_contact_normals = check->get<bool>();
        }
        if (scene.check_contact_normals) {
            // The controller's rule, in its words (contact_normal_problem), before the IK would
            // chase a palm turned inside out ("iteration_limit, residual 0.027").
            for (std::size_t i = 0; i < scene.start.contacts.size(); ++i) {
                const std::string problem = coopdyn::contact_normal_problem(scene.start.contacts[i]);
                if (!problem.empty()) {
                    reader.fail(detail::index_path("start.contacts", i) + ".orientation", problem);
                }
            }
        }
        if (const detail::json* posture = reader.optional(document, "posture")) {
            scene.posture = detail::joint_vector(reader, *posture, "posture", scene.joint_names.size());
        }
        if (const detail::json* limits = reader.optional(document, "torque_limits")) {
            scene.torque_limits = detail::joint_vector(reader, *limits, "torque_limits", scene.joint_names.size());
            for (Eigen::Index j = 0; j < scene.torque_limits->size(); ++j) {
                if (!((*scene.torque_limits)(j) > 0.0)) {
                    reader.fail(detail::index_path("torque_limits", static_cast<std::size_t>(j)), "must be positive");
                }
            }
        }
        return scene;
    });
}

/// Reads a scene file (ScenarioError when it cannot be read or is malformed).
inline Scene read_scene(const std::string& path)
{
    const std::filesystem::path file(path);
    return parse_scene(example_common::read_text_file(path), path, file.parent_path());
}

}  // namespace scenes
