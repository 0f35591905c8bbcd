// Bad input to the projected inverse-dynamics controller (include/coopdyn/control/controller.hpp,
// controller_model.hpp): every refused parameter throws InvalidModel naming the parameter and the
// contact; every bad per-tick input is a status with finite torques (never a NaN, never an
// exception); a data or input of another size stops the program with a message.

#include "coopdyn/control/controller.hpp"

#include "arm_systems.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace {

using coopdyn_test::MatrixXd;
using coopdyn_test::Rng;
using coopdyn_test::Vector3d;
using coopdyn_test::VectorXd;
using Index = Eigen::Index;
using coopdyn::Dynamic;
using Parameters = coopdyn::ControllerParameters<double>;
using Model = coopdyn::ControllerModel<double, Dynamic, Dynamic>;
using Data = coopdyn::ControllerData<double, Dynamic, Dynamic>;
using Input = coopdyn::ControllerInput<double, Dynamic, Dynamic>;
using Quaterniond = Eigen::Quaterniond;
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

/// Two opposed palms on free 6-DOF bodies (J = I, Q = 12): a valid controller to spoil.
Parameters valid_parameters()
{
    Parameters p;
    p.joints = 12;
    Eigen::Matrix3d left, right;
    left << 0, 0, 1, 0, -1, 0, 1, 0, 0;
    right << 0, 0, -1, 0, 1, 0, 1, 0, 0;
    coopdyn::ContactPoint<double> a, b;
    a.frame = {Vector3d(-0.15, 0, 0), Quaterniond(left)};
    b.frame = {Vector3d(0.15, 0, 0), Quaterniond(right)};
    a.friction.friction_coefficient = b.friction.friction_coefficient = 0.5;
    a.friction.minimum_normal_force = b.friction.minimum_normal_force = 2.0;
    p.contacts = {a, b};
    p.stiffness = 500.0 * Eigen::Matrix<double, 6, 6>::Identity();
    p.damping = 50.0 * Eigen::Matrix<double, 6, 6>::Identity();
    p.posture_stiffness = VectorXd::Constant(12, 10.0);
    p.posture_damping = VectorXd::Constant(12, 1.0);
    return p;
}

Input valid_input()
{
    Input in(2, 12);
    in.inertia = MatrixXd::Identity(12, 12);
    in.bias = VectorXd::Constant(12, 0.5);
    in.jacobian = MatrixXd::Identity(12, 12);
    in.object.pose = {Vector3d(0, 0, -0.02), Quaterniond::Identity()};
    return in;
}

/// Builds the model and expects InvalidModel naming `parameter` (and `contact`, or no arm).
void expect_refused(const Parameters& p, const std::string& parameter, Index contact = coopdyn::no_arm)
{
    try {
        const Model model(p);
        ADD_FAILURE() << "accepted a bad '" << parameter << "'";
    } catch (const coopdyn::InvalidModel& error) {
        EXPECT_EQ(error.parameter(), parameter) << error.what();
        EXPECT_EQ(error.arm(), contact) << error.what();
        EXPECT_FALSE(error.problem().empty());
    }
}

