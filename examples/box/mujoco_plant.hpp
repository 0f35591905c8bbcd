// The MuJoCo plant of the dual-arm box (docs/dual-arm-box.md, "The MuJoCo plant"): MuJoCo 2.2.2
// is the physical world, the box is held only by friction between the palms and the box (the
// MJCF's palm-box <pair>s), and the controller runs between mj_step1 and mj_step2:
//
//     begin_tick():  mj_step1 (positions, velocities, contacts found), then the arms' M, h, J,
//                    Jdot qdot and the box's measured pose, twist and last acceleration
//     end_tick(tau, wrench):  joint torques and the push on the box, mj_step2, then the contact
//                    forces MuJoCo applied during that step, as each palm's wrench on the box
//
// Each plant owns a copy of the model, so adding mass to its box touches no other plant.
//
// This header belongs to the examples (it depends on MuJoCo), not to the library.
#pragma once

#include "mujoco_arms.hpp"

#include <Eigen/Geometry>

#include <array>
#include <vector>

namespace box_example {

class MujocoPlant {
public:
    MujocoPlant(const DualArmBoxModel& world, const PlantFriction& friction)
        : world_(world),
          model_(mj_copyModel(nullptr, world.get()))
    {
        if (!model_) {
            throw std::runtime_error("MuJoCo cannot copy the model");
        }
        int pairs_found = 0;
        for (int pair = 0; pair < model_->npair; ++pair) {
            const int first = model_->pair_geom1[pair];
            const int second = model_->pair_geom2[pair];
            for (int palm = 0; palm < palms; ++palm) {
                if (first == world.palm_geom(palm) && second == world.box_geom()) {
                    mjtNum* coefficients = model_->pair_friction + 5 * pair;
                    coefficients[0] = coefficients[1] = friction.sliding;
                    coefficients[2] = friction.torsional;
                    ++pairs_found;
                }
            }
        }
        if (pairs_found != palms) {
            throw std::runtime_error("the MJCF needs one <pair geom1=\"<palm>_palm_geom\" geom2=\"box_geom\"> per palm");
        }
        data_.reset(mj_makeData(model_.get()));
        if (!data_) {
            throw std::runtime_error("MuJoCo cannot allocate its mjData");
        }
        mj_resetDataKeyframe(model_.get(), data_.get(), world.hold_key());
        mj_forward(model_.get(), data_.get());
        box_mass_ = model_->body_mass[world.box_body()];
    }

    const mjModel* model() const noexcept { return model_.get(); }
    const mjData* data() const noexcept { return data_.get(); }
    double time() const noexcept { return data_->time; }

    /// mj_step1, then what the controller reads: the arms' terms and the box's state.
    void begin_tick() noexcept
    {
        mj_step1(model_.get(), data_.get());
        read_arm_terms(world_, model_.get(), data_.get(), terms_);
        const mjtNum* pose = data_->qpos + joints;
        box_position_ = Eigen::Vector3d(pose[0], pose[1], pose[2]);
        box_orientation_ = Eigen::Quaterniond(pose[3], pose[4], pose[5], pose[6]).normalized();
        const Eigen::Matrix3d rotation = box_orientation_.toRotationMatrix();
        const mjtNum* velocity = data_->qvel + joints;
        // A free joint's linear velocity is in {w}, its angular velocity in the body frame.
        box_twist_ << velocity[0], velocity[1], velocity[2],
            rotation * Eigen::Vector3d(velocity[3], velocity[4], velocity[5]);
    }

    const ArmTerms& arm_terms() const noexcept { return terms_; }
    const Eigen::Vector3d& box_position() const noexcept { return box_position_; }
    const Eigen::Quaterniond& box_orientation() const noexcept { return box_orientation_; }
    /// [v; w] of the box's centre, {w}.
    const Vector6d& box_twist() const noexcept { return box_twist_; }
    /// [a; alpha] of the box's centre in the last step, {w} (what an accelerometer on the box reads,
    /// one tick late).
    const Vector6d& box_acceleration() const noexcept { return box_acceleration_; }
    JointVector joint_positions() const noexcept { return Eigen::Map<const JointVector>(data_->qpos); }
    JointVector joint_velocities() const noexcept { return Eigen::Map<const JointVector>(data_->qvel); }

    /// The joint torques and the wrench [F; T] on the box's centre ({w}) for this step, mj_step2,
    /// then the palms' measured wrenches on the box.
    void end_tick(const JointVector& tau, const Vector6d& box_wrench) noexcept
    {
        for (int j = 0; j < joints; ++j) {
            data_->qfrc_applied[j] = tau(j);
        }
        coopdyn::mujoco_set_applied_wrench(model_.get(), data_.get(), world_.box_body(), box_wrench);
        mj_step2(model_.get(), data_.get());
        const Eigen::Matrix3d rotation = box_orientation_.toRotationMatrix();
        const mjtNum* acceleration = data_->qacc + joints;
        box_acceleration_ << acceleration[0], acceleration[1], acceleration[2],
            rotation * Eigen::Vector3d(acceleration[3], acceleration[4], acceleration[5]);
        measure_contacts();
    }

    /// Palm i's wrench [f; t] on the box about its contact point, {w}, summed over MuJoCo's
    /// contact points between that palm and the box in the last step.
    const Vector6d& measured_contact_wrench(int palm) const noexcept
    {
        return measured_[static_cast<std::size_t>(palm)];
    }
    /// How many contact points each palm had with the box in the last step.
    int contact_points(int palm) const noexcept { return contact_points_[static_cast<std::size_t>(palm)]; }

    double box_mass() const noexcept { return box_mass_; }
    /// Puts mass on the box (docs/dual-arm-box.md, "Add mass"): its mass and rotational inertia grow
    /// in proportion. mj_setConst recomputes the model's derived constants; it overwrites the mjData
    /// it is given, so it gets a scratch one.
    void set_box_mass(double mass)
    {
        const int body = world_.box_body();
        const double ratio = mass / model_->body_mass[body];
        model_->body_mass[body] = mass;
        for (int k = 0; k < 3; ++k) {
            model_->body_inertia[3 * body + k] *= ratio;
        }
        DataPointer scratch(mj_makeData(model_.get()));
        mj_setConst(model_.get(), scratch.get());
        box_mass_ = mass;
    }

private:
    /// The library's measurement (MujocoArms::read_contact_wrenches: each palm's MuJoCo contacts
    /// with the box, mj_contactForce turned to {w}, the moments about the palm's contact site).
    void measure_contacts() noexcept
    {
        world_.arms().read_contact_wrenches(model_.get(), data_.get(), world_.box_body(), contacts_);
        for (int palm = 0; palm < palms; ++palm) {
            const auto index = static_cast<std::size_t>(palm);
            measured_[index] = contacts_.world.col(palm);
            contact_points_[index] = contacts_.points(palm);
        }
    }

    const DualArmBoxModel& world_;
    ModelPointer model_;
    DataPointer data_;
    ArmTerms terms_;
    double box_mass_ = 0.0;
    Eigen::Vector3d box_position_ = Eigen::Vector3d::Zero();
    Eigen::Quaterniond box_orientation_ = Eigen::Quaterniond::Identity();
    Vector6d box_twist_ = Vector6d::Zero();
    Vector6d box_acceleration_ = Vector6d::Zero();
    coopdyn::MujocoContactWrenches<palms> contacts_;
    std::array<Vector6d, palms> measured_{};
    std::array<int, palms> contact_points_{};
};

}  // namespace box_example
