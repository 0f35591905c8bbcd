// Sample systems shared by the tests and the benchmarks: seeded random numbers, random inertias,
// rotations and grasps, random end-effectors, objects and cooperative models (N fixed or
// dynamic), the Section V beam of docs/analysis.md, and literal references written out from
// docs/model.md and docs/spatial.md without calling coopdyn (A (14), b (13), G (24), the relative
// constraints of (53), a rotation matrix from quaternion algebra).
//
// Every draw is seeded (std::mt19937) and the order of the draws is part of the contract: the
// seeded cases of the tests depend on it, so a builder may gain parameters but never change what
// an existing call draws.
#pragma once

#include "coopdyn/model/cooperative_model.hpp"
#include "coopdyn/model/impedance_end_effector.hpp"
#include "coopdyn/model/resolved_acceleration_end_effector.hpp"
#include "coopdyn/model/rigid_object.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <type_traits>
#include <vector>

namespace coopdyn_test {

using Eigen::Index;
using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Rng = std::mt19937;

// =============================================================================================
// 1. Random numbers, matrices, rotations and grasp offsets
// =============================================================================================

COOPDYN_LAZY double uniform(Rng& rng, double low, double high)
{
    return std::uniform_real_distribution<double>(low, high)(rng);
}

/// rows x cols, entries uniform in [low, high], drawn column by column.
COOPDYN_LAZY MatrixXd random_matrix(Index rows, Index cols, Rng& rng, double low = -1.0, double high = 1.0)
{
    MatrixXd result(rows, cols);
    for (Index j = 0; j < cols; ++j) {
        for (Index i = 0; i < rows; ++i) {
            result(i, j) = uniform(rng, low, high);
        }
    }
    return result;
}

COOPDYN_LAZY VectorXd random_vector(Index size, Rng& rng, double low = -1.0, double high = 1.0)
{
    return random_matrix(size, 1, rng, low, high);
}

/// A 3-vector with entries uniform in [-scale, scale].
COOPDYN_LAZY Vector3d random_vector(Rng& rng, double scale = 1.0)
{
    std::uniform_real_distribution<double> entry(-scale, scale);
    return Vector3d(entry(rng), entry(rng), entry(rng));
}

/// A 6-vector of two random_vector(rng, scale).
COOPDYN_LAZY Vector6d random_vector6(Rng& rng, double scale = 1.0)
{
    Vector6d result;
    result << random_vector(rng, scale), random_vector(rng, scale);
    return result;
}

/// General (fully coupled) SPD matrix: scale * (B B^T + floor I), B uniform in [-1, 1].
COOPDYN_LAZY MatrixXd random_spd(Index size, Rng& rng, double scale = 1.0, double floor = 0.5)
{
    const MatrixXd factor = random_matrix(size, size, rng);
    return scale * (factor * factor.transpose() + floor * MatrixXd::Identity(size, size));
}

/// A rotational inertia of a real rigid body: J = (tr(S) I - S) / 2 for S = random_spd(3, ...),
/// a random second moment of mass, so the principal moments (s_j + s_k) / 2 satisfy the triangle
/// inequality (the Model refuses inertias that do not). The same draws as random_spd.
COOPDYN_LAZY Matrix3d random_body_inertia(Rng& rng, double scale = 1.0, double floor = 0.5)
{
    const Matrix3d second_moment = random_spd(3, rng, scale, floor);
    return 0.5 * (second_moment.trace() * Matrix3d::Identity() - second_moment);
}

// Unit quaternions. All four are uniformly distributed rotations; they differ in the draws and in
// how the draws are assigned to the coefficients, and each keeps the seeded cases of its users.

/// Four standard normal draws in the order x, y, z, w, redrawn while their norm is below 0.1.
COOPDYN_LAZY Eigen::Quaterniond random_unit_quaternion(Rng& rng)
{
    std::normal_distribution<double> normal(0.0, 1.0);
    Eigen::Vector4d v;
    do {
        for (Index k = 0; k < 4; ++k) {
            v(k) = normal(rng);
        }
    } while (v.norm() < 0.1);
    v.normalize();
    return Eigen::Quaterniond(v(3), v(0), v(1), v(2));
}

/// Four standard normal draws as the coefficients (x, y, z, w), normalised.
COOPDYN_LAZY Eigen::Quaterniond gaussian_quaternion(Rng& rng)
{
    std::normal_distribution<double> normal(0.0, 1.0);
    return Eigen::Quaterniond(Eigen::Vector4d(normal(rng), normal(rng), normal(rng), normal(rng)).normalized());
}

/// Four standard normal draws given to the (w, x, y, z) constructor, then normalised.
COOPDYN_LAZY Eigen::Quaterniond gaussian_quaternion_wxyz(Rng& rng)
{
    std::normal_distribution<double> normal(0.0, 1.0);
    Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
    q.normalize();
    return q;
}

/// Four draws uniform in [-1, 1] as the coefficients (x, y, z, w), normalised (the benchmarks').
COOPDYN_LAZY Eigen::Quaterniond box_quaternion(Rng& rng)
{
    Eigen::Vector4d coefficients(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    return Eigen::Quaterniond(coefficients.normalized());
}

/// Grasp offsets r (3 x N), each column of length 0.2..1 in a random direction: no symmetry.
COOPDYN_LAZY MatrixXd random_offsets(Index arms, Rng& rng)
{
    MatrixXd r(3, arms);
    for (Index i = 0; i < arms; ++i) {
        Vector3d direction;
        do {
            direction = random_vector(3, rng);
        } while (direction.norm() < 0.1);
        r.col(i) = uniform(rng, 0.2, 1.0) * direction.normalized();
    }
    return r;
}

/// random_offsets with a common shift of length 1.5, so that any weighted centroid of the offsets
/// lies well away from the object's centre of mass (|shift| exceeds every |r_i| <= 1, so the
/// centroid is at least 0.5 away, whatever the weights).
COOPDYN_LAZY MatrixXd off_centre_offsets(Index arms, Rng& rng)
{
    MatrixXd r = random_offsets(arms, rng);
    const Vector3d shift = 1.5 * Vector3d(random_vector(3, rng)).normalized();
    r.colwise() += shift;
    return r;
}

// =============================================================================================
// 2. Literal references (no coopdyn code)
// =============================================================================================

/// S(a), written out.
COOPDYN_LAZY Matrix3d hat(const Vector3d& a)
{
    Matrix3d s;
    s << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
    return s;
}

/// a with S(a) = (m - m^T) / 2 (the axial vector of the skew part).
COOPDYN_LAZY Vector3d vee_skew_part(const Matrix3d& m)
{
    return 0.5 * Vector3d(m(2, 1) - m(1, 2), m(0, 2) - m(2, 0), m(1, 0) - m(0, 1));
}

/// Rotation matrix of a unit quaternion, written out (not Eigen's toRotationMatrix).
COOPDYN_LAZY Matrix3d rotation_matrix(const Eigen::Quaterniond& q)
{
    const double w = q.w(), x = q.x(), y = q.y(), z = q.z();
    Matrix3d r;
    r << 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),  //
        2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),  //
        2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y);
    return r;
}