TEST(ControllerModel, RefusesEachBadParameterByName)
{
    EXPECT_NO_THROW(Model{valid_parameters()});
    {
        Parameters p = valid_parameters();
        p.contacts.pop_back();
        expect_refused(p, "contacts");
    }
    {
        Parameters p = valid_parameters();
        p.joints = 11;  // fewer than 6K
        expect_refused(p, "joints");
    }
    {
        Parameters p = valid_parameters();
        p.contacts[1].friction.friction_coefficient = -0.2;
        expect_refused(p, "friction_coefficient", 1);
    }
    {
        Parameters p = valid_parameters();
        p.contacts[0].friction.patch_half_length_y = 0.0;
        expect_refused(p, "patch_half_length_y", 0);
    }
    {
        Parameters p = valid_parameters();
        p.contacts[1].friction.minimum_normal_force = nan;
        expect_refused(p, "minimum_normal_force", 1);
    }
    {
        Parameters p = valid_parameters();
        p.contacts[0].friction.pyramid_edges = 200;
        expect_refused(p, "pyramid_edges", 0);
    }
    {
        Parameters p = valid_parameters();
        p.contacts[1].frame.position(2) = nan;
        expect_refused(p, "frame.position", 1);
    }
    {
        Parameters p = valid_parameters();
        p.contacts[0].frame.orientation.coeffs() *= 1.1;
        expect_refused(p, "frame.orientation", 0);
    }
    {
        Parameters p = valid_parameters();
        p.stiffness(0, 1) = 50.0;  // not symmetric
        expect_refused(p, "stiffness");
    }
    {
        Parameters p = valid_parameters();
        p.damping(3, 3) = -1.0;
        expect_refused(p, "damping");
    }
    {
        Parameters p = valid_parameters();
        p.posture_stiffness(4) = -1.0;
        expect_refused(p, "posture_stiffness");
    }
    {
        Parameters p = valid_parameters();
        p.posture_damping = VectorXd::Ones(11);
        expect_refused(p, "posture_damping");
    }
    {
        Parameters p = valid_parameters();
        p.objective.moment_weight = -1.0;
        expect_refused(p, "objective.moment_weight");
    }
    {
        Parameters p = valid_parameters();
        p.objective.internal_weight = -1.0;
        expect_refused(p, "objective.internal_weight");
    }
    {
        Parameters p = valid_parameters();
        p.objective.internal_weight = std::numeric_limits<double>::quiet_NaN();
        expect_refused(p, "objective.internal_weight");
    }
    {
        Parameters p = valid_parameters();
        p.objective = coopdyn::SqueezeObjective<double>::least_torque_centred();
        p.objective.torque_weight = 0.0;
        p.objective.squeeze_weight = 0.0;  // the Hessian would be singular
        expect_refused(p, "objective.squeeze_weight");
    }
    {
        Parameters p = valid_parameters();
        p.objective.internal_weight = 0.0;  // the least squeeze's default has neither of the others
        expect_refused(p, "objective.squeeze_weight");
    }
    {
        Parameters p = valid_parameters();
        p.qp.fallback_weight = 0.0;
        expect_refused(p, "qp.fallback_weight");
    }
    {
        Parameters p = valid_parameters();
        p.qp.iteration_limit = -3;
        expect_refused(p, "qp.iteration_limit");
    }
}

/// A frame at `point` on the face of outward normal `face_normal`, z the inward normal, x turned
/// by `angle` about it.
coopdyn::Pose<double> frame_on_face(const Vector3d& point, const Vector3d& face_normal, double angle)
{
    const Vector3d z = -face_normal;
    const Vector3d seed = std::abs(z.x()) < 0.9 ? Vector3d::UnitX() : Vector3d::UnitY();
    const Vector3d x0 = (seed - seed.dot(z) * z).normalized();
    const Vector3d x = Eigen::AngleAxisd(angle, z) * x0;
    Eigen::Matrix3d rotation;
    rotation << x, z.cross(x), z;
    return {point, Quaterniond(rotation)};
}

