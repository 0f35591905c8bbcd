/// \file
/// \brief Exact discretisation and simulation of one axis of the apparent impedance,
/// m pdd + d pd + k p = f (the 1-DOF projection of (52), docs/analysis.md), on a uniform sample
/// grid, with the output error's Gauss-Newton normal equations: the model the identification
/// (identification.hpp) fits.
#pragma once

#include "coopdyn/numerics/matrix_exponential.hpp"

#include <Eigen/Core>
#include <Eigen/LU>

#include <cmath>
#include <limits>

namespace coopdyn {

/// \brief How the sampled force is interpolated between samples by the output-error simulation.
enum class ForceInterpolation {
    zero_order_hold,  ///< f(t) = f[n] on [nT, (n+1)T)
    linear,           ///< first-order hold: straight line between f[n] and f[n+1]
    cubic             ///< cubic through the four nearest samples (default)
};

namespace detail {

/// Number of force samples that define the interpolant on one sample interval.
inline int interpolation_points(ForceInterpolation interpolation) noexcept
{
    switch (interpolation) {
    case ForceInterpolation::zero_order_hold: return 1;
    case ForceInterpolation::linear: return 2;
    case ForceInterpolation::cubic: return 4;
    }
    return 4;
}

/// Exact discretisation, over one sample period, of the model x' = A x + B f (x = [p; v]) together
/// with its sensitivities s_m, s_d, s_k (z = [x; s_m; s_d; s_k], 8 states) for a polynomial force
/// interpolated through `points` samples. One step: z[n+1] = transition z[n] + input[v] f_window,
/// where the window starts at sample n - v (v = 0, except for cubic: 1 inside, 0 on the first
/// interval, 2 on the last).
struct ImpedanceDiscretization {
    int points = 4;
    int variants = 3;
    std::array<double, 64> transition{};                ///< 8x8, row-major
    std::array<std::array<double, 32>, 3> input{};      ///< per variant: 8 x points, row-major (stride 4)
};

/// Fills `out` for (m, d, k) and period T. Returns false (out unusable) when m <= 0 or the
/// exponential is not finite.
inline bool discretize_impedance(double mass, double damping, double stiffness, double sample_period,
                                 ForceInterpolation interpolation, ImpedanceDiscretization& out)
{
    if (!(mass > 0.0) || !std::isfinite(mass) || !std::isfinite(damping) || !std::isfinite(stiffness)) {
        return false;
    }
    const int points = interpolation_points(interpolation);
    const Eigen::Index size = 8 + points;
    const double t = sample_period;
    const double inverse_mass = 1.0 / mass;
    const double inverse_mass_squared = inverse_mass * inverse_mass;

    // Continuous augmented matrix times T. States: [x; s_m; s_d; s_k; u_0 .. u_{q-1}], where
    // u_i = T^i d^i f / dt^i (derivatives in the sample-normalised time sigma = t / T), so the
    // input chain is u_i' = u_{i+1} / T and f = u_0.
    Eigen::MatrixXd z = Eigen::MatrixXd::Zero(size, size);
    Eigen::Matrix2d a;
    a << 0.0, 1.0, -stiffness * inverse_mass, -damping * inverse_mass;
    Eigen::Matrix2d a_mass;  // dA/dm
    a_mass << 0.0, 0.0, stiffness * inverse_mass_squared, damping * inverse_mass_squared;
    Eigen::Matrix2d a_damping;  // dA/dd
    a_damping << 0.0, 0.0, 0.0, -inverse_mass;
    Eigen::Matrix2d a_stiffness;  // dA/dk
    a_stiffness << 0.0, 0.0, -inverse_mass, 0.0;
    for (Eigen::Index block = 0; block < 4; ++block) {
        z.block<2, 2>(2 * block, 2 * block) = a * t;
    }
    z.block<2, 2>(2, 0) = a_mass * t;
    z.block<2, 2>(4, 0) = a_damping * t;
    z.block<2, 2>(6, 0) = a_stiffness * t;
    z(1, 8) = inverse_mass * t;            // B = [0; 1/m]
    z(3, 8) = -inverse_mass_squared * t;   // dB/dm = [0; -1/m^2]
    for (Eigen::Index i = 0; i + 1 < points; ++i) {
        z(8 + i, 9 + i) = 1.0;
    }
    const Eigen::MatrixXd exponential = numerics::matrix_exponential(z);
    if (!exponential.allFinite()) {
        return false;
    }
    // z[n+1] = Phi z[n] + Psi u(0); u(0) = C f_window, C = diag(i!) V^-1 with V_ji = node_j^i
    // the Vandermonde matrix of the window's nodes (in sample units relative to sample n).
    const Eigen::MatrixXd psi = exponential.topRightCorner(8, points);
    out.points = points;
    out.variants = interpolation == ForceInterpolation::cubic ? 3 : 1;
    for (Eigen::Index row = 0; row < 8; ++row) {
        for (Eigen::Index column = 0; column < 8; ++column) {
            out.transition[static_cast<std::size_t>(8 * row + column)] = exponential(row, column);
        }
    }
    for (int variant = 0; variant < out.variants; ++variant) {
        Eigen::MatrixXd vandermonde(points, points);
        for (Eigen::Index j = 0; j < points; ++j) {
            const double node = static_cast<double>(j - variant);
            double power = 1.0;
            for (Eigen::Index i = 0; i < points; ++i) {
                vandermonde(j, i) = power;
                power *= node;
            }
        }
        Eigen::MatrixXd coefficients = vandermonde.fullPivLu().inverse();
        double factorial = 1.0;
        for (Eigen::Index i = 0; i < points; ++i) {
            factorial *= i > 0 ? static_cast<double>(i) : 1.0;
            coefficients.row(i) *= factorial;
        }
        const Eigen::MatrixXd gamma = psi * coefficients;
        auto& input = out.input[static_cast<std::size_t>(variant)];
        for (Eigen::Index row = 0; row < 8; ++row) {
            for (Eigen::Index j = 0; j < points; ++j) {
                input[static_cast<std::size_t>(4 * row + j)] = gamma(row, j);
            }
        }
    }
    return true;
}

/// First sample of the force window of interval n (of `samples`), and its variant.
inline void force_window(const ImpedanceDiscretization& model, Eigen::Index n, Eigen::Index samples,
                         Eigen::Index& start, std::size_t& variant) noexcept
{
    if (model.variants == 1) {
        start = n;
        variant = 0;
        return;
    }
    start = std::clamp<Eigen::Index>(n - 1, 0, samples - 4);
    variant = static_cast<std::size_t>(n - start);
}

/// Simulated positions from (p0, v0) under `force`; writes them to `output` when not null and
/// returns sum (p_model[n] - position[n])^2 when `position` is not null (else 0). Returns +inf
/// when the simulation is not finite.
inline double simulate_discretized(const ImpedanceDiscretization& model, const double* force, Eigen::Index samples,
                                   double initial_position, double initial_velocity, const double* position,
                                   double* output)
{
    const auto& phi = model.transition;
    double p = initial_position;
    double v = initial_velocity;
    double cost = 0.0;
    const Eigen::Index points = model.points;
    for (Eigen::Index n = 0; n < samples; ++n) {
        if (output != nullptr) {
            output[n] = p;
        }
        if (position != nullptr) {
            const double residual = p - position[n];
            cost += residual * residual;
        }
        if (n + 1 == samples) {
            break;
        }
        Eigen::Index start = 0;
        std::size_t variant = 0;
        force_window(model, n, samples, start, variant);
        const auto& gamma = model.input[variant];
        double p_next = phi[0] * p + phi[1] * v;
        double v_next = phi[8] * p + phi[9] * v;
        for (Eigen::Index j = 0; j < points; ++j) {
            const double sample = force[start + j];
            p_next += gamma[static_cast<std::size_t>(j)] * sample;
            v_next += gamma[static_cast<std::size_t>(4 + j)] * sample;
        }
        p = p_next;
        v = v_next;
    }
    return std::isfinite(cost) && std::isfinite(p) ? cost : std::numeric_limits<double>::infinity();
}

/// Output-error cost with its Gauss-Newton normal equations: cost = sum r_n^2,
/// normal = J^T J, gradient = J^T r, for the parameters (m, d, k[, p0, v0]) (`parameters` = 3 or 5).
inline double output_error_normal_equations(const ImpedanceDiscretization& model, const double* force,
                                            const double* position, Eigen::Index samples, double initial_position,
                                            double initial_velocity, int parameters,
                                            Eigen::Matrix<double, 5, 5>& normal, Eigen::Matrix<double, 5, 1>& gradient)
{
    const auto& phi = model.transition;
    std::array<double, 8> state{initial_position, initial_velocity, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    std::array<double, 8> next{};
    // Phi^n restricted to x: columns d x / d p0 and d x / d v0.
    double q00 = 1.0, q01 = 0.0, q10 = 0.0, q11 = 1.0;
    std::array<double, 15> normal_upper{};  // packed upper triangle of the 5x5 J^T J
    std::array<double, 5> gradient_sum{};
    std::array<double, 5> row{};
    double cost = 0.0;
    const Eigen::Index points = model.points;
    for (Eigen::Index n = 0; n < samples; ++n) {
        const double residual = state[0] - position[n];
        cost += residual * residual;
        row = {state[2], state[4], state[6], q00, q01};
        std::size_t packed = 0;
        for (std::size_t i = 0; i < static_cast<std::size_t>(parameters); ++i) {
            gradient_sum[i] += row[i] * residual;
            for (std::size_t j = i; j < static_cast<std::size_t>(parameters); ++j) {
                normal_upper[packed++] += row[i] * row[j];
            }
        }
        if (n + 1 == samples) {
            break;
        }
        Eigen::Index start = 0;
        std::size_t variant = 0;
        force_window(model, n, samples, start, variant);
        const auto& gamma = model.input[variant];
        for (std::size_t i = 0; i < 8; ++i) {
            double sum = 0.0;
            for (std::size_t j = 0; j < 8; ++j) {
                sum += phi[8 * i + j] * state[j];
            }
            for (Eigen::Index j = 0; j < points; ++j) {
                sum += gamma[4 * i + static_cast<std::size_t>(j)] * force[start + j];
            }
            next[i] = sum;
        }
        state = next;
        const double r00 = phi[0] * q00 + phi[1] * q10;
        const double r01 = phi[0] * q01 + phi[1] * q11;
        const double r10 = phi[8] * q00 + phi[9] * q10;
        const double r11 = phi[8] * q01 + phi[9] * q11;
        q00 = r00;
        q01 = r01;
        q10 = r10;
        q11 = r11;
    }
    normal.setZero();
    gradient.setZero();
    std::size_t packed = 0;
    for (Eigen::Index i = 0; i < parameters; ++i) {
        gradient(i) = gradient_sum[static_cast<std::size_t>(i)];
        for (Eigen::Index j = i; j < parameters; ++j) {
            normal(i, j) = normal_upper[packed];
            normal(j, i) = normal_upper[packed];
            ++packed;
        }
    }
    if (!std::isfinite(cost) || !normal.allFinite() || !gradient.allFinite()) {
        return std::numeric_limits<double>::infinity();
    }
    return cost;
}

}  // namespace detail
}  // namespace coopdyn
