// The controller under faults (include/coopdyn/control/controller_faults.hpp, controller.hpp;
// docs/control.md, "Faults: dropout, safe hold, slip, torque limits"). References the fault
// handling was not derived from:
// - the undisturbed run of the same hold (the true measurement every tick): a dropout's torques
//   against it, and the predicted pose against the true trajectory written in closed form
//   (p_0 + v t + a t^2 / 2, an axis-angle rotation);
// - the exact constrained motion of the arms and the object with the contact wrenches as unknowns
//   (tests/common/arm_systems.hpp, solve_physical_model): the safe-hold torque is h + J^T w with w
//   the wrenches the world applied under the last computed torque, and under it the arms and the
//   object stay at rest with the same contact wrenches;
// - contacts moved and turned by hand by known amounts (slip), hand-clamped torques (limits);
// - the allocation counter in each new mode; named errors for each new parameter.
// One controller size only, <double, Dynamic, Dynamic> (each instantiation costs compile time).

#include "../allocation_counter.hpp"

#include "coopdyn/control/controller.hpp"

#include "controller_cases.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace {

using coopdyn_test::MatrixXd;
using coopdyn_test::Rng;
using coopdyn_test::Vector3d;
using coopdyn_test::Vector6d;
using coopdyn_test::VectorXd;
using Index = Eigen::Index;
using coopdyn::ControlStatus;
using coopdyn::Dynamic;
using coopdyn::ReplacedInput;
using Parameters = coopdyn::ControllerParameters<double>;
using Model = coopdyn::ControllerModel<double, Dynamic, Dynamic>;
using Data = coopdyn::ControllerData<double, Dynamic, Dynamic>;
using Input = coopdyn::ControllerInput<double, Dynamic, Dynamic>;
using Quaterniond = Eigen::Quaterniond;
using Case = coopdyn_test::ControllerCase;
constexpr double nan = std::numeric_limits<double>::quiet_NaN();
constexpr double tick_period = 1e-3;

/// A two-arm case (Q = 14) whose first tick is ok, with the given prediction limit.
Case hold_case(unsigned seed, double prediction_limit)
{
    Rng rng(seed);
    for (;;) {
        Case c = coopdyn_test::random_controller_case(2, false, rng);
        c.parameters.faults.tick_period = tick_period;
        c.parameters.faults.prediction_limit = prediction_limit;
        const Model model(c.parameters);
        Data data(model);
        coopdyn::controller_tick(model, data, c.input);
        if (data.status == ControlStatus::ok) {
            return c;
        }
    }
}

/// The true object motion of the hold: the case's twist plus a constant linear acceleration a, a
/// constant angular velocity: p(t) = p_0 + v_0 t + a t^2 / 2, q(t) = exp(omega t) q_0 (axis-angle,
/// not the library's quaternion_exp), twist [v_0 + a t; omega], acceleration [a; 0]. M, h, J are
/// held (a short hold). With the contacts' poses filled from the object's pose and each contact
/// frame as the grasp really is (the model's frame off by a small constant offset, so that a
/// prediction from the model's frames would be wrong and only the recorded offsets are right).
struct Hold {
    Case c;
    Vector3d linear_acceleration{0.3, -0.2, 0.25};
    std::vector<coopdyn::Pose<double>> true_frames;

    coopdyn::RigidBodyState<double> truth(double t) const
    {
        coopdyn::RigidBodyState<double> state;
        const Vector3d v0 = c.input.object.twist.head<3>();
        const Vector3d omega = c.input.object.twist.tail<3>();
        state.pose.position = c.input.object.pose.position + v0 * t + 0.5 * linear_acceleration * t * t;
        state.pose.orientation = coopdyn_test::rotation_exponential(omega * t) * c.input.object.pose.orientation;
        state.twist << v0 + linear_acceleration * t, omega;
        return state;
    }

    Input input(int tick, bool with_contacts) const
    {
        Input in = c.input;
        in.object = truth(tick * tick_period);
        in.object_acceleration << linear_acceleration, Vector3d::Zero();
        in.contact_poses_filled = with_contacts;
        for (Index i = 0; i < 2; ++i) {
            const auto& frame = true_frames[static_cast<std::size_t>(i)];
            in.contact_positions.col(i) = in.object.pose.transform_point(frame.position);
            in.contact_orientations.col(i) = (in.object.pose.orientation * frame.orientation).coeffs();
        }
        return in;
    }
};

