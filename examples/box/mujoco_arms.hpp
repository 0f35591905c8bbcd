// The dual-arm box's MJCF model (dual_arm_box.xml) loaded into MuJoCo, and what the controller
// needs of the two arms each tick (box_model.hpp's ArmTerms): M (14 x 14), h (14), the palms'
// stacked Jacobian J (12 x 14, rows [v; w] per palm in {w}) and Jdot qdot (12), read by the
// library's MuJoCo adapter (coopdyn/adapters/mujoco.hpp, docs/adapters.md) for the 14 arm joints
// and the sites left_palm, right_palm; and the grasp at the MJCF's keyframe "hold".
// docs/dual-arm-box.md, "The plants".
//
// The box's free joint is a separate kinematic tree: it couples to the arms neither in M nor in
// the bias (the adapter checks that the arms' joints and palms move with no other joint).
//
// This header belongs to the examples (the MJCF's names and sizes), not to the library.
#pragma once

#include "box_model.hpp"

#include <coopdyn/adapters/mujoco.hpp>

#include <Eigen/Core>
#include <mujoco/mujoco.h>

#include <array>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace box_example {

using ModelPointer = coopdyn::MujocoModelPointer;  // the adapter's owners (adapters/mujoco_model.hpp)
using DataPointer = coopdyn::MujocoDataPointer;

/// The MJCF model with the ids of everything the experiments use, checked once at load.
class DualArmBoxModel {
public:
    explicit DualArmBoxModel(const std::string& path)
    {
        std::array<char, 1000> error{};
        model_.reset(mj_loadXML(path.c_str(), nullptr, error.data(), static_cast<int>(error.size())));
        if (!model_) {
            throw std::runtime_error(path + ": MuJoCo cannot load it: " + error.data());
        }
        if (model_->nq != joints + 7 || model_->nv != joints + 6) {
            throw std::runtime_error(path + ": expected 14 arm joints and the box's free joint (nq = 21, nv = 20), got nq = " +
                                     std::to_string(model_->nq) + ", nv = " + std::to_string(model_->nv));
        }
        if (model_->opt.timestep != controller_period) {
            throw std::runtime_error(path + ": the controller runs at 1 kHz, one step per tick: the timestep must be 0.001, got " +
                                     std::to_string(model_->opt.timestep));
        }
        palm_site_ = {id(mjOBJ_SITE, "left_palm", path), id(mjOBJ_SITE, "right_palm", path)};
        palm_geom_ = {id(mjOBJ_GEOM, "left_palm_geom", path), id(mjOBJ_GEOM, "right_palm_geom", path)};
        box_body_ = id(mjOBJ_BODY, "box", path);
        box_geom_ = id(mjOBJ_GEOM, "box_geom", path);
        hold_key_ = id(mjOBJ_KEY, "hold", path);
        const int box_joint = id(mjOBJ_JOINT, "box_free", path);
        if (model_->jnt_qposadr[box_joint] != joints || model_->jnt_dofadr[box_joint] != joints) {
            throw std::runtime_error(path + ": the box's free joint must follow the 14 arm joints");
        }
        std::vector<std::string> joint_names;
        for (const char* side : {"left", "right"}) {
            for (int joint = 1; joint <= joints / palms; ++joint) {
                joint_names.push_back(std::string(side) + "_joint" + std::to_string(joint));
            }
        }
        arms_.emplace(model_.get(), joint_names, std::vector<std::string>{"left_palm", "right_palm"});
    }

    mjModel* get() const noexcept { return model_.get(); }
    int palm_site(int palm) const noexcept { return palm_site_[static_cast<std::size_t>(palm)]; }
    int palm_geom(int palm) const noexcept { return palm_geom_[static_cast<std::size_t>(palm)]; }
    int box_body() const noexcept { return box_body_; }
    int box_geom() const noexcept { return box_geom_; }
    int hold_key() const noexcept { return hold_key_; }
    /// The adapter for the 14 arm joints (q's order: left_joint1..7, right_joint1..7) and the palms.
    const coopdyn::MujocoArms<palms, joints>& arms() const noexcept { return *arms_; }

