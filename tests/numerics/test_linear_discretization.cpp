// Tests of coopdyn/numerics/linear_discretization.hpp against references it was not derived from
// (it reads Phi and the input moments off one augmented matrix exponential):
// - closed forms: the scalar ODE x' = a x + b u (Phi = e^{aT}, Gamma_0 = b T (e^{aT} - 1) / (aT),
//   Gamma_1 = b T (e^{aT} - 1 - aT) / (aT)^2, evaluated by series near a = 0) and the double
//   integrator (every moment is a polynomial in T);
// - a fine classical Runge-Kutta (RK4) integration of random systems driven by the interpolating
//   polynomial, built here from Lagrange's basis (not from a Vandermonde matrix), for zero-order
//   hold, first-order hold and centred and one-sided cubic windows, over one period and over
//   many periods of a globally cubic input;
// - the defining property of the interpolated input matrix: sum_j W_j node_j^i = Gamma_i.
#include "coopdyn/numerics/linear_discretization.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <vector>

namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;
namespace numerics = coopdyn::numerics;

MatrixXd random_matrix(Index rows, Index cols, std::mt19937& rng)
{
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    MatrixXd result(rows, cols);
    for (Index k = 0; k < result.size(); ++k) {
        result(k) = uniform(rng);
    }
    return result;
}

double relative_difference(const MatrixXd& value, const MatrixXd& reference)
{
    return (value - reference).cwiseAbs().maxCoeff() / std::max(reference.cwiseAbs().maxCoeff(), 1e-300);
}

/// phi_k(x) = sum_{j >= 0} x^j / (j + k)!: phi_1 = (e^x - 1) / x, phi_2 = (e^x - 1 - x) / x^2.
double phi(int k, double x)
{
    if (std::abs(x) > 0.5) {
        return k == 1 ? std::expm1(x) / x : (std::expm1(x) - x) / (x * x);
    }
    double factorial = 1.0;
    for (int j = 2; j <= k; ++j) {
        factorial *= j;
    }
    double term = 1.0 / factorial;
    double sum = 0.0;
    for (int j = 0; j < 30; ++j) {
        sum += term;
        term *= x / static_cast<double>(j + k + 1);
    }
    return sum;
}

