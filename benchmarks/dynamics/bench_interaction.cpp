// Benchmarks of the per-tick interaction solve (docs/dynamics.md, paper (18)):
//
//   BM_BlockDiagonalKernel / BM_BlockDiagonalDynamic  structured solver, M_i = diag(m_i I3, J_i)
//   BM_GeneralKernel / BM_GeneralDynamic              structured solver, general SPD 6x6 M_i
//   BM_GeneralEigenReference                          the same structured solve written plainly with
//                                                     Eigen (LLT<Matrix6d>, dense 6x6 products): the
//                                                     yardstick of the general kernel (issue 20)
//   BM_ModelTick / BM_ModelTickDynamic                interaction_dynamics(model, data, ...) with
//                                                     ImpedanceEndEffector (kinematics, impedance
//                                                     law, hSigma and the solve)
//   BM_UdwadiaKalaba                                  generic reference on the dense system
//   BM_LiteralBaseline                                (18) transcribed: symmetric square root and
//                                                     pseudo-inverse, dynamic matrices
//   BM_RangeSpaceBaseline                             A^T (A M^-1 A^T)^-1 (b - A M^-1 hSigma), LDLT
//
// "Kernel" and "ModelTick" use fixed N; the "Dynamic" variants take the same inputs with
// N chosen at run time and write into preallocated buffers. Every variant is checked once,
// before its timed loop, against coopdyn::udwadia_kalaba (relative error <= 1e-9); a mismatch
// aborts that benchmark with SkipWithError, so the numbers always belong to a correct solve.
//
// Ratios in the report are taken against BM_LiteralBaseline at the same N; the general kernel's
// also against BM_GeneralEigenReference (docs/performance.md, "The general SPD kernel").


#include <coopdyn/coopdyn.hpp>

#include "sample_systems.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/QR>
#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>
#include <random>
#include <vector>

