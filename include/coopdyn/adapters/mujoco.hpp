/// \file
/// \brief The MuJoCo adapter: what the controller needs of the arms each tick (ControllerInput's
/// M, h, J, Jdot qdot, q, qdot), read from a MuJoCo model's state for Q chosen joints and K contact
/// points; and the helpers every user otherwise writes: the contact frames in the object
/// (ControllerParameters::contacts), an inverse kinematics for start postures and each hand's
/// contact wrench on the object (read_contact_wrenches; a wrench applied to a body is in
/// mujoco_forces.hpp). docs/adapters.md ("Conventions", "MuJoCo").
///
///     coopdyn::MujocoArms<2, 14> arms(model, joint_names, {"left_palm", "right_palm"});
///     mj_step1(model, data);              // or mj_forward: positions and velocities current
///     arms.read(model, data, input);      // allocation-free, leaves data unchanged
///     ... controller_tick(controller, controller_data, input); ... mj_step2(model, data);
///
/// Needs MuJoCo (written and tested against 2.2.2; CMake target coopdyn::mujoco).
#pragma once

#include "coopdyn/adapters/mujoco_forces.hpp"
#include "coopdyn/adapters/mujoco_model.hpp"
#include "coopdyn/config.hpp"
#include "coopdyn/control/controller_model.hpp"
#include "coopdyn/control/friction.hpp"
#include "coopdyn/errors.hpp"
#include "coopdyn/model/contact_frames.hpp"
#include "coopdyn/numerics/damped_least_squares.hpp"
#include "coopdyn/spatial/pose.hpp"
#include "coopdyn/spatial/quaternion.hpp"

#include <Eigen/Core>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace coopdyn {

/// \brief Options of MujocoArms::place_hands (numerics/damped_least_squares.hpp). The tolerance is
/// on |e| with e = [p_target - p; log(R_target R^T)] stacked over the hands (m and rad).
using InverseKinematicsOptions = numerics::DampedLeastSquaresOptions;
using InverseKinematicsResult = numerics::DampedLeastSquaresResult;

/// \brief K contact points (MuJoCo sites, or bodies' frames) on arms moved by Q hinge or slide
/// joints of a MuJoCo model, read into the controller's input. K and Q are fixed or Eigen::Dynamic.
///
/// read() needs `data` after the position and velocity stages (mj_forward, or mj_step1 before
/// mj_step2), at the state the controller acts on; it reads MuJoCo's already-computed fields
/// (qM, qfrc_bias, cdof, cdof_dot, cvel, subtree_com, site and body poses) and writes nothing to
/// `data`. After a whole mj_step those fields belong to the state before the step (qpos and qvel
/// were integrated after them): call mj_forward first, or split the step.
template <int ArmsAtCompileTime = Eigen::Dynamic, int JointsAtCompileTime = Eigen::Dynamic>
class MujocoArms {
public:
    static constexpr int Arms = ArmsAtCompileTime;
    static constexpr int Joints = JointsAtCompileTime;
    using Input = ControllerInput<double, Arms, Joints>;

    /// \param joint_names Q hinge or slide joints, in the order of q (and of M's rows, J's columns).
    /// \param contact_sites K names, one per hand, in the order of J's row blocks: a site, or (when
    ///   no site has the name, e.g. a URDF's fixed link) a body, whose frame is the contact frame:
    ///   origin the contact point, z the object's inward normal. A body's frame is its origin, not
    ///   a point on its surface (a hand's body named instead of its palm's site puts the contact
    ///   inside the hand): contact_frame_kind and contact_description say which was used.
    /// \param frames MujocoContactFrames::sites_only refuses a name that is a body's only.
    /// \throws InvalidModel naming the joint or site ("arm i" for sites): a name the model lacks (or,
    ///   with sites_only, names a body), a joint that is not a hinge or slide or is named twice, a
    ///   joint or contact that moves with a joint outside joint_names (M, h and J would miss that
    ///   coupling), counts other than K, Q.
    MujocoArms(const mjModel* model, const std::vector<std::string>& joint_names,
               const std::vector<std::string>& contact_sites,
               MujocoContactFrames frames = MujocoContactFrames::sites_or_bodies)
        : selection_(counted(model, joint_names, contact_sites), joint_names, contact_sites, frames)
    {
    }

