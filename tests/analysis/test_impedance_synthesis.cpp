// Tests of coopdyn/analysis/impedance_synthesis.hpp: per-arm gains for a requested apparent object
// stiffness K and damping D (Theorem 2 read backwards, docs/analysis.md with errata E3), and
// classical damping.
//
// References, none of which the synthesis was derived from:
// - round trip through apparent_impedance (31)-(32), E3: targets produced from known random
//   positive gains on non-symmetric grasps must come back (gains and matrices);
// - the worked numbers of docs/analysis.md (two-arm examples, section V beam);
// - for unreachable targets, the optimality (Kuhn-Tucker) conditions of the non-negative least
//   squares fit, evaluated on the cone generators written out from the block formula of K
//   (E3, docs/analysis.md) in this file;
// - for classical damping, the generalized eigenproblem K v = w^2 M v (Eigen's
//   GeneralizedSelfAdjointEigenSolver), the commutator D M^-1 K - K M^-1 D, and the scalar
//   formula d = 2 zeta sqrt(m k) for diagonal M, K.

#include "coopdyn/analysis/impedance_synthesis.hpp"
#include "coopdyn/analysis/stability.hpp"
#include "coopdyn/dynamics/cooperative_dynamics.hpp"

#include "sample_systems.hpp"

#include <Eigen/Eigenvalues>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

// Every member of the class template compiles.
template struct coopdyn::SynthesisResult<double>;

