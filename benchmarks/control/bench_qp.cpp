// Benchmarks of the dense QP solver (coopdyn/numerics/qp_solver.hpp, Goldfarb-Idnani) on
// contact-force QPs like a cooperative controller's per-tick wrench QP:
//
//   BM_Cold<C>            QpSolver<double, 3C, 15C>::solve, the same problem every call
//   BM_SolveQp<C>         the one-shot solve_qp (builds the fixed-size workspace on the stack)
//   BM_WarmSame<C>        solve_warm on the same problem as the previous call
//   BM_ColdSequence<C>    solve along a slowly changing sequence (1 ms ticks of a 1 Hz motion)
//   BM_WarmSequence<C>    solve_warm along the same sequence, each tick warm-started from the last
//   BM_ColdDynamic<C>     QpSolver<double, Dynamic, Dynamic>::solve, the BM_Cold problem
//   QpShape/<case>/<sizes>/<cold|warm>/<set_once|four_args>
//                         the controller's two- and three-palm QPs (palms2_6x30, palms3_12x45) and
//                         a random 20 x 80 (random_20x80), fixed and dynamic sizes; cold = solve,
//                         warm = solve_warm after solving the same problem; set_once = C given once
//                         (set_constraints) and solve(H, g, d) per call, four_args = solve(H, g,
//                         C, d) per call. Define COOPDYN_QP_BASELINE to build the file against a
//                         coopdyn without set_constraints (the four_args cases only), for
//                         before/after comparisons.
//
// The QPs are those of qp_cases.hpp. BM_*<C>: C point contacts with 3D forces (n = 3C variables),
// each limited by a 13-facet friction pyramid and 1 <= f_n <= 50 (15 rows per contact: m = 15C):
// C = 2 is the 6 x 30 two-contact QP, C = 4 the 12 x 60 four-contact one. The objective tracks a
// desired force, outside the friction cone for some contacts, in the metric of a random SPD H of
// condition 100, so a few rows are active at the optimum.
// Before its timed loop every variant checks the KKT conditions of its first solve (relative
// residuals <= 1e-9) and skips with an error otherwise. The counters: "steps", the mean number of
// Goldfarb-Idnani steps per solve, and "active", the mean number of rows active at the optimum.

#include <coopdyn/numerics/qp_solver.hpp>

#include "qp_cases.hpp"

#include <benchmark/benchmark.h>

#include <vector>

namespace {

using coopdyn::Dynamic;
using coopdyn_bench::ContactQp;
using Eigen::Index;

/// True when the result satisfies the KKT conditions to 1e-9 relative; otherwise skips.
template <typename Result>
bool check(benchmark::State& state, const ContactQp& p, const Eigen::VectorXd& g, const Result& result)
{
    if (!coopdyn_bench::satisfies_kkt(p, g, result)) {
        state.SkipWithError("QP result fails its KKT check");
        return false;
    }
    return true;
}

const ContactQp& case_for(Index contacts)
{
    static const ContactQp two = coopdyn_bench::contact_qp(2);
    static const ContactQp four = coopdyn_bench::contact_qp(4);
    return contacts == 2 ? two : four;
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

/// The QpShape cases: 0 the two-palm 6 x 30, 1 the three-palm 12 x 45, 2 the random 20 x 80.
const ContactQp& shape_case(int shape)
{
    static const ContactQp palms2 = coopdyn_bench::palm_qp(2);
    static const ContactQp palms3 = coopdyn_bench::palm_qp(3);
    static const ContactQp random = coopdyn_bench::random_qp(20, 80);
    return shape == 0 ? palms2 : shape == 1 ? palms3 : random;
}

/// One solve: cold or warm, C given per call (four_args) or set once before (set_once).
template <bool Warm, bool SetOnce, typename Solver, typename H, typename G, typename C, typename D>
const typename Solver::Result& solve_with(Solver& solver, const H& h, const G& g, const C& c, const D& d)
{
#ifndef COOPDYN_QP_BASELINE
    if constexpr (SetOnce) {
        return Warm ? solver.solve_warm(h, g, d) : solver.solve(h, g, d);
    }
#endif
    return Warm ? solver.solve_warm(h, g, c, d) : solver.solve(h, g, c, d);
}

template <int N, int M, int Shape, bool FixedSizes, bool Warm, bool SetOnce> void BM_Shape(benchmark::State& state)
{
    constexpr int n = FixedSizes ? N : Dynamic;
    constexpr int m = FixedSizes ? M : Dynamic;
    const ContactQp& p = shape_case(Shape);
    if (p.h.rows() != N || p.c.rows() != M) {
        state.SkipWithError("no such QP (no seeded case gave one)");
        return;
    }
    const coopdyn_bench::SizedQp<n, m> q(p);
    coopdyn::QpSolver<double, n, m> solver(N, M);
#ifndef COOPDYN_QP_BASELINE
    solver.set_constraints(q.c);
#endif
    solve_with<false, SetOnce>(solver, q.h, q.g, q.c, q.d);  // the warm start's active set
    if (!check(state, p, p.g, solve_with<Warm, SetOnce>(solver, q.h, q.g, q.c, q.d))) {
        return;
    }
    for (auto _ : state) {
        benchmark::ClobberMemory();  // the inputs may change between ticks
        const auto& result = solve_with<Warm, SetOnce>(solver, q.h, q.g, q.c, q.d);
        benchmark::DoNotOptimize(result.x.data());
    }
    state.counters["steps"] = solver.result().iterations;
    state.counters["active"] = solver.result().active_count;
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

// QpShape/<case>/<fixed|dynamic>/<cold|warm>/<api> for one case and one API.
#define COOPDYN_BENCHMARK_SHAPE(N, M, SHAPE, LABEL, SET_ONCE, API)                                                     \
    BENCHMARK_TEMPLATE(BM_Shape, N, M, SHAPE, true, false, SET_ONCE)->Name("QpShape/" LABEL "/fixed/cold/" API);     \
    BENCHMARK_TEMPLATE(BM_Shape, N, M, SHAPE, true, true, SET_ONCE)->Name("QpShape/" LABEL "/fixed/warm/" API);      \
    BENCHMARK_TEMPLATE(BM_Shape, N, M, SHAPE, false, false, SET_ONCE)->Name("QpShape/" LABEL "/dynamic/cold/" API);  \
    BENCHMARK_TEMPLATE(BM_Shape, N, M, SHAPE, false, true, SET_ONCE)->Name("QpShape/" LABEL "/dynamic/warm/" API)

COOPDYN_BENCHMARK_SHAPE(6, 30, 0, "palms2_6x30", false, "four_args");
COOPDYN_BENCHMARK_SHAPE(12, 45, 1, "palms3_12x45", false, "four_args");
COOPDYN_BENCHMARK_SHAPE(20, 80, 2, "random_20x80", false, "four_args");
#ifndef COOPDYN_QP_BASELINE
COOPDYN_BENCHMARK_SHAPE(6, 30, 0, "palms2_6x30", true, "set_once");
COOPDYN_BENCHMARK_SHAPE(12, 45, 1, "palms3_12x45", true, "set_once");
COOPDYN_BENCHMARK_SHAPE(20, 80, 2, "random_20x80", true, "set_once");
#endif
