// Tests of coopdyn/spatial/spatial_vector.hpp (Motion, Force, centripetal_acceleration) and of the
// logarithm map quaternion_log of coopdyn/spatial/quaternion.hpp (docs/spatial.md, paper (10),
// (11), (13), (24)).
//
// References are independent of the code under test: the literal 6x6 grasp map
// G(r) = [[I3, 0], [S(r), I3]] written out here, Eigen's stacked Vector6 arithmetic, central
// finite differences of rigid motions built with Eigen::AngleAxis (velocity of a body point,
// centripetal acceleration), Eigen::AngleAxis for the logarithm; typed over double and float,
// autodiff derivatives against central differences.

#include "coopdyn/config.hpp"
#include "coopdyn/spatial/quaternion.hpp"
#include "coopdyn/spatial/spatial_vector.hpp"
#include "spatial_references.hpp"

#include <unsupported/Eigen/AutoDiff>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <random>
#include <sstream>
#include <string>

// Every non-template member compiles for the supported scalars.
template struct coopdyn::Motion<double>;
template struct coopdyn::Motion<float>;
template struct coopdyn::Force<double>;
template struct coopdyn::Force<float>;
template struct coopdyn::detail::SpatialVectorBase<coopdyn::Motion<double>, double>;
template struct coopdyn::detail::SpatialVectorBase<coopdyn::Motion<float>, float>;
template struct coopdyn::detail::SpatialVectorBase<coopdyn::Force<double>, double>;
template struct coopdyn::detail::SpatialVectorBase<coopdyn::Force<float>, float>;

