// Benchmarks of the KDL adapter's per-tick read (coopdyn/adapters/kdl.hpp, KdlArms::read): M by
// the adapter's composite-rigid-body algorithm, h by KDL's tree RNEA, J and Jdot qdot by KDL's
// chain solvers, for the shipped heterogeneous pair (examples/robots: UR5e + Franka Emika Panda),
// at a seeded random state with nonzero joint velocities.
//
//   KdlRead/pair_K2_Q13/fixed      two chains, KdlArms<2, 13>
//   KdlRead/pair_K2_Q13/dynamic    the same, KdlArms<> (Dynamic sizes)
//   KdlRead/torso_K2_Q14/fixed     one tree, both arms on a torso joint they share
//   KdlInertiaByRnea/pair_Q13      what M would cost as Q calls of KDL's tree RNEA with unit joint
//                                  accelerations (the alternative to the adapter's CRBA)
#include <coopdyn/adapters/kdl_urdf.hpp>

#include <benchmark/benchmark.h>

#include <kdl/treeidsolver_recursive_newton_euler.hpp>

#include <Eigen/Dense>

#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace {

KDL::Chain robot_chain(const std::string& robot, const std::string& base)
{
    const KDL::Tree tree =
        coopdyn::kdl_tree_from_urdf(std::string(COOPDYN_ROBOTS_DIR) + "/" + robot + "/" + robot + ".urdf");
    KDL::Chain chain;
    tree.getChain(base, robot + "_palm", chain);
    return chain;
}

std::vector<KDL::Chain> pair_chains() { return {robot_chain("ur5e", "ur5e_base"), robot_chain("panda", "panda_link0")}; }

std::vector<KDL::Frame> pair_bases()
{
    return {KDL::Frame(KDL::Vector(0.0, -0.4, 0.0)), KDL::Frame(KDL::Rotation::RotZ(M_PI), KDL::Vector(0.0, 0.4, 0.0))};
}

KDL::Tree torso_tree()
{
    KDL::Tree tree("world");
    tree.addSegment(KDL::Segment("torso", KDL::Joint(KDL::Joint::RotZ), KDL::Frame(KDL::Vector(0, 0, 0.6)),
                                 KDL::RigidBodyInertia(15.0, KDL::Vector(0.0, 0.0, -0.2))),
                    "world");
    const std::vector<KDL::Chain> chains = pair_chains();
    for (std::size_t i = 0; i < 2; ++i) {
        const std::string mount = "mount" + std::to_string(i);
        tree.addSegment(KDL::Segment(mount, KDL::Joint(KDL::Joint::None), pair_bases()[i]), "torso");
        tree.addChain(chains[i], mount);
    }
    return tree;
}

Eigen::VectorXd random_vector(std::mt19937& rng, Eigen::Index n, double scale)
{
    std::uniform_real_distribution<double> unit(-scale, scale);
    Eigen::VectorXd v(n);
    for (Eigen::Index i = 0; i < n; ++i) {
        v[i] = unit(rng);
    }
    return v;
}

template <typename Arms> void run_read(benchmark::State& state, Arms& arms)
{
    typename Arms::Input input(arms.arms(), arms.joints());
    std::mt19937 rng(20261127u);
    const Eigen::VectorXd q = random_vector(rng, arms.joints(), M_PI);
    const Eigen::VectorXd qdot = random_vector(rng, arms.joints(), 2.0);
    if (!arms.read(q, qdot, input)) {
        state.SkipWithError("KdlArms::read reported a KDL solver error");
        return;
    }
    for (auto _ : state) {
        arms.read(q, qdot, input);
        benchmark::DoNotOptimize(input.inertia.data());
        benchmark::DoNotOptimize(input.jacobian_rate_qdot.data());
        benchmark::ClobberMemory();
    }
}

void pair_fixed(benchmark::State& state)
{
    coopdyn::KdlArms<2, 13> arms(pair_chains(), pair_bases());
    run_read(state, arms);
}
void pair_dynamic(benchmark::State& state)
{
    coopdyn::KdlArms<> arms(pair_chains(), pair_bases());
    run_read(state, arms);
}
void torso_fixed(benchmark::State& state)
{
    coopdyn::KdlArms<2, 14> arms(torso_tree(), {"ur5e_palm", "panda_palm"});
    run_read(state, arms);
}

void inertia_by_rnea(benchmark::State& state)
{
    const coopdyn::KdlArms<2, 13> arms(pair_chains(), pair_bases());
    KDL::TreeIdSolver_RNE rnea(arms.tree(), KDL::Vector::Zero());
    KDL::JntArray q(13), zero(13), qdd(13), torque(13);
    std::mt19937 rng(20261127u);
    // JntArray's storage comes from liborocos-kdl (16-byte aligned on Debian): unaligned views,
    // as in the adapter, under -march=native.
    coopdyn::kdl_detail::view(q) = random_vector(rng, 13, M_PI);
    Eigen::Matrix<double, 13, 13> inertia;
    for (auto _ : state) {
        for (unsigned int i = 0; i < 13; ++i) {
            coopdyn::kdl_detail::view(qdd).setZero();
            qdd(i) = 1.0;
            rnea.CartToJnt(q, zero, qdd, KDL::WrenchMap(), torque);
            inertia.col(i) = coopdyn::kdl_detail::view(torque);
        }
        benchmark::DoNotOptimize(inertia.data());
    }
}

BENCHMARK(pair_fixed)->Name("KdlRead/pair_K2_Q13/fixed");
BENCHMARK(pair_dynamic)->Name("KdlRead/pair_K2_Q13/dynamic");
BENCHMARK(torso_fixed)->Name("KdlRead/torso_K2_Q14/fixed");
BENCHMARK(inertia_by_rnea)->Name("KdlInertiaByRnea/pair_Q13");

}  // namespace