TEST(ControllerModel, RefusesAContactFacingOutOfTheObjectOrAlongIt)
{
    // Seeded points on the faces of asymmetric boxes, anywhere on a face (near its corners too):
    // the inward normal is accepted, the same frame flipped (pi about x) is refused naming the
    // contact; at the face's centre, a z laid along the face (pi/2 about x) is refused too;
    // check_contact_normals = false accepts both.
    std::mt19937 rng(3301);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const Quaterniond flip(Eigen::AngleAxisd(3.14159265358979323846, Vector3d::UnitX()));
    const Quaterniond lay(Eigen::AngleAxisd(0.5 * 3.14159265358979323846, Vector3d::UnitX()));
    for (int trial = 0; trial < 40; ++trial) {
        const Vector3d half(0.05 + 0.2 * std::abs(unit(rng)), 0.05 + 0.2 * std::abs(unit(rng)), 0.01 + 0.1 * std::abs(unit(rng)));
        const int axis = trial % 3;
        const Index contact = trial % 2;
        const auto slot = static_cast<std::size_t>(contact);
        const double side = contact == 0 ? -1.0 : 1.0;
        const Vector3d normal = side * Vector3d::Unit(axis);
        Vector3d point(unit(rng) * half.x(), unit(rng) * half.y(), unit(rng) * half.z());
        point(axis) = side * half(axis);
        const Vector3d centre = side * half(axis) * Vector3d::Unit(axis);
        for (const bool at_centre : {false, true}) {
            Parameters p = valid_parameters();
            p.contacts[slot].frame = frame_on_face(at_centre ? centre : point, normal, 3.0 * unit(rng));
            p.contacts[1 - slot].frame = frame_on_face(-point, -normal, 0.0);
            EXPECT_NO_THROW(Model{p}) << trial;
            p.contacts[slot].frame.orientation = p.contacts[slot].frame.orientation * (at_centre ? lay : flip);
            expect_refused(p, "frame.orientation", contact);
            p.check_contact_normals = false;
            EXPECT_NO_THROW(Model{p}) << trial;
        }
    }
    // A plate held from below near its rim: z . r is small and negative, and accepted.
    Parameters plate = valid_parameters();
    plate.contacts[0].frame = frame_on_face(Vector3d(-0.4, 0, -0.005), -Vector3d::UnitZ(), 0.0);
    plate.contacts[1].frame = frame_on_face(Vector3d(0.4, 0, -0.005), -Vector3d::UnitZ(), 0.0);
    EXPECT_NO_THROW(Model{plate});
    // The message says which way the normal points and how to fix it.
    Parameters flipped = valid_parameters();
    flipped.contacts[1].frame.orientation = flipped.contacts[1].frame.orientation * Quaterniond(0, 1, 0, 0);
    try {
        const Model model(flipped);
        ADD_FAILURE() << "accepted an outward normal";
    } catch (const coopdyn::InvalidModel& error) {
        EXPECT_NE(std::string(error.what()).find("points out of the object"), std::string::npos) << error.what();
        EXPECT_NE(std::string(error.what()).find("check_contact_normals"), std::string::npos) << error.what();
    }
}

TEST(ControllerModel, NamesJointsWhenEveryPerJointVectorDisagreesWithIt)
{
    Parameters p = valid_parameters();
    p.posture_stiffness = p.posture_damping = VectorXd::Ones(13);  // a 13-joint cell, joints = 12
    expect_refused(p, "joints");
    p.torque_limits = VectorXd::Ones(13);
    expect_refused(p, "joints");
    p.torque_limits = VectorXd::Ones(12);  // the vectors disagree among themselves: the first is named
    expect_refused(p, "posture_stiffness");
    p = valid_parameters();
    p.joint_names = {"a", "b"};
    expect_refused(p, "joint_names");
    p.joint_names.clear();
    for (int j = 0; j < 12; ++j) {
        p.joint_names.push_back("xarm_joint" + std::to_string(j + 1));
    }
    p.torque_limits = VectorXd::Constant(12, 30.0);
    p.torque_limits(3) = 0.0;
    try {
        const Model model(p);
        ADD_FAILURE() << "accepted a zero torque limit";
    } catch (const coopdyn::InvalidModel& error) {
        EXPECT_EQ(error.parameter(), "torque_limits");
        EXPECT_NE(std::string(error.what()).find("joint 3 (xarm_joint4)"), std::string::npos) << error.what();
    }
    p.torque_limits.resize(0);
    p.posture_damping(5) = -1.0;
    try {
        const Model model(p);
        ADD_FAILURE() << "accepted a negative posture gain";
    } catch (const coopdyn::InvalidModel& error) {
        EXPECT_EQ(error.parameter(), "posture_damping");
        EXPECT_NE(std::string(error.what()).find("joint 5 (xarm_joint6)"), std::string::npos) << error.what();
    }
}

