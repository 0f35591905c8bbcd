// Tests of coopdyn/numerics/levenberg_marquardt.hpp on problems with known minimisers:
// - Rosenbrock's function (More, Garbow and Hillstrom 1981, problem 1) from (-1.2, 1): (1, 1);
// - Powell's badly scaled function (problem 3) from (0, 1): zero residual at
//   (1.098159e-5, 9.106146), parameters five orders of magnitude apart;
// - curve fits with seeded random true parameters (exponential decay with offset, damped
//   sinusoid) from noise-free data: the parameters come back; from noisy data: the cost is at
//   most the cost at the truth and the gradient vanishes;
// - a linear least-squares problem: the QR solution;
// - the stopping rules: zero iterations, a start where the cost is not defined, a cost that is
//   undefined on part of the parameter space.
#include "coopdyn/numerics/levenberg_marquardt.hpp"

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
namespace numerics = coopdyn::numerics;

/// Levenberg-Marquardt on residuals r(theta) with their exact Jacobian J(theta).
template <typename Residuals, typename Jacobian>
numerics::LevenbergMarquardtResult fit(const VectorXd& start, Residuals residuals, Jacobian jacobian,
                                       numerics::LevenbergMarquardtOptions options = {1e-12, 500})
{
    return numerics::levenberg_marquardt(
        start, [&](const VectorXd& theta) { return residuals(theta).squaredNorm(); },
        [&](const VectorXd& theta) { return numerics::normal_equations(residuals(theta), jacobian(theta)); }, options);
}

TEST(LevenbergMarquardt, Rosenbrock)
{
    const auto residuals = [](const VectorXd& p) {
        return VectorXd((VectorXd(2) << 10.0 * (p(1) - p(0) * p(0)), 1.0 - p(0)).finished());
    };
    const auto jacobian = [](const VectorXd& p) {
        return MatrixXd((MatrixXd(2, 2) << -20.0 * p(0), 10.0, -1.0, 0.0).finished());
    };
    const auto result = fit(Eigen::Vector2d(-1.2, 1.0), residuals, jacobian);
    std::printf("[ measured ] Rosenbrock: (%.15f, %.15f), cost %.2e after %d iterations\n", result.parameters(0),
                result.parameters(1), result.cost, result.iterations);
    EXPECT_TRUE(result.converged);
    EXPECT_NEAR(result.parameters(0), 1.0, 1e-10);
    EXPECT_NEAR(result.parameters(1), 1.0, 1e-10);
    EXPECT_NEAR(result.initial_cost, 24.2, 1e-12);  // 10^2 (1 - 1.44)^2 + 2.2^2
}

TEST(LevenbergMarquardt, PowellBadlyScaled)
{
    const auto residuals = [](const VectorXd& p) {
        return VectorXd(
            (VectorXd(2) << 1e4 * p(0) * p(1) - 1.0, std::exp(-p(0)) + std::exp(-p(1)) - 1.0001).finished());
    };
    const auto jacobian = [](const VectorXd& p) {
        return MatrixXd((MatrixXd(2, 2) << 1e4 * p(1), 1e4 * p(0), -std::exp(-p(0)), -std::exp(-p(1))).finished());
    };
    const auto result = fit(Eigen::Vector2d(0.0, 1.0), residuals, jacobian);
    std::printf("[ measured ] Powell badly scaled: (%.7e, %.7f), cost %.2e after %d iterations\n",
                result.parameters(0), result.parameters(1), result.cost, result.iterations);
    EXPECT_TRUE(result.converged);
    EXPECT_LT(result.cost, 1e-24);
    EXPECT_NEAR(result.parameters(0) / 1.098159e-5, 1.0, 1e-6);
    EXPECT_NEAR(result.parameters(1) / 9.106146, 1.0, 1e-6);
}

/// y = a e^{-b t} + c.
VectorXd decay(const VectorXd& p, const VectorXd& t) { return (p(0) * (-p(1) * t.array()).exp() + p(2)).matrix(); }

MatrixXd decay_jacobian(const VectorXd& p, const VectorXd& t)
{
    MatrixXd j(t.size(), 3);
    j.col(0) = (-p(1) * t.array()).exp().matrix();
    j.col(1) = (-p(0) * t.array() * (-p(1) * t.array()).exp()).matrix();
    j.col(2).setOnes();
    return j;
}