namespace {

using coopdyn_test::epsilon;
using coopdyn_test::literal_grasp_map;
using coopdyn_test::literal_skew;
using coopdyn_test::random_six;
using coopdyn_test::random_vector;
using coopdyn_test::round_to;
using coopdyn_test::rounded;
using coopdyn_test::scientific;

using coopdyn::Force;
using coopdyn::Motion;
using Eigen::Matrix3d;
using Eigen::Vector3d;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Quaterniond = Eigen::Quaterniond;
using AutoDiff = Eigen::AutoDiffScalar<Eigen::VectorXd>;

constexpr double pi = 3.14159265358979323846;

static_assert(coopdyn::pi<double>() == pi);
static_assert(coopdyn::pi<float>() == static_cast<float>(pi));
static_assert(coopdyn::pi() == pi, "double by default");

Quaterniond random_quaternion(std::mt19937& rng)
{
    std::normal_distribution<double> normal(0.0, 1.0);
    return Quaterniond(Eigen::Vector4d(normal(rng), normal(rng), normal(rng), normal(rng)).normalized());
}

/// Rotation by |v| about v / |v| with Eigen::AngleAxis (independent of quaternion_exp).
Matrix3d angle_axis_rotation(const Vector3d& rotation_vector)
{
    const double angle = rotation_vector.norm();
    return angle == 0.0 ? Matrix3d::Identity() : Eigen::AngleAxisd(angle, rotation_vector / angle).toRotationMatrix();
}

template <typename Scalar> Vector6d to_double(const Motion<Scalar>& m) { return m.vector().template cast<double>(); }
template <typename Scalar> Vector6d to_double(const Force<Scalar>& f) { return f.vector().template cast<double>(); }

double relative_error(const Vector6d& value, const Vector6d& reference)
{
    return (value - reference).norm() / std::max(reference.norm(), std::numeric_limits<double>::min());
}

template <typename Scalar> class SpatialVectorTyped : public ::testing::Test {};
using Scalars = ::testing::Types<double, float>;
TYPED_TEST_SUITE(SpatialVectorTyped, Scalars);

// --- Stacking and vector-space operations ---------------------------------------------------------

TYPED_TEST(SpatialVectorTyped, StackingRoundTripsLinearFirst)
{
    using Scalar = TypeParam;
    using Six = coopdyn::Vector6<Scalar>;
    Six six;
    six << Scalar(1), Scalar(2), Scalar(3), Scalar(4), Scalar(5), Scalar(6);
    const Motion<Scalar> motion = Motion<Scalar>::from(six);
    EXPECT_EQ(motion.linear, coopdyn::Vector3<Scalar>(Scalar(1), Scalar(2), Scalar(3)));
    EXPECT_EQ(motion.angular, coopdyn::Vector3<Scalar>(Scalar(4), Scalar(5), Scalar(6)));
    EXPECT_EQ(motion.vector(), six);
    const Force<Scalar> force = Force<Scalar>::from(six);
    EXPECT_EQ(force.linear, six.template head<3>());
    EXPECT_EQ(force.angular, six.template tail<3>());
    EXPECT_EQ(force.vector(), six);
    // From a segment of a longer stack, and back into another segment.
    Eigen::Matrix<Scalar, 18, 1> stack = Eigen::Matrix<Scalar, 18, 1>::Zero();
    stack.template segment<6>(6) = six;
    EXPECT_EQ(Motion<Scalar>::from(stack.template segment<6>(6)).vector(), six);
    force.write_to(stack.template segment<6>(12));
    EXPECT_EQ(stack.template segment<6>(12), six);
    EXPECT_EQ(stack.template head<6>(), Six::Zero());
    // From two 3-vector expressions.
    EXPECT_EQ(Motion<Scalar>::make(six.template head<3>(), six.template tail<3>()).vector(), six);
    // Zero.
    EXPECT_EQ(Motion<Scalar>().vector(), Six::Zero());
    EXPECT_EQ(Motion<Scalar>::Zero().vector(), Six::Zero());
    EXPECT_EQ(Force<Scalar>::Zero().vector(), Six::Zero());
}

TYPED_TEST(SpatialVectorTyped, ArithmeticMatchesStackedVectors)
{
    using Scalar = TypeParam;
    std::mt19937 rng(21);
    for (int trial = 0; trial < 20; ++trial) {
        const Vector6d a = rounded<Scalar>(random_six(rng, 2.0, 3.0));
        const Vector6d b = rounded<Scalar>(random_six(rng, 0.5, 7.0));
        const double s = round_to<Scalar>(-2.5 + 0.3 * trial);
        const Motion<Scalar> ma = Motion<Scalar>::from(a.cast<Scalar>());
        const Motion<Scalar> mb = Motion<Scalar>::from(b.cast<Scalar>());
        const Force<Scalar> fa = Force<Scalar>::from(a.cast<Scalar>());
        const Force<Scalar> fb = Force<Scalar>::from(b.cast<Scalar>());
        // Sums, differences and negation are exact to one rounding of each entry.
        EXPECT_LT((to_double(ma + mb) - (a + b)).cwiseAbs().maxCoeff(), epsilon<Scalar>() * (a + b).cwiseAbs().maxCoeff());
        EXPECT_LT((to_double(fa - fb) - (a - b)).cwiseAbs().maxCoeff(), epsilon<Scalar>() * (a - b).cwiseAbs().maxCoeff());
        EXPECT_EQ(to_double(-ma), (-a).eval());
        EXPECT_EQ(to_double(-fa), (-a).eval());
        EXPECT_LT(relative_error(to_double(static_cast<Scalar>(s) * ma), s * a), epsilon<Scalar>());
        EXPECT_LT(relative_error(to_double(static_cast<Scalar>(s) * fb), s * b), epsilon<Scalar>());
        Motion<Scalar> accumulated = ma;
        accumulated += mb;
        EXPECT_EQ(accumulated.vector(), (ma + mb).vector());
        accumulated -= mb;
        EXPECT_LT(relative_error(to_double(accumulated), a), 4.0 * epsilon<Scalar>() * (1.0 + b.norm() / a.norm()));
        Force<Scalar> force_sum = fa;
        force_sum += fb;
        EXPECT_EQ(force_sum.vector(), (fa + fb).vector());
        // Power xdot . h.
        EXPECT_NEAR(static_cast<double>(ma.dot(fb)), a.dot(b), 8.0 * epsilon<Scalar>() * a.norm() * b.norm());
    }
}

// --- Change of reference point: G(r)^T (10) and G(r) (24) --------------------------------------

TYPED_TEST(SpatialVectorTyped, MotionAtPointIsTransposedLiteralGraspMap)
{
    using Scalar = TypeParam;
    std::mt19937 rng(22);
    double worst = 0.0;
    for (const double offset : {1e-3, 0.1, 0.45, 2.0, 30.0}) {
        for (int trial = 0; trial < 20; ++trial) {
            const Vector6d twist = rounded<Scalar>(random_six(rng, 1.0, 2.5));
            const Vector3d r = rounded<Scalar>(Vector3d(offset * random_vector(rng).cwiseProduct(Vector3d(1.0, 0.3, 2.0))));
            const Motion<Scalar> motion = Motion<Scalar>::from(twist.cast<Scalar>());
            const coopdyn::Vector3<Scalar> r_s = r.cast<Scalar>();
            const Vector6d expected = literal_grasp_map(r).transpose() * twist;
            const double error = (to_double(motion.at_point(r_s)) - expected).norm() / (twist.norm() * (1.0 + r.norm()));
            worst = std::max(worst, error);
            EXPECT_LT(error, 4.0 * epsilon<Scalar>()) << "offset " << offset;
            // [v + w x r; w] written the other way round.
            EXPECT_LT((Vector6d(to_double(motion.at_point(r_s))).head<3>() - (twist.head<3>() + twist.tail<3>().cross(r))).norm(),
                      4.0 * epsilon<Scalar>() * twist.norm() * (1.0 + r.norm()));
            EXPECT_EQ(motion.at_point(r_s).angular, motion.angular);
        }
    }
    ::testing::Test::RecordProperty("worst_relative_error_over_eps", scientific(worst / epsilon<Scalar>()));
}

TYPED_TEST(SpatialVectorTyped, ForceShiftedIsLiteralGraspMap)
{
    using Scalar = TypeParam;
    std::mt19937 rng(23);
    double worst = 0.0;
    for (const double offset : {1e-3, 0.1, 0.45, 2.0, 30.0}) {
        for (int trial = 0; trial < 20; ++trial) {
            const Vector6d wrench = rounded<Scalar>(random_six(rng, 20.0, 3.0));
            const Vector3d r = rounded<Scalar>(Vector3d(offset * random_vector(rng).cwiseProduct(Vector3d(2.0, 1.0, 0.2))));
            const Force<Scalar> force = Force<Scalar>::from(wrench.cast<Scalar>());
            const coopdyn::Vector3<Scalar> r_s = r.cast<Scalar>();
            const Vector6d expected = literal_grasp_map(r) * wrench;
            const double error = (to_double(force.shifted(r_s)) - expected).norm() / (wrench.norm() * (1.0 + r.norm()));
            worst = std::max(worst, error);
            EXPECT_LT(error, 4.0 * epsilon<Scalar>()) << "offset " << offset;
            EXPECT_EQ(force.shifted(r_s).linear, force.linear);
        }
    }
    ::testing::Test::RecordProperty("worst_relative_error_over_eps", scientific(worst / epsilon<Scalar>()));
}

TYPED_TEST(SpatialVectorTyped, PowerIsIndependentOfTheReferencePoint)
{
    // G^T and G are adjoint: (G(r)^T xdot) . h = xdot . (G(r) h), the principle of virtual power.
    using Scalar = TypeParam;
    std::mt19937 rng(24);
    for (int trial = 0; trial < 50; ++trial) {
        const Motion<Scalar> motion = Motion<Scalar>::from(random_six(rng, 1.0, 2.0).cast<Scalar>());
        const Force<Scalar> force = Force<Scalar>::from(random_six(rng, 10.0, 2.0).cast<Scalar>());
        const coopdyn::Vector3<Scalar> r = random_vector(rng, 0.8).cast<Scalar>();
        const double scale = to_double(motion).norm() * to_double(force).norm() * (1.0 + 2.0 * static_cast<double>(r.norm()));
        EXPECT_NEAR(static_cast<double>(motion.at_point(r).dot(force)), static_cast<double>(motion.dot(force.shifted(r))),
                    16.0 * epsilon<Scalar>() * scale);
    }
}

TYPED_TEST(SpatialVectorTyped, ChangesOfReferencePointCompose)
{
    // G(a) G(b) = G(a + b) and G(r) G(-r) = I: shifting by a then b is shifting by a + b.
    using Scalar = TypeParam;
    std::mt19937 rng(25);
    double worst = 0.0;
    for (int trial = 0; trial < 50; ++trial) {
        const Motion<Scalar> motion = Motion<Scalar>::from(random_six(rng, 1.0, 2.0).cast<Scalar>());
        const Force<Scalar> force = Force<Scalar>::from(random_six(rng, 10.0, 2.0).cast<Scalar>());
        const coopdyn::Vector3<Scalar> a = random_vector(rng, 0.7).cast<Scalar>();
        const coopdyn::Vector3<Scalar> b = random_vector(rng, 1.3).cast<Scalar>();
        const coopdyn::Vector3<Scalar> sum = a + b;
        const double motion_scale = to_double(motion).norm() * 3.0;
        const double force_scale = to_double(force).norm() * 3.0;
        const double motion_error = (to_double(motion.at_point(a).at_point(b)) - to_double(motion.at_point(sum))).norm() / motion_scale;
        const double force_error = (to_double(force.shifted(a).shifted(b)) - to_double(force.shifted(sum))).norm() / force_scale;
        worst = std::max({worst, motion_error, force_error});
        EXPECT_LT(motion_error, 4.0 * epsilon<Scalar>());
        EXPECT_LT(force_error, 4.0 * epsilon<Scalar>());
        const coopdyn::Vector3<Scalar> minus_a = -a;
        EXPECT_LT((to_double(motion.at_point(a).at_point(minus_a)) - to_double(motion)).norm() / motion_scale, 4.0 * epsilon<Scalar>());
        EXPECT_LT((to_double(force.shifted(a).shifted(minus_a)) - to_double(force)).norm() / force_scale, 4.0 * epsilon<Scalar>());
        // Shifting by zero changes nothing, bit for bit.
        EXPECT_EQ(motion.at_point(coopdyn::Vector3<Scalar>::Zero()).vector(), motion.vector());
        EXPECT_EQ(force.shifted(coopdyn::Vector3<Scalar>::Zero()).vector(), force.vector());
    }
    ::testing::Test::RecordProperty("worst_relative_error_over_eps", scientific(worst / epsilon<Scalar>()));
}

TYPED_TEST(SpatialVectorTyped, CentripetalAccelerationIsOmegaCrossOmegaCrossR)
{
    using Scalar = TypeParam;
    std::mt19937 rng(26);
    for (int trial = 0; trial < 50; ++trial) {
        const Vector3d r = rounded<Scalar>(random_vector(rng, 0.9));
        const Vector3d omega = rounded<Scalar>(random_vector(rng, 4.0));
        const coopdyn::Vector3<Scalar> value = coopdyn::centripetal_acceleration(r.cast<Scalar>(), omega.cast<Scalar>());
        // S(w)^2 r, and -|w|^2 times the part of r orthogonal to w.
        const Vector3d dense = literal_skew(omega) * literal_skew(omega) * r;
        const Vector3d orthogonal = r - omega * omega.dot(r) / omega.squaredNorm();
        const double scale = omega.squaredNorm() * r.norm();
        EXPECT_LT((value.template cast<double>() - dense).norm(), 8.0 * epsilon<Scalar>() * scale);
        EXPECT_LT((dense + omega.squaredNorm() * orthogonal).norm(), 1e-13 * scale);
        // It points inward: no component along w, and r . a = -|w x r|^2.
        EXPECT_NEAR(static_cast<double>(value.template cast<double>().dot(omega)), 0.0, 8.0 * epsilon<Scalar>() * scale * omega.norm());
        EXPECT_NEAR(value.template cast<double>().dot(r), -omega.cross(r).squaredNorm(), 8.0 * epsilon<Scalar>() * scale * r.norm());
    }
}

// --- Rotation: diag(R, R), blkdiag(R, ..., R) and blkdiag(R_1, R_1, ..., R_K, R_K) ---------------

/// blkdiag(R_1, ..., R_n) of the 3x3 blocks given (as columns of `rotations`, 3 x 3n), written out.
Eigen::MatrixXd literal_block_diagonal(const Eigen::MatrixXd& rotations)
{
    const Eigen::Index n = rotations.cols() / 3;
    Eigen::MatrixXd result = Eigen::MatrixXd::Zero(3 * n, 3 * n);
    for (Eigen::Index b = 0; b < n; ++b) {
        result.block<3, 3>(3 * b, 3 * b) = rotations.block<3, 3>(0, 3 * b);
    }
    return result;
}

/// [R, R, ..., R] (n copies) and [R_1, R_1, ..., R_K, R_K]: the 3x3 blocks of the references above.
Eigen::MatrixXd repeated(const Eigen::MatrixXd& rotations, Eigen::Index copies)
{
    Eigen::MatrixXd result(3, rotations.cols() * copies);
    for (Eigen::Index b = 0; b < rotations.cols() / 3; ++b) {
        for (Eigen::Index c = 0; c < copies; ++c) {
            result.block<3, 3>(0, 3 * (copies * b + c)) = rotations.block<3, 3>(0, 3 * b);
        }
    }
    return result;
}

/// rows x cols uniform in [-scale, scale], each entry representable in Scalar.
template <typename Scalar> Eigen::MatrixXd random_matrix(std::mt19937& rng, Eigen::Index rows, Eigen::Index cols, double scale)
{
    std::uniform_real_distribution<double> uniform(-scale, scale);
    Eigen::MatrixXd result(rows, cols);
    for (Eigen::Index k = 0; k < result.size(); ++k) {
        result(k) = round_to<Scalar>(uniform(rng));
    }
    return result;
}

/// max over columns of |value - reference| / |in| (column norms): the error of a rotated stack
/// relative to what was rotated.
double column_error(const Eigen::MatrixXd& value, const Eigen::MatrixXd& reference, const Eigen::MatrixXd& in)
{
    double worst = 0.0;
    for (Eigen::Index j = 0; j < in.cols(); ++j) {
        worst = std::max(worst, (value.col(j) - reference.col(j)).norm() / in.col(j).norm());
    }
    return worst;
}

TYPED_TEST(SpatialVectorTyped, RotatedIsTheLiteralBlockDiagonalRotation)
{
    using Scalar = TypeParam;
    std::mt19937 rng(31);
    double worst = 0.0;
    for (int trial = 0; trial < 50; ++trial) {
        const Matrix3d rotation = rounded<Scalar>(coopdyn_test::random_rotation(rng));
        const Vector6d six = rounded<Scalar>(random_six(rng, 3.0, 0.5));
        const Vector6d other = rounded<Scalar>(random_six(rng, 0.2, 4.0));
        const Vector3d r = rounded<Scalar>(random_vector(rng, 0.7));
        const Matrix6d block = literal_block_diagonal(repeated(rotation, 2));
        const coopdyn::Matrix3<Scalar> rotation_s = rotation.cast<Scalar>();
        const Motion<Scalar> motion = Motion<Scalar>::from(six.cast<Scalar>());
        const Force<Scalar> force = Force<Scalar>::from(six.cast<Scalar>());
        // [R v; R w] and [R^T v; R^T w] against the 6x6 products, for both kinds of vector.
        for (const double error : {relative_error(to_double(motion.rotated(rotation_s)), block * six),
                                   relative_error(to_double(force.rotated(rotation_s)), block * six),
                                   relative_error(to_double(motion.rotated_back(rotation_s)), block.transpose() * six),
                                   relative_error(to_double(force.rotated_back(rotation_s)), block.transpose() * six)}) {
            worst = std::max(worst, error);
            EXPECT_LT(error, 4.0 * epsilon<Scalar>());
        }
        // Back and forth (R orthogonal to the rounding of Scalar).
        EXPECT_LT(relative_error(to_double(motion.rotated(rotation_s).rotated_back(rotation_s)), six), 8.0 * epsilon<Scalar>());
        EXPECT_LT(relative_error(to_double(force.rotated_back(rotation_s).rotated(rotation_s)), six), 8.0 * epsilon<Scalar>());
        // Power is frame-independent: (R6 xdot) . (R6 h) = xdot . h.
        const Force<Scalar> wrench = Force<Scalar>::from(other.cast<Scalar>());
        EXPECT_NEAR(static_cast<double>(motion.rotated(rotation_s).dot(wrench.rotated(rotation_s))), six.dot(other),
                    16.0 * epsilon<Scalar>() * six.norm() * other.norm());
        // Rotation commutes with the change of reference point: R6 G(r) = G(R r) R6 ((24) in a
        // turned frame), so shifting then turning equals turning then shifting by R r.
        const coopdyn::Vector3<Scalar> r_s = r.cast<Scalar>();
        const coopdyn::Vector3<Scalar> turned_r = rotation_s * r_s;
        const double shift_scale = six.norm() * (1.0 + r.norm());
        EXPECT_LT((to_double(force.shifted(r_s).rotated(rotation_s)) - to_double(force.rotated(rotation_s).shifted(turned_r))).norm(),
                  16.0 * epsilon<Scalar>() * shift_scale);
        EXPECT_LT(
            (to_double(motion.at_point(r_s).rotated(rotation_s)) - to_double(motion.rotated(rotation_s).at_point(turned_r))).norm(),
            16.0 * epsilon<Scalar>() * shift_scale);
    }
    // The identity changes nothing, bit for bit.
    const Vector6d six = rounded<Scalar>(random_six(rng, 1.0, 1.0));
    const coopdyn::Matrix3<Scalar> identity = coopdyn::Matrix3<Scalar>::Identity();
    EXPECT_EQ(Force<Scalar>::from(six.cast<Scalar>()).rotated(identity).vector(), six.cast<Scalar>());
    EXPECT_EQ(Motion<Scalar>::from(six.cast<Scalar>()).rotated_back(identity).vector(), six.cast<Scalar>());
    ::testing::Test::RecordProperty("worst_relative_error_over_eps", scientific(worst / epsilon<Scalar>()));
}

/// rotate_stack(_back) and rotate_stack_per_block(_back) on K stacked 6-vectors and on 6K x m
/// matrices, sizes fixed (Fixed) or dynamic, against the literal 6K x 6K block-diagonal products.
template <typename Scalar, int K, bool Fixed> double check_stack_rotations(std::mt19937& rng)
{
    constexpr int Rows = Fixed ? 6 * K : Eigen::Dynamic;
    constexpr int Columns = Fixed ? 6 * K - 5 : Eigen::Dynamic;  // the internal-wrench basis' 6(K-1), and one more
    using Stack = Eigen::Matrix<Scalar, Rows, 1>;
    using StackMatrix = Eigen::Matrix<Scalar, Rows, Columns>;
    using Rotations = Eigen::Matrix<Scalar, 3, Fixed ? 3 * K : Eigen::Dynamic>;
    const double tolerance = 4.0 * epsilon<Scalar>();
    double worst = 0.0;
    const auto check = [&](const auto& value, const Eigen::MatrixXd& reference, const Eigen::MatrixXd& in) {
        const double error = column_error(value.template cast<double>(), reference, in);
        worst = std::max(worst, error);
        EXPECT_LT(error, tolerance) << "K " << K << (Fixed ? " fixed" : " dynamic");
    };
    for (int trial = 0; trial < 10; ++trial) {
        const Matrix3d rotation = rounded<Scalar>(coopdyn_test::random_rotation(rng));
        Eigen::MatrixXd rotations(3, 3 * K);
        for (int k = 0; k < K; ++k) {
            rotations.block<3, 3>(0, 3 * k) = rounded<Scalar>(coopdyn_test::random_rotation(rng));
        }
        const Eigen::MatrixXd same = literal_block_diagonal(repeated(rotation, 2 * K));
        const Eigen::MatrixXd each = literal_block_diagonal(repeated(rotations, 2));
        const Eigen::MatrixXd stack = random_matrix<Scalar>(rng, 6 * K, 1, 5.0);
        const Eigen::MatrixXd matrix = random_matrix<Scalar>(rng, 6 * K, 6 * K - 5, 1.0);

        const coopdyn::Matrix3<Scalar> rotation_s = rotation.cast<Scalar>();
        const Rotations rotations_s = rotations.cast<Scalar>();
        const Stack stack_s = stack.cast<Scalar>();
        const StackMatrix matrix_s = matrix.cast<Scalar>();
        Stack out = Stack::Zero(6 * K);
        StackMatrix out_matrix = StackMatrix::Zero(6 * K, 6 * K - 5);

        coopdyn::rotate_stack(rotation_s, stack_s, out);
        check(out, same * stack, stack);
        coopdyn::rotate_stack(rotation_s, matrix_s, out_matrix);
        check(out_matrix, same * matrix, matrix);
        // In place, bit for bit what the out-of-place call gives.
        StackMatrix in_place = matrix_s;
        coopdyn::rotate_stack(rotation_s, in_place, in_place);
        EXPECT_EQ(in_place, out_matrix);
        coopdyn::rotate_stack_back(rotation_s, stack_s, out);
        check(out, same.transpose() * stack, stack);
        coopdyn::rotate_stack_back(rotation_s, matrix_s, out_matrix);
        check(out_matrix, same.transpose() * matrix, matrix);
        coopdyn::rotate_stack_back(rotation_s, in_place, in_place);  // back to the start (R orthogonal to rounding)
        EXPECT_LT(column_error(in_place.template cast<double>(), matrix, matrix), 8.0 * epsilon<Scalar>());

        coopdyn::rotate_stack_per_block(rotations_s, stack_s, out);
        check(out, each * stack, stack);
        coopdyn::rotate_stack_per_block(rotations_s, matrix_s, out_matrix);
        check(out_matrix, each * matrix, matrix);
        coopdyn::rotate_stack_per_block_back(rotations_s, stack_s, out);
        check(out, each.transpose() * stack, stack);
        coopdyn::rotate_stack_per_block_back(rotations_s, matrix_s, out_matrix);
        check(out_matrix, each.transpose() * matrix, matrix);
        in_place = matrix_s;
        coopdyn::rotate_stack_per_block_back(rotations_s, in_place, in_place);
        EXPECT_EQ(in_place, out_matrix);

        // Each block of the stack is Force::rotated of that block; into a segment of a longer
        // stack (expressions in and out).
        Eigen::Matrix<Scalar, Eigen::Dynamic, 1> longer = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>::Zero(6 * K + 12);
        coopdyn::rotate_stack(rotation_s, stack_s, longer.segment(6, 6 * K));
        for (int k = 0; k < K; ++k) {
            EXPECT_EQ(longer.template segment<6>(6 + 6 * k),
                      Force<Scalar>::from(stack_s.template segment<6>(6 * k)).rotated(rotation_s).vector());
        }
        EXPECT_TRUE(longer.template head<6>().isZero(0) && longer.template tail<6>().isZero(0));
    }
    return worst;
}

TYPED_TEST(SpatialVectorTyped, StackRotationsAreTheLiteralBlockDiagonalProducts)
{
    using Scalar = TypeParam;
    std::mt19937 rng(32);
    const double worst = std::max({check_stack_rotations<Scalar, 1, true>(rng), check_stack_rotations<Scalar, 2, true>(rng),
                                   check_stack_rotations<Scalar, 3, true>(rng), check_stack_rotations<Scalar, 4, true>(rng),
                                   check_stack_rotations<Scalar, 1, false>(rng), check_stack_rotations<Scalar, 2, false>(rng),
                                   check_stack_rotations<Scalar, 3, false>(rng), check_stack_rotations<Scalar, 4, false>(rng)});
    ::testing::Test::RecordProperty("worst_relative_error_over_eps", scientific(worst / epsilon<Scalar>()));
}

TEST(SpatialVector, AutodiffDerivativesOfTheRotationsAreExact)
{
    // x -> R6 x is linear: its Jacobian is blkdiag(R, R). And along R(theta) = exp(theta S(u)) R_0,
    // d/dtheta (R x) = S(u) R x: with R's entries carrying dR/dtheta = S(u) R, the autodiff
    // derivative of rotated(R) is [S(u) R v; S(u) R w], of rotated_back(R) [-R^T S(u) v; ...].
    std::mt19937 rng(33);
    for (int trial = 0; trial < 5; ++trial) {
        const Matrix3d rotation = coopdyn_test::random_rotation(rng);
        const Vector3d axis = random_vector(rng).normalized();
        const Vector6d six = random_six(rng, 2.0, 1.0);
        coopdyn::Vector6<AutoDiff> six_ad;
        for (int k = 0; k < 6; ++k) {
            six_ad(k) = AutoDiff(six(k), 7, k);
        }
        const Matrix3d rate = literal_skew(axis) * rotation;
        coopdyn::Matrix3<AutoDiff> rotation_ad;
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                rotation_ad(i, j) = AutoDiff(rotation(i, j), Eigen::VectorXd::Unit(7, 6) * rate(i, j));
            }
        }
        const Force<AutoDiff> turned = Force<AutoDiff>::from(six_ad).rotated(rotation_ad);
        const Motion<AutoDiff> back = Motion<AutoDiff>::from(six_ad).rotated_back(rotation_ad);
        Eigen::Matrix<double, 6, 7> turned_jacobian, back_jacobian;
        for (int i = 0; i < 6; ++i) {
            turned_jacobian.row(i) = turned.vector()(i).derivatives().transpose();
            back_jacobian.row(i) = back.vector()(i).derivatives().transpose();
        }
        const Matrix6d block = literal_block_diagonal(repeated(rotation, 2));
        EXPECT_LT((turned_jacobian.leftCols<6>() - block).norm(), 1e-15);
        EXPECT_LT((back_jacobian.leftCols<6>() - block.transpose()).norm(), 1e-15);
        const Matrix6d block_rate = literal_block_diagonal(repeated(rate, 2));
        EXPECT_LT((turned_jacobian.col(6) - block_rate * six).norm(), 1e-14 * six.norm());
        EXPECT_LT((back_jacobian.col(6) - block_rate.transpose() * six).norm(), 1e-14 * six.norm());
        // The stacked form, on a dynamic-size autodiff stack of two.
        Eigen::Matrix<AutoDiff, Eigen::Dynamic, 1> stack(12), stack_out(12);
        stack << six_ad, six_ad;
        coopdyn::rotate_stack(rotation_ad, stack, stack_out);
        for (int i = 0; i < 12; ++i) {
            EXPECT_EQ(stack_out(i).value(), turned.vector()(i % 6).value());
            EXPECT_EQ(stack_out(i).derivatives(), turned.vector()(i % 6).derivatives());
        }
    }
}