namespace {

using coopdyn::Dynamic;
using coopdyn_test::Index;
using coopdyn_test::random_matrix;
using coopdyn_test::random_spd;
using coopdyn_test::Rng;
using coopdyn_test::TickFixture;
using coopdyn_test::uniform;
using MatrixX = Eigen::MatrixXd;
using VectorX = Eigen::VectorXd;

constexpr double tolerance = 1e-9;

// ---------------------------------------------------------------------------------------------
// Inputs: one random, well-conditioned cooperative system per N, from a fixed seed.
// ---------------------------------------------------------------------------------------------

/// Everything a solve needs, stored with dynamic sizes; the fixed-N benchmarks copy it into
/// fixed-size matrices.
struct Case {
    double object_mass = 0;
    Eigen::Matrix3d object_rotational = Eigen::Matrix3d::Zero();  // J_o in {w}
    MatrixX object_general;                                       // general SPD 6x6 M_o
    VectorX masses;                                               // m_i, N
    MatrixX rotational;                                           // J_i, 3 x 3N
    MatrixX general;                                              // general SPD M_i, 6 x 6N
    Eigen::Matrix3Xd r;                                           // 3 x N
    Eigen::Vector3d omega = Eigen::Vector3d::Zero();
    VectorX h_sigma;                                              // 6(N+1)
};


Case make_case(Index arms, std::uint32_t seed)
{
    Rng rng(seed);
    Case c;
    c.object_mass = uniform(rng, 1, 5);
    c.object_rotational = random_spd(3, rng, 1.0, 0.5);
    c.object_general = random_spd(6, rng, 1.0, 2.0);
    c.masses.resize(arms);
    c.rotational.resize(3, 3 * arms);
    c.general.resize(6, 6 * arms);
    for (Index i = 0; i < arms; ++i) {
        c.masses(i) = uniform(rng, 1, 5);
        c.rotational.block(0, 3 * i, 3, 3) = random_spd(3, rng, 1.0, 0.5);
        c.general.block(0, 6 * i, 6, 6) = random_spd(6, rng, 1.0, 2.0);
    }
    c.r = random_matrix(3, arms, rng);  // r_i in [-1, 1]^3
    c.omega = random_matrix(3, 1, rng, -2, 2);
    c.h_sigma = random_matrix(6 * (arms + 1), 1, rng, -10, 10);
    return c;
}

const Case& case_for(Index arms)
{
    // One case per N, built on first use (outside every timed loop) and kept alive.
    static std::vector<Case> cases(17);
    Case& c = cases[static_cast<std::size_t>(arms)];
    if (c.masses.size() == 0) {
        c = make_case(arms, 20240601u + static_cast<std::uint32_t>(arms));
    }
    return c;
}

/// The dense system of (18): M = blkdiag(M_o, M_1, ..., M_N), A (14), b (13).
struct DenseSystem {
    MatrixX M;
    MatrixX A;
    VectorX b;
    VectorX h_sigma;
};

DenseSystem dense_system(const MatrixX& object_inertia, const MatrixX& ee_inertias, const Eigen::Matrix3Xd& r,
                         const Eigen::Vector3d& omega, const VectorX& h_sigma)
{
    const Index arms = r.cols();
    DenseSystem system;
    system.M = MatrixX::Zero(6 * (arms + 1), 6 * (arms + 1));
    system.M.topLeftCorner(6, 6) = object_inertia;
    for (Index i = 0; i < arms; ++i) {
        system.M.block(6 * (i + 1), 6 * (i + 1), 6, 6) = ee_inertias.block(0, 6 * i, 6, 6);
    }
    system.A = coopdyn::constraint_matrix(r);
    system.b = coopdyn::constraint_bias(r, omega);
    system.h_sigma = h_sigma;
    return system;
}

MatrixX block_diagonal_object(const Case& c)
{
    MatrixX result = MatrixX::Zero(6, 6);
    result.topLeftCorner(3, 3).diagonal().setConstant(c.object_mass);
    result.bottomRightCorner(3, 3) = c.object_rotational;
    return result;
}

MatrixX block_diagonal_end_effectors(const Case& c)
{
    const Index arms = c.r.cols();
    MatrixX result = MatrixX::Zero(6, 6 * arms);
    for (Index i = 0; i < arms; ++i) {
        result.block(0, 6 * i, 3, 3).diagonal().setConstant(c.masses(i));
        result.block(3, 6 * i + 3, 3, 3) = c.rotational.block(0, 3 * i, 3, 3);
    }
    return result;
}

DenseSystem block_diagonal_system(const Case& c)
{
    return dense_system(block_diagonal_object(c), block_diagonal_end_effectors(c), c.r, c.omega, c.h_sigma);
}

DenseSystem general_system(const Case& c)
{
    return dense_system(c.object_general, c.general, c.r, c.omega, c.h_sigma);
}

VectorX reference(const DenseSystem& s) { return coopdyn::udwadia_kalaba(s.M, s.A, s.b, s.h_sigma); }

/// Checks `h` against the reference once, before timing. Returns false (and marks the benchmark
/// as failed) on a mismatch.
template <typename Derived>
bool check(benchmark::State& state, const Eigen::MatrixBase<Derived>& h, const VectorX& expected)
{
    const double error = (h - expected).norm() / expected.norm();
    if (!(error <= tolerance)) {
        state.SkipWithError("result differs from coopdyn::udwadia_kalaba");
        return false;
    }
    return true;
}

// ---------------------------------------------------------------------------------------------
// Baselines a reader of the paper would write (dynamic sizes, allocating).
// ---------------------------------------------------------------------------------------------

/// (18) as printed: h = M^(1/2) (A M^(-1/2))^+ (b - A M^-1 hSigma), with the symmetric square
/// root from an eigen-decomposition and the pseudo-inverse from a complete orthogonal
/// decomposition.
VectorX literal_baseline(const MatrixX& M, const MatrixX& A, const VectorX& b, const VectorX& h_sigma)
{
    const Eigen::SelfAdjointEigenSolver<MatrixX> eigen(M);
    const MatrixX root = eigen.operatorSqrt();
    const MatrixX inverse_root = eigen.operatorInverseSqrt();
    const MatrixX pseudo_inverse = Eigen::CompleteOrthogonalDecomposition<MatrixX>(A * inverse_root).pseudoInverse();
    const VectorX unconstrained = inverse_root * (inverse_root * h_sigma);  // M^-1 hSigma
    return root * (pseudo_inverse * (b - A * unconstrained));
}

/// Range-space (Lagrange multiplier) form: h = A^T (A M^-1 A^T)^-1 (b - A M^-1 hSigma).
VectorX range_space_baseline(const MatrixX& M, const MatrixX& A, const VectorX& b, const VectorX& h_sigma)
{
    const Eigen::LDLT<MatrixX> inertia(M);
    const MatrixX inverse_inertia_a_transpose = inertia.solve(A.transpose());
    const Eigen::LDLT<MatrixX> schur(A * inverse_inertia_a_transpose);
    return A.transpose() * schur.solve(b - A * inertia.solve(h_sigma));
}

// ---------------------------------------------------------------------------------------------
// 1. Structured solver, block-diagonal inertias diag(m I3, J).
// ---------------------------------------------------------------------------------------------

/// The block-diagonal inertias of a case as the kernel takes them: diag(m_i I3, J_i) per arm.
template <typename Inertias> void fill_block_diagonal(const Case& c, Inertias& inertias)
{
    for (Index i = 0; i < c.masses.size(); ++i) {
        inertias[static_cast<std::size_t>(i)] =
            coopdyn::CentralInertia<double>(c.masses(i), c.rotational.block<3, 3>(0, 3 * i));
    }
}

template <int N> void BM_BlockDiagonalKernel(benchmark::State& state)
{
    const Case& c = case_for(N);
    const auto object = coopdyn::CentralInertia<double>(c.object_mass, c.object_rotational);
    std::array<coopdyn::CentralInertia<double>, N> inertias;
    fill_block_diagonal(c, inertias);
    const coopdyn::PerArmVector3<double, N> r = c.r;
    const Eigen::Vector3d omega = c.omega;
    const coopdyn::FullStackVector<double, N> h_sigma = c.h_sigma;

    if (!check(state,
               coopdyn::interaction_wrenches(object, inertias, r, omega, h_sigma),
               reference(block_diagonal_system(c)))) {
        return;
    }
    for (auto _ : state) {
        // The inputs may change between ticks: ClobberMemory keeps the compiler from hoisting.
        benchmark::ClobberMemory();
        auto h = coopdyn::interaction_wrenches(object, inertias, r, omega, h_sigma);
        benchmark::DoNotOptimize(h);
    }
}

template <int N> void BM_BlockDiagonalDynamic(benchmark::State& state)
{
    const Case& c = case_for(N);
    VectorX accelerations = VectorX::Zero(6 * (N + 1));
    VectorX wrenches = VectorX::Zero(6 * (N + 1));
    const auto object = coopdyn::CentralInertia<double>(c.object_mass, c.object_rotational);
    std::vector<coopdyn::CentralInertia<double>> inertias(static_cast<std::size_t>(N));
    fill_block_diagonal(c, inertias);
    coopdyn::interaction_wrenches(object, inertias, c.r, c.omega, c.h_sigma, accelerations, wrenches);
    if (!check(state, wrenches, reference(block_diagonal_system(c)))) {
        return;
    }
    for (auto _ : state) {
        benchmark::ClobberMemory();
        coopdyn::interaction_wrenches(object, inertias, c.r, c.omega, c.h_sigma, accelerations, wrenches);
        benchmark::DoNotOptimize(wrenches.data());
        benchmark::DoNotOptimize(accelerations.data());
    }
}

// ---------------------------------------------------------------------------------------------
// 2. Structured solver, general SPD 6x6 inertias.
// ---------------------------------------------------------------------------------------------

/// A case's general-SPD inputs in fixed-size matrices (N known at compile time).
template <int N> struct FixedGeneralInputs {
    explicit FixedGeneralInputs(const Case& c)
        : object_inertia(c.object_general), inertias(c.general), r(c.r), omega(c.omega), h_sigma(c.h_sigma)
    {
    }
    Eigen::Matrix<double, 6, 6> object_inertia;
    coopdyn::PerArmMatrix6<double, N> inertias;
    coopdyn::PerArmVector3<double, N> r;
    Eigen::Vector3d omega;
    coopdyn::FullStackVector<double, N> h_sigma;
};

/// Times `solve(inputs)` on case N's general-SPD inputs after checking it once against the dense
/// reference.
template <int N, typename Solve> void run_general(benchmark::State& state, const Solve& solve)
{
    const Case& c = case_for(N);
    const FixedGeneralInputs<N> inputs(c);
    if (!check(state, solve(inputs), reference(general_system(c)))) {
        return;
    }
    for (auto _ : state) {
        benchmark::ClobberMemory();
        auto h = solve(inputs);
        benchmark::DoNotOptimize(h);
    }
}

template <int N> void BM_GeneralKernel(benchmark::State& state)
{
    run_general<N>(state, [](const FixedGeneralInputs<N>& in) {
        return coopdyn::interaction_wrenches(in.object_inertia, in.inertias, in.r, in.omega, in.h_sigma);
    });
}

template <int N> void BM_GeneralDynamic(benchmark::State& state)
{
    const Case& c = case_for(N);
    VectorX accelerations = VectorX::Zero(6 * (N + 1));
    VectorX wrenches = VectorX::Zero(6 * (N + 1));
    coopdyn::interaction_wrenches(c.object_general, c.general, c.r, c.omega, c.h_sigma, accelerations, wrenches);
    if (!check(state, wrenches, reference(general_system(c)))) {
        return;
    }
    for (auto _ : state) {
        benchmark::ClobberMemory();
        coopdyn::interaction_wrenches(c.object_general, c.general, c.r, c.omega, c.h_sigma, accelerations,
                                      wrenches);
        benchmark::DoNotOptimize(wrenches.data());
        benchmark::DoNotOptimize(accelerations.data());
    }
}

/// The structured solve in reduced coordinates (docs/dynamics.md) as a reader would write it with
/// Eigen's fixed-size types, the yardstick of the general kernel: per arm an LLT<Matrix6d> of M_i
/// for its unconstrained acceleration a_i = M_i^-1 hSigma_i, the composite inertia
/// M_o + sum_i X_i^T M_i X_i from dense 6x6 products (X_i = G_i^T = [[I3, S(r_i)^T], [0, I3]])
/// solved by LLT, then back-substitution xdd_i = X_i xdd_o + b_i, h_i = M_i (xdd_i - a_i)
/// (Udwadia-Kalaba's constraint force). Returns h = [h_o; h_1; ...; h_N].
template <int N>
coopdyn::FullStackVector<double, N> general_eigen_reference(const Eigen::Matrix<double, 6, 6>& object_inertia,
                                                            const coopdyn::PerArmMatrix6<double, N>& inertias,
                                                            const coopdyn::PerArmVector3<double, N>& r,
                                                            const Eigen::Vector3d& omega,
                                                            const coopdyn::FullStackVector<double, N>& h_sigma)
{
    using Matrix6d = Eigen::Matrix<double, 6, 6>;
    using Vector6d = Eigen::Matrix<double, 6, 1>;
    std::array<Matrix6d, N> maps;                 // X_i
    std::array<Vector6d, N> biases;               // b_i = [w x (w x r_i); 0]
    std::array<Vector6d, N> unconstrained;        // a_i
    Matrix6d composite = object_inertia;
    Vector6d rhs = h_sigma.template head<6>();    // M_o a_o = hSigma_o
    for (int i = 0; i < N; ++i) {
        const Matrix6d inertia = inertias.template block<6, 6>(0, 6 * i);
        const Eigen::Vector3d r_i = r.col(i);
        Matrix6d& map = maps[static_cast<std::size_t>(i)];
        map.setIdentity();
        map.template topRightCorner<3, 3>() << 0, r_i(2), -r_i(1), -r_i(2), 0, r_i(0), r_i(1), -r_i(0), 0;
        Vector6d& bias = biases[static_cast<std::size_t>(i)];
        bias << omega.cross(omega.cross(r_i)), Eigen::Vector3d::Zero();
        const Eigen::LLT<Matrix6d> factor(inertia);
        Vector6d& a_i = unconstrained[static_cast<std::size_t>(i)];
        a_i = factor.solve(h_sigma.template segment<6>(6 + 6 * i));
        composite.noalias() += map.transpose() * inertia * map;
        rhs.noalias() += map.transpose() * (inertia * (a_i - bias));
    }
    const Vector6d object_acceleration = Eigen::LLT<Matrix6d>(composite).solve(rhs);
    coopdyn::FullStackVector<double, N> h;
    h.template head<6>().noalias() = object_inertia * object_acceleration - h_sigma.template head<6>();
    for (int i = 0; i < N; ++i) {
        const auto k = static_cast<std::size_t>(i);
        const Vector6d acceleration = maps[k] * object_acceleration + biases[k];
        h.template segment<6>(6 + 6 * i).noalias() =
            inertias.template block<6, 6>(0, 6 * i) * (acceleration - unconstrained[k]);
    }
    return h;
}

template <int N> void BM_GeneralEigenReference(benchmark::State& state)
{
    run_general<N>(state, [](const FixedGeneralInputs<N>& in) {
        return general_eigen_reference<N>(in.object_inertia, in.inertias, in.r, in.omega, in.h_sigma);
    });
}

// ---------------------------------------------------------------------------------------------
// 3. Full Model/Data tick with impedance end-effectors.
// ---------------------------------------------------------------------------------------------

/// The dense system the last tick of `f` solved, for the reference check.
template <int Arms> DenseSystem last_system(const TickFixture<Arms>& f)
{
    const Index arms = f.model.arms();
    MatrixX ee_inertias(6, 6 * arms);
    for (Index i = 0; i < arms; ++i) {
        ee_inertias.block(0, 6 * i, 6, 6) = f.model.end_effector(i).inertia().matrix();
    }
    const MatrixX object_inertia = f.model.object().spatial_inertia(f.data.object_rotation);
    const Eigen::Matrix3Xd r = f.data.grasp_offsets;
    return dense_system(object_inertia, ee_inertias, r, f.state.twist.template tail<3>(), f.data.h_sigma);
}

template <int Arms> void run_tick(benchmark::State& state, Index arms)
{
    TickFixture<Arms> f(arms);
    coopdyn::interaction_dynamics(f.model, f.data, f.state, f.setpoints, f.disturbances);
    if (!check(state, f.data.wrenches, reference(last_system(f)))) {
        return;
    }
    for (auto _ : state) {
        benchmark::ClobberMemory();
        const auto& h = coopdyn::interaction_dynamics(f.model, f.data, f.state, f.setpoints, f.disturbances);
        benchmark::DoNotOptimize(h.data());
    }
}

template <int N> void BM_ModelTick(benchmark::State& state) { run_tick<N>(state, N); }
template <int N> void BM_ModelTickDynamic(benchmark::State& state) { run_tick<Dynamic>(state, N); }

// ---------------------------------------------------------------------------------------------
// 4./5. Generic reference and the two baselines, on the dense block-diagonal system.
// ---------------------------------------------------------------------------------------------

template <int N> void BM_UdwadiaKalaba(benchmark::State& state)
{
    const DenseSystem s = block_diagonal_system(case_for(N));
    for (auto _ : state) {
        benchmark::ClobberMemory();
        VectorX h = coopdyn::udwadia_kalaba(s.M, s.A, s.b, s.h_sigma);
        benchmark::DoNotOptimize(h.data());
    }
}

template <int N> void BM_LiteralBaseline(benchmark::State& state)
{
    const DenseSystem s = block_diagonal_system(case_for(N));
    if (!check(state, literal_baseline(s.M, s.A, s.b, s.h_sigma), reference(s))) {
        return;
    }
    for (auto _ : state) {
        benchmark::ClobberMemory();
        VectorX h = literal_baseline(s.M, s.A, s.b, s.h_sigma);
        benchmark::DoNotOptimize(h.data());
    }
}

template <int N> void BM_RangeSpaceBaseline(benchmark::State& state)
{
    const DenseSystem s = block_diagonal_system(case_for(N));
    if (!check(state, range_space_baseline(s.M, s.A, s.b, s.h_sigma), reference(s))) {
        return;
    }
    for (auto _ : state) {
        benchmark::ClobberMemory();
        VectorX h = range_space_baseline(s.M, s.A, s.b, s.h_sigma);
        benchmark::DoNotOptimize(h.data());
    }
}

}  // namespace