    Index arms() const noexcept { return selection_.arms(); }
    Index joints() const noexcept { return selection_.joints(); }
    /// The model's ids and addresses of joint j (in q's order) and of contact i.
    int joint_id(Index j) const noexcept { return selection_.joint(j).id; }
    int dof_address(Index j) const noexcept { return selection_.joint(j).dof; }
    int qpos_address(Index j) const noexcept { return selection_.joint(j).qpos; }
    const detail::MujocoContact& contact(Index i) const noexcept { return selection_.contact(i); }
    /// Whether contact i's frame is a site or a body's own frame (a name no site has).
    MujocoFrameKind contact_frame_kind(Index i) const noexcept
    {
        return contact(i).is_site ? MujocoFrameKind::site : MujocoFrameKind::body;
    }
    /// What contact i's frame is, for logs and checks: "site 'left_palm' on body 'left_link7'", or
    /// "body 'left_link7' (no site has that name: the contact frame is the body's own frame, not a
    /// point on its surface; sites on this body: 'left_palm')".
    const std::string& contact_description(Index i) const noexcept { return selection_.contact_description(i); }

    /// \brief Fills input.inertia, bias, jacobian, jacobian_rate_qdot, positions and velocities,
    /// and the contacts' poses (read_contact_poses; the object's state and the desired motion are
    /// the caller's). Allocation-free; `data` is read only. `model` is the one the adapter was
    /// built from or a copy of it.
    void read(const mjModel* model, const mjData* data, Input& input) const noexcept
    {
        read_inertia(model, data, input.inertia);
        read_bias(data, input.bias);
        read_jacobian(model, data, input.jacobian);
        read_jacobian_rate_qdot(model, data, input.jacobian_rate_qdot);
        read_positions(data, input.positions);
        read_velocities(data, input.velocities);
        read_contact_poses(data, input);
    }

    /// input.contact_positions and contact_orientations from the contact sites' frames (the arms'
    /// forward kinematics), and input.contact_poses_filled: what the controller predicts the
    /// object's pose from during a dropout and measures each contact's slip with (docs/control.md,
    /// "Faults: dropout, safe hold, slip, torque limits").
    void read_contact_poses(const mjData* data, Input& input) const noexcept
    {
        for (Index i = 0; i < arms(); ++i) {
            input.contact_positions.col(i) = contact_position(data, i);
            input.contact_orientations.col(i) = Eigen::Quaterniond(contact_rotation(data, i)).normalized().coeffs();
        }
        input.contact_poses_filled = true;
    }

    /// M restricted to the chosen joints (Q x Q), armature included (MuJoCo adds it to qM).
    void read_inertia(const mjModel* model, const mjData* data, Eigen::Ref<Eigen::MatrixXd> inertia) const noexcept
    {
        selection_.read_inertia(model, data, inertia);
    }
    /// h = C(q, qdot) qdot + g(q): MuJoCo's qfrc_bias. Passive forces (joint damping and
    /// stiffness, fluid drag: qfrc_passive) are not in it (docs/adapters.md, "MuJoCo").
    void read_bias(const mjData* data, Eigen::Ref<Eigen::VectorXd> bias) const noexcept
    {
        for (Index j = 0; j < joints(); ++j) {
            bias(j) = data->qfrc_bias[dof_address(j)];
        }
    }
    /// J (6K x Q): rows 6i..6i+5 map qdot to contact i's twist [v; w], v the contact point's
    /// velocity, both in {w}.
    void read_jacobian(const mjModel* model, const mjData* data, Eigen::Ref<Eigen::MatrixXd> jacobian) const noexcept
    {
        selection_.read_jacobian(model, data, jacobian);
    }
    /// Jdot qdot (6K): each contact point's classical acceleration [a; alpha] in {w} at zero joint
    /// acceleration (without gravity).
    void read_jacobian_rate_qdot(const mjModel* model, const mjData* data, Eigen::Ref<Eigen::VectorXd> rate) const noexcept
    {
        selection_.read_jacobian_rate_qdot(model, data, rate);
    }
    void read_positions(const mjData* data, Eigen::Ref<Eigen::VectorXd> q) const noexcept
    {
        for (Index j = 0; j < joints(); ++j) {
            q(j) = data->qpos[qpos_address(j)];
        }
    }
    void read_velocities(const mjData* data, Eigen::Ref<Eigen::VectorXd> qdot) const noexcept
    {
        for (Index j = 0; j < joints(); ++j) {
            qdot(j) = data->qvel[dof_address(j)];
        }
    }

    /// Contact i's frame in {w}: the point and the rotation to {w} (columns: x, y, z = normal).
    Eigen::Vector3d contact_position(const mjData* data, Index i) const noexcept
    {
        return Eigen::Map<const Eigen::Vector3d>(contact(i).position(data));
    }
    Eigen::Matrix3d contact_rotation(const mjData* data, Index i) const noexcept
    {
        return Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(contact(i).rotation(data));  // MuJoCo: row-major
    }
    Pose<double> contact_pose(const mjData* data, Index i) const
    {
        return {contact_position(data, i), Eigen::Quaterniond(contact_rotation(data, i)).normalized()};
    }

