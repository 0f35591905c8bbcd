/// \file
/// \brief A small Levenberg-Marquardt minimiser of a sum of squares r(theta)^T r(theta), for dense
/// problems with a handful of parameters (the output-error identification,
/// analysis/identification.hpp; docs/numerics.md).
///
/// Each iteration solves the damped Gauss-Newton equations
///
///     (J^T J + mu diag(J^T J)) step = -J^T r
///
/// with Marquardt's scaling diag(J^T J) (Marquardt, "An algorithm for least-squares estimation of
/// nonlinear parameters", SIAM J. Appl. Math. 11(2), 1963), which makes the iteration invariant
/// under a rescaling of the parameters. The damping factor mu follows Nielsen's update from the
/// gain ratio rho = actual / predicted reduction: mu *= max(1/3, 1 - (2 rho - 1)^3) on success,
/// mu *= nu, nu *= 2 on failure (Nielsen, "Damping parameter in Marquardt's method", IMM-REP-1999-05;
/// Madsen, Nielsen and Tingleff, "Methods for non-linear least squares problems", 2004,
/// Algorithm 3.16). Convergence is declared on scale-free tests in the spirit of More, "The
/// Levenberg-Marquardt algorithm: implementation and theory", 1978: the largest cosine between
/// the residual and a Jacobian column, or a relative reduction of the cost or a relative step,
/// below `tolerance`.
#pragma once

#include "coopdyn/config.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>

namespace coopdyn::numerics {

/// \brief Cost and Gauss-Newton normal equations of a sum of squares at one point.
struct NormalEquations {
    double cost = 0.0;         ///< r^T r (+inf where r is not defined)
    Eigen::MatrixXd normal;    ///< J^T J, n x n
    Eigen::VectorXd gradient;  ///< J^T r, n (half the gradient of the cost)
};

/// \brief NormalEquations from residuals r (m) and their Jacobian J (m x n).
COOPDYN_LAZY NormalEquations normal_equations(const Eigen::VectorXd& residuals, const Eigen::MatrixXd& jacobian)
{
    return {residuals.squaredNorm(), jacobian.transpose() * jacobian, jacobian.transpose() * residuals};
}

/// \brief Stopping rules of levenberg_marquardt.
struct LevenbergMarquardtOptions {
    /// Relative tolerance of the convergence tests (cosine, cost reduction, step), > 0.
    double tolerance = 1e-10;
    /// Iteration cap (each iteration solves one damped system and evaluates the cost once).
    int max_iterations = 100;
};

/// \brief Outcome of levenberg_marquardt.
struct LevenbergMarquardtResult {
    Eigen::VectorXd parameters;  ///< the minimiser (the best point found when not converged)
    double cost = 0.0;           ///< r^T r at `parameters`
    double initial_cost = 0.0;   ///< r^T r at the start
    int iterations = 0;          ///< damped systems solved (accepted or rejected steps)
    bool converged = false;      ///< a convergence test passed (false: iteration cap or damping overflow)
};

namespace detail {

/// Nielsen's damping factor mu and its growth nu (see the file comment).
struct MarquardtDamping {
    double factor = 1e-3;
    double growth = 2.0;

    void reject()
    {
        factor *= growth;
        growth *= 2.0;
    }
    void accept(double gain_ratio)
    {
        const double cube = (2.0 * gain_ratio - 1.0) * (2.0 * gain_ratio - 1.0) * (2.0 * gain_ratio - 1.0);
        factor = std::max(factor * std::max(1.0 / 3.0, 1.0 - cube), 1e-15);
        growth = 2.0;
    }
    bool exhausted() const { return factor > 1e20; }
};

/// Marquardt's scaling diag(J^T J), floored at eps times its largest entry so that an unexcited
/// parameter still gets some damping; empty when J^T J has no positive diagonal.
COOPDYN_LAZY Eigen::VectorXd marquardt_scale(const Eigen::MatrixXd& normal)
{
    const Eigen::VectorXd diagonal = normal.diagonal();
    const double largest = diagonal.size() > 0 ? diagonal.maxCoeff() : 0.0;
    if (!(largest > 0.0)) {
        return {};
    }
    return diagonal.cwiseMax(std::numeric_limits<double>::epsilon() * largest);
}

/// Scale-free first-order test: the largest cosine |J_j^T r| / (|J_j| |r|) between the residual and
/// a Jacobian column is at most `tolerance` (or the cost is zero, or J is zero).
COOPDYN_LAZY bool is_stationary(const NormalEquations& point, const Eigen::VectorXd& scale, double tolerance)
{
    if (point.cost == 0.0 || scale.size() == 0) {
        return true;
    }
    return (point.gradient.array().abs() / (scale.array() * point.cost).sqrt()).maxCoeff() <= tolerance;
}

}  // namespace detail

/// \brief Minimises a sum of squares from `start` (Levenberg-Marquardt; see the file comment).
/// \param start theta_0, n parameters (n >= 1).
/// \param cost_at cost_at(const Eigen::VectorXd& theta) -> double: r^T r, +inf where not defined.
/// \param linearise_at linearise_at(const Eigen::VectorXd& theta) -> NormalEquations at theta
///        (n x n and n), cost +inf where not defined.
/// \param options tolerance and iteration cap.
/// \return the minimiser, its cost, the cost at `start`, the iterations and whether a convergence
///         test passed. When the cost is not finite at `start`, returns `start` with that cost and
///         converged = false.
template <typename CostFunction, typename LineariseFunction>
LevenbergMarquardtResult levenberg_marquardt(const Eigen::VectorXd& start, CostFunction&& cost_at,
                                             LineariseFunction&& linearise_at,
                                             const LevenbergMarquardtOptions& options = {})
{
    NormalEquations current = linearise_at(start);
    LevenbergMarquardtResult result{start, current.cost, current.cost, 0, false};
    detail::MarquardtDamping damping;
    while (std::isfinite(result.cost) && result.iterations < options.max_iterations) {
        const Eigen::VectorXd scale = detail::marquardt_scale(current.normal);
        if (detail::is_stationary(current, scale, options.tolerance)) {
            result.converged = true;
            break;
        }
        ++result.iterations;
        Eigen::MatrixXd system = current.normal;
        system.diagonal() += damping.factor * scale;
        const Eigen::VectorXd step = system.ldlt().solve(-current.gradient);
        if (!step.allFinite()) {
            damping.reject();
            if (damping.exhausted()) {
                break;
            }
            continue;
        }
        const Eigen::VectorXd candidate = result.parameters + step;
        const double candidate_cost = cost_at(candidate);
        const double predicted = -2.0 * step.dot(current.gradient) - step.dot(current.normal * step);
        const double actual = result.cost - candidate_cost;
        const double tolerance = options.tolerance;
        const bool small_reduction = predicted <= tolerance * result.cost && std::abs(actual) <= tolerance * result.cost;
        const bool small_step = std::sqrt(step.cwiseAbs2().dot(scale)) <=
                                tolerance * std::sqrt(result.parameters.cwiseAbs2().dot(scale));
        if (actual > 0.0 && std::isfinite(candidate_cost)) {
            damping.accept(predicted > 0.0 ? actual / predicted : 0.0);
            result.parameters = candidate;
            current = linearise_at(candidate);
            if (!std::isfinite(current.cost)) {  // a linearisation that disagrees with cost_at
                result.cost = candidate_cost;
                break;
            }
            result.cost = current.cost;
        } else {
            damping.reject();
        }
        result.converged = small_reduction || small_step;
        if (result.converged || damping.exhausted()) {
            break;
        }
    }
    return result;
}

}  // namespace coopdyn::numerics
