// Tests of the load distribution (include/coopdyn/coordination/load_distribution.hpp): the
// weighted generalized inverse G+_M of paper (25) with errata E2 and the centroid shift of
// docs/coordination.md, the desired end-effector wrenches (26), and the LoadDistribution class.
//
// Every check compares with something the code was not derived from:
//  - the literal grasp matrix G (24) of sample_systems.hpp: G G+_M = I6;
//  - the weighted least-norm right inverse W G^T (G W G^T)^-1, W = blkdiag(M*_i), a second,
//    dense method (the distribution (26) minimises sum_i hbar_i^T (M*_i)^-1 hbar_i subject to
//    G hbar = h_o; its Lagrange conditions give that formula, with no centroid shift at all);
//  - the literal internal wrench (53) of the reduced system, built here from explicit relative
//    constraints A' (arm 1 against arm i, 6(N-1) rows, errata E5) and solved as a KKT system;
//  - the printed block order of (25), written out literally, to document errata E2.
// Grasps are random and non-symmetric, with weighted centroids away from the object's centre of
// mass, N = 1..6, and seeded.

#include "coopdyn/analysis/internal_wrenches.hpp"
#include "coopdyn/coordination/load_distribution.hpp"
#include "coopdyn/dynamics/cooperative_dynamics.hpp"
#include "coopdyn/model/cooperative_model.hpp"

#include "sample_systems.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace {

using coopdyn_test::block_diagonal_inertia;
using coopdyn_test::hat;
using coopdyn_test::literal_constraint_bias;
using coopdyn_test::literal_grasp_matrix;
using coopdyn_test::literal_internal_wrench;
using coopdyn_test::relative_constraint_bias;
using coopdyn_test::relative_constraint_matrix;
using coopdyn_test::Matrix3d;
using coopdyn_test::MatrixXd;
using coopdyn_test::off_centre_offsets;
using coopdyn_test::random_offsets;
using coopdyn_test::random_spd;
using coopdyn_test::random_unit_quaternion;
using coopdyn_test::random_vector;
using coopdyn_test::relative_error;
using coopdyn_test::Rng;
using coopdyn_test::uniform;
using coopdyn_test::Vector3d;
using coopdyn_test::Vector6d;
using coopdyn_test::VectorXd;
using coopdyn_test::Weights;
using coopdyn_test::least_norm_right_inverse;
using coopdyn_test::weight_matrix;
using Index = Eigen::Index;

// ---------------------------------------------------------------------------------------------
// Helpers and literal references (no coopdyn calls)
// ---------------------------------------------------------------------------------------------

/// A random weighting of a grasp: m*_i in [0.5, 5], J*_i general SPD (fully coupled).
Weights random_weights(Index arms, Rng& rng)
{
    Weights weights{VectorXd(arms), MatrixXd(3, 3 * arms)};
    for (Index i = 0; i < arms; ++i) {
        weights.mass(i) = uniform(rng, 0.5, 5.0);
        weights.inertia.block(0, 3 * i, 3, 3) = random_spd(3, rng, uniform(rng, 0.05, 0.5), 0.2);
    }
    return weights;
}

Vector3d weighted_centroid(const MatrixXd& r, const VectorXd& mass)
{
    return r * mass / mass.sum();
}

/// The same least-norm inverse in long double, from the literal G: a reference accurate enough to
/// measure the rounding error of the double computation on ill-conditioned grasps.
Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic> least_norm_right_inverse_long_double(
    const MatrixXd& r, const Weights& weights)
{
    using Matrix = Eigen::Matrix<long double, Eigen::Dynamic, Eigen::Dynamic>;
    const Matrix g = literal_grasp_matrix(r).cast<long double>();
    const Matrix w = weight_matrix(weights).cast<long double>();
    const Matrix gram = g * w * g.transpose();
    return w * g.transpose() * gram.partialPivLu().inverse();
}

/// (25) written out for a CENTRED grasp (sum m*_i r_i = 0, as the paper requires), in the
/// printed order of the upper-right block, m*_i (J*_o)^-1 S(r_i)^T, or in the corrected order
/// m*_i S(r_i)^T (J*_o)^-1 (errata E2).
MatrixXd literal_equation_25(const MatrixXd& r, const Weights& weights, bool printed_order)
{
    const Index arms = r.cols();
    const double total_mass = weights.mass.sum();
    Matrix3d total_inertia = Matrix3d::Zero();
    for (Index i = 0; i < arms; ++i) {
        const Matrix3d s = hat(r.col(i));
        total_inertia += weights.inertia.block(0, 3 * i, 3, 3) + weights.mass(i) * s * s.transpose();
    }
    const Matrix3d inverse = total_inertia.inverse();
    MatrixXd result = MatrixXd::Zero(6 * arms, 6);
    for (Index i = 0; i < arms; ++i) {
        const Matrix3d s = hat(r.col(i));
        result.block(6 * i, 0, 3, 3) = (weights.mass(i) / total_mass) * Matrix3d::Identity();
        result.block(6 * i, 3, 3, 3) =
            printed_order ? Matrix3d(weights.mass(i) * inverse * s.transpose())
                          : Matrix3d(weights.mass(i) * s.transpose() * inverse);
        result.block(6 * i + 3, 3, 3, 3) = weights.inertia.block(0, 3 * i, 3, 3) * inverse;
    }
    return result;
}

double max_abs(const MatrixXd& m) { return m.cwiseAbs().maxCoeff(); }