/// [cos(angle/2); sin(angle/2) axis]: the rotation by `angle` about the unit vector `axis`.
COOPDYN_LAZY Eigen::Quaterniond axis_angle(double angle, const Vector3d& axis)
{
    const double s = std::sin(angle / 2);
    return Eigen::Quaterniond(std::cos(angle / 2), s * axis.x(), s * axis.y(), s * axis.z());
}

/// exp of a world-frame rotation vector, [cos(a/2); sin(a/2) u] (closed form).
COOPDYN_LAZY Eigen::Quaterniond rotation_exponential(const Vector3d& rotation_vector)
{
    const double angle = rotation_vector.norm();
    if (angle == 0.0) {
        return Eigen::Quaterniond::Identity();
    }
    return axis_angle(angle, rotation_vector / angle);
}

/// Angle of the rotation taking b to a (sign-invariant).
COOPDYN_LAZY double rotation_angle_between(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b)
{
    const Eigen::Quaterniond e = a * b.conjugate();
    return 2.0 * std::atan2(e.vec().norm(), std::abs(e.w()));
}

/// blkdiag(m I3, J).
COOPDYN_LAZY Matrix6d block_diagonal_inertia(double mass, const Matrix3d& rotational)
{
    Matrix6d result = Matrix6d::Zero();
    result.topLeftCorner<3, 3>() = mass * Matrix3d::Identity();
    result.bottomRightCorner<3, 3>() = rotational;
    return result;
}

