// Tests of coopdyn/numerics/qp_solver.hpp (Goldfarb-Idnani dual active-set QP) against references
// the solver was not derived from:
// A. the KKT conditions of min 1/2 x^T H x + g^T x s.t. C x <= d, checked directly on every
//    solve of thousands of seeded random problems (H up to cond 1e8, many rows active at the
//    optimum, duplicated, scaled-duplicate and linearly dependent rows);
// B. a brute-force enumeration of active sets (equality-constrained KKT solves by FullPivLU) on
//    small problems;
// C. infeasible problems, the iteration cap and a semidefinite H (statuses);
// D. warm starts along slowly changing problems (control loop), against cold solves;
// E. float against double;
// F. no allocation (tests/allocation_counter.hpp), fixed and dynamic sizes;
// G. constraints set once (set_constraints, solve(H, g, d)): the same results as solve_qp, the
//    KKT conditions, and the new answer after C changes.
#include "../allocation_counter.hpp"

#include "coopdyn/numerics/qp_solver.hpp"

#include "coopdyn/control/qp_solver.hpp"  // the deprecated path: must still compile

#include <Eigen/LU>
#include <Eigen/QR>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

// Every member of the class template compiles, fixed and dynamic, double and float.
template class coopdyn::QpSolver<double, 6, 30>;
template class coopdyn::QpSolver<double, coopdyn::Dynamic, coopdyn::Dynamic>;
template class coopdyn::QpSolver<float, 6, 30>;
template class coopdyn::QpSolver<float, coopdyn::Dynamic, coopdyn::Dynamic>;
template struct coopdyn::QpResult<double, 12, 60>;
template struct coopdyn::QpResult<float, coopdyn::Dynamic, coopdyn::Dynamic>;

