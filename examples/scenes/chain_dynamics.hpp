// One arm of a scene evaluated by its own recursion instead of MuJoCo's stages (docs/scenes.md, "The
// rigid plant"): M, h, J, Jdot qdot and the contact frame of a serial chain of hinge joints, built
// once from the MuJoCo model's constants (bodies' poses, joints' axes and anchors, masses and
// inertias, armature, gravity) and evaluated without MuJoCo, the same quantities as the library's
// adapter (coopdyn::MujocoArms::read after mj_kinematics, mj_comPos, mj_crb, mj_comVel, mj_rne;
// test_scenes compares the two at random states to rounding). The rigid scene plant evaluates its
// arms this way: MuJoCo 2.2.2's stages and the read cost about 6.1 us per evaluation of the
// three-arm scene's 26 degrees of freedom, this recursion 1.6 us (docs/performance.md).
//
// Frames. MuJoCo turns a body with a hinge joint about the joint's axis a through its anchor p (both
// in the body frame B) by theta = q - qpos0: B(theta) = B(0) Trans(p) Rot(a, theta) Trans(-p).
// With C a rotation taking z to a, Rot(a, theta) = C RotZ(theta) C^T, so the link's joint frame
// F(theta) = B(0) Trans(p) C RotZ(theta) has its origin on the axis (the pivot) and its z along it,
// and everything fixed in the link is fixed in F. Between two joints (and from the world to the
// first) the chain is a constant transform X_k: F_k(theta) = F_{k-1} X_k RotZ(theta_k), which
// takes in the bodies without joints on the way. Bodies without joints that hang from link k (a
// palm, a flange) are lumped into it (their masses, centres and inertias added exactly); those that
// hang from the world do not move. Then the outward pass (Luh-Walker-Paul) and
// examples/common/chain_recursion.hpp's inward pass and contact terms.
//
// What it does not model, and says so (ChainDynamics::from_mujoco returns no chain and the reason;
// the plant then runs MuJoCo's stages): slide, ball or free joints in an arm, a body with more than
// one joint, a joint outside the arm's list that moves with it (a gripper's finger), an arm of more
// than max_chain_joints joints. This header belongs to the examples.
#pragma once

#include "../common/chain_recursion.hpp"
#include "../common/sin_cos.hpp"

#include <coopdyn/adapters/mujoco.hpp>
#include <coopdyn/spatial/inertia.hpp>
#include <coopdyn/spatial/pose.hpp>
#include <coopdyn/spatial/symmetric3.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <array>
#include <optional>
#include <string>
#include <vector>

namespace scenes {

/// The most joints of one arm the own recursion evaluates (its workspace's fixed capacity).
constexpr int max_chain_joints = 12;

class ChainDynamics {
public:
    using Index = Eigen::Index;

    /// The chain of `arms`' arm `arm`, whose joints are q's [first, first + count), from `model`
    /// (the one the adapter was built from, or a copy). No chain, with `why` set, when the arm is
    /// not a serial chain of hinge joints (the file comment).
    static std::optional<ChainDynamics> from_mujoco(const mjModel* model, const coopdyn::MujocoArms<>& arms, Index arm,
                                                    Index first, Index count, std::string& why);

    Index joints() const noexcept { return static_cast<Index>(joint_count_); }

    /// M (n x n), h (n), J (6 x n, rows [v; w] of the contact point), Jdot qdot (6) and the contact
    /// frame at (q, qdot) (n each), into the given blocks. Allocates nothing. Six- and seven-joint
    /// arms run at those fixed sizes (the loops unrolled), others at run-time sizes.
    template <typename Q, typename Qdot, typename Inertia, typename Bias, typename Jacobian, typename Rate>
    void evaluate(const Q& q, const Qdot& qdot, Inertia&& inertia, Bias&& bias, Jacobian&& jacobian, Rate&& rate,
                  coopdyn::Pose<double>& contact) const noexcept
    {
        switch (joint_count_) {
        case 6: evaluate_at<6>(q, qdot, inertia, bias, jacobian, rate, contact); break;
        case 7: evaluate_at<7>(q, qdot, inertia, bias, jacobian, rate, contact); break;
        default: evaluate_at<Eigen::Dynamic>(q, qdot, inertia, bias, jacobian, rate, contact); break;
        }
    }

private:
    ChainDynamics() = default;

