/// \file
/// \brief The MuJoCo adapter's model-side part (adapters/mujoco.hpp): which of a MuJoCo model's
/// joints and contact frames the arms are, checked once, and the reads of M, J and Jdot qdot from
/// MuJoCo's already-computed fields for them; the object's pose and twist as the controller
/// measures them. docs/adapters.md, "MuJoCo".
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/errors.hpp"
#include "coopdyn/spatial/pose.hpp"

#include <Eigen/Core>
#include <mujoco/mujoco.h>

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace coopdyn {

/// \brief Owners of MuJoCo's model and data (mj_deleteModel, mj_deleteData on destruction), for
/// code that loads its own model: `MujocoModelPointer model(mj_loadXML(...))`.
struct MujocoModelDeleter {
    void operator()(mjModel* model) const noexcept { mj_deleteModel(model); }
};
struct MujocoDataDeleter {
    void operator()(mjData* data) const noexcept { mj_deleteData(data); }
};
using MujocoModelPointer = std::unique_ptr<mjModel, MujocoModelDeleter>;
using MujocoDataPointer = std::unique_ptr<mjData, MujocoDataDeleter>;

/// \brief The object's pose as the controller's input object.pose measures it: its body's centre
/// of mass (xipos) and its body frame's orientation (xquat), in {w}. mj_kinematics must have run.
inline Pose<double> mujoco_object_pose(const mjModel* /*model*/, const mjData* data, int body) noexcept
{
    const mjtNum* q = data->xquat + 4 * body;  // MuJoCo: (w, x, y, z)
    return {Eigen::Vector3d(data->xipos[3 * body], data->xipos[3 * body + 1], data->xipos[3 * body + 2]),
            Eigen::Quaterniond(q[0], q[1], q[2], q[3])};
}

/// \brief The object's state for ControllerInput::object: mujoco_object_pose and the twist
/// [v; w] of its centre of mass in {w} (mj_objectVelocity; mj_comVel must have run).
inline RigidBodyState<double> mujoco_object_state(const mjModel* model, const mjData* data, int body) noexcept
{
    RigidBodyState<double> state;
    state.pose = mujoco_object_pose(model, data, body);
    mjtNum velocity[6];  // [w; v] at xipos, in {w}
    mj_objectVelocity(model, data, mjOBJ_BODY, body, velocity, 0);
    state.twist << velocity[3], velocity[4], velocity[5], velocity[0], velocity[1], velocity[2];
    return state;
}

/// \brief What a MujocoArms contact frame is (MujocoArms::contact_frame_kind): a site, or a body's
/// own frame (its origin and axes: a URDF's fixed link, or a body named where a site was meant).
enum class MujocoFrameKind { site, body };

/// \brief Which names MujocoArms accepts as contact frames: a site or, when no site has the name, a
/// body (the default; URDF has no sites), or sites only (a body's name is refused, so that a hand's
/// body cannot stand in for the site on its palm's surface). docs/adapters.md, "Construction".
enum class MujocoContactFrames { sites_or_bodies, sites_only };

namespace detail {

/// A joint of the selection: its id and its (single) dof and qpos addresses.
struct MujocoJoint {
    int id = -1;
    int dof = -1;
    int qpos = -1;
};

/// A contact frame: a site, or a body's frame (a URDF's fixed link), and the body it moves with.
struct MujocoContact {
    int id = -1;
    int body = -1;
    bool is_site = true;
    const mjtNum* position(const mjData* data) const noexcept
    {
        return (is_site ? data->site_xpos : data->xpos) + 3 * id;
    }
    const mjtNum* rotation(const mjData* data) const noexcept
    {
        return (is_site ? data->site_xmat : data->xmat) + 9 * id;
    }
};

inline std::string mujoco_name(const mjModel* model, mjtObj type, int id)
{
    const char* name = mj_id2name(model, type, id);
    return name != nullptr ? "'" + std::string(name) + "'" : "#" + std::to_string(id);
}

/// "; sites on this body: 'a', 'b'" (or "; this body has no site"): where a body was named instead
/// of a site, the sites the user may have meant.
inline std::string mujoco_sites_on_body(const mjModel* model, int body)
{
    std::string sites;
    for (int site = 0; site < model->nsite; ++site) {
        if (model->site_bodyid[site] == body) {
            sites += (sites.empty() ? "; sites on this body: " : ", ") + mujoco_name(model, mjOBJ_SITE, site);
        }
    }
    return sites.empty() ? "; this body has no site" : sites;
}

inline int mujoco_body_id(const mjModel* model, const std::string& name)
{
    const int id = mj_name2id(model, mjOBJ_BODY, name.c_str());
    if (id < 0) {
        throw InvalidArgument("MuJoCo arms", "object_body", no_arm, "names no body of the model: '" + name + "'");
    }
    return id;
}

/// \brief The chosen joints and contacts of a model, checked at construction (see MujocoArms),
/// and the per-tick reads that do not depend on K and Q at compile time.
class MujocoSelection {
public:
    MujocoSelection(const mjModel* model, const std::vector<std::string>& joint_names,
                    const std::vector<std::string>& contact_names,
                    MujocoContactFrames frames = MujocoContactFrames::sites_or_bodies)
    {
        if (model == nullptr) {
            throw InvalidModel("MuJoCo arms", "model", no_arm, "is null");
        }
        nv_ = model->nv;
        select_joints(model, joint_names);
        select_contacts(model, contact_names, frames);
    }

    Index joints() const noexcept { return static_cast<Index>(joints_.size()); }
    Index arms() const noexcept { return static_cast<Index>(contacts_.size()); }
    const MujocoJoint& joint(Index j) const noexcept { return joints_[static_cast<std::size_t>(j)]; }
    const MujocoContact& contact(Index i) const noexcept { return contacts_[static_cast<std::size_t>(i)]; }
    /// "site 'left_palm' on body 'left_link7'", or "body 'link7' (no site has that name: ...)".
    const std::string& contact_description(Index i) const noexcept
    {
        return contact_descriptions_[static_cast<std::size_t>(i)];
    }

    /// M's rows and columns of the chosen dofs, from MuJoCo's sparse qM: row d holds, from
    /// dof_Madr[d] on, M(d, d) and then M(d, a) for the dof's ancestors a (dof_parentid), the only
    /// nonzeros left of the diagonal. The construction made every ancestor a chosen dof.
    void read_inertia(const mjModel* model, const mjData* data, Eigen::Ref<Eigen::MatrixXd> inertia) const noexcept
    {
        COOPDYN_ASSERT(model->nv == nv_, "MujocoArms: another model than the one it was built for");
        COOPDYN_ASSERT(inertia.rows() == joints() && inertia.cols() == joints(), "MujocoArms: M has the wrong size");
        inertia.setZero();
        for (Index row = 0; row < joints(); ++row) {
            int address = model->dof_Madr[joint(row).dof];
            for (int dof = joint(row).dof; dof >= 0; dof = model->dof_parentid[dof], ++address) {
                const Index col = column_of_dof_[static_cast<std::size_t>(dof)];
                inertia(row, col) = inertia(col, row) = data->qM[address];
            }
        }
    }

    /// Per contact, per dof of its chain: the dof's motion cdof = [w; v] (v at the tree's
    /// reference point c = subtree_com of its root body, as MuJoCo's mj_jac) moved to the contact
    /// point p: [v + w x (p - c); w].
    void read_jacobian(const mjModel* model, const mjData* data, Eigen::Ref<Eigen::MatrixXd> jacobian) const noexcept
    {
        COOPDYN_ASSERT(jacobian.rows() == 6 * arms() && jacobian.cols() == joints(), "MujocoArms: J has the wrong size");
        jacobian.setZero();
        for (Index i = 0; i < arms(); ++i) {
            const Eigen::Vector3d offset = point(data, i) - reference(model, data, i);
            for (std::size_t k = chain_begin_[static_cast<std::size_t>(i)]; k < chain_begin_[static_cast<std::size_t>(i) + 1]; ++k) {
                const int dof = chain_dofs_[k];
                const Eigen::Map<const Eigen::Vector3d> angular(data->cdof + 6 * dof);
                const Eigen::Map<const Eigen::Vector3d> linear(data->cdof + 6 * dof + 3);
                const Index col = column_of_dof_[static_cast<std::size_t>(dof)];
                jacobian.block<3, 1>(6 * i, col) = linear + angular.cross(offset);
                jacobian.block<3, 1>(6 * i + 3, col) = angular;
            }
        }
    }

    /// Jdot qdot without MuJoCo's RNE (2.2.2 has no mj_jacDot, and mj_rnePostConstraint writes to
    /// data): the spatial acceleration of the contact's body at zero joint acceleration is
    /// sum cdof_dot qvel over its chain (mj_comVel's cdof_dot = cvel x cdof; the reference point c
    /// held fixed in space), [alpha; a_c]. The contact point's classical acceleration adds the
    /// change of point and the velocity term: a_p = a_c + alpha x (p - c) + w x v_p, with
    /// v_p = v_c + w x (p - c) from the body's cvel = [w; v_c] (docs/adapters.md, "Conventions").
    void read_jacobian_rate_qdot(const mjModel* model, const mjData* data, Eigen::Ref<Eigen::VectorXd> rate) const noexcept
    {
        COOPDYN_ASSERT(rate.size() == 6 * arms(), "MujocoArms: Jdot qdot has the wrong size");
        for (Index i = 0; i < arms(); ++i) {
            Eigen::Vector3d angular = Eigen::Vector3d::Zero();
            Eigen::Vector3d linear = Eigen::Vector3d::Zero();
            for (std::size_t k = chain_begin_[static_cast<std::size_t>(i)]; k < chain_begin_[static_cast<std::size_t>(i) + 1]; ++k) {
                const int dof = chain_dofs_[k];
                angular += data->qvel[dof] * Eigen::Map<const Eigen::Vector3d>(data->cdof_dot + 6 * dof);
                linear += data->qvel[dof] * Eigen::Map<const Eigen::Vector3d>(data->cdof_dot + 6 * dof + 3);
            }
            const int body = contact(i).body;
            const Eigen::Map<const Eigen::Vector3d> omega(data->cvel + 6 * body);
            const Eigen::Map<const Eigen::Vector3d> velocity_at_reference(data->cvel + 6 * body + 3);
            const Eigen::Vector3d offset = point(data, i) - reference(model, data, i);
            const Eigen::Vector3d velocity = velocity_at_reference + omega.cross(offset);
            rate.segment<3>(6 * i) = linear + angular.cross(offset) + omega.cross(velocity);
            rate.segment<3>(6 * i + 3) = angular;
        }
    }

private:
    Eigen::Vector3d point(const mjData* data, Index i) const noexcept
    {
        return Eigen::Map<const Eigen::Vector3d>(contact(i).position(data));
    }
    static Eigen::Vector3d reference_of(const mjModel* model, const mjData* data, int body) noexcept
    {
        return Eigen::Map<const Eigen::Vector3d>(data->subtree_com + 3 * model->body_rootid[body]);
    }
    Eigen::Vector3d reference(const mjModel* model, const mjData* data, Index i) const noexcept
    {
        return reference_of(model, data, contact(i).body);
    }

    void select_joints(const mjModel* model, const std::vector<std::string>& names)
    {
        if (names.empty()) {
            throw InvalidModel("MuJoCo arms", "joint_names", no_arm, "is empty");
        }
        column_of_dof_.assign(static_cast<std::size_t>(model->nv), -1);
        for (std::size_t j = 0; j < names.size(); ++j) {
            const std::string parameter = "joint_names[" + std::to_string(j) + "]";
            const int id = mj_name2id(model, mjOBJ_JOINT, names[j].c_str());
            if (id < 0) {
                throw InvalidModel("MuJoCo arms", parameter, no_arm, "names no joint of the model: '" + names[j] + "'");
            }
            const int type = model->jnt_type[id];
            if (type != mjJNT_HINGE && type != mjJNT_SLIDE) {
                throw InvalidModel("MuJoCo arms", parameter, no_arm,
                                   "'" + names[j] + "' is a " + (type == mjJNT_FREE ? "free" : "ball") +
                                       " joint: only hinge and slide joints (one dof each) can be arm joints");
            }
            const MujocoJoint joint{id, model->jnt_dofadr[id], model->jnt_qposadr[id]};
            Index& column = column_of_dof_[static_cast<std::size_t>(joint.dof)];
            if (column >= 0) {
                throw InvalidModel("MuJoCo arms", parameter, no_arm,
                                   "'" + names[j] + "' is also joint_names[" + std::to_string(column) + "]");
            }
            column = static_cast<Index>(j);
            joints_.push_back(joint);
        }
        // A chosen joint below an unchosen one (a torso, a mobile base) couples to it in M and h:
        // the Q x Q block would be the arms' inertia with that joint locked, and h would miss the
        // forces its motion causes. Refused rather than silently wrong.
        for (std::size_t j = 0; j < names.size(); ++j) {
            for (int dof = model->dof_parentid[joints_[j].dof]; dof >= 0; dof = model->dof_parentid[dof]) {
                require_chosen(model, dof, "joint_names[" + std::to_string(j) + "]", no_arm,
                               "'" + names[j] + "'", "M and h would miss their coupling");
            }
        }
    }

    void select_contacts(const mjModel* model, const std::vector<std::string>& names, MujocoContactFrames frames)
    {
        if (names.empty()) {
            throw InvalidModel("MuJoCo arms", "contact_sites", no_arm, "is empty");
        }
        chain_begin_.push_back(0);
        for (std::size_t i = 0; i < names.size(); ++i) {
            const std::string parameter = "contact_sites[" + std::to_string(i) + "]";
            const Index arm = static_cast<Index>(i);
            MujocoContact contact;
            contact.id = mj_name2id(model, mjOBJ_SITE, names[i].c_str());
            if (contact.id >= 0) {
                contact.body = model->site_bodyid[contact.id];
                contact_descriptions_.push_back("site '" + names[i] + "' on body " +
                                                mujoco_name(model, mjOBJ_BODY, contact.body));
            } else {
                // No site: a body's frame (URDF has no sites; a fixed link kept as a body). Its
                // origin is wherever the body's frame is, often inside the hand (a palm's site sits
                // on the surface): said in the description, refused with sites_only.
                contact.is_site = false;
                contact.id = mj_name2id(model, mjOBJ_BODY, names[i].c_str());
                contact.body = contact.id;
                if (contact.id < 0) {
                    throw InvalidModel("MuJoCo arms", parameter, arm,
                                       (frames == MujocoContactFrames::sites_only ? "names no site of the model: '"
                                                                                  : "names no site or body of the model: '") +
                                           names[i] + "'");
                }
                const std::string sites = mujoco_sites_on_body(model, contact.body);
                if (frames == MujocoContactFrames::sites_only) {
                    throw InvalidModel("MuJoCo arms", parameter, arm,
                                       "names no site of the model: '" + names[i] +
                                           "' is a body, whose own frame is not a point on its surface" + sites +
                                           " (MujocoContactFrames::sites_only refuses bodies)");
                }
                contact_descriptions_.push_back("body '" + names[i] +
                                                "' (no site has that name: the contact frame is the body's own frame, "
                                                "not a point on its surface" + sites + ")");
            }
            for (int body = contact.body; body > 0; body = model->body_parentid[body]) {
                for (int k = 0; k < model->body_dofnum[body]; ++k) {
                    const int dof = model->body_dofadr[body] + k;
                    require_chosen(model, dof, parameter, arm, "'" + names[i] + "'", "J would miss its column");
                    chain_dofs_.push_back(dof);
                }
            }
            chain_begin_.push_back(chain_dofs_.size());
            contacts_.push_back(contact);
        }
    }

    void require_chosen(const mjModel* model, int dof, const std::string& parameter, Index arm, const std::string& what,
                        const std::string& consequence) const
    {
        if (column_of_dof_[static_cast<std::size_t>(dof)] < 0) {
            throw InvalidModel("MuJoCo arms", parameter, arm,
                               what + " moves with joint " + mujoco_name(model, mjOBJ_JOINT, model->dof_jntid[dof]) +
                                   ", which joint_names lacks: " + consequence);
        }
    }

    int nv_ = 0;
    std::vector<MujocoJoint> joints_;
    std::vector<MujocoContact> contacts_;
    std::vector<std::string> contact_descriptions_;  ///< per contact, what its frame is
    std::vector<Index> column_of_dof_;               ///< per dof of the model: its column in q, or -1
    std::vector<int> chain_dofs_;                    ///< per contact, the dofs that move it (all chosen)
    std::vector<std::size_t> chain_begin_;  ///< contact i's chain: chain_dofs_[chain_begin_[i], chain_begin_[i + 1])
};

}  // namespace detail
}  // namespace coopdyn