Hold make_hold(unsigned seed, double prediction_limit)
{
    Hold hold;
    hold.c = hold_case(seed, prediction_limit);
    for (const auto& contact : hold.c.parameters.contacts) {
        coopdyn::Pose<double> frame = contact.frame;
        frame.position += Vector3d(0.002, -0.001, 0.0015);
        frame.orientation = (frame.orientation * coopdyn_test::axis_angle(0.01, Vector3d::UnitX())).normalized();
        hold.true_frames.push_back(frame);
    }
    return hold;
}

double relative(const VectorXd& a, const VectorXd& b) { return (a - b).norm() / b.norm(); }

TEST(Dropout, OneTenAndHundredTicksInAHoldAreDegradedThenOk)
{
    const Hold hold = make_hold(2301, 0.15);
    const Model model(hold.c.parameters);
    const int ticks = 260, start = 100;
    for (const bool with_contacts : {false, true}) {
        Data undisturbed_data(model);
        std::vector<VectorXd> undisturbed;
        for (int k = 0; k < ticks; ++k) {
            undisturbed.push_back(coopdyn::controller_tick(model, undisturbed_data, hold.input(k, with_contacts)));
            ASSERT_EQ(undisturbed_data.status, ControlStatus::ok) << k;
        }
        for (const int length : {1, 10, 100}) {
            Data data(model);
            double worst = 0, worst_position = 0, worst_angle = 0;
            for (int k = 0; k < ticks; ++k) {
                Input in = hold.input(k, with_contacts);
                const bool dropped = k >= start && k < start + length;
                if (dropped) {
                    in.object.pose.position(k % 3) = nan;  // a motion-capture dropout
                }
                const VectorXd tau = coopdyn::controller_tick(model, data, in);
                ASSERT_TRUE(tau.allFinite()) << k;
                ASSERT_EQ(data.status, dropped ? ControlStatus::degraded : ControlStatus::ok) << k << ", " << length;
                if (!dropped) {
                    EXPECT_EQ(data.replaced_input, ReplacedInput::none);
                    continue;
                }
                EXPECT_EQ(data.replaced_input, with_contacts ? ReplacedInput::object_state_from_contacts
                                                             : ReplacedInput::object_state_from_twist);
                EXPECT_EQ(data.input_problem, coopdyn::ControllerInputProblem::object_position_not_finite);
                EXPECT_NEAR(data.prediction_age, (k - start + 1) * tick_period, 1e-15);
                worst = std::max(worst, relative(tau, undisturbed[static_cast<std::size_t>(k)]));
                // The pose against the true trajectory: from the contacts exact (the grasp is rigid);
                // from the last measurement's twist off by a t^2 / 2 exactly (t since it), the
                // rotation exact (constant omega).
                const auto truth = hold.truth(k * tick_period);
                const double t = data.prediction_age;
                const double expected_position_error = with_contacts ? 0.0 : 0.5 * hold.linear_acceleration.norm() * t * t;
                worst_position = std::max(worst_position, std::abs((data.object.pose.position - truth.pose.position).norm() -
                                                                   expected_position_error));
                worst_angle = std::max(worst_angle, data.object.pose.orientation.angularDistance(truth.pose.orientation));
            }
            std::printf("%s, dropout of %3d ticks: torque off the undisturbed by %.3g (relative, worst), pose "
                        "off the closed form by %.2g m, %.2g rad\n",
                        with_contacts ? "contacts" : "twist   ", length, worst, worst_position, worst_angle);
            EXPECT_LT(worst_position, 1e-12);
            EXPECT_LT(worst_angle, 1e-9);
            if (length <= 10) {
                EXPECT_LT(worst, 0.05);
            }
        }
    }
}