/// Literal (53) in its printed pseudo-inverse form, M'^(1/2) (A' M'^(-1/2))^+ (b' - A' M'^-1 h),
/// with the Cholesky factor as the square root (docs/dynamics.md): a cross-check of the KKT form.
VectorXd pseudo_inverse_internal_wrench(const MatrixXd& ee_inertia, const MatrixXd& r, const Vector3d& omega,
                                        const VectorXd& commanded)
{
    const Index arms = r.cols();
    MatrixXd inertia = MatrixXd::Zero(6 * arms, 6 * arms);
    for (Index i = 0; i < arms; ++i) {
        inertia.block(6 * i, 6 * i, 6, 6) = ee_inertia.block(0, 6 * i, 6, 6);
    }
    const Eigen::LLT<MatrixXd> llt(inertia);
    const MatrixXd lower = llt.matrixL();
    const MatrixXd a = relative_constraint_matrix(r);
    // A' L^-T = (L^-1 A'^T)^T
    const MatrixXd scaled = lower.triangularView<Eigen::Lower>().solve(a.transpose()).transpose();
    const VectorXd residual = relative_constraint_bias(r, omega) - a * llt.solve(commanded);
    return lower * scaled.completeOrthogonalDecomposition().pseudoInverse() * residual;
}

/// Stack of blkdiag(m_i I3, J_i) as 6 x 6N.
MatrixXd stacked_inertias(const VectorXd& mass, const MatrixXd& rotational)
{
    const Index arms = mass.size();
    MatrixXd result(6, 6 * arms);
    for (Index i = 0; i < arms; ++i) {
        result.block(0, 6 * i, 6, 6) = block_diagonal_inertia(mass(i), rotational.block(0, 3 * i, 3, 3));
    }
    return result;
}

/// Runs `action`, expects coopdyn::InvalidModel, and checks that what() contains every fragment.
void expect_invalid_model(const std::function<void()>& action, const std::vector<std::string>& fragments,
                          const char* what)
{
    try {
        action();
        ADD_FAILURE() << what << ": no exception";
    } catch (const coopdyn::InvalidModel& error) {
        const std::string message = error.what();
        std::printf("[ refused ] %s: %s\n", what, message.c_str());
        for (const std::string& fragment : fragments) {
            EXPECT_NE(message.find(fragment), std::string::npos)
                << what << ": message '" << message << "' lacks '" << fragment << "'";
        }
    } catch (...) {
        ADD_FAILURE() << what << ": wrong exception type";
    }
}

// ---------------------------------------------------------------------------------------------
// 1. G G+_M = I6 and the second (least-norm) method; errata E2
// ---------------------------------------------------------------------------------------------

TEST(WeightedGraspInverse, IsARightInverseOfTheLiteralGraspMatrixForOffCentreGrasps)
{
    Rng rng(20240601);
    double worst_identity = 0.0;
    double worst_second_method = 0.0;
    double smallest_centroid = 1e9;
    for (Index arms = 1; arms <= 6; ++arms) {
        for (int trial = 0; trial < 25; ++trial) {
            const MatrixXd r = off_centre_offsets(arms, rng);
            const Weights weights = random_weights(arms, rng);
            smallest_centroid = std::min(smallest_centroid, weighted_centroid(r, weights.mass).norm());
            const MatrixXd inverse = coopdyn::weighted_grasp_inverse(r, weights.mass, weights.inertia);
            ASSERT_EQ(inverse.rows(), 6 * arms);
            ASSERT_EQ(inverse.cols(), 6);
            const MatrixXd g = literal_grasp_matrix(r);
            const double identity_error = max_abs(g * inverse - MatrixXd::Identity(6, 6));
            const double second_method_error = relative_error(inverse, least_norm_right_inverse(g, weights));
            worst_identity = std::max(worst_identity, identity_error);
            worst_second_method = std::max(worst_second_method, second_method_error);
            EXPECT_LT(identity_error, 1e-12) << "N = " << arms << ", trial " << trial;
            EXPECT_LT(second_method_error, 1e-12) << "N = " << arms << ", trial " << trial;
        }
    }
    std::printf("[ G G+_M ] N = 1..6, 150 off-centre grasps (|c| >= %.3f m): max |G G+_M - I6| = %.2e, "
                "max rel. diff. to W G^T (G W G^T)^-1 = %.2e\n",
                smallest_centroid, worst_identity, worst_second_method);
    EXPECT_GT(smallest_centroid, 0.5);  // the centroid shift really is exercised
}

TEST(WeightedGraspInverse, FixedSizeAndFloatArgumentsAgree)
{
    // Fixed N = 3 (compile-time sizes, no allocation) and float: same inverse.
    Rng rng(7);
    const MatrixXd r = off_centre_offsets(3, rng);
    const Weights weights = random_weights(3, rng);
    const Eigen::Matrix<double, 3, 3> r_fixed = r;
    const Eigen::Matrix<double, 3, 1> mass_fixed = weights.mass;
    const Eigen::Matrix<double, 3, 9> inertia_fixed = weights.inertia;
    const Eigen::Matrix<double, 18, 6> fixed = coopdyn::weighted_grasp_inverse(r_fixed, mass_fixed, inertia_fixed);
    const MatrixXd dynamic = coopdyn::weighted_grasp_inverse(r, weights.mass, weights.inertia);
    EXPECT_LT(max_abs(fixed - dynamic), 1e-15);

    const Eigen::Matrix<float, 3, 3> r_float = r_fixed.cast<float>();
    const Eigen::Matrix<float, 18, 6> single = coopdyn::weighted_grasp_inverse(
        r_float, mass_fixed.cast<float>().eval(), inertia_fixed.cast<float>().eval());
    const double float_identity =
        max_abs(literal_grasp_matrix(r_float.cast<double>()) * single.cast<double>() - MatrixXd::Identity(6, 6));
    std::printf("[ G G+_M ] float, N = 3: max |G G+_M - I6| = %.2e\n", float_identity);
    EXPECT_LT(float_identity, 1e-5);
}

