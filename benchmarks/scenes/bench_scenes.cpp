// Benchmarks on the shipped scenes of any arms (examples/scenes, docs/scenes.md; docs/performance.md,
// "Scenes of any arms"): the real arms' M, h, J, Jdot qdot, read from MuJoCo where the hold has the
// object (the scene's start, then 0.2 s of the palms pressing in and 0.1 s of holding, in MuJoCo),
// not random matrices.
//
//   SceneTick/<scene>/{fixed,dynamic}   one controller_tick on that input (the same input every
//                                       tick, warm-started QP), ControllerModel<double, K, Q> with
//                                       the scene's K and Q, and <double, Dynamic, Dynamic> as the
//                                       scene layer builds it; the parameters are the scene layer's
//                                       (SceneWorld::controller_parameters at the start)
//   MujocoRead/<scene>/{fixed,dynamic}  MujocoArms<K, Q>::read (and <Dynamic, Dynamic>) at that
//                                       state (MuJoCo's stages already run, as after mj_step1)
//   KdlRead/ur5e_panda/{fixed,dynamic}  KdlArms<2, 13>::read (and KdlArms<>) on the URDF files
//                                       (examples/robots), mounted where the scene mounts them, at
//                                       the same q, qdot (checked against MuJoCo's M to 1e-10)
//   ArmTerms/<scene>/{own_recursion,mujoco}  the rigid plant's evaluation of all arms' M, h, J,
//                                       Jdot qdot and contact frames at the held state: its own
//                                       recursion (scene_rigid.hpp, evaluate_chains) and MuJoCo's
//                                       five smooth stages plus MujocoArms<>::read on a scratch
//                                       mjData (checked to agree to 1e-12)
//   SceneHold/<scene>/{mujoco,rigid}    the hold loop (scene_hold.hpp, run_hold_on) of 500 ticks
//                                       from the scene's start (0.2 s settling + 0.3 s held) on the
//                                       MuJoCo plant and on the rigid plant (scene_rigid.hpp);
//                                       counters: us_per_tick (CPU time per 1 ms tick, the
//                                       controller model's construction included once per 500
//                                       ticks), RTF = 1 ms / us_per_tick, controller_us (the
//                                       controller ticks' mean wall time, from run_hold_on)
//
// <scene>: lwr4_pair (K = 2, Q = 14), ur5e_panda (K = 2, Q = 13), three_arms (K = 3, Q = 20). A
// benchmark whose tick is not ok, or whose hold drops the object or has a tick not ok, is skipped
// with an error.
#include "scene_hold.hpp"
#include "scene_rigid.hpp"

#ifdef COOPDYN_SCENES_HAVE_KDL
#include <coopdyn/adapters/kdl_urdf.hpp>
#endif

#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using coopdyn::Dynamic;

/// A scene started and held: its world (left at the start state by every benchmark), the
/// controller's parameters at the start, the start state and the held state (after mj_step1),
/// and the controller's input read at the held state.
struct HeldScene {
    std::unique_ptr<scenes::SceneWorld> world;
    coopdyn::ControllerParameters<double> parameters;
    scenes::DataPointer start;
    scenes::DataPointer held;
    std::optional<coopdyn::ControllerInput<double>> input;
    std::string error;  ///< set up problem (the benchmarks skip with it)
};

HeldScene make_held_scene(const std::string& name)
{
    HeldScene s;
    s.world = std::make_unique<scenes::SceneWorld>(scenes::read_scene(std::string(COOPDYN_SCENES_DIR) + "/" + name + ".json"));
    scenes::SceneWorld& world = *s.world;
    mjModel* model = world.model();
    world.start();
    s.start.reset(mj_makeData(model));
    mj_copyData(s.start.get(), model, world.data());
    const scenes::HoldSettings defaults;
    s.parameters = world.controller_parameters(defaults.controller);
    const coopdyn::Pose<double> desired = coopdyn::mujoco_object_pose(model, world.data(), world.object_body());

    scenes::HoldSettings settings;
    settings.settle_seconds = 0.2;
    settings.seconds = 0.1;
    const scenes::HoldResult hold = scenes::run_hold(world, settings);
    if (hold.dropped || hold.not_ok_ticks > 0) {
        s.error = name + ": the hold before the measurement dropped the object or had a tick not ok";
    }
    scenes::MujocoScenePlant plant(world);
    s.input.emplace(world.arms().arms(), world.arms().joints());
    plant.begin_tick(*s.input);  // mj_step1 and the adapter's read, as the hold loop does
    s.input->posture = world.posture();
    s.input->desired_pose = desired;
    s.input->object_acceleration.setZero();
    s.held.reset(mj_makeData(model));
    mj_copyData(s.held.get(), model, world.data());
    mj_copyData(world.data(), model, s.start.get());
    return s;
}

