// Tests of coopdyn/numerics/non_negative_least_squares.hpp against references it was not derived
// from (it is Lawson and Hanson's active-set iteration):
// - the Karush-Kuhn-Tucker conditions of min |A x - b|^2 s.t. x >= 0: x >= 0, w = A^T (b - A x)
//   <= 0, and w_j = 0 where x_j > 0;
// - a brute-force enumeration of every passive set (2^n unconstrained solves, the best feasible
//   one) on small random problems, over- and under-determined;
// - exact recovery of a non-negative solution with zeros, the unconstrained solution when it is
//   positive, and invariance under a rescaling of the columns (units).
// Seeded random problems of several sizes.
#include "coopdyn/numerics/non_negative_least_squares.hpp"

#include <Eigen/QR>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

namespace {

using coopdyn::numerics::non_negative_least_squares;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

MatrixXd random_matrix(Index rows, Index cols, std::mt19937& rng)
{
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    MatrixXd result(rows, cols);
    for (Index k = 0; k < result.size(); ++k) {
        result(k) = uniform(rng);
    }
    return result;
}

/// argmin |A x - b| over x >= 0 by enumerating every passive set (exponential, small n only).
VectorXd brute_force(const MatrixXd& a, const VectorXd& b)
{
    const Index n = a.cols();
    VectorXd best = VectorXd::Zero(n);
    double best_residual = b.squaredNorm();
    for (unsigned mask = 1; mask < (1u << n); ++mask) {
        std::vector<Index> columns;
        for (Index j = 0; j < n; ++j) {
            if ((mask & (1u << j)) != 0u) {
                columns.push_back(j);
            }
        }
        MatrixXd reduced(a.rows(), static_cast<Index>(columns.size()));
        for (std::size_t c = 0; c < columns.size(); ++c) {
            reduced.col(static_cast<Index>(c)) = a.col(columns[c]);
        }
        const VectorXd solution = reduced.completeOrthogonalDecomposition().solve(b);
        if ((solution.array() < 0.0).any()) {
            continue;
        }
        VectorXd x = VectorXd::Zero(n);
        for (std::size_t c = 0; c < columns.size(); ++c) {
            x(columns[c]) = solution(static_cast<Index>(c));
        }
        const double residual = (a * x - b).squaredNorm();
        if (residual < best_residual) {
            best_residual = residual;
            best = x;
        }
    }
    return best;
}

/// Largest violation of the KKT conditions, relative to |A| |b|.
double kkt_violation(const MatrixXd& a, const VectorXd& b, const VectorXd& x)
{
    const VectorXd w = a.transpose() * (b - a * x);
    double worst = 0.0;
    for (Index j = 0; j < x.size(); ++j) {
        worst = std::max(worst, x(j) > 0.0 ? std::abs(w(j)) : std::max(0.0, w(j)));
        worst = std::max(worst, -x(j));
    }
    return worst / (a.norm() * b.norm());
}

TEST(NonNegativeLeastSquares, KktConditionsAndBruteForceOverdetermined)
{
    std::mt19937 rng(2024);
    double worst_kkt = 0.0;
    double worst_brute = 0.0;
    int active_bounds = 0;
    for (Index n : {1, 2, 3, 5, 8}) {
        for (int trial = 0; trial < 30; ++trial) {
            const MatrixXd a = random_matrix(n + 4, n, rng);
            const VectorXd b = random_matrix(n + 4, 1, rng);
            const VectorXd x = non_negative_least_squares(a, b);
            ASSERT_EQ(x.size(), n);
            EXPECT_TRUE((x.array() >= 0.0).all());
            worst_kkt = std::max(worst_kkt, kkt_violation(a, b, x));
            active_bounds += static_cast<int>((x.array() == 0.0).count());
            const VectorXd reference = brute_force(a, b);
            worst_brute = std::max(worst_brute, (x - reference).cwiseAbs().maxCoeff() / std::max(1.0, reference.norm()));
        }
    }
    std::printf("[ measured ] NNLS, m = n + 4: worst KKT violation %.2e, worst difference to brute force %.2e, "
                "%d active bounds\n",
                worst_kkt, worst_brute, active_bounds);
    EXPECT_LT(worst_kkt, 1e-14);
    EXPECT_LT(worst_brute, 1e-14);
    EXPECT_GT(active_bounds, 100);  // the bounds really are exercised
}

TEST(NonNegativeLeastSquares, UnderdeterminedMatchesBruteForceResidual)
{
    // m < n: the minimiser is not unique; its residual is.
    std::mt19937 rng(99);
    double worst_kkt = 0.0;
    double worst_residual = 0.0;
    for (const auto& [rows, columns] : {std::pair<Index, Index>{2, 4}, {3, 6}, {4, 7}}) {
        for (int trial = 0; trial < 20; ++trial) {
            const MatrixXd a = random_matrix(rows, columns, rng);
            const VectorXd b = random_matrix(rows, 1, rng);
            const VectorXd x = non_negative_least_squares(a, b);
            worst_kkt = std::max(worst_kkt, kkt_violation(a, b, x));
            const double residual = (a * x - b).norm();
            const double reference = (a * brute_force(a, b) - b).norm();
            worst_residual = std::max(worst_residual, std::abs(residual - reference) / b.norm());
        }
    }
    std::printf("[ measured ] NNLS, m < n: worst KKT violation %.2e, worst residual difference to brute force %.2e\n",
                worst_kkt, worst_residual);
    EXPECT_LT(worst_kkt, 1e-14);
    EXPECT_LT(worst_residual, 1e-14);
}

TEST(NonNegativeLeastSquares, ExactAndUnconstrainedSolutions)
{
    std::mt19937 rng(5);
    double worst_exact = 0.0;
    double worst_unconstrained = 0.0;
    for (Index n : {2, 4, 7}) {
        for (int trial = 0; trial < 10; ++trial) {
            const MatrixXd a = random_matrix(2 * n, n, rng);
            // b = A x_true with x_true >= 0 and half its entries zero: found exactly.
            VectorXd truth = random_matrix(n, 1, rng).cwiseAbs();
            for (Index j = 0; j < n; j += 2) {
                truth(j) = 0.0;
            }
            const VectorXd exact = non_negative_least_squares(a, a * truth);
            worst_exact = std::max(worst_exact, (exact - truth).cwiseAbs().maxCoeff() / truth.norm());
            // An unconstrained minimiser that is positive is the answer.
            const VectorXd positive = VectorXd::Constant(n, 1.0) + random_matrix(n, 1, rng).cwiseAbs();
            const VectorXd b = a * positive + 1e-3 * random_matrix(2 * n, 1, rng);
            const VectorXd least_squares = a.colPivHouseholderQr().solve(b);
            ASSERT_TRUE((least_squares.array() > 0.0).all());
            worst_unconstrained = std::max(worst_unconstrained, (non_negative_least_squares(a, b) - least_squares)
                                                                        .cwiseAbs()
                                                                        .maxCoeff() /
                                                                    least_squares.norm());
        }
    }
    std::printf("[ measured ] NNLS: exact non-negative solution recovered to %.2e, positive unconstrained to %.2e\n",
                worst_exact, worst_unconstrained);
    EXPECT_LT(worst_exact, 5e-15);
    EXPECT_LT(worst_unconstrained, 5e-15);
}

TEST(NonNegativeLeastSquares, IndependentOfColumnUnits)
{
    // Scaling column j by s_j scales x_j by 1 / s_j (a stiffness in N/m or in N/um).
    std::mt19937 rng(8);
    const MatrixXd a = random_matrix(9, 5, rng);
    const VectorXd b = random_matrix(9, 1, rng);
    const VectorXd scales = (VectorXd(5) << 1e-6, 1.0, 1e3, 1e8, 0.5).finished();
    const VectorXd x = non_negative_least_squares(a, b);
    const VectorXd scaled = non_negative_least_squares(a * scales.asDiagonal(), b);
    const double difference = (scaled.cwiseProduct(scales) - x).cwiseAbs().maxCoeff() / x.norm();
    std::printf("[ measured ] NNLS: column scalings 1e-6 .. 1e8 change x by %.2e relative\n", difference);
    EXPECT_LT(difference, 5e-15);
    EXPECT_EQ((x.array() == 0.0).count(), (scaled.array() == 0.0).count());
}

TEST(NonNegativeLeastSquares, DegenerateInputs)
{
    const MatrixXd a = (MatrixXd(3, 3) << 1.0, 0.0, 2.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0).finished();
    // Zero right-hand side: x = 0.
    EXPECT_EQ(non_negative_least_squares(a, VectorXd::Zero(3)), VectorXd::Zero(3));
    // A zero column gets x_j = 0.
    const VectorXd x = non_negative_least_squares(a, VectorXd::Ones(3));
    EXPECT_EQ(x(1), 0.0);
    EXPECT_LT(kkt_violation(a, VectorXd::Ones(3), x), 1e-15);
    // No unknowns.
    EXPECT_EQ(non_negative_least_squares(MatrixXd(3, 0), VectorXd::Ones(3)).size(), 0);
    // Every column points away from b: x = 0.
    EXPECT_EQ(non_negative_least_squares(-MatrixXd::Identity(2, 2), VectorXd::Ones(2)), VectorXd::Zero(2));
    // Duplicate columns (rank deficient): the residual is still minimal.
    const MatrixXd twins = (MatrixXd(3, 2) << 1.0, 1.0, 2.0, 2.0, 0.0, 0.0).finished();
    const VectorXd y = non_negative_least_squares(twins, (VectorXd(3) << 1.0, 2.0, 5.0).finished());
    EXPECT_NEAR(y.sum(), 1.0, 1e-14);
    EXPECT_TRUE((y.array() >= 0.0).all());
}

}  // namespace