/// x(T) of x' = A x + B u(t) by RK4 with `steps` equal steps, u given as a function of sigma = t / T.
VectorXd rk4(const MatrixXd& a, const MatrixXd& b, double period, const std::function<VectorXd(double)>& input,
             VectorXd x, int steps, double sigma_start = 0.0, double sigma_end = 1.0)
{
    const double h = (sigma_end - sigma_start) / static_cast<double>(steps);  // in sigma
    const auto f = [&](double sigma, const VectorXd& state) -> VectorXd {
        return period * (a * state + b * input(sigma));
    };
    for (int i = 0; i < steps; ++i) {
        const double sigma = sigma_start + h * static_cast<double>(i);
        const VectorXd k1 = f(sigma, x);
        const VectorXd k2 = f(sigma + 0.5 * h, x + 0.5 * h * k1);
        const VectorXd k3 = f(sigma + 0.5 * h, x + 0.5 * h * k2);
        const VectorXd k4 = f(sigma + h, x + h * k3);
        x += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    return x;
}

/// The polynomial through (nodes(j), samples.col(j)) at sigma, by Lagrange's basis.
VectorXd lagrange(const VectorXd& nodes, const MatrixXd& samples, double sigma)
{
    VectorXd value = VectorXd::Zero(samples.rows());
    for (Index j = 0; j < nodes.size(); ++j) {
        double basis = 1.0;
        for (Index l = 0; l < nodes.size(); ++l) {
            if (l != j) {
                basis *= (sigma - nodes(l)) / (nodes(j) - nodes(l));
            }
        }
        value += basis * samples.col(j);
    }
    return value;
}

TEST(LinearDiscretization, ScalarClosedForms)
{
    double worst = 0.0;
    const double b = 2.0;
    for (double a : {-50.0, -1.0, -1e-3, 0.0, 0.5, 3.0}) {
        for (double period : {1e-3, 0.1, 1.0}) {
            const double x = a * period;
            const MatrixXd a_matrix = MatrixXd::Constant(1, 1, a);
            const MatrixXd b_matrix = MatrixXd::Constant(1, 1, b);
            const numerics::PolynomialInputDiscretization exact =
                numerics::discretize_polynomial_input(a_matrix, b_matrix, period, 1);
            const double gamma_0 = b * period * phi(1, x);
            const double gamma_1 = b * period * phi(2, x);
            worst = std::max({worst, std::abs(exact.transition(0, 0) / std::exp(x) - 1.0),
                              std::abs(exact.moments[0](0, 0) / gamma_0 - 1.0),
                              std::abs(exact.moments[1](0, 0) / gamma_1 - 1.0)});

            const numerics::LinearDiscretization hold = numerics::discretize_zero_order_hold(a_matrix, b_matrix, period);
            worst = std::max(worst, std::abs(hold.input(0, 0) / gamma_0 - 1.0));
            const numerics::LinearDiscretization ramp = numerics::discretize_first_order_hold(a_matrix, b_matrix, period);
            worst = std::max({worst, std::abs(ramp.input(0, 0) / (gamma_0 - gamma_1) - 1.0),
                              std::abs(ramp.input(0, 1) / gamma_1 - 1.0)});
        }
    }
    std::printf("[ measured ] scalar ODE vs closed forms: worst relative %.2e\n", worst);
    EXPECT_LT(worst, 1e-13);
}

TEST(LinearDiscretization, DoubleIntegratorMoments)
{
    // p'' = u: Phi = [[1, T], [0, 1]], Gamma_i = int_0^T [T - t; 1] (t / T)^i dt
    //        = [T^2 / ((i + 1)(i + 2)); T / (i + 1)].
    MatrixXd a = MatrixXd::Zero(2, 2);
    a(0, 1) = 1.0;
    const MatrixXd b = (MatrixXd(2, 1) << 0.0, 1.0).finished();
    double worst = 0.0;
    for (double period : {1e-3, 0.5, 4.0}) {
        const numerics::PolynomialInputDiscretization exact = numerics::discretize_polynomial_input(a, b, period, 5);
        worst = std::max(worst, relative_difference(exact.transition,
                                                    (MatrixXd(2, 2) << 1.0, period, 0.0, 1.0).finished()));
        for (int i = 0; i <= 5; ++i) {
            const double order = static_cast<double>(i);
            const MatrixXd expected =
                (MatrixXd(2, 1) << period * period / ((order + 1.0) * (order + 2.0)), period / (order + 1.0)).finished();
            worst = std::max(worst, relative_difference(exact.moments[static_cast<std::size_t>(i)], expected));
        }
    }
    std::printf("[ measured ] double integrator: worst relative %.2e over 6 moments\n", worst);
    EXPECT_LT(worst, 1e-14);
}

TEST(LinearDiscretization, RandomSystemsAgainstRungeKutta)
{
    std::mt19937 rng(7);
    const double period = 0.01;
    const std::vector<VectorXd> windows{VectorXd::Zero(1), (VectorXd(2) << 0.0, 1.0).finished(),
                                        (VectorXd(4) << -1.0, 0.0, 1.0, 2.0).finished(),
                                        (VectorXd(4) << 0.0, 1.0, 2.0, 3.0).finished(),
                                        (VectorXd(3) << -2.5, 0.3, 1.0).finished()};
    double worst = 0.0;
    for (const auto& [states, inputs] : {std::pair<Index, Index>{2, 1}, {4, 2}, {6, 1}}) {
        for (int trial = 0; trial < 4; ++trial) {
            const MatrixXd a = (2.0 / period) * random_matrix(states, states, rng) / static_cast<double>(states);
            const MatrixXd b = random_matrix(states, inputs, rng);
            const VectorXd x0 = random_matrix(states, 1, rng);
            for (const VectorXd& nodes : windows) {
                const MatrixXd samples = random_matrix(inputs, nodes.size(), rng);
                const numerics::LinearDiscretization exact =
                    numerics::discretize_interpolated_input(a, b, period, nodes);
                const VectorXd stacked = Eigen::Map<const VectorXd>(samples.data(), samples.size());
                const VectorXd discrete = exact.transition * x0 + exact.input * stacked;
                const VectorXd reference = rk4(a, b, period, [&](double s) { return lagrange(nodes, samples, s); }, x0, 2000);
                worst = std::max(worst, relative_difference(discrete, reference));
            }
        }
    }
    std::printf("[ measured ] random systems, 5 windows, one period vs RK4 (2000 steps): worst relative %.2e\n", worst);
    EXPECT_LT(worst, 5e-14);
}

TEST(LinearDiscretization, CubicWindowIsExactForCubicInputOverManyPeriods)
{
    // u(t) cubic in t: every window's interpolant is u itself, so 40 steps of the recurrence with
    // the centred window reproduce the ODE's solution over 40 periods.
    std::mt19937 rng(31);
    const double period = 0.05;
    const Index states = 3;
    const MatrixXd a = random_matrix(states, states, rng) - 1.5 * MatrixXd::Identity(states, states);
    const MatrixXd b = random_matrix(states, 1, rng);
    const VectorXd coefficients = random_matrix(4, 1, rng);
    const auto input_at = [&](double t) {
        return coefficients(0) + t * (coefficients(1) + t * (coefficients(2) + t * coefficients(3)));
    };
    const numerics::LinearDiscretization exact =
        numerics::discretize_interpolated_input(a, b, period, (VectorXd(4) << -1.0, 0.0, 1.0, 2.0).finished());
    const VectorXd x0 = random_matrix(states, 1, rng);
    VectorXd x = x0;
    const int periods = 40;
    for (int n = 0; n < periods; ++n) {
        VectorXd window(4);
        for (Index j = 0; j < 4; ++j) {
            window(j) = input_at(period * static_cast<double>(n - 1 + j));
        }
        x = exact.transition * x + exact.input * window;
    }
    const VectorXd reference =
        rk4(a, b, period, [&](double sigma) { return VectorXd::Constant(1, input_at(period * sigma)); }, x0,
            200 * periods, 0.0, static_cast<double>(periods));
    const double error = relative_difference(x, reference);
    std::printf("[ measured ] cubic input, 40 periods vs RK4 (8000 steps): relative %.2e\n", error);
    EXPECT_LT(error, 2e-14);
}

TEST(LinearDiscretization, InterpolatedInputReproducesMoments)
{
    // sum_j W_j nodes(j)^i = Gamma_i for i < k: the weights integrate every polynomial of degree < k exactly.
    std::mt19937 rng(41);
    const MatrixXd a = random_matrix(3, 3, rng);
    const MatrixXd b = random_matrix(3, 2, rng);
    const numerics::PolynomialInputDiscretization exact = numerics::discretize_polynomial_input(a, b, 0.3, 3);
    double worst = 0.0;
    for (const VectorXd& nodes : {VectorXd((VectorXd(1) << 0.7).finished()), VectorXd((VectorXd(2) << -1.0, 0.5).finished()),
                                  VectorXd((VectorXd(4) << -2.5, 0.3, 1.0, 4.0).finished())}) {
        const MatrixXd weights = numerics::interpolated_input_matrix(exact, nodes);
        ASSERT_EQ(weights.rows(), 3);
        ASSERT_EQ(weights.cols(), 2 * nodes.size());
        for (Index i = 0; i < nodes.size(); ++i) {
            MatrixXd sum = MatrixXd::Zero(3, 2);
            for (Index j = 0; j < nodes.size(); ++j) {
                sum += std::pow(nodes(j), static_cast<double>(i)) * weights.middleCols(2 * j, 2);
            }
            worst = std::max(worst, relative_difference(sum, exact.moments[static_cast<std::size_t>(i)]));
        }
    }
    std::printf("[ measured ] sum_j W_j node_j^i vs Gamma_i: worst relative %.2e\n", worst);
    EXPECT_LT(worst, 1e-14);
}

}  // namespace
