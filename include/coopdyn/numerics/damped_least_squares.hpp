/// \file
/// \brief Damped least squares (Levenberg's damping on the minimum-norm step) for small nonlinear
/// equations e(x) = 0, e.g. inverse kinematics: each iteration takes
///
///     dx = J^T (J J^T + lambda^2 I)^-1 e
///
/// where J is the Jacobian of the quantity whose error e is (J dx ~ e to first order). Far from a
/// singular J the damping slows convergence by a factor about lambda^2 / sigma_min^2 per step; near
/// one it bounds the step by |e| / (2 lambda) instead of letting it blow up (Nakamura and Hanafusa,
/// 1986; Wampler, 1986). docs/adapters.md, "Inverse kinematics for start postures".
///
/// Not a per-tick function: it allocates its Jacobian and error once per call.
#pragma once

#include "coopdyn/config.hpp"

#include <Eigen/Core>

#include <cmath>

namespace coopdyn::numerics {

/// How a damped_least_squares call ended.
enum class DampedLeastSquaresStatus {
    converged,        ///< |e| <= tolerance
    stalled,          ///< the step (after projection, e.g. onto joint ranges) became negligible: a
                      ///< local minimum of |e| that is not a solution (unreachable target, limit)
    iteration_limit,  ///< iteration_limit iterations without either
};

inline const char* to_string(DampedLeastSquaresStatus status) noexcept
{
    switch (status) {
    case DampedLeastSquaresStatus::converged: return "converged";
    case DampedLeastSquaresStatus::stalled: return "stalled";
    case DampedLeastSquaresStatus::iteration_limit: return "iteration_limit";
    }
    return "unknown";
}

struct DampedLeastSquaresOptions {
    double damping = 1e-2;       ///< lambda (units of J's entries)
    double tolerance = 1e-10;    ///< on |e| (2-norm)
    int iteration_limit = 500;
    double max_step = 0.5;       ///< largest |dx| of one step (2-norm): larger steps are scaled down
    double stall_step = 1e-14;   ///< stalled when |dx| <= stall_step (1 + |x|) after projection
};

struct DampedLeastSquaresResult {
    DampedLeastSquaresStatus status = DampedLeastSquaresStatus::iteration_limit;
    double residual = 0.0;  ///< |e| at the returned x
    int iterations = 0;     ///< steps taken
    bool converged() const noexcept { return status == DampedLeastSquaresStatus::converged; }
};

/// \brief One step dx = J^T (J J^T + damping^2 I)^-1 e. J is m x n, e m, step n. The step is zero
/// when J J^T + damping^2 I is not numerically positive definite (damping 0 and a rank-deficient J,
/// or a non-finite J): damped_least_squares then reports the iteration stalled.
///
/// Plain loops: the lower triangle of the Gram matrix, a left-looking Cholesky factorisation and
/// two substitutions, as FixedLlt (fixed_llt.hpp) but at run-time sizes. Eigen's operator* and LLT
/// on dynamic matrices would compile its GEMM kernels, blocked Cholesky and triangular solvers into
/// every file that calls the inverse kinematics, for a 12 x 14 problem solved a few times at start
/// (docs/performance.md, "Compile time and CI").
template <typename DerivedJ, typename DerivedE, typename DerivedStep>
void damped_least_squares_step(const Eigen::MatrixBase<DerivedJ>& jacobian, const Eigen::MatrixBase<DerivedE>& error,
                               double damping, const Eigen::MatrixBase<DerivedStep>& step_out)
{
    auto& step = const_cast<Eigen::MatrixBase<DerivedStep>&>(step_out);
    const Index m = jacobian.rows();
    const Index n = jacobian.cols();
    step.derived().resize(n);
    // J J^T + lambda^2 I is symmetric positive definite for lambda != 0 (and for a full-row-rank J):
    // Cholesky. The m x m form (not (J^T J + lambda^2 I)^-1 J^T e) because the tasks here have at
    // most as many rows as joints (6K <= Q). Column j of L needs only the finished columns k < j:
    // l_jj = sqrt(g_jj - sum_k l_jk^2), l_ij = (g_ij - sum_k l_ik l_jk) / l_jj.
    Eigen::MatrixXd factor(m, m);
    for (Index j = 0; j < m; ++j) {
        for (Index i = j; i < m; ++i) {
            double gram = i == j ? damping * damping : 0.0;
            for (Index k = 0; k < n; ++k) {
                gram += jacobian(i, k) * jacobian(j, k);
            }
            for (Index k = 0; k < j; ++k) {
                gram -= factor(i, k) * factor(j, k);
            }
            if (i == j) {
                if (!(gram > 0.0)) {
                    step.setZero();
                    return;
                }
                factor(j, j) = std::sqrt(gram);
            } else {
                factor(i, j) = gram / factor(j, j);
            }
        }
    }
    // weights = (L L^T)^-1 e: L y = e forward, then L^T weights = y backward.
    Eigen::VectorXd weights(m);
    for (Index i = 0; i < m; ++i) {
        double value = error(i);
        for (Index k = 0; k < i; ++k) {
            value -= factor(i, k) * weights(k);
        }
        weights(i) = value / factor(i, i);
    }
    for (Index i = m - 1; i >= 0; --i) {
        double value = weights(i);
        for (Index k = i + 1; k < m; ++k) {
            value -= factor(k, i) * weights(k);
        }
        weights(i) = value / factor(i, i);
    }
    for (Index c = 0; c < n; ++c) {
        double value = 0.0;
        for (Index i = 0; i < m; ++i) {
            value += jacobian(i, c) * weights(i);
        }
        step(c) = value;
    }
}

/// \brief Solves e(x) = 0 from x by damped least squares.
/// \param evaluate evaluate(const Eigen::VectorXd& x, Eigen::VectorXd& e, Eigen::MatrixXd& J): the
///   error e (m) and the Jacobian J (m x n) with J dx ~ e, i.e. e = target - f(x), J = df/dx.
/// \param project project(Eigen::VectorXd& x): puts x back into its domain after each step (e.g.
///   clamps joints to their ranges); a no-op lambda when there is none.
/// \param x start on entry, the last iterate on return.
template <typename Evaluate, typename Project>
DampedLeastSquaresResult damped_least_squares(Evaluate&& evaluate, Project&& project, Eigen::VectorXd& x,
                                              const DampedLeastSquaresOptions& options = {})
{
    Eigen::VectorXd error;
    Eigen::MatrixXd jacobian;
    Eigen::VectorXd step(x.size());
    Eigen::VectorXd previous(x.size());
    DampedLeastSquaresResult result;
    for (int iteration = 0;; ++iteration) {
        evaluate(static_cast<const Eigen::VectorXd&>(x), error, jacobian);
        result.residual = error.norm();
        result.iterations = iteration;
        if (result.residual <= options.tolerance) {
            result.status = DampedLeastSquaresStatus::converged;
            return result;
        }
        if (iteration >= options.iteration_limit) {
            result.status = DampedLeastSquaresStatus::iteration_limit;
            return result;
        }
        damped_least_squares_step(jacobian, error, options.damping, step);
        const double length = step.norm();
        if (length > options.max_step) {
            step *= options.max_step / length;
        }
        previous = x;
        x += step;
        project(x);
        if ((x - previous).norm() <= options.stall_step * (1.0 + x.norm())) {
            evaluate(static_cast<const Eigen::VectorXd&>(x), error, jacobian);
            result.residual = error.norm();
            result.iterations = iteration + 1;
            result.status = result.residual <= options.tolerance ? DampedLeastSquaresStatus::converged
                                                                 : DampedLeastSquaresStatus::stalled;
            return result;
        }
    }
}

}  // namespace coopdyn::numerics
