// Tests of coopdyn/model/impedance_end_effector.hpp and resolved_acceleration_end_effector.hpp
// (docs/model.md, paper (1), (5), (6), (20)).
//
// References: central finite differences of the potential on SO(3) (perturbations built with
// Eigen::AngleAxis), closed forms kappa (1 - cos theta), and literal re-implementations of (6)
// and (20) with rotation matrices and axis-angle.

#include "coopdyn/model/impedance_end_effector.hpp"
#include "coopdyn/model/resolved_acceleration_end_effector.hpp"

#include "sample_systems.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <random>
#include <sstream>
#include <string>

// Every member compiles.
template struct coopdyn::ImpedanceEndEffector<double>;
template struct coopdyn::ImpedanceEndEffector<float>;
template struct coopdyn::ResolvedAccelerationEndEffector<double>;
template struct coopdyn::ResolvedAccelerationEndEffector<float>;

namespace {

/// Scientific notation for recorded measurements.
std::string scientific(double value)
{
    std::ostringstream stream;
    stream << std::scientific << std::setprecision(2) << value;
    return stream.str();
}

using Matrix3d = Eigen::Matrix3d;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Quaterniond = Eigen::Quaterniond;
using Vector3d = Eigen::Vector3d;
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Pose = coopdyn::Pose<double>;
using coopdyn_test::gaussian_quaternion;
using coopdyn_test::random_vector;
using coopdyn_test::random_vector6;

// random_vector(rng, scale), random_vector6 and gaussian_quaternion: sample_systems.hpp.

Pose random_pose(std::mt19937& rng)
{
    return Pose{random_vector(rng, 0.5), gaussian_quaternion(rng)};
}

Matrix3d random_spd3(std::mt19937& rng)
{
    Matrix3d a;
    a << random_vector(rng), random_vector(rng), random_vector(rng);
    return a * a.transpose() + 0.5 * Matrix3d::Identity();
}

Matrix6d random_matrix6(std::mt19937& rng)
{
    Matrix6d a;
    for (int c = 0; c < 6; ++c) {
        a.col(c) = random_vector6(rng);
    }
    return a;
}

/// World-frame rotation of angle |phi| about phi / |phi| as a quaternion (AngleAxis, not the library).
Quaterniond exact_exp(const Vector3d& phi)
{
    const double angle = phi.norm();
    return angle == 0.0 ? Quaterniond::Identity() : Quaterniond(Eigen::AngleAxisd(angle, phi / angle));
}

coopdyn::ImpedanceEndEffector<double> make_impedance(std::mt19937& rng, double kappa)
{
    coopdyn::ImpedanceEndEffector<double> ee;
    ee.mass = 7.5;
    ee.rotational_inertia = random_spd3(rng);
    ee.translational_damping = 180.0;
    ee.rotational_damping = 12.0;
    ee.translational_stiffness = 300.0;
    ee.rotational_stiffness = kappa;
    return ee;
}

/// sin(theta) u from the axis-angle of a rotation matrix (Eigen::AngleAxis, angle in [0, pi]).
Vector3d sin_angle_axis(const Matrix3d& rotation)
{
    const Eigen::AngleAxisd angle_axis(rotation);
    return std::sin(angle_axis.angle()) * angle_axis.axis();
}

// --- Stiffness wrench (5) is the gradient of the potential -----------------------------------

TEST(ImpedanceEndEffector, StiffnessWrenchIsGradientOfPotential)
{
    std::mt19937 rng(31001);
    const double kappas[] = {0.0, 1.0, 50.0, 170.0};
    const double step = 1e-6;
    double worst_translational = 0.0;
    double worst_rotational = 0.0;
    for (const double kappa : kappas) {
        for (int trial = 0; trial < 25; ++trial) {
            const auto ee = make_impedance(rng, kappa);
            const Pose pose = random_pose(rng);
            const Pose desired = random_pose(rng);
            const Vector6d wrench = ee.stiffness_wrench(pose, desired);

            Vector3d translational_gradient;
            Vector3d rotational_gradient;
            for (int j = 0; j < 3; ++j) {
                const Vector3d e = Vector3d::Unit(j);
                Pose plus = pose;
                Pose minus = pose;
                plus.position += step * e;
                minus.position -= step * e;
                translational_gradient(j) =
                    (ee.potential_energy(plus, desired) - ee.potential_energy(minus, desired)) / (2 * step);
                // World-frame perturbation q(phi) = exp(phi) (x) q.
                plus = pose;
                minus = pose;
                plus.orientation = exact_exp(step * e) * pose.orientation;
                minus.orientation = exact_exp(-step * e) * pose.orientation;
                rotational_gradient(j) =
                    (ee.potential_energy(plus, desired) - ee.potential_energy(minus, desired)) / (2 * step);
            }
            const double translational_error =
                (wrench.head<3>() - translational_gradient).norm() /
                std::max(1.0, wrench.head<3>().norm() + ee.potential_energy(pose, desired));
            // Rounding of the central difference is ~ eps U / step, so scale by the energy too.
            const double energy = ee.potential_energy(pose, desired);
            const double rotational_error =
                (wrench.tail<3>() - rotational_gradient).norm() / std::max(1.0, kappa + energy);
            worst_translational = std::max(worst_translational, translational_error);
            worst_rotational = std::max(worst_rotational, rotational_error);
            EXPECT_LT(translational_error, 1e-8) << "kappa " << kappa << " trial " << trial;
            EXPECT_LT(rotational_error, 1e-8) << "kappa " << kappa << " trial " << trial;
        }
    }
    RecordProperty("worst_translational_relative_error", scientific(worst_translational));
    RecordProperty("worst_rotational_relative_error", scientific(worst_rotational));
}

TEST(ImpedanceEndEffector, BodyFramePerturbationIsNotTheGradient)
{
    // Control: the torque is the gradient for a WORLD-frame perturbation. A body-frame
    // perturbation q (x) exp(phi) gives R^T t instead, which differs for a generic pose.
    std::mt19937 rng(31002);
    const auto ee = make_impedance(rng, 50.0);
    const Pose pose = random_pose(rng);
    const Pose desired = random_pose(rng);
    const double step = 1e-6;
    Vector3d body_gradient;
    for (int j = 0; j < 3; ++j) {
        Pose plus = pose;
        Pose minus = pose;
        plus.orientation = pose.orientation * exact_exp(step * Vector3d::Unit(j));
        minus.orientation = pose.orientation * exact_exp(-step * Vector3d::Unit(j));
        body_gradient(j) =
            (ee.potential_energy(plus, desired) - ee.potential_energy(minus, desired)) / (2 * step);
    }
    const Vector3d torque = ee.stiffness_wrench(pose, desired).tail<3>();
    EXPECT_LT((pose.rotation().transpose() * torque - body_gradient).norm(), 1e-7);
    EXPECT_GT((torque - body_gradient).norm(), 1.0);
}

TEST(ImpedanceEndEffector, PotentialEnergyClosedForm)
{
    std::mt19937 rng(31003);
    for (int trial = 0; trial < 30; ++trial) {
        const double kappa = 10.0 + 5.0 * trial;
        const auto ee = make_impedance(rng, kappa);
        const Pose desired = random_pose(rng);
        const Vector3d axis = random_vector(rng).normalized();
        const double angle = 0.1 * trial;  // 0 .. 2.9 rad
        const Vector3d offset = random_vector(rng, 0.3);
        const Pose pose{desired.position + offset,
                        Quaterniond(Eigen::AngleAxisd(angle, axis)) * desired.orientation};
        const double expected =
            0.5 * ee.translational_stiffness * offset.squaredNorm() + kappa * (1.0 - std::cos(angle));
        EXPECT_NEAR(ee.potential_energy(pose, desired), expected, 1e-12 * std::max(1.0, expected));
        // q -> -q is the same rotation: same energy.
        const Pose flipped{pose.position, Quaterniond(-pose.orientation.coeffs())};
        EXPECT_NEAR(ee.potential_energy(flipped, desired), expected, 1e-12 * std::max(1.0, expected));
    }
}

TEST(ImpedanceEndEffector, InertiaIsBlockDiagonal)
{
    std::mt19937 rng(31004);
    const auto ee = make_impedance(rng, 50.0);
    Matrix6d expected = Matrix6d::Zero();
    expected.topLeftCorner<3, 3>() = ee.mass * Matrix3d::Identity();
    expected.bottomRightCorner<3, 3>() = ee.rotational_inertia;
    EXPECT_EQ(ee.inertia().matrix(), expected);
}

// --- Motion wrench (6), literal re-implementation ---------------------------------------------

TEST(ImpedanceEndEffector, MotionWrenchMatchesLiteralEquation6)
{
    std::mt19937 rng(31005);
    double worst = 0.0;
    for (int trial = 0; trial < 50; ++trial) {
        const double kappa = 5.0 * (trial % 7);
        const auto ee = make_impedance(rng, kappa);
        const Pose pose = random_pose(rng);
        const Pose desired = random_pose(rng);
        const Vector6d twist = random_vector6(rng, 2.0);
        const Vector6d desired_twist = random_vector6(rng, 2.0);
        const Vector6d desired_acceleration = random_vector6(rng, 5.0);

        // M_i xdd^d - D_i (xdot - xdot^d) - h^K, with h^K from rotation matrices:
        // rotational torque kappa sin(theta) u of the axis-angle of R R_d^T.
        Matrix6d M = Matrix6d::Zero();
        M.topLeftCorner<3, 3>() = ee.mass * Matrix3d::Identity();
        M.bottomRightCorner<3, 3>() = ee.rotational_inertia;
        Matrix6d D = Matrix6d::Zero();
        D.topLeftCorner<3, 3>() = ee.translational_damping * Matrix3d::Identity();
        D.bottomRightCorner<3, 3>() = ee.rotational_damping * Matrix3d::Identity();
        Vector6d stiffness;
        stiffness.head<3>() = ee.translational_stiffness * (pose.position - desired.position);
        stiffness.tail<3>() =
            kappa * sin_angle_axis(pose.rotation() * desired.rotation().transpose());
        const Vector6d expected = M * desired_acceleration - D * (twist - desired_twist) - stiffness;

        const Vector6d actual = ee.motion_wrench(pose, twist, desired, desired_twist, desired_acceleration);
        const double error = (actual - expected).norm() / std::max(1.0, expected.norm());
        worst = std::max(worst, error);
        EXPECT_LT(error, 1e-13) << "trial " << trial;
        EXPECT_LT((ee.stiffness_wrench(pose, desired) - stiffness).norm(), 1e-12 * std::max(1.0, stiffness.norm()));
    }
    RecordProperty("worst_relative_error", scientific(worst));
}

TEST(ImpedanceEndEffector, MotionWrenchAcceptsBlockViews)
{
    std::mt19937 rng(31006);
    const auto ee = make_impedance(rng, 20.0);
    const Pose pose = random_pose(rng);
    const Pose desired = random_pose(rng);
    Eigen::Matrix<double, 18, 1> stack;
    for (int k = 0; k < 3; ++k) {
        stack.segment<6>(6 * k) = random_vector6(rng);
    }
    const Vector6d from_views =
        ee.motion_wrench(pose, stack.segment<6>(0), desired, stack.segment<6>(6), stack.segment<6>(12));
    const Vector6d from_copies = ee.motion_wrench(pose, Vector6d(stack.segment<6>(0)), desired,
                                                  Vector6d(stack.segment<6>(6)), Vector6d(stack.segment<6>(12)));
    EXPECT_EQ(from_views, from_copies);
}

// --- Resolved-acceleration end-effector (20) --------------------------------------------------

TEST(ResolvedAccelerationEndEffector, MotionWrenchMatchesLiteralEquation20)
{
    std::mt19937 rng(31007);
    double worst = 0.0;
    for (int trial = 0; trial < 50; ++trial) {
        coopdyn::ResolvedAccelerationEndEffector<double> ee;
        const Matrix6d a = random_matrix6(rng);
        ee.apparent_inertia = a * a.transpose() + Matrix6d::Identity();
        ee.derivative_gain = random_matrix6(rng) * 20.0;
        ee.proportional_gain = random_matrix6(rng) * 100.0;

        // Pose with a known error rotation: q = exp(theta u) (x) q_d, theta in (0, pi), so
        // dq = q (x) q_d^-1 = [cos(theta/2); sin(theta/2) u] exactly (no sign ambiguity).
        const Pose desired = random_pose(rng);
        const Vector3d axis = random_vector(rng).normalized();
        const double angle = 0.05 + 3.0 * (trial / 50.0);
        const Vector3d offset = random_vector(rng, 0.4);
        const Pose pose{desired.position + offset,
                        Quaterniond(Eigen::AngleAxisd(angle, axis)) * desired.orientation};
        const Vector6d twist = random_vector6(rng, 2.0);
        const Vector6d desired_twist = random_vector6(rng, 2.0);
        const Vector6d desired_acceleration = random_vector6(rng, 5.0);

        Vector6d pose_error;
        pose_error << offset, std::sin(angle / 2.0) * axis;
        const Vector6d expected =
            ee.apparent_inertia * (desired_acceleration - ee.derivative_gain * (twist - desired_twist) -
                                   ee.proportional_gain * pose_error);
        EXPECT_LT((ee.pose_error(pose, desired) - pose_error).norm(), 1e-14);
        const Vector6d actual = ee.motion_wrench(pose, twist, desired, desired_twist, desired_acceleration);
        const double error = (actual - expected).norm() / std::max(1.0, expected.norm());
        worst = std::max(worst, error);
        EXPECT_LT(error, 1e-13) << "trial " << trial;
        EXPECT_EQ(ee.inertia().matrix(), ee.apparent_inertia);
    }
    RecordProperty("worst_relative_error", scientific(worst));
}

TEST(ResolvedAccelerationEndEffector, DiagonalGainsReduceToImpedanceForm)
{
    // With Lambda = diag(m I3, J), K_D = Lambda^-1 D, K_P = Lambda^-1 diag(k I3, 2 kappa I3) and
    // a rotation error with d_eta > 0, h^Pi equals the impedance motion wrench up to the factor
    // d_eta on the rotational stiffness torque: 2 kappa d_eps vs 2 d_eta kappa d_eps.
    std::mt19937 rng(31008);
    const auto impedance = make_impedance(rng, 40.0);
    coopdyn::ResolvedAccelerationEndEffector<double> ra;
    ra.apparent_inertia = impedance.inertia().matrix();
    Matrix6d damping = Matrix6d::Zero();
    damping.topLeftCorner<3, 3>() = impedance.translational_damping * Matrix3d::Identity();
    damping.bottomRightCorner<3, 3>() = impedance.rotational_damping * Matrix3d::Identity();
    Matrix6d stiffness = Matrix6d::Zero();
    stiffness.topLeftCorner<3, 3>() = impedance.translational_stiffness * Matrix3d::Identity();
    stiffness.bottomRightCorner<3, 3>() = 2.0 * impedance.rotational_stiffness * Matrix3d::Identity();
    const Matrix6d inverse = ra.apparent_inertia.inverse();
    ra.derivative_gain = inverse * damping;
    ra.proportional_gain = inverse * stiffness;

    const Pose desired = random_pose(rng);
    const Vector3d axis = random_vector(rng).normalized();
    const double angle = 0.7;
    const Pose pose{desired.position + random_vector(rng, 0.3),
                    Quaterniond(Eigen::AngleAxisd(angle, axis)) * desired.orientation};
    const Vector6d twist = random_vector6(rng);
    const Vector6d desired_twist = random_vector6(rng);
    const Vector6d desired_acceleration = random_vector6(rng);
    Vector6d ra_wrench = ra.motion_wrench(pose, twist, desired, desired_twist, desired_acceleration);
    const Vector6d impedance_wrench =
        impedance.motion_wrench(pose, twist, desired, desired_twist, desired_acceleration);
    // Remove the difference in the rotational spring: (1 - d_eta) 2 kappa d_eps.
    const double d_eta = std::cos(angle / 2.0);
    const Vector3d d_eps = std::sin(angle / 2.0) * axis;
    ra_wrench.tail<3>() -= (d_eta - 1.0) * 2.0 * impedance.rotational_stiffness * d_eps;
    EXPECT_LT((ra_wrench - impedance_wrench).norm(), 1e-10 * impedance_wrench.norm());
}

}  // namespace
