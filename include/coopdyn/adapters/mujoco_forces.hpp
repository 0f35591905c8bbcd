/// \file
/// \brief The MuJoCo adapter's forces (adapters/mujoco.hpp): a wrench applied to a body (MuJoCo's
/// xfrc_applied: a person's push on the object), and what MuJoCo's contacts exert, one contact at
/// a time (mujoco_contact_wrench) and summed per hand (MujocoContactWrenches, filled by
/// MujocoArms::read_contact_wrenches). docs/adapters.md, "Applied wrenches and contact forces".
///
/// Every function here is noexcept and allocation-free (per tick); MujocoContactWrenches allocates
/// once, when it is made for K hands at run time.
#pragma once

#include "coopdyn/config.hpp"

#include <Eigen/Core>
#include <mujoco/mujoco.h>

namespace coopdyn {

/// \brief Sets the wrench [F; T] in {w} that MuJoCo applies to `body` at its centre of mass (its
/// xfrc_applied, which mj_step2 and mj_forward read) until it is set again: a person's push on the
/// object. Replaces the body's previous applied wrench.
inline void mujoco_set_applied_wrench(const mjModel* model, mjData* data, int body, const Vector6<double>& wrench) noexcept
{
    COOPDYN_ASSERT(body >= 0 && body < model->nbody, "mujoco_set_applied_wrench: no such body");
    static_cast<void>(model);
    Eigen::Map<Vector6<double>>(data->xfrc_applied + 6 * body) = wrench;
}

/// \brief The same for the force F applied at `point` ({w}) together with the torque T: MuJoCo
/// applies the wrench at the body's centre of mass c (xipos, current after mj_kinematics), where
/// the torque is T + (point - c) x F.
inline void mujoco_set_applied_wrench(const mjModel* model, mjData* data, int body, const Vector6<double>& wrench,
                                      const Eigen::Vector3d& point) noexcept
{
    const Eigen::Map<const Eigen::Vector3d> centre(data->xipos + 3 * body);
    Vector6<double> at_centre = wrench;
    at_centre.tail<3>() += (point - centre).cross(wrench.head<3>());
    mujoco_set_applied_wrench(model, data, body, at_centre);
}

/// \brief The wrench [F; T] ({w}, at the centre of mass) that MuJoCo applies to `body`.
inline Vector6<double> mujoco_applied_wrench(const mjModel* /*model*/, const mjData* data, int body) noexcept
{
    return Eigen::Map<const Vector6<double>>(data->xfrc_applied + 6 * body);
}

/// \brief Clears every body's applied wrench (xfrc_applied).
inline void mujoco_clear_applied_wrenches(const mjModel* model, mjData* data) noexcept
{
    mju_zero(data->xfrc_applied, 6 * model->nbody);
}

/// \brief One MuJoCo contact's force on its second geom as [f; t] in {w}, t about the contact's
/// point (contact.pos). `local` is mj_contactForce's result in the contact frame (the rows of
/// contact.frame: the normal from geom1 to geom2, then the two tangents): the normal and the two
/// friction forces, then the torsional moment about the normal and the rolling moments about the
/// tangents (zero below condim 4 and 6).
inline Vector6<double> mujoco_contact_wrench(const mjContact& contact, const mjtNum* local) noexcept
{
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> frame(contact.frame);
    Vector6<double> wrench;
    wrench.head<3>() = frame.transpose() * Eigen::Vector3d(local[0], local[1], local[2]);
    wrench.tail<3>() = frame.transpose() * Eigen::Vector3d(local[3], local[4], local[5]);
    return wrench;
}

/// \brief What MuJoCo's contacts between each of K hands and one object exerted in the last
/// constraint solve (MujocoArms::read_contact_wrenches): per hand i, its wrench on the object.
template <int ArmsAtCompileTime = Eigen::Dynamic> struct MujocoContactWrenches {
    /// Column i: hand i's wrench [f; t] on the object in {w}, t about contact point i (contact i's
    /// frame origin, where the controller's contact wrench acts).
    Eigen::Matrix<double, 6, ArmsAtCompileTime> world;
    /// Column i: the same in contact i's frame, [R_i^T f; R_i^T t]: row 2 is the normal force
    /// (z is the object's inward normal), rows 0-1 the friction force, row 5 the torsion; the
    /// layout of ControllerData::contact_frame_wrenches.
    Eigen::Matrix<double, 6, ArmsAtCompileTime> contact_frame;
    /// Per hand: its contacts' normal forces summed along MuJoCo's own contact normals (N, >= 0).
    Eigen::Matrix<double, ArmsAtCompileTime, 1> normal_forces;
    /// Per hand: how many MuJoCo contacts it has with the object.
    Eigen::Matrix<int, ArmsAtCompileTime, 1> points;

    explicit MujocoContactWrenches(Index arms = ArmsAtCompileTime == Eigen::Dynamic ? 0 : ArmsAtCompileTime)
        : world(6, arms), contact_frame(6, arms), normal_forces(arms), points(arms)
    {
        set_zero();
    }
    Index arms() const noexcept { return world.cols(); }
    void set_zero() noexcept
    {
        world.setZero();
        contact_frame.setZero();
        normal_forces.setZero();
        points.setZero();
    }
};

}  // namespace coopdyn
