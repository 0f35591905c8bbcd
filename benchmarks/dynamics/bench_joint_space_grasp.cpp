// Benchmark of the joint-space rigid grasp (coopdyn/dynamics/joint_space_grasp.hpp, docs/dynamics.md
// "Arms in joint space"): K = 2 arms of 7 joints welded to one object, the dual-arm box's rigid
// plant's structured weld solve (once per RK4 stage, docs/dual-arm-box.md): set_arm for each arm,
// then solve, as the plant calls them.
//
// Checked once before timing by the three conditions that determine the solution (the KKT
// equations of docs/dynamics.md, which the solver never forms): each arm's dynamics
// M_i qdd_i = u_i + J_i^T h_i, each weld J_i qdd_i + Jdot_i qdot_i = G_i^T xdd_o + b_i + beta_i,
// and the object's M_o xdd_o = hSigma_o - sum_i G_i h_i; a residual above 1e-9 (relative) skips
// the benchmark.
#include <coopdyn/dynamics/joint_space_grasp.hpp>

#include "sample_systems.hpp"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace {

constexpr int arms = 2;
constexpr int joints = 7;
using Matrix7 = Eigen::Matrix<double, joints, joints>;
using Jacobian = Eigen::Matrix<double, 6, joints>;
using Vector7 = Eigen::Matrix<double, joints, 1>;
using coopdyn_test::Vector3d;
using coopdyn_test::Vector6d;

struct Arm {
    Matrix7 inertia;
    Jacobian jacobian;
    Vector7 free_torque;
    Vector6d rate, beta;
};

struct Chain {
    std::array<Arm, arms> arm;
    coopdyn::CentralInertia<double> object;
    Eigen::Matrix<double, 3, arms> r;
    Vector3d omega;
    Vector6d object_h_sigma;
};

/// Random arms as tests/dynamics/test_joint_space_grasp.cpp draws them: M_i's diagonal from about
/// 1e-2 to 10 kg m^2, a palm Jacobian away from its singularities, a central object inertia.
Chain make_chain()
{
    coopdyn_test::Rng rng(20261127u);
    Chain chain;
    const Vector7 scale = Vector7::LinSpaced(0.5, -1.0).unaryExpr([](double e) { return std::pow(10.0, e); });
    for (int i = 0; i < arms; ++i) {
        Arm& arm = chain.arm[static_cast<std::size_t>(i)];
        arm.inertia = scale.asDiagonal() * coopdyn_test::random_spd(joints, rng, 2.0, 0.2) * scale.asDiagonal();
        arm.jacobian = 0.5 * coopdyn_test::random_matrix(6, joints, rng);
        arm.jacobian.leftCols<6>() += Eigen::Matrix<double, 6, 6>::Identity();
        arm.free_torque = coopdyn_test::random_vector(joints, rng, -20.0, 20.0);
        arm.rate = coopdyn_test::random_vector6(rng, 3.0);
        arm.beta = coopdyn_test::random_vector6(rng, 0.5);
        chain.r.col(i) = coopdyn_test::random_vector(rng, 0.4);
    }
    chain.omega = coopdyn_test::random_vector(rng, 2.0);
    chain.object_h_sigma = coopdyn_test::random_vector6(rng, 10.0);
    chain.object = coopdyn::CentralInertia<double>(coopdyn_test::uniform(rng, 0.5, 3.0),
                                                   coopdyn_test::random_body_inertia(rng, 0.1));
    return chain;
}

using Grasp = coopdyn::JointSpaceGrasp<double, arms, joints>;
using JointStack = Eigen::Matrix<double, arms * joints, 1>;

bool weld_solve(Grasp& grasp, const Chain& chain, JointStack& qdd)
{
    for (int i = 0; i < arms; ++i) {
        const Arm& arm = chain.arm[static_cast<std::size_t>(i)];
        if (!grasp.set_arm(i, arm.inertia, arm.jacobian, arm.free_torque, arm.rate, arm.beta)) {
            return false;
        }
    }
    return grasp.solve(chain.object, chain.r, chain.omega, chain.object_h_sigma, qdd);
}

/// The largest relative residual of the three conditions in the file comment.
double residual(const Grasp& grasp, const Chain& chain, const JointStack& qdd)
{
    const Vector6d object_acceleration = grasp.object_acceleration();
    const Vector3d alpha = object_acceleration.tail<3>();
    Vector6d object_balance = chain.object.matrix() * object_acceleration - chain.object_h_sigma;
    double worst = 0.0;
    for (int i = 0; i < arms; ++i) {
        const Arm& arm = chain.arm[static_cast<std::size_t>(i)];
        const Vector3d r = chain.r.col(i);
        const Vector6d h = grasp.palm_wrench(i);
        const Vector7 qdd_i = qdd.segment<joints>(joints * i);
        const Vector7 arm_balance = arm.inertia * qdd_i - arm.free_torque - arm.jacobian.transpose() * h;
        Vector6d weld = arm.jacobian * qdd_i + arm.rate - arm.beta;
        weld.head<3>() -= object_acceleration.head<3>() + alpha.cross(r) + chain.omega.cross(chain.omega.cross(r));
        weld.tail<3>() -= alpha;
        object_balance.head<3>() += h.head<3>();
        object_balance.tail<3>() += h.tail<3>() + r.cross(h.head<3>());
        worst = std::max({worst, arm_balance.norm() / arm.free_torque.norm(), weld.norm() / arm.rate.norm()});
    }
    return std::max(worst, object_balance.norm() / chain.object_h_sigma.norm());
}

void BM_JointSpaceGraspSolve(benchmark::State& state)
{
    const Chain chain = make_chain();
    Grasp grasp;
    JointStack qdd = JointStack::Zero();
    if (!weld_solve(grasp, chain, qdd) || !(residual(grasp, chain, qdd) <= 1e-9)) {
        state.SkipWithError("the weld solve fails its KKT conditions");
        return;
    }
    for (auto _ : state) {
        benchmark::ClobberMemory();
        const bool solved = weld_solve(grasp, chain, qdd);
        benchmark::DoNotOptimize(solved);
        benchmark::DoNotOptimize(qdd.data());
    }
}

}  // namespace

BENCHMARK(BM_JointSpaceGraspSolve);