// --- Finite differences of rigid motions ---------------------------------------------------------

TEST(SpatialVector, AtPointIsTheVelocityOfTheBodyPoint_FiniteDifferences)
{
    // A body moves with p(t) = p0 + v t and R(t) = exp(S(w) t) R0 (w in {w}); the point fixed in the
    // body at r = R0 r_body from the reference point is at x(t) = p(t) + R(t) r_body. Its
    // velocity by central differences is the linear part of [v; w].at_point(r).
    std::mt19937 rng(27);
    double worst = 0.0;
    for (int trial = 0; trial < 30; ++trial) {
        const Vector3d p0 = random_vector(rng, 2.0);
        const Matrix3d rotation0 = random_quaternion(rng).toRotationMatrix();
        const Vector3d v = random_vector(rng, 1.5);
        const Vector3d w = random_vector(rng, 3.0);
        const Vector3d r_body = random_vector(rng, 0.6).cwiseProduct(Vector3d(1.0, 0.2, 1.7));
        const auto position = [&](double t) {
            return Vector3d(p0 + v * t + angle_axis_rotation(w * t) * rotation0 * r_body);
        };
        const double h = 1e-5;
        const Vector3d velocity = (position(h) - position(-h)) / (2.0 * h);
        Vector6d twist;
        twist << v, w;
        const Motion<double> at_point = Motion<double>::from(twist).at_point(Vector3d(rotation0 * r_body));
        const double error = (at_point.linear - velocity).norm() / velocity.norm();
        worst = std::max(worst, error);
        EXPECT_LT(error, 1e-8);
    }
    RecordProperty("worst_relative_error_vs_central_differences", scientific(worst));
}

