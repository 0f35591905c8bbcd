// Simulated time per wall-clock time of the paper's two-arm beam (docs/analysis.md; the main
// job examples/beam/two_arm_beam): N = 2 fixed, RK4, 1 kHz, logging off. Target: >= 2000x real time,
// i.e. 20 s of simulation in <= 10 ms.
//
//   BM_Beam20s/constant       20 000 RK4 steps, constant inputs (held beam, constant push)
//   BM_Beam20s/multisine      20 000 RK4 steps, the example's inputs: a 6-axis multisine on the
//                             object (11 sines per axis at each RK4 stage) and the desired
//                             wrenches redistributed by (26) at every tick
//   BM_Step                   one RK4 step (four evaluations of the dynamics and the update)
//   BM_InteractionWrench      one interaction_dynamics: grasp kinematics, impedance law, hSigma,
//                             structured interaction solve (docs/dynamics.md)
//   BM_InternalExternal       one decompose_wrenches: internal/external split (53)-(54) (analysis)
//   BM_LoadDistribution       one grasp_kinematics + LoadDistribution::distribute (26)
//
// Per-step split reported in docs/two-arm-beam.md: interaction wrench = 4 x BM_InteractionWrench,
// integration = BM_Step - 4 x BM_InteractionWrench, analysis = BM_InternalExternal (what the
// example adds per logged step, with BM_LoadDistribution for its controller).
#include <coopdyn/coopdyn.hpp>

#include "sample_systems.hpp"

#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <random>

