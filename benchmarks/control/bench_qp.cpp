// Benchmarks of the dense QP solver (coopdyn/numerics/qp_solver.hpp, Goldfarb-Idnani) on
// contact-force QPs like a cooperative controller's per-tick wrench QP:
//
//   BM_Cold<C>            QpSolver<double, 3C, 15C>::solve, the same problem every call
//   BM_SolveQp<C>         the one-shot solve_qp (builds the fixed-size workspace on the stack)
//   BM_WarmSame<C>        solve_warm on the same problem as the previous call
//   BM_ColdSequence<C>    solve along a slowly changing sequence (1 ms ticks of a 1 Hz motion)
//   BM_WarmSequence<C>    solve_warm along the same sequence, each tick warm-started from the last
//   BM_ColdDynamic<C>     QpSolver<double, Dynamic, Dynamic>::solve, the BM_Cold problem
//
// C contacts with 3D forces (n = 3C variables), each limited by a 13-facet friction pyramid and
// 1 <= f_n <= 50 (15 rows per contact: m = 15C): C = 2 is the 6 x 30 two-arm QP, C = 4 the 12 x 60
// four-arm one. The objective tracks a desired force, outside the friction cone for some contacts,
// in the metric of a random SPD H of condition 100, so a few rows are active at the optimum.
// Before its timed loop every variant checks the KKT conditions of its first solve (relative
// residuals <= 1e-9) and skips with an error otherwise. The counters: "steps", the mean number of
// Goldfarb-Idnani steps per solve, and "active", the mean number of rows active at the optimum.

#include <coopdyn/numerics/qp_solver.hpp>

#include <Eigen/Geometry>
#include <Eigen/QR>
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