HeldScene& held_scene(const std::string& name)
{
    static std::map<std::string, HeldScene> cache;
    auto found = cache.find(name);
    if (found == cache.end()) {
        found = cache.emplace(name, make_held_scene(name)).first;
    }
    return found->second;
}

bool check_sizes(benchmark::State& state, const HeldScene& s, int arms, int joints)
{
    if (!s.error.empty()) {
        state.SkipWithError(s.error.c_str());
        return false;
    }
    if ((arms != Dynamic && s.world->arms().arms() != arms) || (joints != Dynamic && s.world->arms().joints() != joints)) {
        state.SkipWithError("the scene's K or Q is not the benchmark's");
        return false;
    }
    return true;
}

// ---- the controller tick -----------------------------------------------------------------------

template <int K, int Q> void BM_SceneTick(benchmark::State& state, const char* name)
{
    const HeldScene& s = held_scene(name);
    if (!check_sizes(state, s, K, Q)) {
        return;
    }
    const coopdyn::ControllerModel<double, K, Q> model(s.parameters);
    coopdyn::ControllerData<double, K, Q> data(model);
    const coopdyn::ControllerInput<double, K, Q> input(*s.input);
    coopdyn::controller_tick(model, data, input);  // the warm start's first active set
    if (data.status != coopdyn::ControlStatus::ok || data.fallback_used) {
        state.SkipWithError((std::string("the tick is not ok: ") + coopdyn::to_string(data.status)).c_str());
        return;
    }
    for (auto _ : state) {
        const auto& tau = coopdyn::controller_tick(model, data, input);
        benchmark::DoNotOptimize(tau.data());
        benchmark::ClobberMemory();
    }
    if (data.status != coopdyn::ControlStatus::ok) {
        state.SkipWithError(coopdyn::to_string(data.status));
        return;
    }
    state.counters["qp_iterations"] = data.qp_iterations;
}


// ---- the adapters' read ------------------------------------------------------------------------

template <int K, int Q> void BM_MujocoRead(benchmark::State& state, const char* name)
{
    const HeldScene& s = held_scene(name);
    if (!check_sizes(state, s, K, Q)) {
        return;
    }
    const scenes::SceneWorld& world = *s.world;
    const coopdyn::MujocoArms<K, Q> arms(world.model(), world.scene().joint_names, world.scene().contact_sites);
    coopdyn::ControllerInput<double, K, Q> input(world.arms().arms(), world.arms().joints());
    arms.read(world.model(), s.held.get(), input);
    if ((input.inertia - s.input->inertia).cwiseAbs().maxCoeff() != 0.0) {
        state.SkipWithError("the read differs from the scene layer's");
        return;
    }
    for (auto _ : state) {
        arms.read(world.model(), s.held.get(), input);
        benchmark::DoNotOptimize(input.jacobian_rate_qdot.data());
        benchmark::ClobberMemory();
    }
}


