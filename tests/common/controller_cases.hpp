// Seeded controller set-ups for the tests and benchmarks of include/coopdyn/control/controller.hpp:
// a random joint-space system (arm_systems.hpp) with the object at a random pose, each contact
// frame's normal pointing at the object's centre, random gains and a random desired motion.
#pragma once

#include "coopdyn/control/controller_model.hpp"

#include "arm_systems.hpp"

namespace coopdyn_test {

using ControllerParameters = coopdyn::ControllerParameters<double>;
using DynamicControllerInput = coopdyn::ControllerInput<double, coopdyn::Dynamic, coopdyn::Dynamic>;

/// A palm: mu 0.8, gamma 3 cm, an 8 x 10 cm patch, f_min 5 N, the paper's 8-edge pyramid.
inline coopdyn::ContactFriction<double> palm_friction()
{
    coopdyn::ContactFriction<double> friction;
    friction.friction_coefficient = 0.8;
    friction.torsional_coefficient = 0.03;
    friction.patch_half_length_x = 0.04;
    friction.patch_half_length_y = 0.05;
    friction.minimum_normal_force = 5.0;
    return friction;
}

/// A rotation whose z axis is `normal` (a contact frame with that inward normal), turned about it
/// by `spin`.
inline Eigen::Quaterniond frame_with_normal(const Vector3d& normal, double spin)
{
    const Eigen::Quaterniond align = Eigen::Quaterniond::FromTwoVectors(Vector3d::UnitZ(), normal);
    return (align * Eigen::Quaterniond(Eigen::AngleAxisd(spin, Vector3d::UnitZ()))).normalized();
}

/// The system, the controller's parameters for it, and one tick's input.
struct ControllerCase {
    JointSpaceSystem s;
    ControllerParameters parameters;
    DynamicControllerInput input{2, 1};
};

/// The controller and input for a given system (see the file comment).
inline ControllerCase make_controller_case(const JointSpaceSystem& s, Rng& rng)
{
    ControllerCase c{s, ControllerParameters{}, DynamicControllerInput(s.arms, s.joints)};
    const Eigen::Quaterniond object_orientation = random_unit_quaternion(rng);
    const Matrix3d R_o = object_orientation.toRotationMatrix();
    ControllerParameters& p = c.parameters;
    p.joints = s.joints;
    for (Index i = 0; i < s.arms; ++i) {
        coopdyn::ContactPoint<double> contact;
        const Vector3d body_offset = R_o.transpose() * s.r.col(i);
        contact.frame = {body_offset, frame_with_normal(-body_offset.normalized(), uniform(rng, 0, 3))};
        contact.friction = palm_friction();
        p.contacts.push_back(contact);
    }
    p.stiffness = random_spd(6, rng, 300.0, 0.2);
    p.damping = random_spd(6, rng, 40.0, 0.2);
    p.posture_stiffness = random_vector(s.joints, rng, 5.0, 30.0);
    p.posture_damping = random_vector(s.joints, rng, 1.0, 5.0);

    DynamicControllerInput& in = c.input;
    in.inertia = s.M;
    in.bias = s.h;
    in.jacobian = s.J;
    in.jacobian_rate_qdot = s.Jdot * s.qdot;
    in.positions = random_vector(s.joints, rng);
    in.velocities = s.qdot;
    in.posture = random_vector(s.joints, rng);
    in.object.pose = {Vector3d(random_vector(rng)), object_orientation};
    in.object.twist = literal_grasp(s.r, s.J).Jx * s.qdot;
    in.object_acceleration = random_vector6(rng, 2.0);
    in.desired_pose = {Vector3d(in.object.pose.position + 0.05 * random_vector(rng)),
                       (object_orientation * axis_angle(0.1, random_vector(rng).normalized())).normalized()};
    in.desired_twist = random_vector6(rng, 0.3);
    in.desired_acceleration = random_vector6(rng, 1.0);
    return c;
}

inline ControllerCase random_controller_case(Index arms, bool torso, Rng& rng)
{
    return make_controller_case(random_joint_space_system(arms, torso, rng), rng);
}

}  // namespace coopdyn_test
