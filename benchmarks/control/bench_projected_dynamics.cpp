// Benchmarks of the projected dynamics (coopdyn/control/projected_dynamics.hpp): one
// ProjectedDynamics::compute (Jx, Jc, B, P, Mc, Lambda_c, hc and the exact rate terms) and the
// contact-wrench bias w_0 (E11) per tick, for
//
//   K = 2 arms of 7 joints (Q = 14), K = 2 with a shared torso joint (Q = 15), K = 3 (Q = 21),
//
// fixed and dynamic sizes, on the seeded random systems of tests/common/arm_systems.hpp.

#include <coopdyn/control/contact_wrenches.hpp>
#include <coopdyn/control/projected_dynamics.hpp>

#include "arm_systems.hpp"

#include <benchmark/benchmark.h>

namespace {

using coopdyn::Dynamic;

template <int Arms, int Joints, bool Torso, bool FixedSizes> struct Fixture {
    static constexpr int K = FixedSizes ? Arms : Dynamic;
    static constexpr int Q = FixedSizes ? Joints : Dynamic;
    Eigen::Matrix<double, Q, Q> M;
    Eigen::Matrix<double, Q, 1> h, qdot, tau_u, qdd, scratch;
    Eigen::Matrix<double, coopdyn::times_six(K), Q> J;
    Eigen::Matrix<double, coopdyn::times_six(K), 1> Jdot_qdot, bias;
    Eigen::Matrix<double, 3, K> r;
    Eigen::Matrix<double, 6, 1> external;
    coopdyn::ProjectedDynamics<double, K, Q> dynamics;

    Fixture() : dynamics(Arms, Joints)
    {
        coopdyn_test::Rng rng(2024);
        const coopdyn_test::JointSpaceSystem s = coopdyn_test::random_joint_space_system(Arms, Torso, rng);
        M = s.M;
        h = s.h;
        qdot = s.qdot;
        J = s.J;
        Jdot_qdot = s.Jdot * s.qdot;
        r = s.r;
        external = 10.0 * coopdyn_test::random_vector(6, rng);
        tau_u = Eigen::VectorXd::Zero(Joints);
        qdd = tau_u;
        scratch = tau_u;
        bias = Eigen::VectorXd::Zero(6 * Arms);
    }
};

template <int Arms, int Joints, bool Torso, bool FixedSizes> void BM_ProjectedDynamics(benchmark::State& state)
{
    Fixture<Arms, Joints, Torso, FixedSizes> f;
    for (auto _ : state) {
        f.dynamics.compute(f.M, f.h, f.J, f.Jdot_qdot, f.qdot, f.r);
        benchmark::DoNotOptimize(f.dynamics.task_bias.data());
    }
    if (f.dynamics.status != coopdyn::ProjectionStatus::ok) {
        state.SkipWithError("singular sample system");
    }
}

template <int Arms, int Joints, bool Torso, bool FixedSizes> void BM_ContactWrenchBias(benchmark::State& state)
{
    Fixture<Arms, Joints, Torso, FixedSizes> f;
    f.dynamics.compute(f.M, f.h, f.J, f.Jdot_qdot, f.qdot, f.r);
    f.tau_u.noalias() = f.dynamics.projector * (f.dynamics.object_jacobian.transpose() * f.external);
    for (auto _ : state) {
        coopdyn::contact_wrench_bias(f.dynamics, f.M, f.h, f.tau_u, f.external, f.qdd, f.bias, f.scratch);
        benchmark::DoNotOptimize(f.bias.data());
    }
}

BENCHMARK_TEMPLATE(BM_ProjectedDynamics, 2, 14, false, true)->Name("ProjectedDynamics/K2_Q14/fixed");
BENCHMARK_TEMPLATE(BM_ProjectedDynamics, 2, 14, false, false)->Name("ProjectedDynamics/K2_Q14/dynamic");
BENCHMARK_TEMPLATE(BM_ProjectedDynamics, 2, 15, true, true)->Name("ProjectedDynamics/K2_Q15_torso/fixed");
BENCHMARK_TEMPLATE(BM_ProjectedDynamics, 2, 15, true, false)->Name("ProjectedDynamics/K2_Q15_torso/dynamic");
BENCHMARK_TEMPLATE(BM_ProjectedDynamics, 3, 21, false, true)->Name("ProjectedDynamics/K3_Q21/fixed");
BENCHMARK_TEMPLATE(BM_ProjectedDynamics, 3, 21, false, false)->Name("ProjectedDynamics/K3_Q21/dynamic");
BENCHMARK_TEMPLATE(BM_ContactWrenchBias, 2, 14, false, true)->Name("ContactWrenchBias/K2_Q14/fixed");
BENCHMARK_TEMPLATE(BM_ContactWrenchBias, 2, 14, false, false)->Name("ContactWrenchBias/K2_Q14/dynamic");

}  // namespace