namespace {

using coopdyn::QpStatus;
using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;
using Rng = std::mt19937;
using DynamicSolver = coopdyn::QpSolver<double, coopdyn::Dynamic, coopdyn::Dynamic>;

constexpr double eps = std::numeric_limits<double>::epsilon();

double uniform(Rng& rng, double low, double high) { return std::uniform_real_distribution<double>(low, high)(rng); }

MatrixXd random_matrix(Index rows, Index cols, Rng& rng)
{
    MatrixXd result(rows, cols);
    for (Index k = 0; k < result.size(); ++k) {
        result(k) = uniform(rng, -1, 1);
    }
    return result;
}

/// Q diag(lambda) Q^T, Q a random orthogonal matrix, eigenvalues log-spaced from 1 to `condition`
/// (then scaled by `scale`): the condition number is known exactly.
MatrixXd random_spd(Index n, double condition, double scale, Rng& rng)
{
    const MatrixXd q = Eigen::HouseholderQR<MatrixXd>(random_matrix(n, n, rng)).householderQ();
    VectorXd eigenvalues(n);
    for (Index i = 0; i < n; ++i) {
        eigenvalues(i) = n == 1 ? 1.0 : std::pow(condition, static_cast<double>(i) / static_cast<double>(n - 1));
    }
    MatrixXd h = scale * q * eigenvalues.asDiagonal() * q.transpose();
    return 0.5 * (h + h.transpose());
}

struct Problem {
    MatrixXd h;
    VectorXd g;
    MatrixXd c;
    VectorXd d;
    double condition = 1;
    VectorXd x_star;  // the minimiser, by construction (empty when unknown)
};

/// A problem with a known optimum: x*, `active` independent rows held with equality and positive
/// multipliers, the rest satisfied with slack; g = -H x* - C^T lambda* makes x* stationary. Then
/// degenerate rows are appended: exact and scaled duplicates of rows (same set, same slack ratio)
/// and non-negative combinations of rows (active when all their parts are), some with a zero
/// multiplier on an active row (weakly active).
Problem random_problem(Index n, Index independent_rows, Index active, Index degenerate_rows, double condition, Rng& rng)
{
    Problem p;
    p.condition = condition;
    const double scale = std::pow(10.0, uniform(rng, -2, 2));  // units: H, g, C, d all scaled
    p.h = random_spd(n, condition, scale, rng);
    const VectorXd x_star = random_matrix(n, 1, rng) * std::pow(10.0, uniform(rng, -1, 1));
    const Index m = independent_rows + degenerate_rows;
    p.c.resize(m, n);
    p.d.resize(m);
    VectorXd lambda = VectorXd::Zero(m);
    for (Index i = 0; i < independent_rows; ++i) {
        p.c.row(i) = random_matrix(1, n, rng) * std::pow(10.0, uniform(rng, -1, 1));
        const double slack = i < active ? 0.0 : uniform(rng, 0.01, 1.0) * p.c.row(i).norm();
        p.d(i) = p.c.row(i).dot(x_star) + slack;
        if (i < active) {
            // Some active rows are weakly active (zero multiplier): a degenerate optimum.
            lambda(i) = uniform(rng, 0, 1) < 0.15 ? 0.0 : uniform(rng, 0.1, 2.0) * scale;
        }
    }
    for (Index i = independent_rows; i < m; ++i) {
        const Index a = std::uniform_int_distribution<Index>(0, independent_rows - 1)(rng);
        const Index b = std::uniform_int_distribution<Index>(0, independent_rows - 1)(rng);
        switch (std::uniform_int_distribution<int>(0, 2)(rng)) {
        case 0: p.c.row(i) = p.c.row(a); p.d(i) = p.d(a); break;  // exact duplicate
        case 1: {                                                    // scaled duplicate
            const double factor = uniform(rng, 0.1, 10.0);
            p.c.row(i) = factor * p.c.row(a);
            p.d(i) = factor * p.d(a);
            break;
        }
        default: {                                                   // exact combination
            const double wa = uniform(rng, 0.1, 2.0);
            const double wb = uniform(rng, 0.1, 2.0);
            p.c.row(i) = wa * p.c.row(a) + wb * p.c.row(b);
            p.d(i) = wa * p.d(a) + wb * p.d(b);
            break;
        }
        }
    }
    p.g = -p.h * x_star - p.c.transpose() * lambda;
    p.x_star = x_star;
    return p;
}

/// Residuals of the KKT conditions, each divided by the scale of the terms it sums (so they are
/// pure rounding ratios, in units of nothing).
struct Kkt {
    double stationarity = 0;
    double feasibility = 0;
    double dual = 0;
    double complementarity = 0;
};

Kkt kkt_residuals(const Problem& p, const VectorXd& x, const VectorXd& lambda)
{
    Kkt k;
    // Stationarity, relative to the size of the summed terms |H||x| + |g| + |C^T||lambda|.
    const VectorXd stationarity = p.h * x + p.g + p.c.transpose() * lambda;
    const double stationarity_scale =
        p.h.norm() * x.norm() + p.g.norm() + p.c.norm() * lambda.norm() + std::numeric_limits<double>::min();
    k.stationarity = stationarity.norm() / stationarity_scale;
    const double lambda_scale = lambda.cwiseAbs().maxCoeff() + std::numeric_limits<double>::min();
    for (Index i = 0; i < p.c.rows(); ++i) {
        // Row residuals relative to the rounding scale of evaluating the row, |c_i||x| + |d_i|.
        const double row_scale = p.c.row(i).norm() * x.norm() + std::abs(p.d(i)) + std::numeric_limits<double>::min();
        const double slack = (p.c.row(i).dot(x) - p.d(i)) / row_scale;
        k.feasibility = std::max(k.feasibility, slack);
        k.dual = std::max(k.dual, -lambda(i) / lambda_scale);
        k.complementarity = std::max(k.complementarity, std::abs(slack) * lambda(i) / lambda_scale);
    }
    return k;
}

void worst_of(Kkt& worst, const Kkt& k)
{
    worst.stationarity = std::max(worst.stationarity, k.stationarity);
    worst.feasibility = std::max(worst.feasibility, k.feasibility);
    worst.dual = std::max(worst.dual, k.dual);
    worst.complementarity = std::max(worst.complementarity, k.complementarity);
}

// ---------------------------------------------------------------------------------------------
// A. KKT certificate on random problems.

TEST(QpSolverKkt, RandomProblemsSatisfyKkt)
{
    Rng rng(20261123);
    const int problems = 3000;
    Kkt worst;
    Kkt worst_scaled;  // divided by the tolerance each check uses: <= 1 passes
    int iterations = 0;
    int max_iterations = 0;
    long active_rows = 0;
    double worst_x = 0;
    for (int k = 0; k < problems; ++k) {
        const Index n = std::uniform_int_distribution<Index>(2, 20)(rng);
        const Index independent = std::uniform_int_distribution<Index>(1, std::min<Index>(60, 4 * n))(rng);
        const Index active = std::uniform_int_distribution<Index>(0, std::min(n, independent))(rng);
        const Index degenerate = std::uniform_int_distribution<Index>(0, 20)(rng);
        const double condition = std::pow(10.0, uniform(rng, 0, 8));
        const Problem p = random_problem(n, independent, active, degenerate, condition, rng);
        DynamicSolver solver(n, p.c.rows());
        const auto& result = solver.solve(p.h, p.g, p.c, p.d);
        ASSERT_EQ(result.status, QpStatus::solved) << "problem " << k << " n " << n << " m " << p.c.rows();
        iterations += result.iterations;
        max_iterations = std::max(max_iterations, result.iterations);
        active_rows += result.active_count;
        worst_x = std::max(worst_x, (result.x - p.x_star).norm() / (p.x_star.norm() * p.condition * eps));
        const Kkt residuals = kkt_residuals(p, result.x, result.multipliers);
        worst_of(worst, residuals);
        // Tolerances. Stationarity: an error in x along H's weak directions (where it is large,
        // up to eps cond H) is multiplied by H's small eigenvalues in H x, so the residual is
        // rounding of the sums, relative to |H||x| + |g| + |C||lambda| and independent of cond H:
        // the test's own evaluation (2n + 1 terms per entry, (2n + 1) eps by the dot-product
        // bound) plus a few eps per solver step (each updates x by t z and lambda by t r); the
        // factor 4 covers the norm inequalities. Measured: at most 28 eps (n = 6, 4 steps).
        // Feasibility: each active row is met exactly by its full step, up to rounding in
        // z = J2 J2^T n_p, whose columns carry rounding of order eps |L^-1|, so c_i^T x errs by
        // about eps |L^-1|^2 |H| = eps cond H relative to |c_i||x| (measured: at most 41 eps cond H);
        // later steps along z, orthogonal to the active rows in exact arithmetic, add the same
        // order. Complementarity has the feasibility tolerance (it multiplies that slack by
        // lambda_i / max lambda <= 1). Dual feasibility is exact: multipliers are clamped at zero.
        const double stationarity_tolerance = 4 * eps * static_cast<double>(2 * n + 1 + result.iterations);
        const double feasibility_tolerance = 1000 * eps * p.condition;
        Kkt scaled = residuals;
        scaled.stationarity /= stationarity_tolerance;
        scaled.feasibility /= feasibility_tolerance;
        scaled.complementarity /= feasibility_tolerance;
        worst_of(worst_scaled, scaled);
        EXPECT_LE(residuals.stationarity, stationarity_tolerance) << "problem " << k;
        EXPECT_LE(residuals.feasibility, feasibility_tolerance) << "problem " << k;
        EXPECT_LE(residuals.dual, 0.0) << "problem " << k;
        EXPECT_LE(residuals.complementarity, feasibility_tolerance) << "problem " << k;
    }
    std::printf("[qp kkt] %d problems, n 2..20, m up to 80, cond H up to 1e8, %.1f rows active and %.1f steps on "
                "average, at most %d steps\n"
                "         worst relative residuals: stationarity %.2e, feasibility %.2e, dual %.2e, "
                "complementarity %.2e\n"
                "         worst as a fraction of the tolerance: stationarity %.2e, feasibility %.2e, "
                "complementarity %.2e\n",
                problems, static_cast<double>(active_rows) / problems, static_cast<double>(iterations) / problems,
                max_iterations, worst.stationarity,
                worst.feasibility, worst.dual, worst.complementarity, worst_scaled.stationarity,
                worst_scaled.feasibility, worst_scaled.complementarity);
    // Reported, not asserted: the forward error also grows with the conditioning of the active
    // rows (random, sometimes nearly dependent), which the KKT residuals above do not depend on.
    std::printf("         worst |x - x*| / (|x*| eps cond H) = %.2e (x* the constructed minimiser)\n", worst_x);
}

// ---------------------------------------------------------------------------------------------
// B. Brute force over active sets.

/// The minimiser by enumeration: for every subset S of rows (|S| <= n) solve
/// [H C_S^T; C_S 0] [x; mu] = [-g; d_S] (FullPivLU; singular systems skipped) and keep the best
/// objective among the feasible points with mu >= 0.
struct BruteForce {
    VectorXd x;
    double objective = std::numeric_limits<double>::infinity();
};

BruteForce brute_force(const Problem& p)
{
    const Index n = p.h.rows();
    const Index m = p.c.rows();
    BruteForce best;
    for (unsigned mask = 0; mask < (1u << m); ++mask) {
        std::vector<Index> rows;
        for (Index i = 0; i < m; ++i) {
            if (mask & (1u << i)) {
                rows.push_back(i);
            }
        }
        const Index q = static_cast<Index>(rows.size());
        if (q > n) {
            continue;
        }
        MatrixXd kkt = MatrixXd::Zero(n + q, n + q);
        VectorXd rhs(n + q);
        kkt.topLeftCorner(n, n) = p.h;
        rhs.head(n) = -p.g;
        for (Index k = 0; k < q; ++k) {
            kkt.block(0, n + k, n, 1) = p.c.row(rows[static_cast<std::size_t>(k)]).transpose();
            kkt.block(n + k, 0, 1, n) = p.c.row(rows[static_cast<std::size_t>(k)]);
            rhs(n + k) = p.d(rows[static_cast<std::size_t>(k)]);
        }
        const Eigen::FullPivLU<MatrixXd> lu(kkt);
        if (!lu.isInvertible()) {
            continue;
        }
        const VectorXd solution = lu.solve(rhs);
        const VectorXd x = solution.head(n);
        if (q > 0 && solution.tail(q).minCoeff() < -1e-9 * (1 + solution.tail(q).cwiseAbs().maxCoeff())) {
            continue;
        }
        if (((p.c * x - p.d).array() > 1e-9 * (1 + p.d.cwiseAbs().maxCoeff())).any()) {
            continue;
        }
        const double objective = 0.5 * x.dot(p.h * x) + p.g.dot(x);
        if (objective < best.objective) {
            best.objective = objective;
            best.x = x;
        }
    }
    return best;
}

TEST(QpSolverBruteForce, AgreesWithActiveSetEnumeration)
{
    Rng rng(77);
    const int problems = 400;
    double worst_x = 0;
    double worst_objective = 0;
    for (int k = 0; k < problems; ++k) {
        const Index n = std::uniform_int_distribution<Index>(1, 4)(rng);
        Problem p;
        p.h = random_spd(n, std::pow(10.0, uniform(rng, 0, 3)), 1.0, rng);
        p.g = random_matrix(n, 1, rng) * 3.0;
        const Index m = std::uniform_int_distribution<Index>(1, 8)(rng);
        p.c = random_matrix(m, n, rng);
        p.d = random_matrix(m, 1, rng).cwiseAbs() * 0.5;  // x = 0 is feasible
        if (k % 4 == 0 && m >= 2) {
            p.c.row(m - 1) = 2.0 * p.c.row(0);  // a scaled duplicate
            p.d(m - 1) = 2.0 * p.d(0);
        }
        const BruteForce reference = brute_force(p);
        ASSERT_TRUE(std::isfinite(reference.objective)) << "problem " << k;
        const auto result = coopdyn::solve_qp(p.h, p.g, p.c, p.d);
        ASSERT_EQ(result.status, QpStatus::solved) << "problem " << k;
        const double x_error = (result.x - reference.x).norm() / (1 + reference.x.norm());
        const double objective_error =
            std::abs(result.objective - reference.objective) / (1 + std::abs(reference.objective));
        worst_x = std::max(worst_x, x_error);
        worst_objective = std::max(worst_objective, objective_error);
        // Both sides are backward stable on cond(H) <= 1e3 (cond of the KKT matrix similar).
        EXPECT_LE(x_error, 1e-9) << "problem " << k;
        EXPECT_LE(objective_error, 1e-12) << "problem " << k;
    }
    std::printf("[qp brute force] %d problems, n 1..4, m 1..8: worst relative difference x %.2e, objective %.2e\n",
                problems, worst_x, worst_objective);
}

// ---------------------------------------------------------------------------------------------
// C. Statuses.

void expect_finite(const coopdyn::QpResult<double, coopdyn::Dynamic, coopdyn::Dynamic>& result)
{
    EXPECT_TRUE(result.x.allFinite());
    EXPECT_TRUE(result.multipliers.allFinite());
    EXPECT_TRUE(std::isfinite(result.objective));
    EXPECT_GE(result.multipliers.minCoeff(), 0.0);
}

/// Replaces the last row by -sum a_i c_i <= -sum a_i d_i - delta over rows 0 .. parts - 1 (a_i,
/// delta > 0): a non-negative combination of the rows reads 0 <= -delta, so no x satisfies them
/// (Farkas).
void make_last_row_contradict(Problem& p, Index parts, Rng& rng)
{
    const Index m = p.c.rows();
    p.c.row(m - 1).setZero();
    p.d(m - 1) = -uniform(rng, 0.01, 1.0);
    for (Index i = 0; i < parts; ++i) {
        const double weight = uniform(rng, 0.1, 2.0);
        p.c.row(m - 1) -= weight * p.c.row(i);
        p.d(m - 1) -= weight * p.d(i);
    }
}

TEST(QpSolverStatus, ContradictoryBoundsAreInfeasible)
{
    // x_1 <= -1 and -x_1 <= -1 (x_1 >= 1).
    const MatrixXd h = MatrixXd::Identity(3, 3);
    const VectorXd g = VectorXd::Zero(3);
    MatrixXd c = MatrixXd::Zero(2, 3);
    c(0, 0) = 1;
    c(1, 0) = -1;
    const VectorXd d = VectorXd::Constant(2, -1.0);
    const auto result = coopdyn::solve_qp(h, g, c, d);
    EXPECT_EQ(result.status, QpStatus::infeasible);
    EXPECT_STREQ(coopdyn::to_string(result.status), "infeasible");
    expect_finite(result);
}

TEST(QpSolverStatus, RandomInfeasibleProblems)
{
    // k random rows, plus the row -sum a_i c_i with bound -sum a_i d_i - delta (a_i > 0): a
    // non-negative combination of the rows reads 0 <= -delta, so no x satisfies them (Farkas).
    Rng rng(31);
    int infeasible = 0;
    const int problems = 300;
    for (int k = 0; k < problems; ++k) {
        const Index n = std::uniform_int_distribution<Index>(2, 10)(rng);
        const Index m = std::uniform_int_distribution<Index>(2, 30)(rng);
        Problem p;
        p.h = random_spd(n, std::pow(10.0, uniform(rng, 0, 6)), 1.0, rng);
        p.g = random_matrix(n, 1, rng);
        p.c = random_matrix(m, n, rng);
        p.d = random_matrix(m, 1, rng);
        const Index parts = std::uniform_int_distribution<Index>(1, std::min<Index>(m - 1, n + 2))(rng);
        make_last_row_contradict(p, parts, rng);
        DynamicSolver solver(n, m);
        const auto& result = solver.solve(p.h, p.g, p.c, p.d);
        infeasible += result.status == QpStatus::infeasible ? 1 : 0;
        EXPECT_EQ(result.status, QpStatus::infeasible) << "problem " << k;
        expect_finite(result);
    }
    std::printf("[qp infeasible] %d of %d infeasible problems reported infeasible\n", infeasible, problems);
}

TEST(QpSolverStatus, IterationCap)
{
    // Unconstrained minimum at (2, 2); both rows x_i <= 0 are active at the optimum: two steps.
    const Eigen::Matrix2d h = Eigen::Matrix2d::Identity();
    const Eigen::Vector2d g(-2, -2);
    const Eigen::Matrix2d c = Eigen::Matrix2d::Identity();
    const Eigen::Vector2d d = Eigen::Vector2d::Zero();
    coopdyn::QpSolver<double, 2, 2> solver;
    EXPECT_EQ(solver.iteration_limit(), 40);
    solver.set_iteration_limit(1);
    const auto& capped = solver.solve(h, g, c, d);
    EXPECT_EQ(capped.status, QpStatus::iteration_limit);
    EXPECT_EQ(capped.iterations, 1);
    EXPECT_TRUE(capped.x.allFinite() && std::isfinite(capped.objective));
    solver.set_iteration_limit(2);
    const auto& full = solver.solve(h, g, c, d);
    EXPECT_EQ(full.status, QpStatus::solved);
    EXPECT_LE(full.x.cwiseAbs().maxCoeff(), 1e-15);
    EXPECT_NEAR(full.multipliers(0), 2.0, 1e-15);
    EXPECT_NEAR(full.multipliers(1), 2.0, 1e-15);
    EXPECT_EQ(full.active_count, 2);
}

TEST(QpSolverStatus, SemidefiniteAndIndefiniteHessians)
{
    Rng rng(5);
    const MatrixXd factor = random_matrix(4, 3, rng);
    const MatrixXd semidefinite = factor * factor.transpose();  // rank 3
    MatrixXd indefinite = MatrixXd::Identity(4, 4);
    indefinite(2, 2) = -1;
    const VectorXd g = VectorXd::Ones(4);
    const MatrixXd c = random_matrix(5, 4, rng);
    const VectorXd d = VectorXd::Ones(5);
    for (const MatrixXd& h : {semidefinite, indefinite, MatrixXd(MatrixXd::Zero(4, 4))}) {
        const auto result = coopdyn::solve_qp(h, g, c, d);
        EXPECT_EQ(result.status, QpStatus::not_positive_definite);
        EXPECT_EQ(result.x, VectorXd::Zero(4));
        EXPECT_EQ(result.objective, 0.0);
        expect_finite(result);
    }
    EXPECT_STREQ(coopdyn::to_string(QpStatus::not_positive_definite), "not_positive_definite");
    EXPECT_STREQ(coopdyn::to_string(QpStatus::solved), "solved");
    EXPECT_STREQ(coopdyn::to_string(QpStatus::iteration_limit), "iteration_limit");
}

TEST(QpSolverStatus, NoRowsAndZeroRows)
{
    const Eigen::Matrix3d h = Eigen::Vector3d(1, 2, 4).asDiagonal();
    const Eigen::Vector3d g(1, 1, 1);
    const auto free = coopdyn::solve_qp(h, g, MatrixXd(0, 3), VectorXd(0));
    EXPECT_EQ(free.status, QpStatus::solved);
    EXPECT_TRUE(free.x.isApprox(Eigen::Vector3d(-1, -0.5, -0.25)));
    // 0 x <= 1 holds for every x; 0 x <= -1 for none.
    Eigen::Matrix<double, 1, 3> zero = Eigen::Matrix<double, 1, 3>::Zero();
    EXPECT_EQ(coopdyn::solve_qp(h, g, zero, Eigen::Matrix<double, 1, 1>(1.0)).status, QpStatus::solved);
    EXPECT_EQ(coopdyn::solve_qp(h, g, zero, Eigen::Matrix<double, 1, 1>(-1.0)).status, QpStatus::infeasible);
}

TEST(QpSolverStatusDeathTest, WrongSizesStopInReleaseToo)
{
    // A problem of another size than the workspace would read and write past its buffers: the
    // solver stops with a message (COOPDYN_REQUIRE_SHAPE, active in Release).
    DynamicSolver solver(3, 5);
    const MatrixXd h = MatrixXd::Identity(4, 4);
    const VectorXd g = VectorXd::Zero(4);
    const MatrixXd c = MatrixXd::Zero(5, 4);
    const VectorXd d = VectorXd::Zero(5);
    EXPECT_DEATH(solver.solve(h, g, c, d), "sized for another problem");
}

// ---------------------------------------------------------------------------------------------
// D. Warm start in a control loop.

/// A contact-force QP: `contacts` point contacts with 3D forces (n = 3 contacts), each limited by
/// a 13-facet friction pyramid c_k^T f <= 0 plus fn_min <= fn <= fn_max (15 rows per contact),
/// tracking a desired force in the metric of a random SPD H (condition ~100).
struct ContactProblem {
    MatrixXd h;
    MatrixXd c;
    VectorXd d;
    VectorXd desired;  // g = -H desired
};

ContactProblem contact_problem(Index contacts, Rng& rng)
{
    const Index n = 3 * contacts;
    const Index facets = 13;
    ContactProblem p;
    p.h = random_spd(n, 100.0, 1.0, rng);
    p.c = MatrixXd::Zero(15 * contacts, n);
    p.d = VectorXd::Zero(15 * contacts);
    p.desired.resize(n);
    for (Index k = 0; k < contacts; ++k) {
        const Eigen::Matrix3d frame =
            Eigen::Quaterniond(Eigen::Vector4d(random_matrix(4, 1, rng))).normalized().toRotationMatrix();
        const double friction = uniform(rng, 0.3, 0.8);
        for (Index j = 0; j < facets; ++j) {
            const double angle = 2 * 3.141592653589793 * static_cast<double>(j) / static_cast<double>(facets);
            const Eigen::Vector3d local(std::cos(angle), std::sin(angle), -friction);
            p.c.block(15 * k + j, 3 * k, 1, 3) = (frame * local).transpose();
        }
        p.c.block(15 * k + 13, 3 * k, 1, 3) = frame.col(2).transpose();   // fn <= fn_max
        p.d(15 * k + 13) = 50.0;
        p.c.block(15 * k + 14, 3 * k, 1, 3) = -frame.col(2).transpose();  // fn >= fn_min
        p.d(15 * k + 14) = -1.0;
        // Desired force: tangential part often outside the cone, so a few facets are active.
        const Eigen::Vector3d local(uniform(rng, -8, 8), uniform(rng, -8, 8), uniform(rng, 0, 15));
        p.desired.segment(3 * k, 3) = frame * local;
    }
    return p;
}

TEST(QpSolverWarmStart, SameAnswerFewerSteps)
{
    Rng rng(2024);
    double worst = 0;
    long cold_steps = 0;
    long warm_steps = 0;
    int solves = 0;
    for (const Index contacts : {Index(2), Index(4)}) {
        const ContactProblem base = contact_problem(contacts, rng);
        const Index n = base.h.rows();
        const Index m = base.c.rows();
        DynamicSolver cold(n, m);
        DynamicSolver warm(n, m);
        const VectorXd phase = random_matrix(n, 1, rng) * 3.0;
        for (int tick = 0; tick < 500; ++tick) {
            // The desired force drifts slowly (1 ms ticks of a ~1 Hz motion), H changes a little.
            const double time = 1e-3 * tick;
            VectorXd desired = base.desired;
            for (Index i = 0; i < n; ++i) {
                desired(i) += 4.0 * std::sin(2 * 3.141592653589793 * time + phase(i));
            }
            const MatrixXd h = base.h * (1.0 + 0.1 * std::sin(time));
            const VectorXd g = -h * desired;
            const auto& cold_result = cold.solve(h, g, base.c, base.d);
            const auto& warm_result = warm.solve_warm(h, g, base.c, base.d);
            ASSERT_EQ(cold_result.status, QpStatus::solved);
            ASSERT_EQ(warm_result.status, QpStatus::solved);
            // The minimiser is unique and both solves are backward stable on cond(H) = 100.
            const double difference = (warm_result.x - cold_result.x).norm() / (1 + cold_result.x.norm());
            worst = std::max(worst, difference);
            EXPECT_LE(difference, 1e-12) << "tick " << tick;
            cold_steps += cold_result.iterations;
            warm_steps += warm_result.iterations;
            ++solves;
        }
    }
    std::printf("[qp warm start] %d solves (6 x 30 and 12 x 60 contact QPs): steps per solve cold %.2f, warm %.2f; "
                "worst |x_warm - x_cold| / (1 + |x|) %.2e\n",
                solves, static_cast<double>(cold_steps) / solves, static_cast<double>(warm_steps) / solves, worst);
    EXPECT_LT(warm_steps, cold_steps);
}

TEST(QpSolverWarmStart, RandomProblemsAgreeWithCold)
{
    // Warm starts from an unrelated problem's active set still give the cold answer.
    Rng rng(99);
    for (int k = 0; k < 200; ++k) {
        const Index n = std::uniform_int_distribution<Index>(2, 10)(rng);
        const Problem first = random_problem(n, 3 * n, n, 5, 1e4, rng);
        const Problem second = random_problem(n, 3 * n, n / 2, 5, 1e4, rng);
        DynamicSolver solver(n, first.c.rows());
        solver.solve(first.h, first.g, first.c, first.d);
        const VectorXd warm_x = solver.solve_warm(second.h, second.g, second.c, second.d).x;
        ASSERT_EQ(solver.result().status, QpStatus::solved);
        const VectorXd cold_x = solver.solve(second.h, second.g, second.c, second.d).x;
        EXPECT_LE((warm_x - cold_x).norm(), 1e-9 * (1 + cold_x.norm())) << "problem " << k;
    }
}

// ---------------------------------------------------------------------------------------------
// E. float.

TEST(QpSolverFloat, AgreesWithDouble)
{
    Rng rng(8);
    const ContactProblem p = contact_problem(2, rng);
    const VectorXd g = -p.h * p.desired;
    const auto reference = coopdyn::solve_qp(p.h, g, p.c, p.d);
    const Eigen::Matrix<float, 6, 6> h = p.h.cast<float>();
    const Eigen::Matrix<float, 6, 1> gf = g.cast<float>();
    const Eigen::Matrix<float, 30, 6> c = p.c.cast<float>();
    const Eigen::Matrix<float, 30, 1> d = p.d.cast<float>();
    const coopdyn::QpResult<float, 6, 30> result = coopdyn::solve_qp(h, gf, c, d);
    ASSERT_EQ(result.status, QpStatus::solved);
    ASSERT_EQ(reference.status, QpStatus::solved);
    EXPECT_GT(reference.active_count, 0);
    // Float rounding (6e-8) amplified by cond(H) = 100 and the data's own rounding to float.
    const double difference = (result.x.cast<double>() - reference.x).norm() / reference.x.norm();
    EXPECT_LE(difference, 1e-4);
    std::printf("[qp float] 6 x 30 contact QP, %d rows active: |x_float - x_double| / |x| = %.2e\n",
                reference.active_count, difference);
}

// ---------------------------------------------------------------------------------------------
// F. No allocation.

using allocation_counter::Allocations;
using allocation_counter::count_allocations;

TEST(QpSolverAllocation, DetectorFires)
{
    const Allocations eigen = count_allocations([] {
        Eigen::VectorXd values = Eigen::VectorXd::Ones(100);
        allocation_counter::sink = values.data();
    });
    EXPECT_GE(eigen.eigen, 1);
    const Allocations dynamic_solver = count_allocations([] {
        DynamicSolver solver(6, 30);
        allocation_counter::sink = &solver;
    });
    EXPECT_GE(dynamic_solver.eigen, 1);  // the constructor allocates (and nothing else should)
}

TEST(QpSolverAllocation, SolvesDoNotAllocate)
{
    Rng rng(12);
    const ContactProblem p = contact_problem(2, rng);
    const ContactProblem p4 = contact_problem(4, rng);
    const Eigen::Matrix<double, 6, 6> h = p.h;
    const Eigen::Matrix<double, 6, 1> g = -p.h * p.desired;
    const Eigen::Matrix<double, 30, 6> c = p.c;
    const Eigen::Matrix<double, 30, 1> d = p.d;
    const VectorXd g4 = -p4.h * p4.desired;
    coopdyn::QpSolver<double, 6, 30> fixed;
    DynamicSolver dynamic(12, 60);
    DynamicSolver dynamic_small(6, 30);
    DynamicSolver dynamic_once(p4.c);
    int active = 0;
    const Allocations counts = count_allocations([&] {
        coopdyn::QpSolver<double, 6, 30> fixed_once(c);  // fixed sizes: no heap, constructor included
        for (int tick = 0; tick < 10; ++tick) {
            // C set once: the per-tick path of the controller.
            active += fixed_once.solve(h, g, d).active_count;
            active += fixed_once.solve_warm(h, g, d).active_count;
            fixed_once.set_constraints(c);
            dynamic_once.set_constraints(p4.c);
            active += dynamic_once.solve(p4.h, g4, p4.d).active_count;
            active += dynamic_once.solve_warm(p4.h, g4, p4.d).active_count;
            const auto result = coopdyn::solve_qp(h, g, c, d);
            active += result.active_count;
            active += fixed.solve(h, g, c, d).active_count;
            active += fixed.solve_warm(h, g, c, d).active_count;
            active += dynamic.solve(p4.h, g4, p4.c, p4.d).active_count;
            active += dynamic.solve_warm(p4.h, g4, p4.c, p4.d).active_count;
            active += dynamic_small.solve_warm(h, g, c, d).active_count;  // fixed arguments, dynamic solver
        }
    });
    EXPECT_EQ(counts.operator_new, 0);
    EXPECT_EQ(counts.eigen, 0);
    // Each kind on its own, so that a failure names the culprit.
    const Allocations one_shot = count_allocations([&] { active += coopdyn::solve_qp(h, g, c, d).active_count; });
    const Allocations dynamic_only = count_allocations([&] {
        active += dynamic.solve(p4.h, g4, p4.c, p4.d).active_count;
        active += dynamic.solve_warm(p4.h, g4, p4.c, p4.d).active_count;
    });
    const Allocations set_once_only = count_allocations([&] {
        dynamic_once.set_constraints(p4.c);
        active += dynamic_once.solve_warm(p4.h, g4, p4.d).active_count;
    });
    EXPECT_EQ(one_shot.operator_new + one_shot.eigen, 0);
    EXPECT_EQ(dynamic_only.operator_new + dynamic_only.eigen, 0);
    EXPECT_EQ(set_once_only.operator_new + set_once_only.eigen, 0);
    EXPECT_GT(active, 0);
    EXPECT_EQ(dynamic.result().status, QpStatus::solved);
    EXPECT_EQ(dynamic_once.result().status, QpStatus::solved);
    std::printf("[qp allocation] 100 solves and 20 set_constraints (fixed 6 x 30, dynamic 12 x 60 and 6 x 30, cold "
                "and warm, C per solve and C set once): operator new %ld, Eigen malloc %ld\n",
                counts.operator_new, counts.eigen);
}

// ---------------------------------------------------------------------------------------------
// G. Constraints set once.

/// A problem of n variables and m rows: random_problem with m / 8 degenerate rows, 1 .. n rows
/// active at the optimum and cond(H) up to 1e6; when `feasible` is false its last row is made to
/// contradict the first few (make_last_row_contradict).
Problem shaped_problem(Index n, Index m, bool feasible, Rng& rng)
{
    const Index degenerate = m / 8;
    const Index active = std::uniform_int_distribution<Index>(1, n)(rng);
    Problem p = random_problem(n, m - degenerate, active, degenerate, std::pow(10.0, uniform(rng, 0, 6)), rng);
    if (!feasible) {
        make_last_row_contradict(p, std::uniform_int_distribution<Index>(1, n + 2)(rng), rng);
    }
    return p;
}

/// Bit-identical results: the set-once path and solve_qp run the same arithmetic.
template <typename A, typename B> void expect_same_result(const A& a, const B& b, const char* what, int k)
{
    EXPECT_EQ(a.status, b.status) << what << " problem " << k;
    EXPECT_EQ(a.iterations, b.iterations) << what << " problem " << k;
    EXPECT_EQ(a.active_count, b.active_count) << what << " problem " << k;
    EXPECT_TRUE(a.x == b.x) << what << " problem " << k;
    EXPECT_TRUE(a.multipliers == b.multipliers) << what << " problem " << k;
    EXPECT_TRUE(a.active == b.active) << what << " problem " << k;
    EXPECT_EQ(a.objective, b.objective) << what << " problem " << k;
}

/// For `problems` seeded problems of N variables and M rows (every second one infeasible): a
/// fixed-size and a dynamic-size solver given C once (constructor) agree with solve_qp of the
/// same sizes, cold and then warm from the previous problem's active set; the feasible ones
/// satisfy the KKT conditions (tolerances of test A). Returns the number solved.
template <int N, int M> int check_set_once_shape(int problems, Rng& rng)
{
    using Fixed = coopdyn::QpSolver<double, N, M>;
    int solved = 0;
    Fixed fixed_once{Eigen::Matrix<double, M, N>::Zero()};
    Fixed fixed_four;
    DynamicSolver dynamic_once(N, M);
    DynamicSolver dynamic_four(N, M);
    for (int k = 0; k < problems; ++k) {
        const bool feasible = k % 2 == 0;
        const Problem p = shaped_problem(N, M, feasible, rng);
        const Eigen::Matrix<double, N, N> h = p.h;
        const Eigen::Matrix<double, N, 1> g = p.g;
        const Eigen::Matrix<double, M, N> c = p.c;
        const Eigen::Matrix<double, M, 1> d = p.d;
        const auto reference = coopdyn::solve_qp(h, g, c, d);
        const auto dynamic_reference = coopdyn::solve_qp(p.h, p.g, p.c, p.d);
        expect_same_result(Fixed(c).solve(h, g, d), reference, "fixed, constructor", k);
        expect_same_result(DynamicSolver(p.c).solve(p.h, p.g, p.d), dynamic_reference, "dynamic, constructor", k);
        // Warm from the previous problem's active set: set_constraints then the three-argument
        // solve against the four-argument one from the same state.
        fixed_once.set_constraints(c);
        dynamic_once.set_constraints(p.c);
        expect_same_result(fixed_once.solve_warm(h, g, d), fixed_four.solve_warm(h, g, c, d), "fixed, warm", k);
        expect_same_result(dynamic_once.solve_warm(p.h, p.g, p.d), dynamic_four.solve_warm(p.h, p.g, p.c, p.d),
                           "dynamic, warm", k);
        EXPECT_EQ(reference.status, feasible ? QpStatus::solved : QpStatus::infeasible) << "problem " << k;
        EXPECT_EQ(dynamic_reference.status, reference.status) << "problem " << k;
        if (reference.status != QpStatus::solved) {
            continue;
        }
        ++solved;
        const Kkt residuals = kkt_residuals(p, fixed_once.result().x, fixed_once.result().multipliers);
        EXPECT_LE(residuals.stationarity, 4 * eps * static_cast<double>(2 * N + 1 + fixed_once.result().iterations))
            << "problem " << k;
        EXPECT_LE(residuals.feasibility, 1000 * eps * p.condition) << "problem " << k;
        EXPECT_LE(residuals.dual, 0.0) << "problem " << k;
        EXPECT_LE(residuals.complementarity, 1000 * eps * p.condition) << "problem " << k;
    }
    return solved;
}

TEST(QpSolverSetOnce, SameResultsAsSolveQp)
{
    Rng rng(4521);
    const int problems = 40;
    const int solved_6 = check_set_once_shape<6, 30>(problems, rng);
    const int solved_12 = check_set_once_shape<12, 45>(problems, rng);
    const int solved_20 = check_set_once_shape<20, 80>(problems, rng);
    EXPECT_EQ(solved_6, problems / 2);
    EXPECT_EQ(solved_12, problems / 2);
    EXPECT_EQ(solved_20, problems / 2);
    std::printf("[qp set once] 6 x 30, 12 x 45, 20 x 80: %d problems each (half infeasible), fixed and dynamic, "
                "cold and warm: identical to solve_qp\n",
                problems);
}

TEST(QpSolverSetOnce, NewConstraintsGiveTheNewAnswer)
{
    Rng rng(77);
    int changed = 0;
    for (int k = 0; k < 60; ++k) {
        const Problem first = shaped_problem(6, 30, true, rng);
        const Problem second = shaped_problem(6, 30, k % 3 != 0, rng);
        const auto first_answer = coopdyn::solve_qp(first.h, first.g, first.c, first.d);
        // The same H and g with the second problem's rows and bounds.
        const auto reference = coopdyn::solve_qp(first.h, first.g, second.c, second.d);
        DynamicSolver solver(first.c);
        expect_same_result(solver.solve(first.h, first.g, first.d), first_answer, "first C", k);
        solver.set_constraints(second.c);
        EXPECT_TRUE(solver.constraints() == second.c);
        expect_same_result(solver.solve(first.h, first.g, second.d), reference, "second C", k);
        changed += (reference.x - first_answer.x).norm() > 1e-6 * (1 + first_answer.x.norm()) ? 1 : 0;
        // Warm across the change: the first C's active set is only a starting guess.
        solver.set_constraints(first.c);
        solver.solve(first.h, first.g, first.d);
        solver.set_constraints(second.c);
        const auto& warm = solver.solve_warm(first.h, first.g, second.d);
        ASSERT_EQ(warm.status, reference.status) << "problem " << k;
        if (reference.status == QpStatus::solved) {
            EXPECT_LE((warm.x - reference.x).norm(), 1e-9 * (1 + reference.x.norm())) << "problem " << k;
        }
    }
    EXPECT_GE(changed, 50);  // the new rows move the answer (a check that the test tests)
}

}  // namespace
