// The structured O(N) interaction kernels (dynamics/interaction_wrenches.hpp) against the generic
// Udwadia-Kalaba solve of the assembled system, Newton's third law, the constraints, and the
// composite rigid body built from first principles (parallel-axis theorem).
#include "coopdyn/dynamics/interaction_wrenches.hpp"
#include "coopdyn/dynamics/udwadia_kalaba.hpp"
#include "coopdyn/model/grasp.hpp"

#include "sample_systems.hpp"

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <limits>
#include <type_traits>
#include <vector>

namespace {

using namespace coopdyn_test;

/// diag(m_i I3, J_i) per arm, as the kernels take block-diagonal inertias: a std::array for a
/// fixed N (Arms > 0), a std::vector otherwise.
template <int Arms = 0, typename Masses, typename Rotational>
auto block_diagonal_inertias(const Masses& masses, const Rotational& rotational)
{
    using Scalar = typename Masses::Scalar;
    using Inertia = coopdyn::CentralInertia<Scalar>;
    std::conditional_t<Arms == 0, std::vector<Inertia>, std::array<Inertia, static_cast<std::size_t>(Arms)>> result{};
    if constexpr (Arms == 0) {
        result.resize(static_cast<std::size_t>(masses.size()));
    }
    for (Index i = 0; i < masses.size(); ++i) {
        result[static_cast<std::size_t>(i)] =
            Inertia(masses(i), Eigen::Matrix<Scalar, 3, 3>(rotational.block(0, 3 * i, 3, 3)));
    }
    return result;
}

constexpr double tolerance = 1e-12;
constexpr unsigned cases_per_arm_count = 30;
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

/// One random rigid-grasp problem with N arms.
struct Problem {
    double object_mass = 0.0;
    Matrix3d object_rotational = Matrix3d::Zero();  // general SPD J_o
    Matrix6d object_general = Matrix6d::Zero();     // general 6x6 SPD M_o (coupled)
    MatrixXd ee_general;                            // 6 x 6N, general SPD blocks
    VectorXd ee_masses;                             // N
    MatrixXd ee_rotational;                         // 3 x 3N, general SPD blocks
    MatrixXd r;                                     // 3 x N
    Vector3d omega = Vector3d::Zero();
    VectorXd h_sigma;                               // 6(N+1)

