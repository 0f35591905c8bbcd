// Tests of coopdyn/spatial/symmetric3.hpp (docs/spatial.md).
//
// References are independent of the code under test: dense Eigen 3x3 products written out here
// (S(a) S(a)^T with a literal skew matrix, R S R^T), Matrix3::determinant, Matrix3::inverse and
// Eigen's LLT, all computed in double from the same (exactly representable) inputs; typed over
// double and float with tolerances scaled by the scalar's epsilon; an autodiff derivative of the
// solve against central differences.

#include "coopdyn/spatial/skew.hpp"
#include "coopdyn/spatial/symmetric3.hpp"
#include "spatial_references.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <unsupported/Eigen/AutoDiff>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <random>
#include <sstream>
#include <string>

// Every non-template member compiles for the supported scalars (and for an autodiff scalar).
template class coopdyn::Symmetric3<double>;
template class coopdyn::Symmetric3<float>;
template class coopdyn::Symmetric3<Eigen::AutoDiffScalar<Eigen::VectorXd>>;

namespace {

using coopdyn_test::epsilon;
using coopdyn_test::literal_skew;
using coopdyn_test::random_rotation;
using coopdyn_test::random_vector;
using coopdyn_test::relative_error;
using coopdyn_test::round_to;
using coopdyn_test::rounded;
using coopdyn_test::scientific;

using coopdyn::Symmetric3;
using Eigen::Matrix3d;
using Eigen::Vector3d;
using AutoDiff = Eigen::AutoDiffScalar<Eigen::VectorXd>;

/// Symmetric (not necessarily definite) random matrix, entries in [-scale, scale].
Matrix3d random_symmetric(std::mt19937& rng, double scale = 1.0)
{
    std::uniform_real_distribution<double> uniform(-scale, scale);
    Matrix3d m;
    for (int j = 0; j < 3; ++j) {
        for (int i = j; i < 3; ++i) {
            m(i, j) = m(j, i) = uniform(rng);
        }
    }
    return m;
}

/// SPD matrix R diag(scale, scale c^u, scale c) R^T with condition number about c.
Matrix3d random_spd(std::mt19937& rng, double scale, double condition)
{
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const Eigen::Vector3d eigenvalues(scale, scale * std::pow(condition, unit(rng)), scale * condition);
    const Matrix3d rotation = random_rotation(rng);
    const Matrix3d m = rotation * eigenvalues.asDiagonal() * rotation.transpose();
    return 0.5 * (m + m.transpose());
}

template <typename Scalar> Symmetric3<Scalar> to_symmetric(const Matrix3d& m) { return Symmetric3<Scalar>(m.cast<Scalar>()); }
template <typename Scalar> Matrix3d dense(const Symmetric3<Scalar>& s) { return s.matrix().template cast<double>(); }

template <typename Scalar> class Symmetric3Typed : public ::testing::Test {};
using Scalars = ::testing::Types<double, float>;
TYPED_TEST_SUITE(Symmetric3Typed, Scalars);

// --- Storage ---------------------------------------------------------------------------------

TYPED_TEST(Symmetric3Typed, EntriesMapToTheLowerTriangleAndItsMirror)
{
    using Scalar = TypeParam;
    const Symmetric3<Scalar> s(Scalar(1), Scalar(2), Scalar(3), Scalar(4), Scalar(5), Scalar(6));
    coopdyn::Matrix3<Scalar> expected;
    expected << Scalar(1), Scalar(2), Scalar(3), Scalar(2), Scalar(4), Scalar(5), Scalar(3), Scalar(5), Scalar(6);
    EXPECT_EQ(s.matrix(), expected);
    EXPECT_EQ(s.trace(), Scalar(11));

    // Only the lower triangle of a dense matrix is read.
    coopdyn::Matrix3<Scalar> lower_only = expected;
    lower_only(0, 1) = Scalar(-100);
    lower_only(0, 2) = Scalar(-200);
    lower_only(1, 2) = Scalar(-300);
    EXPECT_EQ(Symmetric3<Scalar>(lower_only), s);
    EXPECT_EQ(Symmetric3<Scalar>(lower_only).matrix(), expected);

    EXPECT_EQ(Symmetric3<Scalar>().matrix(), coopdyn::Matrix3<Scalar>::Zero());
    EXPECT_EQ(Symmetric3<Scalar>::Zero().matrix(), coopdyn::Matrix3<Scalar>::Zero());
    EXPECT_EQ(Symmetric3<Scalar>::Identity().matrix(), coopdyn::Matrix3<Scalar>::Identity());
    EXPECT_EQ(Symmetric3<Scalar>::scaled_identity(Scalar(2.5)).matrix(),
              (Scalar(2.5) * coopdyn::Matrix3<Scalar>::Identity()).eval());
    EXPECT_EQ(Symmetric3<Scalar>::diagonal(Scalar(1), Scalar(2), Scalar(3)).matrix(),
              coopdyn::Vector3<Scalar>(Scalar(1), Scalar(2), Scalar(3)).asDiagonal().toDenseMatrix());

    // Equality compares every entry.
    Symmetric3<Scalar> other = s;
    EXPECT_TRUE(other == s);
    EXPECT_FALSE(other != s);
    other.zy = Scalar(5.5);
    EXPECT_FALSE(other == s);
    EXPECT_TRUE(other != s);
}

TYPED_TEST(Symmetric3Typed, CastRoundTrips)
{
    using Scalar = TypeParam;
    std::mt19937 rng(3);
    const Matrix3d m = rounded<float>(random_symmetric(rng, 3.0));  // exactly representable in both
    const Symmetric3<Scalar> s = to_symmetric<Scalar>(m);
    EXPECT_EQ(dense(s.template cast<double>()), m);
    EXPECT_EQ(dense(s.template cast<float>()), m);
    EXPECT_EQ(s.template cast<double>().template cast<Scalar>(), s);

    // double -> float rounds each entry once.
    const Matrix3d full = random_symmetric(rng, 3.0);
    EXPECT_EQ(dense(to_symmetric<double>(full).template cast<float>()), rounded<float>(full));
}

// --- Parallel-axis term S(a) S(a)^T ------------------------------------------------------------

TYPED_TEST(Symmetric3Typed, SkewSquareIsTheDenseProductOfLiteralSkewMatrices)
{
    using Scalar = TypeParam;
    std::mt19937 rng(11);
    double worst = 0.0;
    for (const double scale : {1e-3, 0.1, 1.0, 7.0, 1e3}) {
        for (int trial = 0; trial < 20; ++trial) {
            const Vector3d a = rounded<Scalar>(random_vector(rng, scale));
            const Matrix3d expected = literal_skew(a) * literal_skew(a).transpose();
            const coopdyn::Vector3<Scalar> a_s = a.cast<Scalar>();
            const Symmetric3<Scalar> s = Symmetric3<Scalar>::skew_square(a_s);
            const double error = relative_error(dense(s), expected);
            worst = std::max(worst, error);
            EXPECT_LT(error, 4.0 * epsilon<Scalar>()) << "scale " << scale;
            // skew_gram is the same matrix, dense.
            EXPECT_EQ(coopdyn::skew_gram(a_s), s.matrix());
            // |a|^2 I3 - a a^T, the other closed form.
            EXPECT_LT(relative_error(dense(s), (a.squaredNorm() * Matrix3d::Identity() - a * a.transpose()).eval()),
                      4.0 * epsilon<Scalar>());
            // Positive semi-definite with a in its null space.
            EXPECT_LT((dense(s) * a).norm(), 8.0 * epsilon<Scalar>() * a.norm() * a.squaredNorm());
        }
    }
    ::testing::Test::RecordProperty("worst_relative_error_over_eps", scientific(worst / epsilon<Scalar>()));
}

TYPED_TEST(Symmetric3Typed, AddSkewSquareAddsTheMassWeightedParallelAxisTerm)
{
    using Scalar = TypeParam;
    std::mt19937 rng(12);
    double worst = 0.0;
    for (int trial = 0; trial < 50; ++trial) {
        std::uniform_real_distribution<double> mass(-5.0, 20.0);  // negative: subtracting a term
        const double m = round_to<Scalar>(mass(rng));
        const Vector3d a = rounded<Scalar>(random_vector(rng, 2.0));
        const Matrix3d start = rounded<Scalar>(random_symmetric(rng, 4.0));
        Symmetric3<Scalar> s = to_symmetric<Scalar>(start);
        s.add_skew_square(static_cast<Scalar>(m), a.cast<Scalar>());
        const Matrix3d expected = start + m * literal_skew(a) * literal_skew(a).transpose();
        const double scale = start.cwiseAbs().maxCoeff() + std::abs(m) * a.squaredNorm();
        const double error = (dense(s) - expected).cwiseAbs().maxCoeff() / scale;
        worst = std::max(worst, error);
        EXPECT_LT(error, 6.0 * epsilon<Scalar>());
    }
    ::testing::Test::RecordProperty("worst_relative_error_over_eps", scientific(worst / epsilon<Scalar>()));
}

// --- Arithmetic, rotation ------------------------------------------------------------------------

TYPED_TEST(Symmetric3Typed, ArithmeticMatchesDenseMatrices)
{
    using Scalar = TypeParam;
    std::mt19937 rng(13);
    const double tolerance = 4.0 * epsilon<Scalar>();
    for (int trial = 0; trial < 20; ++trial) {
        const Matrix3d a = rounded<Scalar>(random_symmetric(rng, 3.0));
        const Matrix3d b = rounded<Scalar>(random_symmetric(rng, 0.5));
        const Vector3d x = rounded<Scalar>(random_vector(rng, 2.0));
        const double s = round_to<Scalar>(-1.7 + 0.1 * trial);
        const Symmetric3<Scalar> sa = to_symmetric<Scalar>(a);
        const Symmetric3<Scalar> sb = to_symmetric<Scalar>(b);

        EXPECT_LT(relative_error(dense(sa + sb), (a + b).eval()), tolerance);
        EXPECT_LT(relative_error(dense(sa - sb), (a - b).eval()), tolerance);
        EXPECT_EQ(dense(-sa), (-a).eval());
        EXPECT_LT(relative_error(dense(static_cast<Scalar>(s) * sa), (s * a).eval()), tolerance);
        Symmetric3<Scalar> accumulated = sa;
        accumulated += sb;
        EXPECT_EQ(accumulated, sa + sb);
        accumulated -= sb;
        EXPECT_LT(relative_error(dense(accumulated), a), tolerance);
        accumulated = sa;
        accumulated *= static_cast<Scalar>(s);
        EXPECT_EQ(accumulated, static_cast<Scalar>(s) * sa);

        const coopdyn::Vector3<Scalar> product = sa * x.cast<Scalar>();
        const Vector3d expected = a * x;
        EXPECT_LT((product.template cast<double>() - expected).norm(), tolerance * a.norm() * x.norm());
    }
}

TYPED_TEST(Symmetric3Typed, RotatedIsRSRTransposeAndPreservesInvariants)
{
    using Scalar = TypeParam;
    std::mt19937 rng(14);
    double worst = 0.0;
    for (int trial = 0; trial < 30; ++trial) {
        const Matrix3d a = rounded<Scalar>(random_symmetric(rng, 2.0));
        const Matrix3d rotation = rounded<Scalar>(random_rotation(rng));
        const Symmetric3<Scalar> s = to_symmetric<Scalar>(a);
        const coopdyn::Matrix3<Scalar> rotation_s = rotation.cast<Scalar>();
        const Symmetric3<Scalar> rotated = s.rotated(rotation_s);
        const Matrix3d expected = rotation * a * rotation.transpose();
        const double error = (dense(rotated) - expected).cwiseAbs().maxCoeff() / a.norm();
        worst = std::max(worst, error);
        EXPECT_LT(error, 10.0 * epsilon<Scalar>());
        // Back with R^T (R is orthogonal to rounding of Scalar).
        const Symmetric3<Scalar> back = rotated.rotated(rotation_s.transpose());
        EXPECT_LT((dense(back) - a).cwiseAbs().maxCoeff() / a.norm(), 20.0 * epsilon<Scalar>());
        // Trace and determinant are similarity invariants.
        EXPECT_NEAR(static_cast<double>(rotated.trace()), a.trace(), 10.0 * epsilon<Scalar>() * a.norm());
        EXPECT_NEAR(static_cast<double>(rotated.determinant()), a.determinant(),
                    30.0 * epsilon<Scalar>() * std::pow(a.norm(), 3.0));
    }
    ::testing::Test::RecordProperty("worst_relative_error_over_eps", scientific(worst / epsilon<Scalar>()));
}

TYPED_TEST(Symmetric3Typed, RotatedBackAndRotatedDiagonalAreTheDenseProducts)
{
    using Scalar = TypeParam;
    std::mt19937 rng(20);
    double worst = 0.0;
    const auto record = [&worst](double error) {
        worst = std::max(worst, error);
        EXPECT_LT(error, 10.0 * epsilon<Scalar>());
    };
    for (int trial = 0; trial < 50; ++trial) {
        const Matrix3d a = rounded<Scalar>(random_symmetric(rng, 2.0));
        const Matrix3d rotation = rounded<Scalar>(random_rotation(rng));
        const Matrix3d second = rounded<Scalar>(random_rotation(rng));
        const Vector3d d = rounded<Scalar>(Vector3d(random_vector(rng, 1.0).cwiseAbs()));
        const Symmetric3<Scalar> s = to_symmetric<Scalar>(a);
        const coopdyn::Matrix3<Scalar> rotation_s = rotation.cast<Scalar>();
        // R^T S R, the dense product.
        record((dense(s.rotated_back(rotation_s)) - rotation.transpose() * a * rotation).cwiseAbs().maxCoeff() / a.norm());
        // R diag(d) R^T, the dense product, and diagonal(d).rotated(R).
        const Symmetric3<Scalar> turned_diagonal = Symmetric3<Scalar>::rotated_diagonal(d.cast<Scalar>(), rotation_s);
        record((dense(turned_diagonal) - rotation * d.asDiagonal() * rotation.transpose()).cwiseAbs().maxCoeff() / d.norm());
        const Symmetric3<Scalar> from_diagonal =
            Symmetric3<Scalar>::diagonal(Scalar(d(0)), Scalar(d(1)), Scalar(d(2))).rotated(rotation_s);
        EXPECT_LT((dense(turned_diagonal) - dense(from_diagonal)).cwiseAbs().maxCoeff() / d.norm(), 10.0 * epsilon<Scalar>());
        // Back and forth, both ways round.
        EXPECT_LT((dense(s.rotated(rotation_s).rotated_back(rotation_s)) - a).cwiseAbs().maxCoeff() / a.norm(),
                  20.0 * epsilon<Scalar>());
        EXPECT_LT((dense(s.rotated_back(rotation_s).rotated(rotation_s)) - a).cwiseAbs().maxCoeff() / a.norm(),
                  20.0 * epsilon<Scalar>());
        // Composition: (R2 R1) S (R2 R1)^T, the dense product of the double rotations.
        const Matrix3d both = second * rotation;
        EXPECT_LT((dense(s.rotated(rotation_s).rotated(second.cast<Scalar>())) - both * a * both.transpose()).cwiseAbs().maxCoeff() /
                      a.norm(),
                  20.0 * epsilon<Scalar>());
        // The rotation of a point-mass parallel-axis term is the term of the rotated point:
        // R S(c) S(c)^T R^T = S(R c) S(R c)^T.
        const Vector3d c = rounded<Scalar>(random_vector(rng, 0.5));
        const Symmetric3<Scalar> turned_term = Symmetric3<Scalar>::skew_square(c.cast<Scalar>()).rotated(rotation_s);
        const Matrix3d term_of_turned = literal_skew(rotation * c) * literal_skew(rotation * c).transpose();
        EXPECT_LT((dense(turned_term) - term_of_turned).cwiseAbs().maxCoeff() / c.squaredNorm(), 20.0 * epsilon<Scalar>());
    }
    // The identity changes nothing, bit for bit.
    const Symmetric3<Scalar> s = to_symmetric<Scalar>(rounded<Scalar>(random_symmetric(rng)));
    EXPECT_EQ(s.rotated(coopdyn::Matrix3<Scalar>::Identity()), s);
    EXPECT_EQ(s.rotated_back(coopdyn::Matrix3<Scalar>::Identity()), s);
    ::testing::Test::RecordProperty("worst_relative_error_over_eps", scientific(worst / epsilon<Scalar>()));
}

// --- Determinant, inverse, solve ----------------------------------------------------------------

TYPED_TEST(Symmetric3Typed, DeterminantAndInverseMatchEigen)
{
    using Scalar = TypeParam;
    std::mt19937 rng(15);
    double worst_inverse = 0.0;
    for (int trial = 0; trial < 50; ++trial) {
        const double scale = std::pow(10.0, -2.0 + 0.1 * trial);
        const Matrix3d a = rounded<Scalar>(random_spd(rng, scale, 20.0));
        const Symmetric3<Scalar> s = to_symmetric<Scalar>(a);
        EXPECT_NEAR(static_cast<double>(s.determinant()), a.determinant(), 30.0 * epsilon<Scalar>() * std::pow(a.norm(), 3.0));
        const Matrix3d expected = a.inverse();
        const double error = relative_error(dense(s.inverse()), expected);
        worst_inverse = std::max(worst_inverse, error);
        EXPECT_LT(error, 20.0 * 20.0 * epsilon<Scalar>()) << "scale " << scale;  // ~ cond eps
        EXPECT_LT((dense(s.inverse()) * a - Matrix3d::Identity()).norm(), 20.0 * 20.0 * epsilon<Scalar>());
        // Against an inverse that does not use cofactors (Eigen's 3x3 inverse does).
        const Matrix3d llt_inverse = a.llt().solve(Matrix3d::Identity());
        EXPECT_LT(relative_error(dense(s.inverse()), llt_inverse), 20.0 * 20.0 * epsilon<Scalar>());
        EXPECT_TRUE(s.inverse().is_positive_definite());
    }
    ::testing::Test::RecordProperty("worst_inverse_relative_error_over_eps", scientific(worst_inverse / epsilon<Scalar>()));
}

TYPED_TEST(Symmetric3Typed, SolveResidualIsAtRoundingForWellConditionedMatrices)
{
    using Scalar = TypeParam;
    std::mt19937 rng(16);
    double worst_residual = 0.0;
    double worst_error = 0.0;
    for (const double scale : {1e-3, 0.05, 1.0, 30.0, 1e4}) {
        for (int trial = 0; trial < 40; ++trial) {
            const Matrix3d a = rounded<Scalar>(random_spd(rng, scale, 10.0));
            const Vector3d b = rounded<Scalar>(random_vector(rng, 5.0));
            const Symmetric3<Scalar> s = to_symmetric<Scalar>(a);
            const Vector3d x = s.solve(b.cast<Scalar>()).template cast<double>();
            const double residual = (a * x - b).norm() / b.norm();
            const Vector3d reference = a.llt().solve(b);
            const double error = (x - reference).norm() / reference.norm();
            worst_residual = std::max(worst_residual, residual);
            worst_error = std::max(worst_error, error);
            EXPECT_LT(residual, 20.0 * epsilon<Scalar>()) << "scale " << scale;
            EXPECT_LT(error, 40.0 * epsilon<Scalar>()) << "scale " << scale;
            // The solve is the inverse applied.
            EXPECT_LT(((s.inverse() * b.cast<Scalar>()).template cast<double>() - x).norm() / x.norm(),
                      40.0 * epsilon<Scalar>());
        }
    }
    ::testing::Test::RecordProperty("worst_relative_residual_over_eps", scientific(worst_residual / epsilon<Scalar>()));
    ::testing::Test::RecordProperty("worst_relative_error_vs_llt_over_eps", scientific(worst_error / epsilon<Scalar>()));
}

/// Solution of a x = b in long double (Eigen's LLT), the accuracy reference for ill-conditioned a.
Vector3d long_double_solve(const Matrix3d& a, const Vector3d& b)
{
    using Matrix3l = Eigen::Matrix<long double, 3, 3>;
    using Vector3l = Eigen::Matrix<long double, 3, 1>;
    const Vector3l x = Matrix3l(a.cast<long double>()).llt().solve(Vector3l(b.cast<long double>()));
    return x.cast<double>();
}

/// A rigid body's rotational inertia about its centre of mass, tr(Sigma) I3 - Sigma for the second
/// moment Sigma = R diag(a^2, b^2, c^2) R^T: its eigenvalues b^2 + c^2, a^2 + c^2, a^2 + b^2 obey
/// the triangle inequality, so at most one of them is small (a rod: a >> b, c).
Matrix3d random_rigid_body_inertia(std::mt19937& rng, double smallest_extent)
{
    std::uniform_real_distribution<double> exponent(std::log10(smallest_extent), 0.0);
    const Vector3d extents(std::pow(10.0, exponent(rng)), std::pow(10.0, exponent(rng)), std::pow(10.0, exponent(rng)));
    const Matrix3d rotation = random_rotation(rng);
    const Matrix3d second_moment = rotation * extents.cwiseAbs2().asDiagonal() * rotation.transpose();
    const Matrix3d inertia = second_moment.trace() * Matrix3d::Identity() - second_moment;
    return 0.5 * (inertia + inertia.transpose());
}

TEST(Symmetric3, SolveErrorIsConditionTimesEpsilonForRigidBodyInertias)
{
    // The accuracy the solver is used at: a rotational inertia (at most one small eigenvalue).
    // Forward error against a long double LLT, divided by cond(S) eps: O(1), like double LLT.
    std::mt19937 rng(17);
    double worst_ratio = 0.0;
    double worst_llt_ratio = 0.0;
    double largest_condition = 0.0;
    for (const double smallest_extent : {1e-1, 1e-2, 1e-3, 1e-4, 1e-5}) {
        for (int trial = 0; trial < 100; ++trial) {
            const Matrix3d a = random_rigid_body_inertia(rng, smallest_extent);
            const Vector3d b = random_vector(rng);
            const Vector3d reference = long_double_solve(a, b);
            const Eigen::Vector3d eigenvalues = Eigen::SelfAdjointEigenSolver<Matrix3d>(a).eigenvalues();
            const double condition = eigenvalues(2) / eigenvalues(0);
            largest_condition = std::max(largest_condition, condition);
            const double unit = condition * epsilon<double>() * reference.norm();
            const double ratio = (to_symmetric<double>(a).solve(b) - reference).norm() / unit;
            worst_ratio = std::max(worst_ratio, ratio);
            worst_llt_ratio = std::max(worst_llt_ratio, (a.llt().solve(b) - reference).norm() / unit);
            EXPECT_LT(ratio, 4.0) << "condition " << condition;
        }
    }
    EXPECT_GT(largest_condition, 1e8);
    RecordProperty("worst_error_over_condition_eps", scientific(worst_ratio));
    RecordProperty("worst_llt_error_over_condition_eps", scientific(worst_llt_ratio));
}

TEST(Symmetric3, SolveErrorForTwoSmallEigenvaluesGrowsLikeConditionSquared)
{
    // The documented limit of the adjugate (Cramer) solve: with two small eigenvalues
    // (lambda_max >> lambda_mid, impossible for a rotational inertia), the error grows like
    // cond(S) (lambda_max / lambda_mid) eps = cond(S)^2 eps here, where LLT stays at cond(S) eps.
    std::mt19937 rng(18);
    double worst_ratio = 0.0;
    double worst_over_condition = 0.0;
    for (const double condition : {1e2, 1e3, 1e4, 1e5, 1e6}) {
        for (int trial = 0; trial < 40; ++trial) {
            const Matrix3d rotation = random_rotation(rng);
            const Matrix3d a = rotation * Vector3d(0.3, 0.3, 0.3 * condition).asDiagonal() * rotation.transpose();
            const Matrix3d symmetric = 0.5 * (a + a.transpose());
            const Vector3d b = random_vector(rng);
            const Vector3d reference = long_double_solve(symmetric, b);
            const double error = (to_symmetric<double>(symmetric).solve(b) - reference).norm() / reference.norm();
            worst_ratio = std::max(worst_ratio, error / (condition * condition * epsilon<double>()));
            worst_over_condition = std::max(worst_over_condition, error / (condition * epsilon<double>()));
            EXPECT_LT(error, condition * condition * epsilon<double>()) << "condition " << condition;
        }
    }
    EXPECT_GT(worst_over_condition, 1e3);  // far worse than cond eps: the limit is real
    RecordProperty("worst_error_over_condition_squared_eps", scientific(worst_ratio));
    RecordProperty("worst_error_over_condition_eps", scientific(worst_over_condition));
}

TEST(Symmetric3, IsPositiveDefiniteBySylvestersCriterion)
{
    using S = Symmetric3<double>;
    EXPECT_TRUE(S::Identity().is_positive_definite());
    EXPECT_TRUE(S::diagonal(1e-12, 3.0, 1e9).is_positive_definite());
    EXPECT_TRUE(S(2.0, -1.0, 0.0, 2.0, -1.0, 2.0).is_positive_definite());  // 1-D Laplacian
    EXPECT_FALSE(S::Zero().is_positive_definite());
    EXPECT_FALSE(S::diagonal(1.0, 1.0, 0.0).is_positive_definite());   // semi-definite
    EXPECT_FALSE(S::diagonal(1.0, -1.0, 1.0).is_positive_definite());  // second minor fails
    EXPECT_FALSE(S::diagonal(-1.0, -1.0, 1.0).is_positive_definite()); // det > 0, first minor fails
    EXPECT_FALSE(S::diagonal(1.0, 1.0, -1.0).is_positive_definite());  // only the determinant fails
    EXPECT_FALSE(S(1.0, 2.0, 0.0, 1.0, 0.0, 1.0).is_positive_definite());  // indefinite 2x2 block
    EXPECT_FALSE((-S::Identity()).is_positive_definite());
    // Rank 2: S(a) S(a)^T is semi-definite, exactly for an axis-aligned a.
    EXPECT_FALSE(S::skew_square(Vector3d(0.0, 0.0, 2.0)).is_positive_definite());

    // Random matrices: agrees with the signs of Eigen's eigenvalues away from singularity.
    std::mt19937 rng(18);
    int definite = 0;
    for (int trial = 0; trial < 200; ++trial) {
        const Matrix3d a = random_symmetric(rng, 1.0) + 0.6 * Matrix3d::Identity();
        const double smallest = Eigen::SelfAdjointEigenSolver<Matrix3d>(a).eigenvalues().minCoeff();
        if (std::abs(smallest) < 1e-9) {
            continue;
        }
        EXPECT_EQ(to_symmetric<double>(a).is_positive_definite(), smallest > 0.0) << a;
        definite += smallest > 0.0 ? 1 : 0;
    }
    EXPECT_GT(definite, 20);   // both outcomes are exercised
    EXPECT_LT(definite, 180);
}

// --- Autodiff --------------------------------------------------------------------------------

TEST(Symmetric3, AutodiffRotatedDerivativeIsTheCommutatorWithTheAxis)
{
    // Along R(theta) = exp(theta S(u)) R_0, X = R S R^T has dX/dtheta = S(u) X - X S(u); with R's
    // entries carrying dR/dtheta = S(u) R the autodiff derivative of rotated(R) must be that, and
    // rotated_back(R) = R^T S R has d/dtheta = -R^T S(u) S R + R^T S S(u) R. Checked also against
    // central differences of the double computation.
    std::mt19937 rng(21);
    for (int trial = 0; trial < 10; ++trial) {
        const Matrix3d a = random_symmetric(rng, 1.5);
        const Matrix3d rotation = random_rotation(rng);
        const Vector3d axis = random_vector(rng).normalized();
        const Matrix3d rate = literal_skew(axis) * rotation;
        coopdyn::Matrix3<AutoDiff> rotation_ad;
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                rotation_ad(i, j) = AutoDiff(rotation(i, j), Eigen::VectorXd::Unit(2, 0) * rate(i, j));  // (size 1 trips g++ 12's -Warray-bounds)
            }
        }
        const Symmetric3<AutoDiff> s_ad = to_symmetric<double>(a).cast<AutoDiff>();
        const Symmetric3<AutoDiff> turned = s_ad.rotated(rotation_ad);
        const Symmetric3<AutoDiff> back = s_ad.rotated_back(rotation_ad);
        const auto derivative = [](const Symmetric3<AutoDiff>& x) {
            Matrix3d result;
            for (int i = 0; i < 3; ++i) {
                for (int j = 0; j < 3; ++j) {
                    result(i, j) = x.matrix()(i, j).derivatives()(0);
                }
            }
            return result;
        };
        const Matrix3d x = rotation * a * rotation.transpose();
        const Matrix3d exact = literal_skew(axis) * x - x * literal_skew(axis);
        EXPECT_LT((derivative(turned) - exact).norm(), 1e-14 * a.norm());
        const Matrix3d exact_back = -rotation.transpose() * literal_skew(axis) * a * rotation +
                                    rotation.transpose() * a * literal_skew(axis) * rotation;
        EXPECT_LT((derivative(back) - exact_back).norm(), 1e-14 * a.norm());
        const double h = 1e-6;
        const auto turned_by = [&](double theta) {
            const Matrix3d r = Eigen::AngleAxisd(theta, axis).toRotationMatrix() * rotation;
            return dense(to_symmetric<double>(a).rotated(r));
        };
        EXPECT_LT((derivative(turned) - (turned_by(h) - turned_by(-h)) / (2.0 * h)).norm(), 1e-8 * a.norm());
    }
}

