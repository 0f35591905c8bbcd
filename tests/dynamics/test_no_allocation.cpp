// The per-tick path allocates nothing once Model and Data are built.
//
// The detectors (tests/allocation_counter.hpp) count calls of the replaced global operator new
// and Eigen heap allocations (EIGEN_RUNTIME_NO_MALLOC) inside a counting window; the Sanity tests
// show that both fire.

#include "../allocation_counter.hpp"

#include "coopdyn/dynamics/cooperative_dynamics.hpp"
#include "coopdyn/dynamics/input_check.hpp"
#include "coopdyn/dynamics/interaction_wrenches.hpp"
#include "coopdyn/dynamics/simulator.hpp"
#include "coopdyn/dynamics/udwadia_kalaba.hpp"
#include "coopdyn/model/resolved_acceleration_end_effector.hpp"

#include "sample_systems.hpp"

#include <gtest/gtest.h>

#include <array>
#include <vector>

namespace {

using namespace coopdyn_test;

using allocation_counter::Allocations;
using allocation_counter::count_allocations;
using allocation_counter::sink;

// ---------------------------------------------------------------------------------------------
// The detectors work.

TEST(NoAllocationSanity, OperatorNewIsCounted)
{
    const Allocations plain = count_allocations([] {
        void* pointer = ::operator new(64);
        sink = pointer;
        ::operator delete(pointer);
    });
    EXPECT_EQ(plain.operator_new, 1);

    const Allocations aligned = count_allocations([] {
        void* pointer = ::operator new(100, std::align_val_t(64));
        sink = pointer;
        ::operator delete(pointer, std::align_val_t(64));
    });
    EXPECT_EQ(aligned.operator_new, 1);

    const Allocations vector = count_allocations([] {
        std::vector<double> values(100, 1.0);
        sink = values.data();
    });
    EXPECT_GE(vector.operator_new, 1);
    EXPECT_EQ(vector.eigen, 0);
}

TEST(NoAllocationSanity, EigenHeapAllocationIsDetected)
{
    const Allocations eigen = count_allocations([] {
        Eigen::VectorXd values = Eigen::VectorXd::Ones(100);
        sink = values.data();
    });
    EXPECT_GE(eigen.eigen, 1);

    // The generic reference solver is documented to allocate: the detector must see it.
    Rng rng(1);
    const MatrixXd M = random_spd(12, rng);
    const MatrixXd A = random_matrix(6, 12, rng);
    const VectorXd b = random_vector(6, rng);
    const VectorXd h_sigma = random_vector(12, rng);
    VectorXd h;
    const Allocations solver = count_allocations([&] { h = coopdyn::udwadia_kalaba(M, A, b, h_sigma); });
    EXPECT_GT(solver.eigen, 0);

    // Fixed-size Eigen work allocates nothing.
    const Allocations fixed = count_allocations([] {
        Matrix6d m = Matrix6d::Identity();
        m = m * m + Matrix6d::Ones();
        sink = m.data();
    });
    EXPECT_EQ(fixed.operator_new, 0);
    EXPECT_EQ(fixed.eigen, 0);
}

TEST(NoAllocation, FullRankUdwadiaKalabaWithFixedSizes)
{
    // The dual-arm box's rigid plant: 20 coordinates, 12 weld rows.
    Rng rng(2);
    const Eigen::Matrix<double, 20, 20> M = random_spd(20, rng);
    const Eigen::Matrix<double, 12, 20> A = random_matrix(12, 20, rng);
    const Eigen::Matrix<double, 12, 1> b = random_vector(12, rng);
    const Eigen::Matrix<double, 20, 1> h_sigma = random_vector(20, rng);
    Eigen::Matrix<double, 12, 1> lambda;
    Eigen::Matrix<double, 20, 1> xdd;
    bool solved = false;
    const Allocations solver = count_allocations(
        [&] { solved = coopdyn::try_udwadia_kalaba_full_rank(M, A, b, h_sigma, lambda, xdd); });
    EXPECT_TRUE(solved);
    EXPECT_EQ(solver.operator_new, 0);
    EXPECT_EQ(solver.eigen, 0);
}

// ---------------------------------------------------------------------------------------------
// Model/Data per-tick path.

/// Random models (sample_systems.hpp) with constant gains: m_o = 1.5, Lambda_i = 2 (B B^T + 0.5 I6),
/// D_i = 20 I6, K_i = 100 I6; impedance d_i, delta_i, k_i, kappa_i = 100, 10, 300, 50.
SampleRanges constant_gains()
{
    SampleRanges ranges;
    ranges.object.mass = {1.5, 1.5};
    ranges.impedance.inertia_scale = {0.5, 0.5};
    ranges.impedance.translational_damping = {100.0, 100.0};
    ranges.impedance.rotational_damping = {10.0, 10.0};
    ranges.impedance.translational_stiffness = {300.0, 300.0};
    ranges.impedance.rotational_stiffness = {50.0, 50.0};
    ranges.resolved_acceleration.inertia_scale = {2.0, 2.0};
    ranges.resolved_acceleration.derivative_gain = {20.0, 0.0};
    ranges.resolved_acceleration.proportional_gain = {100.0, 0.0};
    return ranges;
}

template <typename ModelType> void expect_per_tick_path_does_not_allocate(Index arms)
{
    constexpr int Arms = ModelType::arms_at_compile_time;
    const ModelType model = random_model<ModelType>(arms, 11u, constant_gains());
    coopdyn::Data<ModelType> data(model);
    Rng rng(12);
    const coopdyn::RigidBodyState<double> state = random_state(rng);
    coopdyn::Setpoints<double, Arms> setpoints(arms);
    setpoints.positions = random_matrix(3, arms, rng);
    setpoints.twists = random_vector(6 * arms, rng);
    setpoints.accelerations = random_vector(6 * arms, rng);
    setpoints.wrenches = random_vector(6 * arms, rng);
    coopdyn::Disturbances<double, Arms> disturbances(arms);
    disturbances.object = random_vector(6, rng);
    disturbances.end_effectors = random_vector(6 * arms, rng);

    const Allocations kinematics = count_allocations([&] {
        for (int tick = 0; tick < 10; ++tick) {
            coopdyn::grasp_kinematics(model, data, state);
        }
    });
    EXPECT_EQ(kinematics.operator_new, 0);
    EXPECT_EQ(kinematics.eigen, 0);

    const Allocations dynamics = count_allocations([&] {
        for (int tick = 0; tick < 10; ++tick) {
            coopdyn::interaction_dynamics(model, data, state, setpoints, disturbances);
        }
    });
    EXPECT_EQ(dynamics.operator_new, 0);
    EXPECT_EQ(dynamics.eigen, 0);

    bool inputs_ok = false;
    const Allocations check = count_allocations([&] {
        for (int tick = 0; tick < 10; ++tick) {
            inputs_ok = static_cast<bool>(coopdyn::check_inputs(model, state, setpoints, disturbances));
        }
    });
    EXPECT_TRUE(inputs_ok);

    // Gain scheduling between ticks: replacing an arm's parameters (validated) allocates nothing.
    ModelType scheduled = model;
    const auto end_effector = scheduled.end_effector(0);
    const Allocations schedule = count_allocations([&] {
        for (int tick = 0; tick < 10; ++tick) {
            scheduled.set_end_effector(0, end_effector);
        }
    });
    EXPECT_EQ(schedule.operator_new, 0);
    EXPECT_EQ(schedule.eigen, 0);
    EXPECT_EQ(check.operator_new, 0);
    EXPECT_EQ(check.eigen, 0);
    EXPECT_TRUE(data.wrenches.allFinite());
    EXPECT_GT(data.wrenches.norm(), 0.0);
}

TEST(NoAllocation, InteractionDynamicsImpedanceFixedTwoArms)
{
    expect_per_tick_path_does_not_allocate<coopdyn::Model<double, 2, coopdyn::ImpedanceEndEffector>>(2);
}

TEST(NoAllocation, InteractionDynamicsImpedanceDynamicThreeArms)
{
    expect_per_tick_path_does_not_allocate<coopdyn::Model<double, coopdyn::Dynamic, coopdyn::ImpedanceEndEffector>>(3);
}

TEST(NoAllocation, InteractionDynamicsResolvedAccelerationFixedAndDynamic)
{
    expect_per_tick_path_does_not_allocate<coopdyn::Model<double, 2, coopdyn::ResolvedAccelerationEndEffector>>(2);
    expect_per_tick_path_does_not_allocate<
        coopdyn::Model<double, coopdyn::Dynamic, coopdyn::ResolvedAccelerationEndEffector>>(3);
}

// ---------------------------------------------------------------------------------------------
// Kernels.

TEST(NoAllocation, SolveKernelsIntoPreallocatedDynamicVectors)
{
    Rng rng(20);
    const Index arms = 3;
    const MatrixXd object = random_spd(6, rng);
    MatrixXd ee(6, 6 * arms);
    for (Index i = 0; i < arms; ++i) {
        ee.block(0, 6 * i, 6, 6) = random_spd(6, rng);
    }
    const Matrix3d object_rotational = random_spd(3, rng, 0.2);
    const VectorXd masses = random_vector(arms, rng, 1.0, 5.0);
    MatrixXd rotational(3, 3 * arms);
    for (Index i = 0; i < arms; ++i) {
        rotational.block(0, 3 * i, 3, 3) = random_spd(3, rng, 0.3);
    }
    const MatrixXd r = random_offsets(arms, rng);
    const Vector3d omega = random_vector(3, rng);
    const VectorXd h_sigma = random_vector(6 * (arms + 1), rng);
    VectorXd accelerations = VectorXd::Zero(6 * (arms + 1));
    VectorXd wrenches = VectorXd::Zero(6 * (arms + 1));
    // The block-diagonal inertias as the kernel takes them, built before counting.
    const auto object_block = coopdyn::CentralInertia<double>(1.5, object_rotational);
    std::vector<coopdyn::CentralInertia<double>> ee_block;
    for (Index i = 0; i < arms; ++i) {
        ee_block.push_back(
            coopdyn::CentralInertia<double>(masses(i), Matrix3d(rotational.block(0, 3 * i, 3, 3))));
    }

    const Allocations general = count_allocations([&] {
        coopdyn::interaction_wrenches(object, ee, r, omega, h_sigma, accelerations, wrenches);
    });
    EXPECT_EQ(general.operator_new, 0);
    EXPECT_EQ(general.eigen, 0);
    EXPECT_TRUE(wrenches.allFinite());

    const Allocations block = count_allocations([&] {
        coopdyn::interaction_wrenches(object_block, ee_block, r, omega, h_sigma, accelerations, wrenches);
    });
    EXPECT_EQ(block.operator_new, 0);
    EXPECT_EQ(block.eigen, 0);
    EXPECT_TRUE(wrenches.allFinite());
}

TEST(NoAllocation, FixedSizeInteractionWrenches)
{
    Rng rng(21);
    const Matrix6d object = random_spd(6, rng);
    Eigen::Matrix<double, 6, 12> ee;
    ee << random_spd(6, rng), random_spd(6, rng);
    const Eigen::Matrix<double, 3, 2> r = random_offsets(2, rng);
    const Vector3d omega = random_vector(3, rng);
    const Eigen::Matrix<double, 18, 1> h_sigma = random_vector(18, rng);
    const Matrix3d object_rotational = random_spd(3, rng, 0.2);
    const Eigen::Vector2d masses(2.0, 3.0);
    Eigen::Matrix<double, 3, 6> rotational;
    rotational << random_spd(3, rng, 0.3), random_spd(3, rng, 0.3);
    Eigen::Matrix<double, 18, 1> wrenches = Eigen::Matrix<double, 18, 1>::Zero();
    Eigen::Matrix<double, 18, 1> block_wrenches = Eigen::Matrix<double, 18, 1>::Zero();
    const auto object_block = coopdyn::CentralInertia<double>(2.5, object_rotational);
    const std::array<coopdyn::CentralInertia<double>, 2> ee_block{
        coopdyn::CentralInertia<double>(masses(0), Matrix3d(rotational.block<3, 3>(0, 0))),
        coopdyn::CentralInertia<double>(masses(1), Matrix3d(rotational.block<3, 3>(0, 3)))};

    const Allocations counts = count_allocations([&] {
        wrenches = coopdyn::interaction_wrenches(object, ee, r, omega, h_sigma);
        block_wrenches = coopdyn::interaction_wrenches(object_block, ee_block, r, omega, h_sigma);
    });
    EXPECT_EQ(counts.operator_new, 0);
    EXPECT_EQ(counts.eigen, 0);
    EXPECT_TRUE(wrenches.allFinite());
    EXPECT_TRUE(block_wrenches.allFinite());
}

// ---------------------------------------------------------------------------------------------
// Simulator::step().

template <typename ModelType> void expect_simulator_step_does_not_allocate(Index arms, coopdyn::Integrator integrator)
{
    const ModelType model = random_model<ModelType>(arms, 30u, constant_gains());
    Rng rng(31);
    coopdyn::Simulator<ModelType> simulator(model, 1e-3, random_state(rng), integrator);
    simulator.setpoints().positions = random_matrix(3, arms, rng);
    simulator.disturbances().object = random_vector(6, rng);
    const Allocations counts = count_allocations([&] {
        for (int tick = 0; tick < 20; ++tick) {
            simulator.step();
        }
    });
    EXPECT_EQ(counts.operator_new, 0);
    EXPECT_EQ(counts.eigen, 0);
    EXPECT_TRUE(simulator.state().twist.allFinite());
    EXPECT_NEAR(simulator.time(), 0.02, 1e-12);
}

TEST(NoAllocation, SimulatorStepFixedTwoArms)
{
    using ModelType = coopdyn::Model<double, 2, coopdyn::ImpedanceEndEffector>;
    expect_simulator_step_does_not_allocate<ModelType>(2, coopdyn::Integrator::runge_kutta_4);
    expect_simulator_step_does_not_allocate<ModelType>(2, coopdyn::Integrator::semi_implicit_euler);
}

TEST(NoAllocation, SimulatorStepDynamicArms)
{
    using ModelType = coopdyn::Model<double, coopdyn::Dynamic, coopdyn::ImpedanceEndEffector>;
    expect_simulator_step_does_not_allocate<ModelType>(3, coopdyn::Integrator::runge_kutta_4);
    expect_simulator_step_does_not_allocate<ModelType>(3, coopdyn::Integrator::semi_implicit_euler);
    using ResolvedModel = coopdyn::Model<double, coopdyn::Dynamic, coopdyn::ResolvedAccelerationEndEffector>;
    expect_simulator_step_does_not_allocate<ResolvedModel>(4, coopdyn::Integrator::runge_kutta_4);
}

}  // namespace
