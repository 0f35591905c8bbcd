// A scene's MuJoCo world (docs/scenes.md): the model loaded from the scene's MJCF, the library's
// MuJoCo adapter for its Q joints and K contacts at dynamic sizes
// (coopdyn::MujocoArms<Eigen::Dynamic, Eigen::Dynamic>), the object's free body and each palm's
// contact geom (found through the MJCF's palm-object <pair>s), the start state (a given posture,
// or the IK placing every contact frame at its target on the object) and, from that state, the
// controller's contact points and model (coopdyn::ControllerModel<double>, dynamic sizes).
//
// This header belongs to the examples (it depends on MuJoCo), not to the library.
#pragma once

#include "scene.hpp"

#include <coopdyn/adapters/mujoco.hpp>
#include <coopdyn/control.hpp>

#include <mujoco/mujoco.h>

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace scenes {

using ModelPointer = coopdyn::MujocoModelPointer;  // the adapter's owners (adapters/mujoco_model.hpp)
using DataPointer = coopdyn::MujocoDataPointer;
using Arms = coopdyn::MujocoArms<Eigen::Dynamic, Eigen::Dynamic>;

/// A scene's set-up problem (a name the model lacks, an IK that does not converge, ...).
class SceneError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// The controller's own settings (not the scene's): its friction model and gains. The defaults are
/// the dual-arm box's (examples/box/box_scenario.hpp, ControllerSettings), except the minimum normal
/// force, which is the smallest that the box's scenarios hold a 0.7-0.8 kg object with (the box
/// uses 60 N for its pushes and added mass).
struct ControllerSettings {
    double friction = 0.2;              ///< mu of the controller's model (the MJCF's is 0.5)
    double torsional_friction = 0.002;  ///< gamma (m)
    double patch_half_size = 0.04;      ///< delta_x = delta_y (m): the 8 x 8 cm palms
    double minimum_normal_force = 30.0; ///< f_min (N)
    double translational_stiffness = 100.0;
    double rotational_stiffness = 30.0;
    double translational_damping = 60.0;
    double rotational_damping = 4.0;
    double posture_stiffness = 20.0;
    double posture_damping = 4.0;
};

/// How the start state was found.
struct StartReport {
    bool inverse_kinematics = false;  ///< the IK placed the hands (else: given positions)
    coopdyn::InverseKinematicsResult ik{};
    double contact_position_error = 0.0;     ///< max_i |p_i - target_i| (m) after the start
    double contact_orientation_error = 0.0;  ///< max_i angle(R_i, target_i) (rad)
};

class SceneWorld {
public:
    explicit SceneWorld(const Scene& scene) : scene_(scene), model_(load(scene)), arms_(make_arms(model_.get(), scene))
    {
        data_.reset(mj_makeData(model_.get()));
        if (!data_) {
            throw SceneError(scene.source + ": MuJoCo cannot allocate its mjData");
        }
        object_body_ = coopdyn::detail::mujoco_body_id(model_.get(), scene.object_body);
        const int joint = model_->body_jntadr[object_body_];
        if (model_->body_jntnum[object_body_] != 1 || model_->jnt_type[joint] != mjJNT_FREE) {
            throw SceneError(scene.source + ": object.body '" + scene.object_body + "' must have one free joint");
        }
        object_qpos_ = model_->jnt_qposadr[joint];
        object_dof_ = model_->jnt_dofadr[joint];
        find_palm_geoms();
    }

    const Scene& scene() const noexcept { return scene_; }
    mjModel* model() noexcept { return model_.get(); }
    const mjModel* model() const noexcept { return model_.get(); }
    mjData* data() noexcept { return data_.get(); }
    const mjData* data() const noexcept { return data_.get(); }
    const Arms& arms() const noexcept { return arms_; }
    int object_body() const noexcept { return object_body_; }
    int object_dof() const noexcept { return object_dof_; }
    /// Contact i's palm geom and the object's geom of their <pair>.
    int palm_geom(Eigen::Index i) const noexcept { return palm_geoms_[static_cast<std::size_t>(i)]; }
    int object_geom(Eigen::Index i) const noexcept { return object_geoms_[static_cast<std::size_t>(i)]; }
    /// q at the start (after start()), and q_n: the scene's posture or the start posture.
    const Eigen::VectorXd& start_positions() const noexcept { return start_positions_; }
    Eigen::VectorXd posture() const { return scene_.posture ? *scene_.posture : start_positions_; }

    /// Resets the state (qpos0, zero velocities) and puts the world at the scene's start: the
    /// object at its pose and the arms at the given posture, or moved by the IK until each
    /// contact frame is at its target. Ends with mj_forward. Throws SceneError when the IK fails.
    StartReport start(const coopdyn::InverseKinematicsOptions& options = {})
    {
        mjModel* model = model_.get();
        mjData* data = data_.get();
        mj_resetData(model, data);
        const coopdyn::Pose<double>& object = scene_.object_pose;
        for (int k = 0; k < 3; ++k) {
            data->qpos[object_qpos_ + k] = object.position(k);
        }
        const Eigen::Quaterniond orientation = object.orientation.normalized();
        data->qpos[object_qpos_ + 3] = orientation.w();
        data->qpos[object_qpos_ + 4] = orientation.x();
        data->qpos[object_qpos_ + 5] = orientation.y();
        data->qpos[object_qpos_ + 6] = orientation.z();
        StartReport report;
        std::vector<coopdyn::Pose<double>> targets;
        if (scene_.start.positions) {
            set_positions(*scene_.start.positions);
        } else {
            report.inverse_kinematics = true;
            if (scene_.start.seed) {
                set_positions(*scene_.start.seed);
            }
            for (std::size_t i = 0; i < scene_.start.contacts.size(); ++i) {
                const coopdyn::Pose<double>& contact = scene_.start.contacts[i];
                const std::string problem =
                    scene_.check_contact_normals ? coopdyn::contact_normal_problem(contact) : std::string();
                if (!problem.empty()) {  // a Scene built in code, not read (the reader refuses it too)
                    throw SceneError(scene_.source + ": start.contacts[" + std::to_string(i) + "].orientation: " + problem);
                }
                targets.push_back({object.position + orientation * contact.position,
                                   (orientation * contact.orientation.normalized()).normalized()});
            }
            report.ik = arms_.place_hands(model, data, targets, options);
            if (!report.ik.converged()) {
                throw SceneError(scene_.source + ": the IK did not place the hands (" +
                                 coopdyn::numerics::to_string(report.ik.status) + ", residual " +
                                 std::to_string(report.ik.residual) + " after " + std::to_string(report.ik.iterations) +
                                 " steps): move start.seed or the object");
            }
        }
        mj_forward(model, data);
        start_positions_.resize(arms_.joints());
        arms_.read_positions(data, start_positions_);
        for (std::size_t i = 0; i < targets.size(); ++i) {
            const coopdyn::Pose<double> pose = arms_.contact_pose(data, static_cast<Eigen::Index>(i));
            report.contact_position_error =
                std::max(report.contact_position_error, (pose.position - targets[i].position).norm());
            report.contact_orientation_error = std::max(report.contact_orientation_error,
                                                        pose.orientation.angularDistance(targets[i].orientation));
        }
        return report;
    }

    /// The controller's parameters at the current state (after start()): each contact frame in the
    /// object as the adapter measures it (contact_points), the friction model and gains.
    coopdyn::ControllerParameters<double> controller_parameters(const ControllerSettings& settings) const
    {
        coopdyn::ContactFriction<double> friction;
        friction.friction_coefficient = settings.friction;
        friction.torsional_coefficient = settings.torsional_friction;
        friction.patch_half_length_x = settings.patch_half_size;
        friction.patch_half_length_y = settings.patch_half_size;
        friction.minimum_normal_force = settings.minimum_normal_force;
        coopdyn::ControllerParameters<double> parameters;
        parameters.joints = arms_.joints();
        parameters.joint_names = scene_.joint_names;
        parameters.check_contact_normals = scene_.check_contact_normals;
        parameters.contacts = arms_.contact_points(model_.get(), data_.get(), scene_.object_body, friction);
        parameters.stiffness.diagonal() << Eigen::Vector3d::Constant(settings.translational_stiffness),
            Eigen::Vector3d::Constant(settings.rotational_stiffness);
        parameters.damping.diagonal() << Eigen::Vector3d::Constant(settings.translational_damping),
            Eigen::Vector3d::Constant(settings.rotational_damping);
        parameters.posture_stiffness = Eigen::VectorXd::Constant(arms_.joints(), settings.posture_stiffness);
        parameters.posture_damping = Eigen::VectorXd::Constant(arms_.joints(), settings.posture_damping);
        return parameters;
    }

private:
    static ModelPointer load(const Scene& scene)
    {
        char error[1000] = "";
        ModelPointer model(mj_loadXML(scene.model_path.string().c_str(), nullptr, error, sizeof error));
        if (!model) {
            throw SceneError(scene.source + ": model: MuJoCo cannot load '" + scene.model_path.string() + "': " + error);
        }
        return model;
    }

    static Arms make_arms(const mjModel* model, const Scene& scene)
    {
        try {
            return Arms(model, scene.joint_names, scene.contact_sites);
        } catch (const coopdyn::InvalidModel& error) {
            throw SceneError(scene.source + ": " + error.what());
        }
    }

    void set_positions(const Eigen::VectorXd& q) noexcept
    {
        for (Eigen::Index j = 0; j < arms_.joints(); ++j) {
            data_->qpos[arms_.qpos_address(j)] = q(j);
        }
    }

    /// Each contact's palm geom: the geom of a <pair> that moves with the contact's body while the
    /// other geom belongs to the object.
    void find_palm_geoms()
    {
        const mjModel* model = model_.get();
        for (Eigen::Index i = 0; i < arms_.arms(); ++i) {
            const int body = arms_.contact(i).body;
            int palm = -1;
            int object = -1;
            for (int pair = 0; pair < model->npair; ++pair) {
                const int first = model->pair_geom1[pair];
                const int second = model->pair_geom2[pair];
                if (model->geom_bodyid[first] == body && model->geom_bodyid[second] == object_body_) {
                    palm = first;
                    object = second;
                } else if (model->geom_bodyid[second] == body && model->geom_bodyid[first] == object_body_) {
                    palm = second;
                    object = first;
                }
            }
            if (palm < 0) {
                throw SceneError(scene_.source + ": contact_sites[" + std::to_string(i) + "] '" +
                                 scene_.contact_sites[static_cast<std::size_t>(i)] +
                                 "': the MJCF has no <pair> of a geom on its body and one of the object");
            }
            palm_geoms_.push_back(palm);
            object_geoms_.push_back(object);
        }
    }

    Scene scene_;
    ModelPointer model_;
    Arms arms_;
    DataPointer data_;
    int object_body_ = -1;
    int object_qpos_ = -1;
    int object_dof_ = -1;
    std::vector<int> palm_geoms_;
    std::vector<int> object_geoms_;
    Eigen::VectorXd start_positions_;
};

}  // namespace scenes
