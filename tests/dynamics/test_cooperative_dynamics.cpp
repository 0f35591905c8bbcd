// The Model/Data algorithm interaction_dynamics (dynamics/cooperative_dynamics.hpp) against an
// independent recomputation from docs/spatial.md, docs/model.md and docs/dynamics.md: grasp
// kinematics (10) written out with quaternion algebra by hand, the impedance law (1)/(5)/(6)
// with a rotation-matrix stiffness torque kappa sin(theta) u, the resolved-acceleration law (20),
// hSigma_o with gravity (E1), and the generic Udwadia-Kalaba solve (18) of the assembled system.
#include "coopdyn/dynamics/cooperative_dynamics.hpp"
#include "coopdyn/dynamics/udwadia_kalaba.hpp"
#include "coopdyn/model/resolved_acceleration_end_effector.hpp"

#include "sample_systems.hpp"

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <vector>

namespace {

using namespace coopdyn_test;
using Impedance = coopdyn::ImpedanceEndEffector<double>;
using ResolvedAcceleration = coopdyn::ResolvedAccelerationEndEffector<double>;

constexpr double tolerance = 1e-12;

// ---------------------------------------------------------------------------------------------
// Quaternion algebra written out (w, x, y, z), independent of Eigen::Quaternion's operators.
struct Quat {
    double w;
    Vector3d v;
};

Quat quat(const Eigen::Quaterniond& q) { return {q.w(), q.vec()}; }

Quat hamilton(const Quat& a, const Quat& b)
{
    return {a.w * b.w - a.v.dot(b.v), a.w * b.v + b.w * a.v + a.v.cross(b.v)};
}

Quat conjugate(const Quat& q) { return {q.w, -q.v}; }

Matrix3d rotation(const Quat& q)
{
    const double w = q.w, x = q.v.x(), y = q.v.y(), z = q.v.z();
    Matrix3d r;
    r << 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),  //
        2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),   //
        2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y);
    return r;
}

// ---------------------------------------------------------------------------------------------
// Random parameters: wide ranges, and resolved-acceleration gains that are arbitrary (not even
// definite) matrices.
SampleRanges end_effector_ranges()
{
    SampleRanges ranges;
    ranges.impedance.mass = {0.5, 10.0};
    ranges.impedance.inertia_scale = {0.05, 1.0};
    ranges.impedance.inertia_floor = 0.2;
    ranges.impedance.translational_damping = {1.0, 200.0};
    ranges.impedance.rotational_damping = {0.5, 20.0};
    ranges.impedance.translational_stiffness = {10.0, 500.0};
    ranges.impedance.rotational_stiffness = {5.0, 100.0};
    ranges.resolved_acceleration.inertia_scale = {0.5, 10.0};
    // Full, non-symmetric gains, but no negative gain (a Model refuses those, docs/model.md):
    // g I6 + B with |B_jk| <= 0.14 g, so every eigenvalue's real part is >= g (1 - 6 * 0.14) > 0
    // (Gershgorin).
    ranges.resolved_acceleration.derivative_gain = {20.0, 2.8, -1.0, 1.0};
    ranges.resolved_acceleration.proportional_gain = {100.0, 14.0, -1.0, 1.0};
    return ranges;
}

/// Everything random about one evaluation, stored in plain (dynamic) form.
template <typename EndEffector> struct Scenario {
    double object_mass = 0.0;
    Matrix3d object_inertia_body = Matrix3d::Zero();
    Vector3d gravity = Vector3d::Zero();
    std::vector<EndEffector> end_effectors;
    MatrixXd r_body;                          // 3 x N
    std::vector<Eigen::Quaterniond> grasp_q;  // dq_i
    Vector3d object_position = Vector3d::Zero();
    Eigen::Quaterniond object_q = Eigen::Quaterniond::Identity();
    Vector6d object_twist = Vector6d::Zero();
    MatrixXd desired_positions;                 // 3 x N
    std::vector<Eigen::Quaterniond> desired_q;  // q_i^d
    VectorXd desired_twists, desired_accelerations, desired_wrenches;  // 6N
    Vector6d object_disturbance = Vector6d::Zero();
    VectorXd end_effector_disturbances;  // 6N

    Index arms() const { return r_body.cols(); }
};