TEST(WeightedGraspInverse, PrintedBlockOrderOfEquation25IsNotARightInverse)
{
    // Errata E2, on centred grasps (sum m*_i r_i = 0, the paper's own condition), so the only
    // difference between the two literal forms is the order of (J*_o)^-1 and S(r_i)^T.
    Rng rng(2502);
    double worst_corrected = 0.0;
    double smallest_printed = 1e9;
    double largest_printed = 0.0;
    double worst_library = 0.0;
    for (Index arms = 2; arms <= 6; ++arms) {
        for (int trial = 0; trial < 10; ++trial) {
            const Weights weights = random_weights(arms, rng);
            MatrixXd r = random_offsets(arms, rng);
            r.colwise() -= weighted_centroid(r, weights.mass);
            const MatrixXd g = literal_grasp_matrix(r);
            const MatrixXd corrected = literal_equation_25(r, weights, /*printed_order=*/false);
            const MatrixXd printed = literal_equation_25(r, weights, /*printed_order=*/true);
            const double corrected_error = (g * corrected - MatrixXd::Identity(6, 6)).norm();
            const double printed_error = (g * printed - MatrixXd::Identity(6, 6)).norm();
            worst_corrected = std::max(worst_corrected, corrected_error);
            smallest_printed = std::min(smallest_printed, printed_error);
            largest_printed = std::max(largest_printed, printed_error);
            // With the centroid at the centre of mass the library must be the corrected literal.
            worst_library = std::max(
                worst_library,
                relative_error(coopdyn::weighted_grasp_inverse(r, weights.mass, weights.inertia), corrected));
        }
    }
    std::printf("[ E2 ] centred grasps N = 2..6: |G G+ - I|_F corrected order <= %.2e, printed order in "
                "[%.3f, %.3f]; library vs corrected literal %.2e\n",
                worst_corrected, smallest_printed, largest_printed, worst_library);
    EXPECT_LT(worst_corrected, 1e-13);
    EXPECT_GT(smallest_printed, 1e-3);
    EXPECT_LT(worst_library, 1e-13);
}

// ---------------------------------------------------------------------------------------------
// 2. The O(N) distribution against the matrix, and G hbar^d = h_o^d
// ---------------------------------------------------------------------------------------------

TEST(LoadDistribution, EqualsMinusGeneralizedInverseTimesWrenchAndReproducesTheObjectWrench)
{
    Rng rng(26);
    double worst_blocks = 0.0;
    double worst_sum = 0.0;
    for (Index arms = 2; arms <= 6; ++arms) {
        for (int trial = 0; trial < 20; ++trial) {
            const MatrixXd r = off_centre_offsets(arms, rng);
            const Weights weights = random_weights(arms, rng);
            const Vector6d object_wrench = 20.0 * random_vector(6, rng);
            const VectorXd desired = coopdyn::load_distribution(r, weights.mass, weights.inertia, object_wrench);
            ASSERT_EQ(desired.size(), 6 * arms);
            const VectorXd via_matrix =
                -(coopdyn::weighted_grasp_inverse(r, weights.mass, weights.inertia) * object_wrench);
            for (Index i = 0; i < arms; ++i) {
                const double error = (desired.segment(6 * i, 6) - via_matrix.segment(6 * i, 6)).norm() /
                                     object_wrench.norm();
                worst_blocks = std::max(worst_blocks, error);
                EXPECT_LT(error, 1e-13) << "N = " << arms << ", arm " << i;
            }
            // The arms apply hbar^d = -h'^d; the literal G must give back the object wrench (26).
            const VectorXd applied = -desired;
            const double sum_error = relative_error(literal_grasp_matrix(r) * applied, object_wrench);
            worst_sum = std::max(worst_sum, sum_error);
            EXPECT_LT(sum_error, 1e-13);

            // The noexcept kernel writes the same into caller storage.
            VectorXd written = VectorXd::Zero(6 * arms);
            EXPECT_TRUE(coopdyn::try_distribute_load(r, weights.mass, weights.inertia, object_wrench, written));
            EXPECT_EQ(written, desired);
        }
    }
    std::printf("[ distribution ] N = 2..6: max |h_i^d + (G+_M h_o^d)_i| / |h_o^d| = %.2e, "
                "max |G hbar^d - h_o^d| / |h_o^d| = %.2e\n",
                worst_blocks, worst_sum);
}