TEST(Dropout, AStaleFlagOrANaNAccelerationIsReplacedToo)
{
    const Hold hold = make_hold(2302, 0.1);
    const Model model(hold.c.parameters);
    Data data(model);
    coopdyn::controller_tick(model, data, hold.input(0, false));
    Input stale = hold.input(1, false);
    stale.object_stale = true;
    coopdyn::controller_tick(model, data, stale);
    EXPECT_EQ(data.status, ControlStatus::degraded);
    EXPECT_EQ(data.input_problem, coopdyn::ControllerInputProblem::object_stale);
    EXPECT_EQ(data.replaced_input, ReplacedInput::object_state_from_twist);
    Input acceleration = hold.input(2, false);
    acceleration.object_acceleration(4) = nan;
    coopdyn::controller_tick(model, data, acceleration);
    EXPECT_EQ(data.status, ControlStatus::degraded);
    EXPECT_EQ(data.replaced_input, ReplacedInput::object_acceleration);
    EXPECT_EQ(data.object_acceleration, hold.input(0, false).object_acceleration);  // the last valid one
    EXPECT_EQ(data.object.pose.position, acceleration.object.pose.position);  // the measured pose
    EXPECT_EQ(data.prediction_age, 0.0);
}

/// The system at rest (qdot = 0), so that h + J^T w holds the arms and the object still.
Case rest_case(unsigned seed)
{
    Case c = hold_case(seed, 0.01);
    c.s.qdot.setZero();
    c.input.velocities.setZero();
    c.input.jacobian_rate_qdot.setZero();
    c.input.object.twist.setZero();
    c.input.object_acceleration.setZero();
    return c;
}

TEST(SafeHold, ADropoutLongerThanTheLimitHoldsWithHPlusJTransposeW)
{
    const Case c = rest_case(2303);
    const Model model(c.parameters);  // prediction_limit 10 ms = 10 ticks
    Data data(model);
    VectorXd last_tau;
    Vector6d last_external = Vector6d::Zero();
    for (int k = 0; k < 40; ++k) {
        Input in = c.input;
        const bool dropped = k >= 5 && k < 30;
        if (dropped) {
            in.object.pose.orientation.coeffs().setConstant(nan);
        }
        const VectorXd tau = coopdyn::controller_tick(model, data, in);
        ASSERT_TRUE(tau.allFinite());
        const ControlStatus expected =
            !dropped ? ControlStatus::ok : k - 5 < 10 ? ControlStatus::degraded : ControlStatus::safe_hold;
        ASSERT_EQ(data.status, expected) << k;
        if (expected != ControlStatus::safe_hold) {
            last_tau = tau;
            last_external = data.external_wrench;
            continue;
        }
        // The reference: the wrenches the world applied under the last computed torque.
        const auto world = coopdyn_test::solve_physical_model(c.s, last_tau, last_external);
        const VectorXd reference = c.s.h + c.s.J.transpose() * world.applied;
        EXPECT_GT(tau.norm(), 1.0);
        EXPECT_LT(relative(tau, reference), 1e-12) << k;
        // Under it the arms and the object stay at rest and the contacts keep those wrenches.
        const auto held = coopdyn_test::solve_physical_model(c.s, tau, last_external);
        EXPECT_LT(held.qdd.norm(), 1e-9 * tau.norm());
        EXPECT_LT(held.object_acceleration.norm(), 1e-9 * tau.norm());
        EXPECT_LT(relative(held.applied, world.applied), 1e-10);
        EXPECT_EQ(data.input_problem, coopdyn::ControllerInputProblem::object_orientation_not_unit);
        EXPECT_FALSE(coopdyn::control_computed(data.status));
    }
    // A singular J after a computed tick: this tick's h and J with the last computed tick's wrenches.
    {
        Data singular_data(model);
        coopdyn::controller_tick(model, singular_data, c.input);
        const VectorXd computed = singular_data.torque;
        const Vector6d external = singular_data.external_wrench;
        Input singular = c.input;
        singular.jacobian.row(8).setZero();
        const VectorXd tau = coopdyn::controller_tick(model, singular_data, singular);
        EXPECT_EQ(singular_data.status, ControlStatus::singular);
        const auto world = coopdyn_test::solve_physical_model(c.s, computed, external);
        const VectorXd reference = singular.bias + singular.jacobian.transpose() * world.applied;
        EXPECT_LT(relative(tau, reference), 1e-12);
    }
    // A NaN in M after a computed tick: the same safe hold, from the last computed tick.
    const VectorXd hold_torque = data.hold_torque;
    Input bad = c.input;
    bad.inertia(2, 3) = nan;
    EXPECT_EQ(coopdyn::controller_tick(model, data, bad), hold_torque);
    EXPECT_EQ(data.status, ControlStatus::safe_hold);
    EXPECT_EQ(data.input_problem, coopdyn::ControllerInputProblem::inertia_not_finite);
}

