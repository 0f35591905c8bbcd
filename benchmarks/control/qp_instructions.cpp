// A driver for instruction counts of the QP solver under `valgrind --tool=callgrind` (repeatable
// on a loaded machine, unlike wall-clock time): runs `solves` solves of one QpShape case of
// bench_qp.cpp (qp_cases.hpp) and prints the last result. Instructions per solve:
// (Ir(solves = N2) - Ir(solves = N1)) / (N2 - N1), which cancels the set-up.
//
//   qp_instructions <palms2|palms3|random20> <fixed|dynamic> <cold|warm> <set_once|four_args> <solves>
//
// Define COOPDYN_QP_BASELINE to build it against a coopdyn without set_constraints (four_args only).

#include <coopdyn/numerics/qp_solver.hpp>

#include "qp_cases.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace {

using coopdyn::Dynamic;
using coopdyn_bench::ContactQp;

template <int N, int M, bool FixedSizes>
int run(const ContactQp& p, bool warm, bool set_once, long solves)
{
    constexpr int n = FixedSizes ? N : Dynamic;
    constexpr int m = FixedSizes ? M : Dynamic;
    if (p.h.rows() != N || p.c.rows() != M) {
        std::fprintf(stderr, "qp_instructions: no such QP\n");
        return 1;
    }
    const coopdyn_bench::SizedQp<n, m> q(p);
    const auto& h = q.h;
    const auto& g = q.g;
    const auto& c = q.c;
    const auto& d = q.d;
    coopdyn::QpSolver<double, n, m> solver(N, M);
#ifndef COOPDYN_QP_BASELINE
    solver.set_constraints(c);
#else
    if (set_once) {
        std::fprintf(stderr, "qp_instructions: set_once needs set_constraints\n");
        return 1;
    }
#endif
    long active = 0;
    for (long k = 0; k < solves; ++k) {
#ifndef COOPDYN_QP_BASELINE
        if (set_once) {
            active += (warm ? solver.solve_warm(h, g, d) : solver.solve(h, g, d)).active_count;
            continue;
        }
#endif
        active += (warm ? solver.solve_warm(h, g, c, d) : solver.solve(h, g, c, d)).active_count;
    }
    const auto& result = solver.result();
    std::printf("%s, %d steps, %d active, KKT %s, active sum %ld\n", coopdyn::to_string(result.status),
                result.iterations, result.active_count, coopdyn_bench::satisfies_kkt(p, p.g, result) ? "ok" : "FAILS",
                active);
    return 0;
}

template <int N, int M> int run_sizes(const ContactQp& p, bool fixed, bool warm, bool set_once, long solves)
{
    return fixed ? run<N, M, true>(p, warm, set_once, solves) : run<N, M, false>(p, warm, set_once, solves);
}

}  // namespace

int main(int argc, char** argv)
{
    if (argc != 6) {
        std::fprintf(stderr, "usage: %s <palms2|palms3|random20> <fixed|dynamic> <cold|warm> <set_once|four_args> <solves>\n",
                     argv[0]);
        return 2;
    }
    const bool fixed = std::strcmp(argv[2], "fixed") == 0;
    const bool warm = std::strcmp(argv[3], "warm") == 0;
    const bool set_once = std::strcmp(argv[4], "set_once") == 0;
    const long solves = std::atol(argv[5]);
    if (std::strcmp(argv[1], "palms2") == 0) {
        return run_sizes<6, 30>(coopdyn_bench::palm_qp(2), fixed, warm, set_once, solves);
    }
    if (std::strcmp(argv[1], "palms3") == 0) {
        return run_sizes<12, 45>(coopdyn_bench::palm_qp(3), fixed, warm, set_once, solves);
    }
    return run_sizes<20, 80>(coopdyn_bench::random_qp(20, 80), fixed, warm, set_once, solves);
}