TEST(LoadDistribution, WeightListOverloadsMatchTheLeastNormInverseAndTheStackedForm)
{
    // The overloads in the conventional order (weights, r, ...) take the weights as a list of
    // CentralInertia diag(m*_i I3, J*_i): checked against W G^T (G W G^T)^-1 from the literal G,
    // G hbar^d = h_o^d, and the stacked-weight overloads, N = 1..6, std::vector and std::array.
    Rng rng(2526);
    double worst_inverse = 0.0;
    double worst_sum = 0.0;
    for (Index arms = 1; arms <= 6; ++arms) {
        for (int trial = 0; trial < 10; ++trial) {
            const MatrixXd r = off_centre_offsets(arms, rng);
            const Weights weights = random_weights(arms, rng);
            std::vector<coopdyn::CentralInertia<double>> list;
            for (Index i = 0; i < arms; ++i) {
                list.emplace_back(weights.mass(i), Matrix3d(weights.inertia.block(0, 3 * i, 3, 3)));
            }
            const MatrixXd g = literal_grasp_matrix(r);
            const MatrixXd inverse = coopdyn::weighted_grasp_inverse(list, r);
            const double inverse_error = relative_error(inverse, least_norm_right_inverse(g, weights));
            worst_inverse = std::max(worst_inverse, inverse_error);
            EXPECT_LT(inverse_error, 1e-12) << "N = " << arms;
            EXPECT_LT(max_abs(inverse - coopdyn::weighted_grasp_inverse(r, weights.mass, weights.inertia)), 1e-13);

            const Vector6d object_wrench = 20.0 * random_vector(6, rng);
            const VectorXd desired = coopdyn::load_distribution(list, r, object_wrench);
            const double sum_error = relative_error(g * (-desired), object_wrench);
            worst_sum = std::max(worst_sum, sum_error);
            EXPECT_LT(sum_error, 1e-13);
            VectorXd written = VectorXd::Zero(6 * arms);
            EXPECT_TRUE(coopdyn::try_distribute_load(list, r, object_wrench, written));
            EXPECT_EQ(written, desired);
            EXPECT_LT(max_abs(desired - coopdyn::load_distribution(r, weights.mass, weights.inertia, object_wrench)),
                      1e-12);
        }
    }
    // Fixed size: std::array weights, fixed r and output.
    const Eigen::Matrix<double, 3, 2> r2 = off_centre_offsets(2, rng);
    const std::array<coopdyn::CentralInertia<double>, 2> pair{
        coopdyn::CentralInertia<double>(2.0, Matrix3d(Vector3d(0.1, 0.2, 0.3).asDiagonal())),
        coopdyn::CentralInertia<double>(3.0, Matrix3d(Vector3d(0.3, 0.1, 0.2).asDiagonal()))};
    const Eigen::Matrix<double, 12, 6> fixed_inverse = coopdyn::weighted_grasp_inverse(pair, r2);
    EXPECT_LT(max_abs(literal_grasp_matrix(r2) * fixed_inverse - MatrixXd::Identity(6, 6)), 1e-13);
    std::printf("[ weights as CentralInertia ] N = 1..6: max rel. diff. to W G^T (G W G^T)^-1 = %.2e, "
                "max |G hbar^d - h_o^d| / |h_o^d| = %.2e\n",
                worst_inverse, worst_sum);
}

TEST(LoadDistribution, WeightListOverloadsRefuseBadWeightsNamingTheArm)
{
    Rng rng(11);
    const MatrixXd r = off_centre_offsets(3, rng);
    std::vector<coopdyn::CentralInertia<double>> list(3, coopdyn::CentralInertia<double>(1.0, Matrix3d::Identity()));
    list[2] = coopdyn::CentralInertia<double>(-1.0, Matrix3d::Identity());
    try {
        (void)coopdyn::weighted_grasp_inverse(list, r);
        ADD_FAILURE() << "a negative mass weight was accepted";
    } catch (const coopdyn::InvalidModel& error) {
        EXPECT_EQ(error.parameter(), "mass_weights");
        EXPECT_TRUE(error.has_arm());
        EXPECT_EQ(error.arm(), 2);
    }
    list.pop_back();  // two weights for three arms
    EXPECT_THROW((void)coopdyn::load_distribution(list, r, Vector6d::Zero()), coopdyn::InvalidModel);
}

// ---------------------------------------------------------------------------------------------
// 3. Non-squeezing, against the literal (53)
// ---------------------------------------------------------------------------------------------

TEST(LoadDistribution, LiteralInternalWrenchReferenceIsConsistent)
{
    // The reference itself: KKT and pseudo-inverse forms of (53) agree; the internal part of a
    // general commanded wrench lies in the null space of G (Definition 1) and makes the commanded
    // motion rigid; coopdyn::internal_wrenches (structured form) agrees with it.
    Rng rng(53);
    double worst_forms = 0.0;
    double worst_null_space = 0.0;
    double worst_rigidity = 0.0;
    double worst_library = 0.0;
    double worst_external = 0.0;
    for (Index arms = 2; arms <= 6; ++arms) {
        for (int trial = 0; trial < 8; ++trial) {
            const MatrixXd r = random_offsets(arms, rng);
            MatrixXd inertia(6, 6 * arms);
            for (Index i = 0; i < arms; ++i) {
                inertia.block(0, 6 * i, 6, 6) = random_spd(6, rng, uniform(rng, 0.5, 5.0));
            }
            const Vector3d omega = 1.5 * random_vector(3, rng);
            const VectorXd commanded = 10.0 * random_vector(6 * arms, rng);
            const VectorXd internal = literal_internal_wrench(inertia, r, omega, commanded);
            const double scale = commanded.norm();
            worst_forms = std::max(
                worst_forms, (internal - pseudo_inverse_internal_wrench(inertia, r, omega, commanded)).norm() / scale);
            const MatrixXd g = literal_grasp_matrix(r);
            worst_null_space = std::max(worst_null_space, (g * internal).norm() / scale);
            // M'^-1 (h^x + h_int) satisfies the full (object-referenced) rigid-grasp constraint
            // up to an arbitrary object acceleration: its relative form A' xdd = b'.
            VectorXd acceleration(6 * arms);
            for (Index i = 0; i < arms; ++i) {
                acceleration.segment(6 * i, 6) =
                    inertia.block(0, 6 * i, 6, 6).llt().solve(Vector6d(commanded.segment(6 * i, 6) +
                                                                       internal.segment(6 * i, 6)));
            }
            worst_rigidity = std::max(worst_rigidity, (relative_constraint_matrix(r) * acceleration -
                                                       relative_constraint_bias(r, omega))
                                                          .norm());
            worst_library = std::max(
                worst_library, (coopdyn::internal_wrenches(inertia, r, omega, commanded) - internal).norm() / scale);
            const VectorXd measured = 10.0 * random_vector(6 * arms, rng);
            const VectorXd external = coopdyn::external_wrenches(inertia, r, omega, commanded, measured);
            worst_external = std::max(worst_external, (g * external - g * measured).norm() / measured.norm());
        }
    }
    std::printf("[ (53) reference ] N = 2..6, general SPD M_i, |w| ~ 1.5: KKT vs pinv %.2e, |G h_int|/|h^x| %.2e, "
                "|A' xdd - b'| %.2e, coopdyn::internal_wrenches vs literal %.2e, |G (h_ext - h')| %.2e\n",
                worst_forms, worst_null_space, worst_rigidity, worst_library, worst_external);
    EXPECT_LT(worst_forms, 1e-12);
    EXPECT_LT(worst_null_space, 1e-12);
    EXPECT_LT(worst_rigidity, 1e-11);
    EXPECT_LT(worst_library, 1e-12);
    EXPECT_LT(worst_external, 1e-12);
}