/// Contact poses exactly where the measured object and the model's frames put them.
void fill_exact_contacts(const Model& model, Input& in)
{
    in.contact_poses_filled = true;
    for (Index i = 0; i < model.arms(); ++i) {
        in.contact_positions.col(i) = in.object.pose.transform_point(model.contact(i).frame.position);
        in.contact_orientations.col(i) = (in.object.pose.orientation * model.contact(i).frame.orientation).coeffs();
    }
}

TEST(Slip, AContactMovedOrTurnedByHandReportsThatAmount)
{
    Case c = hold_case(2304, 0.1);
    Input in = c.input;
    double normal_before = 0;
    {
        const Model unraised(c.parameters);
        Data before(unraised);
        fill_exact_contacts(unraised, in);
        coopdyn::controller_tick(unraised, before, in);
        normal_before = std::max(before.contact_frame_wrenches(2, 0), before.contact_frame_wrenches(2, 1));
    }
    // A factor that makes f_min twice the larger normal force of the grasp without slip.
    const double f_min = c.parameters.contacts[1].friction.minimum_normal_force;
    const double factor = 2.0 * normal_before / f_min;
    c.parameters.faults.slip_squeeze_factor = factor;
    const Model model(c.parameters);
    Data data(model);
    coopdyn::controller_tick(model, data, in);
    ASSERT_TRUE(data.slip_measured);
    EXPECT_LT(data.slip_distance.maxCoeff(), 1e-15);
    EXPECT_LT(data.slip_angle.maxCoeff(), 1e-7);  // acos-free: log of a quaternion within rounding of 1
    EXPECT_EQ(data.slipping_contacts, 0);
    EXPECT_EQ(data.status, ControlStatus::ok);
    EXPECT_LT(data.contact_frame_wrenches(2, 1), normal_before * (1 + 1e-12));  // no slip: not raised

    const Vector3d moved(0.003, -0.004, 0.012);  // 13 mm
    in.contact_positions.col(1) += moved;
    const double angle = 0.1;
    const Quaterniond turned = coopdyn_test::axis_angle(angle, Vector3d(1, 2, -2) / 3.0) *
                               Quaterniond(Eigen::Vector4d(in.contact_orientations.col(0)));
    in.contact_orientations.col(0) = turned.coeffs();
    coopdyn::controller_tick(model, data, in);
    EXPECT_NEAR(data.slip_distance(1), 0.013, 1e-15);
    EXPECT_LT((data.slip_displacement.col(1) - moved).norm(), 1e-15);
    EXPECT_NEAR(data.slip_angle(0), angle, 1e-14);
    EXPECT_LT(data.slip_distance(0), 1e-15);  // turned about its own origin
    EXPECT_LT(data.slip_angle(1), 1e-7);
    EXPECT_TRUE(data.slipping(0) && data.slipping(1));  // 13 mm > 5 mm, 0.1 rad > 0.05 rad
    EXPECT_EQ(data.slipping_contacts, 2);
    EXPECT_EQ(data.status, ControlStatus::slipping);  // what users check says it, on this tick
    EXPECT_TRUE(coopdyn::control_computed(data.status));
    // f_min times the factor on both: each presses at least twice the former normal force now.
    EXPECT_GE(data.contact_frame_wrenches(2, 1), factor * f_min * (1 - 1e-12));
    EXPECT_GE(data.contact_frame_wrenches(2, 0), factor * f_min * (1 - 1e-12));
    std::printf("slipping contacts' normal forces %.3f, %.3f N (f_min %.1f N x %.2f; before at most %.3f N)\n",
                data.contact_frame_wrenches(2, 0), data.contact_frame_wrenches(2, 1), f_min, factor, normal_before);
}

