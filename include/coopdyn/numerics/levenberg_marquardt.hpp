/// \file
/// \brief A small Levenberg-Marquardt minimiser of a sum of squares, for dense problems with a
/// handful of parameters (the output-error identification, docs/analysis.md).
///
/// Marquardt's scaling diag(J^T J) of the damping (Marquardt 1963) and Nielsen's update of the
/// damping factor from the gain ratio (Nielsen 1999, as in Madsen, Nielsen and Tingleff,
/// "Methods for non-linear least squares problems", 2004). Convergence is declared on a
/// scale-free gradient test (the largest cosine between the residual and a Jacobian column), a
/// relative reduction of the cost or a relative step below `tolerance`.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>

namespace coopdyn::numerics {

/// \brief Outcome of levenberg_marquardt.
struct LevenbergMarquardtResult {
    double cost = 0.0;      ///< sum of squared residuals at the returned parameters
    int iterations = 0;     ///< accepted or rejected steps taken
    bool converged = false; ///< a convergence test passed (false: iteration cap or damping overflow)
};

/// \brief Minimises a sum of squared residuals over the first `free_parameters` entries of `theta`
/// (the others are held fixed).
/// \param theta parameters (Size entries), start on entry, minimiser on return.
/// \param initial_cost linearise_at(theta) at the start, already evaluated by the caller (so
///        `normal` and `gradient` hold the linearisation there).
/// \param free_parameters number of leading parameters that are free, 1 <= free_parameters <= Size.
/// \param cost_at cost_at(theta) -> double: the cost, +infinity where it is not defined.
/// \param linearise_at linearise_at(theta) -> double: the cost, and writes the Gauss-Newton
///        normal matrix J^T J into `normal` and J^T r into `gradient` (Size x Size and Size, only
///        the leading `free_parameters` block is read); +infinity where it is not defined.
/// \param tolerance relative tolerance of the convergence tests (> 0).
/// \param max_iterations iteration cap.
template <int Size, typename CostFunction, typename LineariseFunction>
LevenbergMarquardtResult levenberg_marquardt(Eigen::Matrix<double, Size, 1>& theta, double initial_cost, int free_parameters,
                                             CostFunction&& cost_at,
                                             LineariseFunction&& linearise_at,
                                             const Eigen::Matrix<double, Size, Size>& normal,
                                             const Eigen::Matrix<double, Size, 1>& gradient, double tolerance,
                                             int max_iterations)
{
    using Vector = Eigen::Matrix<double, Size, 1>;
    double cost = initial_cost;
    double damping_factor = 1e-3;
    double growth = 2.0;
    int iteration = 0;
    bool converged = false;
    const Eigen::Index n_parameters = free_parameters;
    // The active block of the normal equations is copied element by element into dynamic-size
    // objects, and the step is added index by index: expressions such as head(n) on the fixed
    // 5-vectors with a run-time n make GCC 12 report false -Warray-bounds once inlined at -O2/-O3.
    Eigen::MatrixXd h(n_parameters, n_parameters);
    Eigen::VectorXd g(n_parameters);
    Eigen::VectorXd active(n_parameters);
    Eigen::VectorXd scale(n_parameters);
    while (!converged && iteration < max_iterations) {
        for (Eigen::Index i = 0; i < n_parameters; ++i) {
            g(i) = gradient(i);
            active(i) = theta(i);
            for (Eigen::Index j = 0; j < n_parameters; ++j) {
                h(i, j) = normal(i, j);
            }
        }
        scale = h.diagonal();
        const double largest = scale.maxCoeff();
        if (cost == 0.0 || !(largest > 0.0)) {
            converged = true;
            break;
        }
        scale = scale.cwiseMax(std::numeric_limits<double>::epsilon() * largest);
        // Cosine between the residual and each Jacobian column (scale-free gradient test).
        const double cosine = (g.array().abs() / (scale.array() * cost).sqrt()).maxCoeff();
        if (cosine <= tolerance) {
            converged = true;
            break;
        }
        ++iteration;
        Eigen::MatrixXd system = h;
        system.diagonal() += damping_factor * scale;
        const Eigen::VectorXd step = system.ldlt().solve(-g);
        if (!step.allFinite()) {
            damping_factor *= growth;
            growth *= 2.0;
            if (damping_factor > 1e20) {
                break;
            }
            continue;
        }
        Vector candidate = theta;
        for (Eigen::Index i = 0; i < n_parameters; ++i) {
            candidate(i) += step(i);
        }
        const double predicted = -2.0 * step.dot(g) - step.dot(h * step);
        const double candidate_cost = cost_at(candidate);
        const double actual = cost - candidate_cost;
        const double step_size = std::sqrt(step.cwiseAbs2().dot(scale));
        const double parameter_size = std::sqrt(active.cwiseAbs2().dot(scale));
        const bool small_reduction = predicted <= tolerance * cost && std::abs(actual) <= tolerance * cost;
        const bool small_step = step_size <= tolerance * parameter_size;
        if (actual > 0.0 && std::isfinite(candidate_cost)) {
            theta = candidate;
            const double ratio = predicted > 0.0 ? actual / predicted : 0.0;
            const double cube = (2.0 * ratio - 1.0) * (2.0 * ratio - 1.0) * (2.0 * ratio - 1.0);
            damping_factor *= std::max(1.0 / 3.0, 1.0 - cube);
            damping_factor = std::max(damping_factor, 1e-15);
            growth = 2.0;
            cost = linearise_at(theta);
            if (!std::isfinite(cost)) {  // cannot happen: the same simulation was finite above
                cost = candidate_cost;
                break;
            }
        } else {
            damping_factor *= growth;
            growth *= 2.0;
        }
        if (small_reduction || small_step) {
            converged = true;
        } else if (damping_factor > 1e20) {
            break;
        }
    }

    return {cost, iteration, converged};
}

}  // namespace coopdyn::numerics