TEST(ControllerModel, FixedSizesRefuseAnotherCountOfContactsJointsOrEdges)
{
    const Parameters p = valid_parameters();
    EXPECT_NO_THROW((coopdyn::ControllerModel<double, 2, 12>(p)));
    try {
        coopdyn::ControllerModel<double, 3, 12> model(p);
        ADD_FAILURE() << "accepted 2 contacts for K = 3";
    } catch (const coopdyn::InvalidModel& error) {
        EXPECT_EQ(error.parameter(), "contacts");
    }
    try {
        coopdyn::ControllerModel<double, 2, 14> model(p);
        ADD_FAILURE() << "accepted 12 joints for Q = 14";
    } catch (const coopdyn::InvalidModel& error) {
        EXPECT_EQ(error.parameter(), "joints");
    }
    try {
        coopdyn::ControllerModel<double, 2, 12, 6> model(p);  // the contacts have n = 8
        ADD_FAILURE() << "accepted 8-edge pyramids for Edges = 6";
    } catch (const coopdyn::InvalidModel& error) {
        EXPECT_EQ(error.parameter(), "friction.pyramid_edges");
        EXPECT_EQ(error.arm(), 0);
    }
    // Dynamic edges: each contact its own pyramid.
    Parameters mixed = p;
    mixed.contacts[1].friction.pyramid_edges = 5;
    const coopdyn::ControllerModel<double, 2, 12, Dynamic> model(mixed);
    EXPECT_EQ(model.rows(), 15 + 12);
    EXPECT_EQ(model.row_offset(1), 15);
}

/// One tick with `spoil` applied to a valid input: the status, the named input, finite torques.
void expect_status(const std::function<void(Input&)>& spoil, coopdyn::ControlStatus expected,
                   const std::string& named_input)
{
    const Model model(valid_parameters());
    Data data(model);
    Input in = valid_input();
    coopdyn::controller_tick(model, data, in);
    ASSERT_EQ(data.status, coopdyn::ControlStatus::ok);
    spoil(in);
    const VectorXd tau = coopdyn::controller_tick(model, data, in);
    EXPECT_EQ(data.status, expected) << coopdyn::to_string(data.status);
    EXPECT_NE(std::string(coopdyn::to_string(data.input_problem)).find(named_input), std::string::npos)
        << coopdyn::to_string(data.input_problem);
    EXPECT_TRUE(tau.allFinite());
    EXPECT_TRUE(data.contact_wrenches.allFinite() && data.squeeze.allFinite());
    // The next good tick recovers.
    const VectorXd good = coopdyn::controller_tick(model, data, valid_input());
    EXPECT_EQ(data.status, coopdyn::ControlStatus::ok);
    EXPECT_TRUE(good.allFinite());
}

/// After a tick that computed the control, a bad object measurement is predicted (degraded) and
/// any other bad input holds the grasp (safe_hold, the hold torque); before any such tick there is
/// nothing to hold and the torque is zero (invalid_input). Until the fault-tolerance work every one
/// of these was invalid_input with zero torque, which dropped the object.
TEST(ControllerTick, ANaNInAnyInputIsAStatusWithFiniteTorque)
{
    using coopdyn::ControlStatus;
    const auto hold = ControlStatus::safe_hold;
    const auto degraded = ControlStatus::degraded;
    expect_status([](Input& in) { in.inertia(3, 4) = nan; }, hold, "inertia");
    expect_status([](Input& in) { in.bias(0) = nan; }, hold, "bias");
    expect_status([](Input& in) { in.jacobian(7, 2) = std::numeric_limits<double>::infinity(); }, hold, "jacobian");
    expect_status([](Input& in) { in.jacobian_rate_qdot(1) = nan; }, hold, "jacobian_rate_qdot");
    expect_status([](Input& in) { in.positions(5) = nan; }, hold, "positions");
    expect_status([](Input& in) { in.velocities(5) = nan; }, hold, "velocities");
    expect_status([](Input& in) { in.object.pose.position(1) = nan; }, degraded, "object.pose.position");
    expect_status([](Input& in) { in.object.pose.orientation.coeffs().setZero(); }, degraded, "object.pose.orientation");
    expect_status([](Input& in) { in.object.twist(4) = nan; }, degraded, "object.twist");
    expect_status([](Input& in) { in.object_acceleration(0) = nan; }, degraded, "object_acceleration");
    expect_status([](Input& in) { in.desired_pose.position(2) = nan; }, hold, "desired_pose.position");
    expect_status([](Input& in) { in.desired_pose.orientation.coeffs() *= 2.0; }, hold, "desired_pose.orientation");
    expect_status([](Input& in) { in.desired_twist(0) = nan; }, hold, "desired_twist");
    expect_status([](Input& in) { in.desired_acceleration(0) = nan; }, hold, "desired_acceleration");
    expect_status([](Input& in) { in.posture(11) = nan; }, hold, "posture");

    const Model model(valid_parameters());
    Data data(model);
    Input in = valid_input();
    in.bias(2) = nan;
    EXPECT_TRUE(coopdyn::controller_tick(model, data, in).isZero());
    EXPECT_EQ(data.status, ControlStatus::invalid_input);
}