TEST(LoadDistribution, WeightsEqualToTheInertiasDoNotSqueeze)
{
    // With m*_i = m_i, J*_i = J_i the distributed wrenches are hbar_i = M_i a_i for a rigid-body
    // acceleration field a_i (linear f / m*_o at the centroid, angular (J*_o)^-1 t_c). Added to a
    // rigid commanded motion (with nonzero angular velocity) they keep it rigid, so the literal
    // (53) finds no internal wrench. Other weights (equal ones) do squeeze: the check has teeth.
    Rng rng(3);
    double worst_inertia_weights = 0.0;
    double smallest_other_weights = 1e9;
    double worst_library = 0.0;
    for (Index arms = 2; arms <= 6; ++arms) {
        for (int trial = 0; trial < 10; ++trial) {
            const MatrixXd r = off_centre_offsets(arms, rng);
            VectorXd mass(arms);
            MatrixXd rotational(3, 3 * arms);
            for (Index i = 0; i < arms; ++i) {
                mass(i) = uniform(rng, 1.0, 12.0);
                rotational.block(0, 3 * i, 3, 3) = random_spd(3, rng, uniform(rng, 0.05, 0.6), 0.2);
            }
            const MatrixXd inertia = stacked_inertias(mass, rotational);
            const Vector6d object_wrench = 30.0 * random_vector(6, rng);
            const Vector3d omega = 2.0 * random_vector(3, rng);
            // A rigid commanded motion of the end-effectors: xdd_i = G_i^T a_o + b_i(w) (literal).
            const VectorXd rigid = literal_grasp_matrix(r).transpose() * random_vector(6, rng) +
                                   literal_constraint_bias(r, omega);
            VectorXd rigid_wrench(6 * arms);
            for (Index i = 0; i < arms; ++i) {
                rigid_wrench.segment(6 * i, 6) = inertia.block(0, 6 * i, 6, 6) * rigid.segment(6 * i, 6);
            }
            // hSigma_i = M_i xdd_i^rigid - h_i^d (15), h^d from (26).
            const VectorXd desired = coopdyn::load_distribution(r, mass, rotational, object_wrench);
            const VectorXd commanded = rigid_wrench - desired;
            const VectorXd internal = literal_internal_wrench(inertia, r, omega, commanded);
            const double relative = internal.norm() / desired.norm();
            worst_inertia_weights = std::max(worst_inertia_weights, relative);
            EXPECT_LT(relative, 1e-12) << "N = " << arms << ", trial " << trial;
            worst_library = std::max(
                worst_library, (coopdyn::internal_wrenches(inertia, r, omega, commanded) - internal).norm() /
                                   desired.norm());

            const VectorXd equal_desired = coopdyn::load_distribution(
                r, VectorXd::Ones(arms), MatrixXd::Identity(3, 3).replicate(1, arms), object_wrench);
            const VectorXd squeezed = literal_internal_wrench(inertia, r, omega, rigid_wrench - equal_desired);
            smallest_other_weights = std::min(smallest_other_weights, squeezed.norm() / equal_desired.norm());
        }
    }
    std::printf("[ non-squeezing ] N = 2..6, |w| ~ 2 rad/s: weights = inertias: max |h'_int| / |h'^d| = %.2e "
                "(coopdyn::internal_wrenches agrees to %.2e); equal weights: min |h'_int| / |h'^d| = %.3f\n",
                worst_inertia_weights, worst_library, smallest_other_weights);
    EXPECT_LT(worst_library, 1e-12);
    EXPECT_GT(smallest_other_weights, 1e-3);
}

TEST(LoadDistribution, ZeroRotationalWeightsCarryTheTorqueWithForcesOnly)
{
    // A physical corner case that is NOT degenerate: three non-collinear grasp points with
    // J*_i = 0 (point contacts that cannot take torque). J*_o is then the spread alone; the
    // distributed torques must vanish and the forces alone reproduce the object wrench.
    Rng rng(11);
    for (Index arms = 3; arms <= 5; ++arms) {
        const MatrixXd r = off_centre_offsets(arms, rng);
        const VectorXd mass = (random_vector(arms, rng).array() + 2.0).matrix();
        const MatrixXd zero = MatrixXd::Zero(3, 3 * arms);
        const Vector6d object_wrench = 10.0 * random_vector(6, rng);
        const VectorXd desired = coopdyn::load_distribution(r, mass, zero, object_wrench);
        double torque = 0.0;
        for (Index i = 0; i < arms; ++i) {
            torque = std::max(torque, desired.segment(6 * i + 3, 3).norm());
        }
        EXPECT_EQ(torque, 0.0);
        EXPECT_LT(relative_error(literal_grasp_matrix(r) * (-desired), object_wrench), 1e-13);
    }
}

// ---------------------------------------------------------------------------------------------
// 4. Degenerate weights are refused, naming the parameter (and the arm)
// ---------------------------------------------------------------------------------------------

