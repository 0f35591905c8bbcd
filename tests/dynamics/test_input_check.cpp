// Per-tick input checks (include/coopdyn/dynamics/input_check.hpp, docs/conventions.md): every
// input a user reported as silently corrupting a tick (a state quaternion scaled by 1.5, setpoint
// quaternions scaled by 3 or left at zero, NaN in the state, the setpoints or the disturbances)
// is named by check_inputs, with its arm, and stops a debug build.

#include "coopdyn/dynamics/cooperative_dynamics.hpp"
#include "coopdyn/dynamics/input_check.hpp"

#include "sample_systems.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace {

using coopdyn::Index;
using coopdyn::InputProblem;
using Fixture = coopdyn_test::TickFixture<3>;

const double kNan = std::numeric_limits<double>::quiet_NaN();

Fixture good_tick()
{
    Fixture tick(3);
    EXPECT_TRUE(coopdyn::check_inputs(tick.model, tick.state, tick.setpoints, tick.disturbances).ok());
    return tick;
}

void expect_problem(const Fixture& tick, InputProblem problem, Index arm)
{
    const coopdyn::InputCheck check = coopdyn::check_inputs(tick.model, tick.state, tick.setpoints, tick.disturbances);
    EXPECT_FALSE(check.ok());
    EXPECT_EQ(check.problem, problem) << check.input();
    EXPECT_EQ(check.arm, arm);
}

TEST(InputCheck, NamesTheBadQuaternion)
{
    Fixture scaled_state = good_tick();
    scaled_state.state.pose.orientation.coeffs() *= 1.5;
    expect_problem(scaled_state, InputProblem::state_orientation, coopdyn::no_arm);

    Fixture scaled_setpoint = good_tick();
    scaled_setpoint.setpoints.orientations.col(1) *= 3.0;
    expect_problem(scaled_setpoint, InputProblem::setpoint_orientation, 1);

    Fixture zero_setpoint = good_tick();
    zero_setpoint.setpoints.orientations.col(2).setZero();
    expect_problem(zero_setpoint, InputProblem::setpoint_orientation, 2);
}

TEST(InputCheck, NamesTheNonFiniteInputAndItsArm)
{
    Fixture a = good_tick();
    a.state.twist(4) = kNan;
    expect_problem(a, InputProblem::state_twist, coopdyn::no_arm);
    Fixture b = good_tick();
    b.state.pose.position(0) = std::numeric_limits<double>::infinity();
    expect_problem(b, InputProblem::state_position, coopdyn::no_arm);
    Fixture c = good_tick();
    c.setpoints.wrench(2)(1) = kNan;
    expect_problem(c, InputProblem::setpoint_wrench, 2);
    Fixture d = good_tick();
    d.setpoints.twist(0)(5) = kNan;
    expect_problem(d, InputProblem::setpoint_twist, 0);
    Fixture e = good_tick();
    e.setpoints.acceleration(1)(0) = kNan;
    expect_problem(e, InputProblem::setpoint_acceleration, 1);
    Fixture f = good_tick();
    f.setpoints.positions(2, 1) = kNan;
    expect_problem(f, InputProblem::setpoint_position, 1);
    Fixture g = good_tick();
    g.disturbances.object(3) = kNan;
    expect_problem(g, InputProblem::object_disturbance, coopdyn::no_arm);
    Fixture h = good_tick();
    h.disturbances.end_effector(2)(2) = kNan;
    expect_problem(h, InputProblem::arm_disturbance, 2);
}

TEST(InputCheck, AcceptsAQuaternionNormalisedInFloat)
{
    // A measurement normalised in float and used in double is off by ~1e-7: accepted.
    Fixture tick = good_tick();
    const Eigen::Quaternionf single = tick.state.pose.orientation.cast<float>().normalized();
    tick.state.pose.orientation = single.cast<double>();
    EXPECT_TRUE(coopdyn::check_inputs(tick.model, tick.state, tick.setpoints, tick.disturbances).ok());
    tick.state.pose.orientation.coeffs() *= 1.0 + 1e-5;
    expect_problem(tick, InputProblem::state_orientation, coopdyn::no_arm);
}

#ifndef NDEBUG
TEST(InputCheckDeathTest, DebugBuildsStopOnAScaledStateQuaternion)
{
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    Fixture tick = good_tick();
    tick.state.pose.orientation.coeffs() *= 1.5;
    EXPECT_DEATH(coopdyn::interaction_dynamics(tick.model, tick.data, tick.state, tick.setpoints, tick.disturbances),
                 "state.pose.orientation");
    Fixture nan_wrench = good_tick();
    nan_wrench.setpoints.wrench(1)(0) = kNan;
    EXPECT_DEATH(coopdyn::interaction_dynamics(nan_wrench.model, nan_wrench.data, nan_wrench.state,
                                               nan_wrench.setpoints, nan_wrench.disturbances),
                 "arm 1: setpoints.wrenches");
}
#endif

}  // namespace