template <typename EndEffector> Scenario<EndEffector> random_scenario(Index arms, Rng& rng)
{
    Scenario<EndEffector> s;
    s.object_mass = uniform(rng, 0.2, 5.0);
    s.object_inertia_body = coopdyn_test::random_body_inertia(rng, uniform(rng, 0.01, 1.0), 0.2);
    s.gravity = Vector3d(uniform(rng, -1.0, 1.0), uniform(rng, -1.0, 1.0), uniform(rng, -10.5, -9.0));
    s.end_effectors.resize(static_cast<std::size_t>(arms));
    for (EndEffector& e : s.end_effectors) {
        e = random_end_effector<EndEffector>(rng, end_effector_ranges());
    }
    s.r_body = random_offsets(arms, rng);
    for (Index i = 0; i < arms; ++i) {
        s.grasp_q.push_back(random_unit_quaternion(rng));
        s.desired_q.push_back(random_unit_quaternion(rng));  // any angle, also beyond 90 degrees
    }
    s.object_position = random_vector(3, rng, -2.0, 2.0);
    s.object_q = random_unit_quaternion(rng);
    s.object_twist = random_vector(6, rng, -2.0, 2.0);
    s.desired_positions = random_matrix(3, arms, rng, -2.0, 2.0);
    s.desired_twists = random_vector(6 * arms, rng, -2.0, 2.0);
    s.desired_accelerations = random_vector(6 * arms, rng, -5.0, 5.0);
    s.desired_wrenches = random_vector(6 * arms, rng, -20.0, 20.0);
    s.object_disturbance = random_vector(6, rng, -10.0, 10.0);
    s.end_effector_disturbances = random_vector(6 * arms, rng, -10.0, 10.0);
    return s;
}

template <typename ModelType, typename EndEffector> ModelType make_model(const Scenario<EndEffector>& s)
{
    coopdyn::RigidObject<double> object;
    object.mass = s.object_mass;
    object.inertia_body = s.object_inertia_body;
    std::vector<typename ModelType::ArmType> arms;
    for (Index i = 0; i < s.arms(); ++i) {
        typename ModelType::ArmType arm;
        arm.end_effector = s.end_effectors[static_cast<std::size_t>(i)];
        arm.grasp_body.position = s.r_body.col(i);
        arm.grasp_body.orientation = s.grasp_q[static_cast<std::size_t>(i)];
        arms.push_back(arm);
    }
    return ModelType(object, arms, s.gravity);
}

/// Output of one evaluation, copied out of Data.
struct Evaluation {
    MatrixXd grasp_offsets, positions;
    std::vector<Matrix3d> rotations;
    VectorXd twists, h_sigma, accelerations, wrenches;
};

template <typename ModelType, typename EndEffector> Evaluation evaluate(const Scenario<EndEffector>& s)
{
    constexpr int Arms = ModelType::arms_at_compile_time;
    const ModelType model = make_model<ModelType>(s);
    coopdyn::Data<ModelType> data(model);
    coopdyn::RigidBodyState<double> state;
    state.pose.position = s.object_position;
    state.pose.orientation = s.object_q;
    state.twist = s.object_twist;
    coopdyn::Setpoints<double, Arms> setpoints(s.arms());
    setpoints.positions = s.desired_positions;
    for (Index i = 0; i < s.arms(); ++i) {
        setpoints.orientations.col(i) = s.desired_q[static_cast<std::size_t>(i)].coeffs();
    }
    setpoints.twists = s.desired_twists;
    setpoints.accelerations = s.desired_accelerations;
    setpoints.wrenches = s.desired_wrenches;
    coopdyn::Disturbances<double, Arms> disturbances(s.arms());
    disturbances.object = s.object_disturbance;
    disturbances.end_effectors = s.end_effector_disturbances;

    const auto& returned = coopdyn::interaction_dynamics(model, data, state, setpoints, disturbances);
    EXPECT_EQ(&returned, &data.wrenches);

    Evaluation e;
    e.grasp_offsets = data.grasp_offsets;
    e.positions = data.end_effector_positions;
    for (Index i = 0; i < s.arms(); ++i) {
        e.rotations.push_back(data.end_effector_pose(i).orientation.toRotationMatrix());
    }
    e.twists = data.end_effector_twists;
    e.h_sigma = data.h_sigma;
    e.accelerations = data.accelerations;
    e.wrenches = data.wrenches;
    return e;
}

// ---------------------------------------------------------------------------------------------
// Independent reference.