/// blkdiag(M_o, M_1, ..., M_N) from the 6x6 object inertia and the 6 x 6N stack.
COOPDYN_LAZY MatrixXd assemble_inertia(const MatrixXd& object_inertia, const MatrixXd& ee_inertia)
{
    const Index arms = ee_inertia.cols() / 6;
    MatrixXd result = MatrixXd::Zero(6 * (arms + 1), 6 * (arms + 1));
    result.topLeftCorner(6, 6) = object_inertia;
    for (Index i = 0; i < arms; ++i) {
        result.block(6 * (i + 1), 6 * (i + 1), 6, 6) = ee_inertia.block(0, 6 * i, 6, 6);
    }
    return result;
}

/// A of (14), docs/model.md, block row i: [[-I3, S(r_i)], [0, -I3]] | I6 in arm i's columns.
COOPDYN_LAZY MatrixXd literal_constraint_matrix(const MatrixXd& r)
{
    const Index arms = r.cols();
    MatrixXd a = MatrixXd::Zero(6 * arms, 6 * (arms + 1));
    for (Index i = 0; i < arms; ++i) {
        a.block(6 * i, 0, 3, 3) = -Matrix3d::Identity();
        a.block(6 * i, 3, 3, 3) = hat(r.col(i));
        a.block(6 * i + 3, 3, 3, 3) = -Matrix3d::Identity();
        a.block(6 * i, 6 * (i + 1), 6, 6).setIdentity();
    }
    return a;
}

/// b of (13), docs/model.md: b_i = [S(w)^2 r_i; 0].
COOPDYN_LAZY VectorXd literal_constraint_bias(const MatrixXd& r, const Vector3d& omega)
{
    const Index arms = r.cols();
    VectorXd b = VectorXd::Zero(6 * arms);
    const Matrix3d s = hat(omega);
    for (Index i = 0; i < arms; ++i) {
        b.segment(6 * i, 3) = s * s * Vector3d(r.col(i));
    }
    return b;
}

/// G = [G_1 ... G_N], G_i = [[I3, 0], [S(r_i), I3]].
COOPDYN_LAZY MatrixXd literal_grasp_matrix(const MatrixXd& r)
{
    const Index arms = r.cols();
    MatrixXd g = MatrixXd::Zero(6, 6 * arms);
    for (Index i = 0; i < arms; ++i) {
        g.block(0, 6 * i, 3, 3).setIdentity();
        g.block(3, 6 * i, 3, 3) = hat(r.col(i));
        g.block(3, 6 * i + 3, 3, 3).setIdentity();
    }
    return g;
}

/// Load-distribution weights as plain numbers: m*_i (N) and J*_i side by side (3 x 3N).
struct Weights {
    VectorXd mass;     // N
    MatrixXd inertia;  // 3 x 3N
};

/// W = blkdiag(diag(m*_i I3, J*_i)), 6N x 6N.
COOPDYN_LAZY MatrixXd weight_matrix(const Weights& weights)
{
    const Index arms = weights.mass.size();
    MatrixXd w = MatrixXd::Zero(6 * arms, 6 * arms);
    for (Index i = 0; i < arms; ++i) {
        w.block(6 * i, 6 * i, 3, 3) = weights.mass(i) * Matrix3d::Identity();
        w.block(6 * i + 3, 6 * i + 3, 3, 3) = weights.inertia.block(0, 3 * i, 3, 3);
    }
    return w;
}

/// The weighted least-norm right inverse W G^T (G W G^T)^-1 of a grasp matrix (dense, no
/// centroid shift): the minimiser of sum_i hbar_i^T (M*_i)^-1 hbar_i subject to G hbar = h_o, a
/// second method for the weighted inverse (25).
COOPDYN_LAZY MatrixXd least_norm_right_inverse(const MatrixXd& g, const Weights& weights)
{
    const MatrixXd w = weight_matrix(weights);
    const MatrixXd gram = g * w * g.transpose();
    return w * g.transpose() * gram.partialPivLu().inverse();
}

/// |a - b| / |b|.
template <typename DerivedA, typename DerivedB>
double relative_error(const Eigen::MatrixBase<DerivedA>& a, const Eigen::MatrixBase<DerivedB>& b)
{
    return static_cast<double>((a - b).norm() / b.norm());
}

// Literal (53), shared by the coordination tests: the reduced system's constraint wrench from
// explicit relative constraints.

