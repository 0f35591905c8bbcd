/// \file
/// \brief One axis of the apparent impedance, m pdd + d pd + k p = f (the 1-DOF projection of
/// (52), docs/analysis.md), discretised exactly on a uniform sample grid together with the
/// derivatives of the discretisation with respect to (m, d, k), and run over a record: the model
/// that the identification (identification.hpp) fits.
///
/// With x = (p, pd), x' = A x + B f, A = [[0, 1], [-k/m, -d/m]], B = [0; 1/m], and the force
/// interpolated between samples by the polynomial through a window of samples, one sample period
/// is exactly (numerics/linear_discretization.hpp)
///
///     x[n+1] = Phi x[n] + W f_window(n).
///
/// Differentiating this recurrence gives the exact derivatives of the simulated output, which are
/// the columns of the output-error Jacobian:
///
///     s_theta[n+1] = Phi s_theta[n] + (dPhi/dtheta) x[n] + (dW/dtheta) f_window(n),  theta = m, d, k,
///     dx[n] / d(p0, v0) = Phi^n  (the same recurrence without the last two terms).
///
/// dPhi/dtheta and dW/dtheta are read off the exact discretisation of the forward-sensitivity
/// system of the ODE, s_theta' = A s_theta + (dA/dtheta) x + (dB/dtheta) f: with the states
/// [x; s_m; s_d; s_k] its matrix is block lower triangular with A on the diagonal, so its
/// transition matrix is [[Phi, 0], [dPhi/dtheta, Phi]] block by block and its input matrix
/// [W; dW/dtheta].
#pragma once

#include "coopdyn/config.hpp"

#include "coopdyn/numerics/levenberg_marquardt.hpp"
#include "coopdyn/numerics/linear_discretization.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <vector>

