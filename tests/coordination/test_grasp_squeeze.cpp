// Tests of squeeze monitoring (include/coopdyn/coordination/grasp_squeeze.hpp): the component
// hbar_sq = hbar - G+_M G hbar of the wrenches the arms apply to the object that lies in the null
// space of G, relative to the non-squeezing distribution of their net wrench.
//
// References the code was not derived from:
//  - the dense projection I - W G^T (G W G^T)^-1 G with the literal grasp matrix (24);
//  - hand-known squeezes: a 20 N push-pull commanded on the Section V beam held at rest;
//  - the identity hbar_sq = -h'_int + (I - G+_M G)(hbar^d + htilde) that holds in every state when
//    the weights are the end-effector inertias (docs/coordination.md), with h'_int from the
//    library's (53) (itself tested against the literal (53) in test_internal_wrenches.cpp) and the
//    projection dense: the monitor differs from (53) exactly by the commanded squeeze.

#include "coopdyn/analysis/internal_wrenches.hpp"
#include "coopdyn/coordination/grasp_squeeze.hpp"
#include "coopdyn/coordination/kinematic_coordination.hpp"
#include "coopdyn/coordination/load_distribution.hpp"
#include "coopdyn/dynamics/cooperative_dynamics.hpp"

#include "sample_systems.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <vector>