/// A' of (53): 6(N-1) x 6N relative constraints of arm 1 (index 0) against arm i. From the rigid
/// grasp (11)-(12) with d_i = r_i - r_1: pdd_i - pdd_1 + S(d_i) wd_1 = w x (w x d_i),
/// wd_i - wd_1 = 0 (errata E5: 6(N-1) rows).
COOPDYN_LAZY MatrixXd relative_constraint_matrix(const MatrixXd& r)
{
    const Index arms = r.cols();
    MatrixXd a = MatrixXd::Zero(6 * (arms - 1), 6 * arms);
    for (Index i = 1; i < arms; ++i) {
        const Index row = 6 * (i - 1);
        a.block(row, 0, 3, 3) = -Matrix3d::Identity();
        a.block(row, 3, 3, 3) = hat(r.col(i) - r.col(0));
        a.block(row + 3, 3, 3, 3) = -Matrix3d::Identity();
        a.block(row, 6 * i, 6, 6).setIdentity();
    }
    return a;
}

/// b' of (53), 6(N-1): [w x (w x (r_i - r_1)); 0].
COOPDYN_LAZY VectorXd relative_constraint_bias(const MatrixXd& r, const Vector3d& omega)
{
    const Index arms = r.cols();
    VectorXd b = VectorXd::Zero(6 * (arms - 1));
    for (Index i = 1; i < arms; ++i) {
        b.segment(6 * (i - 1), 3) = omega.cross(omega.cross(Vector3d(r.col(i) - r.col(0))));
    }
    return b;
}

/// Literal (53): the constraint wrench of the reduced system (end-effectors only, inertia
/// blkdiag(M_i) given as 6 x 6N) driven by `commanded` (6N), from the KKT conditions of Gauss'
/// principle: M' xdd - A'^T mu = commanded, A' xdd = b'; h'_int = M' xdd - commanded.
COOPDYN_LAZY VectorXd literal_internal_wrench(const MatrixXd& ee_inertia, const MatrixXd& r, const Vector3d& omega,
                                        const VectorXd& commanded)
{
    const Index arms = r.cols();
    const Index n = 6 * arms;
    const Index m = 6 * (arms - 1);
    const MatrixXd a = relative_constraint_matrix(r);
    MatrixXd kkt = MatrixXd::Zero(n + m, n + m);
    for (Index i = 0; i < arms; ++i) {
        kkt.block(6 * i, 6 * i, 6, 6) = ee_inertia.block(0, 6 * i, 6, 6);
    }
    const MatrixXd inertia = kkt.topLeftCorner(n, n);
    kkt.topRightCorner(n, m) = -a.transpose();
    kkt.bottomLeftCorner(m, n) = a;
    VectorXd rhs(n + m);
    rhs << commanded, relative_constraint_bias(r, omega);
    const VectorXd solution = kkt.fullPivLu().solve(rhs);
    return inertia * solution.head(n) - commanded;
}

// =============================================================================================
// 3. Random end-effectors, objects and models
// =============================================================================================

/// A parameter drawn uniformly from [low, high]; when low == high, that constant and no draw.
struct Draw {
    double low = 0.0;
    double high = 0.0;

    double operator()(Rng& rng) const { return low == high ? low : uniform(rng, low, high); }
};

/// identity I6 + scale U, U a 6x6 matrix with entries uniform in [low, high] (no draw when
/// scale == 0): a gain matrix of a resolved-acceleration end-effector.
struct GainDraw {
    double identity = 0.0;
    double scale = 0.0;
    double low = -1.0;
    double high = 1.0;

    Matrix6d operator()(Rng& rng) const
    {
        Matrix6d gain = identity * Matrix6d::Identity();
        if (scale != 0.0) {
            gain += scale * random_matrix(6, 6, rng, low, high);
        }
        return gain;
    }
};

/// m_o, and J_o_body = s (B B^T + floor I3) (random_spd) with s drawn from inertia_scale.
struct ObjectRanges {
    Draw mass{0.5, 3.0};
    Draw inertia_scale{0.1, 0.1};
    double inertia_floor = 0.5;
};

/// m_i, J_i = s (B B^T + floor I3) with s drawn first, then d_i, delta_i, k_i, kappa_i.
struct ImpedanceRanges {
    Draw mass{1.0, 10.0};
    Draw inertia_scale{0.1, 1.0};
    double inertia_floor = 0.5;
    Draw translational_damping{20.0, 300.0};
    Draw rotational_damping{2.0, 30.0};
    Draw translational_stiffness{50.0, 800.0};
    Draw rotational_stiffness{5.0, 100.0};
};

/// Lambda_i = s (B B^T + floor I6) with s drawn first, then D_i and K_i.
struct ResolvedAccelerationRanges {
    Draw inertia_scale{0.5, 5.0};
    double inertia_floor = 0.5;
    GainDraw derivative_gain{20.0, 1.0};
    GainDraw proportional_gain{100.0, 5.0};
};