    // from_mujoco's three steps (below the class); each sets `why` and returns false when the arm
    // is not a chain the recursion models.
    bool set_joints(const mjModel* model, const coopdyn::MujocoArms<>& arms, Index first, std::vector<int>& bodies,
                    std::vector<Eigen::Isometry3d>& frames, std::string& why);
    bool set_contact(const mjModel* model, const coopdyn::detail::MujocoContact& contact, int last_body,
                     const Eigen::Isometry3d& last_frame, std::string& why);
    bool set_inertias(const mjModel* model, const std::vector<int>& bodies, const std::vector<Eigen::Isometry3d>& frames,
                      std::string& why);

    template <int N, typename Q, typename Qdot, typename Inertia, typename Bias, typename Jacobian, typename Rate>
    void evaluate_at(const Q& q, const Qdot& qdot, Inertia& inertia, Bias& bias, Jacobian& jacobian, Rate& rate,
                     coopdyn::Pose<double>& contact) const noexcept
    {
        example_common::ChainKinematics<N, N == Eigen::Dynamic ? max_chain_joints : N> pass(joints());
        Eigen::Matrix3d rotation;
        Eigen::Vector3d origin, origin_acceleration;
        outward_pass(q, qdot, pass, rotation, origin, origin_acceleration);
        example_common::chain_inward_pass(pass, mass_, gravity_, inertia, bias);
        inertia.diagonal() += armature_.head(joints());
        contact.position = origin + rotation * contact_point_;
        contact.orientation = Eigen::Quaterniond(rotation * contact_rotation_).normalized();
        example_common::chain_contact_terms(pass, contact.position, origin, origin_acceleration, jacobian, rate);
    }

    /// Frames, axes, velocities and velocity-product accelerations of the links; the last link's
    /// frame (rotation, origin: its pivot) and its pivot's acceleration.
    template <typename Q, typename Qdot, typename Kinematics>
    void outward_pass(const Q& q, const Qdot& qdot, Kinematics& pass, Eigen::Matrix3d& rotation, Eigen::Vector3d& origin,
                      Eigen::Vector3d& origin_acceleration) const noexcept
    {
        using Eigen::Vector3d;
        std::array<double, max_chain_joints> angle{};
        for (std::size_t k = 0; k < joint_count_; ++k) {
            angle[k] = q(static_cast<Index>(k)) - reference_[k];
        }
        const example_common::SinCos<max_chain_joints> joint = example_common::sin_cos(angle);
        auto& [axis, pivot, com, angular_velocity, angular_acceleration, com_acceleration, inertia_world] = pass;
        rotation.setIdentity();
        origin.setZero();
        origin_acceleration.setZero();
        Vector3d w = Vector3d::Zero(), alpha = Vector3d::Zero();
        for (std::size_t k = 0; k < static_cast<std::size_t>(pass.joints()); ++k) {
            const auto i = static_cast<Index>(k);
            // F_{k-1} X_k: the frame before joint k turns. Its pivot is fixed in link k - 1, so it
            // accelerates with that link's w and alpha.
            const Eigen::Matrix3d before = rotation * fixed_rotation_[k];
            const Vector3d next_origin = origin + rotation * fixed_translation_[k];
            const Vector3d step = next_origin - origin;
            origin_acceleration += alpha.cross(step) + w.cross(w.cross(step));
            origin = next_origin;
            // RotZ(theta_k).
            const double c = joint.cosine[k], s = joint.sine[k];
            rotation.col(0) = c * before.col(0) + s * before.col(1);
            rotation.col(1) = -s * before.col(0) + c * before.col(1);
            rotation.col(2) = before.col(2);
            axis.col(i) = before.col(2);
            pivot.col(i) = origin;

            const Vector3d spin = axis.col(i) * qdot(i);
            alpha += w.cross(spin);
            w += spin;
            com.col(i) = origin + rotation * com_[k];
            const Vector3d to_com = com.col(i) - origin;
            com_acceleration.col(i) = origin_acceleration + alpha.cross(to_com) + w.cross(w.cross(to_com));
            angular_velocity.col(i) = w;
            angular_acceleration.col(i) = alpha;
            inertia_world[k] = inertia_[k].rotated(rotation);
        }
    }