    /// A new mjData at the keyframe "hold" (arms in q_hold, box between the palms, at rest).
    DataPointer make_data_at_hold() const
    {
        DataPointer data(mj_makeData(model_.get()));
        if (!data) {
            throw std::runtime_error("MuJoCo cannot allocate its mjData");
        }
        mj_resetDataKeyframe(model_.get(), data.get(), hold_key_);
        mj_forward(model_.get(), data.get());
        return data;
    }

private:
    int id(mjtObj type, const char* name, const std::string& path) const
    {
        const int found = mj_name2id(model_.get(), type, name);
        if (found < 0) {
            throw std::runtime_error(path + ": has no " + mju_type2Str(type) + " named '" + name + "'");
        }
        return found;
    }

    ModelPointer model_;
    std::array<int, palms> palm_site_{};
    std::array<int, palms> palm_geom_{};
    int box_body_ = -1;
    int box_geom_ = -1;
    int hold_key_ = -1;
    std::optional<coopdyn::MujocoArms<palms, joints>> arms_;  // built once the model is checked
};

/// Runs the position- and velocity-dependent stages MuJoCo needs for M, h, J and Jdot qdot on
/// `data` (its qpos, qvel): forward kinematics, composite inertia and the bias by RNE. No
/// collision detection, so it serves any state of the arms (the rigid plant's RK4 stages).
inline void compute_arm_stages(const mjModel* model, mjData* data) noexcept
{
    mj_kinematics(model, data);
    mj_comPos(model, data);
    mj_crb(model, data);
    mj_comVel(model, data);
    mj_rne(model, data, 0, data->qfrc_bias);
}

/// Reads M, h, J, Jdot qdot and the palm frames of the arms from `data`, whose stages are current
/// (compute_arm_stages, or mj_step1 / mj_forward), with the library's adapter: allocation-free, and
/// `data` is left as it is (Jdot qdot is the palms' acceleration at qdd = 0, docs/adapters.md).
/// `model` is `world`'s model or a copy of it (ids from `world`).
inline void read_arm_terms(const DualArmBoxModel& world, const mjModel* model, const mjData* data, ArmTerms& terms) noexcept
{
    const auto& arms = world.arms();
    arms.read_inertia(model, data, terms.inertia);
    arms.read_bias(data, terms.bias);
    arms.read_jacobian(model, data, terms.jacobian);
    arms.read_jacobian_rate_qdot(model, data, terms.jacobian_rate_qdot);
    for (int palm = 0; palm < palms; ++palm) {
        terms.palm_position[static_cast<std::size_t>(palm)] = arms.contact_position(data, palm);
        terms.palm_rotation[static_cast<std::size_t>(palm)] = arms.contact_rotation(data, palm);
    }
}

/// The same; `scratch` is unused (the adapter needs none) and stays for the callers that pass one.
inline void read_arm_terms(const DualArmBoxModel& world, const mjModel* model, const mjData* data, ArmTerms& terms,
                           const mjtNum* /*scratch*/) noexcept
{
    read_arm_terms(world, model, data, terms);
}

/// The grasp at the keyframe "hold": the box's pose, the palms' contact frames, the arms' q.
inline Grasp hold_grasp(const DualArmBoxModel& world)
{
    const DataPointer data = world.make_data_at_hold();
    compute_arm_stages(world.get(), data.get());
    ArmTerms terms;
    read_arm_terms(world, world.get(), data.get(), terms);
    Grasp grasp;
    const mjtNum* box = data->qpos + joints;
    grasp.box.position = Eigen::Vector3d(box[0], box[1], box[2]);
    grasp.box.orientation = Eigen::Quaterniond(box[3], box[4], box[5], box[6]).normalized();
    grasp.palm_position = terms.palm_position;
    grasp.palm_rotation = terms.palm_rotation;
    grasp.q = Eigen::Map<const JointVector>(data->qpos);
    return grasp;
}

}  // namespace box_example