/// The ranges of a random system. A test that needs other ranges changes the members it needs.
struct SampleRanges {
    ObjectRanges object;
    ImpedanceRanges impedance;
    ResolvedAccelerationRanges resolved_acceleration;
};

/// The ranges of the analysis tests (apparent impedance, stability): heavier arms with a fixed
/// inertia scale, moderate gains, light objects.
COOPDYN_LAZY SampleRanges analysis_ranges()
{
    SampleRanges ranges;
    ranges.object.mass = {1.0, 3.0};
    ranges.object.inertia_scale = {0.03, 0.03};
    ranges.impedance.mass = {1.0, 12.0};
    ranges.impedance.inertia_scale = {0.05, 0.05};
    ranges.impedance.translational_damping = {20.0, 200.0};
    ranges.impedance.rotational_damping = {1.0, 15.0};
    ranges.impedance.translational_stiffness = {100.0, 600.0};
    ranges.impedance.rotational_stiffness = {10.0, 80.0};
    return ranges;
}

COOPDYN_LAZY coopdyn::RigidObject<double> random_object(Rng& rng, const ObjectRanges& ranges)
{
    coopdyn::RigidObject<double> object;
    object.mass = ranges.mass(rng);
    const double scale = ranges.inertia_scale(rng);
    object.inertia_body = random_body_inertia(rng, scale, ranges.inertia_floor);
    return object;
}

/// random_object with the analysis ranges.
COOPDYN_LAZY coopdyn::RigidObject<double> random_object(Rng& rng) { return random_object(rng, analysis_ranges().object); }

COOPDYN_LAZY coopdyn::ImpedanceEndEffector<double> random_impedance_end_effector(Rng& rng, const ImpedanceRanges& ranges)
{
    coopdyn::ImpedanceEndEffector<double> e;
    e.mass = ranges.mass(rng);
    const double scale = ranges.inertia_scale(rng);
    e.rotational_inertia = random_spd(3, rng, scale, ranges.inertia_floor);
    e.translational_damping = ranges.translational_damping(rng);
    e.rotational_damping = ranges.rotational_damping(rng);
    e.translational_stiffness = ranges.translational_stiffness(rng);
    e.rotational_stiffness = ranges.rotational_stiffness(rng);
    return e;
}

COOPDYN_LAZY coopdyn::ResolvedAccelerationEndEffector<double>
random_resolved_acceleration_end_effector(Rng& rng, const ResolvedAccelerationRanges& ranges)
{
    coopdyn::ResolvedAccelerationEndEffector<double> e;
    const double scale = ranges.inertia_scale(rng);
    e.apparent_inertia = random_spd(6, rng, scale, ranges.inertia_floor);
    e.derivative_gain = ranges.derivative_gain(rng);
    e.proportional_gain = ranges.proportional_gain(rng);
    return e;
}

/// A random end-effector of either kind, from the matching member of `ranges`.
template <typename EndEffector> EndEffector random_end_effector(Rng& rng, const SampleRanges& ranges = {})
{
    if constexpr (std::is_same_v<EndEffector, coopdyn::ImpedanceEndEffector<double>>) {
        return random_impedance_end_effector(rng, ranges.impedance);
    } else {
        static_assert(std::is_same_v<EndEffector, coopdyn::ResolvedAccelerationEndEffector<double>>,
                      "random_end_effector: impedance or resolved-acceleration end-effectors of double");
        return random_resolved_acceleration_end_effector(rng, ranges.resolved_acceleration);
    }
}

/// A random object, then per arm a random end-effector and grasp orientation, at the given
/// body-frame grasp offsets (3 x N). ModelType: any Model<double, N or Dynamic, EndEffector>.
template <typename ModelType>
ModelType random_model_at(const MatrixXd& offsets_body, Rng& rng, const SampleRanges& ranges = {})
{
    const coopdyn::RigidObject<double> object = random_object(rng, ranges.object);
    std::vector<typename ModelType::ArmType> arms;
    for (Index i = 0; i < offsets_body.cols(); ++i) {
        typename ModelType::ArmType arm;
        arm.end_effector = random_end_effector<typename ModelType::EndEffectorModel>(rng, ranges);
        arm.grasp_body = coopdyn::Pose<double>(Vector3d(offsets_body.col(i)), random_unit_quaternion(rng));
        arms.push_back(arm);
    }
    return ModelType(object, arms);
}