namespace {

using coopdyn_test::least_norm_right_inverse;
using coopdyn_test::literal_grasp_matrix;
using coopdyn_test::MatrixXd;
using coopdyn_test::off_centre_offsets;
using coopdyn_test::random_spd;
using coopdyn_test::random_unit_quaternion;
using coopdyn_test::random_vector;
using coopdyn_test::relative_error;
using coopdyn_test::Rng;
using coopdyn_test::uniform;
using coopdyn_test::Vector3d;
using coopdyn_test::Vector6d;
using coopdyn_test::VectorXd;
using coopdyn_test::Weights;
using Index = Eigen::Index;

/// I - W G^T (G W G^T)^-1 G: the dense projector onto null(G) along the weighted range.
MatrixXd dense_squeeze_projector(const MatrixXd& r, const Weights& weights)
{
    const MatrixXd g = literal_grasp_matrix(r);
    return MatrixXd::Identity(g.cols(), g.cols()) - least_norm_right_inverse(g, weights) * g;
}

std::vector<coopdyn::CentralInertia<double>> weight_list(const Weights& weights)
{
    std::vector<coopdyn::CentralInertia<double>> list;
    for (Index i = 0; i < weights.mass.size(); ++i) {
        list.emplace_back(weights.mass(i), coopdyn::Matrix3<double>(weights.inertia.block(0, 3 * i, 3, 3)));
    }
    return list;
}

Weights random_weights(Index arms, Rng& rng)
{
    Weights weights{VectorXd(arms), MatrixXd(3, 3 * arms)};
    for (Index i = 0; i < arms; ++i) {
        weights.mass(i) = uniform(rng, 0.5, 20.0);
        weights.inertia.block(0, 3 * i, 3, 3) = random_spd(3, rng, uniform(rng, 0.05, 0.5), 0.2);
    }
    return weights;
}

// ---------------------------------------------------------------------------------------------
// A. The kernel against the dense projection.
// ---------------------------------------------------------------------------------------------

TEST(SqueezeWrenches, EqualsTheDenseNullSpaceProjectionForOneToSixArms)
{
    Rng rng(11);
    double worst = 0.0;
    double worst_net = 0.0;
    for (Index arms = 1; arms <= 6; ++arms) {
        for (int trial = 0; trial < 10; ++trial) {
            const MatrixXd r = off_centre_offsets(arms, rng);
            const Weights weights = random_weights(arms, rng);
            const VectorXd applied = 20.0 * random_vector(6 * arms, rng);
            const VectorXd squeeze = coopdyn::squeeze_wrenches(weight_list(weights), r, applied);
            const VectorXd reference = dense_squeeze_projector(r, weights) * applied;
            // For one arm null(G) = {0}: compare absolutely.
            const double error = arms == 1 ? squeeze.norm() / applied.norm() : relative_error(squeeze, reference);
            worst = std::max(worst, error);
            EXPECT_LT(error, 1e-11) << "N = " << arms << ", trial " << trial;
            // The squeeze exerts no net wrench on the object: G hbar_sq = 0.
            const double net = (literal_grasp_matrix(r) * squeeze).norm() / applied.norm();
            worst_net = std::max(worst_net, net);
            EXPECT_LT(net, 1e-13) << "N = " << arms;
        }
    }
    std::printf("[ squeeze ] N = 1..6: vs dense I - W G^T (G W G^T)^-1 G: %.2e; |G hbar_sq| / |hbar|: %.2e\n", worst,
                worst_net);
}

TEST(SqueezeWrenches, IsAProjectionThatKeepsNullSpaceWrenchesAndRemovesDistributedOnes)
{
    Rng rng(12);
    const Index arms = 4;
    const MatrixXd r = off_centre_offsets(arms, rng);
    const Weights weights = random_weights(arms, rng);
    const auto list = weight_list(weights);
    const VectorXd applied = 10.0 * random_vector(6 * arms, rng);
    const VectorXd once = coopdyn::squeeze_wrenches(list, r, applied);
    EXPECT_LT(relative_error(coopdyn::squeeze_wrenches(list, r, once), once), 1e-13);
    // A distribution of any object wrench by the same weights does not squeeze ...
    const Vector6d object_wrench = 30.0 * random_vector(6, rng);
    const VectorXd distributed = -coopdyn::load_distribution(list, r, object_wrench);
    EXPECT_LT(coopdyn::squeeze_wrenches(list, r, distributed).norm() / distributed.norm(), 1e-13);
    // ... but it does squeeze relative to other weights (the measure depends on the reference).
    const auto other = weight_list(random_weights(arms, rng));
    EXPECT_GT(coopdyn::squeeze_wrenches(other, r, distributed).norm() / distributed.norm(), 1e-3);
}

TEST(SqueezeWrenches, TryFormIsNoexceptMayAliasAndRefusesDegenerateWeights)
{
    Rng rng(13);
    const MatrixXd r = off_centre_offsets(3, rng);
    const Weights weights = random_weights(3, rng);
    const auto list = weight_list(weights);
    const VectorXd applied = random_vector(18, rng);
    VectorXd in_place = applied;
    static_assert(noexcept(coopdyn::try_squeeze_wrenches(list, r, applied, in_place)), "per-tick form is noexcept");
    ASSERT_TRUE(coopdyn::try_squeeze_wrenches(list, r, in_place, in_place));
    EXPECT_LT(relative_error(in_place, coopdyn::squeeze_wrenches(list, r, applied)), 1e-15);

    // Two arms, no rotational weights: the torque about the grasp line cannot be distributed.
    const MatrixXd line = (MatrixXd(3, 2) << -0.4, 0.4, 0.0, 0.0, 0.0, 0.0).finished();
    const std::vector<coopdyn::CentralInertia<double>> points{coopdyn::CentralInertia<double>(1.0, coopdyn::Matrix3<double>::Zero()),
                                                              coopdyn::CentralInertia<double>(2.0, coopdyn::Matrix3<double>::Zero())};
    VectorXd untouched = VectorXd::Constant(12, 7.0);
    EXPECT_FALSE(coopdyn::try_squeeze_wrenches(points, line, VectorXd::Ones(12), untouched));
    EXPECT_EQ(untouched, VectorXd::Constant(12, 7.0));
    EXPECT_THROW(coopdyn::squeeze_wrenches(points, line, VectorXd::Ones(12)), coopdyn::InvalidModel);

    // A non-positive mass weight names itself and the arm; a wrong-size input is an argument error.
    std::vector<coopdyn::CentralInertia<double>> negative = list;
    negative[1] = coopdyn::CentralInertia<double>(-1.0, coopdyn::Matrix3<double>::Identity());
    try {
        (void)coopdyn::squeeze_wrenches(negative, r, applied);
        ADD_FAILURE() << "a negative mass weight was accepted";
    } catch (const coopdyn::InvalidModel& error) {
        EXPECT_EQ(error.arm(), 1);
        EXPECT_NE(std::string(error.what()).find("mass"), std::string::npos) << error.what();
    }
    EXPECT_THROW(coopdyn::squeeze_wrenches(list, r, VectorXd::Ones(17)), coopdyn::InvalidArgument);
}

// ---------------------------------------------------------------------------------------------
// B. The Section V beam held at rest: commanded squeezes with known values.
// ---------------------------------------------------------------------------------------------

using Beam = coopdyn::Model<double, 2>;

struct HeldBeam {
    coopdyn::Data<Beam> data;
    coopdyn::WrenchDecomposition<Beam> decomposition;
};

/// The beam at rest at the origin, setpoints at its grasp poses, h^d = (distribution of the
/// weight's compensation h_g by `distribution`) - `commanded_squeeze` (on the object: hbar^d
/// gains the squeeze); the interaction solve and (53) evaluated there.
HeldBeam hold_beam(const Beam& beam, const coopdyn::LoadDistribution<Beam>& distribution,
                   const VectorXd& commanded_squeeze)
{
    HeldBeam held{coopdyn::Data<Beam>(beam), coopdyn::WrenchDecomposition<Beam>(beam)};
    coopdyn::RigidBodyState<double> state;  // at rest, identity orientation
    coopdyn::Setpoints<double, 2> setpoints;
    coopdyn::coordinate_setpoints(beam, state, Vector6d::Zero(), setpoints);
    coopdyn::grasp_kinematics(beam, held.data, state);
    distribution.distribute(held.data, beam.object().gravity_wrench(beam.gravity()), setpoints);
    setpoints.wrenches -= commanded_squeeze;
    coopdyn::interaction_dynamics(beam, held.data, state, setpoints, coopdyn::Disturbances<double, 2>());
    coopdyn::decompose_wrenches(beam, held.data, held.decomposition);
    return held;
}

TEST(SqueezeWrenches, BeamPushPullOfTwentyNewtonsIsSeenExactlyWhereEquation53SeesNothing)
{
    const Beam beam = coopdyn_test::section_five_beam_model<Beam>();
    const coopdyn::LoadDistribution<Beam> reference(beam);  // weights (10, 10), J* = 0.5 I3
    // Grasps at y = -0.4 and +0.4: each arm pushes 20 N towards the other.
    VectorXd push_pull = VectorXd::Zero(12);
    push_pull(1) = 20.0;
    push_pull(7) = -20.0;
    const HeldBeam held = hold_beam(beam, reference, push_pull);
    ASSERT_LT(held.data.object_acceleration().norm(), 1e-12) << "the beam is held in equilibrium";

    VectorXd squeeze(12);
    static_assert(noexcept(coopdyn::squeeze_wrenches(reference, held.data, squeeze)), "per tick");
    coopdyn::squeeze_wrenches(reference, held.data, squeeze);
    std::printf("[ beam push-pull 20 N ] squeeze arm 1 (%.12f, %.12f, %.12f) N, arm 2 (%.12f, %.12f, %.12f) N; "
                "|(53)| = %.2e N\n",
                squeeze(0), squeeze(1), squeeze(2), squeeze(6), squeeze(7), squeeze(8),
                held.decomposition.internal.norm());
    EXPECT_LT((squeeze - push_pull).norm(), 1e-12);
    EXPECT_LT(held.decomposition.internal.norm(), 1e-12);
    // (54) carries it all: the measured wrenches h' = h^d here.
    EXPECT_LT((held.decomposition.external - held.data.end_effector_wrenches()).norm(), 1e-12);
    // The wrench arm 1 applies to the object contains the push: hbar_1 = -h_1.
    EXPECT_NEAR(held.data.wrench_on_object(0)(1), 20.0, 1e-12);
}

TEST(SqueezeWrenches, UnequalLoadWeightsSqueezeRelativeToEqualOnes)
{
    // The example: the weight distributed with mass weights (10, 1000) instead of (10, 10)
    // (J*_i = 0.5 I3 in both). By hand, from (25) with the centroid c = 0.392079 m: arm 1 carries
    // 0.43320 of the weight F = 1.75 * 9.81 N, arm 2 0.56680, and each a torque -0.026721 F about x.
    // Relative to (10, 10) (0.5 F each, no torque) the squeeze is -/+0.066802 F in z and -0.026721 F
    // about x, which (53) does not see.
    const Beam beam = coopdyn_test::section_five_beam_model<Beam>();
    const coopdyn::LoadDistribution<Beam> reference(beam);
    const coopdyn::LoadDistribution<Beam> unequal(beam, Eigen::Vector2d(10.0, 1000.0),
                                                  beam.end_effector_rotational_inertias());
    const HeldBeam held = hold_beam(beam, unequal, VectorXd::Zero(12));
    ASSERT_LT(held.data.object_acceleration().norm(), 1e-12);
    VectorXd squeeze(12);
    coopdyn::squeeze_wrenches(reference, held.data, squeeze);

    const double weight = 1.75 * 9.81;
    const double c = (10.0 * -0.4 + 1000.0 * 0.4) / 1010.0;
    const double arm1 = -0.4 - c;
    const double arm2 = 0.4 - c;
    const double spread = 10.0 * arm1 * arm1 + 1000.0 * arm2 * arm2;
    const double omega_x = -c * weight / (1.0 + spread);  // (J*_o)^-1 t_c, J*_o,xx = 2 * 0.5 + spread
    VectorXd by_hand = VectorXd::Zero(12);
    by_hand(2) = 10.0 * (weight / 1010.0 + omega_x * arm1) - 0.5 * weight;
    by_hand(3) = 0.5 * omega_x;
    by_hand(8) = 1000.0 * (weight / 1010.0 + omega_x * arm2) - 0.5 * weight;
    by_hand(9) = 0.5 * omega_x;
    std::printf("[ beam weights (10, 1000) vs (10, 10) ] squeeze f_z = (%.6f, %.6f) N, t_x = (%.6f, %.6f) Nm; "
                "by hand (%.6f, %.6f) N, (%.6f, %.6f) Nm; |(53)| = %.2e N\n",
                squeeze(2), squeeze(8), squeeze(3), squeeze(9), by_hand(2), by_hand(8), by_hand(3), by_hand(9),
                held.decomposition.internal.norm());
    EXPECT_NEAR(by_hand(2) / weight, -0.066802, 1e-6);
    EXPECT_LT((squeeze - by_hand).norm(), 1e-12);
    EXPECT_LT(held.decomposition.internal.norm(), 1e-12);
}

// ---------------------------------------------------------------------------------------------
// C. Any state: the monitor differs from (53) exactly by the commanded squeeze.
// ---------------------------------------------------------------------------------------------

template <typename ModelType> void expect_monitor_is_53_plus_commanded_squeeze(Index arms, unsigned seed)
{
    constexpr int Arms = ModelType::arms_at_compile_time;
    Rng rng(seed);
    coopdyn_test::SampleRanges ranges;
    const ModelType model = coopdyn_test::random_model_at<ModelType>(off_centre_offsets(arms, rng), rng, ranges);
    const coopdyn::LoadDistribution<ModelType> distribution(model);  // weights: the end-effector inertias
    coopdyn::Data<ModelType> data(model);
    coopdyn::WrenchDecomposition<ModelType> decomposition(model);
    const Weights weights{model.end_effector_masses(), model.end_effector_rotational_inertias()};
    double worst = 0.0;
    double smallest_internal = 1e9;
    double smallest_commanded = 1e9;
    for (int trial = 0; trial < 8; ++trial) {
        coopdyn::RigidBodyState<double> state;
        state.pose.position = random_vector(3, rng);
        state.pose.orientation = random_unit_quaternion(rng);
        state.twist = 2.0 * random_vector(6, rng);
        coopdyn::grasp_kinematics(model, data, state);
        const MatrixXd projector = dense_squeeze_projector(MatrixXd(data.grasp_offsets), weights);

        // Uncoordinated setpoints (the motion controllers squeeze: h'_int != 0), a distributed
        // object wrench plus a commanded squeeze in null(G), and disturbances on every body.
        coopdyn::Setpoints<double, Arms> setpoints(arms);
        for (Index i = 0; i < arms; ++i) {
            setpoints.set_pose(i, coopdyn::Pose<double>{Vector3d(data.end_effector_positions.col(i) + 0.05 * random_vector(3, rng)),
                                                        random_unit_quaternion(rng)});
        }
        setpoints.twists = random_vector(6 * arms, rng);
        setpoints.accelerations = random_vector(6 * arms, rng);
        distribution.distribute(data, Vector6d(25.0 * random_vector(6, rng)), setpoints);
        const VectorXd commanded = projector * (15.0 * random_vector(6 * arms, rng));
        setpoints.wrenches -= commanded;
        coopdyn::Disturbances<double, Arms> disturbances(arms);
        disturbances.object = random_vector(6, rng);
        disturbances.end_effectors = random_vector(6 * arms, rng);

        coopdyn::interaction_dynamics(model, data, state, setpoints, disturbances);
        coopdyn::decompose_wrenches(model, data, decomposition);
        VectorXd squeeze(6 * arms);
        coopdyn::squeeze_wrenches(distribution, data, squeeze);

        // hbar_sq = -h'_int + P (hbar^d + htilde), hbar^d = -h^d; P hbar^d = commanded here.
        const VectorXd predicted =
            -VectorXd(decomposition.internal) + projector * (-VectorXd(setpoints.wrenches) + VectorXd(disturbances.end_effectors));
        const double error = relative_error(squeeze, predicted);
        worst = std::max(worst, error);
        EXPECT_LT(error, 1e-11) << "N = " << arms << ", trial " << trial;
        EXPECT_LT(relative_error(VectorXd(projector * -VectorXd(setpoints.wrenches)), commanded), 1e-11);
        smallest_internal = std::min(smallest_internal, decomposition.internal.norm());
        smallest_commanded = std::min(smallest_commanded, commanded.norm());
    }
    std::printf("[ squeeze = -(53) + commanded ] N = %d (%s): worst rel. error %.2e; min |h'_int| %.2f N, "
                "min |commanded| %.2f N\n",
                static_cast<int>(arms), Arms == coopdyn::Dynamic ? "dynamic" : "fixed", worst, smallest_internal,
                smallest_commanded);
    // Teeth: both terms are large, so neither side of the identity is trivially zero.
    EXPECT_GT(smallest_internal, 0.1);
    EXPECT_GT(smallest_commanded, 1.0);
}

TEST(SqueezeWrenches, DiffersFromEquation53ExactlyByTheCommandedSqueezeInAnyState)
{
    expect_monitor_is_53_plus_commanded_squeeze<coopdyn::Model<double, 2>>(2, 21);
    expect_monitor_is_53_plus_commanded_squeeze<coopdyn::Model<double, 3>>(3, 22);
    expect_monitor_is_53_plus_commanded_squeeze<coopdyn::Model<double, coopdyn::Dynamic>>(5, 23);
}

TEST(SqueezeWrenches, FloatAgreesWithDouble)
{
    Rng rng(31);
    const MatrixXd r = off_centre_offsets(3, rng);
    const Weights weights = random_weights(3, rng);
    const VectorXd applied = 20.0 * random_vector(18, rng);
    std::vector<coopdyn::CentralInertia<float>> float_weights;
    for (const auto& weight : weight_list(weights)) {
        float_weights.emplace_back(static_cast<float>(weight.mass()), coopdyn::Matrix3<float>(weight.rotational().matrix().cast<float>()));
    }
    const Eigen::Matrix<float, 3, 3> r_float = r.cast<float>();
    const Eigen::Matrix<float, 18, 1> applied_float = applied.cast<float>();
    const auto squeeze_float = coopdyn::squeeze_wrenches(float_weights, r_float, applied_float);
    static_assert(decltype(squeeze_float)::RowsAtCompileTime == 18, "N = 3 is deduced from r");
    const VectorXd squeeze = coopdyn::squeeze_wrenches(weight_list(weights), r, applied);
    const double error = relative_error(VectorXd(squeeze_float.cast<double>()), squeeze);
    std::printf("[ squeeze float vs double ] N = 3: rel. diff. %.2e\n", error);
    EXPECT_LT(error, 1e-5);
}

}  // namespace
