// Benchmarks of the coordination and analysis layer (docs/coordination.md, docs/analysis.md), per call:
//
//   BM_LoadDistribution<N>     LoadDistribution::distribute: h'^d = -G+_M h_o^d (26), O(N)
//   BM_WrenchDecomposition<N>  decompose_wrenches: internal (53) and external (54) parts of h'
//   BM_ApparentImpedance<N>    apparent_impedance(model, data): M (31), D (32), exact K (E3)
//   BM_FullTick<N>             one controller tick: coordinated setpoints (27) and tracking
//                              feed-forward (Theorem 1), load distribution (26), interaction
//                              dynamics (18), internal/external split (53)-(54)
//
// All use a random Model with fixed N (and BM_FullTickDynamic with N chosen at run time), built
// in a fixture outside the timed loop. Target (issue "Coordination and analysis"): full tick at
// N = 2 <= 1 us, allocation-free (the allocation check is tests/analysis/test_internal_wrenches).

#include <coopdyn/coopdyn.hpp>

#include "sample_systems.hpp"

#include <benchmark/benchmark.h>

namespace {

using coopdyn::Dynamic;
using coopdyn_test::Index;
using coopdyn_test::random_matrix;
using coopdyn_test::Rng;
using coopdyn_test::TickFixture;

/// The per-tick fixture plus the coordination/analysis workspaces and a desired object motion.
template <int Arms> struct AnalysisFixture : TickFixture<Arms> {
    using Base = TickFixture<Arms>;
    using typename Base::ModelType;

    coopdyn::LoadDistribution<ModelType> load_distribution;
    coopdyn::WrenchDecomposition<ModelType> decomposition;
    coopdyn::RigidBodyState<double> desired_object;
    coopdyn::Vector6<double> desired_acceleration;

    explicit AnalysisFixture(Index arms)
        : Base(arms), load_distribution(this->model), decomposition(this->model)
    {
        Rng rng(99u + static_cast<std::uint32_t>(arms));
        desired_object = this->state;
        desired_object.twist += 0.1 * random_matrix(6, 1, rng);
        desired_acceleration = random_matrix(6, 1, rng);
        coopdyn::interaction_dynamics(this->model, this->data, this->state, this->setpoints, this->disturbances);
    }
};

template <int N> void BM_LoadDistribution(benchmark::State& state)
{
    AnalysisFixture<N> f(N);
    Rng rng(5u);
    const coopdyn::Vector6<double> object_wrench = random_matrix(6, 1, rng, -10, 10);
    for (auto _ : state) {
        benchmark::ClobberMemory();
        f.load_distribution.distribute(f.data, object_wrench, f.setpoints);
        benchmark::DoNotOptimize(f.setpoints.wrenches.data());
    }
}

template <int N> void BM_WrenchDecomposition(benchmark::State& state)
{
    AnalysisFixture<N> f(N);
    for (auto _ : state) {
        benchmark::ClobberMemory();
        const auto& result = coopdyn::decompose_wrenches(f.model, f.data, f.decomposition);
        benchmark::DoNotOptimize(result.internal.data());
    }
}

template <int N> void BM_ApparentImpedance(benchmark::State& state)
{
    AnalysisFixture<N> f(N);
    for (auto _ : state) {
        benchmark::ClobberMemory();
        const auto impedance = coopdyn::apparent_impedance(f.model, f.data);
        benchmark::DoNotOptimize(impedance.stiffness.data());
    }
}

template <int Arms> void run_full_tick(benchmark::State& state, Index arms)
{
    AnalysisFixture<Arms> f(arms);
    for (auto _ : state) {
        benchmark::ClobberMemory();
        // Coordinated setpoints (27) and the tracking feed-forward of Theorem 1 ...
        coopdyn::coordinate_setpoints(f.model, f.desired_object, f.desired_acceleration, f.setpoints);
        const coopdyn::Vector6<double> object_wrench =
            coopdyn::tracking_object_wrench(f.model, f.desired_object, f.desired_acceleration);
        // ... distributed without squeezing (26) at the current grasp configuration ...
        coopdyn::grasp_kinematics(f.model, f.data, f.state);
        f.load_distribution.distribute(f.data, object_wrench, f.setpoints);
        // ... the interaction wrenches (18) and their internal/external split (53)-(54).
        coopdyn::interaction_dynamics(f.model, f.data, f.state, f.setpoints, f.disturbances);
        const auto& result = coopdyn::decompose_wrenches(f.model, f.data, f.decomposition);
        benchmark::DoNotOptimize(result.external.data());
    }
}

template <int N> void BM_FullTick(benchmark::State& state) { run_full_tick<N>(state, N); }
template <int N> void BM_FullTickDynamic(benchmark::State& state) { run_full_tick<Dynamic>(state, N); }

#define COOPDYN_BENCHMARK_ARMS(name) \
    BENCHMARK_TEMPLATE(name, 2);     \
    BENCHMARK_TEMPLATE(name, 4);     \
    BENCHMARK_TEMPLATE(name, 8);     \
    BENCHMARK_TEMPLATE(name, 16)

COOPDYN_BENCHMARK_ARMS(BM_LoadDistribution);
COOPDYN_BENCHMARK_ARMS(BM_WrenchDecomposition);
COOPDYN_BENCHMARK_ARMS(BM_ApparentImpedance);
COOPDYN_BENCHMARK_ARMS(BM_FullTick);
COOPDYN_BENCHMARK_ARMS(BM_FullTickDynamic);

}  // namespace