TEST(SpatialVector, CentripetalAccelerationIsTheSecondDerivative_FiniteDifferences)
{
    // A point at r from the reference point of a body spinning at constant w (no angular or linear
    // acceleration): x(t) = exp(S(w) t) r, xdd(0) = w x (w x r), by second central differences.
    std::mt19937 rng(28);
    double worst = 0.0;
    for (int trial = 0; trial < 30; ++trial) {
        const Vector3d r = random_vector(rng, 0.8);
        const Vector3d w = random_vector(rng, 3.0);
        const auto position = [&](double t) { return Vector3d(angle_axis_rotation(w * t) * r); };
        const double h = 1e-4;
        const Vector3d acceleration = (position(h) - 2.0 * position(0.0) + position(-h)) / (h * h);
        const Vector3d value = coopdyn::centripetal_acceleration(r, w);
        const double error = (value - acceleration).norm() / value.norm();
        worst = std::max(worst, error);
        EXPECT_LT(error, 1e-6);
    }
    RecordProperty("worst_relative_error_vs_central_differences", scientific(worst));
}

TEST(SpatialVector, AutodiffDerivativesOfTheShiftsMatchCentralDifferences)
{
    // d/dr of [v + w x r; w] and [f; t + r x f]: exact (-S(w) and -S(f)), and central differences.
    std::mt19937 rng(29);
    for (int trial = 0; trial < 5; ++trial) {
        const Vector6d twist = random_six(rng, 1.0, 2.0);
        const Vector6d wrench = random_six(rng, 10.0, 1.0);
        const Vector3d r = random_vector(rng, 0.5);
        coopdyn::Vector3<AutoDiff> r_ad;
        for (int k = 0; k < 3; ++k) {
            r_ad(k) = AutoDiff(r(k), 3, k);
        }
        const Motion<AutoDiff> moved = Motion<AutoDiff>::from(twist.cast<AutoDiff>()).at_point(r_ad);
        const Force<AutoDiff> shifted = Force<AutoDiff>::from(wrench.cast<AutoDiff>()).shifted(r_ad);
        Matrix3d motion_jacobian, force_jacobian;
        for (int i = 0; i < 3; ++i) {
            for (int k = 0; k < 3; ++k) {
                motion_jacobian(i, k) = moved.linear(i).derivatives().size() > 0 ? moved.linear(i).derivatives()(k) : 0.0;
                force_jacobian(i, k) = shifted.angular(i).derivatives().size() > 0 ? shifted.angular(i).derivatives()(k) : 0.0;
            }
        }
        EXPECT_LT((motion_jacobian - literal_skew(twist.tail<3>())).norm(), 1e-15);
        EXPECT_LT((force_jacobian + literal_skew(wrench.head<3>())).norm(), 1e-15);
        for (int k = 0; k < 3; ++k) {
            const double h = 1e-6;
            const Vector3d step = h * Vector3d::Unit(k);
            const Vector3d motion_difference = (Motion<double>::from(twist).at_point(Vector3d(r + step)).linear -
                                               Motion<double>::from(twist).at_point(Vector3d(r - step)).linear) / (2.0 * h);
            const Vector3d force_difference = (Force<double>::from(wrench).shifted(Vector3d(r + step)).angular -
                                               Force<double>::from(wrench).shifted(Vector3d(r - step)).angular) / (2.0 * h);
            EXPECT_LT((motion_jacobian.col(k) - motion_difference).norm(), 1e-8);
            EXPECT_LT((force_jacobian.col(k) - force_difference).norm(), 1e-8);
        }
    }
}