TEST(Symmetric3, AutodiffSolveDerivativeMatchesCentralDifferences)
{
    // x(p) = S(p)^-1 b with S depending on the six entries p; d x / d p against central differences.
    std::mt19937 rng(19);
    double worst = 0.0;
    for (int trial = 0; trial < 10; ++trial) {
        const Matrix3d a = random_spd(rng, 1.5, 8.0);
        const Vector3d b = random_vector(rng, 2.0);
        const Symmetric3<double> s = to_symmetric<double>(a);
        const double entries[6] = {s.xx, s.yx, s.zx, s.yy, s.zy, s.zz};
        AutoDiff seeded[6];
        for (int k = 0; k < 6; ++k) {
            seeded[k] = AutoDiff(entries[k], 6, k);
        }
        const Symmetric3<AutoDiff> s_ad(seeded[0], seeded[1], seeded[2], seeded[3], seeded[4], seeded[5]);
        const coopdyn::Vector3<AutoDiff> x_ad = s_ad.solve(b.cast<AutoDiff>());
        for (int k = 0; k < 6; ++k) {
            const double step = 1e-6;
            double plus[6], minus[6];
            std::copy(entries, entries + 6, plus);
            std::copy(entries, entries + 6, minus);
            plus[k] += step;
            minus[k] -= step;
            const Vector3d x_plus = Symmetric3<double>(plus[0], plus[1], plus[2], plus[3], plus[4], plus[5]).solve(b);
            const Vector3d x_minus = Symmetric3<double>(minus[0], minus[1], minus[2], minus[3], minus[4], minus[5]).solve(b);
            const Vector3d difference = (x_plus - x_minus) / (2.0 * step);
            Vector3d derivative;
            for (int i = 0; i < 3; ++i) {
                derivative(i) = x_ad(i).derivatives()(k);
            }
            const double error = (derivative - difference).norm() / std::max(difference.norm(), 1.0);
            worst = std::max(worst, error);
            EXPECT_LT(error, 1e-7) << "entry " << k;
            // And the closed form -S^-1 E_k x, with E_k the symmetric unit perturbation of entry k.
            Matrix3d unit = Matrix3d::Zero();
            const int rows[6] = {0, 1, 2, 1, 2, 2};
            const int cols[6] = {0, 0, 0, 1, 1, 2};
            unit(rows[k], cols[k]) = unit(cols[k], rows[k]) = 1.0;
            const Vector3d x = a.llt().solve(b);
            const Vector3d exact = -a.llt().solve(unit * x);
            EXPECT_LT((derivative - exact).norm() / std::max(exact.norm(), 1.0), 1e-12) << "entry " << k;
        }
    }
    RecordProperty("worst_derivative_error_vs_central_differences", scientific(worst));
}

}  // namespace
