// The generic numerics (include/coopdyn/numerics/) against references they were not derived
// from: closed forms of the matrix exponential (Rodrigues' formula, nilpotent and diagonal
// matrices) and its semigroup property; the Karush-Kuhn-Tucker conditions and a brute-force
// enumeration of active sets for non-negative least squares; the known minimisers of
// Rosenbrock's function and of a noise-free exponential fit for Levenberg-Marquardt.
#include "coopdyn/numerics/levenberg_marquardt.hpp"
#include "coopdyn/numerics/matrix_exponential.hpp"
#include "coopdyn/numerics/non_negative_least_squares.hpp"

#include <Eigen/Geometry>
#include <Eigen/QR>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

namespace {

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

TEST(MatrixExponential, RodriguesFormulaForRotationGenerators)
{
    std::mt19937 rng(11);
    double worst = 0.0;
    for (int trial = 0; trial < 50; ++trial) {
        Eigen::Vector3d axis = random_matrix(3, 1, rng);
        axis.normalize();
        const double angle = 0.01 + 6.0 * std::abs(random_matrix(1, 1, rng)(0));  // up to about 2 pi
        Eigen::Matrix3d generator;
        generator << 0, -axis(2), axis(1), axis(2), 0, -axis(0), -axis(1), axis(0), 0;
        const MatrixXd exponential = coopdyn::numerics::matrix_exponential(MatrixXd(angle * generator));
        const Eigen::Matrix3d rodrigues = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
        worst = std::max(worst, (exponential - rodrigues).cwiseAbs().maxCoeff());
    }
    std::printf("[ measured ] exp(theta S(u)) vs Rodrigues: worst %.2e\n", worst);
    EXPECT_LT(worst, 1e-13);
}

TEST(MatrixExponential, NilpotentDiagonalAndSemigroup)
{
    // Nilpotent: exp(N) = I + N + N^2 / 2 exactly for a strictly upper triangular 3x3.
    MatrixXd nilpotent = MatrixXd::Zero(3, 3);
    nilpotent(0, 1) = 2.0;
    nilpotent(1, 2) = -3.0;
    nilpotent(0, 2) = 0.5;
    const MatrixXd expected = MatrixXd::Identity(3, 3) + nilpotent + 0.5 * nilpotent * nilpotent;
    EXPECT_LT((coopdyn::numerics::matrix_exponential(nilpotent) - expected).cwiseAbs().maxCoeff(), 1e-14);

    // Diagonal: exp of the entries, relative, across scales that need many squarings.
    const VectorXd diagonal = (VectorXd(4) << -50.0, -1e-3, 0.7, 20.0).finished();
    const MatrixXd diagonal_exponential = coopdyn::numerics::matrix_exponential(MatrixXd(diagonal.asDiagonal()));
    for (Index k = 0; k < 4; ++k) {
        EXPECT_NEAR(diagonal_exponential(k, k) / std::exp(diagonal(k)), 1.0, 1e-13) << diagonal(k);
    }

    // exp(A (s + t)) = exp(A s) exp(A t), random A (the damped oscillator shape and general).
    std::mt19937 rng(3);
    double worst = 0.0;
    for (int trial = 0; trial < 30; ++trial) {
        const MatrixXd a = 3.0 * random_matrix(4, 4, rng);
        const MatrixXd whole = coopdyn::numerics::matrix_exponential(MatrixXd(0.7 * a));
        const MatrixXd split =
            coopdyn::numerics::matrix_exponential(MatrixXd(0.3 * a)) * coopdyn::numerics::matrix_exponential(MatrixXd(0.4 * a));
        worst = std::max(worst, (whole - split).cwiseAbs().maxCoeff() / whole.cwiseAbs().maxCoeff());
    }
    std::printf("[ measured ] exp(0.7 A) vs exp(0.3 A) exp(0.4 A): worst relative %.2e\n", worst);
    EXPECT_LT(worst, 1e-13);

    // Refusals are NaN, never a wrong finite number.
    MatrixXd infinite = MatrixXd::Identity(2, 2);
    infinite(0, 0) = std::numeric_limits<double>::infinity();
    EXPECT_FALSE(coopdyn::numerics::matrix_exponential(infinite).allFinite());
}

/// argmin |A x - b| over x >= 0 by enumerating every passive set (exponential, for small n).
VectorXd brute_force_nnls(const MatrixXd& a, const VectorXd& b)
{
    const Index n = a.cols();
    VectorXd best = VectorXd::Zero(n);
    double best_residual = b.squaredNorm();
    for (unsigned mask = 1; mask < (1u << n); ++mask) {
        std::vector<Index> columns;
        for (Index j = 0; j < n; ++j) {
            if (mask & (1u << j)) {
                columns.push_back(j);
            }
        }
        MatrixXd reduced(a.rows(), static_cast<Index>(columns.size()));
        for (std::size_t c = 0; c < columns.size(); ++c) {
            reduced.col(static_cast<Index>(c)) = a.col(columns[c]);
        }
        const VectorXd solution = reduced.colPivHouseholderQr().solve(b);
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

TEST(NonNegativeLeastSquares, KktConditionsAndBruteForce)
{
    std::mt19937 rng(2024);
    double worst_kkt = 0.0;
    double worst_brute = 0.0;
    int active_constraints = 0;
    for (Index n : {1, 2, 4, 6}) {
        for (int trial = 0; trial < 25; ++trial) {
            const MatrixXd a = random_matrix(n + 5, n, rng);
            const VectorXd b = random_matrix(n + 5, 1, rng);
            const VectorXd x = coopdyn::numerics::non_negative_least_squares(a, b);
            ASSERT_EQ(x.size(), n);
            EXPECT_TRUE((x.array() >= 0.0).all());
            // KKT: w = A^T (b - A x) <= 0, and w_j = 0 where x_j > 0.
            const VectorXd w = a.transpose() * (b - a * x);
            const double scale = a.norm() * b.norm();
            for (Index j = 0; j < n; ++j) {
                const double violation = x(j) > 0.0 ? std::abs(w(j)) : std::max(0.0, w(j));
                worst_kkt = std::max(worst_kkt, violation / scale);
                active_constraints += x(j) == 0.0 ? 1 : 0;
            }
            const VectorXd reference = brute_force_nnls(a, b);
            worst_brute = std::max(worst_brute, (x - reference).cwiseAbs().maxCoeff() / std::max(1.0, reference.norm()));
        }
    }
    std::printf("[ measured ] NNLS: worst KKT violation %.2e, worst difference to brute force %.2e, %d active bounds\n",
                worst_kkt, worst_brute, active_constraints);
    EXPECT_LT(worst_kkt, 1e-12);
    EXPECT_LT(worst_brute, 1e-10);
    EXPECT_GT(active_constraints, 20);  // the bounds really are exercised
}

/// Runs levenberg_marquardt on residuals r(theta) with a forward-difference-free, exact Jacobian.
template <int Size, typename Residuals, typename Jacobian>
coopdyn::numerics::LevenbergMarquardtResult fit(Eigen::Matrix<double, Size, 1>& theta, Residuals residuals,
                                                 Jacobian jacobian)
{
    Eigen::Matrix<double, Size, Size> normal;
    Eigen::Matrix<double, Size, 1> gradient;
    const auto cost_at = [&](const Eigen::Matrix<double, Size, 1>& p) { return residuals(p).squaredNorm(); };
    const auto linearise_at = [&](const Eigen::Matrix<double, Size, 1>& p) {
        const MatrixXd j = jacobian(p);
        const VectorXd r = residuals(p);
        normal = j.transpose() * j;
        gradient = j.transpose() * r;
        return r.squaredNorm();
    };
    const double initial = linearise_at(theta);
    return coopdyn::numerics::levenberg_marquardt(theta, initial, Size, cost_at, linearise_at, normal, gradient,
                                                  1e-12, 500);
}

TEST(LevenbergMarquardt, RosenbrockAndExponentialFit)
{
    // Rosenbrock: r = (10 (y - x^2), 1 - x), minimum 0 at (1, 1), started in the curved valley.
    Eigen::Vector2d theta(-1.2, 1.0);
    const auto rosenbrock = [](const Eigen::Vector2d& p) {
        return VectorXd((VectorXd(2) << 10.0 * (p(1) - p(0) * p(0)), 1.0 - p(0)).finished());
    };
    const auto rosenbrock_jacobian = [](const Eigen::Vector2d& p) {
        return MatrixXd((MatrixXd(2, 2) << -20.0 * p(0), 10.0, -1.0, 0.0).finished());
    };
    const auto result = fit<2>(theta, rosenbrock, rosenbrock_jacobian);
    std::printf("[ measured ] Rosenbrock: (%.12f, %.12f) after %d iterations\n", theta(0), theta(1), result.iterations);
    EXPECT_TRUE(result.converged);
    EXPECT_NEAR(theta(0), 1.0, 1e-8);
    EXPECT_NEAR(theta(1), 1.0, 1e-8);

    // y = a exp(-b t) + c sampled without noise: the parameters come back.
    const VectorXd t = VectorXd::LinSpaced(40, 0.0, 4.0);
    const Eigen::Vector3d truth(2.5, 1.3, -0.4);
    const auto model = [&](const Eigen::Vector3d& p) {
        return VectorXd((p(0) * (-p(1) * t.array()).exp() + p(2)).matrix());
    };
    const VectorXd data = model(truth);
    const auto residuals = [&](const Eigen::Vector3d& p) { return VectorXd(model(p) - data); };
    const auto jacobian = [&](const Eigen::Vector3d& p) {
        MatrixXd j(t.size(), 3);
        j.col(0) = (-p(1) * t.array()).exp().matrix();
        j.col(1) = (-p(0) * t.array() * (-p(1) * t.array()).exp()).matrix();
        j.col(2).setOnes();
        return j;
    };
    Eigen::Vector3d start(1.0, 0.5, 0.0);
    const auto fitted = fit<3>(start, residuals, jacobian);
    EXPECT_TRUE(fitted.converged);
    EXPECT_LT((start - truth).cwiseAbs().maxCoeff(), 1e-8) << start.transpose();
}

}  // namespace