// --- quaternion_log (coopdyn/spatial/quaternion.hpp), the inverse of quaternion_exp -------------

/// Rotation vector from Eigen::AngleAxis (angle in [0, pi]), the reference for quaternion_log.
Vector3d angle_axis_log(const Quaterniond& q)
{
    const Eigen::AngleAxisd angle_axis(q);
    return angle_axis.angle() * angle_axis.axis();
}

TEST(QuaternionLog, InvertsAngleAxisOverManyScales)
{
    std::mt19937 rng(30);
    const double angles[] = {3.14159265358979, 3.1, 3.0, 2.0, 1.0, 0.3, 1e-2, 1e-3, 2e-4, 1.0000001e-4, 1e-4,
                             0.9999999e-4, 5e-5, 1e-6, 1e-9, 1e-200};
    double worst = 0.0;
    for (const double angle : angles) {
        for (int trial = 0; trial < 10; ++trial) {
            const Vector3d axis = random_vector(rng).normalized();
            const Quaterniond q(Eigen::AngleAxisd(angle, axis));
            const Vector3d log = coopdyn::quaternion_log(q);
            const double error = (log - angle * axis).norm() / angle;
            worst = std::max(worst, error);
            EXPECT_LT(error, 4.0 * epsilon<double>()) << "angle " << angle;
            // Both representatives give the same rotation vector (the shorter rotation).
            const Quaterniond minus_q(-q.w(), -q.x(), -q.y(), -q.z());
            EXPECT_EQ(coopdyn::quaternion_log(minus_q), log) << "angle " << angle;
        }
    }
    RecordProperty("worst_relative_error", scientific(worst));
}