/// Impedance motion wrench (6) with the stiffness wrench (5) as [k dp; kappa sin(theta) u], the
/// rotation (theta, u) taken from the rotation matrix R_i R_d^T.
Vector6d reference_motion_wrench(const Impedance& e, const Vector3d& position, const Quat& orientation,
                                 const Vector6d& twist, const Vector3d& desired_position, const Quat& desired,
                                 const Vector6d& desired_twist, const Vector6d& desired_acceleration)
{
    Vector6d stiffness;
    stiffness.head<3>() = e.translational_stiffness * (position - desired_position);
    const Matrix3d error_rotation = rotation(orientation) * rotation(desired).transpose();
    stiffness.tail<3>() = e.rotational_stiffness * vee_skew_part(error_rotation);  // kappa sin(theta) u
    Matrix6d damping = Matrix6d::Zero();
    damping.topLeftCorner<3, 3>() = e.translational_damping * Matrix3d::Identity();
    damping.bottomRightCorner<3, 3>() = e.rotational_damping * Matrix3d::Identity();
    return block_diagonal_inertia(e.mass, e.rotational_inertia) * desired_acceleration -
           damping * (twist - desired_twist) - stiffness;
}

/// h^Pi of (20): Lambda [xdd_d - K_D (xdot - xdot_d) - K_P [dp; d_eps]], dq = q (x) qd^-1.
Vector6d reference_motion_wrench(const ResolvedAcceleration& e, const Vector3d& position, const Quat& orientation,
                                 const Vector6d& twist, const Vector3d& desired_position, const Quat& desired,
                                 const Vector6d& desired_twist, const Vector6d& desired_acceleration)
{
    Vector6d pose_error;
    pose_error.head<3>() = position - desired_position;
    pose_error.tail<3>() = hamilton(orientation, conjugate(desired)).v;
    return e.apparent_inertia * (desired_acceleration - e.derivative_gain * (twist - desired_twist) -
                                 e.proportional_gain * pose_error);
}

Matrix6d inertia_of(const Impedance& e) { return block_diagonal_inertia(e.mass, e.rotational_inertia); }
Matrix6d inertia_of(const ResolvedAcceleration& e) { return e.apparent_inertia; }

struct ReferenceResult {
    MatrixXd r, positions;
    std::vector<Matrix3d> rotations;
    std::vector<Quat> orientations;
    VectorXd twists, h_sigma, accelerations, wrenches;
};

template <typename EndEffector> ReferenceResult reference(const Scenario<EndEffector>& s)
{
    const Index n = s.arms();
    ReferenceResult out;
    const Quat q_o = quat(s.object_q);
    const Matrix3d R_o = rotation(q_o);
    const Vector3d v_o = s.object_twist.head(3);
    const Vector3d w_o = s.object_twist.tail(3);
    const Matrix3d J_o = R_o * s.object_inertia_body * R_o.transpose();

    out.r.resize(3, n);
    out.positions.resize(3, n);
    out.twists.resize(6 * n);
    out.h_sigma.resize(6 * (n + 1));
    MatrixXd ee_inertia(6, 6 * n);
    for (Index i = 0; i < n; ++i) {
        const std::size_t k = static_cast<std::size_t>(i);
        const Vector3d r_i = R_o * s.r_body.col(i);
        out.r.col(i) = r_i;
        out.positions.col(i) = s.object_position + r_i;
        const Quat q_i = hamilton(q_o, quat(s.grasp_q[k]));
        out.orientations.push_back(q_i);
        out.rotations.push_back(rotation(q_i));
        Vector6d twist;
        twist << v_o + w_o.cross(r_i), w_o;
        out.twists.segment<6>(6 * i) = twist;
        const Vector6d motion = reference_motion_wrench(
            s.end_effectors[k], out.positions.col(i), q_i, twist, s.desired_positions.col(i), quat(s.desired_q[k]),
            s.desired_twists.segment(6 * i, 6), s.desired_accelerations.segment(6 * i, 6));
        out.h_sigma.segment<6>(6 * (i + 1)) =
            motion - s.desired_wrenches.segment(6 * i, 6) + s.end_effector_disturbances.segment(6 * i, 6);
        ee_inertia.block(0, 6 * i, 6, 6) = inertia_of(s.end_effectors[k]);
    }
    // hSigma_o = htilde_o - [0; w x J_o w] - [-m_o g; 0] (16) with errata E1.
    Vector6d coriolis;
    coriolis << Vector3d::Zero(), w_o.cross(J_o * w_o);
    Vector6d gravity_wrench;
    gravity_wrench << -s.object_mass * s.gravity, Vector3d::Zero();
    out.h_sigma.head<6>() = s.object_disturbance - coriolis - gravity_wrench;

    const MatrixXd M = assemble_inertia(block_diagonal_inertia(s.object_mass, J_o), ee_inertia);
    out.wrenches = coopdyn::udwadia_kalaba(M, literal_constraint_matrix(out.r),
                                           literal_constraint_bias(out.r, w_o), out.h_sigma);
    out.accelerations = M.ldlt().solve(out.h_sigma + out.wrenches);
    return out;
}