namespace coopdyn {

/// \brief How the sampled force is interpolated between samples by the output-error simulation.
enum class ForceInterpolation {
    zero_order_hold,  ///< f(t) = f[n] on [nT, (n+1)T)
    linear,           ///< first-order hold: straight line between f[n] and f[n+1]
    cubic             ///< cubic through the four nearest samples (default)
};

namespace detail {

/// Number of force samples that define the interpolant on one sample interval; 0 for a value
/// that is not a ForceInterpolation.
inline int interpolation_points(ForceInterpolation interpolation) noexcept
{
    switch (interpolation) {
    case ForceInterpolation::zero_order_hold: return 1;
    case ForceInterpolation::linear: return 2;
    case ForceInterpolation::cubic: return 4;
    }
    return 0;
}

/// A 2-row matrix multiplying a window of at most four force samples.
using WindowMatrix = Eigen::Matrix<double, 2, Eigen::Dynamic, Eigen::ColMajor, 2, 4>;

/// The input matrix W of one window placement with its derivatives dW/dm, dW/dd, dW/dk.
struct WindowInput {
    WindowMatrix value;
    std::array<WindowMatrix, 3> derivative;
};

/// The exact recurrence of one sample period with the derivatives of its matrices with respect
/// to (m, d, k) (see the file comment).
struct DiscreteImpedance {
    Eigen::Matrix2d transition = Eigen::Matrix2d::Identity();  ///< Phi = exp(A T)
    std::array<Eigen::Matrix2d, 3> transition_derivative{};    ///< dPhi/dm, dPhi/dd, dPhi/dk
    Eigen::Index points = 4;                                   ///< force samples per window
    std::vector<WindowInput> inputs;                           ///< one per window placement
};

/// The sample window of the interval [nT, (n+1)T): samples start .. start + points - 1, and the
/// placement of those samples relative to n (an index into DiscreteImpedance::inputs).
struct ForceWindow {
    Eigen::Index start = 0;
    std::size_t placement = 0;
};

/// The window of interval n of a record of `samples`. Zero-order hold and linear: samples from n
/// on (one placement). Cubic: the centred window n - 1 .. n + 2, made one-sided on the first and
/// the last interval where the centred one would leave the record; placement v has the sample
/// offsets j - v, j = 0 .. 3, relative to n.
inline ForceWindow force_window(Eigen::Index points, Eigen::Index n, Eigen::Index samples) noexcept
{
    if (points < 4) {
        return {n, 0};
    }
    const Eigen::Index start = std::clamp<Eigen::Index>(n - 1, 0, samples - 4);
    return {start, static_cast<std::size_t>(n - start)};
}

/// Offsets of the samples of window placement `placement` relative to n: j - placement.
COOPDYN_LAZY Eigen::VectorXd window_nodes(Eigen::Index points, Eigen::Index placement)
{
    Eigen::VectorXd nodes(points);
    for (Eigen::Index j = 0; j < points; ++j) {
        nodes(j) = static_cast<double>(j - placement);
    }
    return nodes;
}

/// The forward-sensitivity system (see the file comment): states [x; s_m; s_d; s_k], matrix
/// [[A, 0, 0, 0], [A_m, A, 0, 0], [A_d, 0, A, 0], [A_k, 0, 0, A]], input [B; B_m; 0; 0].
struct SensitivitySystem {
    Eigen::MatrixXd matrix = Eigen::MatrixXd::Zero(8, 8);
    Eigen::MatrixXd input = Eigen::MatrixXd::Zero(8, 1);
};

COOPDYN_LAZY SensitivitySystem sensitivity_system(double mass, double damping, double stiffness)
{
    const double inverse_mass = 1.0 / mass;
    const double inverse_mass_squared = inverse_mass * inverse_mass;
    Eigen::Matrix2d a;
    a << 0.0, 1.0, -stiffness * inverse_mass, -damping * inverse_mass;
    Eigen::Matrix2d a_mass;  // dA/dm
    a_mass << 0.0, 0.0, stiffness * inverse_mass_squared, damping * inverse_mass_squared;
    Eigen::Matrix2d a_damping;  // dA/dd
    a_damping << 0.0, 0.0, 0.0, -inverse_mass;
    Eigen::Matrix2d a_stiffness;  // dA/dk
    a_stiffness << 0.0, 0.0, -inverse_mass, 0.0;

    SensitivitySystem system;
    for (Eigen::Index block = 0; block < 4; ++block) {
        system.matrix.block<2, 2>(2 * block, 2 * block) = a;
    }
    system.matrix.block<2, 2>(2, 0) = a_mass;
    system.matrix.block<2, 2>(4, 0) = a_damping;
    system.matrix.block<2, 2>(6, 0) = a_stiffness;
    system.input(1, 0) = inverse_mass;            // B = [0; 1/m]
    system.input(3, 0) = -inverse_mass_squared;  // dB/dm = [0; -1/m^2]
    return system;
}

/// The exact recurrence of m pdd + d pd + k p = f over one period T with its derivatives (see the
/// file comment); nullopt when m <= 0, a parameter is not finite, or the recurrence is not finite.
COOPDYN_LAZY std::optional<DiscreteImpedance> discretize_impedance(double mass, double damping, double stiffness,
                                                             double sample_period, ForceInterpolation interpolation)
{
    if (!(mass > 0.0) || !std::isfinite(mass) || !std::isfinite(damping) || !std::isfinite(stiffness)) {
        return std::nullopt;
    }
    const SensitivitySystem system = sensitivity_system(mass, damping, stiffness);
    DiscreteImpedance model;
    model.points = interpolation_points(interpolation);
    const numerics::PolynomialInputDiscretization exact = numerics::discretize_polynomial_input(
        system.matrix, system.input, sample_period, static_cast<int>(model.points) - 1);
    const bool finite = exact.transition.allFinite() &&
                        std::all_of(exact.moments.begin(), exact.moments.end(),
                                    [](const Eigen::MatrixXd& moment) { return moment.allFinite(); });
    if (!finite) {
        return std::nullopt;
    }
    model.transition = exact.transition.topLeftCorner<2, 2>();
    for (Eigen::Index parameter = 0; parameter < 3; ++parameter) {
        model.transition_derivative[static_cast<std::size_t>(parameter)] =
            exact.transition.block<2, 2>(2 + 2 * parameter, 0);
    }
    const Eigen::Index placements = interpolation == ForceInterpolation::cubic ? 3 : 1;
    for (Eigen::Index placement = 0; placement < placements; ++placement) {
        const Eigen::MatrixXd input = numerics::interpolated_input_matrix(exact, window_nodes(model.points, placement));
        WindowInput window{input.topRows<2>(), {}};
        for (Eigen::Index parameter = 0; parameter < 3; ++parameter) {
            window.derivative[static_cast<std::size_t>(parameter)] = input.middleRows<2>(2 + 2 * parameter);
        }
        model.inputs.push_back(window);
    }
    return model;
}

/// The simulated axis' motion (p, pd) with its derivatives with respect to the five parameters
/// that the output error is minimised over: the first row of `sensitivity` is a row of the
/// output-error Jacobian.
struct MotionWithSensitivities {
    Eigen::Vector2d motion = Eigen::Vector2d::Zero();                   ///< (p, pd)
    Eigen::Matrix<double, 2, 5> sensitivity = Eigen::Matrix<double, 2, 5>::Zero();  ///< d(p, pd)/d(m, d, k, p0, v0)
};

/// x[n+1] = Phi x[n] + W f_window.
COOPDYN_LAZY Eigen::Vector2d advance(const DiscreteImpedance& model, const Eigen::Vector2d& motion, const WindowInput& input,
                               const Eigen::Ref<const Eigen::VectorXd>& window)
{
    return model.transition * motion + input.value * window;
}

/// The motion and, by the differentiated recurrence (see the file comment), its sensitivities.
COOPDYN_LAZY MotionWithSensitivities advance(const DiscreteImpedance& model, const MotionWithSensitivities& state,
                                       const WindowInput& input, const Eigen::Ref<const Eigen::VectorXd>& window)
{
    MotionWithSensitivities next;
    next.motion = advance(model, state.motion, input, window);
    next.sensitivity = model.transition * state.sensitivity;
    for (std::size_t parameter = 0; parameter < 3; ++parameter) {
        next.sensitivity.col(static_cast<Eigen::Index>(parameter)) +=
            model.transition_derivative[parameter] * state.motion + input.derivative[parameter] * window;
    }
    return next;
}

/// Runs the recurrence over the record: visit(n, state) at every sample n = 0 .. N-1 of `force`,
/// starting from `state` at n = 0. `State` is the motion alone (Eigen::Vector2d) or
/// MotionWithSensitivities.
template <typename State, typename Visit>
void run_over_record(const DiscreteImpedance& model, const Eigen::VectorXd& force, State state, Visit&& visit)
{
    const Eigen::Index samples = force.size();
    for (Eigen::Index n = 0; n < samples; ++n) {
        visit(n, state);
        if (n + 1 < samples) {
            const ForceWindow window = force_window(model.points, n, samples);
            state = advance(model, state, model.inputs[window.placement], force.segment(window.start, model.points));
        }
    }
}

/// The simulated positions p[n] from (p0, v0).
COOPDYN_LAZY Eigen::VectorXd simulated_positions(const DiscreteImpedance& model, const Eigen::VectorXd& force,
                                           const Eigen::Vector2d& initial_state)
{
    Eigen::VectorXd positions(force.size());
    run_over_record(model, force, initial_state,
                    [&](Eigen::Index n, const Eigen::Vector2d& motion) { positions(n) = motion(0); });
    return positions;
}

/// Output error sum_n (p_model[n] - position[n])^2 from (p0, v0); +inf when it is not finite.
COOPDYN_LAZY double output_error_cost(const DiscreteImpedance& model, const Eigen::VectorXd& force,
                                const Eigen::VectorXd& position, const Eigen::Vector2d& initial_state)
{
    double cost = 0.0;
    run_over_record(model, force, initial_state, [&](Eigen::Index n, const Eigen::Vector2d& motion) {
        const double residual = motion(0) - position(n);
        cost += residual * residual;
    });
    return std::isfinite(cost) ? cost : std::numeric_limits<double>::infinity();
}

/// The output error with its Gauss-Newton normal equations over the first `parameters` of
/// (m, d, k, p0, v0) (3: the initial state is held fixed, or 5); cost +inf when not finite.
COOPDYN_LAZY numerics::NormalEquations output_error_normal_equations(const DiscreteImpedance& model,
                                                               const Eigen::VectorXd& force,
                                                               const Eigen::VectorXd& position,
                                                               const Eigen::Vector2d& initial_state,
                                                               Eigen::Index parameters)
{
    MotionWithSensitivities start;
    start.motion = initial_state;
    start.sensitivity.rightCols<2>().setIdentity();  // d(p0, v0)/d(p0, v0) = Phi^0
    Eigen::Matrix<double, 5, 5> normal = Eigen::Matrix<double, 5, 5>::Zero();
    Eigen::Matrix<double, 5, 1> gradient = Eigen::Matrix<double, 5, 1>::Zero();
    double cost = 0.0;
    run_over_record(model, force, start, [&](Eigen::Index n, const MotionWithSensitivities& state) {
        const double residual = state.motion(0) - position(n);
        const Eigen::Matrix<double, 5, 1> jacobian_row = state.sensitivity.row(0).transpose();
        cost += residual * residual;
        gradient += residual * jacobian_row;
        normal += jacobian_row * jacobian_row.transpose();
    });
    // Copied entry by entry: a run-time-sized block of the fixed 5x5 makes GCC 12 report false
    // -Warray-bounds once inlined at -O2/-O3.
    numerics::NormalEquations result{cost, Eigen::MatrixXd(parameters, parameters), Eigen::VectorXd(parameters)};
    for (Eigen::Index i = 0; i < parameters; ++i) {
        result.gradient(i) = gradient(i);
        for (Eigen::Index j = 0; j < parameters; ++j) {
            result.normal(i, j) = normal(i, j);
        }
    }
    if (!std::isfinite(cost) || !result.normal.allFinite() || !result.gradient.allFinite()) {
        result.cost = std::numeric_limits<double>::infinity();
    }
    return result;
}

}  // namespace detail
}  // namespace coopdyn
