// The dual-arm box example's loop (examples/box, docs/dual-arm-box.md): the controller tick as the
// experiment calls it (inputs read from MuJoCo at the hold), one MuJoCo plant tick (mj_step1,
// reading M, h, J, Jdot qdot, mj_step2, the contact wrenches), one rigid-plant RK4 step (four
// evaluations of the arms' own dynamics, four structured weld solves) and its parts against their
// alternatives (the arms' terms from MuJoCo; the constraint-space and generic weld solves), and
// each shipped experiment on each plant (counters: real-time factor).
#include "box_experiment.hpp"
#include "box_scenario_loader.hpp"
#include "mujoco_plant.hpp"
#include "mujoco_rigid_plant.hpp"

#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace {

using namespace box_example;

const DualArmBoxModel& world()
{
    static const DualArmBoxModel model(COOPDYN_BOX_MJCF);
    return model;
}

BoxScenario hold_scenario()
{
    return load_box_scenario(std::string(COOPDYN_BOX_SCENARIOS) + "/hold.json");
}

void BM_ControllerTickInTheLoop(benchmark::State& state)
{
    const Grasp grasp = hold_grasp(world());
    const Controller controller(controller_parameters(hold_scenario().controller, grasp));
    ControllerData data(controller);
    ControllerInput input(controller);
    MujocoPlant plant(world(), PlantFriction{});
    plant.begin_tick();
    const ArmTerms& terms = plant.arm_terms();
    input.inertia = terms.inertia;
    input.bias = terms.bias;
    input.jacobian = terms.jacobian;
    input.jacobian_rate_qdot = terms.jacobian_rate_qdot;
    input.positions = plant.joint_positions();
    input.posture = grasp.q;
    input.object.pose.position = plant.box_position() - Eigen::Vector3d(0, 0, 0.05);  // sagging: F_x = weight
    input.object.pose.orientation = plant.box_orientation();
    input.desired_pose = grasp.box;
    for (auto _ : state) {
        benchmark::DoNotOptimize(coopdyn::controller_tick(controller, data, input).data());
    }
}
BENCHMARK(BM_ControllerTickInTheLoop);

/// MuJoCo's own step of the box model (what the MuJoCo plant adds to the controller besides
/// reading M, h, J, Jdot qdot and the contacts): the arms gravity-compensated, squeezing nothing;
/// restarted at the keyframe every 200 steps (the box falls between the palms).
void BM_MujocoStep(benchmark::State& state)
{
    const mjModel* model = world().get();
    const DataPointer data = world().make_data_at_hold();
    long steps = 0;
    for (auto _ : state) {
        for (int j = 0; j < joints; ++j) {
            data->qfrc_applied[j] = data->qfrc_bias[j];
        }
        mj_step(model, data.get());
        if (++steps % 200 == 0) {
            mj_resetDataKeyframe(model, data.get(), world().hold_key());
            mj_forward(model, data.get());
        }
    }
}
BENCHMARK(BM_MujocoStep)->Unit(benchmark::kMicrosecond);

/// One RK4 step of the rigid plant (four evaluations of the arms' own dynamics, four structured
/// weld solves); restarted every 200 steps.
void BM_RigidPlantStep(benchmark::State& state)
{
    const DataPointer start = world().make_data_at_hold();
    auto plant = std::make_unique<RigidGraspPlant>(make_rigid_plant(world(), *start, box_inertia(world(), 0.7)));
    const JointVector tau = plant->arm_terms().bias;
    long steps = 0;
    for (auto _ : state) {
        plant->end_tick(tau, Vector6d::Zero());
        if (++steps % 200 == 0) {
            state.PauseTiming();
            plant = std::make_unique<RigidGraspPlant>(make_rigid_plant(world(), *start, box_inertia(world(), 0.7)));
            state.ResumeTiming();
        }
    }
}
BENCHMARK(BM_RigidPlantStep)->Unit(benchmark::kMicrosecond);

/// The arms' M, h, J, Jdot qdot and palm frames at a moving state: by the rigid plant's own
/// recursion (lwr4_dynamics.hpp, both arms) and from MuJoCo (compute_arm_stages + read_arm_terms).
JointVector moving_velocities()
{
    JointVector qdot;
    for (int j = 0; j < joints; ++j) {
        qdot(j) = 0.3 * std::sin(1.0 + j);
    }
    return qdot;
}