namespace {

using namespace coopdyn_test;
using ModelX = coopdyn::Model<double, coopdyn::Dynamic>;
using Model2 = coopdyn::Model<double, 2>;

// ---------------------------------------------------------------------------------------------
// Literal references.

/// T(r) = [[I3, S(r)^T], [S(r), S(r) S(r)^T]]: one arm's unit translational gain at the object
/// (block formula of K, errata E3, docs/analysis.md).
Matrix6d literal_translational_generator(const Vector3d& r)
{
    const Matrix3d s = hat(r);
    Matrix6d result;
    result << Matrix3d::Identity(), s.transpose(), s, s * s.transpose();
    return result;
}

/// R = diag(0, I3): a unit rotational gain at the object.
Matrix6d literal_rotational_generator()
{
    Matrix6d result = Matrix6d::Zero();
    result.bottomRightCorner<3, 3>().setIdentity();
    return result;
}

/// K = sum_i k_i T(r_i) + (sum_i kappa_i) R (docs/analysis.md, E3), for any signs of the gains.
Matrix6d literal_object_matrix(const MatrixXd& r, const VectorXd& translational, double total_rotational)
{
    Matrix6d result = total_rotational * literal_rotational_generator();
    for (Index i = 0; i < r.cols(); ++i) {
        result += translational(i) * literal_translational_generator(r.col(i));
    }
    return result;
}

/// Frobenius inner product <A, B> = trace(A^T B).
double frobenius(const Matrix6d& a, const Matrix6d& b) { return (a.array() * b.array()).sum(); }

/// Kuhn-Tucker conditions of min ||K(g) - sym(target)||_F over g >= 0, scaled to be
/// dimensionless: with residual E = sym(target) - K(g) and generator X_j (unit Frobenius norm),
/// <X_j, E> <= 0 for every gain, and = 0 where the gain is positive. Returns the worst violation
/// relative to ||target||.
double optimality_violation(const MatrixXd& r, const coopdyn::SynthesisResult<double>& result, const Matrix6d& target)
{
    const Matrix6d residual = 0.5 * (target + target.transpose()) - result.achieved;
    double worst = 0.0;
    const auto check = [&](const Matrix6d& generator, double gain) {
        const double gradient = frobenius(generator / generator.norm(), residual) / target.norm();
        worst = std::max(worst, gain > 0.0 ? std::abs(gradient) : std::max(gradient, 0.0));
    };
    for (Index i = 0; i < r.cols(); ++i) {
        check(literal_translational_generator(r.col(i)), result.translational(i));
    }
    check(literal_rotational_generator(), result.total_rotational);
    return worst;
}

// ---------------------------------------------------------------------------------------------
// Random models with known positive gains: random_model and random_state of sample_systems.hpp
// (default ranges).

struct RoundTrip {
    double stiffness = 0.0;  // |K(synthesized) - K_target| / |K_target| through apparent_impedance
    double damping = 0.0;
    double inertia = 0.0;
    double residual = 0.0;   // reported relative residuals, worst of K and D
    double gains = 0.0;      // recovered per-arm translational and summed rotational gains
};

template <typename ModelType> RoundTrip round_trip(Index arms, unsigned seed)
{
    const ModelType model = random_model<ModelType>(arms, seed);
    Rng rng(seed + 7);
    const coopdyn::RigidBodyState<double> state = random_state(rng);
    coopdyn::Data<ModelType> data(model);
    coopdyn::grasp_kinematics(model, data, state);
    const coopdyn::ApparentImpedance<double> target = coopdyn::apparent_impedance(model, data);

    const coopdyn::SynthesisResult<double> stiffness = coopdyn::synthesize_stiffness(model, data, target.stiffness);
    const coopdyn::SynthesisResult<double> damping = coopdyn::synthesize_damping(model, data, target.damping);
    EXPECT_TRUE(stiffness.achievable) << "N = " << arms << ", residual " << stiffness.relative_residual;
    EXPECT_TRUE(damping.achievable) << "N = " << arms << ", residual " << damping.relative_residual;
    EXPECT_TRUE((stiffness.translational.array() >= 0.0).all() && (stiffness.rotational.array() >= 0.0).all());
    EXPECT_TRUE((damping.translational.array() >= 0.0).all() && (damping.rotational.array() >= 0.0).all());

    // Feed the gains back through apparent_impedance at the same configuration.
    const ModelType synthesized = coopdyn::with_damping(coopdyn::with_stiffness(model, stiffness), damping);
    coopdyn::Data<ModelType> synthesized_data(synthesized);
    coopdyn::grasp_kinematics(synthesized, synthesized_data, state);
    const coopdyn::ApparentImpedance<double> achieved = coopdyn::apparent_impedance(synthesized, synthesized_data);

    RoundTrip result;
    result.stiffness = relative_error(achieved.stiffness, target.stiffness);
    result.damping = relative_error(achieved.damping, target.damping);
    result.inertia = relative_error(achieved.inertia, target.inertia);
    result.residual = std::max(stiffness.relative_residual, damping.relative_residual);
    // The map from (k_1..k_N, sum kappa) to K is injective for N <= 6 generic grasps (N + 1
    // unknowns against the 10 independent numbers sum k, sum k r, sum k S S^T), so the gains
    // themselves must come back; only the split of the rotational sum is free.
    double true_rotational_stiffness = 0.0;
    double true_rotational_damping = 0.0;
    VectorXd true_stiffness(arms);
    VectorXd true_damping(arms);
    for (Index i = 0; i < arms; ++i) {
        true_stiffness(i) = model.end_effector(i).translational_stiffness;
        true_damping(i) = model.end_effector(i).translational_damping;
        true_rotational_stiffness += model.end_effector(i).rotational_stiffness;
        true_rotational_damping += model.end_effector(i).rotational_damping;
    }
    result.gains = std::max({relative_error(stiffness.translational, true_stiffness),
                             relative_error(damping.translational, true_damping),
                             std::abs(stiffness.total_rotational / true_rotational_stiffness - 1.0),
                             std::abs(damping.total_rotational / true_rotational_damping - 1.0),
                             std::abs(stiffness.rotational.sum() / true_rotational_stiffness - 1.0)});
    return result;
}

// ---------------------------------------------------------------------------------------------
// E. Synthesis round trip.

TEST(ImpedanceSynthesis, GainsReproduceRequestedStiffnessAndDampingThroughApparentImpedance)
{
    RoundTrip worst;
    int cases = 0;
    const auto record = [&](const RoundTrip& trip) {
        worst.stiffness = std::max(worst.stiffness, trip.stiffness);
        worst.damping = std::max(worst.damping, trip.damping);
        worst.inertia = std::max(worst.inertia, trip.inertia);
        worst.residual = std::max(worst.residual, trip.residual);
        worst.gains = std::max(worst.gains, trip.gains);
        ++cases;
    };
    for (Index arms = 2; arms <= 6; ++arms) {
        for (unsigned trial = 0; trial < 8; ++trial) {
            record(round_trip<ModelX>(arms, static_cast<unsigned>(100 * arms) + trial));
        }
    }
    for (unsigned trial = 0; trial < 4; ++trial) {
        record(round_trip<Model2>(2, 900 + trial));  // fixed N: with_stiffness builds a Model<double, 2>
    }
    std::printf("[synthesis round trip] %d cases, N = 2..6, non-symmetric grasps:\n"
                "  K: |K(gains) - K_target| / |K_target| via apparent_impedance  worst %.2e\n"
                "  D: |D(gains) - D_target| / |D_target|                          worst %.2e\n"
                "  M unchanged                                                     worst %.2e\n"
                "  reported relative residual                                      worst %.2e\n"
                "  recovered gains (k_i, d_i, sums of kappa_i, delta_i)             worst relative %.2e\n",
                cases, worst.stiffness, worst.damping, worst.inertia, worst.residual, worst.gains);
    EXPECT_LT(worst.stiffness, 1e-10);
    EXPECT_LT(worst.damping, 1e-10);
    EXPECT_EQ(worst.inertia, 0.0);
    EXPECT_LT(worst.residual, 1e-10);
    EXPECT_LT(worst.gains, 1e-9);
}

TEST(ImpedanceSynthesis, WorkedNumbersOfTheModelPage)
{
    // Example after Theorem 2: k_i = kappa_i = 100, r_1,2 = (+-1, 0, 0): translational 200
    // isotropic, rotational (200, 400, 400).
    MatrixXd r(3, 2);
    r << 1.0, -1.0, 0.0, 0.0, 0.0, 0.0;
    Vector6d diagonal;
    diagonal << 200.0, 200.0, 200.0, 200.0, 400.0, 400.0;
    const coopdyn::SynthesisResult<double> example = coopdyn::synthesize_gains(r, Matrix6d(diagonal.asDiagonal()));
    EXPECT_TRUE(example.achievable);
    EXPECT_LT(relative_error(example.translational, Eigen::Vector2d(100.0, 100.0)), 1e-13);
    EXPECT_LT(relative_error(example.rotational, Eigen::Vector2d(100.0, 100.0)), 1e-13);

    // Section V beam: r_1,2 = (0, -+0.4, 0), K = diag(600 I3, 196, 100, 196) from k_i = 300,
    // kappa_i = 50; D = diag(360 I3, 77.6, 20, 77.6) from d_i = 180, delta_i = 10 ((59), (61)).
    BeamParameters beam = section_five_beam();
    for (ArmParameters& arm : beam.arms) {
        arm.damping = 1.0;  // deliberately wrong: the synthesis must find 180 / 10
        arm.rotational_damping = 1.0;
        arm.stiffness = 1.0;  // ... and 300 / 50
        arm.rotational_stiffness = 1.0;
    }
    const Model2 model = make_model<Model2>(beam.object, beam.arms);
    coopdyn::Data<Model2> data(model);
    coopdyn::grasp_kinematics(model, data, coopdyn::RigidBodyState<double>{});
    Vector6d stiffness_diagonal;
    stiffness_diagonal << 600.0, 600.0, 600.0, 196.0, 100.0, 196.0;
    Vector6d damping_diagonal;
    damping_diagonal << 360.0, 360.0, 360.0, 77.6, 20.0, 77.6;
    const auto stiffness = coopdyn::synthesize_stiffness(model, data, Matrix6d(stiffness_diagonal.asDiagonal()));
    const auto damping = coopdyn::synthesize_damping(model, data, Matrix6d(damping_diagonal.asDiagonal()));
    std::printf("[beam synthesis] k = (%.12g, %.12g), kappa = (%.12g, %.12g), d = (%.12g, %.12g), "
                "delta = (%.12g, %.12g), residuals %.2e, %.2e\n",
                stiffness.translational(0), stiffness.translational(1), stiffness.rotational(0),
                stiffness.rotational(1), damping.translational(0), damping.translational(1), damping.rotational(0),
                damping.rotational(1), stiffness.relative_residual, damping.relative_residual);
    EXPECT_TRUE(stiffness.achievable);
    EXPECT_TRUE(damping.achievable);
    EXPECT_LT(relative_error(stiffness.translational, Eigen::Vector2d(300.0, 300.0)), 1e-13);
    EXPECT_LT(relative_error(stiffness.rotational, Eigen::Vector2d(50.0, 50.0)), 1e-13);
    EXPECT_LT(relative_error(damping.translational, Eigen::Vector2d(180.0, 180.0)), 1e-13);
    EXPECT_LT(relative_error(damping.rotational, Eigen::Vector2d(10.0, 10.0)), 1e-13);
    // The synthesized model reproduces (56), (59), (61).
    const Model2 tuned = coopdyn::with_damping(coopdyn::with_stiffness(model, stiffness), damping);
    coopdyn::Data<Model2> tuned_data(tuned);
    coopdyn::grasp_kinematics(tuned, tuned_data, coopdyn::RigidBodyState<double>{});
    const auto impedance = coopdyn::apparent_impedance(tuned, tuned_data);
    Vector6d inertia_diagonal;
    inertia_diagonal << 21.75, 21.75, 21.75, 4.255, 1.0, 4.255;
    EXPECT_LT(relative_error(impedance.inertia, Matrix6d(inertia_diagonal.asDiagonal())), 1e-14);
    EXPECT_LT(relative_error(impedance.stiffness, Matrix6d(stiffness_diagonal.asDiagonal())), 1e-13);
    EXPECT_LT(relative_error(impedance.damping, Matrix6d(damping_diagonal.asDiagonal())), 1e-13);
}

TEST(ImpedanceSynthesis, ResultDoesNotDependOnUnits)
{
    // The same request in other units (scaled by 1e-16 .. 1e12) gives the same gains, scaled.
    const ModelX model = random_model<ModelX>(3, 31);
    coopdyn::Data<ModelX> data(model);
    Rng rng(32);
    coopdyn::grasp_kinematics(model, data, random_state(rng));
    const Matrix6d target = coopdyn::apparent_impedance(model, data).stiffness;
    const auto reference = coopdyn::synthesize_stiffness(model, data, target);
    ASSERT_TRUE(reference.achievable);
    double worst = 0.0;
    for (const double scale : {1e-16, 1e-8, 1e6, 1e12}) {
        const auto scaled = coopdyn::synthesize_stiffness(model, data, Matrix6d(scale * target));
        EXPECT_TRUE(scaled.achievable) << "scale " << scale << ": residual " << scaled.relative_residual;
        const double error = std::max(relative_error(VectorXd(scaled.translational / scale), reference.translational),
                                      std::abs(scaled.total_rotational / scale - reference.total_rotational) /
                                          reference.total_rotational);
        EXPECT_LT(error, 1e-12) << "scale " << scale;
        worst = std::max(worst, error);
    }
    std::printf("[synthesis units] targets scaled 1e-16..1e12: worst relative gain difference %.2e\n", worst);
}

// ---------------------------------------------------------------------------------------------
// Impossible requests: reported, with the residual, never approximated silently.

struct Verdict {
    bool achievable;
    double residual;
};

/// Synthesize `target` on `r`, check the verdict is "not achievable" and that what is reported is
/// true: the residual of the returned gains (recomputed literally and through apparent_impedance
/// of a model with those gains), non-negative gains, optimality of the fit; applying the result
/// through with_stiffness is refused.
Verdict expect_unachievable(const ModelX& model, const coopdyn::Data<ModelX>& data, const Matrix6d& target,
                            const char* what)
{
    const auto result = coopdyn::synthesize_stiffness(model, data, target);
    const MatrixXd r = data.grasp_offsets;
    EXPECT_FALSE(result.achievable) << what;
    EXPECT_GT(result.relative_residual, result.tolerance) << what;
    EXPECT_TRUE((result.translational.array() >= 0.0).all() && result.total_rotational >= 0.0) << what;
    // The residual is what the returned gains really give.
    const Matrix6d literal = literal_object_matrix(r, result.translational, result.total_rotational);
    // (Errors relative to the target: the achieved matrix may be zero.)
    EXPECT_LT((result.achieved - literal).norm() / target.norm(), 1e-14) << what;
    EXPECT_NEAR(result.relative_residual, (literal - target).norm() / target.norm(), 1e-14) << what;
    const ModelX applied(model.object(), coopdyn::arms_with_stiffness(model, result));
    coopdyn::Data<ModelX> applied_data(applied);
    coopdyn::grasp_kinematics(applied, applied_data, data.object_state);
    EXPECT_LT((coopdyn::apparent_impedance(applied, applied_data).stiffness - literal).norm() / target.norm(), 1e-13)
        << what;
    // And the gains are the closest non-negative ones (Kuhn-Tucker conditions).
    const double violation = optimality_violation(r, result, target);
    EXPECT_LT(violation, 1e-12) << what;
    EXPECT_THROW(coopdyn::with_stiffness(model, result), coopdyn::InvalidArgument) << what;
    std::printf("[unachievable: %s] achievable = %d, relative residual %.3e, KKT violation %.1e\n", what,
                result.achievable ? 1 : 0, result.relative_residual, violation);
    return {result.achievable, result.relative_residual};
}

TEST(ImpedanceSynthesis, ImpossibleRequestsAreReportedWithTheirResidual)
{
    const Index arms = 3;
    const ModelX model = random_model<ModelX>(arms, 41);
    coopdyn::Data<ModelX> data(model);
    Rng rng(42);
    coopdyn::grasp_kinematics(model, data, random_state(rng));
    const Matrix6d reachable = coopdyn::apparent_impedance(model, data).stiffness;
    const double scale = reachable.norm();

    // 1. Symmetric translation/rotation coupling (K_tr = c I3): every reachable coupling block is
    //    the skew matrix S(sum k_i r_i)^T. The target is still symmetric positive definite.
    Matrix6d coupled = reachable;
    coupled.topRightCorner<3, 3>() += 0.05 * scale * Matrix3d::Identity();
    coupled.bottomLeftCorner<3, 3>() += 0.05 * scale * Matrix3d::Identity();
    ASSERT_GT(Eigen::SelfAdjointEigenSolver<Matrix6d>(coupled).eigenvalues().minCoeff(), 0.0);
    expect_unachievable(model, data, coupled, "symmetric coupling");

    // 2. Anisotropic translational stiffness: the translational block is always (sum k_i) I3.
    Matrix6d anisotropic = reachable;
    anisotropic.topLeftCorner<3, 3>() += Eigen::Vector3d(0.0, 0.1, 0.3).asDiagonal() * reachable(0, 0);
    expect_unachievable(model, data, anisotropic, "anisotropic translation");

    // 3. Non-symmetric target: the skew part can never be produced; the residual is at least it.
    Matrix6d skew_part = random_matrix(6, 6, rng);
    skew_part = 0.5 * (skew_part - skew_part.transpose()).eval();
    skew_part *= 1e-3 * scale / skew_part.norm();
    const Verdict asymmetric = expect_unachievable(model, data, Matrix6d(reachable + skew_part), "non-symmetric");
    EXPECT_GE(asymmetric.residual, (1.0 - 1e-12) * skew_part.norm() / (reachable + skew_part).norm());

    // 4. Negative definite target: no non-negative gains give anything better than zero.
    const auto negative = coopdyn::synthesize_stiffness(model, data, Matrix6d(-reachable));
    expect_unachievable(model, data, Matrix6d(-reachable), "negative definite");
    EXPECT_EQ(negative.translational.cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ(negative.total_rotational, 0.0);
    EXPECT_NEAR(negative.relative_residual, 1.0, 1e-15);

    // 5. Symmetric, and of the reachable structure, but only with a negative gain: k_1 < 0.
    const MatrixXd r = data.grasp_offsets;
    VectorXd signed_gains(arms);
    signed_gains << -60.0, 400.0, 500.0;
    const Matrix6d needs_negative = literal_object_matrix(r, signed_gains, 90.0);
    ASSERT_GT(Eigen::SelfAdjointEigenSolver<Matrix6d>(needs_negative).eigenvalues().minCoeff(), 0.0)
        << "still a positive definite stiffness";
    expect_unachievable(model, data, needs_negative, "needs a negative gain");

    // The same target made reachable (all gains positive) is achievable to rounding: the verdicts
    // above are about the targets, not about the solver.
    signed_gains(0) = 60.0;
    const auto positive = coopdyn::synthesize_gains(r, literal_object_matrix(r, signed_gains, 90.0));
    EXPECT_TRUE(positive.achievable);
    EXPECT_LT(relative_error(positive.translational, signed_gains), 1e-10);
}

TEST(ImpedanceSynthesis, InvalidInputsThrow)
{
    const ModelX model = random_model<ModelX>(3, 51);
    coopdyn::Data<ModelX> data(model);
    coopdyn::grasp_kinematics(model, data, coopdyn::RigidBodyState<double>{});
    Matrix6d not_finite = Matrix6d::Identity();
    not_finite(2, 3) = std::nan("");
    EXPECT_THROW(coopdyn::synthesize_stiffness(model, data, not_finite), coopdyn::InvalidArgument);
    EXPECT_THROW(coopdyn::synthesize_gains(MatrixXd::Zero(2, 3), Matrix6d::Identity()), coopdyn::InvalidArgument);
    EXPECT_THROW(coopdyn::synthesize_gains(MatrixXd::Zero(3, 2), Matrix6d::Identity(), 0.0), coopdyn::InvalidArgument);
    // Gains for another number of arms are refused.
    const ModelX other = random_model<ModelX>(2, 52);
    coopdyn::Data<ModelX> other_data(other);
    coopdyn::grasp_kinematics(other, other_data, coopdyn::RigidBodyState<double>{});
    const Matrix6d other_target = coopdyn::apparent_impedance(other, other_data).stiffness;
    const auto two_arm = coopdyn::synthesize_stiffness(other, other_data, other_target);
    ASSERT_TRUE(two_arm.achievable);
    EXPECT_THROW(coopdyn::with_stiffness(model, two_arm), coopdyn::InvalidArgument);
}

// ---------------------------------------------------------------------------------------------
// Classical damping.

struct ModalCheck {
    double ratio = 0.0;        // max_k |v_k^T D v_k / (2 w_k) - zeta| / max(zeta, 1)
    double decoupling = 0.0;   // max_{j != k} |v_j^T D v_k| / max_k |v_k^T D v_k|
    double commutator = 0.0;   // |D M^-1 K - K M^-1 D| / |D M^-1 K|
    double library_modes = 0.0;  // coopdyn::modes damping ratios against zeta
};

ModalCheck check_classical(const Matrix6d& inertia, const Matrix6d& stiffness, double zeta)
{
    const Matrix6d damping = coopdyn::classical_damping(inertia, stiffness, zeta);
    const Eigen::GeneralizedSelfAdjointEigenSolver<Matrix6d> modes(stiffness, inertia);  // K v = w^2 M v, v^T M v = 1
    const Matrix6d shapes = modes.eigenvectors();
    const Matrix6d modal_damping = shapes.transpose() * damping * shapes;
    ModalCheck result;
    double largest = 0.0;
    for (Index k = 0; k < 6; ++k) {
        const double frequency = std::sqrt(modes.eigenvalues()(k));
        const double ratio = modal_damping(k, k) / (2.0 * frequency);
        result.ratio = std::max(result.ratio, std::abs(ratio - zeta) / std::max(zeta, 1.0));
        largest = std::max(largest, std::abs(modal_damping(k, k)));
    }
    for (Index j = 0; j < 6; ++j) {
        for (Index k = 0; k < 6; ++k) {
            if (j != k) {
                result.decoupling = std::max(result.decoupling, std::abs(modal_damping(j, k)) / largest);
            }
        }
    }
    const Matrix6d left = damping * inertia.inverse() * stiffness;
    const Matrix6d right = stiffness * inertia.inverse() * damping;
    result.commutator = (left - right).norm() / left.norm();
    coopdyn::ApparentImpedance<double> impedance;
    impedance.inertia = inertia;
    impedance.stiffness = stiffness;
    impedance.damping = damping;
    const auto library = coopdyn::modes(impedance);
    for (Index k = 0; k < 6; ++k) {
        result.library_modes =
            std::max(result.library_modes, std::abs(library.damping_ratios(k) - zeta) / std::max(zeta, 1.0));
    }
    return result;
}

TEST(ClassicalDamping, EveryModeGetsTheRequestedDampingRatio)
{
    ModalCheck worst;
    int cases = 0;
    const auto record = [&](const ModalCheck& check) {
        worst.ratio = std::max(worst.ratio, check.ratio);
        worst.decoupling = std::max(worst.decoupling, check.decoupling);
        worst.commutator = std::max(worst.commutator, check.commutator);
        worst.library_modes = std::max(worst.library_modes, check.library_modes);
        ++cases;
    };
    for (unsigned seed = 0; seed < 10; ++seed) {
        Rng rng(600 + seed);
        // General fully coupled SPD M and K.
        const Matrix6d inertia = random_spd(6, rng, uniform(rng, 0.5, 20.0));
        const Matrix6d stiffness = random_spd(6, rng, uniform(rng, 10.0, 1000.0));
        // The apparent impedance of a random non-symmetric grasp (coupled M and K, E3/E4).
        const ModelX model = random_model<ModelX>(2 + static_cast<Index>(seed % 5), 700 + seed);
        coopdyn::Data<ModelX> data(model);
        coopdyn::grasp_kinematics(model, data, random_state(rng));
        const auto impedance = coopdyn::apparent_impedance(model, data);
        for (const double zeta : {0.05, 0.7, 1.0, 2.5}) {
            record(check_classical(inertia, stiffness, zeta));
            record(check_classical(impedance.inertia, impedance.stiffness, zeta));
            const Matrix6d from_impedance = coopdyn::classical_damping(impedance, zeta);
            EXPECT_EQ((from_impedance - coopdyn::classical_damping(impedance.inertia, impedance.stiffness, zeta))
                          .cwiseAbs()
                          .maxCoeff(),
                      0.0);
        }
    }
    std::printf("[classical damping] %d cases (random SPD and apparent M, K; zeta 0.05..2.5):\n"
                "  |v^T D v / (2 w) - zeta|          worst %.2e\n"
                "  modal off-diagonal |v_j^T D v_k|  worst relative %.2e\n"
                "  |D M^-1 K - K M^-1 D| / |D M^-1 K| worst %.2e\n"
                "  coopdyn::modes ratios vs zeta     worst %.2e\n",
                cases, worst.ratio, worst.decoupling, worst.commutator, worst.library_modes);
    EXPECT_LT(worst.ratio, 1e-11);
    EXPECT_LT(worst.decoupling, 1e-11);
    EXPECT_LT(worst.commutator, 1e-11);
    EXPECT_LT(worst.library_modes, 1e-11);
}

TEST(ClassicalDamping, DiagonalSystemsAndEdgeCases)
{
    // Uncoupled: d_k = 2 zeta sqrt(m_k k_k).
    Vector6d masses;
    masses << 21.75, 21.75, 21.75, 4.255, 1.0, 4.255;
    Vector6d stiffnesses;
    stiffnesses << 600.0, 600.0, 600.0, 196.0, 100.0, 196.0;
    const double zeta = 0.7;
    const Matrix6d damping =
        coopdyn::classical_damping(Matrix6d(masses.asDiagonal()), Matrix6d(stiffnesses.asDiagonal()), zeta);
    const Vector6d expected = 2.0 * zeta * (masses.array() * stiffnesses.array()).sqrt().matrix();
    const double error = relative_error(damping, Matrix6d(expected.asDiagonal()));
    std::printf("[classical damping diagonal] beam M, K, zeta = 0.7: relative error %.2e (d_x = %.6g)\n", error,
                damping(0, 0));
    EXPECT_LT(error, 1e-14);
    // zeta = 0 gives D = 0; a semi-definite K (a free direction) gives finite D with zero there.
    EXPECT_EQ(coopdyn::classical_damping(Matrix6d(masses.asDiagonal()), Matrix6d(stiffnesses.asDiagonal()), 0.0)
                  .cwiseAbs()
                  .maxCoeff(),
              0.0);
    Vector6d semidefinite = stiffnesses;
    semidefinite(4) = 0.0;
    const Matrix6d free_axis =
        coopdyn::classical_damping(Matrix6d(masses.asDiagonal()), Matrix6d(semidefinite.asDiagonal()), zeta);
    EXPECT_TRUE(free_axis.allFinite());
    EXPECT_EQ(free_axis(4, 4), 0.0);
    // Invalid inputs are refused, not turned into NaN.
    Matrix6d not_symmetric = Matrix6d(masses.asDiagonal());
    not_symmetric(0, 1) = 1.0;
    EXPECT_THROW(coopdyn::classical_damping(not_symmetric, Matrix6d(stiffnesses.asDiagonal()), zeta),
                 coopdyn::InvalidArgument);
    Vector6d indefinite = stiffnesses;
    indefinite(2) = -1.0;
    EXPECT_THROW(coopdyn::classical_damping(Matrix6d(masses.asDiagonal()), Matrix6d(indefinite.asDiagonal()), zeta),
                 coopdyn::InvalidArgument);
    EXPECT_THROW(coopdyn::classical_damping(Matrix6d(masses.asDiagonal()), Matrix6d(stiffnesses.asDiagonal()), -0.1),
                 coopdyn::InvalidArgument);
}

TEST(ClassicalDamping, FedToSynthesisReachableOnlyWhenTheStructureAllowsIt)
{
    // Paper beam (section V): classical damping of its (M, K) is diagonal but its rotational part
    // is not of the form (sum d_i) S S^T + (sum delta_i) I3: reported unreachable, with residual.
    BeamParameters beam = section_five_beam();
    for (ArmParameters& arm : beam.arms) {
        arm.damping = 0.0;  // undamped: the damping is what the synthesis is asked for
        arm.rotational_damping = 0.0;
    }
    const Model2 model = make_model<Model2>(beam.object, beam.arms);
    coopdyn::Data<Model2> data(model);
    coopdyn::grasp_kinematics(model, data, coopdyn::RigidBodyState<double>{});
    const double zeta = 0.7;
    const Matrix6d beam_classical = coopdyn::classical_damping(coopdyn::apparent_impedance(model, data), zeta);
    const auto beam_damping = coopdyn::synthesize_damping(model, data, beam_classical);
    EXPECT_FALSE(beam_damping.achievable);
    EXPECT_GT(beam_damping.relative_residual, 1e-3);
    EXPECT_THROW(coopdyn::with_damping(model, beam_damping), coopdyn::InvalidArgument);

    // Built so that M = c K (two identical arms at (+-L, 0, 0), object inertia chosen to match):
    // then classical D = 2 zeta sqrt(c) K is reachable, d_i = 2 zeta sqrt(c) k, delta_i = 2 zeta
    // sqrt(c) kappa, and the synthesized arms give every mode the damping ratio zeta.
    const double mass = 10.0;
    const double rotational = 0.5;
    const double stiffness = 300.0;
    const double rotational_stiffness = 50.0;
    const double length = 0.4;
    coopdyn::RigidObject<double> object;
    object.mass = 1.75;
    const double ratio = (object.mass + 2.0 * mass) / (2.0 * stiffness);  // c
    const double inertia_x = ratio * 2.0 * rotational_stiffness - 2.0 * rotational;
    const double inertia_yz = ratio * (2.0 * rotational_stiffness + 2.0 * stiffness * length * length) -
                              2.0 * rotational - 2.0 * mass * length * length;
    object.inertia_body = Eigen::Vector3d(inertia_x, inertia_yz, inertia_yz).asDiagonal();
    std::vector<Model2::ArmType> proportional_arms(2);
    for (auto& arm : proportional_arms) {
        arm.end_effector.mass = mass;
        arm.end_effector.rotational_inertia = rotational * Matrix3d::Identity();
        arm.end_effector.translational_stiffness = stiffness;
        arm.end_effector.rotational_stiffness = rotational_stiffness;
    }
    proportional_arms[0].grasp_body.position = Vector3d(length, 0.0, 0.0);
    proportional_arms[1].grasp_body.position = Vector3d(-length, 0.0, 0.0);
    const Model2 proportional(object, proportional_arms);
    coopdyn::Data<Model2> proportional_data(proportional);
    coopdyn::grasp_kinematics(proportional, proportional_data, coopdyn::RigidBodyState<double>{});
    const auto impedance = coopdyn::apparent_impedance(proportional, proportional_data);
    ASSERT_LT(relative_error(impedance.inertia, Matrix6d(ratio * impedance.stiffness)), 1e-14);
    const auto damping = coopdyn::synthesize_damping(proportional, proportional_data,
                                                     coopdyn::classical_damping(impedance, zeta));
    const double factor = 2.0 * zeta * std::sqrt(ratio);
    EXPECT_TRUE(damping.achievable);
    EXPECT_LT(relative_error(damping.translational, Eigen::Vector2d::Constant(factor * stiffness)), 1e-12);
    EXPECT_LT(relative_error(damping.rotational, Eigen::Vector2d::Constant(factor * rotational_stiffness)), 1e-12);
    const Model2 tuned = coopdyn::with_damping(proportional, damping);
    coopdyn::Data<Model2> tuned_data(tuned);
    coopdyn::grasp_kinematics(tuned, tuned_data, coopdyn::RigidBodyState<double>{});
    const auto tuned_modes = coopdyn::modes(coopdyn::apparent_impedance(tuned, tuned_data));
    const double worst = (tuned_modes.damping_ratios.array() - zeta).abs().maxCoeff();
    std::printf("[classical damping -> synthesis] beam: reachable = %d, residual %.3e; proportional set-up: "
                "d = %.6g, delta = %.6g, worst |zeta_k - %.1f| = %.2e\n",
                beam_damping.achievable ? 1 : 0, beam_damping.relative_residual, damping.translational(0),
                damping.rotational(0), zeta, worst);
    EXPECT_LT(worst, 1e-12);
}

}  // namespace