// ---------------------------------------------------------------------------------------------
// The arm's own control law holds with the computed wrench h_i.

/// (1): M_i (xdd_i - xdd_i^d) + D_i (xdot_i - xdot_i^d) + h_i^K = h_i - h_i^d + htilde_i.
double law_residual(const Impedance& e, const ReferenceResult& ref, const Scenario<Impedance>& s,
                    const Evaluation& eval, Index i)
{
    const std::size_t k = static_cast<std::size_t>(i);
    const Vector6d xdd = eval.accelerations.segment<6>(6 * (i + 1));
    const Vector6d xdot = ref.twists.segment<6>(6 * i);
    Vector6d stiffness;
    stiffness.head<3>() = e.translational_stiffness * (ref.positions.col(i) - s.desired_positions.col(i));
    stiffness.tail<3>() =
        e.rotational_stiffness * vee_skew_part(ref.rotations[k] * rotation(quat(s.desired_q[k])).transpose());
    Vector6d damping_wrench;
    damping_wrench << e.translational_damping * (xdot - s.desired_twists.segment(6 * i, 6)).head<3>(),
        e.rotational_damping * (xdot - s.desired_twists.segment(6 * i, 6)).tail<3>();
    const Vector6d inertial = inertia_of(e) * (xdd - s.desired_accelerations.segment(6 * i, 6));
    const Vector6d lhs = inertial + damping_wrench + stiffness;
    const Vector6d h_i = eval.wrenches.segment<6>(6 * (i + 1));
    const Vector6d rhs = h_i - s.desired_wrenches.segment(6 * i, 6) + s.end_effector_disturbances.segment(6 * i, 6);
    const double scale = inertial.norm() + damping_wrench.norm() + stiffness.norm() + h_i.norm() +
                         s.desired_wrenches.segment(6 * i, 6).norm() +
                         s.end_effector_disturbances.segment(6 * i, 6).norm();
    return (lhs - rhs).norm() / scale;
}

/// (20)-(21) with h^d and htilde: Lambda (xdd - xdd^d + K_D (xdot - xdot^d) + K_P dx) = h_i - h_i^d + htilde_i.
double law_residual(const ResolvedAcceleration& e, const ReferenceResult& ref, const Scenario<ResolvedAcceleration>& s,
                    const Evaluation& eval, Index i)
{
    const std::size_t k = static_cast<std::size_t>(i);
    const Vector6d xdd = eval.accelerations.segment<6>(6 * (i + 1));
    const Vector6d xdot = ref.twists.segment<6>(6 * i);
    Vector6d pose_error;
    pose_error << ref.positions.col(i) - s.desired_positions.col(i),
        hamilton(ref.orientations[k], conjugate(quat(s.desired_q[k]))).v;
    const Vector6d lhs = e.apparent_inertia * (xdd - s.desired_accelerations.segment(6 * i, 6) +
                                               e.derivative_gain * (xdot - s.desired_twists.segment(6 * i, 6)) +
                                               e.proportional_gain * pose_error);
    const Vector6d h_i = eval.wrenches.segment<6>(6 * (i + 1));
    const Vector6d rhs = h_i - s.desired_wrenches.segment(6 * i, 6) + s.end_effector_disturbances.segment(6 * i, 6);
    const double scale = e.apparent_inertia.norm() *
                             (xdd.norm() + s.desired_accelerations.segment(6 * i, 6).norm() +
                              e.derivative_gain.norm() * (xdot - s.desired_twists.segment(6 * i, 6)).norm() +
                              e.proportional_gain.norm() * pose_error.norm()) +
                         rhs.norm();
    return (lhs - rhs).norm() / scale;
}

// ---------------------------------------------------------------------------------------------

template <int ArmsValue, template <typename> class EndEffectorTemplate> struct Config {
    static constexpr int arms = ArmsValue;
    using EndEffector = EndEffectorTemplate<double>;
    using ModelType = coopdyn::Model<double, ArmsValue, EndEffectorTemplate>;
    using DynamicModelType = coopdyn::Model<double, coopdyn::Dynamic, EndEffectorTemplate>;
};