    /// \brief Each hand's wrench on `object_body` from MuJoCo's contacts (docs/adapters.md,
    /// "Applied wrenches and contact forces"): hand i is contact i's body with the bodies welded to
    /// it (no joint between them: the arm's last link and its palm), the object `object_body` with
    /// the bodies welded to it; every contact between a geom of the one and a geom of the other
    /// counts, in either order, with its force from mj_contactForce (mujoco_contact_wrench), the
    /// moments taken about contact point i. `data` must hold a constraint solve and the contacts it
    /// solved for: after mj_step2 (the forces of that step; the positions are still the step's
    /// start) or mj_forward, not after mj_step1 alone (its new contacts would be read with the last
    /// step's forces). Allocation-free; `out` has K columns.
    void read_contact_wrenches(const mjModel* model, const mjData* data, int object_body,
                               MujocoContactWrenches<Arms>& out) const noexcept
    {
        COOPDYN_ASSERT(out.arms() == arms(), "MujocoArms: the contact wrenches have the wrong size");
        out.set_zero();
        const int object = model->body_weldid[object_body];
        for (int c = 0; c < data->ncon; ++c) {
            const mjContact& found = data->contact[c];
            const int first = model->body_weldid[model->geom_bodyid[found.geom1]];
            const int second = model->body_weldid[model->geom_bodyid[found.geom2]];
            for (Index i = 0; i < arms(); ++i) {
                const int hand = model->body_weldid[contact(i).body];
                if (!((first == hand && second == object) || (second == hand && first == object))) {
                    continue;
                }
                mjtNum local[6];
                mj_contactForce(model, data, c, local);  // geom1's force on geom2
                const double sign = first == hand ? 1.0 : -1.0;
                const Vector6<double> wrench = sign * mujoco_contact_wrench(found, local);
                const Eigen::Vector3d force = wrench.template head<3>();
                const Eigen::Vector3d arm = Eigen::Map<const Eigen::Vector3d>(found.pos) - contact_position(data, i);
                out.world.template block<3, 1>(0, i) += force;
                out.world.template block<3, 1>(3, i) += arm.cross(force) + wrench.template tail<3>();
                out.normal_forces(i) += local[0];
                ++out.points(i);
            }
        }
        for (Index i = 0; i < arms(); ++i) {
            const Eigen::Matrix3d rotation = contact_rotation(data, i);
            out.contact_frame.template block<3, 1>(0, i) = rotation.transpose() * out.world.template block<3, 1>(0, i);
            out.contact_frame.template block<3, 1>(3, i) = rotation.transpose() * out.world.template block<3, 1>(3, i);
        }
    }

    /// \brief ControllerParameters::contacts from the current state: each contact frame relative to
    /// the object (mujoco_object_pose: its centre of mass, its body's axes), with `friction`.
    /// Allocates (construction time). \throws InvalidArgument when the model has no such body.
    std::vector<ContactPoint<double>> contact_points(const mjModel* model, const mjData* data, const std::string& object_body,
                                                     const ContactFriction<double>& friction = {}) const
    {
        const Pose<double> object = mujoco_object_pose(model, data, detail::mujoco_body_id(model, object_body));
        std::vector<ContactPoint<double>> points(static_cast<std::size_t>(arms()));
        for (Index i = 0; i < arms(); ++i) {
            points[static_cast<std::size_t>(i)].frame = contact_frame_in_object(object, contact_pose(data, i));
            points[static_cast<std::size_t>(i)].friction = friction;
        }
        return points;
    }