#ifdef COOPDYN_SCENES_HAVE_KDL
/// The UR5e + Panda pair from the URDF files, each robot's tree on the scene's mount body.
template <int K, int Q> void BM_KdlRead(benchmark::State& state)
{
    const HeldScene& s = held_scene("ur5e_panda");
    if (!check_sizes(state, s, 2, 13)) {
        return;
    }
    const mjModel* model = s.world->model();
    std::vector<KDL::Chain> chains;
    std::vector<KDL::Frame> bases;
    const char* robots[2][3] = {{"ur5e", "ur5e_base", "ur5e_mount"}, {"panda", "panda_link0", "panda_mount"}};
    for (const auto& robot : robots) {
        const std::string urdf = std::string(COOPDYN_ROBOTS_DIR) + "/" + robot[0] + "/" + robot[0] + ".urdf";
        const KDL::Tree tree = coopdyn::kdl_tree_from_urdf(urdf);
        KDL::Chain chain;
        if (!tree.getChain(robot[1], std::string(robot[0]) + "_palm", chain)) {
            state.SkipWithError("no chain to the palm in the URDF");
            return;
        }
        chains.push_back(chain);
        const int mount = mj_name2id(model, mjOBJ_BODY, robot[2]);
        const mjtNum* p = model->body_pos + 3 * mount;
        const mjtNum* w = model->body_quat + 4 * mount;
        bases.emplace_back(KDL::Rotation::Quaternion(w[1], w[2], w[3], w[0]), KDL::Vector(p[0], p[1], p[2]));
    }
    coopdyn::KdlArms<K, Q> arms(chains, bases);
    typename coopdyn::KdlArms<K, Q>::Input input(arms.arms(), arms.joints());
    const Eigen::VectorXd q = s.input->positions;
    const Eigen::VectorXd qdot = s.input->velocities;
    if (!arms.read(q, qdot, input) || (input.inertia - s.input->inertia).cwiseAbs().maxCoeff() > 1e-10) {
        state.SkipWithError("KDL's read failed or its M differs from MuJoCo's");
        return;
    }
    for (auto _ : state) {
        arms.read(q, qdot, input);
        benchmark::DoNotOptimize(input.inertia.data());
        benchmark::DoNotOptimize(input.jacobian_rate_qdot.data());
        benchmark::ClobberMemory();
    }
}
#endif

// ---- the rigid plant's evaluation of the arms' terms --------------------------------------------

template <bool Own> void BM_ArmTerms(benchmark::State& state, const char* name)
{
    const HeldScene& s = held_scene(name);
    if (!check_sizes(state, s, Dynamic, Dynamic)) {
        return;
    }
    const scenes::SceneWorld& world = *s.world;
    const mjModel* model = world.model();
    const scenes::Arms& arms = world.arms();
    coopdyn::ControllerInput<double> input(arms.arms(), arms.joints());
    const Eigen::VectorXd q = s.input->positions;
    const Eigen::VectorXd qdot = s.input->velocities;
    std::string why;
    const std::vector<scenes::ChainDynamics> chains = scenes::arm_chains(world, why);
    std::vector<coopdyn::Pose<double>> contacts(chains.size());
    scenes::DataPointer scratch(mj_makeData(model));
    mj_copyData(scratch.get(), model, s.held.get());
    const auto evaluate = [&] {
        if constexpr (Own) {
            scenes::evaluate_chains(chains, q, qdot, input, contacts);
        } else {
            scenes::run_arm_stages(model, scratch.get(), arms, q, qdot);
            arms.read(model, scratch.get(), input);
        }
    };
    evaluate();
    if (chains.empty() || (input.inertia - s.input->inertia).norm() > 1e-12 * s.input->inertia.norm() ||
        (input.bias - s.input->bias).norm() > 1e-12 * s.input->bias.norm()) {
        state.SkipWithError(("no own recursion, or its terms differ from MuJoCo's: " + why).c_str());
        return;
    }
    for (auto _ : state) {
        evaluate();
        benchmark::DoNotOptimize(input.inertia.data());
        benchmark::DoNotOptimize(input.jacobian_rate_qdot.data());
        benchmark::ClobberMemory();
    }
}

// ---- the whole 1 ms step: the hold loop on both plants ---------------------------------------------

template <bool Rigid> void BM_SceneHold(benchmark::State& state, const char* name)
{
    HeldScene& s = held_scene(name);
    if (!check_sizes(state, s, Dynamic, Dynamic)) {
        return;
    }
    scenes::SceneWorld& world = *s.world;
    scenes::HoldSettings settings;
    settings.settle_seconds = 0.2;
    settings.seconds = 0.3;
    const double ticks = 500.0;
    double controller_seconds = 0.0;
    double runs = 0.0;
    for (auto _ : state) {
        state.PauseTiming();
        mj_copyData(world.data(), world.model(), s.start.get());
        std::optional<scenes::MujocoScenePlant> mujoco;
        std::optional<scenes::RigidScenePlant> rigid;
        if constexpr (Rigid) {
            rigid.emplace(world);
        } else {
            mujoco.emplace(world);
        }
        state.ResumeTiming();
        const scenes::HoldResult hold = Rigid ? scenes::run_hold_on(world, *rigid, settings)
                                              : scenes::run_hold_on(world, *mujoco, settings);
        state.PauseTiming();
        if (hold.dropped || hold.not_ok_ticks > 0 || hold.ticks + 200 != static_cast<long>(ticks)) {
            state.SkipWithError("the hold dropped the object, had a tick not ok or ran other ticks");
            state.ResumeTiming();
            break;
        }
        controller_seconds += 1e-6 * hold.tick_microseconds;
        runs += 1.0;
        state.ResumeTiming();
    }
    mj_copyData(world.data(), world.model(), s.start.get());
    state.counters["us_per_tick"] = benchmark::Counter(ticks, benchmark::Counter::kIsIterationInvariantRate |
                                                                 benchmark::Counter::kInvert);  // s (printed "u": us)
    // Simulated seconds per CPU second (printed with "/s").
    state.counters["RTF"] = benchmark::Counter(ticks * 1e-3, benchmark::Counter::kIsIterationInvariantRate);
    state.counters["controller_us"] = runs > 0.0 ? 1e6 * controller_seconds / runs : 0.0;
}