TEST(QuaternionLog, MatchesAngleAxisAndRoundTripsWithExpForRandomRotations)
{
    std::mt19937 rng(31);
    double worst_log = 0.0;
    double worst_exp = 0.0;
    double worst_vector = 0.0;
    for (int trial = 0; trial < 500; ++trial) {
        const Quaterniond q = random_quaternion(rng);  // both hemispheres
        const Vector3d log = coopdyn::quaternion_log(q);
        EXPECT_LE(log.norm(), pi * (1.0 + 2.0 * epsilon<double>()));
        worst_log = std::max(worst_log, (log - angle_axis_log(q)).norm());
        // exp(log(q)) = +-q.
        const Quaterniond back = coopdyn::quaternion_exp(log);
        worst_exp = std::max(worst_exp, std::min((back.coeffs() - q.coeffs()).norm(), (back.coeffs() + q.coeffs()).norm()));
        // log(exp(v)) = v for |v| < pi.
        const Vector3d v = random_vector(rng, 1.8);
        if (v.norm() < pi - 1e-3) {
            worst_vector = std::max(worst_vector, (coopdyn::quaternion_log(coopdyn::quaternion_exp(v)) - v).norm());
        }
    }
    EXPECT_LT(worst_log, 8.0 * epsilon<double>());
    EXPECT_LT(worst_exp, 4.0 * epsilon<double>());
    EXPECT_LT(worst_vector, 8.0 * epsilon<double>());
    RecordProperty("worst_error_vs_angle_axis", scientific(worst_log));
    RecordProperty("worst_exp_log_round_trip", scientific(worst_exp));
    RecordProperty("worst_log_exp_round_trip", scientific(worst_vector));
}