    std::size_t joint_count_ = 0;
    std::array<Eigen::Matrix3d, max_chain_joints> fixed_rotation_{};    // X_k's rotation
    std::array<Eigen::Vector3d, max_chain_joints> fixed_translation_{};  // X_k's translation
    std::array<double, max_chain_joints> reference_{};                  // qpos0
    std::array<double, max_chain_joints> mass_{};                       // link k with what is lumped into it
    std::array<Eigen::Vector3d, max_chain_joints> com_{};               // its centre of mass in F_k
    std::array<coopdyn::Symmetric3<double>, max_chain_joints> inertia_{};  // about the centre, F_k's axes
    Eigen::Matrix<double, max_chain_joints, 1> armature_ = Eigen::Matrix<double, max_chain_joints, 1>::Zero();
    Eigen::Vector3d gravity_ = Eigen::Vector3d::Zero();
    Eigen::Vector3d contact_point_ = Eigen::Vector3d::Zero();              // in F_n
    Eigen::Matrix3d contact_rotation_ = Eigen::Matrix3d::Identity();       // in F_n
};

namespace detail {

/// Body b's frame in its parent's (MuJoCo's body_pos, body_quat: at qpos0).
inline Eigen::Isometry3d body_local(const mjModel* model, int body)
{
    const mjtNum* p = model->body_pos + 3 * body;
    const mjtNum* q = model->body_quat + 4 * body;
    Eigen::Isometry3d local = Eigen::Isometry3d::Identity();
    local.linear() = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
    local.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
    return local;
}

/// Body b's frame in its ancestor `ancestor`'s (0: the world), at qpos0; nullopt when `ancestor`
/// is not an ancestor of b or a body between them has a joint.
inline std::optional<Eigen::Isometry3d> static_path(const mjModel* model, int ancestor, int body)
{
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    for (int b = body; b != ancestor; b = model->body_parentid[b]) {
        if (b == 0 || (b != body && model->body_jntnum[b] > 0)) {
            return std::nullopt;
        }
        pose = body_local(model, b) * pose;
    }
    return pose;
}

/// Body b's joint frame in B (the file comment): origin at the joint's anchor, z along its axis.
inline Eigen::Isometry3d joint_frame(const mjModel* model, int joint)
{
    const Eigen::Vector3d axis = Eigen::Map<const Eigen::Vector3d>(model->jnt_axis + 3 * joint).normalized();
    Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
    frame.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis).toRotationMatrix();
    frame.translation() = Eigen::Map<const Eigen::Vector3d>(model->jnt_pos + 3 * joint);
    return frame;
}

/// The nearest body at or above b that has a joint (0: none, the world).
inline int moving_ancestor(const mjModel* model, int body)
{
    int b = body;
    while (b != 0 && model->body_jntnum[b] == 0) {
        b = model->body_parentid[b];
    }
    return b;
}

/// Body b's inertia (MuJoCo's body_mass, body_ipos, body_iquat, body_inertia), its frame `pose`
/// in a link's joint frame, as a spatial inertia about that frame's origin: the links' lumped
/// inertias are sums of these (coopdyn::SpatialInertia's parallel axes).
inline coopdyn::SpatialInertia<double> body_inertia(const mjModel* model, int body, const Eigen::Isometry3d& pose)
{
    const mjtNum* q = model->body_iquat + 4 * body;
    const Eigen::Matrix3d axes = pose.linear() * Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
    const Eigen::Vector3d centre = pose * Eigen::Vector3d(Eigen::Map<const Eigen::Vector3d>(model->body_ipos + 3 * body));
    const Eigen::Vector3d principal = Eigen::Map<const Eigen::Vector3d>(model->body_inertia + 3 * body);
    return coopdyn::SpatialInertia<double>::from_centre(model->body_mass[body], centre,
                                                        coopdyn::Symmetric3<double>::rotated_diagonal(principal, axes));
}

}  // namespace detail

inline std::optional<ChainDynamics> ChainDynamics::from_mujoco(const mjModel* model, const coopdyn::MujocoArms<>& arms,
                                                               Index arm, Index first, Index count, std::string& why)
{
    const std::string name = "arm " + std::to_string(arm);
    if (count < 1 || count > max_chain_joints) {
        why = name + " has " + std::to_string(count) + " joints (the own recursion takes 1 to " +
              std::to_string(max_chain_joints) + ")";
        return std::nullopt;
    }
    ChainDynamics chain;
    chain.joint_count_ = static_cast<std::size_t>(count);
    std::vector<int> bodies;                // each joint's body
    std::vector<Eigen::Isometry3d> frames;  // each joint frame in its body's frame
    if (!chain.set_joints(model, arms, first, bodies, frames, why) ||
        !chain.set_contact(model, arms.contact(arm), bodies.back(), frames.back(), why) ||
        !chain.set_inertias(model, bodies, frames, why)) {
        why = name + ": " + why;
        return std::nullopt;
    }
    const bool gravity = (model->opt.disableflags & mjDSBL_GRAVITY) == 0;
    chain.gravity_ = gravity ? Eigen::Vector3d(Eigen::Map<const Eigen::Vector3d>(model->opt.gravity)) : Eigen::Vector3d::Zero();
    return chain;
}

