/// \file
/// \brief Non-negative least squares, argmin ||A x - b||_2 subject to x >= 0, by the active-set
/// algorithm NNLS of Lawson and Hanson, "Solving Least Squares Problems", 1974, chapter 23
/// (docs/numerics.md). The impedance synthesis (analysis/impedance_synthesis.hpp) fits per-arm
/// gains with it.
///
/// The variables are split into a passive set P (free, positive) and an active set Z (held at
/// zero). Outer loop: the variable of Z with the largest positive gradient w = A^T (b - A x)
/// enters P; when none has one, the Karush-Kuhn-Tucker conditions hold and x is optimal. Inner
/// loop: the unconstrained least-squares solution z over P is taken if it is positive; otherwise
/// x moves towards z until the first variable of P reaches zero, which goes back to Z, and the
/// solve is repeated.
#pragma once

#include "coopdyn/config.hpp"

#include <Eigen/Core>
#include <Eigen/QR>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

namespace coopdyn::numerics {

namespace detail {

/// The Lawson-Hanson iteration on the unit-scaled problem: A's columns and b scaled to unit norm,
/// so that every threshold is relative and the result does not depend on units (a stiffness in
/// N/m or in N/um).
struct LawsonHanson {
    Eigen::MatrixXd matrix;        ///< A with unit-norm columns (zero columns stay zero)
    Eigen::VectorXd target;        ///< b / ||b||
    Eigen::VectorXd column_norms;  ///< ||A e_j||
    double threshold = 0.0;        ///< relative rounding level: smaller gradients and values are zero
    Eigen::VectorXd solution;      ///< x of the scaled problem
    std::vector<bool> passive;     ///< P
    /// Variables whose unconstrained value came out non-positive on entering (possible only
    /// through rounding): kept out of P until P next changes, instead of re-entering forever.
    std::vector<bool> blocked;