namespace {

using coopdyn::Dynamic;
using Eigen::Index;
using MatrixX = Eigen::MatrixXd;
using VectorX = Eigen::VectorXd;
using Rng = std::mt19937;

constexpr double two_pi = 6.283185307179586;

double uniform(Rng& rng, double low, double high) { return std::uniform_real_distribution<double>(low, high)(rng); }

MatrixX random_matrix(Index rows, Index cols, Rng& rng)
{
    MatrixX result(rows, cols);
    for (Index k = 0; k < result.size(); ++k) {
        result(k) = uniform(rng, -1, 1);
    }
    return result;
}

/// Q diag(1 .. condition, log-spaced) Q^T with a random orthogonal Q.
MatrixX random_spd(Index n, double condition, Rng& rng)
{
    const MatrixX q = Eigen::HouseholderQR<MatrixX>(random_matrix(n, n, rng)).householderQ();
    VectorX eigenvalues(n);
    for (Index i = 0; i < n; ++i) {
        eigenvalues(i) = std::pow(condition, static_cast<double>(i) / static_cast<double>(n - 1));
    }
    const MatrixX h = q * eigenvalues.asDiagonal() * q.transpose();
    return 0.5 * (h + h.transpose());
}

/// The contact QP of the file comment, plus a sequence of slowly changing gradients.
struct ContactQp {
    MatrixX h;
    VectorX g;
    MatrixX c;
    VectorX d;
    std::vector<VectorX> sequence;  // g at successive 1 ms ticks
};

ContactQp contact_qp(Index contacts)
{
    Rng rng(static_cast<std::uint32_t>(1000 + contacts));
    const Index n = 3 * contacts;
    const Index facets = 13;
    ContactQp p;
    p.h = random_spd(n, 100.0, rng);
    p.c = MatrixX::Zero(15 * contacts, n);
    p.d = VectorX::Zero(15 * contacts);
    VectorX desired(n);
    for (Index k = 0; k < contacts; ++k) {
        const Eigen::Matrix3d frame =
            Eigen::Quaterniond(Eigen::Vector4d(random_matrix(4, 1, rng))).normalized().toRotationMatrix();
        const double friction = uniform(rng, 0.3, 0.8);
        for (Index j = 0; j < facets; ++j) {
            const double angle = two_pi * static_cast<double>(j) / static_cast<double>(facets);
            const Eigen::Vector3d local(std::cos(angle), std::sin(angle), -friction);
            p.c.block(15 * k + j, 3 * k, 1, 3) = (frame * local).transpose();
        }
        p.c.block(15 * k + 13, 3 * k, 1, 3) = frame.col(2).transpose();
        p.d(15 * k + 13) = 50.0;
        p.c.block(15 * k + 14, 3 * k, 1, 3) = -frame.col(2).transpose();
        p.d(15 * k + 14) = -1.0;
        const Eigen::Vector3d local(uniform(rng, -12, 12), uniform(rng, -12, 12), uniform(rng, 0, 10));
        desired.segment(3 * k, 3) = frame * local;
    }
    p.g = -p.h * desired;
    const VectorX phase = random_matrix(n, 1, rng) * 3.0;
    for (int tick = 0; tick < 1000; ++tick) {
        VectorX moving = desired;
        for (Index i = 0; i < n; ++i) {
            moving(i) += 4.0 * std::sin(two_pi * 1e-3 * tick + phase(i));
        }
        p.sequence.push_back(-p.h * moving);
    }
    return p;
}

const ContactQp& case_for(Index contacts)
{
    static const ContactQp two = contact_qp(2);
    static const ContactQp four = contact_qp(4);
    return contacts == 2 ? two : four;
}

/// True when the result satisfies the KKT conditions to 1e-9 relative; otherwise skips.
template <typename Result>
bool check(benchmark::State& state, const ContactQp& p, const VectorX& g, const Result& result)
{
    const VectorX x = result.x;
    const VectorX lambda = result.multipliers;
    const double scale = p.h.norm() * x.norm() + g.norm() + p.c.norm() * lambda.norm();
    const double stationarity = (p.h * x + g + p.c.transpose() * lambda).norm() / scale;
    const VectorX slack = p.c * x - p.d;
    const double feasibility = slack.maxCoeff() / (p.c.norm() * x.norm() + p.d.norm());
    const double complementarity = lambda.cwiseProduct(slack).cwiseAbs().maxCoeff() / scale;
    if (result.status != coopdyn::QpStatus::solved || stationarity > 1e-9 || feasibility > 1e-9 ||
        complementarity > 1e-9 || lambda.minCoeff() < 0) {
        state.SkipWithError("QP result fails its KKT check");
        return false;
    }
    return true;
}

template <int Contacts> struct Fixed {
    static constexpr int n = 3 * Contacts;
    static constexpr int m = 15 * Contacts;
    Eigen::Matrix<double, n, n> h;
    Eigen::Matrix<double, n, 1> g;
    Eigen::Matrix<double, m, n> c;
    Eigen::Matrix<double, m, 1> d;
    std::vector<Eigen::Matrix<double, n, 1>> sequence;

    explicit Fixed(const ContactQp& p) : h(p.h), g(p.g), c(p.c), d(p.d), sequence(p.sequence.begin(), p.sequence.end()) {}
};

template <int Contacts> void BM_Cold(benchmark::State& state)
{
    const ContactQp& p = case_for(Contacts);
    const Fixed<Contacts> f(p);
    coopdyn::QpSolver<double, Fixed<Contacts>::n, Fixed<Contacts>::m> solver;
    if (!check(state, p, p.g, solver.solve(f.h, f.g, f.c, f.d))) {
        return;
    }
    for (auto _ : state) {
        benchmark::ClobberMemory();  // the inputs may change between ticks
        const auto& result = solver.solve(f.h, f.g, f.c, f.d);
        benchmark::DoNotOptimize(result.x.data());
    }
    state.counters["steps"] = solver.result().iterations;
    state.counters["active"] = solver.result().active_count;
}

template <int Contacts> void BM_SolveQp(benchmark::State& state)
{
    const ContactQp& p = case_for(Contacts);
    const Fixed<Contacts> f(p);
    if (!check(state, p, p.g, coopdyn::solve_qp(f.h, f.g, f.c, f.d))) {
        return;
    }
    for (auto _ : state) {
        benchmark::ClobberMemory();
        auto result = coopdyn::solve_qp(f.h, f.g, f.c, f.d);
        benchmark::DoNotOptimize(result.x.data());
    }
}

template <int Contacts> void BM_WarmSame(benchmark::State& state)
{
    const ContactQp& p = case_for(Contacts);
    const Fixed<Contacts> f(p);
    coopdyn::QpSolver<double, Fixed<Contacts>::n, Fixed<Contacts>::m> solver;
    solver.solve(f.h, f.g, f.c, f.d);
    if (!check(state, p, p.g, solver.solve_warm(f.h, f.g, f.c, f.d))) {
        return;
    }
    for (auto _ : state) {
        benchmark::ClobberMemory();
        const auto& result = solver.solve_warm(f.h, f.g, f.c, f.d);
        benchmark::DoNotOptimize(result.x.data());
    }
    state.counters["steps"] = solver.result().iterations;
}

/// Solves along the tick sequence, cold or warm; reports the mean steps per solve.
template <int Contacts, bool Warm> void run_sequence(benchmark::State& state)
{
    const ContactQp& p = case_for(Contacts);
    const Fixed<Contacts> f(p);
    coopdyn::QpSolver<double, Fixed<Contacts>::n, Fixed<Contacts>::m> solver;
    for (std::size_t k = 0; k < f.sequence.size(); ++k) {
        const auto& result = Warm ? solver.solve_warm(f.h, f.sequence[k], f.c, f.d)
                                  : solver.solve(f.h, f.sequence[k], f.c, f.d);
        if (!check(state, p, p.sequence[k], result)) {
            return;
        }
    }
    std::size_t tick = 0;
    long steps = 0;
    long active = 0;
    long solves = 0;
    for (auto _ : state) {
        benchmark::ClobberMemory();
        const auto& result = Warm ? solver.solve_warm(f.h, f.sequence[tick], f.c, f.d)
                                  : solver.solve(f.h, f.sequence[tick], f.c, f.d);
        benchmark::DoNotOptimize(result.x.data());
        steps += result.iterations;
        active += result.active_count;
        ++solves;
        tick = tick + 1 == f.sequence.size() ? 0 : tick + 1;
    }
    const double count = static_cast<double>(solves > 0 ? solves : 1);
    state.counters["steps"] = static_cast<double>(steps) / count;
    state.counters["active"] = static_cast<double>(active) / count;
}

template <int Contacts> void BM_ColdSequence(benchmark::State& state) { run_sequence<Contacts, false>(state); }
template <int Contacts> void BM_WarmSequence(benchmark::State& state) { run_sequence<Contacts, true>(state); }

template <int Contacts> void BM_ColdDynamic(benchmark::State& state)
{
    const ContactQp& p = case_for(Contacts);
    coopdyn::QpSolver<double, Dynamic, Dynamic> solver(p.h.rows(), p.c.rows());
    if (!check(state, p, p.g, solver.solve(p.h, p.g, p.c, p.d))) {
        return;
    }
    for (auto _ : state) {
        benchmark::ClobberMemory();
        const auto& result = solver.solve(p.h, p.g, p.c, p.d);
        benchmark::DoNotOptimize(result.x.data());
    }
}

}  // namespace

// C = 2 (6 x 30) and C = 4 (12 x 60) for every benchmark.
#define COOPDYN_BENCHMARK_CONTACTS(name)                               \
    BENCHMARK_TEMPLATE(name, 2)->Unit(benchmark::kNanosecond);         \
    BENCHMARK_TEMPLATE(name, 4)->Unit(benchmark::kNanosecond)

COOPDYN_BENCHMARK_CONTACTS(BM_Cold);
COOPDYN_BENCHMARK_CONTACTS(BM_SolveQp);
COOPDYN_BENCHMARK_CONTACTS(BM_WarmSame);
COOPDYN_BENCHMARK_CONTACTS(BM_ColdSequence);
COOPDYN_BENCHMARK_CONTACTS(BM_WarmSequence);
COOPDYN_BENCHMARK_CONTACTS(BM_ColdDynamic);