    Index arms() const { return r.cols(); }
    Matrix6d object_block_diagonal() const { return block_diagonal_inertia(object_mass, object_rotational); }
    MatrixXd ee_block_diagonal() const
    {
        MatrixXd stack(6, 6 * arms());
        for (Index i = 0; i < arms(); ++i) {
            stack.block(0, 6 * i, 6, 6) = block_diagonal_inertia(ee_masses(i), ee_rotational.block(0, 3 * i, 3, 3));
        }
        return stack;
    }
};

Problem random_problem(Index arms, Rng& rng)
{
    Problem p;
    p.object_mass = uniform(rng, 0.2, 5.0);
    p.object_rotational = random_spd(3, rng, uniform(rng, 0.01, 1.0), 0.2);
    p.object_general = random_spd(6, rng, uniform(rng, 0.2, 5.0));
    p.ee_general.resize(6, 6 * arms);
    p.ee_masses.resize(arms);
    p.ee_rotational.resize(3, 3 * arms);
    for (Index i = 0; i < arms; ++i) {
        p.ee_general.block(0, 6 * i, 6, 6) = random_spd(6, rng, uniform(rng, 0.5, 10.0));
        p.ee_masses(i) = uniform(rng, 0.5, 10.0);
        p.ee_rotational.block(0, 3 * i, 3, 3) = random_spd(3, rng, uniform(rng, 0.05, 1.0), 0.2);
    }
    p.r = random_offsets(arms, rng);
    p.omega = random_vector(3, rng, -3.0, 3.0);
    p.h_sigma = random_vector(6 * (arms + 1), rng, -20.0, 20.0);
    return p;
}

struct Reference {
    VectorXd accelerations;
    VectorXd wrenches;
};

/// Generic UK on M = blkdiag(M_o, M_1..M_N), A (14) and b (13) written out from docs/model.md.
Reference uk_reference(const MatrixXd& object_inertia, const MatrixXd& ee_inertia, const MatrixXd& r,
                       const Vector3d& omega, const VectorXd& h_sigma)
{
    const MatrixXd M = assemble_inertia(object_inertia, ee_inertia);
    const VectorXd h =
        coopdyn::udwadia_kalaba(M, literal_constraint_matrix(r), literal_constraint_bias(r, omega), h_sigma);
    return {M.ldlt().solve(h_sigma + h), h};
}

struct Result {
    VectorXd accelerations;
    VectorXd wrenches;
};

/// Fixed-size (N known at compile time) calls of the general and block-diagonal kernels.
template <int N> struct FixedKernels {
    using R = Eigen::Matrix<double, 3, N>;
    using Stack6 = Eigen::Matrix<double, 6, 6 * N>;
    using Stack3 = Eigen::Matrix<double, 3, 3 * N>;
    using Full = Eigen::Matrix<double, 6 * (N + 1), 1>;

    static Result general(const Matrix6d& object, const MatrixXd& ee, const Problem& p)
    {
        const Stack6 ee_fixed = ee;
        const R r = p.r;
        const Full h_sigma = p.h_sigma;
        // NaN-filled outputs: every entry must be written by the kernel.
        Full accelerations = Full::Constant(nan);
        Full wrenches = Full::Constant(nan);
        coopdyn::interaction_wrenches(object, ee_fixed, r, p.omega, h_sigma, accelerations, wrenches);
        const Full returned = coopdyn::interaction_wrenches(object, ee_fixed, r, p.omega, h_sigma);
        static_assert(std::is_same<std::decay_t<decltype(returned)>, Full>::value, "fixed-size result");
        EXPECT_TRUE((returned.array() == wrenches.array()).all()) << "interaction_wrenches != solve_..._dynamics";
        return {accelerations, wrenches};
    }

    static Result block_diagonal(const Problem& p)
    {
        const Eigen::Matrix<double, N, 1> masses = p.ee_masses;
        const Stack3 rotational = p.ee_rotational;
        const R r = p.r;
        const Full h_sigma = p.h_sigma;
        // NaN-filled outputs: every entry must be written by the kernel.
        Full accelerations = Full::Constant(nan);
        Full wrenches = Full::Constant(nan);
        const auto object = coopdyn::CentralInertia<double>(p.object_mass, p.object_rotational);
        const auto inertias = block_diagonal_inertias<N>(masses, rotational);
        coopdyn::interaction_wrenches(object, inertias, r, p.omega, h_sigma, accelerations, wrenches);
        const auto returned = coopdyn::interaction_wrenches(object, inertias, r, p.omega, h_sigma);
        static_assert(std::is_same<std::decay_t<decltype(returned)>, Full>::value, "fixed-size result");
        EXPECT_TRUE((returned.array() == wrenches.array()).all());
        return {accelerations, wrenches};
    }
};

Result dynamic_general(const Matrix6d& object, const MatrixXd& ee, const Problem& p)
{
    const MatrixXd object_dynamic = object;
    VectorXd accelerations = VectorXd::Constant(p.h_sigma.size(), nan);
    VectorXd wrenches = VectorXd::Constant(p.h_sigma.size(), nan);
    coopdyn::interaction_wrenches(object_dynamic, ee, p.r, p.omega, p.h_sigma, accelerations, wrenches);
    const VectorXd returned = coopdyn::interaction_wrenches(object_dynamic, ee, p.r, p.omega, p.h_sigma);
    EXPECT_TRUE((returned.array() == wrenches.array()).all());
    return {accelerations, wrenches};
}

Result dynamic_block_diagonal(const Problem& p)
{
    VectorXd accelerations = VectorXd::Constant(p.h_sigma.size(), nan);
    VectorXd wrenches = VectorXd::Constant(p.h_sigma.size(), nan);
    const auto object = coopdyn::CentralInertia<double>(p.object_mass, p.object_rotational);
    const auto inertias = block_diagonal_inertias(p.ee_masses, p.ee_rotational);
    coopdyn::interaction_wrenches(object, inertias, p.r, p.omega, p.h_sigma, accelerations, wrenches);
    const VectorXd returned = coopdyn::interaction_wrenches(object, inertias, p.r, p.omega, p.h_sigma);
    EXPECT_TRUE((returned.array() == wrenches.array()).all());

    // J_o given as a dynamic-size 3x3 matrix: the object inertia is built from its entries, so
    // the result must not depend on how J_o was stored (it is not an N effect).
    const MatrixXd object_rotational_dynamic = p.object_rotational;
    const VectorXd with_dynamic_object = coopdyn::interaction_wrenches(
        coopdyn::CentralInertia<double>(p.object_mass, object_rotational_dynamic), inertias, p.r,
        p.omega, p.h_sigma);
    EXPECT_LT(relative_error(with_dynamic_object, wrenches), 1e-15);
    return {accelerations, wrenches};
}

void expect_bit_identical(const VectorXd& fixed, const VectorXd& dynamic, const char* what)
{
    ASSERT_EQ(fixed.size(), dynamic.size());
    for (Index k = 0; k < fixed.size(); ++k) {
        EXPECT_EQ(fixed(k), dynamic(k)) << what << " coefficient " << k;
    }
}

/// Properties every kernel result must have: A xdd = b and h_o = -G h'.
void expect_physical_identities(const Result& result, const Problem& p, const VectorXd& h_sigma)
{
    const MatrixXd A = literal_constraint_matrix(p.r);
    const VectorXd b = literal_constraint_bias(p.r, p.omega);
    const double residual = (A * result.accelerations - b).norm() / (A.norm() * result.accelerations.norm() + b.norm());
    EXPECT_LT(residual, 1e-15);
    const MatrixXd G = literal_grasp_matrix(p.r);
    const VectorXd newton = result.wrenches.head(6) + G * result.wrenches.tail(6 * p.arms());
    EXPECT_LT(newton.norm() / (h_sigma.norm() + result.wrenches.norm()), tolerance) << "h_o != -G h'";
}

template <typename ArmCount> class InteractionWrenches : public ::testing::Test {};
using ArmCounts = ::testing::Types<std::integral_constant<int, 1>, std::integral_constant<int, 2>,
                                   std::integral_constant<int, 3>, std::integral_constant<int, 4>,
                                   std::integral_constant<int, 5>, std::integral_constant<int, 6>>;
TYPED_TEST_SUITE(InteractionWrenches, ArmCounts);

TYPED_TEST(InteractionWrenches, GeneralKernelMatchesUdwadiaKalaba)
{
    constexpr int N = TypeParam::value;
    double worst = 0.0;
    for (unsigned seed = 0; seed < cases_per_arm_count; ++seed) {
        Rng rng(1000u * static_cast<unsigned>(N) + seed);
        const Problem p = random_problem(N, rng);
        // Both object inertia structures: diag(m_o I3, J_o) and a general coupled 6x6 SPD.
        for (const Matrix6d& object : {p.object_block_diagonal(), p.object_general}) {
            const Reference reference = uk_reference(object, p.ee_general, p.r, p.omega, p.h_sigma);
            const Result fixed = FixedKernels<N>::general(object, p.ee_general, p);
            const Result dynamic = dynamic_general(object, p.ee_general, p);
            const double acceleration_error = relative_error(fixed.accelerations, reference.accelerations);
            const double wrench_error = relative_error(fixed.wrenches, reference.wrenches);
            EXPECT_LT(acceleration_error, tolerance) << "N " << N << " seed " << seed;
            EXPECT_LT(wrench_error, tolerance) << "N " << N << " seed " << seed;
            worst = std::max({worst, acceleration_error, wrench_error});
            expect_bit_identical(fixed.accelerations, dynamic.accelerations, "accelerations");
            expect_bit_identical(fixed.wrenches, dynamic.wrenches, "wrenches");
            expect_physical_identities(fixed, p, p.h_sigma);
        }
    }
    std::printf("[ measured ] general kernel vs UK, N = %d: worst relative error %.3g\n", N, worst);
}

TYPED_TEST(InteractionWrenches, BlockDiagonalKernelMatchesGeneralKernelAndUdwadiaKalaba)
{
    constexpr int N = TypeParam::value;
    double worst_uk = 0.0;
    double worst_general = 0.0;
    for (unsigned seed = 0; seed < cases_per_arm_count; ++seed) {
        Rng rng(2000u * static_cast<unsigned>(N) + seed);
        const Problem p = random_problem(N, rng);
        const Matrix6d object = p.object_block_diagonal();
        const MatrixXd ee = p.ee_block_diagonal();
        const Reference reference = uk_reference(object, ee, p.r, p.omega, p.h_sigma);
        const Result general = dynamic_general(object, ee, p);
        const Result fixed = FixedKernels<N>::block_diagonal(p);
        const Result dynamic = dynamic_block_diagonal(p);

        const double uk_error = std::max(relative_error(fixed.accelerations, reference.accelerations),
                                         relative_error(fixed.wrenches, reference.wrenches));
        const double general_error = std::max(relative_error(fixed.accelerations, general.accelerations),
                                              relative_error(fixed.wrenches, general.wrenches));
        EXPECT_LT(uk_error, tolerance) << "N " << N << " seed " << seed;
        EXPECT_LT(general_error, tolerance) << "N " << N << " seed " << seed;
        worst_uk = std::max(worst_uk, uk_error);
        worst_general = std::max(worst_general, general_error);
        expect_bit_identical(fixed.accelerations, dynamic.accelerations, "accelerations");
        expect_bit_identical(fixed.wrenches, dynamic.wrenches, "wrenches");
        expect_physical_identities(fixed, p, p.h_sigma);
    }
    std::printf("[ measured ] block-diagonal kernel, N = %d: worst relative error vs UK %.3g, vs general %.3g\n",
                N, worst_uk, worst_general);
}

/// The N + 1 bodies with end-effector hSigma_i = 0 and object hSigma_o = w, w_o = 0, move as one
/// rigid body. Its inertia is built here from first principles: composite mass, composite centre
/// of mass, rotational inertia about that centre by the parallel-axis theorem; then Newton-Euler
/// about the composite centre of mass.
TYPED_TEST(InteractionWrenches, ObjectMovesLikeTheCompositeRigidBody)
{
    constexpr int N = TypeParam::value;
    double worst = 0.0;
    for (unsigned seed = 0; seed < cases_per_arm_count; ++seed) {
        Rng rng(3000u * static_cast<unsigned>(N) + seed);
        Problem p = random_problem(N, rng);
        const Vector6d applied = random_vector(6, rng, -20.0, 20.0);
        p.h_sigma.setZero();
        p.h_sigma.head(6) = applied;
        p.omega.setZero();

        // Composite body. Object centre of mass at the origin; arm i a body of mass m_i at r_i with
        // rotational inertia J_i about its own centre of mass.
        double total_mass = p.object_mass;
        Vector3d first_moment = Vector3d::Zero();
        for (Index i = 0; i < N; ++i) {
            total_mass += p.ee_masses(i);
            first_moment += p.ee_masses(i) * p.r.col(i);
        }
        const Vector3d centre = first_moment / total_mass;
        auto parallel_axis = [](double mass, const Vector3d& d) {
            return mass * (d.squaredNorm() * Matrix3d::Identity() - d * d.transpose());
        };
        Matrix3d inertia_about_centre = p.object_rotational + parallel_axis(p.object_mass, -centre);
        for (Index i = 0; i < N; ++i) {
            inertia_about_centre +=
                p.ee_rotational.block(0, 3 * i, 3, 3) + parallel_axis(p.ee_masses(i), Vector3d(p.r.col(i)) - centre);
        }
        // Newton-Euler about the composite centre (w = 0): f = m a_c, t_c = J_c alpha, with the
        // torque about the object's reference point shifted, t_c = t_o - c x f; then a_o = a_c - alpha x c.
        const Vector3d force = applied.head<3>();
        const Vector3d torque_about_centre = applied.tail<3>() - centre.cross(force);
        const Vector3d angular = inertia_about_centre.ldlt().solve(torque_about_centre);
        const Vector3d linear = force / total_mass - angular.cross(centre);
        VectorXd expected(6 * (N + 1));
        expected.head<3>() = linear;
        expected.segment<3>(3) = angular;
        for (Index i = 0; i < N; ++i) {
            expected.segment<3>(6 * (i + 1)) = linear + angular.cross(Vector3d(p.r.col(i)));
            expected.segment<3>(6 * (i + 1) + 3) = angular;
        }

        const Result block = FixedKernels<N>::block_diagonal(p);
        const Result general = dynamic_general(p.object_block_diagonal(), p.ee_block_diagonal(), p);
        const double error = std::max(relative_error(block.accelerations, expected),
                                      relative_error(general.accelerations, expected));
        EXPECT_LT(error, tolerance) << "N " << N << " seed " << seed;
        worst = std::max(worst, error);

        // With w_o != 0 there is no such closed form, but the UK reference still holds.
        p.omega = random_vector(3, rng, -3.0, 3.0);
        const Reference reference =
            uk_reference(p.object_block_diagonal(), p.ee_block_diagonal(), p.r, p.omega, p.h_sigma);
        const Result spinning = FixedKernels<N>::block_diagonal(p);
        EXPECT_LT(relative_error(spinning.accelerations, reference.accelerations), tolerance);
        EXPECT_LT(relative_error(spinning.wrenches, reference.wrenches), tolerance);
    }
    std::printf("[ measured ] composite rigid body (parallel axis), N = %d: worst relative error %.3g\n", N, worst);
}

TEST(InteractionWrenchesGrasp, LibraryConstraintAndGraspMatricesMatchLiteralOnes)
{
    for (Index arms = 1; arms <= 6; ++arms) {
        Rng rng(static_cast<unsigned>(4000 + arms));
        const MatrixXd r = random_offsets(arms, rng);
        const Vector3d omega = random_vector(3, rng, -3.0, 3.0);
        EXPECT_EQ(MatrixXd(coopdyn::constraint_matrix(r)), literal_constraint_matrix(r));
        EXPECT_EQ(MatrixXd(coopdyn::grasp_matrix(r)), literal_grasp_matrix(r));
        EXPECT_LT(relative_error(VectorXd(coopdyn::constraint_bias(r, omega)), literal_constraint_bias(r, omega)),
                  1e-15);
    }
}

TEST(InteractionWrenchesFloat, FloatAgreesWithDouble)
{
    double worst = 0.0;
    for (unsigned seed = 0; seed < 20; ++seed) {
        Rng rng(5000u + seed);
        const Problem p = random_problem(2, rng);
        const Matrix6d object = p.object_general;
        // Fixed N = 2.
        const Eigen::Matrix<float, 6, 6> object_f = object.cast<float>();
        const Eigen::Matrix<float, 6, 12> ee_f = p.ee_general.cast<float>();
        const Eigen::Matrix<float, 3, 2> r_f = p.r.cast<float>();
        const Eigen::Vector3f omega_f = p.omega.cast<float>();
        const Eigen::Matrix<float, 18, 1> h_sigma_f = p.h_sigma.cast<float>();
        const Eigen::Matrix<float, 18, 1> h_f = coopdyn::interaction_wrenches(object_f, ee_f, r_f, omega_f, h_sigma_f);
        const VectorXd h = coopdyn::interaction_wrenches(object, p.ee_general, p.r, p.omega, p.h_sigma);
        const double general_error = relative_error(VectorXd(h_f.cast<double>()), h);

        // Block-diagonal, dynamic N.
        const Eigen::VectorXf masses_f = p.ee_masses.cast<float>();
        const Eigen::MatrixXf rotational_f = p.ee_rotational.cast<float>();
        const Eigen::Matrix3f object_rotational_f = p.object_rotational.cast<float>();
        const Eigen::VectorXf h_block_f = coopdyn::interaction_wrenches(
            coopdyn::CentralInertia<float>(static_cast<float>(p.object_mass), object_rotational_f),
            block_diagonal_inertias(masses_f, rotational_f), Eigen::MatrixXf(p.r.cast<float>()), omega_f,
            Eigen::VectorXf(p.h_sigma.cast<float>()));
        const VectorXd h_block =
            coopdyn::interaction_wrenches(coopdyn::CentralInertia<double>(p.object_mass, p.object_rotational),
                                          block_diagonal_inertias(p.ee_masses, p.ee_rotational), p.r, p.omega, p.h_sigma);
        const double block_error = relative_error(VectorXd(h_block_f.cast<double>()), h_block);

        EXPECT_LT(general_error, 1e-4) << "seed " << seed;
        EXPECT_LT(block_error, 1e-4) << "seed " << seed;
        worst = std::max({worst, general_error, block_error});
    }
    std::printf("[ measured ] float vs double: worst relative error %.3g\n", worst);
}

}  // namespace