/// A random object, random_offsets, then per arm a random end-effector and grasp orientation.
template <typename ModelType> ModelType random_model(Index arms, Rng& rng, const SampleRanges& ranges = {})
{
    const coopdyn::RigidObject<double> object = random_object(rng, ranges.object);
    const MatrixXd r = random_offsets(arms, rng);
    std::vector<typename ModelType::ArmType> list;
    for (Index i = 0; i < arms; ++i) {
        typename ModelType::ArmType arm;
        arm.end_effector = random_end_effector<typename ModelType::EndEffectorModel>(rng, ranges);
        arm.grasp_body.position = r.col(i);
        arm.grasp_body.orientation = random_unit_quaternion(rng);
        list.push_back(arm);
    }
    return ModelType(object, list);
}

/// random_model from its own generator seeded with `seed`.
template <typename ModelType> ModelType random_model(Index arms, unsigned seed, const SampleRanges& ranges = {})
{
    Rng rng(seed);
    return random_model<ModelType>(arms, rng, ranges);
}

/// A random state: position in [-1, 1]^3, random_unit_quaternion, twist in [-1, 1]^6.
COOPDYN_LAZY coopdyn::RigidBodyState<double> random_state(Rng& rng)
{
    coopdyn::RigidBodyState<double> state;
    state.pose.position = random_vector(3, rng);
    state.pose.orientation = random_unit_quaternion(rng);
    state.twist = random_vector(6, rng);
    return state;
}

COOPDYN_LAZY coopdyn::RigidBodyState<double> make_state(const Vector3d& position, const Eigen::Quaterniond& orientation,
                                                  const Vector6d& twist)
{
    coopdyn::RigidBodyState<double> state;
    state.pose.position = position;
    state.pose.orientation = orientation;
    state.twist = twist;
    return state;
}

/// A random object equilibrium: position in [-1, 1]^3, random_unit_quaternion, at rest.
COOPDYN_LAZY coopdyn::RigidBodyState<double> random_equilibrium(Rng& rng)
{
    return make_state(random_vector(3, rng), random_unit_quaternion(rng), Vector6d::Zero());
}

// ---------------------------------------------------------------------------------------------
// Arms as plain numbers, for tests that write references from the parameters.

/// One impedance arm (1), (5), (6) and its rigid grasp, as plain doubles.
struct ArmParameters {
    double mass = 0.0;
    Matrix3d inertia = Matrix3d::Zero();
    double damping = 0.0;
    double rotational_damping = 0.0;
    double stiffness = 0.0;
    double rotational_stiffness = 0.0;
    Vector3d offset_body = Vector3d::Zero();
    Eigen::Quaterniond grasp_orientation = Eigen::Quaterniond::Identity();
};

/// N arms with different masses, coupled (non-diagonal) inertias, different gains, random
/// offsets (random_offsets, drawn first: no symmetry) and random grasp orientations.
COOPDYN_LAZY std::vector<ArmParameters> random_arms(Index arms, Rng& rng,
                                              const ImpedanceRanges& ranges = analysis_ranges().impedance)
{
    const MatrixXd offsets = random_offsets(arms, rng);
    std::vector<ArmParameters> result(static_cast<std::size_t>(arms));
    for (Index i = 0; i < arms; ++i) {
        ArmParameters& arm = result[static_cast<std::size_t>(i)];
        const coopdyn::ImpedanceEndEffector<double> e = random_impedance_end_effector(rng, ranges);
        arm.mass = e.mass;
        arm.inertia = e.rotational_inertia;
        arm.damping = e.translational_damping;
        arm.rotational_damping = e.rotational_damping;
        arm.stiffness = e.translational_stiffness;
        arm.rotational_stiffness = e.rotational_stiffness;
        arm.offset_body = offsets.col(i);
        arm.grasp_orientation = random_unit_quaternion(rng);
    }
    return result;
}