TEST(LoadDistributionValidation, KernelsRefuseDegenerateGraspsAndNonPositiveMassWeights)
{
    Rng rng(404);
    struct Case {
        const char* name;
        MatrixXd r;
    };
    std::vector<Case> degenerate;
    degenerate.push_back({"two arms, J*_i = 0", random_offsets(2, rng)});
    {
        // Three and four points on one line, unevenly spaced, line off the centre of mass.
        const Vector3d base = random_vector(3, rng);
        const Vector3d direction = Vector3d(random_vector(3, rng)).normalized();
        MatrixXd three(3, 3);
        three << base + 0.3 * direction, base - 0.45 * direction, base + 0.8 * direction;
        degenerate.push_back({"three collinear points, J*_i = 0", three});
        MatrixXd four(3, 4);
        four << base, base + 0.2 * direction, base - 0.7 * direction, base + 0.35 * direction;
        degenerate.push_back({"four collinear points, J*_i = 0", four});
    }
    degenerate.push_back({"one arm, J*_1 = 0", random_offsets(1, rng)});
    for (const Case& c : degenerate) {
        const Index arms = c.r.cols();
        const VectorXd mass = VectorXd::Constant(arms, 2.0) + VectorXd::LinSpaced(arms, 0.0, 1.0);
        const MatrixXd zero = MatrixXd::Zero(3, 3 * arms);
        const Vector6d object_wrench = random_vector(6, rng);
        expect_invalid_model([&] { (void)coopdyn::weighted_grasp_inverse(c.r, mass, zero); },
                             {"load distribution", "inertia_weights"}, c.name);
        expect_invalid_model([&] { (void)coopdyn::load_distribution(c.r, mass, zero, object_wrench); },
                             {"load distribution", "inertia_weights"}, c.name);
        VectorXd untouched = VectorXd::Constant(6 * arms, 7.0);
        EXPECT_FALSE(coopdyn::try_distribute_load(c.r, mass, zero, object_wrench, untouched)) << c.name;
        EXPECT_TRUE((untouched.array() == 7.0).all()) << c.name;
        // A positive definite rotational weight of one arm makes the same grasp valid.
        MatrixXd one_rotational = zero;
        one_rotational.block(0, 0, 3, 3) = 0.1 * Matrix3d::Identity();
        const MatrixXd inverse = coopdyn::weighted_grasp_inverse(c.r, mass, one_rotational);
        EXPECT_LT(max_abs(literal_grasp_matrix(c.r) * inverse - MatrixXd::Identity(6, 6)), 1e-12) << c.name;
    }

    // Non-positive mass weight of arm 1 (zero, then negative): the message names the arm.
    const MatrixXd r = random_offsets(3, rng);
    const Weights weights = random_weights(3, rng);
    const Vector6d object_wrench = random_vector(6, rng);
    for (const double bad : {0.0, -1.5}) {
        VectorXd mass = weights.mass;
        mass(1) = bad;
        expect_invalid_model([&] { (void)coopdyn::weighted_grasp_inverse(r, mass, weights.inertia); },
                             {"arm 1", "mass_weights", "positive"}, "weighted_grasp_inverse, m*_1 <= 0");
        expect_invalid_model([&] { (void)coopdyn::load_distribution(r, mass, weights.inertia, object_wrench); },
                             {"arm 1", "mass_weights", "positive"}, "load_distribution, m*_1 <= 0");
        VectorXd untouched = VectorXd::Constant(18, 7.0);
        EXPECT_FALSE(coopdyn::try_distribute_load(r, mass, weights.inertia, object_wrench, untouched));
        EXPECT_TRUE((untouched.array() == 7.0).all());
    }
    // Wrong sizes.
    expect_invalid_model([&] { (void)coopdyn::weighted_grasp_inverse(r, weights.mass.head(2), weights.inertia); },
                         {"mass_weights"}, "weighted_grasp_inverse, 2 mass weights for 3 arms");
    expect_invalid_model(
        [&] { (void)coopdyn::load_distribution(r, weights.mass, weights.inertia.leftCols(6), object_wrench); },
        {"inertia_weights"}, "load_distribution, 3 x 6 inertia weights for 3 arms");
}

