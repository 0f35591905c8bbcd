// Tests of coopdyn/analysis/internal_wrenches.hpp: internal and external end-effector wrenches,
// paper (53)-(54), docs/analysis.md with errata E5; plus the allocation-free "full tick"
// (coordination, load distribution, interaction dynamics, wrench decomposition).
//
// References, none of which the code under test was derived from (it uses the structured
// reduced-coordinate form of (53), docs/analysis.md):
// - the literal (53): M' = blkdiag(M_1..M_N), A' with 6(N-1) relative constraints (arm 1 against
//   arm i, derived in literal_relative_constraint from docs/model.md), b' from the
//   centripetal terms, h'_int = M'^(1/2) (A' M'^(-1/2))^+ (b' - A' M'^-1 h'^x) with the symmetric
//   square root (SelfAdjointEigenSolver) and a CompleteOrthogonalDecomposition pseudo-inverse;
// - the KKT system of the same constrained least-squares problem (Gauss's principle);
// - identities: G h'_int = 0, h'_int = 0 for rigid commanded motions, G h'_ext = G h';
// - physics: Theorem 1 (coordinated setpoints and the load distribution (26): no internal wrench,
//   the end-effectors carry exactly the load) and a two-arm squeeze with an analytic answer.
//
// The allocation detectors are those of tests/allocation_counter.hpp (counting global operator
// new; EIGEN_RUNTIME_NO_MALLOC with a redefined eigen_assert that aborts outside a counting
// window, so Eigen's own checks stay active for every other test here).

#include "../allocation_counter.hpp"

#include "coopdyn/analysis/internal_wrenches.hpp"
#include "coopdyn/coordination/kinematic_coordination.hpp"
#include "coopdyn/coordination/grasp_squeeze.hpp"
#include "coopdyn/coordination/load_distribution.hpp"
#include "coopdyn/dynamics/cooperative_dynamics.hpp"
#include "coopdyn/model/resolved_acceleration_end_effector.hpp"

#include "sample_systems.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>

#include <gtest/gtest.h>

#include <array>

#include <algorithm>
#include <vector>

// Every member of the class template compiles, for both inertia paths.
template struct coopdyn::WrenchDecomposition<coopdyn::Model<double, 2>>;
template struct coopdyn::WrenchDecomposition<
    coopdyn::Model<double, coopdyn::Dynamic, coopdyn::ResolvedAccelerationEndEffector>>;