TEST(TorqueLimits, SaturationIsReportedAndTheTorquesClamped)
{
    Case c = hold_case(2305, 0.1);
    Model unlimited_model(c.parameters);
    Data unlimited(unlimited_model);
    const VectorXd wanted = coopdyn::controller_tick(unlimited_model, unlimited, c.input);
    // Every even joint limited to half its torque, every odd one far above it.
    VectorXd limits(14);
    for (Index j = 0; j < 14; ++j) {
        limits(j) = j % 2 == 0 ? 0.5 * std::abs(wanted(j)) : 10.0 * std::abs(wanted(j)) + 1.0;
    }
    c.parameters.torque_limits = limits;
    const Model model(c.parameters);
    Data data(model);
    const VectorXd tau = coopdyn::controller_tick(model, data, c.input);
    EXPECT_EQ(unlimited.status, ControlStatus::ok);
    EXPECT_EQ(data.requested_torque, wanted);
    EXPECT_EQ(data.saturated_count, 7);
    EXPECT_EQ(data.status, ControlStatus::torque_saturated);  // on the tick it clips
    EXPECT_TRUE(coopdyn::control_computed(data.status));
    for (Index j = 0; j < 14; ++j) {
        EXPECT_EQ(data.saturated_joints(j), j % 2 == 0) << j;
        EXPECT_EQ(tau(j), j % 2 == 0 ? std::copysign(limits(j), wanted(j)) : wanted(j)) << j;
    }
    // The rate limit: a second tick with the goal moved may change each torque by 0.05 N m at most.
    c.parameters.torque_limits.resize(0);
    c.parameters.torque_rate_limits = VectorXd::Constant(14, 0.05);
    const Model rate_model(c.parameters);
    Data rate(rate_model);
    const VectorXd first = coopdyn::controller_tick(rate_model, rate, c.input);
    EXPECT_EQ(first, wanted);  // nothing sent before: no limit
    EXPECT_EQ(rate.status, ControlStatus::ok);
    Input moved = c.input;
    moved.desired_pose.position += Vector3d(0.05, 0.0, -0.03);
    const VectorXd second = coopdyn::controller_tick(rate_model, rate, moved);
    EXPECT_LE((second - first).cwiseAbs().maxCoeff(), 0.05 + 1e-12 * first.cwiseAbs().maxCoeff());  // rounding of first + 0.05
    EXPECT_GT(rate.saturated_count, 0);
    EXPECT_EQ(rate.status, ControlStatus::torque_saturated);
    for (Index j = 0; j < 14; ++j) {
        const double change = rate.requested_torque(j) - first(j);
        EXPECT_EQ(second(j), std::abs(change) > 0.05 ? first(j) + std::copysign(0.05, change) : rate.requested_torque(j));
    }
}

TEST(Faults, NoNewModeAllocates)
{
    Hold hold = make_hold(2306, 0.01);
    hold.c.parameters.torque_limits = VectorXd::Constant(14, 5.0);
    hold.c.parameters.torque_rate_limits = VectorXd::Constant(14, 1.0);
    hold.c.parameters.faults.slip_squeeze_factor = 3.0;
    const Model model(hold.c.parameters);
    Data data(model);
    const auto count = [&](const Input& in) {
        const auto counts = allocation_counter::count_allocations([&] { coopdyn::controller_tick(model, data, in); });
        return counts.operator_new + counts.eigen;
    };
    std::vector<Input> inputs;
    for (int k = 0; k < 30; ++k) {
        inputs.push_back(hold.input(k, k < 15));
    }
    inputs[1].contact_positions.col(0) += Vector3d(0.01, 0, 0);  // slip, the squeeze raised
    for (int k = 2; k < 30; ++k) {
        if (k >= 5 && k != 12) {
            inputs[static_cast<std::size_t>(k)].object.twist(2) = nan;  // contacts 5-11 and 13-14, twist 15-22, hold 23-
        }
    }
    inputs[12].bias(0) = nan;  // safe hold on a bad arm input
    std::vector<ControlStatus> seen;
    int predicted = 0;
    for (const Input& in : inputs) {
        EXPECT_EQ(count(in), 0) << coopdyn::to_string(data.status);
        seen.push_back(data.status);
        predicted += data.replaced_input != coopdyn::ReplacedInput::none ? 1 : 0;
    }
    EXPECT_EQ(data.status, ControlStatus::safe_hold);
    // The predicted ticks clip at these limits: torque_saturated outranks degraded, and
    // replaced_input still says a prediction ran (docs/control.md, "Check data.status first").
    EXPECT_GT(predicted, 0);
    EXPECT_NE(std::find(seen.begin(), seen.end(), ControlStatus::torque_saturated), seen.end());
    EXPECT_NE(std::find(seen.begin(), seen.end(), ControlStatus::slipping), seen.end());
    EXPECT_GT(std::count(seen.begin(), seen.end(), ControlStatus::safe_hold), 1);
}