/// Three deliberately different arms at asymmetric offsets, with seeded perturbations of the
/// offsets (+-3 cm) and random grasp orientations; rotated anisotropic inertias unless
/// `isotropic_inertia`.
COOPDYN_LAZY std::array<ArmParameters, 3> asymmetric_arms(Rng& rng, bool isotropic_inertia)
{
    std::uniform_real_distribution<double> jitter(-0.03, 0.03);
    const std::array<double, 3> masses{2.0, 3.5, 5.0};
    const std::array<double, 3> inertias{0.04, 0.07, 0.10};
    const std::array<double, 3> damping{20.0, 35.0, 50.0};
    const std::array<double, 3> rotational_damping{1.5, 2.5, 4.0};
    const std::array<double, 3> stiffness{150.0, 260.0, 340.0};
    const std::array<double, 3> rotational_stiffness{12.0, 25.0, 40.0};
    const std::array<Vector3d, 3> offsets{Vector3d(0.30, 0.05, 0.00), Vector3d(-0.12, 0.25, 0.06),
                                          Vector3d(-0.10, -0.20, -0.08)};
    std::array<ArmParameters, 3> arms{};
    for (std::size_t i = 0; i < 3; ++i) {
        ArmParameters& arm = arms[i];
        arm.mass = masses[i];
        if (isotropic_inertia) {
            arm.inertia = inertias[i] * Matrix3d::Identity();
        } else {
            const Matrix3d r = rotation_matrix(gaussian_quaternion_wxyz(rng));
            arm.inertia = r * Vector3d(inertias[i], 1.4 * inertias[i], 0.7 * inertias[i]).asDiagonal() *
                          r.transpose();
        }
        arm.damping = damping[i];
        arm.rotational_damping = rotational_damping[i];
        arm.stiffness = stiffness[i];
        arm.rotational_stiffness = rotational_stiffness[i];
        arm.offset_body = offsets[i] + Vector3d(jitter(rng), jitter(rng), jitter(rng));
        arm.grasp_orientation = gaussian_quaternion_wxyz(rng);
    }
    return arms;
}

/// m_o = 1.5 and a randomly rotated anisotropic J_o_body (principal moments 0.02, 0.035, 0.05).
COOPDYN_LAZY coopdyn::RigidObject<double> asymmetric_object(Rng& rng)
{
    coopdyn::RigidObject<double> object;
    object.mass = 1.5;
    const Matrix3d r = rotation_matrix(gaussian_quaternion_wxyz(rng));
    object.inertia_body = r * Vector3d(0.02, 0.035, 0.05).asDiagonal() * r.transpose();
    return object;
}

/// The Model of `object` and `arms` (any container of ArmParameters) in ModelType's scalar
/// (double, float, autodiff).
template <typename ModelType, typename ArmList>
ModelType make_model(const coopdyn::RigidObject<double>& object, const ArmList& arms,
                     const Vector3d& gravity = coopdyn::standard_gravity<double>())
{
    using Scalar = typename ModelType::Scalar;
    std::vector<typename ModelType::ArmType> list;
    for (const ArmParameters& p : arms) {
        typename ModelType::ArmType arm;
        arm.end_effector.mass = Scalar(p.mass);
        arm.end_effector.rotational_inertia = p.inertia.template cast<Scalar>();
        arm.end_effector.translational_damping = Scalar(p.damping);
        arm.end_effector.rotational_damping = Scalar(p.rotational_damping);
        arm.end_effector.translational_stiffness = Scalar(p.stiffness);
        arm.end_effector.rotational_stiffness = Scalar(p.rotational_stiffness);
        arm.grasp_body = coopdyn::Pose<double>(p.offset_body, p.grasp_orientation).template cast<Scalar>();
        list.push_back(arm);
    }
    if constexpr (std::is_same_v<Scalar, double>) {
        return ModelType(object, list, gravity);
    } else {
        coopdyn::RigidObject<Scalar> object_as;
        object_as.mass = Scalar(object.mass);
        object_as.inertia_body = object.inertia_body.template cast<Scalar>();
        return ModelType(object_as, list, gravity.template cast<Scalar>());
    }
}

// =============================================================================================
// 4. The Section V beam of docs/analysis.md
// =============================================================================================

/// Object and arms of a two-arm system, as plain numbers.
struct BeamParameters {
    coopdyn::RigidObject<double> object;
    std::vector<ArmParameters> arms;
};