int register_benchmarks()
{
    benchmark::RegisterBenchmark("SceneTick/lwr4_pair_K2_Q14/fixed", BM_SceneTick<2, 14>, "lwr4_pair");
    benchmark::RegisterBenchmark("SceneTick/lwr4_pair_K2_Q14/dynamic", BM_SceneTick<Dynamic, Dynamic>, "lwr4_pair");
    benchmark::RegisterBenchmark("SceneTick/ur5e_panda_K2_Q13/fixed", BM_SceneTick<2, 13>, "ur5e_panda");
    benchmark::RegisterBenchmark("SceneTick/ur5e_panda_K2_Q13/dynamic", BM_SceneTick<Dynamic, Dynamic>, "ur5e_panda");
    benchmark::RegisterBenchmark("SceneTick/three_arms_K3_Q20/fixed", BM_SceneTick<3, 20>, "three_arms");
    benchmark::RegisterBenchmark("SceneTick/three_arms_K3_Q20/dynamic", BM_SceneTick<Dynamic, Dynamic>, "three_arms");
    benchmark::RegisterBenchmark("MujocoRead/lwr4_pair_K2_Q14/fixed", BM_MujocoRead<2, 14>, "lwr4_pair");
    benchmark::RegisterBenchmark("MujocoRead/lwr4_pair_K2_Q14/dynamic", BM_MujocoRead<Dynamic, Dynamic>, "lwr4_pair");
    benchmark::RegisterBenchmark("MujocoRead/ur5e_panda_K2_Q13/fixed", BM_MujocoRead<2, 13>, "ur5e_panda");
    benchmark::RegisterBenchmark("MujocoRead/ur5e_panda_K2_Q13/dynamic", BM_MujocoRead<Dynamic, Dynamic>, "ur5e_panda");
    benchmark::RegisterBenchmark("MujocoRead/three_arms_K3_Q20/fixed", BM_MujocoRead<3, 20>, "three_arms");
    benchmark::RegisterBenchmark("MujocoRead/three_arms_K3_Q20/dynamic", BM_MujocoRead<Dynamic, Dynamic>, "three_arms");
#ifdef COOPDYN_SCENES_HAVE_KDL
    benchmark::RegisterBenchmark("KdlRead/ur5e_panda_K2_Q13/fixed", BM_KdlRead<2, 13>);
    benchmark::RegisterBenchmark("KdlRead/ur5e_panda_K2_Q13/dynamic", BM_KdlRead<Dynamic, Dynamic>);
#endif
    for (const char* scene : {"lwr4_pair", "ur5e_panda", "three_arms"}) {
        const std::string terms = std::string("ArmTerms/") + scene;
        benchmark::RegisterBenchmark((terms + "/own_recursion").c_str(), BM_ArmTerms<true>, scene);
        benchmark::RegisterBenchmark((terms + "/mujoco").c_str(), BM_ArmTerms<false>, scene);
    }
    for (const char* scene : {"lwr4_pair", "ur5e_panda", "three_arms"}) {
        const std::string name = std::string("SceneHold/") + scene;
        benchmark::RegisterBenchmark((name + "/mujoco").c_str(), BM_SceneHold<false>, scene)->Unit(benchmark::kMillisecond);
        benchmark::RegisterBenchmark((name + "/rigid").c_str(), BM_SceneHold<true>, scene)->Unit(benchmark::kMillisecond);
    }
    return 0;
}
[[maybe_unused]] const int registered = register_benchmarks();

}  // namespace