    /// \brief Inverse kinematics for start postures: moves the chosen joints' qpos in `data` so that
    /// each contact frame reaches its target pose in {w} (position and orientation), by damped
    /// least squares from data's current qpos, clamping to the joints' ranges where the model
    /// limits them. Other joints (the object, other robots) stay. On return data's kinematics match
    /// its qpos (mj_kinematics); run mj_forward before simulating. Allocates: not for the tick.
    /// \throws InvalidArgument when `targets` does not hold K poses, a target is not finite or its
    /// quaternion is zero ("targets[i]"), or an option is out of range ("options.damping", ...).
    InverseKinematicsResult place_hands(const mjModel* model, mjData* data, const std::vector<Pose<double>>& targets,
                                        const InverseKinematicsOptions& options = {}) const
    {
        check_targets(targets, options);
        Eigen::VectorXd q(joints());
        read_positions(data, q);
        const auto evaluate = [&](const Eigen::VectorXd& x, Eigen::VectorXd& error, Eigen::MatrixXd& jacobian) {
            set_positions(model, data, x);
            error.resize(6 * arms());
            jacobian.resize(6 * arms(), joints());
            for (Index i = 0; i < arms(); ++i) {
                const Pose<double> pose = contact_pose(data, i);
                const Pose<double>& target = targets[static_cast<std::size_t>(i)];
                error.template segment<3>(6 * i) = target.position - pose.position;
                // log(R_target R^T): the rotation in {w} that takes the hand to the target, which J's
                // angular rows predict to first order (R(q + dq) ~ exp(J_w dq) R).
                error.template segment<3>(6 * i + 3) =
                    quaternion_log(Eigen::Quaterniond(target.orientation.normalized() * pose.orientation.conjugate()));
            }
            read_jacobian(model, data, jacobian);
        };
        const auto project = [&](Eigen::VectorXd& x) {
            for (Index j = 0; j < joints(); ++j) {
                const int id = joint_id(j);
                if (model->jnt_limited[id]) {
                    x(j) = std::min(std::max(x(j), model->jnt_range[2 * id]), model->jnt_range[2 * id + 1]);
                }
            }
        };
        project(q);
        const InverseKinematicsResult result = numerics::damped_least_squares(evaluate, project, q, options);
        set_positions(model, data, q);
        return result;
    }

private:
    /// The chosen joints' qpos, then the stages that give the contact poses and cdof (for J).
    void set_positions(const mjModel* model, mjData* data, const Eigen::VectorXd& q) const noexcept
    {
        for (Index j = 0; j < joints(); ++j) {
            data->qpos[qpos_address(j)] = q(j);
        }
        mj_kinematics(model, data);
        mj_comPos(model, data);
    }

    /// place_hands' inputs: K finite targets with nonzero quaternions, options in range.
    void check_targets(const std::vector<Pose<double>>& targets, const InverseKinematicsOptions& options) const
    {
        if (targets.size() != static_cast<std::size_t>(arms())) {
            throw InvalidArgument("MuJoCo arms", "targets", no_arm,
                                  "has " + std::to_string(targets.size()) + " poses for " + std::to_string(arms()) + " contacts");
        }
        for (std::size_t i = 0; i < targets.size(); ++i) {
            const Pose<double>& target = targets[i];
            if (!target.position.allFinite() || !target.orientation.coeffs().allFinite() ||
                !(target.orientation.coeffs().norm() > 0.0)) {
                throw InvalidArgument("MuJoCo arms", "targets[" + std::to_string(i) + "]", static_cast<Index>(i),
                                      "must have a finite position and a finite, nonzero quaternion");
            }
        }
        const auto require = [](bool ok, const char* parameter, const std::string& what) {
            if (!ok) {
                throw InvalidArgument("MuJoCo arms", parameter, no_arm, what);
            }
        };
        require(std::isfinite(options.damping) && options.damping >= 0.0, "options.damping",
                "must be finite and >= 0, got " + std::to_string(options.damping));
        require(std::isfinite(options.tolerance) && options.tolerance >= 0.0, "options.tolerance",
                "must be finite and >= 0, got " + std::to_string(options.tolerance));
        require(options.iteration_limit >= 0, "options.iteration_limit",
                "must be >= 0, got " + std::to_string(options.iteration_limit));
        require(std::isfinite(options.max_step) && options.max_step > 0.0, "options.max_step",
                "must be finite and positive, got " + std::to_string(options.max_step));
        require(std::isfinite(options.stall_step) && options.stall_step >= 0.0, "options.stall_step",
                "must be finite and >= 0, got " + std::to_string(options.stall_step));
    }

    /// `model`, once the counts match a fixed K and Q (checked before any name is looked up).
    static const mjModel* counted(const mjModel* model, const std::vector<std::string>& joint_names,
                                  const std::vector<std::string>& contact_sites)
    {
        require_count("joint_names", joint_names.size(), Joints, "Q");
        require_count("contact_sites", contact_sites.size(), Arms, "K");
        return model;
    }

    static void require_count(const char* parameter, std::size_t count, int fixed, const char* symbol)
    {
        if (fixed != Eigen::Dynamic && count != static_cast<std::size_t>(fixed)) {
            throw InvalidModel("MuJoCo arms", parameter, no_arm,
                               "has " + std::to_string(count) + " names, the adapter's " + symbol + " is " +
                                   std::to_string(fixed));
        }
    }

    detail::MujocoSelection selection_;
};

}  // namespace coopdyn
