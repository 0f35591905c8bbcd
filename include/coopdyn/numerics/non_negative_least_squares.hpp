/// \file
/// \brief Non-negative least squares (the impedance synthesis' fit, docs/numerics.md).
#pragma once

#include <Eigen/Core>
#include <Eigen/QR>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

namespace coopdyn::numerics {

namespace detail {

/// The unconstrained least-squares solution of scaled x = target over the columns flagged in
/// `passive`, zero elsewhere (the inner problem of the Lawson-Hanson iteration).
inline Eigen::VectorXd passive_least_squares(const Eigen::MatrixXd& scaled, const Eigen::VectorXd& target,
                                             const std::vector<bool>& passive)
{
    std::vector<Eigen::Index> columns;
    for (std::size_t j = 0; j < passive.size(); ++j) {
        if (passive[j]) {
            columns.push_back(static_cast<Eigen::Index>(j));
        }
    }
    Eigen::MatrixXd reduced(scaled.rows(), static_cast<Eigen::Index>(columns.size()));
    for (std::size_t c = 0; c < columns.size(); ++c) {
        reduced.col(static_cast<Eigen::Index>(c)) = scaled.col(columns[c]);
    }
    const Eigen::VectorXd reduced_solution = reduced.completeOrthogonalDecomposition().solve(target);
    Eigen::VectorXd candidate = Eigen::VectorXd::Zero(scaled.cols());
    for (std::size_t c = 0; c < columns.size(); ++c) {
        candidate(columns[c]) = reduced_solution(static_cast<Eigen::Index>(c));
    }
    return candidate;
}

}  // namespace detail

/// \brief Lawson-Hanson non-negative least squares (Lawson and Hanson, Solving Least Squares Problems,
/// 1974, algorithm NNLS): argmin ||A x - b||_2 subject to x >= 0.
///
/// The columns of A and b are scaled to unit norm first, so every threshold below is relative and
/// the result does not depend on units (a stiffness in N/m or in N/um). An entering variable
/// whose unconstrained value comes out non-positive (possible only through rounding) is blocked
/// until the passive set next changes, instead of being re-entered forever.
inline Eigen::VectorXd non_negative_least_squares(const Eigen::MatrixXd& matrix, const Eigen::VectorXd& rhs)
{
    const Eigen::Index unknowns = matrix.cols();
    Eigen::VectorXd result = Eigen::VectorXd::Zero(unknowns);
    const double rhs_norm = rhs.norm();
    if (unknowns == 0 || !(rhs_norm > 0.0)) {
        return result;
    }
    Eigen::VectorXd column_norms = matrix.colwise().norm().transpose();
    Eigen::MatrixXd scaled = matrix;
    for (Eigen::Index j = 0; j < unknowns; ++j) {
        if (column_norms(j) > 0.0) {
            scaled.col(j) /= column_norms(j);
        }
    }
    const Eigen::VectorXd target = rhs / rhs_norm;
    const double threshold = 64.0 * static_cast<double>(std::max<Eigen::Index>(unknowns, matrix.rows())) *
                             std::numeric_limits<double>::epsilon();

    Eigen::VectorXd solution = Eigen::VectorXd::Zero(unknowns);
    std::vector<bool> passive(static_cast<std::size_t>(unknowns), false);
    std::vector<bool> blocked(static_cast<std::size_t>(unknowns), false);
    const auto at = [](std::vector<bool>& flags, Eigen::Index j) { return flags[static_cast<std::size_t>(j)]; };
    const auto set = [](std::vector<bool>& flags, Eigen::Index j, bool value) { flags[static_cast<std::size_t>(j)] = value; };

    const auto passive_solution = [&]() { return detail::passive_least_squares(scaled, target, passive); };

    const int iteration_limit = 10 * static_cast<int>(unknowns) + 30;
    for (int outer = 0; outer < iteration_limit; ++outer) {
        const Eigen::VectorXd gradient = scaled.transpose() * (target - scaled * solution);
        Eigen::Index entering = -1;
        double largest = threshold;
        for (Eigen::Index j = 0; j < unknowns; ++j) {
            if (!at(passive, j) && !at(blocked, j) && column_norms(j) > 0.0 && gradient(j) > largest) {
                largest = gradient(j);
                entering = j;
            }
        }
        if (entering < 0) {
            break;  // Kuhn-Tucker conditions hold: no inactive variable can reduce the residual.
        }
        set(passive, entering, true);
        bool first_inner = true;
        for (int inner = 0; inner < iteration_limit; ++inner) {
            const Eigen::VectorXd candidate = passive_solution();
            if (first_inner && !(candidate(entering) > 0.0)) {
                // Rounding: the entering variable cannot move into the feasible region.
                set(passive, entering, false);
                set(blocked, entering, true);
                break;
            }
            first_inner = false;
            bool feasible = true;
            double step = 1.0;
            for (Eigen::Index j = 0; j < unknowns; ++j) {
                if (at(passive, j) && !(candidate(j) > 0.0)) {
                    feasible = false;
                    const double denominator = solution(j) - candidate(j);
                    if (denominator > 0.0) {
                        step = std::min(step, solution(j) / denominator);
                    }
                }
            }
            if (feasible) {
                solution = candidate;
                std::fill(blocked.begin(), blocked.end(), false);
                break;
            }
            solution += step * (candidate - solution);
            for (Eigen::Index j = 0; j < unknowns; ++j) {
                if (at(passive, j) && !(solution(j) > threshold)) {
                    solution(j) = 0.0;
                    set(passive, j, false);
                }
            }
            std::fill(blocked.begin(), blocked.end(), false);
        }
    }
    for (Eigen::Index j = 0; j < unknowns; ++j) {
        result(j) = column_norms(j) > 0.0 ? rhs_norm * std::max(solution(j), 0.0) / column_norms(j) : 0.0;
    }
    return result;
}

}  // namespace coopdyn::numerics
