// Tests of the projected inverse-dynamics controller (include/coopdyn/control/controller.hpp,
// controller_model.hpp). References the controller was not derived from:
// - the exact constrained motion of the arms and a massless object with the contact wrenches as
//   unknowns (tests/common/arm_systems.hpp, solve_physical_model): the object obeys L(15), the
//   contacts apply the predicted wrenches, the posture torque moves neither;
// - closed forms of the contact QP for two opposed palms holding a weight (edge and facet of the
//   pyramid, torsion);
// - the least violation of a load no squeeze can hold, by hand;
// - named errors for bad parameters, statuses for bad per-tick inputs, no allocation per tick.

#include "../allocation_counter.hpp"

#include "coopdyn/control/controller.hpp"

#include "arm_systems.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace {

using coopdyn_test::JointSpaceSystem;
using coopdyn_test::MatrixXd;
using coopdyn_test::random_joint_space_system;
using coopdyn_test::random_vector;
using coopdyn_test::Rng;
using coopdyn_test::Vector3d;
using coopdyn_test::Vector6d;
using coopdyn_test::VectorXd;
using Index = Eigen::Index;
using coopdyn::Dynamic;
using Parameters = coopdyn::ControllerParameters<double>;
using Model = coopdyn::ControllerModel<double, Dynamic, Dynamic>;
using Data = coopdyn::ControllerData<double, Dynamic, Dynamic>;
using Input = coopdyn::ControllerInput<double, Dynamic, Dynamic>;
using Matrix3d = Eigen::Matrix3d;
using Quaterniond = Eigen::Quaterniond;

coopdyn::ContactFriction<double> palm_friction()
{
    coopdyn::ContactFriction<double> friction;
    friction.friction_coefficient = 0.8;
    friction.torsional_coefficient = 0.03;
    friction.patch_half_length_x = 0.04;
    friction.patch_half_length_y = 0.05;
    friction.minimum_normal_force = 5.0;
    return friction;
}

/// A rotation whose z axis is `normal` (the contact frame of an inward normal), turned about it by
/// `spin`.
Quaterniond frame_with_normal(const Vector3d& normal, double spin)
{
    const Quaterniond align = Quaterniond::FromTwoVectors(Vector3d::UnitZ(), normal);
    return (align * Quaterniond(Eigen::AngleAxisd(spin, Vector3d::UnitZ()))).normalized();
}

/// A controller and an input for a random joint-space system: the object at a random pose, each
/// contact frame's normal pointing at the object's centre, random gains, a random desired motion.
struct Case {
    JointSpaceSystem s;
    Parameters parameters;
    Input input;
};

Case random_case(Index arms, bool torso, Rng& rng)
{
    Case c{random_joint_space_system(arms, torso, rng), Parameters{}, Input(arms, 1)};
    const JointSpaceSystem& s = c.s;
    const Quaterniond object_orientation = coopdyn_test::random_unit_quaternion(rng);
    const Matrix3d R_o = object_orientation.toRotationMatrix();
    Parameters& p = c.parameters;
    p.joints = s.joints;
    for (Index i = 0; i < arms; ++i) {
        coopdyn::ContactPoint<double> contact;
        const Vector3d body_offset = R_o.transpose() * s.r.col(i);
        contact.frame = {body_offset, frame_with_normal(-body_offset.normalized(), coopdyn_test::uniform(rng, 0, 3))};
        contact.friction = palm_friction();
        p.contacts.push_back(contact);
    }
    p.stiffness = coopdyn_test::random_spd(6, rng, 300.0, 0.2);
    p.damping = coopdyn_test::random_spd(6, rng, 40.0, 0.2);
    p.posture_stiffness = random_vector(s.joints, rng, 5.0, 30.0);
    p.posture_damping = random_vector(s.joints, rng, 1.0, 5.0);

    Input& in = c.input;
    in = Input(arms, s.joints);
    in.inertia = s.M;
    in.bias = s.h;
    in.jacobian = s.J;
    in.jacobian_rate_qdot = s.Jdot * s.qdot;
    in.positions = random_vector(s.joints, rng);
    in.velocities = s.qdot;
    in.posture = random_vector(s.joints, rng);
    in.object.pose = {Vector3d(random_vector(rng)), object_orientation};
    const coopdyn_test::LiteralGrasp grasp = coopdyn_test::literal_grasp(s.r, s.J);
    in.object.twist = grasp.Jx * s.qdot;
    in.object_acceleration = coopdyn_test::random_vector6(rng, 2.0);
    in.desired_pose = {Vector3d(in.object.pose.position + 0.05 * random_vector(rng)),
                       (object_orientation * coopdyn_test::axis_angle(0.1, random_vector(rng).normalized())).normalized()};
    in.desired_twist = coopdyn_test::random_vector6(rng, 0.3);
    in.desired_acceleration = coopdyn_test::random_vector6(rng, 1.0);
    return c;
}

double relative(const VectorXd& a, const VectorXd& b) { return (a - b).norm() / std::max(b.norm(), 1e-300); }