namespace {

using Model = coopdyn::ImpedanceModel2;
using Simulator = coopdyn::Simulator<Model>;
using State = coopdyn::RigidBodyState<double>;
using Setpoints = coopdyn::Setpoints<double, 2>;
using Disturbances = coopdyn::Disturbances<double, 2>;

constexpr double time_step = 1e-3;
constexpr coopdyn::Index steps_20s = 20000;
constexpr double pi = 3.14159265358979323846;

const Model& model()
{
    // The paper's beam (sample_systems.hpp): m_o = 1.75 kg, J_o_body = diag(0.055, 0, 0.055), arms
    // at y = -+0.4 m with m_i = 10, J_i = 0.5 I3, d_i = 180, delta_i = 10, k_i = 300, kappa_i = 50.
    static const Model instance = coopdyn_test::section_five_beam_model<Model>();
    return instance;
}

State equilibrium()
{
    State state;
    state.pose.position = Eigen::Vector3d(0.0, 0.0, 1.0);
    return state;
}

/// Setpoints at the grasp poses of the equilibrium, weight carried by the desired wrenches.
Setpoints held_setpoints()
{
    coopdyn::Data<Model> data(model());
    coopdyn::grasp_kinematics(model(), data, equilibrium());
    Setpoints setpoints(2);
    for (coopdyn::Index i = 0; i < 2; ++i) {
        setpoints.set_pose(i, data.end_effector_pose(i));
    }
    coopdyn::LoadDistribution<Model>(model()).distribute(
        data, model().object().gravity_wrench(model().gravity()), setpoints);
    return setpoints;
}

/// Six independent multisines, 11 lines each between 0.1 and 5 Hz, random phases (seeded).
struct Multisine {
    std::array<std::array<double, 11>, 6> omega{}, phase{};
    std::array<double, 6> amplitude{};
    Multisine()
    {
        std::mt19937_64 random(42);
        std::uniform_real_distribution<double> unit(0.0, 1.0);
        for (std::size_t axis = 0; axis < 6; ++axis) {
            amplitude[axis] = (axis < 3 ? 5.0 : 2.0) * std::sqrt(2.0 / 11.0);
            for (std::size_t k = 0; k < 11; ++k) {
                omega[axis][k] = 2.0 * pi * 0.1 * std::pow(50.0, static_cast<double>(k) / 10.0);
                phase[axis][k] = 2.0 * pi * unit(random);
            }
        }
    }
    coopdyn::Vector6<double> operator()(double t) const noexcept
    {
        coopdyn::Vector6<double> wrench;
        for (std::size_t axis = 0; axis < 6; ++axis) {
            double value = 0.0;
            for (std::size_t k = 0; k < 11; ++k) {
                value += std::sin(omega[axis][k] * t + phase[axis][k]);
            }
            wrench(static_cast<Eigen::Index>(axis)) = amplitude[axis] * value;
        }
        return wrench;
    }
};

/// A state away from the equilibrium, with every velocity non-zero (no shortcut in the solve).
State perturbed()
{
    State state = equilibrium();
    state.pose.position += Eigen::Vector3d(3e-3, -2e-3, 4e-3);
    state.pose.orientation = coopdyn::quaternion_exp(Eigen::Vector3d(4e-3, -6e-3, 5e-3));
    state.twist << 0.02, -0.01, 0.015, 0.03, -0.02, 0.025;
    return state;
}

void set_counters(benchmark::State& state, double simulated_seconds_per_iteration)
{
    state.counters["x_real_time"] = benchmark::Counter(simulated_seconds_per_iteration * static_cast<double>(state.iterations()),
                                                       benchmark::Counter::kIsRate);
    state.counters["ns_per_step"] = benchmark::Counter(
        static_cast<double>(steps_20s) * static_cast<double>(state.iterations()),
        benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_Beam20s_constant(benchmark::State& state)
{
    const Setpoints setpoints = held_setpoints();
    Simulator simulator(model(), time_step, equilibrium(), coopdyn::Integrator::runge_kutta_4);
    simulator.setpoints() = setpoints;
    simulator.disturbances().object << 10.0, 0.0, 0.0, 0.0, 0.0, 1.0;  // a push and a twist
    for (auto _ : state) {
        simulator.reset(equilibrium());
        for (coopdyn::Index k = 0; k < steps_20s; ++k) {
            simulator.step();
        }
        benchmark::DoNotOptimize(simulator.state().pose.position.data());
        benchmark::ClobberMemory();
    }
    set_counters(state, static_cast<double>(steps_20s) * time_step);
}
BENCHMARK(BM_Beam20s_constant)->Name("BM_Beam20s/constant")->Unit(benchmark::kMillisecond);

void BM_Beam20s_multisine(benchmark::State& state)
{
    const Multisine excitation;
    Simulator simulator(model(), time_step, equilibrium(), coopdyn::Integrator::runge_kutta_4);
    simulator.setpoints() = held_setpoints();
    const coopdyn::LoadDistribution<Model> distribution(model());
    coopdyn::Data<Model> controller(model());
    const coopdyn::Vector6<double> gravity_wrench = model().object().gravity_wrench(model().gravity());
    const auto inputs = [&](double t, Setpoints& setpoints, Disturbances& disturbances) {
        if (t == simulator.time()) {
            coopdyn::grasp_kinematics(model(), controller, simulator.state());
            distribution.distribute(controller, gravity_wrench, setpoints);
        }
        disturbances.object = excitation(t);
    };
    for (auto _ : state) {
        simulator.reset(equilibrium());
        for (coopdyn::Index k = 0; k < steps_20s; ++k) {
            simulator.step(inputs);
        }
        benchmark::DoNotOptimize(simulator.state().pose.position.data());
        benchmark::ClobberMemory();
    }
    set_counters(state, static_cast<double>(steps_20s) * time_step);
}
BENCHMARK(BM_Beam20s_multisine)->Name("BM_Beam20s/multisine")->Unit(benchmark::kMillisecond);

void BM_Step(benchmark::State& state)
{
    Simulator simulator(model(), time_step, perturbed(), coopdyn::Integrator::runge_kutta_4);
    simulator.setpoints() = held_setpoints();
    simulator.disturbances().object << 10.0, 0.0, 0.0, 0.0, 0.0, 1.0;
    const State start = perturbed();
    coopdyn::Index taken = 0;
    for (auto _ : state) {
        simulator.step();
        benchmark::DoNotOptimize(simulator.state().twist.data());
        if (++taken == 1000) {  // stay near the perturbed state
            simulator.reset(start);
            taken = 0;
        }
    }
}
BENCHMARK(BM_Step);

void BM_InteractionWrench(benchmark::State& state)
{
    coopdyn::Data<Model> data(model());
    const Setpoints setpoints = held_setpoints();
    Disturbances disturbances(2);
    disturbances.object << 10.0, 0.0, 0.0, 0.0, 0.0, 1.0;
    State current = perturbed();
    for (auto _ : state) {
        benchmark::DoNotOptimize(current.twist.data());
        coopdyn::interaction_dynamics(model(), data, current, setpoints, disturbances);
        benchmark::DoNotOptimize(data.wrenches.data());
    }
}
BENCHMARK(BM_InteractionWrench);

void BM_InternalExternal(benchmark::State& state)
{
    coopdyn::Data<Model> data(model());
    const Setpoints setpoints = held_setpoints();
    Disturbances disturbances(2);
    coopdyn::interaction_dynamics(model(), data, perturbed(), setpoints, disturbances);
    coopdyn::WrenchDecomposition<Model> decomposition(model());
    for (auto _ : state) {
        benchmark::DoNotOptimize(data.motion_wrenches.data());
        coopdyn::decompose_wrenches(model(), data, decomposition);
        benchmark::DoNotOptimize(decomposition.internal.data());
        benchmark::DoNotOptimize(decomposition.external.data());
    }
}
BENCHMARK(BM_InternalExternal);

void BM_LoadDistribution(benchmark::State& state)
{
    coopdyn::Data<Model> data(model());
    Setpoints setpoints = held_setpoints();
    const coopdyn::LoadDistribution<Model> distribution(model());
    const coopdyn::Vector6<double> gravity_wrench = model().object().gravity_wrench(model().gravity());
    State current = perturbed();
    for (auto _ : state) {
        benchmark::DoNotOptimize(current.pose.position.data());
        coopdyn::grasp_kinematics(model(), data, current);
        distribution.distribute(data, gravity_wrench, setpoints);
        benchmark::DoNotOptimize(setpoints.wrenches.data());
    }
}
BENCHMARK(BM_LoadDistribution);

}  // namespace