TEST(ControllerTick, AnInertiaThatIsNotPositiveDefiniteIsAStatus)
{
    expect_status([](Input& in) { in.inertia(6, 6) = -1.0; }, coopdyn::ControlStatus::safe_hold,
                  "inertia (not positive definite)");
    expect_status([](Input& in) { in.inertia.row(3).setZero(), in.inertia.col(3).setZero(); },
                  coopdyn::ControlStatus::safe_hold, "inertia (not positive definite)");
}

TEST(ControllerTick, ASingularArmIsAStatusAndTheTorqueCompensatesTheBias)
{
    const Model model(valid_parameters());
    Data data(model);
    Input in = valid_input();
    in.jacobian.row(8).setZero();  // arm 2 lost a direction
    const VectorXd tau = coopdyn::controller_tick(model, data, in);
    EXPECT_EQ(data.status, coopdyn::ControlStatus::singular);
    EXPECT_NE(data.dynamics.status, coopdyn::ProjectionStatus::ok);  // here: the object cannot move along it
    EXPECT_EQ(tau, in.bias);
}

/// After a failed tick (invalid_input, singular, safe_hold) no output holds the previous tick's value: all
/// are reset to zero, the QP marked as not run; the grasp outputs too when the grasp did not run.
void expect_no_stale_output(const Data& data, const Model& model, bool grasp_ran)
{
    EXPECT_FALSE(coopdyn::control_computed(data.status));
    EXPECT_TRUE(data.motion_torque.isZero(0.0) && data.squeeze_torque.isZero(0.0) && data.posture_torque.isZero(0.0));
    EXPECT_TRUE(data.pose_error.isZero(0.0) && data.twist_error.isZero(0.0) && data.motion_wrench.isZero(0.0));
    EXPECT_TRUE(data.external_wrench.isZero(0.0));
    EXPECT_TRUE(data.contact_wrench_bias.isZero(0.0) && data.contact_wrenches.isZero(0.0));
    EXPECT_TRUE(data.contact_frame_wrenches.isZero(0.0) && data.friction_margins.isZero(0.0) && data.squeeze.isZero(0.0));
    EXPECT_EQ(data.tightest_margin, 0.0);
    EXPECT_EQ(data.tightest_contact, 0);
    EXPECT_FALSE(data.qp_ran);
    EXPECT_EQ(data.qp_status, coopdyn::QpStatus::solved);
    EXPECT_EQ(data.qp_iterations, 0);
    EXPECT_FALSE(data.fallback_used);
    EXPECT_EQ(data.fallback_violation, 0.0);
    EXPECT_TRUE(data.joint_acceleration.isZero(0.0));
    if (grasp_ran) {  // r_i = R_o p_i with R_o = I, in the projection (their one owner)
        for (Index i = 0; i < model.arms(); ++i) {
            EXPECT_EQ(data.dynamics.contact_offsets.col(i), model.contact(i).frame.position);
        }
        EXPECT_FALSE(data.contact_rotations.isZero(0.0));
    } else {
        EXPECT_TRUE(data.contact_rotations.isZero(0.0));
    }
}