TEST(QuaternionLog, NearPiGivesTheShorterRotation)
{
    std::mt19937 rng(32);
    for (const double delta : {1e-2, 1e-5, 1e-8, 1e-12, 0.0}) {
        for (int trial = 0; trial < 5; ++trial) {
            const Vector3d axis = random_vector(rng).normalized();
            // Just below pi: the rotation vector itself.
            const Vector3d below = coopdyn::quaternion_log(Quaterniond(Eigen::AngleAxisd(pi - delta, axis)));
            EXPECT_LT((below - (pi - delta) * axis).norm(), 8.0 * epsilon<double>()) << "delta " << delta;
            // Just above pi (w < 0): the same rotation is pi - delta about -axis. (At delta = 0,
            // cos(pi / 2) rounds to +6e-17: both sides give +pi axis, see the half turn below.)
            if (delta == 0.0) {
                continue;
            }
            const Vector3d above = coopdyn::quaternion_log(Quaterniond(Eigen::AngleAxisd(pi + delta, axis)));
            EXPECT_LT((above + (pi - delta) * axis).norm(), 8.0 * epsilon<double>()) << "delta " << delta;
        }
    }
    // Exactly pi (w = 0): +u pi and -u pi are the same rotation; either is a valid answer, and
    // exp gives the rotation back.
    const Vector3d axis = Vector3d(0.48, -0.6, 0.64);  // unit
    const Quaterniond half_turn(0.0, axis.x(), axis.y(), axis.z());
    const Vector3d log = coopdyn::quaternion_log(half_turn);
    EXPECT_NEAR(log.norm(), pi, 4.0 * epsilon<double>());
    EXPECT_NEAR(std::abs(log.normalized().dot(axis)), 1.0, 4.0 * epsilon<double>());
    const Quaterniond back = coopdyn::quaternion_exp(log);
    EXPECT_LT(std::min((back.coeffs() - half_turn.coeffs()).norm(), (back.coeffs() + half_turn.coeffs()).norm()), 4.0 * epsilon<double>());
}

TEST(QuaternionLog, ContinuousAcrossSeriesThreshold)
{
    // The series branch is taken for sin(theta / 2) < 1e-4, i.e. theta < 2e-4: step across it.
    const Vector3d axis = Vector3d(-0.3, 0.8, 0.5).normalized();
    double worst = 0.0;
    for (int k = -50; k <= 50; ++k) {
        const double angle = 2.0 * std::asin(1e-4) * (1.0 + 1e-9 * k);
        const Quaterniond q(std::cos(angle / 2.0), std::sin(angle / 2.0) * axis.x(), std::sin(angle / 2.0) * axis.y(),
                            std::sin(angle / 2.0) * axis.z());
        const double error = (coopdyn::quaternion_log(q) - angle * axis).norm() / angle;
        worst = std::max(worst, error);
        EXPECT_LT(error, 4.0 * epsilon<double>()) << "k " << k;
    }
    RecordProperty("worst_relative_error", scientific(worst));
}

TEST(QuaternionLog, IdentityIsZero)
{
    EXPECT_EQ(coopdyn::quaternion_log(Quaterniond::Identity()), Vector3d::Zero());
    EXPECT_EQ(coopdyn::quaternion_log(Quaterniond(-1.0, 0.0, 0.0, 0.0)), Vector3d::Zero());
}