// N = 2, 3, 4, 8, 16 for every benchmark.
#define COOPDYN_BENCHMARK_ARMS(name)   \
    BENCHMARK_TEMPLATE(name, 2);       \
    BENCHMARK_TEMPLATE(name, 3);       \
    BENCHMARK_TEMPLATE(name, 4);       \
    BENCHMARK_TEMPLATE(name, 8);       \
    BENCHMARK_TEMPLATE(name, 16)

COOPDYN_BENCHMARK_ARMS(BM_BlockDiagonalKernel);
COOPDYN_BENCHMARK_ARMS(BM_BlockDiagonalDynamic);
COOPDYN_BENCHMARK_ARMS(BM_GeneralKernel);
COOPDYN_BENCHMARK_ARMS(BM_GeneralDynamic);
BENCHMARK_TEMPLATE(BM_GeneralEigenReference, 2);
BENCHMARK_TEMPLATE(BM_GeneralEigenReference, 16);
COOPDYN_BENCHMARK_ARMS(BM_ModelTick);
COOPDYN_BENCHMARK_ARMS(BM_ModelTickDynamic);
COOPDYN_BENCHMARK_ARMS(BM_UdwadiaKalaba);
COOPDYN_BENCHMARK_ARMS(BM_LiteralBaseline);
COOPDYN_BENCHMARK_ARMS(BM_RangeSpaceBaseline);
