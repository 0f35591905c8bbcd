// Tests of coopdyn/model/grasp_inverse.hpp: the one implementation of the grasp's pseudo-inverses,
// the weighted inverse W G^T (G W G^T)^-1 of (25) (errata E2) and, with unit weights, the
// Moore-Penrose G^+ = G^T (G G^T)^-1 (docs/model.md, "Grasp inverse").
//
// References the code was not derived from: the literal grasp matrix (24) with Eigen's
// CompleteOrthogonalDecomposition pseudo-inverse, the dense closed forms G^T (G G^T)^-1 and
// W G^T (G W G^T)^-1 (LU-solved), and the right-inverse identity G G+ = I6. Seeded random grasps
// with off-centre (asymmetric) contacts, K = 2, 3, 4, fixed and dynamic sizes.

#include "coopdyn/model/grasp_inverse.hpp"

#include "sample_systems.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>
#include <vector>

namespace {

using coopdyn_test::literal_grasp_matrix;
using coopdyn_test::MatrixXd;
using coopdyn_test::off_centre_offsets;
using coopdyn_test::relative_error;
using coopdyn_test::Rng;
using coopdyn_test::Vector6d;
using coopdyn_test::VectorXd;
using Index = Eigen::Index;
using Inertia = coopdyn::CentralInertia<double>;

constexpr int draws = 20;

/// grasp_pseudo_inverse with r as a fixed-size 3 x K matrix (the result is 6K x 6 at compile time).
template <int K> MatrixXd fixed_size_pseudo_inverse(const MatrixXd& r)
{
    const Eigen::Matrix<double, 3, K> fixed = r;
    const Eigen::Matrix<double, 6 * K, 6> inverse = coopdyn::grasp_pseudo_inverse(fixed);
    return inverse;
}

MatrixXd fixed_size_pseudo_inverse(const MatrixXd& r)
{
    switch (r.cols()) {
    case 2: return fixed_size_pseudo_inverse<2>(r);
    case 3: return fixed_size_pseudo_inverse<3>(r);
    default: return fixed_size_pseudo_inverse<4>(r);
    }
}

/// Random positive weights: m*_i in [0.5, 3], J*_i symmetric positive definite.
coopdyn_test::Weights random_weights(Index arms, Rng& rng)
{
    coopdyn_test::Weights weights{VectorXd(arms), MatrixXd(3, 3 * arms)};
    for (Index i = 0; i < arms; ++i) {
        weights.mass(i) = coopdyn_test::uniform(rng, 0.5, 3.0);
        weights.inertia.block(0, 3 * i, 3, 3) = coopdyn_test::random_body_inertia(rng);
    }
    return weights;
}

std::vector<Inertia> weight_list(const coopdyn_test::Weights& weights)
{
    std::vector<Inertia> list;
    for (Index i = 0; i < weights.mass.size(); ++i) {
        list.emplace_back(weights.mass(i), Eigen::Matrix3d(weights.inertia.block(0, 3 * i, 3, 3)));
    }
    return list;
}

TEST(GraspPseudoInverse, MatchesCompleteOrthogonalDecompositionAndTheClosedForm)
{
    Rng rng(52001);
    double worst_cod = 0.0, worst_closed = 0.0, worst_fixed = 0.0, worst_right = 0.0;
    for (Index arms = 2; arms <= 4; ++arms) {
        for (int draw = 0; draw < draws; ++draw) {
            const MatrixXd r = off_centre_offsets(arms, rng);
            const MatrixXd G = literal_grasp_matrix(r);
            const MatrixXd cod = G.completeOrthogonalDecomposition().pseudoInverse();
            const MatrixXd closed = G.transpose() * (G * G.transpose()).partialPivLu().inverse();
            const MatrixXd dynamic = coopdyn::grasp_pseudo_inverse(r);
            const MatrixXd columns = coopdyn::grasp_pseudo_inverse(Eigen::Matrix3Xd(r));
            ASSERT_EQ(dynamic.rows(), 6 * arms);
            ASSERT_EQ(dynamic.cols(), 6);
            worst_cod = std::max(worst_cod, relative_error(dynamic, cod));
            worst_closed = std::max(worst_closed, relative_error(dynamic, closed));
            worst_fixed = std::max(worst_fixed, relative_error(fixed_size_pseudo_inverse(r), dynamic));
            worst_fixed = std::max(worst_fixed, relative_error(columns, dynamic));
            worst_right = std::max(worst_right, (G * dynamic - MatrixXd::Identity(6, 6)).norm());
        }
    }
    std::printf("G^+ against COD %.2e, closed form %.2e, fixed vs dynamic %.2e, |G G^+ - I| %.2e\n", worst_cod,
                worst_closed, worst_fixed, worst_right);
    EXPECT_LT(worst_cod, 5e-15);
    EXPECT_LT(worst_closed, 5e-15);
    EXPECT_LT(worst_fixed, 1e-15);
    EXPECT_LT(worst_right, 5e-15);
}

TEST(GraspPseudoInverse, IsTheWeightedInverseWithUnitWeights)
{
    // The one implementation: unit weights given as an ordinary list of CentralInertia take the
    // same arithmetic as grasp_pseudo_inverse, to the last bit.
    Rng rng(52002);
    for (Index arms = 2; arms <= 4; ++arms) {
        const MatrixXd r = off_centre_offsets(arms, rng);
        const std::vector<Inertia> unit(static_cast<std::size_t>(arms),
                                        Inertia(1.0, coopdyn::Symmetric3<double>::scaled_identity(1.0)));
        const coopdyn::detail::WeightedGrasp<double> grasp(unit, r);
        ASSERT_TRUE(grasp.valid);
        MatrixXd weighted(6 * arms, 6);
        grasp.write_inverse(unit, r, weighted);
        EXPECT_EQ(weighted, MatrixXd(coopdyn::grasp_pseudo_inverse(r)));
    }
}

TEST(WeightedGraspInverse, MatchesTheDenseWeightedLeastNormInverse)
{
    Rng rng(52003);
    double worst_inverse = 0.0, worst_solve = 0.0, worst_apply = 0.0, worst_right = 0.0;
    for (Index arms = 2; arms <= 4; ++arms) {
        for (int draw = 0; draw < draws; ++draw) {
            const MatrixXd r = off_centre_offsets(arms, rng);
            const coopdyn_test::Weights weights = random_weights(arms, rng);
            const std::vector<Inertia> list = weight_list(weights);
            const MatrixXd G = literal_grasp_matrix(r);
            const MatrixXd W = coopdyn_test::weight_matrix(weights);
            const MatrixXd gram = G * W * G.transpose();
            const MatrixXd reference = W * G.transpose() * gram.partialPivLu().inverse();

            // Fixed rows (3 x K with K dynamic) and, for K = 3, fully fixed offsets.
            const Eigen::Matrix3Xd offsets = r;
            const coopdyn::detail::WeightedGrasp<double> grasp(list, offsets);
            ASSERT_TRUE(grasp.valid);
            MatrixXd inverse(6 * arms, 6);
            grasp.write_inverse(list, offsets, inverse);
            worst_inverse = std::max(worst_inverse, relative_error(inverse, reference));
            worst_right = std::max(worst_right, (G * inverse - MatrixXd::Identity(6, 6)).norm());
            if (arms == 3) {
                const Eigen::Matrix3d fixed = r;
                const coopdyn::detail::WeightedGrasp<double> fixed_grasp(list, fixed);
                Eigen::Matrix<double, 18, 6> fixed_inverse;
                fixed_grasp.write_inverse(list, fixed, fixed_inverse);
                worst_inverse = std::max(worst_inverse, relative_error(MatrixXd(fixed_inverse), reference));
            }

            // (G W G^T)^-1 h (solve) and out -= G+_W h (subtract_inverse_times), per tick.
            const Vector6d wrench = coopdyn_test::random_vector6(rng, 10.0);
            const VectorXd solved = grasp.solve(coopdyn::Force<double>::from(wrench)).vector();
            worst_solve = std::max(worst_solve, relative_error(solved, VectorXd(gram.partialPivLu().solve(wrench))));
            VectorXd applied = VectorXd::Zero(6 * arms);
            grasp.subtract_inverse_times(list, offsets, coopdyn::Force<double>::from(wrench), applied);
            worst_apply = std::max(worst_apply, relative_error(VectorXd(-applied), VectorXd(reference * wrench)));
        }
    }
    std::printf("G+_W against the dense W G^T (G W G^T)^-1: inverse %.2e, solve %.2e, apply %.2e, |G G+_W - I| %.2e\n",
                worst_inverse, worst_solve, worst_apply, worst_right);
    EXPECT_LT(worst_inverse, 1e-14);
    EXPECT_LT(worst_solve, 1e-14);
    EXPECT_LT(worst_apply, 1e-14);
    EXPECT_LT(worst_right, 1e-14);
}

TEST(GraspInverse, PerTickMembersAreNoexcept)
{
    const coopdyn::detail::WeightedGrasp<double> grasp{};
    const coopdyn::detail::UnitGraspWeights<double> unit{2};
    const Eigen::Matrix<double, 3, 2> r = Eigen::Matrix<double, 3, 2>::Zero();
    Eigen::Matrix<double, 12, 1> out;
    const coopdyn::Force<double> wrench{};
    static_assert(noexcept(grasp.solve(wrench)), "per tick");
    static_assert(noexcept(grasp.subtract_inverse_times(unit, r, wrench, out)), "per tick");
    static_assert(noexcept(coopdyn::detail::WeightedGrasp<double>(unit, r)), "per tick");
}

}  // namespace
