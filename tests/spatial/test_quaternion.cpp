// Tests of coopdyn/spatial/quaternion.hpp (docs/spatial.md, paper (2)-(5), errata E6).
//
// Every reference here is independent of the code under test: exact rotations are built with
// Eigen::AngleAxis, kinematics are integrated with a Runge-Kutta scheme written in this file, and
// the Hamilton product is Eigen's.

#include "coopdyn/spatial/quaternion.hpp"
#include "spatial_references.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iomanip>
#include <random>
#include <sstream>
#include <string>

namespace {

using coopdyn_test::random_vector;
using coopdyn_test::scientific;

using coopdyn::Quaternion;
using coopdyn::Vector3;
using Eigen::Vector4d;
using Quaterniond = Eigen::Quaterniond;
using Vector3d = Eigen::Vector3d;

constexpr double pi = 3.14159265358979323846;

Quaterniond random_quaternion(std::mt19937& rng)
{
    std::normal_distribution<double> normal(0.0, 1.0);
    Vector4d coefficients(normal(rng), normal(rng), normal(rng), normal(rng));
    return Quaterniond(coefficients.normalized());
}

/// Exact exponential exp(v) as a unit quaternion, built from Eigen::AngleAxis (not quaternion_exp).
Quaterniond exact_exp(const Vector3d& rotation_vector)
{
    const double angle = rotation_vector.norm();
    if (angle == 0.0) {
        return Quaterniond::Identity();
    }
    return Quaterniond(Eigen::AngleAxisd(angle, rotation_vector / angle));
}

/// Distance between two quaternions as 4-vectors (no sign identification).
double coefficient_distance(const Quaterniond& a, const Quaterniond& b)
{
    return (a.coeffs() - b.coeffs()).norm();
}

/// Distance between the rotations two quaternions represent (q and -q identified).
double rotation_distance(const Quaterniond& a, const Quaterniond& b)
{
    return std::min((a.coeffs() - b.coeffs()).norm(), (a.coeffs() + b.coeffs()).norm());
}

/// Classical RK4 written out for qdot = f(q), fixed step, no renormalisation.
Quaterniond integrate_rk4(const std::function<Vector4d(const Vector4d&)>& f, const Quaterniond& q0,
                          double duration, int steps)
{
    const double h = duration / steps;
    Vector4d y = q0.coeffs();
    for (int k = 0; k < steps; ++k) {
        const Vector4d k1 = f(y);
        const Vector4d k2 = f(y + 0.5 * h * k1);
        const Vector4d k3 = f(y + 0.5 * h * k2);
        const Vector4d k4 = f(y + h * k3);
        y += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    return Quaterniond(y);
}

std::function<Vector4d(const Vector4d&)> world_field(const Vector3d& omega)
{
    return [omega](const Vector4d& y) -> Vector4d {
        return coopdyn::quaternion_derivative_world(Quaterniond(y), omega).coeffs();
    };
}

std::function<Vector4d(const Vector4d&)> body_field(const Vector3d& omega_body)
{
    return [omega_body](const Vector4d& y) -> Vector4d {
        return coopdyn::quaternion_derivative_body(Quaterniond(y), omega_body).coeffs();
    };
}

// --- Kinematics: world-frame and body-frame maps ---------------------------------------------

TEST(QuaternionDerivative, WorldMapIntegratesToLeftExponential)
{
    std::mt19937 rng(20240601);
    double worst = 0.0;
    for (int trial = 0; trial < 10; ++trial) {
        const Quaterniond q0 = random_quaternion(rng);
        const Vector3d omega = random_vector(rng, 2.0);
        const double duration = 1.0;
        const Quaterniond integrated = integrate_rk4(world_field(omega), q0, duration, 1000);
        // Continuous solution from q0: the sign is fixed, so compare coefficients directly.
        const Quaterniond exact = exact_exp(omega * duration) * q0;
        worst = std::max(worst, coefficient_distance(integrated, exact));
        EXPECT_LT(coefficient_distance(integrated, exact), 1e-11) << "trial " << trial;
    }
    RecordProperty("worst_rk4_error", scientific(worst));
}

TEST(QuaternionDerivative, BodyMapIntegratesToRightExponential)
{
    std::mt19937 rng(20240602);
    double worst = 0.0;
    for (int trial = 0; trial < 10; ++trial) {
        const Quaterniond q0 = random_quaternion(rng);
        const Vector3d omega_body = random_vector(rng, 2.0);
        const double duration = 1.0;
        const Quaterniond integrated = integrate_rk4(body_field(omega_body), q0, duration, 1000);
        const Quaterniond exact = q0 * exact_exp(omega_body * duration);
        worst = std::max(worst, coefficient_distance(integrated, exact));
        EXPECT_LT(coefficient_distance(integrated, exact), 1e-11) << "trial " << trial;
    }
    RecordProperty("worst_rk4_error", scientific(worst));
}

TEST(QuaternionDerivative, BodyMapEqualsWorldMapWithRotatedOmega)
{
    // omega = R(q) omega_body: both maps give the same qdot.
    std::mt19937 rng(20240603);
    for (int trial = 0; trial < 20; ++trial) {
        const Quaterniond q = random_quaternion(rng);
        const Vector3d omega_body = random_vector(rng, 3.0);
        const Vector3d omega = q.toRotationMatrix() * omega_body;
        const Quaterniond world = coopdyn::quaternion_derivative_world(q, omega);
        const Quaterniond body = coopdyn::quaternion_derivative_body(q, omega_body);
        EXPECT_LT((world.coeffs() - body.coeffs()).norm(), 1e-15 * 10);
        // Closed forms 1/2 [0; w] (x) q and 1/2 q (x) [0; w_b] with Eigen's Hamilton product.
        const Quaterniond pure_world(0.0, omega.x(), omega.y(), omega.z());
        const Quaterniond pure_body(0.0, omega_body.x(), omega_body.y(), omega_body.z());
        EXPECT_LT((world.coeffs() - 0.5 * (pure_world * q).coeffs()).norm(), 1e-15 * 10);
        EXPECT_LT((body.coeffs() - 0.5 * (q * pure_body).coeffs()).norm(), 1e-15 * 10);
    }
}

TEST(QuaternionDerivative, WorldMapWithBodyOmegaIsWrong_ErratumE6)
{
    // Feeding a body-frame angular velocity to the world-frame map (the printed (3) read the
    // other way round) integrates to exp(w_b t) (x) q0 instead of q0 (x) exp(w_b t).
    const Quaterniond q0(Eigen::AngleAxisd(1.1, Vector3d(1.0, 2.0, -0.5).normalized()));
    const Vector3d omega_body(0.3, -1.2, 0.8);
    const Quaterniond exact = q0 * exact_exp(omega_body);
    const Quaterniond right = integrate_rk4(body_field(omega_body), q0, 1.0, 1000);
    const Quaterniond wrong = integrate_rk4(world_field(omega_body), q0, 1.0, 1000);
    EXPECT_LT(rotation_distance(right, exact), 1e-11);
    EXPECT_GT(rotation_distance(wrong, exact), 0.1);
    // The wrong one is exactly the left exponential, i.e. a rotation about the world axis.
    EXPECT_LT(rotation_distance(wrong, exact_exp(omega_body) * q0), 1e-11);
    // Angle between the two results, for the record: clearly not a rounding effect.
    const double angle = Eigen::AngleAxisd(wrong * exact.conjugate()).angle();
    EXPECT_GT(angle, 0.2);
    RecordProperty("wrong_map_angle_error_rad", scientific(angle));
    RecordProperty("right_map_error", scientific(rotation_distance(right, exact)));
}

TEST(QuaternionDerivative, WorldAndBodyMapsAgreeOnlyWhenOmegaIsInvariant)
{
    // Control for E6: with q0 = identity the frames coincide, so the maps agree.
    const Vector3d omega(0.3, -1.2, 0.8);
    const Quaterniond world = coopdyn::quaternion_derivative_world(Quaterniond::Identity(), omega);
    const Quaterniond body = coopdyn::quaternion_derivative_body(Quaterniond::Identity(), omega);
    EXPECT_EQ(world.coeffs(), body.coeffs());
}

// --- Left-multiplication matrix Q(q) (4) -----------------------------------------------------

TEST(QuaternionLeftMatrix, MultipliesLikeHamiltonProduct)
{
    std::mt19937 rng(20240604);
    for (int trial = 0; trial < 20; ++trial) {
        const Quaterniond q = random_quaternion(rng);
        std::normal_distribution<double> normal(0.0, 1.0);
        const Quaterniond p(normal(rng), normal(rng), normal(rng), normal(rng));  // (w, x, y, z)
        const Eigen::Matrix4d Q = coopdyn::quaternion_left_matrix(q);
        const Vector4d p_wxyz(p.w(), p.x(), p.y(), p.z());
        const Quaterniond qp = q * p;
        const Vector4d expected(qp.w(), qp.x(), qp.y(), qp.z());
        EXPECT_LT((Q * p_wxyz - expected).norm(), 1e-14) << "trial " << trial;
        // For a unit q, Q(q) is orthogonal (|q (x) p| = |p|).
        EXPECT_LT((Q.transpose() * Q - Eigen::Matrix4d::Identity()).norm(), 1e-14);
    }
}

TEST(QuaternionLeftMatrix, BodyDerivativeIsHalfQTimesPureOmega)
{
    // The printed (3): qdot = 1/2 Q(q) [0; w] is the body-frame map.
    std::mt19937 rng(20240605);
    const Quaterniond q = random_quaternion(rng);
    const Vector3d omega_body = random_vector(rng, 2.0);
    const Vector4d pure(0.0, omega_body.x(), omega_body.y(), omega_body.z());
    const Vector4d qdot_wxyz = 0.5 * coopdyn::quaternion_left_matrix(q) * pure;
    const Quaterniond body = coopdyn::quaternion_derivative_body(q, omega_body);
    EXPECT_LT((qdot_wxyz - Vector4d(body.w(), body.x(), body.y(), body.z())).norm(), 1e-15 * 10);
}

// --- Exponential map -------------------------------------------------------------------------

TEST(QuaternionExp, MatchesAngleAxisOverManyScales)
{
    std::mt19937 rng(20240606);
    const double angles[] = {3.0, 2.0, 1.0, 0.3, 1e-2, 1e-3, 2e-4, 1.0000001e-4, 1e-4,
                             0.9999999e-4, 5e-5, 1e-6, 1e-9, 1e-200};
    for (const double angle : angles) {
        for (int trial = 0; trial < 5; ++trial) {
            const Vector3d axis = random_vector(rng).normalized();
            const Vector3d v = angle * axis;
            const Quaterniond q = coopdyn::quaternion_exp(v);
            const Quaterniond expected(Eigen::AngleAxisd(angle, axis));
            EXPECT_LT(coefficient_distance(q, expected), 4e-16) << "angle " << angle;
            EXPECT_NEAR(q.norm(), 1.0, 4e-16) << "angle " << angle;
        }
    }
}

TEST(QuaternionExp, ZeroIsIdentity)
{
    const Quaterniond q = coopdyn::quaternion_exp(Vector3d::Zero());
    EXPECT_EQ(q.w(), 1.0);
    EXPECT_EQ(q.vec(), Vector3d::Zero());
}

TEST(QuaternionExp, ContinuousAcrossSeriesThreshold)
{
    // The Taylor branch is used for |v| < 1e-4. Step across the threshold in tiny increments:
    // the result must change smoothly (no jump beyond rounding), and sin(theta/2)/theta must be
    // consistent on both sides.
    const Vector3d axis = Vector3d(0.2, -0.7, 0.4).normalized();
    // Both sides of the threshold are compared with the closed form to a few ulps, which rules
    // out a jump: |v| ~ 1e-4, so sin(theta/2) u has entries ~ 5e-5 (ulp ~ 7e-21).
    double worst_vec = 0.0;
    for (int k = -50; k <= 50; ++k) {
        const double angle = 1e-4 * (1.0 + 1e-9 * k);
        const Quaterniond q = coopdyn::quaternion_exp(angle * axis);
        const Vector3d expected_vec = std::sin(angle / 2.0) * axis;
        worst_vec = std::max(worst_vec, (q.vec() - expected_vec).cwiseAbs().maxCoeff());
        EXPECT_LT((q.vec() - expected_vec).cwiseAbs().maxCoeff(), 5e-20) << "k " << k;
        EXPECT_NEAR(q.w(), std::cos(angle / 2.0), 2.3e-16) << "k " << k;
    }
    RecordProperty("worst_vec_error", scientific(worst_vec));
}

TEST(QuaternionExp, HomomorphismForParallelVectors)
{
    // exp(a u) (x) exp(b u) = exp((a + b) u), crossing the threshold with a tiny a.
    const Vector3d axis = Vector3d(1.0, 1.0, -2.0).normalized();
    const double a = 3e-5;
    const double b = 0.7;
    const Quaterniond product = coopdyn::quaternion_exp(a * axis) * coopdyn::quaternion_exp(b * axis);
    EXPECT_LT(coefficient_distance(product, coopdyn::quaternion_exp((a + b) * axis)), 1e-15);
}

TEST(QuaternionExp, FloatMatchesAngleAxis)
{
    const Eigen::Vector3f axis = Eigen::Vector3f(0.3f, -0.2f, 0.9f).normalized();
    for (const float angle : {2.0f, 0.1f, 1e-3f, 1e-5f, 0.0f}) {
        const Eigen::Quaternionf q = coopdyn::quaternion_exp((angle * axis).eval());
        const Eigen::Quaternionf expected(Eigen::AngleAxisf(angle, axis));
        EXPECT_LT((q.coeffs() - expected.coeffs()).norm(), 1e-6f) << "angle " << angle;
    }
}

// --- Orientation error and rotational stiffness torque (5), potential (39) --------------------

TEST(OrientationError, IsRelativeRotationInWorldFrame)
{
    std::mt19937 rng(20240607);
    for (int trial = 0; trial < 20; ++trial) {
        const Quaterniond desired = random_quaternion(rng);
        const Vector3d axis = random_vector(rng).normalized();
        const double angle = 0.1 + 2.9 * (trial / 19.0);
        const Quaterniond delta(Eigen::AngleAxisd(angle, axis));
        const Quaterniond q = delta * desired;
        const Quaterniond error = coopdyn::orientation_error(q, desired);
        EXPECT_LT(rotation_distance(error, delta), 1e-14);
        // As rotation matrices: R(dq) = R R_d^T.
        const Eigen::Matrix3d expected = q.toRotationMatrix() * desired.toRotationMatrix().transpose();
        EXPECT_LT((error.toRotationMatrix() - expected).norm(), 1e-14);
    }
}

TEST(RotationalStiffnessTorque, IsKappaSinThetaAxisAndSignInvariant)
{
    std::mt19937 rng(20240608);
    const double kappas[] = {0.5, 50.0, 170.0};
    // Angles beyond pi included: kappa sin(theta) u holds for every theta (it is the same
    // rotation as 2 pi - theta about -u).
    const double angles[] = {1e-6, 0.01, 0.5, 1.0, pi / 2, 2.0, 3.0, pi - 1e-6, 4.0, 5.5};
    for (const double kappa : kappas) {
        for (const double angle : angles) {
            const Quaterniond desired = random_quaternion(rng);
            const Vector3d axis = random_vector(rng).normalized();
            const Quaterniond q = Quaterniond(Eigen::AngleAxisd(angle, axis)) * desired;
            const Vector3d expected = kappa * std::sin(angle) * axis;
            const Vector3d torque =
                coopdyn::rotational_stiffness_torque(coopdyn::orientation_error(q, desired), kappa);
            const double tolerance = 1e-13 * kappa;
            EXPECT_LT((torque - expected).norm(), tolerance) << "kappa " << kappa << " angle " << angle;

            // q -> -q, qd -> -qd, both: same rotation, same torque.
            const Quaterniond minus_q(-q.coeffs());
            const Quaterniond minus_desired(-desired.coeffs());
            for (const auto& pair : {std::make_pair(minus_q, desired), std::make_pair(q, minus_desired),
                                     std::make_pair(minus_q, minus_desired)}) {
                const Vector3d flipped = coopdyn::rotational_stiffness_torque(
                    coopdyn::orientation_error(pair.first, pair.second), kappa);
                EXPECT_LT((flipped - expected).norm(), tolerance);
            }

            // Potential kappa (1 - cos theta), also sign invariant.
            const double potential =
                coopdyn::rotational_potential(coopdyn::orientation_error(q, desired), kappa);
            EXPECT_NEAR(potential, kappa * (1.0 - std::cos(angle)), 1e-13 * kappa);
            EXPECT_NEAR(coopdyn::rotational_potential(coopdyn::orientation_error(minus_q, desired), kappa),
                        potential, 1e-13 * kappa);
        }
    }
}

TEST(RotationalStiffnessTorque, ZeroErrorGivesZeroTorque)
{
    std::mt19937 rng(20240609);
    const Quaterniond q = random_quaternion(rng);
    const Vector3d torque = coopdyn::rotational_stiffness_torque(coopdyn::orientation_error(q, q), 10.0);
    EXPECT_LT(torque.norm(), 1e-14);
    const Vector3d flipped = coopdyn::rotational_stiffness_torque(
        coopdyn::orientation_error(Quaterniond(-q.coeffs()), q), 10.0);
    EXPECT_LT(flipped.norm(), 1e-14);
}

}  // namespace