void BM_ArmTermsOwnRecursion(benchmark::State& state)
{
    const std::array<Lwr4Dynamics, palms> arms{Lwr4Dynamics(Side::left), Lwr4Dynamics(Side::right)};
    const JointVector q = q_hold(), qdot = moving_velocities();
    Lwr4ArmTerms terms;
    for (auto _ : state) {
        for (std::size_t i = 0; i < palms; ++i) {
            const Eigen::Index joint = arm_joints * static_cast<Eigen::Index>(i);
            arms[i].evaluate(q.segment<arm_joints>(joint), qdot.segment<arm_joints>(joint), terms);
            benchmark::DoNotOptimize(terms.inertia.data());
        }
    }
}
BENCHMARK(BM_ArmTermsOwnRecursion);

void BM_ArmTermsMujoco(benchmark::State& state)
{
    const mjModel* model = world().get();
    const DataPointer data = world().make_data_at_hold();
    const JointVector qdot = moving_velocities();
    for (int j = 0; j < joints; ++j) {
        data->qvel[j] = qdot(j);
    }
    ArmTerms terms;
    for (auto _ : state) {
        compute_arm_stages(model, data.get());
        read_arm_terms(world(), model, data.get(), terms);
        benchmark::DoNotOptimize(terms.inertia.data());
    }
}
BENCHMARK(BM_ArmTermsMujoco);

/// One weld solve of the rigid plant (accelerations and the palms' wrenches) at the hold, by each
/// RigidGraspPlant::WeldSolver.
void BM_WeldSolve(benchmark::State& state)
{
    const DataPointer start = world().make_data_at_hold();
    const RigidGraspPlant plant = make_rigid_plant(world(), *start, box_inertia(world(), 0.7));
    const auto solver = static_cast<RigidGraspPlant::WeldSolver>(state.range(0));
    const JointVector tau = plant.arm_terms().bias;
    RigidGraspSolution solution;
    for (auto _ : state) {
        plant.solve(plant.state(), plant.arm_terms(), tau, Vector6d::Zero(), solution, true, solver);
        benchmark::DoNotOptimize(solution.joint_acceleration.data());
    }
}
BENCHMARK(BM_WeldSolve)
    ->ArgName("solver")
    ->Arg(static_cast<int>(RigidGraspPlant::WeldSolver::structured))
    ->Arg(static_cast<int>(RigidGraspPlant::WeldSolver::constraint_space))
    ->Arg(static_cast<int>(RigidGraspPlant::WeldSolver::generic));

/// A whole shipped experiment (examples/box/scenarios/NAME.json, its full duration and the 0.2 s
/// settling) per iteration; counters: simulated seconds per wall second, and microseconds per
/// 1 ms tick. The experiment's own clock (ExperimentRun::wall_seconds) times the loop only, not
/// the scenario file, the plant's construction or the CSV.
template <typename MakePlant>
void run_experiment_benchmark(benchmark::State& state, const std::string& name, MakePlant&& make_plant)
{
    const Grasp grasp = hold_grasp(world());
    const BoxScenario scenario = load_box_scenario(std::string(COOPDYN_BOX_SCENARIOS) + "/" + name + ".json");
    double simulated = 0.0, wall = 0.0;
    for (auto _ : state) {
        auto plant = make_plant(scenario);
        const ExperimentRun run = run_experiment(*plant, scenario, grasp);
        simulated += scenario.duration + settle_seconds;
        wall += run.wall_seconds;
        benchmark::DoNotOptimize(run.log.data());
    }
    state.counters["real_time_factor"] = simulated / wall;
    state.counters["us_per_tick"] = 1e6 * wall / (simulated / 0.001);
}

void BM_ExperimentMujoco(benchmark::State& state, const std::string& name)
{
    run_experiment_benchmark(state, name, [](const BoxScenario& scenario) {
        auto plant = std::make_unique<MujocoPlant>(world(), scenario.plant_friction);
        plant->set_box_mass(scenario.box_mass);
        return plant;
    });
}

void BM_ExperimentRigid(benchmark::State& state, const std::string& name)
{
    run_experiment_benchmark(state, name, [](const BoxScenario& scenario) {
        const DataPointer start = world().make_data_at_hold();
        return std::make_unique<RigidGraspPlant>(make_rigid_plant(world(), *start, box_inertia(world(), scenario.box_mass)));
    });
}

BENCHMARK_CAPTURE(BM_ExperimentMujoco, hold, std::string("hold"))->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_ExperimentMujoco, push, std::string("push"))->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_ExperimentMujoco, add_mass, std::string("add_mass"))->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_ExperimentMujoco, circle, std::string("circle"))->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_ExperimentRigid, hold, std::string("hold"))->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_ExperimentRigid, push, std::string("push"))->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_ExperimentRigid, add_mass, std::string("add_mass"))->Unit(benchmark::kSecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_ExperimentRigid, circle, std::string("circle"))->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
