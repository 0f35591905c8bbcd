// The rigid plant (rigid_plant.hpp, which needs no MuJoCo) started from the MJCF instead of
// lwr4.hpp: the initial state from MuJoCo data (e.g. the keyframe "hold"), the box's inertia and
// the gravity from the model, and a check that the MJCF's arms are lwr4.hpp's (docs/dual-arm-box.md,
// "The rigid plant"). This header belongs to the examples (it depends on MuJoCo), not to the library.
#pragma once

#include "mujoco_arms.hpp"
#include "rigid_plant.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace box_example {

/// The box of the MJCF with `mass`: its inertia (principal, the model's body frame) scaled to it.
inline BoxInertia box_inertia(const DualArmBoxModel& world, double mass)
{
    const mjModel* model = world.get();
    const int body = world.box_body();
    BoxInertia box;
    box.mass = mass;
    const Eigen::Quaterniond principal(model->body_iquat[4 * body], model->body_iquat[4 * body + 1],
                                       model->body_iquat[4 * body + 2], model->body_iquat[4 * body + 3]);
    const Eigen::Matrix3d axes = principal.normalized().toRotationMatrix();
    const Eigen::Vector3d moments(model->body_inertia[3 * body], model->body_inertia[3 * body + 1],
                                  model->body_inertia[3 * body + 2]);
    box.inertia = (mass / model->body_mass[body]) * axes * moments.asDiagonal() * axes.transpose();
    return box;
}

/// The arms and the box as in the MuJoCo data `initial` (qpos, qvel; the box's angular velocity,
/// which MuJoCo's free joint gives in the box frame, turned into {w}).
inline PlantState plant_state(const mjData& initial)
{
    PlantState state;
    for (int j = 0; j < joints; ++j) {
        state.q(j) = initial.qpos[j];
        state.qdot(j) = initial.qvel[j];
    }
    const mjtNum* box_pose = initial.qpos + joints;
    state.box_position = Eigen::Vector3d(box_pose[0], box_pose[1], box_pose[2]);
    state.box_orientation = Eigen::Quaterniond(box_pose[3], box_pose[4], box_pose[5], box_pose[6]).normalized();
    const Eigen::Matrix3d box_rotation = state.box_orientation.toRotationMatrix();
    state.box_velocity = Eigen::Vector3d(initial.qvel[joints], initial.qvel[joints + 1], initial.qvel[joints + 2]);
    state.box_angular_velocity =
        box_rotation * Eigen::Vector3d(initial.qvel[joints + 3], initial.qvel[joints + 4], initial.qvel[joints + 5]);
    return state;
}

/// The plant's arms are lwr4.hpp's (Lwr4Dynamics); the MJCF's must be the same, or the two
/// plants would simulate different robots. Compared once, at the initial state, with MuJoCo's
/// M, h, J, Jdot qdot and palm frames (all 14 joints: the arms must share none, which
/// WeldSolver::structured relies on). Throws std::runtime_error naming what differs.
inline void require_arms_as_in_the_mjcf(const DualArmBoxModel& world, const mjData& initial, const ArmTerms& own)
{
    const mjModel* model = world.get();
    const DataPointer data(mj_makeData(model));
    if (!data) {
        throw std::runtime_error("MuJoCo cannot allocate its mjData");
    }
    mj_copyData(data.get(), model, &initial);
    compute_arm_stages(model, data.get());
    ArmTerms mujoco;
    read_arm_terms(world, model, data.get(), mujoco);
    const auto differs = [](const auto& value, const auto& expected) {
        return !((value - expected).norm() <= 1e-9 * std::max(1.0, expected.norm()));
    };
    const char* problem = differs(own.inertia, mujoco.inertia)                         ? "M"
                          : differs(own.bias, mujoco.bias)                             ? "h"
                          : differs(own.jacobian, mujoco.jacobian)                     ? "J"
                          : differs(own.jacobian_rate_qdot, mujoco.jacobian_rate_qdot) ? "Jdot qdot"
                                                                                       : nullptr;
    for (std::size_t i = 0; i < palms && problem == nullptr; ++i) {
        if (differs(own.palm_position[i], mujoco.palm_position[i]) || differs(own.palm_rotation[i], mujoco.palm_rotation[i])) {
            problem = "palm frame";
        }
    }
    if (problem != nullptr) {
        throw std::runtime_error(std::string("rigid plant: the MJCF's arms are not lwr4.hpp's (") + problem +
                                 " differs from MuJoCo's at the initial state by more than 1e-9)");
    }
}

/// The rigid plant at the MuJoCo data `initial` (e.g. world.make_data_at_hold()) under the MJCF's
/// gravity, each palm welded to the box where it touches it there; throws when the MJCF's arms
/// are not lwr4.hpp's.
inline RigidGraspPlant make_rigid_plant(const DualArmBoxModel& world, const mjData& initial, const BoxInertia& box,
                                        double stabilisation_frequency = 50.0)
{
    const mjtNum* gravity = world.get()->opt.gravity;
    RigidGraspPlant plant(plant_state(initial), box, Eigen::Vector3d(gravity[0], gravity[1], gravity[2]),
                          stabilisation_frequency);
    require_arms_as_in_the_mjcf(world, initial, plant.arm_terms());
    return plant;
}

}  // namespace box_example