/// The beam along y: m_o = 1.75, J_o_body = diag(0.055, inertia_yy, 0.055), r_1,2 = (0, -+0.4, 0)
/// with identity grasp orientations, m_i = 10, J_i = 0.5 I3, d_i = 180, delta_i = 10, k_i = 300,
/// kappa_i = 50. The paper's idealised thin beam has inertia_yy = 0; simulations that want an
/// invertible J_o use a small positive value.
COOPDYN_LAZY BeamParameters section_five_beam(double inertia_yy = 0.0)
{
    BeamParameters beam;
    beam.object.mass = 1.75;
    beam.object.inertia_body = Vector3d(0.055, inertia_yy, 0.055).asDiagonal();
    beam.arms.resize(2);
    for (std::size_t i = 0; i < 2; ++i) {
        ArmParameters& arm = beam.arms[i];
        arm.mass = 10.0;
        arm.inertia = 0.5 * Matrix3d::Identity();
        arm.damping = 180.0;
        arm.rotational_damping = 10.0;
        arm.stiffness = 300.0;
        arm.rotational_stiffness = 50.0;
        arm.offset_body = Vector3d(0.0, i == 0 ? -0.4 : 0.4, 0.0);
    }
    return beam;
}

/// The Section V beam as a Model (standard gravity unless given).
template <typename ModelType = coopdyn::Model<double, 2>>
ModelType section_five_beam_model(const Vector3d& gravity = coopdyn::standard_gravity<double>())
{
    const BeamParameters beam = section_five_beam();
    return make_model<ModelType>(beam.object, beam.arms, gravity);
}

// =============================================================================================
// 5. The benchmarks' systems
// =============================================================================================

/// The ranges of the benchmarks' random model: every J = B B^T + 0.5 I3 (scale 1).
COOPDYN_LAZY SampleRanges benchmark_ranges()
{
    SampleRanges ranges;
    ranges.object.mass = {1.0, 5.0};
    ranges.object.inertia_scale = {1.0, 1.0};
    ranges.impedance.mass = {1.0, 5.0};
    ranges.impedance.inertia_scale = {1.0, 1.0};
    ranges.impedance.translational_damping = {10.0, 50.0};
    ranges.impedance.rotational_damping = {1.0, 5.0};
    ranges.impedance.translational_stiffness = {100.0, 500.0};
    ranges.impedance.rotational_stiffness = {10.0, 50.0};
    return ranges;
}

/// A random cooperative Model of N impedance end-effectors (Arms = N or coopdyn::Dynamic), with a
/// non-symmetric grasp (offsets in [-1, 1]^3) and box_quaternion grasp orientations, from the
/// seed 4242 + N.
template <int Arms> coopdyn::Model<double, Arms, coopdyn::ImpedanceEndEffector> random_impedance_model(Index arms)
{
    Rng rng(4242u + static_cast<std::uint32_t>(arms));
    const SampleRanges ranges = benchmark_ranges();
    const coopdyn::RigidObject<double> object = random_object(rng, ranges.object);
    std::vector<coopdyn::Arm<coopdyn::ImpedanceEndEffector<double>>> arm_list(static_cast<std::size_t>(arms));
    for (auto& arm : arm_list) {
        arm.end_effector = random_impedance_end_effector(rng, ranges.impedance);
        arm.grasp_body.position = random_matrix(3, 1, rng);
        arm.grasp_body.orientation = box_quaternion(rng);
    }
    return coopdyn::Model<double, Arms, coopdyn::ImpedanceEndEffector>(object, arm_list);
}

/// random_impedance_model, its Data and random per-tick inputs for N arms (seed 777 + N).
template <int Arms> struct TickFixture {
    using ModelType = coopdyn::Model<double, Arms, coopdyn::ImpedanceEndEffector>;
    using DataType = coopdyn::Data<ModelType>;

    ModelType model;
    DataType data;
    coopdyn::RigidBodyState<double> state;
    coopdyn::Setpoints<double, Arms> setpoints;
    coopdyn::Disturbances<double, Arms> disturbances;

    explicit TickFixture(Index arms)
        : model(random_impedance_model<Arms>(arms)), data(model), setpoints(arms), disturbances(arms)
    {
        Rng rng(777u + static_cast<std::uint32_t>(arms));
        state.pose.position = random_matrix(3, 1, rng);
        state.pose.orientation = box_quaternion(rng);
        state.twist = random_matrix(6, 1, rng, -2, 2);
        for (Index i = 0; i < arms; ++i) {
            setpoints.positions.col(i) = random_matrix(3, 1, rng);
            setpoints.orientations.col(i) = box_quaternion(rng).coeffs();
        }
        setpoints.twists = random_matrix(6 * arms, 1, rng);
        setpoints.accelerations = random_matrix(6 * arms, 1, rng);
        setpoints.wrenches = random_matrix(6 * arms, 1, rng, -5, 5);
        disturbances.object = random_matrix(6, 1, rng);
        disturbances.end_effectors = random_matrix(6 * arms, 1, rng);
    }
};

}  // namespace coopdyn_test
