// Misuse of the per-tick containers fails loudly instead of corrupting memory (docs/model.md,
// "Sizes and misuse"): dynamic-N inputs cannot be created without arms, a Data or a wrench
// decomposition built for a model with another number of arms stops the program with a message
// (in Release too), and the wrench each arm applies to the object is available directly.

#include "coopdyn/analysis/internal_wrenches.hpp"
#include "coopdyn/dynamics/cooperative_dynamics.hpp"
#include "coopdyn/errors.hpp"
#include "coopdyn/model/cooperative_model.hpp"

#include "sample_systems.hpp"

#include <gtest/gtest.h>

#include <type_traits>

namespace {

using coopdyn::Dynamic;
using coopdyn::Index;
using ModelX = coopdyn::Model<double, Dynamic>;
using State = coopdyn::RigidBodyState<double>;
using SetpointsX = coopdyn::Setpoints<double, Dynamic>;
using DisturbancesX = coopdyn::Disturbances<double, Dynamic>;
using Setpoints2 = coopdyn::Setpoints<double, 2>;

static_assert(!std::is_default_constructible_v<coopdyn::Setpoints<double, Dynamic>>,
              "a dynamic-N Setpoints without arms must not compile");
static_assert(!std::is_default_constructible_v<coopdyn::Disturbances<double, Dynamic>>,
              "a dynamic-N Disturbances without arms must not compile");
static_assert(std::is_default_constructible_v<coopdyn::Setpoints<double, 3>>);
static_assert(std::is_default_constructible_v<coopdyn::Disturbances<double, 3>>);

TEST(Misuse, InputsRefuseAWrongArmCountNamingIt)
{
    EXPECT_THROW(SetpointsX(0), coopdyn::InvalidArgument);
    EXPECT_THROW(DisturbancesX(-1), coopdyn::InvalidArgument);
    try {
        Setpoints2 setpoints(3);
        (void)setpoints;
        FAIL() << "no exception";
    } catch (const coopdyn::InvalidArgument& error) {
        EXPECT_EQ(error.parameter(), "arms");
        EXPECT_NE(std::string(error.what()).find("setpoints"), std::string::npos) << error.what();
    }
    EXPECT_EQ(SetpointsX(4).arms(), 4);
}

/// A model with `arms` arms (dynamic N) and per-tick inputs for it.
struct Tick {
    ModelX model;
    State state;
    coopdyn::Setpoints<double, Dynamic> setpoints;
    coopdyn::Disturbances<double, Dynamic> disturbances;
    explicit Tick(Index arms)
        : model(coopdyn_test::random_impedance_model<Dynamic>(arms)), setpoints(arms), disturbances(arms)
    {
    }
};

using MisuseDeathTest = ::testing::Test;

TEST(MisuseDeathTest, DataBuiltForAnotherModelStopsWithAMessage)
{
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    Tick two(2);
    const Tick three(3);
    coopdyn::Data<ModelX> data_for_three(three.model);
    EXPECT_DEATH(coopdyn::interaction_dynamics(two.model, data_for_three, two.state, two.setpoints, two.disturbances),
                 "Data was built for another model");
    coopdyn::Data<ModelX> data_for_two(two.model);
    EXPECT_DEATH(coopdyn::interaction_dynamics(two.model, data_for_two, two.state, three.setpoints, two.disturbances),
                 "setpoints sized for another number of arms");
    coopdyn::interaction_dynamics(two.model, data_for_two, two.state, two.setpoints, two.disturbances);
    coopdyn::WrenchDecomposition<ModelX> decomposition_for_three(three.model);
    EXPECT_DEATH(coopdyn::decompose_wrenches(two.model, data_for_two, decomposition_for_three),
                 "decomposition sized for another number of arms");
}

TEST(Misuse, WrenchesOnTheObjectSumToTheObjectWrench)
{
    // h_o = -G h' (23): the arms' wrenches on the object, moved to its centre, sum to the h_o
    // the solver computed from M_o xdd_o - hSigma_o.
    coopdyn_test::TickFixture<Dynamic> tick(3);
    coopdyn::interaction_dynamics(tick.model, tick.data, tick.state, tick.setpoints, tick.disturbances);
    Eigen::Matrix<double, 6, 1> sum = Eigen::Matrix<double, 6, 1>::Zero();
    for (Index i = 0; i < 3; ++i) {
        EXPECT_EQ(tick.data.wrench_on_object(i), -tick.data.end_effector_wrench(i));
        sum += tick.data.wrench_on_object_at_centre(i);
    }
    EXPECT_LT((sum - tick.data.object_wrench()).norm(), 1e-12 * (1.0 + tick.data.object_wrench().norm()));
    EXPECT_GT(tick.data.object_wrench().norm(), 1.0);
}

}  // namespace
