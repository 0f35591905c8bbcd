// Tests of include/coopdyn/analysis/stability.hpp (Theorems 3-4, Corollary 1; docs/analysis.md,
// errata E4). References the code was not derived from:
//   - the per-axis closed forms of the Section V beam (docs/analysis.md): omega = sqrt(k/m),
//     zeta = d / (2 sqrt(k m)), poles -zeta omega +- i omega sqrt(1 - zeta^2);
//   - the characteristic polynomial det(M s^2 + D s + K) of (52) (a second eigenvalue method),
//     and Vieta's product of its roots, det K / det M;
//   - a finite-difference linearisation of the full cooperative model (the interaction wrench
//     (18), docs/dynamics.md) about an equilibrium;
//   - Rayleigh damping D = a M + b K, whose modes are known to be classical;
//   - the literal centre of stiffness sum k_i r_i / sum k_i, and the physical property that a
//     force through it produces a pure translation.
// Randomness is seeded; grasps are non-symmetric; N varies.

#include "coopdyn/analysis/stability.hpp"
#include "coopdyn/analysis/apparent_impedance.hpp"
#include "coopdyn/dynamics/cooperative_dynamics.hpp"
#include "coopdyn/model/cooperative_model.hpp"

#include "sample_systems.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <utility>
#include <vector>

// Every class template of the header is instantiated, so every member compiles.
template struct coopdyn::Modes<double>;
template struct coopdyn::Modes<float>;

