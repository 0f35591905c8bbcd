// coopdyn::udwadia_kalaba (docs/dynamics.md, paper (18)-(19)) against references it was not
// derived from: the KKT system of the constrained dynamics, direct minimisation of Gauss's
// function over a null-space parameterisation of the constraint manifold, and the independent
// subsystem of redundant / rank-deficient constraints. The full-row-rank form
// (try_udwadia_kalaba_full_rank) against the same KKT system, and its refusals.
#include "coopdyn/dynamics/udwadia_kalaba.hpp"

#include "sample_systems.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <vector>

namespace {

using namespace coopdyn_test;

struct Solution {
    VectorXd accelerations;
    VectorXd wrench;
    VectorXd multipliers;  ///< lambda, wrench = A^T lambda
};

/// [[M, A^T], [A, 0]] [xdd; -lambda] = [hSigma; b], h = A^T lambda (requires full row rank A).
Solution kkt_solution(const MatrixXd& M, const MatrixXd& A, const VectorXd& b, const VectorXd& h_sigma)
{
    const Index n = M.rows();
    const Index m = A.rows();
    MatrixXd kkt = MatrixXd::Zero(n + m, n + m);
    kkt.topLeftCorner(n, n) = M;
    kkt.topRightCorner(n, m) = A.transpose();
    kkt.bottomLeftCorner(m, n) = A;
    VectorXd rhs(n + m);
    rhs << h_sigma, b;
    const Eigen::FullPivLU<MatrixXd> lu(kkt);
    EXPECT_TRUE(lu.isInvertible());
    const VectorXd solution = lu.solve(rhs);
    const VectorXd lambda = -solution.tail(m);
    return {solution.head(n), A.transpose() * lambda, lambda};
}

/// Accelerations of the library result, xdd = M^-1 (hSigma + h), computed here.
VectorXd accelerations_of(const MatrixXd& M, const VectorXd& h_sigma, const VectorXd& h)
{
    return M.ldlt().solve(h_sigma + h);
}

/// Gauss's function (19): (xdd - M^-1 hSigma)^T M (xdd - M^-1 hSigma).
double gauss_cost(const MatrixXd& M, const VectorXd& h_sigma, const VectorXd& xdd)
{
    const VectorXd deviation = xdd - M.ldlt().solve(h_sigma);
    return deviation.dot(M * deviation);
}

struct RandomProblem {
    MatrixXd M;
    MatrixXd A;
    VectorXd b;
    VectorXd h_sigma;
};

RandomProblem random_problem(Rng& rng, Index n, Index m)
{
    RandomProblem p;
    p.M = random_spd(n, rng, uniform(rng, 0.1, 10.0));
    p.A = random_matrix(m, n, rng);
    p.b = random_vector(m, rng, -3.0, 3.0);
    p.h_sigma = random_vector(n, rng, -10.0, 10.0);
    return p;
}

Index random_index(Rng& rng, Index low, Index high)
{
    return static_cast<Index>(std::uniform_int_distribution<long>(static_cast<long>(low), static_cast<long>(high))(rng));
}

TEST(UdwadiaKalaba, MatchesKktSolution)
{
    double worst_acceleration = 0.0;
    double worst_wrench = 0.0;
    for (unsigned seed = 0; seed < 60; ++seed) {
        Rng rng(seed);
        const Index n = 6 + static_cast<Index>(seed % 25);  // 6..30
        const Index m = random_index(rng, 1, n - 1);
        const RandomProblem p = random_problem(rng, n, m);
        ASSERT_EQ(Eigen::FullPivLU<MatrixXd>(p.A).rank(), m);

        const VectorXd h = coopdyn::udwadia_kalaba(p.M, p.A, p.b, p.h_sigma);
        const VectorXd xdd = accelerations_of(p.M, p.h_sigma, h);
        const Solution reference = kkt_solution(p.M, p.A, p.b, p.h_sigma);

        const double acceleration_error = relative_error(xdd, reference.accelerations);
        const double wrench_error = relative_error(h, reference.wrench);
        EXPECT_LT(acceleration_error, 1e-10) << "seed " << seed << " n " << n << " m " << m;
        EXPECT_LT(wrench_error, 1e-10) << "seed " << seed << " n " << n << " m " << m;
        worst_acceleration = std::max(worst_acceleration, acceleration_error);
        worst_wrench = std::max(worst_wrench, wrench_error);

        // The library's own acceleration helper agrees with M^-1 (hSigma + h).
        const VectorXd library_xdd = coopdyn::udwadia_kalaba_accelerations(p.M, p.A, p.b, p.h_sigma);
        EXPECT_LT(relative_error(library_xdd, reference.accelerations), 1e-10) << "seed " << seed;
    }
    std::printf("[ measured ] UK vs KKT: worst relative error accelerations %.3g, wrench %.3g\n",
                worst_acceleration, worst_wrench);
}

TEST(UdwadiaKalaba, MinimisesGaussFunctionOnConstraintManifold)
{
    double worst = 0.0;
    for (unsigned seed = 100; seed < 140; ++seed) {
        Rng rng(seed);
        const Index n = 6 + static_cast<Index>(seed % 25);
        const Index m = random_index(rng, 1, n - 1);
        const RandomProblem p = random_problem(rng, n, m);

        // xdd = xdd_p + Z z: xdd_p the minimum-norm solution of A xdd = b, Z an orthonormal
        // null-space basis of A (last n - m right singular vectors).
        const Eigen::JacobiSVD<MatrixXd> svd(p.A, Eigen::ComputeFullU | Eigen::ComputeFullV);
        ASSERT_EQ(svd.rank(), m);
        const VectorXd particular = svd.solve(p.b);
        const MatrixXd null_space = svd.matrixV().rightCols(n - m);
        ASSERT_LT((p.A * null_space).norm(), 1e-12 * p.A.norm());

        // Gauss's function in z: (xdd_p + Z z - a)^T M (xdd_p + Z z - a), a = M^-1 hSigma.
        // Normal equations: Z^T M Z z = Z^T M (a - xdd_p).
        const VectorXd unconstrained = p.M.ldlt().solve(p.h_sigma);
        const MatrixXd reduced_hessian = null_space.transpose() * p.M * null_space;
        const VectorXd z =
            reduced_hessian.llt().solve(null_space.transpose() * p.M * (unconstrained - particular));
        const VectorXd minimiser = particular + null_space * z;

        const VectorXd h = coopdyn::udwadia_kalaba(p.M, p.A, p.b, p.h_sigma);
        const VectorXd xdd = accelerations_of(p.M, p.h_sigma, h);
        const double error = relative_error(xdd, minimiser);
        EXPECT_LT(error, 1e-10) << "seed " << seed << " n " << n << " m " << m;
        worst = std::max(worst, error);

        // Every feasible perturbation xdd + Z dz has a larger Gauss cost.
        const double cost = gauss_cost(p.M, p.h_sigma, xdd);
        for (const double scale : {1e-4, 1e-2, 1.0}) {
            for (int trial = 0; trial < 5; ++trial) {
                const VectorXd perturbed = xdd + null_space * (scale * random_vector(n - m, rng));
                EXPECT_LT((p.A * perturbed - p.b).norm(), 1e-10 * (1.0 + p.b.norm()));
                EXPECT_GT(gauss_cost(p.M, p.h_sigma, perturbed), cost)
                    << "seed " << seed << " scale " << scale;
            }
        }
    }
    std::printf("[ measured ] UK vs Gauss minimiser: worst relative error %.3g\n", worst);
}

TEST(UdwadiaKalaba, SatisfiesConstraints)
{
    double worst = 0.0;
    for (unsigned seed = 200; seed < 240; ++seed) {
        Rng rng(seed);
        const Index n = 6 + static_cast<Index>(seed % 25);
        const Index m = random_index(rng, 1, n - 1);
        const RandomProblem p = random_problem(rng, n, m);
        const VectorXd xdd = accelerations_of(p.M, p.h_sigma, coopdyn::udwadia_kalaba(p.M, p.A, p.b, p.h_sigma));
        const double residual = (p.A * xdd - p.b).norm() / (p.A.norm() * xdd.norm() + p.b.norm());
        EXPECT_LT(residual, 1e-12) << "seed " << seed;
        worst = std::max(worst, residual);
    }
    std::printf("[ measured ] UK constraint residual |A xdd - b| / (|A||xdd| + |b|): worst %.3g\n", worst);
}

TEST(UdwadiaKalaba, RedundantRowsGiveTheIndependentSolution)
{
    double worst = 0.0;
    for (unsigned seed = 300; seed < 340; ++seed) {
        Rng rng(seed);
        const Index n = random_index(rng, 8, 30);
        const Index m = random_index(rng, 2, n - 4);
        const RandomProblem p = random_problem(rng, n, m);

        // Independent rows, two duplicated rows and one linear combination, shuffled.
        const Index first = random_index(rng, 0, m - 1);
        const Index second = random_index(rng, 0, m - 1);
        const VectorXd weights = random_vector(m, rng);
        MatrixXd stacked(m + 3, n);
        VectorXd stacked_b(m + 3);
        stacked << p.A, p.A.row(first), p.A.row(second), weights.transpose() * p.A;
        stacked_b << p.b, p.b(first), p.b(second), weights.dot(p.b);
        std::vector<Index> order(static_cast<std::size_t>(m + 3));
        std::iota(order.begin(), order.end(), Index(0));
        std::shuffle(order.begin(), order.end(), rng);
        MatrixXd redundant(m + 3, n);
        VectorXd redundant_b(m + 3);
        for (Index k = 0; k < m + 3; ++k) {
            redundant.row(k) = stacked.row(order[static_cast<std::size_t>(k)]);
            redundant_b(k) = stacked_b(order[static_cast<std::size_t>(k)]);
        }

        const Solution reference = kkt_solution(p.M, p.A, p.b, p.h_sigma);
        const VectorXd h = coopdyn::udwadia_kalaba(p.M, redundant, redundant_b, p.h_sigma);
        const VectorXd xdd = accelerations_of(p.M, p.h_sigma, h);
        const double error = relative_error(xdd, reference.accelerations);
        EXPECT_LT(error, 1e-10) << "seed " << seed << " n " << n << " m " << m;
        EXPECT_LT(relative_error(h, reference.wrench), 1e-10) << "seed " << seed;
        worst = std::max(worst, error);
    }
    std::printf("[ measured ] UK redundant rows vs independent KKT: worst relative error %.3g\n", worst);
}

TEST(UdwadiaKalaba, RankDeficientConsistentConstraintsWithSingularKkt)
{
    double worst = 0.0;
    for (unsigned seed = 400; seed < 440; ++seed) {
        Rng rng(seed);
        const Index n = random_index(rng, 8, 30);
        const Index m = random_index(rng, 2, n - 5);
        const RandomProblem p = random_problem(rng, n, m);

        // A' = C A, b' = C b with C ((m + 4) x m) of rank m: no row is a copy, the rank is m.
        const MatrixXd mixing = random_matrix(m + 4, m, rng);
        const MatrixXd deficient = mixing * p.A;
        const VectorXd deficient_b = mixing * p.b;
        ASSERT_EQ(Eigen::FullPivLU<MatrixXd>(deficient).rank(), m);

        MatrixXd kkt = MatrixXd::Zero(n + m + 4, n + m + 4);
        kkt.topLeftCorner(n, n) = p.M;
        kkt.topRightCorner(n, m + 4) = deficient.transpose();
        kkt.bottomLeftCorner(m + 4, n) = deficient;
        EXPECT_FALSE(Eigen::FullPivLU<MatrixXd>(kkt).isInvertible()) << "KKT should be singular";

        const Solution reference = kkt_solution(p.M, p.A, p.b, p.h_sigma);
        const VectorXd h = coopdyn::udwadia_kalaba(p.M, deficient, deficient_b, p.h_sigma);
        const VectorXd xdd = accelerations_of(p.M, p.h_sigma, h);
        const double error = relative_error(xdd, reference.accelerations);
        EXPECT_LT(error, 1e-10) << "seed " << seed << " n " << n << " m " << m;
        EXPECT_LT(relative_error(h, reference.wrench), 1e-10) << "seed " << seed;
        EXPECT_LT((deficient * xdd - deficient_b).norm(),
                  1e-12 * (deficient.norm() * xdd.norm() + deficient_b.norm()));
        worst = std::max(worst, error);
    }
    std::printf("[ measured ] UK rank-deficient vs independent KKT: worst relative error %.3g\n", worst);
}

TEST(UdwadiaKalaba, FixedSizeArgumentsAgreeWithDynamic)
{
    Rng rng(500);
    const RandomProblem p = random_problem(rng, 12, 5);
    const Eigen::Matrix<double, 12, 12> M = p.M;
    const Eigen::Matrix<double, 5, 12> A = p.A;
    const Eigen::Matrix<double, 5, 1> b = p.b;
    const Eigen::Matrix<double, 12, 1> h_sigma = p.h_sigma;
    const VectorXd fixed = coopdyn::udwadia_kalaba(M, A, b, h_sigma);
    const VectorXd dynamic = coopdyn::udwadia_kalaba(p.M, p.A, p.b, p.h_sigma);
    EXPECT_LT(relative_error(fixed, dynamic), 1e-14);
    EXPECT_LT(relative_error(fixed, kkt_solution(p.M, p.A, p.b, p.h_sigma).wrench), 1e-10);
}

TEST(UdwadiaKalaba, NoConstraintViolationGivesZeroWrench)
{
    // b = A M^-1 hSigma: the unconstrained motion already satisfies the constraints.
    Rng rng(600);
    const RandomProblem p = random_problem(rng, 18, 7);
    const VectorXd b = p.A * p.M.ldlt().solve(p.h_sigma);
    const VectorXd h = coopdyn::udwadia_kalaba(p.M, p.A, b, p.h_sigma);
    EXPECT_LT(h.norm(), 1e-12 * p.h_sigma.norm());
}

// ---------------------------------------------------------------------------------------------
// try_udwadia_kalaba_full_rank: the constraint-space form for full row rank A.

TEST(UdwadiaKalabaFullRank, MatchesKktSolutionAndItsMultipliers)
{
    double worst_acceleration = 0.0, worst_multipliers = 0.0;
    for (unsigned seed = 700; seed < 760; ++seed) {
        Rng rng(seed);
        const Index n = 6 + static_cast<Index>(seed % 25);  // 6..30
        const Index m = random_index(rng, 1, n - 1);
        const RandomProblem p = random_problem(rng, n, m);
        ASSERT_EQ(Eigen::FullPivLU<MatrixXd>(p.A).rank(), m);

        VectorXd lambda(m), xdd(n);
        ASSERT_TRUE(coopdyn::try_udwadia_kalaba_full_rank(p.M, p.A, p.b, p.h_sigma, lambda, xdd)) << "seed " << seed;
        const Solution reference = kkt_solution(p.M, p.A, p.b, p.h_sigma);
        const double acceleration_error = relative_error(xdd, reference.accelerations);
        const double multiplier_error = relative_error(lambda, reference.multipliers);
        EXPECT_LT(acceleration_error, 1e-10) << "seed " << seed << " n " << n << " m " << m;
        EXPECT_LT(multiplier_error, 1e-9) << "seed " << seed << " n " << n << " m " << m;
        EXPECT_LT(relative_error(VectorXd(p.A.transpose() * lambda), reference.wrench), 1e-10) << "seed " << seed;
        worst_acceleration = std::max(worst_acceleration, acceleration_error);
        worst_multipliers = std::max(worst_multipliers, multiplier_error);
    }
    std::printf("[ measured ] full-rank UK vs KKT: worst relative error accelerations %.3g, multipliers %.3g\n",
                worst_acceleration, worst_multipliers);
}

TEST(UdwadiaKalabaFullRank, FixedSizesOfTheDualArmBoxAgreeWithTheGenericSolver)
{
    // The rigid plant's shape (examples/box): 20 coordinates, 12 weld rows.
    for (unsigned seed = 800; seed < 810; ++seed) {
        Rng rng(seed);
        const RandomProblem p = random_problem(rng, 20, 12);
        const Eigen::Matrix<double, 20, 20> M = p.M;
        const Eigen::Matrix<double, 12, 20> A = p.A;
        const Eigen::Matrix<double, 12, 1> b = p.b;
        const Eigen::Matrix<double, 20, 1> h_sigma = p.h_sigma;
        Eigen::Matrix<double, 12, 1> lambda;
        Eigen::Matrix<double, 20, 1> xdd;
        ASSERT_TRUE(coopdyn::try_udwadia_kalaba_full_rank(M, A, b, h_sigma, lambda, xdd));
        const Eigen::Matrix<double, 20, 1> h = coopdyn::udwadia_kalaba(M, A, b, h_sigma);
        EXPECT_LT(relative_error(VectorXd(A.transpose() * lambda), VectorXd(h)), 1e-10) << "seed " << seed;
        EXPECT_LT(relative_error(VectorXd(xdd), VectorXd(M.llt().solve(h_sigma + h))), 1e-10) << "seed " << seed;
    }
}

TEST(UdwadiaKalabaFullRank, RefusesRankDeficientConstraintsAndIndefiniteInertiaLeavingOutputs)
{
    Rng rng(900);
    const RandomProblem p = random_problem(rng, 14, 6);
    VectorXd lambda = VectorXd::Constant(7, 7.0), xdd = VectorXd::Constant(14, 7.0);

    // A row repeated: S = A M^-1 A^T is singular.
    MatrixXd repeated(7, 14);
    repeated << p.A, p.A.row(2);
    VectorXd repeated_b(7);
    repeated_b << p.b, p.b(2);
    EXPECT_FALSE(coopdyn::try_udwadia_kalaba_full_rank(p.M, repeated, repeated_b, p.h_sigma, lambda, xdd));
    // Nearly repeated (1e-9 apart): refused by the pivot test, not solved with huge multipliers.
    repeated.row(6) += 1e-9 * random_vector(14, rng).transpose();
    EXPECT_FALSE(coopdyn::try_udwadia_kalaba_full_rank(p.M, repeated, repeated_b, p.h_sigma, lambda, xdd));
    EXPECT_TRUE((lambda.array() == 7.0).all());
    EXPECT_TRUE((xdd.array() == 7.0).all());
    // The generic solver handles the repeated row (same accelerations as the independent rows).
    const VectorXd h = coopdyn::udwadia_kalaba(p.M, repeated, repeated_b, p.h_sigma);
    EXPECT_TRUE(h.allFinite());

    // An indefinite M.
    MatrixXd indefinite = p.M;
    indefinite(0, 0) = -1.0;
    VectorXd lambda6 = VectorXd::Constant(6, 7.0);
    EXPECT_FALSE(coopdyn::try_udwadia_kalaba_full_rank(indefinite, p.A, p.b, p.h_sigma, lambda6, xdd));
    EXPECT_TRUE((lambda6.array() == 7.0).all());
}

}  // namespace