template <typename ConfigType> class CooperativeDynamics : public ::testing::Test {};
using Configs = ::testing::Types<Config<2, coopdyn::ImpedanceEndEffector>, Config<3, coopdyn::ImpedanceEndEffector>,
                                 Config<coopdyn::Dynamic, coopdyn::ImpedanceEndEffector>,
                                 Config<2, coopdyn::ResolvedAccelerationEndEffector>,
                                 Config<3, coopdyn::ResolvedAccelerationEndEffector>,
                                 Config<coopdyn::Dynamic, coopdyn::ResolvedAccelerationEndEffector>>;
TYPED_TEST_SUITE(CooperativeDynamics, Configs);

std::vector<Index> arm_counts(int arms)
{
    if (arms == coopdyn::Dynamic) {
        return {1, 2, 3, 4, 5, 6};
    }
    return {static_cast<Index>(arms)};
}

TYPED_TEST(CooperativeDynamics, MatchesIndependentRecomputation)
{
    using EndEffector = typename TypeParam::EndEffector;
    using ModelType = typename TypeParam::ModelType;
    double worst = 0.0;
    double worst_law = 0.0;
    for (const Index n : arm_counts(TypeParam::arms)) {
        for (unsigned seed = 0; seed < 20; ++seed) {
            Rng rng(7000u + 100u * static_cast<unsigned>(n) + seed);
            const Scenario<EndEffector> s = random_scenario<EndEffector>(n, rng);
            const Evaluation eval = evaluate<ModelType>(s);
            const ReferenceResult ref = reference(s);

            // Grasp kinematics and hSigma.
            EXPECT_LT(relative_error(eval.grasp_offsets, ref.r), 1e-14);
            EXPECT_LT(relative_error(eval.positions, ref.positions), 1e-14);
            EXPECT_LT(relative_error(eval.twists, ref.twists), 1e-14);
            for (Index i = 0; i < n; ++i) {
                const std::size_t k = static_cast<std::size_t>(i);
                EXPECT_LT((eval.rotations[k] - ref.rotations[k]).norm(), 1e-14) << "arm " << i;
            }
            EXPECT_LT(relative_error(eval.h_sigma, ref.h_sigma), tolerance) << "N " << n << " seed " << seed;

            // The interaction solve.
            const double wrench_error = relative_error(eval.wrenches, ref.wrenches);
            const double acceleration_error = relative_error(eval.accelerations, ref.accelerations);
            EXPECT_LT(wrench_error, tolerance) << "N " << n << " seed " << seed;
            EXPECT_LT(acceleration_error, tolerance) << "N " << n << " seed " << seed;
            worst = std::max({worst, wrench_error, acceleration_error});

            // Each end-effector obeys its own control law with the computed h_i.
            for (Index i = 0; i < n; ++i) {
                const double residual = law_residual(s.end_effectors[static_cast<std::size_t>(i)], ref, s, eval, i);
                EXPECT_LT(residual, tolerance) << "N " << n << " seed " << seed << " arm " << i;
                worst_law = std::max(worst_law, residual);
            }
        }
    }
    std::printf("[ measured ] interaction_dynamics (%s, N %s) vs independent UK: worst relative error %.3g, "
                "control-law residual %.3g\n",
                EndEffector::has_block_diagonal_inertia ? "impedance" : "resolved acceleration",
                TypeParam::arms == coopdyn::Dynamic ? "dynamic 1..6" : "fixed", worst, worst_law);
}

TYPED_TEST(CooperativeDynamics, FixedAndDynamicArmCountAgreeExactly)
{
    using EndEffector = typename TypeParam::EndEffector;
    if (TypeParam::arms == coopdyn::Dynamic) {
        GTEST_SKIP() << "compares a fixed-N model with its dynamic twin";
    }
    for (unsigned seed = 0; seed < 20; ++seed) {
        Rng rng(8000u + seed);
        const Scenario<EndEffector> s = random_scenario<EndEffector>(TypeParam::arms, rng);
        const Evaluation fixed = evaluate<typename TypeParam::ModelType>(s);
        const Evaluation dynamic = evaluate<typename TypeParam::DynamicModelType>(s);
        for (Index k = 0; k < fixed.wrenches.size(); ++k) {
            EXPECT_EQ(fixed.wrenches(k), dynamic.wrenches(k)) << "seed " << seed << " coefficient " << k;
            EXPECT_EQ(fixed.accelerations(k), dynamic.accelerations(k)) << "seed " << seed << " coefficient " << k;
            EXPECT_EQ(fixed.h_sigma(k), dynamic.h_sigma(k)) << "seed " << seed << " coefficient " << k;
        }
    }
}

}  // namespace