namespace {

using coopdyn::Index;
using coopdyn_test::ArmParameters;
using coopdyn_test::hat;
using coopdyn_test::make_model;
using coopdyn_test::Matrix6d;
using coopdyn_test::random_arms;
using coopdyn_test::random_object;
using coopdyn_test::relative_error;
using coopdyn_test::Rng;
using coopdyn_test::rotation_exponential;
using coopdyn_test::rotation_matrix;
using coopdyn_test::uniform;
using coopdyn_test::Vector6d;
using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Quaterniond;
using Eigen::Vector3d;
using Complex = std::complex<double>;
using Eigenvalues = Eigen::Matrix<Complex, 12, 1>;
using Impedance = coopdyn::ApparentImpedance<double>;
using ModelX = coopdyn::Model<double, coopdyn::Dynamic>;
using State = coopdyn::RigidBodyState<double>;

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

// rotation_matrix, rotation_exponential: sample_systems.hpp.

/// Pose displaced by a world-frame twist displacement [dp; dtheta], twist replaced by `twist`.
State displaced(const State& state, const Vector6d& delta, const Vector6d& twist)
{
    State result;
    result.pose.position = state.pose.position + delta.head<3>();
    result.pose.orientation = rotation_exponential(delta.tail<3>()) * state.pose.orientation;
    result.twist = twist;
    return result;
}

// ArmParameters, random_arms, random_object (analysis ranges) and make_model: sample_systems.hpp.

/// A model with its equilibrium (object at rest, setpoints at the grasp poses (38)).
struct System {
    ModelX model;
    State equilibrium;
    coopdyn::Setpoints<double, coopdyn::Dynamic> setpoints;
    std::vector<ArmParameters> arms;
    Impedance impedance;
};

System make_system(const coopdyn::RigidObject<double>& object, const std::vector<ArmParameters>& arms,
                   const State& equilibrium)
{
    ModelX model = make_model<ModelX>(object, arms, Vector3d::Zero());  // zero gravity: no compensation needed
    coopdyn::Setpoints<double, coopdyn::Dynamic> setpoints(model.arms());
    coopdyn::Data<ModelX> data(model);
    coopdyn::grasp_kinematics(model, data, equilibrium);
    for (Index i = 0; i < model.arms(); ++i) {
        setpoints.set_pose(i, data.end_effector_pose(i));
    }
    const Impedance impedance = coopdyn::apparent_impedance(model, data);
    return System{std::move(model), equilibrium, setpoints, arms, impedance};
}

System random_system(Index arms_count, Rng& rng)
{
    const std::vector<ArmParameters> arms = random_arms(arms_count, rng);
    const coopdyn::RigidObject<double> object = random_object(rng);
    State equilibrium;
    equilibrium.pose.position = coopdyn_test::random_vector(3, rng);
    equilibrium.pose.orientation = coopdyn_test::random_unit_quaternion(rng);
    return make_system(object, arms, equilibrium);
}

/// The Section V beam (docs/analysis.md), beam along y, J_o_body = diag(0.055, 0, 0.055);
/// the gains can be changed to make an underdamped variant.
System section_five_beam(double damping = 180.0, double rotational_damping = 10.0)
{
    coopdyn_test::BeamParameters beam = coopdyn_test::section_five_beam();
    for (ArmParameters& arm : beam.arms) {
        arm.damping = damping;
        arm.rotational_damping = rotational_damping;
    }
    State equilibrium;
    equilibrium.pose.position = Vector3d(0.2, 0.0, 1.0);
    return make_system(beam.object, beam.arms, equilibrium);
}

/// Largest |computed - expected| over a one-to-one nearest matching, each relative to |expected|.
/// `expected` and `computed` are multisets of the same size.
double match_eigenvalues(const std::vector<Complex>& expected, const Eigenvalues& computed,
                         const std::vector<double>& tolerances, bool& all_within)
{
    std::vector<bool> used(static_cast<std::size_t>(computed.size()), false);
    double worst = 0.0;
    all_within = expected.size() == static_cast<std::size_t>(computed.size());
    for (std::size_t e = 0; e < expected.size(); ++e) {
        std::size_t best = 0;
        double best_distance = 1e300;
        for (std::size_t c = 0; c < used.size(); ++c) {
            const double distance = std::abs(computed(static_cast<Index>(c)) - expected[e]);
            if (!used[c] && distance < best_distance) {
                best = c;
                best_distance = distance;
            }
        }
        used[best] = true;
        const double error = best_distance / std::abs(expected[e]);
        worst = std::max(worst, error);
        all_within = all_within && error <= tolerances[e];
    }
    return worst;
}

/// sigma_min / sigma_max of M s^2 + D s + K: zero exactly when s is a root of
/// det(M s^2 + D s + K) (the quadratic eigenvalue problem of (52)).
double characteristic_singularity(const Impedance& impedance, const Complex& s)
{
    const Eigen::Matrix<Complex, 6, 6> matrix = impedance.inertia.cast<Complex>() * (s * s) +
                                                impedance.damping.cast<Complex>() * s +
                                                impedance.stiffness.cast<Complex>();
    const Eigen::JacobiSVD<Eigen::Matrix<Complex, 6, 6>> svd(matrix);
    return svd.singularValues()(5) / svd.singularValues()(0);
}

/// Central-difference linearisation of the full cooperative model (interaction_dynamics, the
/// interaction wrench (18), docs/dynamics.md) about an equilibrium at rest, in the state
/// [twist displacement; twist].
Eigen::Matrix<double, 12, 12> full_model_state_matrix(const System& system, double step)
{
    coopdyn::Data<ModelX> data(system.model);
    const coopdyn::Disturbances<double, coopdyn::Dynamic> disturbances(system.model.arms());
    Eigen::Matrix<double, 12, 12> result = Eigen::Matrix<double, 12, 12>::Zero();
    result.topRightCorner<6, 6>().setIdentity();  // d(twist displacement)/dt = twist at rest
    for (Index j = 0; j < 12; ++j) {
        Vector6d delta = Vector6d::Zero(), twist = Vector6d::Zero();
        (j < 6 ? delta(j) : twist(j - 6)) = step;
        coopdyn::interaction_dynamics(system.model, data, displaced(system.equilibrium, delta, twist),
                                      system.setpoints, disturbances);
        const Vector6d plus = data.object_acceleration();
        coopdyn::interaction_dynamics(system.model, data, displaced(system.equilibrium, -delta, -twist),
                                      system.setpoints, disturbances);
        const Vector6d minus = data.object_acceleration();
        result.block<6, 1>(6, j) = (plus - minus) / (2.0 * step);
    }
    return result;
}

/// Per-axis closed forms of the diagonal beam: -zeta omega +- omega sqrt(zeta^2 - 1), which is
/// -zeta omega +- i omega sqrt(1 - zeta^2) when underdamped.
std::vector<Complex> per_axis_poles(const Impedance& impedance)
{
    std::vector<Complex> poles;
    for (Index a = 0; a < 6; ++a) {
        const double m = impedance.inertia(a, a), d = impedance.damping(a, a), k = impedance.stiffness(a, a);
        const double omega = std::sqrt(k / m);
        const double zeta = d / (2.0 * std::sqrt(k * m));
        const Complex root = omega * std::sqrt(Complex(zeta * zeta - 1.0, 0.0));
        poles.push_back(-zeta * omega + root);
        poles.push_back(-zeta * omega - root);
    }
    return poles;
}

// ---------------------------------------------------------------------------------------------
// 1. Eigenvalues of (52)
// ---------------------------------------------------------------------------------------------

TEST(StabilityEigenvalues, BeamPolesMatchThePerAxisClosedForm)
{
    // Beam: translation m 21.75, d 360, k 600 (zeta 1.576, poles -1.88, -14.67, three times);
    // rotation about x, z: 4.255, 77.6, 196 (zeta 1.344); about y: 1, 20, 100 (zeta = 1 exactly,
    // a double pole at -10). The critically damped pair is a defective (Jordan) eigenvalue of
    // the state matrix: rounding of size eps perturbs it by sqrt(eps |A|) ~ 1e-7, so it gets a
    // tolerance of 1e-6 relative; every other pole is simple or semisimple: 1e-12.
    const System beam = section_five_beam();
    const Eigenvalues computed = coopdyn::linearised_eigenvalues(beam.impedance);
    const std::vector<Complex> expected = per_axis_poles(beam.impedance);
    std::vector<double> tolerances;
    for (Index a = 0; a < 6; ++a) {
        const double zeta = beam.impedance.damping(a, a) /
                            (2.0 * std::sqrt(beam.impedance.stiffness(a, a) * beam.impedance.inertia(a, a)));
        tolerances.push_back(std::abs(zeta - 1.0) < 1e-12 ? 1e-6 : 1e-12);
        tolerances.push_back(tolerances.back());
    }
    bool within = false;
    const double worst = match_eigenvalues(expected, computed, tolerances, within);
    std::printf("[ beam poles ]");
    for (Index k = 0; k < 12; ++k) {
        std::printf(" %.4f%+.1ei", computed(k).real(), computed(k).imag());
    }
    std::printf("\n[ beam poles ] worst relative difference to -zeta w +- w sqrt(zeta^2 - 1): %.2e\n", worst);
    EXPECT_TRUE(within);
    EXPECT_LT(computed.real().maxCoeff(), 0.0);
    // Spot value by hand: translation poles -d/(2m) +- sqrt((d/(2m))^2 - k/m)
    // = -8.275862 +- 6.395599 = -1.880263 and -14.671461 1/s.
    const double omega = std::sqrt(600.0 / 21.75), zeta = 360.0 / (2.0 * std::sqrt(600.0 * 21.75));
    EXPECT_NEAR(zeta, 1.575677, 1e-6);
    EXPECT_NEAR(-zeta * omega + omega * std::sqrt(zeta * zeta - 1.0), -1.880263, 1e-6);
    EXPECT_NEAR(computed.real().maxCoeff(), -1.880263, 1e-6);  // the slowest pole
}

TEST(StabilityEigenvalues, UnderdampedBeamPolesAreMinusZetaOmegaPlusMinusIOmegaSqrtOneMinusZetaSquared)
{
    // The beam with d_i = 30, delta_i = 2: every axis is underdamped, so each mode gives a
    // complex pair -zeta w +- i w sqrt(1 - zeta^2).
    const System beam = section_five_beam(30.0, 2.0);
    const Eigenvalues computed = coopdyn::linearised_eigenvalues(beam.impedance);
    std::vector<Complex> expected;
    for (Index a = 0; a < 6; ++a) {
        const double m = beam.impedance.inertia(a, a), d = beam.impedance.damping(a, a), k = beam.impedance.stiffness(a, a);
        const double omega = std::sqrt(k / m), zeta = d / (2.0 * std::sqrt(k * m));
        ASSERT_LT(zeta, 1.0);
        expected.emplace_back(-zeta * omega, omega * std::sqrt(1.0 - zeta * zeta));
        expected.emplace_back(-zeta * omega, -omega * std::sqrt(1.0 - zeta * zeta));
    }
    bool within = false;
    const double worst = match_eigenvalues(expected, computed, std::vector<double>(12, 1e-12), within);
    std::printf("[ underdamped beam ] translation pole %.6f%+.6fi (zeta %.4f); worst relative difference %.2e\n",
                expected[0].real(), expected[0].imag(), 60.0 / (2.0 * std::sqrt(600.0 * 21.75)), worst);
    EXPECT_TRUE(within);
    EXPECT_LT(computed.real().maxCoeff(), 0.0);
}

TEST(StabilityEigenvalues, RandomGraspsAreStableAndPolesAreRootsOfTheCharacteristicPolynomial)
{
    // Theorem 3: M, D, K SPD => Re(s) < 0. Each eigenvalue of the state matrix must make
    // M s^2 + D s + K singular (second method), and the product of all 12 equals
    // det K / det M (Vieta, for det(M s^2 + D s + K) of degree 12 with leading det M).
    Rng rng(52u);
    double worst_singularity = 0.0, worst_product = 0.0, largest_real = -1e300;
    for (const Index arms_count : {Index(1), Index(2), Index(3), Index(4), Index(6)}) {
        for (int trial = 0; trial < 4; ++trial) {
            const System system = random_system(arms_count, rng);
            const Eigenvalues poles = coopdyn::linearised_eigenvalues(system.impedance);
            largest_real = std::max(largest_real, poles.real().maxCoeff());
            EXPECT_LT(poles.real().maxCoeff(), 0.0) << "N = " << arms_count;
            for (Index k = 0; k < 12; ++k) {
                const double singularity = characteristic_singularity(system.impedance, poles(k));
                worst_singularity = std::max(worst_singularity, singularity);
                EXPECT_LE(singularity, 1e-12) << "N = " << arms_count << ", s = " << poles(k);
            }
            Complex product(1.0, 0.0);
            for (Index k = 0; k < 12; ++k) {
                product *= poles(k);
            }
            const double expected = system.impedance.stiffness.determinant() / system.impedance.inertia.determinant();
            const double error = std::abs(product - expected) / expected;
            worst_product = std::max(worst_product, error);
            EXPECT_LE(error, 1e-12);
        }
    }
    std::printf("[ random poles ] N = 1, 2, 3, 4, 6 x 4: largest Re(s) = %.3f 1/s; worst sigma_min/sigma_max of "
                "M s^2 + D s + K = %.1e; |prod s - det K / det M| relative %.1e\n",
                largest_real, worst_singularity, worst_product);
}

TEST(StabilityEigenvalues, StateMatrixIsTheLinearisationOfTheFullModel)
{
    // Central differences (step 1e-6) of the full model's object acceleration about the
    // equilibrium give the state matrix of (52), [[0, I], [-M^-1 K, -M^-1 D]], and the same poles.
    Rng rng(61u);
    double worst_matrix = 0.0, worst_poles = 0.0;
    for (const Index arms_count : {Index(2), Index(3), Index(5)}) {
        for (int trial = 0; trial < 2; ++trial) {
            const System system = random_system(arms_count, rng);
            const Eigen::Matrix<double, 12, 12> expected = coopdyn::state_matrix(system.impedance);
            const Eigen::Matrix<double, 12, 12> linearised = full_model_state_matrix(system, 1e-6);
            const double matrix_error = relative_error(expected, linearised);
            worst_matrix = std::max(worst_matrix, matrix_error);
            EXPECT_LE(matrix_error, 1e-8) << "N = " << arms_count;
            const Eigen::EigenSolver<Eigen::Matrix<double, 12, 12>> solver(linearised, false);
            const Eigenvalues linearised_poles = solver.eigenvalues();
            const std::vector<Complex> reference(linearised_poles.data(), linearised_poles.data() + 12);
            bool within = false;
            const double pole_error = match_eigenvalues(
                reference, coopdyn::linearised_eigenvalues(system.impedance), std::vector<double>(12, 1e-6), within);
            worst_poles = std::max(worst_poles, pole_error);
            EXPECT_TRUE(within) << "N = " << arms_count << ", worst " << pole_error;
        }
    }
    std::printf("[ full-model linearisation ] N = 2, 3, 5: |A - A_fd| / |A_fd| <= %.1e, poles relative <= %.1e\n",
                worst_matrix, worst_poles);
}

// ---------------------------------------------------------------------------------------------
// 2. Modes and damping ratios
// ---------------------------------------------------------------------------------------------

TEST(StabilityModes, GeneralizedEigenvectorsAreMassNormalisedModes)
{
    // K v = omega^2 M v, V^T M V = I, omega ascending, on the beam and random grasps.
    Rng rng(7u);
    std::vector<System> systems;
    systems.push_back(section_five_beam());
    for (const Index arms_count : {Index(1), Index(2), Index(3), Index(5)}) {
        systems.push_back(random_system(arms_count, rng));
    }
    double worst_residual = 0.0, worst_orthonormality = 0.0;
    for (const System& system : systems) {
        const coopdyn::Modes<double> modes = coopdyn::modes(system.impedance);
        const Matrix6d& v = modes.shapes;
        const Matrix6d residual = system.impedance.stiffness * v -
                                  system.impedance.inertia * v * modes.natural_frequencies.array().square().matrix().asDiagonal();
        worst_residual = std::max(worst_residual, residual.norm() / (system.impedance.stiffness.norm() * v.norm()));
        worst_orthonormality =
            std::max(worst_orthonormality, (v.transpose() * system.impedance.inertia * v - Matrix6d::Identity()).norm());
        for (Index k = 1; k < 6; ++k) {
            EXPECT_LE(modes.natural_frequencies(k - 1), modes.natural_frequencies(k));
        }
        EXPECT_GT(modes.natural_frequencies(0), 0.0);
        // Damping ratios are v^T D v / (2 omega) for the M-normalised v (definition).
        for (Index k = 0; k < 6; ++k) {
            const Vector6d shape = v.col(k);
            EXPECT_NEAR(modes.damping_ratios(k),
                        shape.dot(system.impedance.damping * shape) / (2.0 * modes.natural_frequencies(k)),
                        1e-13 * modes.damping_ratios(k));
        }
    }
    std::printf("[ modes ] beam + N = 1, 2, 3, 5: |K V - M V W^2| / (|K| |V|) <= %.1e, |V^T M V - I| <= %.1e\n",
                worst_residual, worst_orthonormality);
    EXPECT_LE(worst_residual, 1e-14);
    EXPECT_LE(worst_orthonormality, 1e-13);
}

TEST(StabilityModes, BeamFrequenciesAndDampingRatiosMatchThePerAxisFormula)
{
    // omega = sqrt(k / m), zeta = d / (2 sqrt(k m)) per axis; ascending: translation x, y, z
    // (sqrt(600/21.75) = 5.252 rad/s, zeta 1.5757), rotation x, z (sqrt(196/4.255) = 6.787,
    // zeta 1.3435), rotation y (10 rad/s, zeta 1). Within a repeated frequency the mode shapes are
    // any M-orthonormal basis, but D is proportional to M there, so zeta is basis-independent.
    const System beam = section_five_beam();
    const coopdyn::Modes<double> modes = coopdyn::modes(beam.impedance);
    const auto axis = [](double m, double d, double k) { return std::make_pair(std::sqrt(k / m), d / (2.0 * std::sqrt(k * m))); };
    const std::array<std::pair<double, double>, 6> expected{axis(21.75, 360, 600), axis(21.75, 360, 600),
                                                            axis(21.75, 360, 600), axis(4.255, 77.6, 196),
                                                            axis(4.255, 77.6, 196), axis(1.0, 20, 100)};
    double worst = 0.0;
    for (std::size_t k = 0; k < 6; ++k) {
        const Index j = static_cast<Index>(k);
        worst = std::max(worst, std::abs(modes.natural_frequencies(j) - expected[k].first) / expected[k].first);
        worst = std::max(worst, std::abs(modes.damping_ratios(j) - expected[k].second) / expected[k].second);
        std::printf("[ beam modes ] omega %.6f rad/s (formula %.6f), zeta %.6f (formula %.6f)\n",
                    modes.natural_frequencies(j), expected[k].first, modes.damping_ratios(j), expected[k].second);
    }
    std::printf("[ beam modes ] worst relative difference %.2e\n", worst);
    EXPECT_LE(worst, 1e-13);
    EXPECT_NEAR(expected[0].second, 360.0 / (2.0 * std::sqrt(600.0 * 21.75)), 1e-15);
}

/// Poles predicted from modes() alone: -zeta omega +- omega sqrt(zeta^2 - 1) for every mode.
std::vector<Complex> modal_poles(const coopdyn::Modes<double>& modes)
{
    std::vector<Complex> poles;
    for (Index k = 0; k < 6; ++k) {
        const double omega = modes.natural_frequencies(k), zeta = modes.damping_ratios(k);
        const Complex root = omega * std::sqrt(Complex(zeta * zeta - 1.0, 0.0));
        poles.push_back(-zeta * omega + root);
        poles.push_back(-zeta * omega - root);
    }
    return poles;
}

TEST(StabilityModes, RayleighDampingIsClassicalAndModalPolesAreExact)
{
    // D = a M + b K commutes in the sense D M^-1 K = K M^-1 D, so the undamped modes decouple
    // (52) and the modal damping ratios predict every pole exactly. Fully coupled M and K from
    // random grasps; a, b chosen so modes are under- and overdamped.
    Rng rng(404u);
    double worst = 0.0, worst_commutator = 0.0;
    for (const Index arms_count : {Index(2), Index(3), Index(4)}) {
        const System system = random_system(arms_count, rng);
        Impedance rayleigh = system.impedance;
        rayleigh.damping = 2.0 * rayleigh.inertia + 0.02 * rayleigh.stiffness;
        const double commutator = coopdyn::classical_damping_commutator(rayleigh);
        const Matrix6d product = rayleigh.damping * rayleigh.inertia.inverse() * rayleigh.stiffness;
        worst_commutator = std::max(worst_commutator, commutator / product.norm());
        EXPECT_LE(commutator, 1e-13 * product.norm());
        bool within = false;
        const double error = match_eigenvalues(modal_poles(coopdyn::modes(rayleigh)),
                                               coopdyn::linearised_eigenvalues(rayleigh), std::vector<double>(12, 1e-10),
                                               within);
        worst = std::max(worst, error);
        EXPECT_TRUE(within) << "N = " << arms_count << ", worst " << error;
    }
    std::printf("[ Rayleigh damping ] N = 2, 3, 4: commutator / |D M^-1 K| <= %.1e; modal poles vs state-matrix "
                "poles <= %.1e\n",
                worst_commutator, worst);
}

// ---------------------------------------------------------------------------------------------
// 3. Classical damping (Theorem 4, errata E4)
// ---------------------------------------------------------------------------------------------

/// D M^-1 K - K M^-1 D with explicit inverses (the definition).
double literal_commutator(const Impedance& impedance)
{
    const Matrix6d inverse = impedance.inertia.inverse();
    return (impedance.damping * inverse * impedance.stiffness - impedance.stiffness * inverse * impedance.damping).norm();
}

TEST(StabilityClassicalDamping, ZeroForTheSymmetricBeamNonzeroForAnAsymmetricGrasp)
{
    const System beam = section_five_beam();
    const double beam_commutator = coopdyn::classical_damping_commutator(beam.impedance);
    const double beam_scale = (beam.impedance.damping * beam.impedance.inertia.inverse() * beam.impedance.stiffness).norm();

    // Asymmetric two-arm grasp: the beam's object, arms at different distances and heights with
    // different gains and gain ratios (d_i / k_i differ, so D is not a combination of M and K).
    const coopdyn::RigidObject<double> object = coopdyn_test::section_five_beam().object;
    std::vector<ArmParameters> arms(2);
    arms[0] = ArmParameters{10.0, 0.5 * Matrix3d::Identity(), 180.0, 10.0, 300.0, 50.0, Vector3d(0.05, -0.3, 0.0),
                            Quaterniond::Identity()};
    arms[1] = ArmParameters{6.0, 0.3 * Matrix3d::Identity(), 90.0, 4.0, 500.0, 30.0, Vector3d(0.0, 0.5, 0.1),
                            Quaterniond(Eigen::AngleAxisd(0.7, Vector3d::UnitX()))};
    State equilibrium;
    const System asymmetric = make_system(object, arms, equilibrium);
    const double commutator = coopdyn::classical_damping_commutator(asymmetric.impedance);
    const double scale =
        (asymmetric.impedance.damping * asymmetric.impedance.inertia.inverse() * asymmetric.impedance.stiffness).norm();

    // Consequence: the modal damping ratios no longer predict the poles.
    bool within = false;
    const double modal_miss = match_eigenvalues(modal_poles(coopdyn::modes(asymmetric.impedance)),
                                                coopdyn::linearised_eigenvalues(asymmetric.impedance),
                                                std::vector<double>(12, 1e-10), within);
    std::printf("[ E4 ] |D M^-1 K - K M^-1 D|: beam %.2e (relative %.1e); asymmetric two-arm grasp %.1f (relative "
                "%.3f; docs/errata.md quotes 540 for its own case); modal-ratio poles miss the true poles by %.1f%%\n",
                beam_commutator, beam_commutator / beam_scale, commutator, commutator / scale, 100.0 * modal_miss);
    EXPECT_LE(beam_commutator, 1e-14 * beam_scale);
    EXPECT_GT(commutator, 1e-2 * scale);
    EXPECT_NEAR(commutator, literal_commutator(asymmetric.impedance), 1e-10 * scale);
    EXPECT_GT(modal_miss, 1e-3);
}

// ---------------------------------------------------------------------------------------------
// 4. Decoupling (Corollary 1) and the centre of stiffness
// ---------------------------------------------------------------------------------------------

TEST(StabilityDecoupling, HomogeneousArmsWithZeroOffsetSumAreDecoupled)
{
    Rng rng(11u);
    EXPECT_TRUE(coopdyn::is_decoupled(section_five_beam().impedance));
    int decoupled = 0, cases = 0;
    for (const Index arms_count : {Index(2), Index(3), Index(4), Index(5)}) {
        // Homogeneous: every arm a copy of the first (coupled J_i, same gains); sum r_i = 0.
        std::vector<ArmParameters> arms = random_arms(arms_count, rng);
        Vector3d mean = Vector3d::Zero();
        for (const ArmParameters& arm : arms) {
            mean += arm.offset_body / static_cast<double>(arms_count);
        }
        for (ArmParameters& arm : arms) {
            const Vector3d offset = arm.offset_body - mean;
            const Quaterniond orientation = arm.grasp_orientation;
            arm = arms.front();
            arm.offset_body = offset;
            arm.grasp_orientation = orientation;  // grasp orientations do not matter (isotropic gains)
        }
        State equilibrium;
        equilibrium.pose.orientation = coopdyn_test::random_unit_quaternion(rng);
        const coopdyn::RigidObject<double> object = random_object(rng);
        const System homogeneous = make_system(object, arms, equilibrium);
        EXPECT_TRUE(coopdyn::is_decoupled(homogeneous.impedance)) << "N = " << arms_count;
        decoupled += coopdyn::is_decoupled(homogeneous.impedance) ? 1 : 0;

        // Offsets not summing to zero: coupled.
        std::vector<ArmParameters> shifted = arms;
        for (ArmParameters& arm : shifted) {
            arm.offset_body += Vector3d(0.05, -0.02, 0.03);
        }
        EXPECT_FALSE(coopdyn::is_decoupled(make_system(object, shifted, equilibrium).impedance)) << "N = " << arms_count;
        // Heterogeneous arms with sum r_i = 0: sum m_i r_i != 0, coupled.
        std::vector<ArmParameters> heterogeneous = arms;
        heterogeneous.front().mass *= 1.5;
        heterogeneous.front().stiffness *= 0.5;
        EXPECT_FALSE(coopdyn::is_decoupled(make_system(object, heterogeneous, equilibrium).impedance))
            << "N = " << arms_count;
        // Random arms at random offsets: coupled.
        EXPECT_FALSE(coopdyn::is_decoupled(random_system(arms_count, rng).impedance)) << "N = " << arms_count;
        ++cases;
    }
    std::printf("[ Corollary 1 ] homogeneous arms, sum r_i = 0: %d of %d decoupled; shifted, heterogeneous and "
                "random grasps coupled\n",
                decoupled, cases);
}

TEST(StabilityCentreOfStiffness, IsTheStiffnessWeightedMeanOfTheGraspPoints)
{
    // c = sum k_i r_i / sum k_i (literal), and physically: a force f acting through c produces a
    // pure translation, K^-1 [f; c x f] = [f / sum k_i; 0].
    Rng rng(99u);
    double worst_centre = 0.0, worst_rotation = 0.0;
    for (const Index arms_count : {Index(1), Index(2), Index(3), Index(5)}) {
        for (int trial = 0; trial < 4; ++trial) {
            const System system = random_system(arms_count, rng);
            const Matrix3d rotation = rotation_matrix(system.equilibrium.pose.orientation);
            Vector3d weighted = Vector3d::Zero();
            double total = 0.0;
            for (const ArmParameters& arm : system.arms) {
                weighted += arm.stiffness * (rotation * arm.offset_body);
                total += arm.stiffness;
            }
            const Vector3d expected = weighted / total;
            const Vector3d centre = coopdyn::centre_of_stiffness(system.impedance.stiffness);
            worst_centre = std::max(worst_centre, (centre - expected).norm() / expected.norm());
            EXPECT_LE((centre - expected).norm(), 1e-14 * expected.norm()) << "N = " << arms_count;

            const Vector3d force = coopdyn_test::random_vector(3, rng, -10.0, 10.0);
            Vector6d wrench;
            wrench << force, centre.cross(force);
            const Vector6d displacement = system.impedance.stiffness.ldlt().solve(wrench);
            worst_rotation = std::max(worst_rotation, displacement.tail<3>().norm() / displacement.head<3>().norm());
            EXPECT_LE(displacement.tail<3>().norm(), 1e-12 * displacement.head<3>().norm());
            EXPECT_LE((displacement.head<3>() - force / total).norm(), 1e-12 * force.norm() / total);
        }
    }
    // Theorem 2 example, r = (+-1, 0, 0), equal k: centre at the object's centre of mass.
    Matrix6d example = Matrix6d::Zero();
    example.topLeftCorner<3, 3>() = 200.0 * Matrix3d::Identity();
    example.bottomRightCorner<3, 3>() = Vector3d(200, 400, 400).asDiagonal();
    EXPECT_EQ(coopdyn::centre_of_stiffness(example), Vector3d::Zero());
    std::printf("[ centre of stiffness ] N = 1, 2, 3, 5 x 4: |c - sum k r / sum k| / |c| <= %.1e; rotation from a "
                "force through c <= %.1e of the translation\n",
                worst_centre, worst_rotation);
}

// ---------------------------------------------------------------------------------------------
// 5. Other scalar types
// ---------------------------------------------------------------------------------------------

TEST(StabilityScalars, FloatAgreesWithDoubleToFloatPrecision)
{
    const System beam = section_five_beam(30.0, 2.0);
    coopdyn::ApparentImpedance<float> single;
    single.inertia = beam.impedance.inertia.cast<float>();
    single.damping = beam.impedance.damping.cast<float>();
    single.stiffness = beam.impedance.stiffness.cast<float>();
    const coopdyn::Modes<float> modes_float = coopdyn::modes(single);
    const coopdyn::Modes<double> modes_double = coopdyn::modes(beam.impedance);
    const double frequency_error =
        relative_error(modes_float.natural_frequencies.cast<double>(), modes_double.natural_frequencies);
    const double ratio_error = relative_error(modes_float.damping_ratios.cast<double>(), modes_double.damping_ratios);
    const Eigen::Matrix<std::complex<float>, 12, 1> poles_float = coopdyn::linearised_eigenvalues(single);
    const Eigenvalues poles_double = coopdyn::linearised_eigenvalues(beam.impedance);
    const std::vector<Complex> reference(poles_double.data(), poles_double.data() + 12);
    bool within = false;
    const double pole_error =
        match_eigenvalues(reference, poles_float.cast<Complex>(), std::vector<double>(12, 1e-5), within);
    std::printf("[ float ] modes: frequencies %.1e, damping ratios %.1e; poles %.1e; commutator %.1e\n",
                frequency_error, ratio_error, pole_error, static_cast<double>(coopdyn::classical_damping_commutator(single)));
    EXPECT_LE(frequency_error, 1e-5);
    EXPECT_LE(ratio_error, 1e-5);
    EXPECT_TRUE(within);
    EXPECT_TRUE(coopdyn::is_decoupled(single, 1e-6f));
    EXPECT_LE((coopdyn::centre_of_stiffness(single.stiffness)).norm(), 1e-6f);
}

}  // namespace