using ArmCase = coopdyn_test::ArmCase;
constexpr const auto& arm_cases = coopdyn_test::arm_cases;

TEST(Controller, TorquesGiveTheObjectL15AndTheContactsThePredictedWrenches)
{
    Rng rng(101);
    double worst_object = 0, worst_wrench = 0, worst_acceleration = 0, worst_residual = 0, worst_posture = 0;
    int solved = 0, ticks = 0;
    for (const ArmCase& a : arm_cases) {
        for (int trial = 0; trial < 3; ++trial) {
            const Case c = random_case(a.arms, a.torso, rng);
            const Model model(c.parameters);
            Data data(model);
            const VectorXd tau = coopdyn::controller_tick(model, data, c.input);
            ASSERT_TRUE(data.status == coopdyn::ControlStatus::ok ||
                        data.status == coopdyn::ControlStatus::friction_infeasible)
                << coopdyn::to_string(data.status);
            ++ticks;
            solved += data.status == coopdyn::ControlStatus::ok ? 1 : 0;
            ASSERT_TRUE(tau.allFinite());
            // The world: the arms, the massless object, the external wrench the controller estimated.
            const Vector6d F_x = data.external_wrench;
            const auto world = coopdyn_test::solve_physical_model(c.s, tau, F_x);
            worst_residual = std::max(worst_residual, world.residual);
            const Vector6d lhs = data.dynamics.task_inertia * world.object_acceleration + data.dynamics.task_bias;
            worst_object = std::max(worst_object, relative(lhs, data.motion_wrench + F_x));
            worst_wrench = std::max(worst_wrench, relative(world.applied, data.contact_wrenches));
            // The posture torque moves neither the object nor the contacts: without it, the same
            // object acceleration and contact wrenches, and qdd differs by M^-1 tau_n exactly.
            const auto without = coopdyn_test::solve_physical_model(c.s, tau - data.posture_torque, F_x);
            worst_posture = std::max({worst_posture,
                                      relative(without.object_acceleration, world.object_acceleration),
                                      relative(without.applied, world.applied)});
            worst_acceleration = std::max(worst_acceleration, relative(without.qdd, data.joint_acceleration));
            const VectorXd self_motion = c.s.M.llt().solve(VectorXd(data.posture_torque));
            worst_acceleration = std::max(worst_acceleration, relative(world.qdd - without.qdd, self_motion));
            EXPECT_GT(data.posture_torque.norm(), 1e-3);
        }
    }
    std::printf("[ controller vs exact constrained motion ] K = 2..4, %d of %d ticks friction-feasible: L(15) %.1e, "
                "contact wrenches %.1e, qdd %.1e, posture moves object/contacts by %.1e (solve residual %.1e)\n",
                solved, ticks, worst_object, worst_wrench, worst_acceleration, worst_posture, worst_residual);
    EXPECT_LT(worst_residual, 1e-12);
    EXPECT_LT(worst_object, 1e-9);
    EXPECT_LT(worst_wrench, 1e-9);
    EXPECT_LT(worst_acceleration, 1e-9);
    EXPECT_LT(worst_posture, 1e-9);
    EXPECT_GT(solved, 0);
}

TEST(Controller, FeasibleTicksMeetEveryFrictionRowAndTheirReportedMargins)
{
    Rng rng(102);
    int checked = 0;
    for (const ArmCase& a : arm_cases) {
        for (int trial = 0; trial < 4; ++trial) {
            const Case c = random_case(a.arms, a.torso, rng);
            const Model model(c.parameters);
            Data data(model);
            coopdyn::controller_tick(model, data, c.input);
            if (data.status != coopdyn::ControlStatus::ok) {
                continue;
            }
            ++checked;
            double tightest = 1e300;
            for (Index i = 0; i < a.arms; ++i) {
                // The wrench in the contact frame, rotated by hand.
                const Matrix3d R_ci = c.input.object.pose.orientation.toRotationMatrix() *
                                      model.contact(i).frame.orientation.toRotationMatrix();
                const Vector6d world = data.contact_wrenches.segment<6>(6 * i);
                Vector6d local;
                local << R_ci.transpose() * world.head<3>(), R_ci.transpose() * world.tail<3>();
                EXPECT_LT((local - data.contact_frame_wrenches.col(i)).norm(), 1e-12 * (1 + local.norm()));
                const double margin = coopdyn::friction_margin(model.contact(i).friction, local);
                EXPECT_NEAR(margin, data.friction_margins(i), 1e-9 * (1 + local.norm()));
                EXPECT_GE(margin, -1e-9 * local.norm());
                EXPECT_GE(local(2), palm_friction().minimum_normal_force * (1 - 1e-12));
                tightest = std::min(tightest, margin);
            }
            EXPECT_NEAR(tightest, data.tightest_margin, 1e-9);
            // At the optimum some row binds: the objective would otherwise squeeze less.
            EXPECT_LT(data.tightest_margin, 1e-6);
        }
    }
    EXPECT_GT(checked, 5);
}

}  // namespace