/// Condition number lambda_max / lambda_min of J*_o = sum J*_i + sum m*_i S(r'_i) S(r'_i)^T,
/// written out (centroid included).
double literal_rotational_condition(const MatrixXd& r, const Weights& weights)
{
    const Vector3d centroid = weighted_centroid(r, weights.mass);
    Matrix3d total = Matrix3d::Zero();
    for (Index i = 0; i < r.cols(); ++i) {
        const Matrix3d s = hat(Vector3d(r.col(i)) - centroid);
        total += weights.inertia.block(0, 3 * i, 3, 3) + weights.mass(i) * s * s.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Matrix3d> eigen(total);
    return eigen.eigenvalues()(2) / eigen.eigenvalues()(0);
}

TEST(LoadDistributionValidation, EveryDegenerateGraspIsRefusedAndNearlyDegenerateOnesAreNot)
{
    // Exactly degenerate grasps are singular only up to rounding: J*_o comes out with a smallest
    // eigenvalue ~1e-16 of its largest, of either sign. An unpivoted Cholesky test accepted about
    // half of them and returned wrenches of 1e5 N for a 1 N object wrench; all must be refused.
    // Grasps with one point 1 mm off the line are valid (condition of J*_o up to ~1e10 here) and
    // must be accepted. (25) inverts J*_o, so the result can only be as accurate as eps times its
    // condition number: compare with the least-norm inverse computed in long double.
    Rng rng(4040);
    int accepted_degenerate = 0;
    int nearly_degenerate = 0;
    double worst_scaled_error = 0.0;
    double largest_condition = 0.0;
    const double epsilon = std::numeric_limits<double>::epsilon();
    const int trials = 1000;
    for (int trial = 0; trial < trials; ++trial) {
        const Index arms = 2 + trial % 3;
        const Vector3d base = random_vector(3, rng);
        const Vector3d direction = Vector3d(random_vector(3, rng)).normalized();
        MatrixXd r(3, arms);
        for (Index i = 0; i < arms; ++i) {
            r.col(i) = base + uniform(rng, -1.0, 1.0) * direction;
        }
        const Weights weights{random_vector(arms, rng, 0.5, 5.0), MatrixXd::Zero(3, 3 * arms)};
        VectorXd out(6 * arms);
        accepted_degenerate +=
            coopdyn::try_distribute_load(r, weights.mass, weights.inertia, random_vector(6, rng), out) ? 1 : 0;

        // One point moved 1 mm off the line (perpendicular), three or more arms.
        if (arms >= 3) {
            MatrixXd off_line = r;
            const Vector3d normal = direction.cross(Vector3d(random_vector(3, rng))).normalized();
            off_line.col(arms - 1) += 1e-3 * normal;
            const double condition = literal_rotational_condition(off_line, weights);
            largest_condition = std::max(largest_condition, condition);
            const MatrixXd inverse = coopdyn::weighted_grasp_inverse(off_line, weights.mass, weights.inertia);
            const auto reference = least_norm_right_inverse_long_double(off_line, weights);
            const double error = static_cast<double>((inverse.cast<long double>() - reference).norm() /
                                                     reference.norm());
            // First-order rounding bound: each entry of J*_o is a sum of N + 1 rounded terms and the
            // 3x3 factorisation and solve add a few ulps more, so the relative forward error is at
            // most about (N + 3) eps cond(J*_o); the measured constant is printed.
            worst_scaled_error =
                std::max(worst_scaled_error, error / (static_cast<double>(arms + 3) * epsilon * condition));
            ++nearly_degenerate;
        }
    }
    std::printf("[ degenerate ] %d exactly collinear grasps with J*_i = 0 (N = 2..4): %d accepted; %d grasps 1 mm "
                "off the line (cond(J*_o) up to %.1e): all accepted, max rel. error vs long double / ((N + 3) eps "
                "cond) = %.2e\n",
                trials, accepted_degenerate, nearly_degenerate, largest_condition, worst_scaled_error);
    EXPECT_EQ(accepted_degenerate, 0);
    EXPECT_LT(worst_scaled_error, 1.0);
}

/// Random arm parameters with the given grasp offsets in the body frame (random_model_at).
template <typename ModelType>
ModelType build_model(const MatrixXd& offsets_body, Rng& rng)
{
    coopdyn_test::SampleRanges ranges;
    ranges.object.inertia_scale = {0.05, 0.05};
    ranges.impedance.inertia_scale = {0.05, 0.5};
    ranges.impedance.inertia_floor = 0.2;
    ranges.impedance.translational_damping = {20.0, 200.0};
    ranges.impedance.rotational_damping = {1.0, 10.0};
    ranges.impedance.translational_stiffness = {100.0, 600.0};
    ranges.impedance.rotational_stiffness = {10.0, 60.0};
    return coopdyn_test::random_model_at<ModelType>(offsets_body, rng, ranges);
}

TEST(LoadDistributionValidation, ClassRefusesDegenerateWeightsNamingParameterAndArm)
{
    Rng rng(405);
    using Model2 = coopdyn::Model<double, 2>;
    using Model3 = coopdyn::Model<double, 3>;
    using ModelX = coopdyn::Model<double, coopdyn::Dynamic>;
    const Model2 two = build_model<Model2>(random_offsets(2, rng), rng);
    EXPECT_NO_THROW(coopdyn::LoadDistribution<Model2> accepted(two));
    expect_invalid_model(
        [&] {
            coopdyn::LoadDistribution<Model2> refused(two, two.end_effector_masses(),
                                                      Eigen::Matrix<double, 3, 6>::Zero());
        },
        {"load distribution", "inertia_weights", "collinear"}, "LoadDistribution, two arms, J*_i = 0");

    const Model3 three = build_model<Model3>(random_offsets(3, rng), rng);
    {
        Eigen::Vector3d mass = three.end_effector_masses();
        mass(1) = 0.0;
        expect_invalid_model(
            [&] { coopdyn::LoadDistribution<Model3> refused(three, mass, three.end_effector_rotational_inertias()); },
            {"arm 1", "mass_weights", "positive"}, "LoadDistribution, m*_1 = 0");
        Eigen::Matrix<double, 3, 9> inertia = three.end_effector_rotational_inertias();
        inertia.block<3, 3>(0, 6) = -Matrix3d::Identity();
        expect_invalid_model(
            [&] { coopdyn::LoadDistribution<Model3> refused(three, three.end_effector_masses(), inertia); },
            {"arm 2", "inertia_weights"}, "LoadDistribution, J*_2 negative definite");
    }

    // Collinear grasp points along body x with J*_i = diag(1, 1, 0): J*_o is positive definite
    // at the identity orientation, but singular once body x points along world z, where neither
    // the spread nor sum J*_i has stiffness about z. The class refuses, since the weights must
    // serve every orientation; the kernel confirms the singular orientation.
    MatrixXd line(3, 3);
    line << 0.4, -0.1, -0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0;
    const Model3 collinear = build_model<Model3>(line, rng);
    Eigen::Matrix<double, 3, 9> flat = Eigen::Matrix<double, 3, 9>::Zero();
    for (Index i = 0; i < 3; ++i) {
        flat(0, 3 * i) = 1.0;
        flat(1, 3 * i + 1) = 1.0;
    }
    EXPECT_NO_THROW((void)coopdyn::weighted_grasp_inverse(line, collinear.end_effector_masses(), flat));
    const Matrix3d x_to_z = Eigen::AngleAxisd(-0.5 * 3.14159265358979323846, Vector3d::UnitY()).toRotationMatrix();
    ASSERT_LT((x_to_z * Vector3d::UnitX() - Vector3d::UnitZ()).norm(), 1e-15);
    expect_invalid_model(
        [&] { (void)coopdyn::weighted_grasp_inverse(x_to_z * line, collinear.end_effector_masses(), flat); },
        {"inertia_weights"}, "kernel, collinear grasp turned onto the null axis of sum J*_i");
    expect_invalid_model(
        [&] { coopdyn::LoadDistribution<Model3> refused(collinear, collinear.end_effector_masses(), flat); },
        {"inertia_weights", "collinear"}, "LoadDistribution, collinear grasp, sum J*_i singular");
    // With positive definite J*_i the collinear grasp is fine (default weights).
    EXPECT_NO_THROW(coopdyn::LoadDistribution<Model3> accepted(collinear));

    // Dynamic N: sizes are checked at run time.
    const ModelX four = build_model<ModelX>(random_offsets(4, rng), rng);
    expect_invalid_model(
        [&] {
            coopdyn::LoadDistribution<ModelX> refused(four, VectorXd::Ones(3), four.end_effector_rotational_inertias());
        },
        {"mass_weights"}, "LoadDistribution, dynamic N = 4, 3 mass weights");
    expect_invalid_model(
        [&] { coopdyn::LoadDistribution<ModelX> refused(four, VectorXd::Ones(4), MatrixXd::Identity(3, 9)); },
        {"inertia_weights"}, "LoadDistribution, dynamic N = 4, 3 x 9 inertia weights");
}

// ---------------------------------------------------------------------------------------------
// 5. LoadDistribution::distribute: noexcept, equal to the kernel and to the second method
// ---------------------------------------------------------------------------------------------

// Every member of the class templates compiles (fixed and dynamic N, double and float).
}  // namespace
template class coopdyn::LoadDistribution<coopdyn::Model<double, 3>>;
template class coopdyn::LoadDistribution<coopdyn::Model<double, coopdyn::Dynamic>>;
template class coopdyn::LoadDistribution<coopdyn::Model<float, 2>>;
namespace {

template <typename ModelType> void check_distribute_matches_kernel(Index arms, unsigned seed)
{
    Rng rng(seed);
    const ModelType model = build_model<ModelType>(off_centre_offsets(arms, rng), rng);
    const coopdyn::LoadDistribution<ModelType> distribution(model);
    coopdyn::Data<ModelType> data(model);
    coopdyn::Setpoints<double, ModelType::arms_at_compile_time> setpoints(arms);
    static_assert(noexcept(distribution.distribute(data, std::declval<const Vector6d&>(), setpoints)),
                  "LoadDistribution::distribute is on the per-tick path and must be noexcept");
    double worst_kernel = 0.0;
    double worst_second_method = 0.0;
    for (int trial = 0; trial < 20; ++trial) {
        coopdyn::RigidBodyState<double> state;
        state.pose.position = random_vector(3, rng);
        state.pose.orientation = random_unit_quaternion(rng);
        state.twist = random_vector(6, rng);
        coopdyn::grasp_kinematics(model, data, state);
        const Vector6d object_wrench = 25.0 * random_vector(6, rng);
        distribution.distribute(data, object_wrench, setpoints);
        const MatrixXd r = data.grasp_offsets;
        const VectorXd kernel = coopdyn::load_distribution(r, VectorXd(model.end_effector_masses()),
                                                           MatrixXd(model.end_effector_rotational_inertias()),
                                                           object_wrench);
        worst_kernel = std::max(worst_kernel, (VectorXd(setpoints.wrenches) - kernel).norm() / kernel.norm());
        const Weights weights{model.end_effector_masses(), model.end_effector_rotational_inertias()};
        const VectorXd second = -(least_norm_right_inverse(literal_grasp_matrix(r), weights) * object_wrench);
        worst_second_method = std::max(worst_second_method, relative_error(VectorXd(setpoints.wrenches), second));
    }
    std::printf("[ LoadDistribution::distribute ] N = %d (%s): vs kernel %.2e, vs W G^T (G W G^T)^-1 %.2e\n",
                static_cast<int>(arms), ModelType::arms_at_compile_time == coopdyn::Dynamic ? "dynamic" : "fixed",
                worst_kernel, worst_second_method);
    EXPECT_LT(worst_kernel, 1e-15);
    EXPECT_LT(worst_second_method, 1e-12);
}

TEST(LoadDistributionClass, DistributeIsNoexceptAndEqualsTheKernel)
{
    check_distribute_matches_kernel<coopdyn::Model<double, 2>>(2, 71);
    check_distribute_matches_kernel<coopdyn::Model<double, 3>>(3, 72);
    check_distribute_matches_kernel<coopdyn::Model<double, coopdyn::Dynamic>>(5, 73);
}

TEST(LoadDistributionClass, CustomWeightsAreUsedAndACommonScaleDoesNotMatter)
{
    // G+_M is invariant when every weight is scaled by the same factor (it appears in both
    // numerator and (J*_o)^-1, m*_o): tiny and huge weights must neither be refused nor change
    // the distribution.
    Rng rng(99);
    using Model4 = coopdyn::Model<double, 4>;
    const Model4 model = build_model<Model4>(off_centre_offsets(4, rng), rng);
    const Weights weights = random_weights(4, rng);
    coopdyn::Data<Model4> data(model);
    coopdyn::RigidBodyState<double> state;
    state.pose.orientation = random_unit_quaternion(rng);
    coopdyn::grasp_kinematics(model, data, state);
    const Vector6d object_wrench = 10.0 * random_vector(6, rng);
    const VectorXd reference =
        coopdyn::load_distribution(MatrixXd(data.grasp_offsets), weights.mass, weights.inertia, object_wrench);
    for (const double scale : {1.0, 1e-14, 1e10}) {
        const coopdyn::LoadDistribution<Model4> distribution(model, scale * weights.mass, scale * weights.inertia);
        coopdyn::Setpoints<double, 4> setpoints;
        distribution.distribute(data, object_wrench, setpoints);
        const double error = relative_error(VectorXd(setpoints.wrenches), reference);
        std::printf("[ weight scale ] x %.0e: rel. diff. %.2e\n", scale, error);
        EXPECT_LT(error, 1e-13) << "scale " << scale;
    }
}

}  // namespace