    bool is_passive(Eigen::Index j) const { return passive[static_cast<std::size_t>(j)]; }
    bool is_blocked(Eigen::Index j) const { return blocked[static_cast<std::size_t>(j)]; }
    void set_passive(Eigen::Index j, bool value) { passive[static_cast<std::size_t>(j)] = value; }
    void unblock_all() { std::fill(blocked.begin(), blocked.end(), false); }
};

COOPDYN_LAZY LawsonHanson scaled_problem(const Eigen::MatrixXd& matrix, const Eigen::VectorXd& rhs, double rhs_norm)
{
    const Eigen::Index unknowns = matrix.cols();
    LawsonHanson problem;
    problem.column_norms = matrix.colwise().norm().transpose();
    problem.matrix = matrix;
    for (Eigen::Index j = 0; j < unknowns; ++j) {
        if (problem.column_norms(j) > 0.0) {
            problem.matrix.col(j) /= problem.column_norms(j);
        }
    }
    problem.target = rhs / rhs_norm;
    problem.threshold = 64.0 * static_cast<double>(std::max<Eigen::Index>(unknowns, matrix.rows())) *
                        std::numeric_limits<double>::epsilon();
    problem.solution = Eigen::VectorXd::Zero(unknowns);
    problem.passive.assign(static_cast<std::size_t>(unknowns), false);
    problem.blocked.assign(static_cast<std::size_t>(unknowns), false);
    return problem;
}

/// z: the unconstrained least-squares solution over the passive columns, zero elsewhere.
COOPDYN_LAZY Eigen::VectorXd passive_least_squares(const LawsonHanson& problem)
{
    std::vector<Eigen::Index> columns;
    for (Eigen::Index j = 0; j < problem.matrix.cols(); ++j) {
        if (problem.is_passive(j)) {
            columns.push_back(j);
        }
    }
    Eigen::MatrixXd reduced(problem.matrix.rows(), static_cast<Eigen::Index>(columns.size()));
    for (std::size_t c = 0; c < columns.size(); ++c) {
        reduced.col(static_cast<Eigen::Index>(c)) = problem.matrix.col(columns[c]);
    }
    const Eigen::VectorXd reduced_solution = reduced.completeOrthogonalDecomposition().solve(problem.target);
    Eigen::VectorXd candidate = Eigen::VectorXd::Zero(problem.matrix.cols());
    for (std::size_t c = 0; c < columns.size(); ++c) {
        candidate(columns[c]) = reduced_solution(static_cast<Eigen::Index>(c));
    }
    return candidate;
}

/// The variable to free: the largest gradient w_j above the threshold among the active,
/// unblocked, non-zero columns; -1 when there is none (the Kuhn-Tucker conditions hold).
COOPDYN_LAZY Eigen::Index entering_variable(const LawsonHanson& problem)
{
    const Eigen::VectorXd gradient =
        problem.matrix.transpose() * (problem.target - problem.matrix * problem.solution);
    Eigen::Index entering = -1;
    double largest = problem.threshold;
    for (Eigen::Index j = 0; j < problem.matrix.cols(); ++j) {
        if (!problem.is_passive(j) && !problem.is_blocked(j) && problem.column_norms(j) > 0.0 &&
            gradient(j) > largest) {
            largest = gradient(j);
            entering = j;
        }
    }
    return entering;
}

/// One inner step towards `candidate` (z): the longest step alpha in (0, 1] that keeps x >= 0;
/// the passive variables that reach zero return to the active set.
COOPDYN_LAZY void step_towards(LawsonHanson& problem, const Eigen::VectorXd& candidate)
{
    double step = 1.0;
    for (Eigen::Index j = 0; j < candidate.size(); ++j) {
        if (problem.is_passive(j) && !(candidate(j) > 0.0)) {
            const double denominator = problem.solution(j) - candidate(j);
            if (denominator > 0.0) {
                step = std::min(step, problem.solution(j) / denominator);
            }
        }
    }
    problem.solution += step * (candidate - problem.solution);
    for (Eigen::Index j = 0; j < candidate.size(); ++j) {
        if (problem.is_passive(j) && !(problem.solution(j) > problem.threshold)) {
            problem.solution(j) = 0.0;
            problem.set_passive(j, false);
        }
    }
    problem.unblock_all();
}

/// The inner loop after `entering` joined the passive set: repeats the passive solve until it is
/// positive (then x = z), or blocks `entering` when rounding makes its first value non-positive.
COOPDYN_LAZY void solve_passive_set(LawsonHanson& problem, Eigen::Index entering, int iteration_limit)
{
    for (int inner = 0; inner < iteration_limit; ++inner) {
        const Eigen::VectorXd candidate = passive_least_squares(problem);
        if (inner == 0 && !(candidate(entering) > 0.0)) {
            problem.set_passive(entering, false);
            problem.blocked[static_cast<std::size_t>(entering)] = true;
            return;
        }
        bool feasible = true;
        for (Eigen::Index j = 0; j < candidate.size(); ++j) {
            feasible = feasible && (!problem.is_passive(j) || candidate(j) > 0.0);
        }
        if (feasible) {
            problem.solution = candidate;
            problem.unblock_all();
            return;
        }
        step_towards(problem, candidate);
    }
}

}  // namespace detail

/// \brief argmin ||A x - b||_2 subject to x >= 0: Lawson and Hanson's NNLS (1974, chapter 23; see
/// the file comment), on unit-norm columns so that the result does not depend on units.
/// \param matrix A, m x n (any m, n; zero columns get x_j = 0).
/// \param rhs b, m.
/// \return x, n, non-negative. The Karush-Kuhn-Tucker conditions hold to about 64 max(m, n) eps
///         relative (measured in tests/numerics/test_non_negative_least_squares.cpp).
COOPDYN_LAZY Eigen::VectorXd non_negative_least_squares(const Eigen::MatrixXd& matrix, const Eigen::VectorXd& rhs)
{
    const Eigen::Index unknowns = matrix.cols();
    Eigen::VectorXd result = Eigen::VectorXd::Zero(unknowns);
    const double rhs_norm = rhs.norm();
    if (unknowns == 0 || !(rhs_norm > 0.0)) {
        return result;
    }
    detail::LawsonHanson problem = detail::scaled_problem(matrix, rhs, rhs_norm);
    // Lawson and Hanson bound the iterations by 3n; the margin only guards against rounding cycles.
    const int iteration_limit = 10 * static_cast<int>(unknowns) + 30;
    for (int outer = 0; outer < iteration_limit; ++outer) {
        const Eigen::Index entering = detail::entering_variable(problem);
        if (entering < 0) {
            break;
        }
        problem.set_passive(entering, true);
        detail::solve_passive_set(problem, entering, iteration_limit);
    }
    for (Eigen::Index j = 0; j < unknowns; ++j) {
        const double norm = problem.column_norms(j);
        result(j) = norm > 0.0 ? rhs_norm * std::max(problem.solution(j), 0.0) / norm : 0.0;
    }
    return result;
}

}  // namespace coopdyn::numerics