/// X_k, qpos0 and the armature of each joint, which must be the only hinge of its body and hang from
/// the previous joint's body (the world for the first) through bodies without joints.
inline bool ChainDynamics::set_joints(const mjModel* model, const coopdyn::MujocoArms<>& arms, Index first,
                                      std::vector<int>& bodies, std::vector<Eigen::Isometry3d>& frames, std::string& why)
{
    for (std::size_t k = 0; k < joint_count_; ++k) {
        const int joint = arms.joint_id(first + static_cast<Index>(k));
        const int body = model->jnt_bodyid[joint];
        const std::string joint_name = "joint " + coopdyn::detail::mujoco_name(model, mjOBJ_JOINT, joint);
        if (model->jnt_type[joint] != mjJNT_HINGE || model->body_jntnum[body] != 1) {
            why = joint_name + " is not the only hinge of its body";
            return false;
        }
        const std::optional<Eigen::Isometry3d> path = detail::static_path(model, k == 0 ? 0 : bodies.back(), body);
        if (!path) {
            why = joint_name + " does not hang from the arm's previous joint through bodies without joints";
            return false;
        }
        const Eigen::Isometry3d frame = detail::joint_frame(model, joint);
        const Eigen::Isometry3d previous = k == 0 ? Eigen::Isometry3d::Identity() : frames.back().inverse();
        const Eigen::Isometry3d fixed = previous * *path * frame;  // X_k
        fixed_rotation_[k] = fixed.linear();
        fixed_translation_[k] = fixed.translation();
        reference_[k] = model->qpos0[model->jnt_qposadr[joint]];
        armature_(static_cast<Index>(k)) = model->dof_armature[model->jnt_dofadr[joint]];
        bodies.push_back(body);
        frames.push_back(frame);
    }
    return true;
}

/// The contact frame in the last link's joint frame F_n (`last_body`, whose joint frame is
/// `last_frame`): the contact's body must be that body or hang from it without joints.
inline bool ChainDynamics::set_contact(const mjModel* model, const coopdyn::detail::MujocoContact& contact, int last_body,
                                       const Eigen::Isometry3d& last_frame, std::string& why)
{
    const std::optional<Eigen::Isometry3d> contact_body = detail::static_path(model, last_body, contact.body);
    if (!contact_body || (contact.body != last_body && model->body_jntnum[contact.body] > 0)) {
        why = "its contact does not move with its last joint alone";
        return false;
    }
    Eigen::Isometry3d contact_local = Eigen::Isometry3d::Identity();
    if (contact.is_site) {
        const mjtNum* q = model->site_quat + 4 * contact.id;
        contact_local.linear() = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
        contact_local.translation() = Eigen::Map<const Eigen::Vector3d>(model->site_pos + 3 * contact.id);
    }
    const Eigen::Isometry3d contact_frame = last_frame.inverse() * *contact_body * contact_local;
    contact_point_ = contact_frame.translation();
    contact_rotation_ = contact_frame.linear();
    return true;
}

/// Each link's mass, centre and inertia: every body that moves with the link's joint and no later
/// one, lumped. A body moving with the arm through a joint that is not the arm's cannot be.
inline bool ChainDynamics::set_inertias(const mjModel* model, const std::vector<int>& bodies,
                                        const std::vector<Eigen::Isometry3d>& frames, std::string& why)
{
    std::vector<coopdyn::SpatialInertia<double>> lumped(bodies.size(), coopdyn::SpatialInertia<double>::Zero());
    for (int body = 1; body < model->nbody; ++body) {
        const int mover = detail::moving_ancestor(model, body);
        const auto link = std::find(bodies.begin(), bodies.end(), mover);
        if (link == bodies.end()) {
            const int parent_mover = mover == 0 ? 0 : detail::moving_ancestor(model, model->body_parentid[mover]);
            if (mover != 0 && std::find(bodies.begin(), bodies.end(), parent_mover) != bodies.end()) {
                why = "body " + coopdyn::detail::mujoco_name(model, mjOBJ_BODY, mover) +
                      " moves with the arm through a joint that is not the arm's";
                return false;
            }
            continue;
        }
        const auto slot = static_cast<std::size_t>(link - bodies.begin());
        lumped[slot] += detail::body_inertia(model, body, frames[slot].inverse() * *detail::static_path(model, mover, body));
    }
    for (std::size_t k = 0; k < lumped.size(); ++k) {
        const bool massive = lumped[k].mass() > 0.0;  // a massless link: no centre, its inertia (zero) as is
        mass_[k] = lumped[k].mass();
        com_[k] = massive ? lumped[k].centre() : Eigen::Vector3d::Zero();
        inertia_[k] = massive ? lumped[k].rotational_about_centre() : lumped[k].rotational();
    }
    return true;
}

}  // namespace scenes