namespace {

using namespace coopdyn_test;

// ---------------------------------------------------------------------------------------------
// Literal references (no coopdyn code).

/// The end-effector inertias of one random case: the 6 x 6N stack, and for block-diagonal
/// inertias diag(m_i I3, J_i) also the masses (N) and rotational blocks (3 x 3N).
struct EndEffectorInertias {
    MatrixXd stack;
    VectorXd masses;
    MatrixXd rotational;
    bool block_diagonal = false;
};

enum class InertiaKind { general, block_diagonal };

const char* name_of(InertiaKind kind) { return kind == InertiaKind::general ? "general SPD" : "diag(m I3, J)"; }

EndEffectorInertias random_end_effector_inertias(Index arms, InertiaKind kind, Rng& rng)
{
    EndEffectorInertias result;
    result.stack = MatrixXd::Zero(6, 6 * arms);
    result.masses = VectorXd::Zero(arms);
    result.rotational = MatrixXd::Zero(3, 3 * arms);
    result.block_diagonal = kind == InertiaKind::block_diagonal;
    for (Index i = 0; i < arms; ++i) {
        if (kind == InertiaKind::general) {
            result.stack.block(0, 6 * i, 6, 6) = random_spd(6, rng, uniform(rng, 0.5, 5.0));
        } else {
            result.masses(i) = uniform(rng, 1.0, 10.0);
            result.rotational.block(0, 3 * i, 3, 3) = random_spd(3, rng, uniform(rng, 0.05, 1.0));
            result.stack.block(0, 6 * i, 6, 6) =
                block_diagonal_inertia(result.masses(i), result.rotational.block(0, 3 * i, 3, 3));
        }
    }
    return result;
}

/// M' = blkdiag(M_1, ..., M_N) from the 6 x 6N stack.
MatrixXd assemble_end_effector_inertia(const MatrixXd& stack)
{
    const Index arms = stack.cols() / 6;
    MatrixXd result = MatrixXd::Zero(6 * arms, 6 * arms);
    for (Index i = 0; i < arms; ++i) {
        result.block(6 * i, 6 * i, 6, 6) = stack.block(0, 6 * i, 6, 6);
    }
    return result;
}

/// A' xdd' = b' of (53): 6(N-1) relative constraints (errata E5), arm 1 against arm i.
///
/// Derivation from docs/model.md: a common rigid acceleration a = [a_lin; alpha] of the
/// object's reference point gives xdd_i = G_i^T a + b_i, i.e.
///     wd_i  = alpha,
///     pdd_i = a_lin + alpha x r_i + w x (w x r_i).
/// Arm 1 fixes a_lin and alpha; eliminating them from arm i's rows leaves
///     wd_i - wd_1 = 0,
///     pdd_i - pdd_1 = alpha x (r_i - r_1) + S(w)^2 (r_i - r_1) = -S(r_i - r_1) wd_1 + S(w)^2 (r_i - r_1),
/// so block row i - 1 of A' is [[-I3, S(r_i - r_1)], [0, -I3]] in arm 1's columns and I6 in arm
/// i's, and b'_(i-1) = [S(w)^2 (r_i - r_1); 0]. The 6(N-1) rows are independent (the I6 blocks),
/// so the motions they allow form exactly the 6-dimensional family xdd_i = G_i^T a + b_i.
struct RelativeConstraint {
    MatrixXd matrix;
    VectorXd bias;
};

RelativeConstraint literal_relative_constraint(const MatrixXd& r, const Vector3d& omega)
{
    const Index arms = r.cols();
    RelativeConstraint result{MatrixXd::Zero(6 * (arms - 1), 6 * arms), VectorXd::Zero(6 * (arms - 1))};
    const Matrix3d s_omega = hat(omega);
    for (Index i = 1; i < arms; ++i) {
        const Vector3d relative = r.col(i) - r.col(0);
        const Index row = 6 * (i - 1);
        result.matrix.block(row, 0, 3, 3) = -Matrix3d::Identity();
        result.matrix.block(row, 3, 3, 3) = hat(relative);
        result.matrix.block(row + 3, 3, 3, 3) = -Matrix3d::Identity();
        result.matrix.block(row, 6 * i, 6, 6).setIdentity();
        result.bias.segment(row, 3) = s_omega * s_omega * relative;
    }
    return result;
}

/// h'_int = M'^(1/2) (A' M'^(-1/2))^+ (b' - A' M'^-1 h'^x), literally (53).
VectorXd literal_internal_wrenches(const MatrixXd& inertia, const RelativeConstraint& constraint,
                                   const VectorXd& h_motion)
{
    const Eigen::SelfAdjointEigenSolver<MatrixXd> eigen(inertia);
    const MatrixXd root = eigen.operatorSqrt();
    const MatrixXd inverse_root = eigen.operatorInverseSqrt();
    const Eigen::CompleteOrthogonalDecomposition<MatrixXd> decomposition(constraint.matrix * inverse_root);
    const VectorXd commanded = inertia.llt().solve(h_motion);  // xdd'^x = M'^-1 h'^x
    return root * decomposition.pseudoInverse() * (constraint.bias - constraint.matrix * commanded);
}

/// The same constrained least squares through its KKT system:
/// [[M', A'^T], [A', 0]] [xdd'; lambda] = [h'^x; b'],  h'_int = M' xdd' - h'^x.
VectorXd kkt_internal_wrenches(const MatrixXd& inertia, const RelativeConstraint& constraint, const VectorXd& h_motion)
{
    const Index n = inertia.rows();
    const Index m = constraint.matrix.rows();
    MatrixXd kkt = MatrixXd::Zero(n + m, n + m);
    kkt.topLeftCorner(n, n) = inertia;
    kkt.topRightCorner(n, m) = constraint.matrix.transpose();
    kkt.bottomLeftCorner(m, n) = constraint.matrix;
    VectorXd rhs(n + m);
    rhs << h_motion, constraint.bias;
    const VectorXd solution = kkt.fullPivLu().solve(rhs);
    return inertia * solution.head(n) - h_motion;
}

/// xdd_i = G_i^T a + b_i for every arm (the rigid motion with acceleration a), literally.
VectorXd literal_rigid_accelerations(const MatrixXd& r, const Vector3d& omega, const Vector6d& a)
{
    return literal_grasp_matrix(r).transpose() * a + literal_constraint_bias(r, omega);
}

Vector3d random_angular_velocity(Rng& rng)
{
    Vector3d omega;
    do {
        omega = random_vector(3, rng, -2.0, 2.0);
    } while (omega.norm() < 0.3);
    return omega;
}

// ---------------------------------------------------------------------------------------------
// A. The kernel against the literal (53) and the KKT system.

TEST(InternalWrenches, MatchLiteralEquation53AndKktForTwoToSixArms)
{
    double worst_literal = 0.0;
    double worst_kkt = 0.0;
    double worst_block_kernel = 0.0;
    double worst_reference_agreement = 0.0;
    double worst_constraint_check = 0.0;
    int cases = 0;
    for (const InertiaKind kind : {InertiaKind::general, InertiaKind::block_diagonal}) {
        for (Index arms = 2; arms <= 6; ++arms) {
            for (int trial = 0; trial < 20; ++trial) {
                Rng rng(static_cast<unsigned>(1000 * arms + 10 * trial + (kind == InertiaKind::general ? 0 : 5)));
                const EndEffectorInertias inertias = random_end_effector_inertias(arms, kind, rng);
                const MatrixXd r = random_offsets(arms, rng);
                const Vector3d omega = random_angular_velocity(rng);
                const VectorXd h_motion = random_vector(6 * arms, rng, -10.0, 10.0);

                const MatrixXd inertia = assemble_end_effector_inertia(inertias.stack);
                const RelativeConstraint constraint = literal_relative_constraint(r, omega);
                // The test's own A', b' admit exactly the rigid motions: A' (G^T a + b) = b'.
                const Vector6d a = random_vector(6, rng);
                const VectorXd rigid = literal_rigid_accelerations(r, omega, a);
                worst_constraint_check =
                    std::max(worst_constraint_check, relative_error(constraint.matrix * rigid, constraint.bias));

                const VectorXd literal = literal_internal_wrenches(inertia, constraint, h_motion);
                const VectorXd kkt = kkt_internal_wrenches(inertia, constraint, h_motion);
                const VectorXd kernel = coopdyn::internal_wrenches(inertias.stack, r, omega, h_motion);
                ASSERT_EQ(kernel.size(), 6 * arms);
                worst_reference_agreement = std::max(worst_reference_agreement, relative_error(kkt, literal));
                const double error_literal = relative_error(kernel, literal);
                const double error_kkt = relative_error(kernel, kkt);
                EXPECT_LT(error_literal, 1e-12) << name_of(kind) << ", N = " << arms << ", trial " << trial;
                EXPECT_LT(error_kkt, 1e-12) << name_of(kind) << ", N = " << arms << ", trial " << trial;
                worst_literal = std::max(worst_literal, error_literal);
                worst_kkt = std::max(worst_kkt, error_kkt);
                if (inertias.block_diagonal) {
                    std::vector<coopdyn::CentralInertia<double>> central;
                    for (Index i = 0; i < arms; ++i) {
                        central.emplace_back(inertias.masses(i), Matrix3d(inertias.rotational.block(0, 3 * i, 3, 3)));
                    }
                    const VectorXd block = coopdyn::internal_wrenches(central, r, omega, h_motion);
                    const double error_block = relative_error(block, literal);
                    EXPECT_LT(error_block, 1e-12) << "N = " << arms << ", trial " << trial;
                    worst_block_kernel = std::max(worst_block_kernel, error_block);
                }
                ++cases;
            }
        }
    }
    EXPECT_LT(worst_constraint_check, 1e-13);
    EXPECT_LT(worst_reference_agreement, 1e-12);
    std::printf("[internal (53)] %d cases, N = 2..6, general SPD and diag(m I3, J), |w| >= 0.3:\n"
                "  kernel vs literal M'^(1/2) (A' M'^(-1/2))^+ (b' - A' M'^-1 h'^x): worst relative error %.2e\n"
                "  kernel vs KKT solve:                                       worst relative error %.2e\n"
                "  block-diagonal kernel vs literal:                          worst relative error %.2e\n"
                "  literal vs KKT (the two references agree):                 worst relative error %.2e\n"
                "  test's A' on rigid motions, |A' xdd - b'| / |b'|:           worst %.2e\n",
                cases, worst_literal, worst_kkt, worst_block_kernel, worst_reference_agreement,
                worst_constraint_check);
}

TEST(InternalWrenches, FloatScalarMatchesDoubleLiteral)
{
    // Generic over Scalar: float inputs, compared with the double literal
    // (53) on the same (float-representable) numbers; float keeps about 7 digits.
    double worst = 0.0;
    for (Index arms = 2; arms <= 6; ++arms) {
        Rng rng(static_cast<unsigned>(3000 + arms));
        const EndEffectorInertias inertias = random_end_effector_inertias(arms, InertiaKind::general, rng);
        const Eigen::MatrixXf stack = inertias.stack.cast<float>();
        const Eigen::MatrixXf r = random_offsets(arms, rng).cast<float>();
        const Eigen::Vector3f omega = random_angular_velocity(rng).cast<float>();
        const Eigen::VectorXf h_motion = random_vector(6 * arms, rng, -10.0, 10.0).cast<float>();
        const Eigen::VectorXf internal = coopdyn::internal_wrenches(stack, r, omega, h_motion);
        const MatrixXd r_double = r.cast<double>();
        const VectorXd literal = literal_internal_wrenches(
            assemble_end_effector_inertia(stack.cast<double>()),
            literal_relative_constraint(r_double, omega.cast<double>()), h_motion.cast<double>());
        worst = std::max(worst, relative_error(VectorXd(internal.cast<double>()), literal));
    }
    std::printf("[internal float] N = 2..6: worst relative error vs double literal %.2e\n", worst);
    EXPECT_LT(worst, 1e-5);
}

TEST(InternalWrenches, SingleArmHasNoInternalWrench)
{
    // N = 1: no relative constraint (A' has 0 rows), the reduced system is unconstrained.
    Rng rng(7);
    const MatrixXd stack = random_spd(6, rng, 2.0);
    const MatrixXd r = random_offsets(1, rng);
    const Vector3d omega = random_angular_velocity(rng);
    const VectorXd h_motion = random_vector(6, rng, -10.0, 10.0);
    const VectorXd internal = coopdyn::internal_wrenches(stack, r, omega, h_motion);
    std::printf("[internal N = 1] |h_int| / |h^x| = %.2e\n", internal.norm() / h_motion.norm());
    EXPECT_LT(internal.norm(), 1e-13 * h_motion.norm());
}

// ---------------------------------------------------------------------------------------------
// B. Identities of the internal wrench (53) (Definition 1, docs/analysis.md).

TEST(InternalWrenches, PropertiesNullSpaceRigidMotionAndExternalPart)
{
    double worst_null_space = 0.0;
    double worst_rigid = 0.0;
    double worst_external = 0.0;
    double worst_sum = 0.0;
    for (const InertiaKind kind : {InertiaKind::general, InertiaKind::block_diagonal}) {
        for (Index arms = 2; arms <= 6; ++arms) {
            for (int trial = 0; trial < 10; ++trial) {
                Rng rng(static_cast<unsigned>(5000 + 100 * arms + 2 * trial + (kind == InertiaKind::general ? 0 : 1)));
                const EndEffectorInertias inertias = random_end_effector_inertias(arms, kind, rng);
                const MatrixXd r = random_offsets(arms, rng);
                const Vector3d omega = random_angular_velocity(rng);
                const MatrixXd grasp = literal_grasp_matrix(r);
                const MatrixXd inertia = assemble_end_effector_inertia(inertias.stack);

                // G h'_int = 0: the internal wrenches do no work on any rigid motion.
                const VectorXd h_motion = random_vector(6 * arms, rng, -10.0, 10.0);
                const VectorXd internal = coopdyn::internal_wrenches(inertias.stack, r, omega, h_motion);
                const double null_space = (grasp * internal).norm() / h_motion.norm();
                EXPECT_LT(null_space, 1e-12) << name_of(kind) << ", N = " << arms;
                worst_null_space = std::max(worst_null_space, null_space);

                // A rigid commanded motion xdd'^x = M'^-1 h'^x = G^T a + b needs no internal wrench.
                const Vector6d a = random_vector(6, rng, -5.0, 5.0);
                const VectorXd rigid_motion = inertia * literal_rigid_accelerations(r, omega, a);
                const VectorXd rigid_internal = coopdyn::internal_wrenches(inertias.stack, r, omega, rigid_motion);
                const double rigid = rigid_internal.norm() / rigid_motion.norm();
                EXPECT_LT(rigid, 1e-12) << name_of(kind) << ", N = " << arms;
                worst_rigid = std::max(worst_rigid, rigid);

                // G h'_ext = G h' for arbitrary h', and h'_int + h'_ext = h'.
                const VectorXd h_end_effectors = random_vector(6 * arms, rng, -20.0, 20.0);
                const VectorXd external =
                    coopdyn::external_wrenches(inertias.stack, r, omega, h_motion, h_end_effectors);
                const double external_error = relative_error(grasp * external, grasp * h_end_effectors);
                EXPECT_LT(external_error, 1e-12) << name_of(kind) << ", N = " << arms;
                worst_external = std::max(worst_external, external_error);
                const double sum_error = relative_error(internal + external, h_end_effectors);
                EXPECT_LT(sum_error, 1e-14);
                worst_sum = std::max(worst_sum, sum_error);
            }
        }
    }
    std::printf("[internal properties] N = 2..6, both inertia kinds, 100 cases:\n"
                "  |G h'_int| / |h'^x|                      worst %.2e\n"
                "  rigid command: |h'_int| / |h'^x|         worst %.2e\n"
                "  |G h'_ext - G h'| / |G h'|               worst %.2e\n"
                "  |h'_int + h'_ext - h'| / |h'|            worst %.2e\n",
                worst_null_space, worst_rigid, worst_external, worst_sum);
}

/// internal_wrenches with N fixed at compile time equals the dynamic-size call.
template <int Arms> double fixed_against_dynamic(unsigned seed)
{
    Rng rng(seed);
    const EndEffectorInertias inertias = random_end_effector_inertias(Arms, InertiaKind::general, rng);
    const MatrixXd r = random_offsets(Arms, rng);
    const Vector3d omega = random_angular_velocity(rng);
    const VectorXd h_motion = random_vector(6 * Arms, rng, -10.0, 10.0);

    const Eigen::Matrix<double, 6, 6 * Arms> stack_fixed = inertias.stack;
    const Eigen::Matrix<double, 3, Arms> r_fixed = r;
    const Eigen::Matrix<double, 6 * Arms, 1> h_motion_fixed = h_motion;
    const auto fixed = coopdyn::internal_wrenches(stack_fixed, r_fixed, omega, h_motion_fixed);
    static_assert(decltype(fixed)::RowsAtCompileTime == 6 * Arms, "N is deduced at compile time");
    // N fixed by r alone: still a fixed-size result.
    const auto mixed = coopdyn::internal_wrenches(inertias.stack, r_fixed, omega, h_motion);
    static_assert(decltype(mixed)::RowsAtCompileTime == 6 * Arms, "N is deduced from r");
    const VectorXd dynamic = coopdyn::internal_wrenches(inertias.stack, r, omega, h_motion);
    return std::max(relative_error(fixed, dynamic), relative_error(mixed, dynamic));
}

TEST(InternalWrenches, FixedSizeEqualsDynamicSize)
{
    const double worst = std::max({fixed_against_dynamic<2>(61), fixed_against_dynamic<3>(62),
                                   fixed_against_dynamic<4>(63), fixed_against_dynamic<5>(64),
                                   fixed_against_dynamic<6>(65)});
    std::printf("[internal fixed vs dynamic N] N = 2..6: worst relative difference %.2e\n", worst);
    // The same arithmetic on the same numbers: at most a few rounding differences.
    EXPECT_LE(worst, 4.0 * Eigen::NumTraits<double>::epsilon());
}

// ---------------------------------------------------------------------------------------------
// C. Model/Data form: decompose_wrenches after interaction_dynamics.

/// Random models (sample_systems.hpp): impedance gains d_i 50..200, delta_i 5..20, k_i 100..500,
/// kappa_i 10..80; resolved-acceleration gains D_i = 20 I6 + U, K_i = 100 I6 + 5 U (U entries in
/// [-1, 1]).
SampleRanges decomposition_ranges()
{
    SampleRanges ranges;
    ranges.impedance.translational_damping = {50.0, 200.0};
    ranges.impedance.rotational_damping = {5.0, 20.0};
    ranges.impedance.translational_stiffness = {100.0, 500.0};
    ranges.impedance.rotational_stiffness = {10.0, 80.0};
    return ranges;
}

/// random_state with an angular velocity of at least 0.3 rad/s.
coopdyn::RigidBodyState<double> random_spinning_state(Rng& rng)
{
    coopdyn::RigidBodyState<double> state;
    state.pose.position = random_vector(3, rng);
    state.pose.orientation = random_unit_quaternion(rng);
    state.twist.head<3>() = random_vector(3, rng);
    state.twist.tail<3>() = random_angular_velocity(rng);
    return state;
}

template <typename ModelType> void expect_decomposition_matches_kernel_and_literal(Index arms, unsigned seed)
{
    constexpr int Arms = ModelType::arms_at_compile_time;
    const ModelType model = random_model<ModelType>(arms, seed, decomposition_ranges());
    coopdyn::Data<ModelType> data(model);
    coopdyn::WrenchDecomposition<ModelType> decomposition(model);
    Rng rng(seed + 1);
    double worst_kernel = 0.0;
    double worst_literal = 0.0;
    for (int trial = 0; trial < 5; ++trial) {
        const coopdyn::RigidBodyState<double> state = random_spinning_state(rng);
        // Setpoints that are not coordinated: generic (squeezing) motion wrenches.
        coopdyn::Setpoints<double, Arms> setpoints(arms);
        for (Index i = 0; i < arms; ++i) {
            setpoints.set_pose(i, coopdyn::Pose<double>{Vector3d(random_vector(3, rng)), random_unit_quaternion(rng)});
        }
        setpoints.twists = random_vector(6 * arms, rng);
        setpoints.accelerations = random_vector(6 * arms, rng);
        setpoints.wrenches = random_vector(6 * arms, rng, -5.0, 5.0);
        coopdyn::Disturbances<double, Arms> disturbances(arms);
        disturbances.object = random_vector(6, rng);
        disturbances.end_effectors = random_vector(6 * arms, rng);

        coopdyn::interaction_dynamics(model, data, state, setpoints, disturbances);
        const auto& result = coopdyn::decompose_wrenches(model, data, decomposition);
        ASSERT_EQ(&result, &decomposition);

        const Vector3d omega = state.twist.tail<3>();
        const MatrixXd r = data.grasp_offsets;
        const VectorXd h_motion = data.motion_wrenches;
        const MatrixXd stack = model.end_effector_inertias();
        // The general-path kernel on the same motion wrenches.
        const VectorXd kernel = coopdyn::internal_wrenches(stack, r, omega, h_motion);
        const double error_kernel = relative_error(decomposition.internal, kernel);
        EXPECT_LT(error_kernel, 1e-12) << "trial " << trial;
        worst_kernel = std::max(worst_kernel, error_kernel);
        // The literal (53).
        const VectorXd literal = literal_internal_wrenches(assemble_end_effector_inertia(stack),
                                                           literal_relative_constraint(r, omega), h_motion);
        const double error_literal = relative_error(decomposition.internal, literal);
        EXPECT_LT(error_literal, 1e-12) << "trial " << trial;
        worst_literal = std::max(worst_literal, error_literal);
        // (54), exactly as defined.
        const VectorXd h_end_effectors = data.end_effector_wrenches();
        EXPECT_EQ((decomposition.external - (h_end_effectors - decomposition.internal)).cwiseAbs().maxCoeff(), 0.0);
        // Per-arm views.
        ASSERT_EQ(decomposition.arms(), arms);
        for (Index i = 0; i < arms; ++i) {
            EXPECT_EQ(Vector6d(decomposition.internal_wrench(i)),
                      Vector6d(decomposition.internal.template segment<6>(6 * i)));
            EXPECT_EQ(Vector6d(decomposition.external_wrench(i)),
                      Vector6d(decomposition.external.template segment<6>(6 * i)));
        }
        EXPECT_GT(decomposition.internal.norm(), 1e-3 * h_motion.norm());  // a generic case squeezes
    }
    std::printf("[decompose_wrenches] %s, N = %ld%s: vs kernel worst %.2e, vs literal (53) worst %.2e\n",
                ModelType::EndEffectorModel::has_block_diagonal_inertia ? "impedance (block-diagonal path)"
                                                                        : "resolved acceleration (general Lambda)",
                static_cast<long>(arms), Arms == coopdyn::Dynamic ? " (dynamic)" : " (fixed)", worst_kernel,
                worst_literal);
}

TEST(DecomposeWrenches, ImpedanceEndEffectorsMatchKernelAndLiteral)
{
    expect_decomposition_matches_kernel_and_literal<coopdyn::Model<double, 2>>(2, 101);
    expect_decomposition_matches_kernel_and_literal<coopdyn::Model<double, coopdyn::Dynamic>>(3, 102);
    expect_decomposition_matches_kernel_and_literal<coopdyn::Model<double, coopdyn::Dynamic>>(6, 103);
}

TEST(DecomposeWrenches, ResolvedAccelerationEndEffectorsMatchKernelAndLiteral)
{
    using Fixed = coopdyn::Model<double, 2, coopdyn::ResolvedAccelerationEndEffector>;
    using Dynamic = coopdyn::Model<double, coopdyn::Dynamic, coopdyn::ResolvedAccelerationEndEffector>;
    expect_decomposition_matches_kernel_and_literal<Fixed>(2, 111);
    expect_decomposition_matches_kernel_and_literal<Dynamic>(3, 112);
    expect_decomposition_matches_kernel_and_literal<Dynamic>(5, 113);
}

/// Theorem 1: coordinated setpoints (27), the object at its desired state, and the desired
/// wrenches (26) of the tracking object wrench distributed with the end-effector inertias as
/// weights. Then the commanded motion is rigid (no internal wrench), the object follows the
/// desired acceleration, and the end-effector wrenches are exactly the distributed load.
template <typename ModelType> void expect_coordinated_motion_carries_load_without_squeezing(Index arms, unsigned seed)
{
    constexpr int Arms = ModelType::arms_at_compile_time;
    const ModelType model = random_model<ModelType>(arms, seed, decomposition_ranges());
    coopdyn::Data<ModelType> data(model);
    coopdyn::WrenchDecomposition<ModelType> decomposition(model);
    const coopdyn::LoadDistribution<ModelType> load(model);
    Rng rng(seed + 1);
    const coopdyn::RigidBodyState<double> desired = random_spinning_state(rng);
    const Vector6d desired_acceleration = random_vector(6, rng, -3.0, 3.0);

    coopdyn::Setpoints<double, Arms> setpoints(arms);
    coopdyn::coordinate_setpoints(model, desired, desired_acceleration, setpoints);
    const Vector6d object_wrench = coopdyn::tracking_object_wrench(model, desired, desired_acceleration);
    coopdyn::grasp_kinematics(model, data, desired);
    load.distribute(data, object_wrench, setpoints);
    const coopdyn::Disturbances<double, Arms> disturbances(arms);
    coopdyn::interaction_dynamics(model, data, desired, setpoints, disturbances);
    coopdyn::decompose_wrenches(model, data, decomposition);

    const VectorXd h_motion = data.motion_wrenches;
    const VectorXd h_end_effectors = data.end_effector_wrenches();
    const MatrixXd grasp = literal_grasp_matrix(data.grasp_offsets);
    const double internal = decomposition.internal.norm() / h_motion.norm();
    const double tracking = relative_error(data.object_acceleration(), desired_acceleration);
    const double load_match = relative_error(h_end_effectors, setpoints.wrenches);
    // The end-effectors carry the load: G h'_ext = -h_o^d (h_o = G hbar = -G h', (23)).
    const double load_carried = relative_error(Vector6d(-(grasp * decomposition.external)), object_wrench);
    // The wrench actually exchanged is non-squeezing: as a commanded wrench of the reduced system
    // at rest it would need no internal wrench (the distribution is M'-weighted, (25)-(26),
    // docs/coordination.md).
    const VectorXd squeeze_of_actual = coopdyn::internal_wrenches(model.end_effector_inertias(), data.grasp_offsets,
                                                                  Vector3d::Zero(), h_end_effectors);
    const double actual_internal = squeeze_of_actual.norm() / h_end_effectors.norm();
    std::printf("[coordinated, N = %ld] |h'_int|/|h'^x| = %.2e, |xdd_o - xdd_o^d| rel %.2e, |h' - h'^d| rel %.2e, "
                "|G h'_ext + h_o^d| rel %.2e, internal part of actual h' %.2e, |h_o^d| = %.3g N\n",
                static_cast<long>(arms), internal, tracking, load_match, load_carried, actual_internal,
                object_wrench.norm());
    EXPECT_LT(internal, 1e-12);
    EXPECT_LT(tracking, 1e-12);
    EXPECT_LT(load_match, 1e-12);
    EXPECT_LT(load_carried, 1e-12);
    EXPECT_LT(actual_internal, 1e-12);
    EXPECT_GT(object_wrench.head<3>().norm(), model.object().mass * 9.0);  // gravity is part of the load
}

TEST(DecomposeWrenches, CoordinatedSetpointsAndLoadDistributionGiveNoInternalWrench)
{
    expect_coordinated_motion_carries_load_without_squeezing<coopdyn::Model<double, 2>>(2, 201);
    expect_coordinated_motion_carries_load_without_squeezing<coopdyn::Model<double, coopdyn::Dynamic>>(3, 202);
    expect_coordinated_motion_carries_load_without_squeezing<coopdyn::Model<double, coopdyn::Dynamic>>(5, 203);
}

/// The same, with every setpoint pulled away from the grasp centroid by `pull` metres: the arms
/// squeeze (here: stretch) the object. The internal wrench is then nonzero, in the null space of
/// G, and still (53) literally.
template <typename ModelType> void expect_pulled_apart_setpoints_squeeze(Index arms, unsigned seed)
{
    constexpr int Arms = ModelType::arms_at_compile_time;
    const ModelType model = random_model<ModelType>(arms, seed, decomposition_ranges());
    coopdyn::Data<ModelType> data(model);
    coopdyn::WrenchDecomposition<ModelType> decomposition(model);
    const coopdyn::LoadDistribution<ModelType> load(model);
    Rng rng(seed + 1);
    const coopdyn::RigidBodyState<double> desired = random_spinning_state(rng);
    const Vector6d desired_acceleration = random_vector(6, rng, -3.0, 3.0);

    coopdyn::Setpoints<double, Arms> setpoints(arms);
    coopdyn::coordinate_setpoints(model, desired, desired_acceleration, setpoints);
    coopdyn::grasp_kinematics(model, data, desired);
    load.distribute(data, coopdyn::tracking_object_wrench(model, desired, desired_acceleration), setpoints);
    const double pull = 0.01;
    const Vector3d centroid = data.grasp_offsets.rowwise().mean();
    for (Index i = 0; i < arms; ++i) {
        const Vector3d outward = (data.grasp_offsets.col(i) - centroid).normalized();
        setpoints.positions.col(i) += pull * outward;
    }
    const coopdyn::Disturbances<double, Arms> disturbances(arms);
    coopdyn::interaction_dynamics(model, data, desired, setpoints, disturbances);
    coopdyn::decompose_wrenches(model, data, decomposition);

    const Vector3d omega = desired.twist.tail<3>();
    const MatrixXd grasp = literal_grasp_matrix(data.grasp_offsets);
    double smallest_stiffness = model.end_effector(0).translational_stiffness;
    for (Index i = 1; i < arms; ++i) {
        smallest_stiffness = std::min(smallest_stiffness, model.end_effector(i).translational_stiffness);
    }
    const VectorXd literal = literal_internal_wrenches(assemble_end_effector_inertia(model.end_effector_inertias()),
                                                       literal_relative_constraint(data.grasp_offsets, omega),
                                                       data.motion_wrenches);
    const double magnitude = decomposition.internal.norm();
    const double null_space = (grasp * decomposition.internal).norm() / magnitude;
    const double error_literal = relative_error(decomposition.internal, literal);
    std::printf("[pulled apart by %.0f mm, N = %ld] |h'_int| = %.3g N (pull x min k = %.3g N), |G h'_int|/|h'_int| = "
                "%.2e, vs literal (53) %.2e\n",
                1e3 * pull, static_cast<long>(arms), magnitude, pull * smallest_stiffness, null_space, error_literal);
    EXPECT_GT(magnitude, 0.1 * pull * smallest_stiffness);
    EXPECT_LT(null_space, 1e-12);
    EXPECT_LT(error_literal, 1e-12);
    EXPECT_LT(relative_error(Vector6d(grasp * decomposition.external), Vector6d(grasp * data.end_effector_wrenches())),
              1e-12);
}

TEST(DecomposeWrenches, PulledApartSetpointsSqueezeTheObject)
{
    expect_pulled_apart_setpoints_squeeze<coopdyn::Model<double, 2>>(2, 301);
    expect_pulled_apart_setpoints_squeeze<coopdyn::Model<double, coopdyn::Dynamic>>(3, 302);
    expect_pulled_apart_setpoints_squeeze<coopdyn::Model<double, coopdyn::Dynamic>>(4, 303);
}

TEST(DecomposeWrenches, TwoIdenticalArmsStretchingABeamAnalytic)
{
    // Two identical arms at r = (-+L, 0, 0), object at rest, setpoints pulled outward by s along
    // x. Then h_i^x = -k (p_i - p_i^d) = -+k s x, G h'^x = 0 (equal and opposite forces on one
    // line), so a_v = 0 and h'_int = -h'^x: the object pulls each arm back towards it with k s.
    using ModelType = coopdyn::Model<double, 2>;
    Rng rng(401);
    const double length = 0.4;
    const double stretch = 0.02;
    coopdyn::ImpedanceEndEffector<double> end_effector =
        random_end_effector<coopdyn::ImpedanceEndEffector<double>>(rng, decomposition_ranges());
    const coopdyn::RigidObject<double> object = section_five_beam(1e-4).object;
    std::vector<ModelType::ArmType> arms(2);
    arms[0].end_effector = end_effector;
    arms[0].grasp_body.position = Vector3d(-length, 0.0, 0.0);
    arms[1].end_effector = end_effector;
    arms[1].grasp_body.position = Vector3d(length, 0.0, 0.0);
    const ModelType model(object, arms);
    coopdyn::Data<ModelType> data(model);
    coopdyn::WrenchDecomposition<ModelType> decomposition(model);
    const coopdyn::LoadDistribution<ModelType> load(model);

    coopdyn::RigidBodyState<double> state;
    state.pose.position = Vector3d(0.1, -0.2, 0.5);
    coopdyn::Setpoints<double, 2> setpoints;
    coopdyn::coordinate_setpoints(model, state, Vector6d::Zero(), setpoints);
    coopdyn::grasp_kinematics(model, data, state);
    load.distribute(data, coopdyn::tracking_object_wrench(model, state, Vector6d::Zero()), setpoints);
    setpoints.positions.col(0) -= stretch * Vector3d::UnitX();
    setpoints.positions.col(1) += stretch * Vector3d::UnitX();
    coopdyn::interaction_dynamics(model, data, state, setpoints, coopdyn::Disturbances<double, 2>());
    coopdyn::decompose_wrenches(model, data, decomposition);

    Eigen::Matrix<double, 12, 1> expected = Eigen::Matrix<double, 12, 1>::Zero();
    expected(0) = end_effector.translational_stiffness * stretch;
    expected(6) = -end_effector.translational_stiffness * stretch;
    const double error = relative_error(decomposition.internal, expected);
    std::printf("[two-arm stretch] k s = %.4g N, internal force on arm 1 = %.6g N, relative error %.2e\n",
                expected(0), decomposition.internal(0), error);
    EXPECT_LT(error, 1e-13);
    // The external part alone holds the object against gravity: G h'_ext = -h_o^d = m_o g.
    const MatrixXd grasp = literal_grasp_matrix(data.grasp_offsets);
    Vector6d weight = Vector6d::Zero();
    weight.head<3>() = object.mass * model.gravity();
    EXPECT_LT(relative_error(Vector6d(grasp * decomposition.external), weight), 1e-12);
}

// ---------------------------------------------------------------------------------------------
// D. No allocation in the full per-tick path.

using allocation_counter::Allocations;
using allocation_counter::count_allocations;
using allocation_counter::sink;

TEST(NoAllocationSanity, DetectorsFire)
{
    const Allocations plain = count_allocations([] {
        void* pointer = ::operator new(64);
        sink = pointer;
        ::operator delete(pointer);
    });
    EXPECT_EQ(plain.operator_new, 1);

    const Allocations vector = count_allocations([] {
        std::vector<double> values(100, 1.0);
        sink = values.data();
    });
    EXPECT_GE(vector.operator_new, 1);

    const Allocations eigen = count_allocations([] {
        Eigen::VectorXd values = Eigen::VectorXd::Ones(100);
        sink = values.data();
    });
    EXPECT_GE(eigen.eigen, 1);

    // The dynamic-size kernel returns a freshly allocated VectorXd: the detector must see it.
    Rng rng(501);
    const MatrixXd stack = random_end_effector_inertias(3, InertiaKind::general, rng).stack;
    const MatrixXd r = random_offsets(3, rng);
    const Vector3d omega = random_angular_velocity(rng);
    const VectorXd h_motion = random_vector(18, rng);
    VectorXd internal;
    const Allocations kernel =
        count_allocations([&] { internal = coopdyn::internal_wrenches(stack, r, omega, h_motion); });
    EXPECT_GT(kernel.eigen, 0);
    std::printf("[allocation sanity] operator new %ld, std::vector %ld, VectorXd %ld, dynamic kernel %ld\n",
                plain.operator_new, vector.operator_new, eigen.eigen, kernel.eigen);
}

template <typename ModelType> void expect_full_tick_does_not_allocate(Index arms)
{
    constexpr int Arms = ModelType::arms_at_compile_time;
    // Construction may allocate (Model, Data, workspaces, inputs).
    const ModelType model = random_model<ModelType>(arms, 601, decomposition_ranges());
    coopdyn::Data<ModelType> data(model);
    coopdyn::WrenchDecomposition<ModelType> decomposition(model);
    const coopdyn::LoadDistribution<ModelType> load(model);
    coopdyn::Setpoints<double, Arms> setpoints(arms);
    coopdyn::Disturbances<double, Arms> disturbances(arms);
    Rng rng(602);
    const coopdyn::RigidBodyState<double> desired = random_spinning_state(rng);
    const Vector6d desired_acceleration = random_vector(6, rng);
    coopdyn::RigidBodyState<double> state = desired;
    state.pose.position += 0.01 * Vector3d(random_vector(3, rng));
    state.twist += 0.1 * Vector6d(random_vector(6, rng));
    disturbances.object = random_vector(6, rng);
    disturbances.end_effectors = random_vector(6 * arms, rng);
    coopdyn::EndEffectorVector<double, Arms> squeeze = coopdyn::EndEffectorVector<double, Arms>::Zero(6 * arms);

    const Allocations counts = count_allocations([&] {
        for (int tick = 0; tick < 10; ++tick) {
            coopdyn::grasp_kinematics(model, data, state);
            coopdyn::coordinate_setpoints(model, desired, desired_acceleration, setpoints);
            load.distribute(data, coopdyn::tracking_object_wrench(model, desired, desired_acceleration), setpoints);
            coopdyn::interaction_dynamics(model, data, state, setpoints, disturbances);
            coopdyn::decompose_wrenches(model, data, decomposition);
            coopdyn::squeeze_wrenches(load, data, squeeze);
        }
    });
    std::printf("[full tick, N = %ld%s] operator new calls %ld, Eigen heap allocations %ld\n", static_cast<long>(arms),
                Arms == coopdyn::Dynamic ? " dynamic" : " fixed", counts.operator_new, counts.eigen);
    EXPECT_EQ(counts.operator_new, 0);
    EXPECT_EQ(counts.eigen, 0);
    EXPECT_TRUE(decomposition.internal.allFinite());
    EXPECT_TRUE(decomposition.external.allFinite());
    EXPECT_GT(decomposition.internal.norm(), 0.0);  // the state is off the setpoints: squeezing
    EXPECT_GT(squeeze.norm(), 0.0);
}

TEST(NoAllocation, FullTickFixedTwoArms) { expect_full_tick_does_not_allocate<coopdyn::Model<double, 2>>(2); }

TEST(NoAllocation, FullTickDynamicThreeArms)
{
    expect_full_tick_does_not_allocate<coopdyn::Model<double, coopdyn::Dynamic>>(3);
}

template <typename ModelType> void expect_general_decomposition_does_not_allocate(Index arms)
{
    constexpr int Arms = ModelType::arms_at_compile_time;
    const ModelType model = random_model<ModelType>(arms, 701, decomposition_ranges());
    coopdyn::Data<ModelType> data(model);
    coopdyn::WrenchDecomposition<ModelType> decomposition(model);
    Rng rng(702);
    const coopdyn::RigidBodyState<double> state = random_spinning_state(rng);
    coopdyn::Setpoints<double, Arms> setpoints(arms);
    setpoints.positions = random_matrix(3, arms, rng);
    const coopdyn::Disturbances<double, Arms> disturbances(arms);
    const Allocations counts = count_allocations([&] {
        for (int tick = 0; tick < 10; ++tick) {
            coopdyn::interaction_dynamics(model, data, state, setpoints, disturbances);
            coopdyn::decompose_wrenches(model, data, decomposition);
        }
    });
    EXPECT_EQ(counts.operator_new, 0);
    EXPECT_EQ(counts.eigen, 0);
    EXPECT_GT(decomposition.internal.norm(), 0.0);
}

TEST(NoAllocation, DecomposeWrenchesGeneralInertiaPath)
{
    using Fixed = coopdyn::Model<double, 2, coopdyn::ResolvedAccelerationEndEffector>;
    expect_general_decomposition_does_not_allocate<Fixed>(2);
    expect_general_decomposition_does_not_allocate<
        coopdyn::Model<double, coopdyn::Dynamic, coopdyn::ResolvedAccelerationEndEffector>>(3);
}

TEST(NoAllocation, FixedSizeKernels)
{
    Rng rng(801);
    const EndEffectorInertias inertias = random_end_effector_inertias(2, InertiaKind::block_diagonal, rng);
    const Eigen::Matrix<double, 6, 12> stack = inertias.stack;
    const Eigen::Vector2d masses = inertias.masses;
    const Eigen::Matrix<double, 3, 6> rotational = inertias.rotational;
    const Eigen::Matrix<double, 3, 2> r = random_offsets(2, rng);
    const Vector3d omega = random_angular_velocity(rng);
    const Eigen::Matrix<double, 12, 1> h_motion = random_vector(12, rng);
    const Eigen::Matrix<double, 12, 1> h_end_effectors = random_vector(12, rng);
    Eigen::Matrix<double, 12, 1> internal = Eigen::Matrix<double, 12, 1>::Zero();
    Eigen::Matrix<double, 12, 1> block = Eigen::Matrix<double, 12, 1>::Zero();
    Eigen::Matrix<double, 12, 1> external = Eigen::Matrix<double, 12, 1>::Zero();
    const std::array<coopdyn::CentralInertia<double>, 2> central{
        coopdyn::CentralInertia<double>(masses(0), Matrix3d(rotational.block<3, 3>(0, 0))),
        coopdyn::CentralInertia<double>(masses(1), Matrix3d(rotational.block<3, 3>(0, 3)))};
    const Allocations counts = count_allocations([&] {
        internal = coopdyn::internal_wrenches(stack, r, omega, h_motion);
        block = coopdyn::internal_wrenches(central, r, omega, h_motion);
        external = coopdyn::external_wrenches(stack, r, omega, h_motion, h_end_effectors);
    });
    EXPECT_EQ(counts.operator_new, 0);
    EXPECT_EQ(counts.eigen, 0);
    EXPECT_LT(relative_error(block, internal), 1e-12);
    EXPECT_LT(relative_error(Eigen::Matrix<double, 12, 1>(internal + external), h_end_effectors), 1e-14);
}

}  // namespace