TEST(QuaternionLog, DerivativeAtIdentity_FiniteDifferences)
{
    // Through the unit quaternion (sqrt(1 - h^2), h e_k): d log / d eps = 2 I3.
    // Through the rotation vector (AngleAxis(h, e_k)): d log / d v = I3.
    // Through w alone (1 + h, 0), a non-unit quaternion the debug check still accepts: 0.
    const double h = 1e-6;
    for (int k = 0; k < 3; ++k) {
        const Vector3d unit = Vector3d::Unit(k);
        const auto along_eps = [&](double s) {
            return Quaterniond(std::sqrt(1.0 - s * s), s * unit.x(), s * unit.y(), s * unit.z());
        };
        const Vector3d d_eps = (coopdyn::quaternion_log(along_eps(h)) - coopdyn::quaternion_log(along_eps(-h))) / (2.0 * h);
        EXPECT_LT((d_eps - 2.0 * unit).norm(), 1e-9) << "k " << k;
        const Vector3d d_v = (coopdyn::quaternion_log(Quaterniond(Eigen::AngleAxisd(h, unit))) -
                              coopdyn::quaternion_log(Quaterniond(Eigen::AngleAxisd(-h, unit)))) / (2.0 * h);
        EXPECT_LT((d_v - unit).norm(), 1e-9) << "k " << k;
    }
    const Vector3d d_w = (coopdyn::quaternion_log(Quaterniond(1.0 + h, 0.0, 0.0, 0.0)) -
                          coopdyn::quaternion_log(Quaterniond(1.0 - h, 0.0, 0.0, 0.0))) / (2.0 * h);
    EXPECT_EQ(d_w, Vector3d::Zero());
}

TEST(QuaternionLog, AutodiffDerivativeMatchesCentralDifferences)
{
    // The Jacobian of log with respect to the four coefficients (w, x, y, z): at the identity
    // [0 | 2 I3] exactly (the series branch), and along the unit sphere at random and near-identity
    // rotations against central differences.
    const auto jacobian_ad = [](const Quaterniond& q) {
        const coopdyn::Quaternion<AutoDiff> q_ad(AutoDiff(q.w(), 4, 0), AutoDiff(q.x(), 4, 1), AutoDiff(q.y(), 4, 2),
                                                 AutoDiff(q.z(), 4, 3));
        const coopdyn::Vector3<AutoDiff> log = coopdyn::quaternion_log(q_ad);
        Eigen::Matrix<double, 3, 4> jacobian;
        for (int i = 0; i < 3; ++i) {
            jacobian.row(i) = log(i).derivatives().transpose();
        }
        return jacobian;
    };
    Eigen::Matrix<double, 3, 4> at_identity = Eigen::Matrix<double, 3, 4>::Zero();
    at_identity.rightCols<3>() = 2.0 * Matrix3d::Identity();
    EXPECT_EQ(jacobian_ad(Quaterniond::Identity()), at_identity);

    std::mt19937 rng(33);
    double worst = 0.0;
    for (int trial = 0; trial < 30; ++trial) {
        Quaterniond q = random_quaternion(rng);
        if (trial < 10) {  // near the identity, on both sides of the series threshold (theta = 2e-4)
            q = Quaterniond(Eigen::AngleAxisd(std::pow(10.0, -1.0 - 0.6 * trial), random_vector(rng).normalized()));
        }
        const Eigen::Matrix<double, 3, 4> jacobian = jacobian_ad(q);
        // Tangent directions t (t . q = 0): the derivative along the unit sphere, by central
        // differences of log(normalise(q + h t)).
        const Eigen::Vector4d coefficients(q.w(), q.x(), q.y(), q.z());
        const Eigen::Matrix4d projector = Eigen::Matrix4d::Identity() - coefficients * coefficients.transpose();
        for (int k = 0; k < 4; ++k) {
            const Eigen::Vector4d tangent = projector.col(k);
            const double h = 1e-6;
            const auto log_at = [&](double step) {
                const Eigen::Vector4d moved = (coefficients + step * tangent).normalized();
                return coopdyn::quaternion_log(Quaterniond(moved(0), moved(1), moved(2), moved(3)));
            };
            const Vector3d difference = (log_at(h) - log_at(-h)) / (2.0 * h);
            const double error = (jacobian * tangent - difference).norm() / std::max(1.0, difference.norm());
            worst = std::max(worst, error);
            EXPECT_LT(error, 1e-8) << "trial " << trial << " direction " << k;
        }
    }
    RecordProperty("worst_derivative_error_vs_central_differences", scientific(worst));

    // Through quaternion_exp at zero: d log(exp(v)) / dv = I3, exactly.
    coopdyn::Vector3<AutoDiff> v;
    for (int k = 0; k < 3; ++k) {
        v(k) = AutoDiff(0.0, 3, k);
    }
    const coopdyn::Vector3<AutoDiff> round_trip = coopdyn::quaternion_log(coopdyn::quaternion_exp(v));
    for (int i = 0; i < 3; ++i) {
        EXPECT_EQ(round_trip(i).value(), 0.0);
        ASSERT_EQ(round_trip(i).derivatives().size(), 3);
        EXPECT_EQ(Vector3d(round_trip(i).derivatives()), Vector3d::Unit(i));
    }
}

TEST(QuaternionLog, FloatMatchesAngleAxis)
{
    std::mt19937 rng(34);
    double worst = 0.0;
    for (const double angle : {3.1, 2.0, 0.5, 1e-2, 1e-4, 1e-6}) {
        for (int trial = 0; trial < 10; ++trial) {
            const Eigen::Vector3f axis = random_vector(rng).normalized().cast<float>();
            const Eigen::Quaternionf q(Eigen::AngleAxisf(static_cast<float>(angle), axis));
            const Eigen::Vector3f log = coopdyn::quaternion_log(q);
            // Reference: the same float quaternion's rotation vector, in double.
            const Vector3d expected = angle_axis_log(q.cast<double>());
            const double error = (log.cast<double>() - expected).norm() / expected.norm();
            worst = std::max(worst, error);
            EXPECT_LT(error, 8.0 * epsilon<float>()) << "angle " << angle;
        }
    }
    RecordProperty("worst_relative_error_over_eps", scientific(worst / epsilon<float>()));
}

}  // namespace