/// y = a e^{-b t} sin(w t + phi).
VectorXd damped_sine(const VectorXd& p, const VectorXd& t)
{
    return (p(0) * (-p(1) * t.array()).exp() * (p(2) * t.array() + p(3)).sin()).matrix();
}

MatrixXd damped_sine_jacobian(const VectorXd& p, const VectorXd& t)
{
    const Eigen::ArrayXd envelope = (-p(1) * t.array()).exp();
    const Eigen::ArrayXd sine = (p(2) * t.array() + p(3)).sin();
    const Eigen::ArrayXd cosine = (p(2) * t.array() + p(3)).cos();
    MatrixXd j(t.size(), 4);
    j.col(0) = (envelope * sine).matrix();
    j.col(1) = (-p(0) * t.array() * envelope * sine).matrix();
    j.col(2) = (p(0) * t.array() * envelope * cosine).matrix();
    j.col(3) = (p(0) * envelope * cosine).matrix();
    return j;
}

TEST(LevenbergMarquardt, CurveFitsRecoverKnownParameters)
{
    std::mt19937 rng(12);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    std::uniform_real_distribution<double> perturbation(0.8, 1.2);
    const VectorXd t = VectorXd::LinSpaced(60, 0.0, 4.0);
    double worst_decay = 0.0;
    double worst_sine = 0.0;
    for (int trial = 0; trial < 8; ++trial) {
        const VectorXd decay_truth = (VectorXd(3) << 1.0 + 3.0 * uniform(rng), 0.3 + 2.0 * uniform(rng),
                                      -1.0 + 2.0 * uniform(rng)).finished();
        const VectorXd decay_data = decay(decay_truth, t);
        VectorXd start = decay_truth.cwiseProduct(VectorXd::NullaryExpr(3, [&] { return perturbation(rng); }));
        const auto decay_fit = fit(
            start, [&](const VectorXd& p) { return VectorXd(decay(p, t) - decay_data); },
            [&](const VectorXd& p) { return decay_jacobian(p, t); });
        EXPECT_TRUE(decay_fit.converged);
        worst_decay = std::max(worst_decay, (decay_fit.parameters - decay_truth).cwiseAbs().maxCoeff());

        const VectorXd sine_truth = (VectorXd(4) << 0.5 + uniform(rng), 0.1 + 0.5 * uniform(rng),
                                     2.0 + 3.0 * uniform(rng), uniform(rng)).finished();
        const VectorXd sine_data = damped_sine(sine_truth, t);
        start = sine_truth.cwiseProduct(VectorXd::NullaryExpr(4, [&] { return 0.95 + 0.1 * uniform(rng); }));
        const auto sine_fit = fit(
            start, [&](const VectorXd& p) { return VectorXd(damped_sine(p, t) - sine_data); },
            [&](const VectorXd& p) { return damped_sine_jacobian(p, t); });
        EXPECT_TRUE(sine_fit.converged);
        worst_sine = std::max(worst_sine, (sine_fit.parameters - sine_truth).cwiseAbs().maxCoeff());
    }
    std::printf("[ measured ] noise-free fits: decay parameters to %.2e, damped sine parameters to %.2e\n",
                worst_decay, worst_sine);
    EXPECT_LT(worst_decay, 1e-10);
    EXPECT_LT(worst_sine, 1e-10);
}