TEST(ControllerTick, AFailedTickLeavesNoOutputOfThePreviousTick)
{
    const Model model(valid_parameters());
    Data data(model);
    Input good = valid_input();
    good.object.twist << 0.01, -0.02, 0.03, 0.1, -0.05, 0.02;
    good.object_acceleration << 0.3, 0.1, -0.2, 0.5, 0.0, -0.4;
    const auto expect_good_tick = [&] {
        coopdyn::controller_tick(model, data, good);
        ASSERT_TRUE(coopdyn::control_computed(data.status)) << coopdyn::to_string(data.status);
        // Every output the failed tick must reset is non-zero here.
        ASSERT_TRUE(data.qp_ran);
        ASSERT_FALSE(data.external_wrench.isZero(0.0) || data.contact_wrench_bias.isZero(0.0) || data.pose_error.isZero(0.0) ||
                     data.twist_error.isZero(0.0) || data.motion_wrench.isZero(0.0) || data.joint_acceleration.isZero(0.0) ||
                     data.contact_wrenches.isZero(0.0) || data.friction_margins.isZero(0.0) || data.motion_torque.isZero(0.0) ||
                     data.contact_rotations.isZero(0.0));  // (J = I: no self-motion, tau_n = 0)
    };
    expect_good_tick();
    // A NaN in h after a computed tick: the safe hold (a NaN object acceleration, this test's bad
    // input until the fault-tolerance work, is now replaced and the control computed).
    Input bad = good;
    bad.bias(0) = nan;
    VectorXd tau = coopdyn::controller_tick(model, data, bad);
    EXPECT_EQ(data.status, coopdyn::ControlStatus::safe_hold);
    EXPECT_EQ(data.input_problem, coopdyn::ControllerInputProblem::bias_not_finite);
    EXPECT_TRUE(tau.allFinite() && !tau.isZero(0.0));
    EXPECT_EQ(tau, data.hold_torque);
    expect_no_stale_output(data, model, false);

    expect_good_tick();
    const VectorXd last_wrenches = data.contact_wrenches;
    Input singular = good;
    singular.jacobian.row(8).setZero();
    tau = coopdyn::controller_tick(model, data, singular);
    EXPECT_EQ(data.status, coopdyn::ControlStatus::singular);
    EXPECT_EQ(data.input_problem, coopdyn::ControllerInputProblem::none);
    // h and, after a computed tick, that tick's contact wrenches through this J (until the
    // fault-tolerance work: h alone, which let go of the object).
    const VectorXd held = singular.bias + singular.jacobian.transpose() * last_wrenches;
    EXPECT_LT((tau - held).norm(), 1e-14 * held.norm());
    expect_no_stale_output(data, model, true);
    expect_good_tick();
}

TEST(ControllerTick, EveryRefusedInputHasItsOwnName)
{
    using Problem = coopdyn::ControllerInputProblem;
    std::vector<std::string> names;
    for (int k = 0; k <= static_cast<int>(Problem::inertia_not_positive_definite); ++k) {
        names.emplace_back(coopdyn::to_string(static_cast<Problem>(k)));
        EXPECT_NE(names.back(), "unknown");
    }
    EXPECT_EQ(names.front(), "none");
    EXPECT_EQ(std::string(coopdyn::to_string(Problem::inertia_not_positive_definite)), "inertia (not positive definite)");
    std::sort(names.begin(), names.end());
    EXPECT_EQ(std::unique(names.begin(), names.end()), names.end());
}

TEST(ControllerTickDeathTest, DataOrInputOfAnotherSizeStopsWithAMessage)
{
    const Model model(valid_parameters());
    Data data(model);
    Parameters three = valid_parameters();
    three.joints = 18;
    three.contacts.push_back(three.contacts[0]);
    Eigen::Matrix3d facing_minus_y;  // columns x, y, z: z = -y, the inward normal at y = +0.15
    facing_minus_y << 1, 0, 0, 0, 0, -1, 0, 1, 0;
    three.contacts[2].frame = {Vector3d(0, 0.15, 0), Quaterniond(facing_minus_y)};
    three.posture_stiffness = three.posture_damping = VectorXd::Ones(18);
    const Model other(three);
    Data other_data(other);
    EXPECT_DEATH(coopdyn::controller_tick(model, other_data, valid_input()), "another controller model");
    Input wrong(2, 13);
    EXPECT_DEATH(coopdyn::controller_tick(model, data, wrong), "another controller model");
}

}  // namespace