/// Builds the model and expects InvalidModel naming `parameter` (no arm: a joint is named in the
/// message; the model does not know which arm a joint belongs to).
void expect_refused(const Parameters& p, const std::string& parameter)
{
    try {
        const Model model(p);
        ADD_FAILURE() << "accepted a bad '" << parameter << "'";
    } catch (const coopdyn::InvalidModel& error) {
        EXPECT_EQ(error.parameter(), parameter) << error.what();
        EXPECT_FALSE(error.problem().empty());
    }
}

TEST(FaultParameters, EachBadOneIsRefusedByName)
{
    const Parameters good = hold_case(2307, 0.1).parameters;
    EXPECT_NO_THROW(Model{good});
    Parameters p = good;
    p.torque_limits = VectorXd::Constant(13, 1.0);
    expect_refused(p, "torque_limits");
    p.torque_limits = VectorXd::Constant(14, 1.0);
    p.torque_limits(3) = -1.0;
    expect_refused(p, "torque_limits");
    p.torque_limits(3) = nan;
    expect_refused(p, "torque_limits");
    p.torque_limits(3) = 0.0;
    try {
        const Model model(p);
        ADD_FAILURE();
    } catch (const coopdyn::InvalidModel& error) {
        EXPECT_NE(std::string(error.what()).find("joint 3"), std::string::npos) << error.what();
    }
    p = good;
    p.torque_rate_limits = VectorXd::Constant(14, std::numeric_limits<double>::infinity());
    expect_refused(p, "torque_rate_limits");
    p = good;
    p.faults.tick_period = 0.0;
    expect_refused(p, "faults.tick_period");
    p = good;
    p.faults.prediction_limit = -0.1;
    expect_refused(p, "faults.prediction_limit");
    p = good;
    p.faults.slip_distance_threshold = 0.0;
    expect_refused(p, "faults.slip_distance_threshold");
    p = good;
    p.faults.slip_angle_threshold = nan;
    expect_refused(p, "faults.slip_angle_threshold");
    p = good;
    p.faults.slip_squeeze_factor = 0.5;
    expect_refused(p, "faults.slip_squeeze_factor");
}

TEST(FaultNames, EveryNewEnumeratorHasItsName)
{
    EXPECT_STREQ(coopdyn::to_string(ControlStatus::degraded), "degraded");
    EXPECT_STREQ(coopdyn::to_string(ControlStatus::safe_hold), "safe_hold");
    EXPECT_STREQ(coopdyn::to_string(ReplacedInput::none), "none");
    EXPECT_STREQ(coopdyn::to_string(ReplacedInput::object_acceleration), "object_acceleration");
    EXPECT_STREQ(coopdyn::to_string(ReplacedInput::object_state_from_contacts), "object_state_from_contacts");
    EXPECT_STREQ(coopdyn::to_string(ReplacedInput::object_state_from_twist), "object_state_from_twist");
    EXPECT_STREQ(coopdyn::to_string(coopdyn::ControllerInputProblem::object_stale), "object (flagged stale)");
    EXPECT_STREQ(coopdyn::to_string(ControlStatus::torque_saturated), "torque_saturated");
    EXPECT_STREQ(coopdyn::to_string(ControlStatus::slipping), "slipping");
    EXPECT_TRUE(coopdyn::control_computed(ControlStatus::degraded));
    EXPECT_TRUE(coopdyn::control_computed(ControlStatus::torque_saturated));
    EXPECT_TRUE(coopdyn::control_computed(ControlStatus::slipping));
    EXPECT_FALSE(coopdyn::control_computed(ControlStatus::safe_hold));
    EXPECT_FALSE(coopdyn::control_computed(ControlStatus::invalid_input));
    EXPECT_FALSE(coopdyn::control_computed(ControlStatus::singular));
}

}  // namespace