TEST(LevenbergMarquardt, NoisyCurveFitIsAStationaryMinimum)
{
    std::mt19937 rng(77);
    std::normal_distribution<double> noise(0.0, 0.05);
    const VectorXd t = VectorXd::LinSpaced(200, 0.0, 5.0);
    const VectorXd truth = (VectorXd(4) << 1.3, 0.4, 3.1, 0.6).finished();
    const VectorXd data = damped_sine(truth, t) + VectorXd::NullaryExpr(t.size(), [&] { return noise(rng); });
    const auto residuals = [&](const VectorXd& p) { return VectorXd(damped_sine(p, t) - data); };
    const auto jacobian = [&](const VectorXd& p) { return damped_sine_jacobian(p, t); };
    const auto result = fit(VectorXd((VectorXd(4) << 1.0, 0.3, 3.0, 0.5).finished()), residuals, jacobian);
    const MatrixXd j = jacobian(result.parameters);
    const VectorXd r = residuals(result.parameters);
    // Cosine between the residual and each Jacobian column: zero at a stationary point.
    const double cosine =
        (j.transpose() * r).cwiseAbs().cwiseQuotient(j.colwise().norm().transpose()).maxCoeff() / r.norm();
    std::printf("[ measured ] noisy damped sine: cost %.6f (at the truth %.6f), largest cosine %.2e, parameter "
                "errors %.2e\n",
                result.cost, residuals(truth).squaredNorm(), cosine, (result.parameters - truth).cwiseAbs().maxCoeff());
    EXPECT_TRUE(result.converged);
    EXPECT_LE(result.cost, residuals(truth).squaredNorm());
    EXPECT_LT(cosine, 1e-9);
    EXPECT_LT((result.parameters - truth).cwiseAbs().maxCoeff(), 0.05);
}

TEST(LevenbergMarquardt, LinearLeastSquaresGivesTheQrSolution)
{
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    double worst = 0.0;
    for (Index n : {1, 3, 6}) {
        const MatrixXd a = MatrixXd::NullaryExpr(3 * n, n, [&] { return uniform(rng); });
        const VectorXd b = VectorXd::NullaryExpr(3 * n, [&] { return uniform(rng); });
        const auto result = fit(
            VectorXd::Zero(n), [&](const VectorXd& p) { return VectorXd(a * p - b); },
            [&](const VectorXd&) { return a; });
        const VectorXd reference = a.colPivHouseholderQr().solve(b);
        EXPECT_TRUE(result.converged);
        worst = std::max(worst, (result.parameters - reference).cwiseAbs().maxCoeff() / reference.norm());
    }
    std::printf("[ measured ] linear least squares vs QR: worst relative %.2e\n", worst);
    EXPECT_LT(worst, 1e-9);
}

TEST(LevenbergMarquardt, StoppingRules)
{
    const auto residuals = [](const VectorXd& p) {
        return VectorXd((VectorXd(2) << 10.0 * (p(1) - p(0) * p(0)), 1.0 - p(0)).finished());
    };
    const auto jacobian = [](const VectorXd& p) {
        return MatrixXd((MatrixXd(2, 2) << -20.0 * p(0), 10.0, -1.0, 0.0).finished());
    };
    const VectorXd start = Eigen::Vector2d(-1.2, 1.0);

    // Zero iterations: the start, its cost, not converged.
    const auto none = fit(start, residuals, jacobian, {1e-12, 0});
    EXPECT_EQ(none.parameters, start);
    EXPECT_EQ(none.cost, none.initial_cost);
    EXPECT_EQ(none.iterations, 0);
    EXPECT_FALSE(none.converged);

    // The cost is not defined at the start: returned untouched.
    const auto undefined = numerics::levenberg_marquardt(
        start, [](const VectorXd&) { return std::numeric_limits<double>::infinity(); },
        [](const VectorXd&) { return numerics::NormalEquations{std::numeric_limits<double>::infinity(), {}, {}}; });
    EXPECT_EQ(undefined.parameters, start);
    EXPECT_FALSE(undefined.converged);
    EXPECT_EQ(undefined.iterations, 0);

    // A cost undefined for x < 0.5 (e.g. a model that cannot be simulated there): steps into that
    // region are rejected, and the minimiser (1, 1) is still found from (2, 0).
    const auto guarded = numerics::levenberg_marquardt(
        Eigen::Vector2d(2.0, 0.0).eval(),
        [&](const VectorXd& p) {
            return p(0) < 0.5 ? std::numeric_limits<double>::infinity() : residuals(p).squaredNorm();
        },
        [&](const VectorXd& p) { return numerics::normal_equations(residuals(p), jacobian(p)); },
        numerics::LevenbergMarquardtOptions{1e-12, 500});
    EXPECT_TRUE(guarded.converged);
    EXPECT_NEAR(guarded.parameters(0), 1.0, 1e-10);

    // Already at the minimum: converged without a step.
    const auto at_minimum = fit(Eigen::Vector2d(1.0, 1.0), residuals, jacobian);
    EXPECT_TRUE(at_minimum.converged);
    EXPECT_EQ(at_minimum.iterations, 0);
}

}  // namespace
