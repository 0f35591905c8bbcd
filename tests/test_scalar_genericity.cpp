// Scalar genericity of the per-tick algorithm: interaction_dynamics runs
// with float and with Eigen::AutoDiffScalar, for fixed N = 2 and for N = Dynamic.
//
// References: float is compared with double; autodiff derivatives of the interaction wrenches
// h = [h_o; h_1; h_2] are compared with central finite differences computed in double (object
// orientation perturbed on SO(3) with Eigen::AngleAxis).

#include "coopdyn/dynamics/cooperative_dynamics.hpp"
#include "coopdyn/dynamics/interaction_wrenches.hpp"
#include "coopdyn/dynamics/udwadia_kalaba.hpp"
#include "coopdyn/model/cooperative_model.hpp"
#include "coopdyn/model/grasp.hpp"
#include "coopdyn/model/resolved_acceleration_end_effector.hpp"
#include "coopdyn/spatial/quaternion.hpp"

#include "sample_systems.hpp"

#include <unsupported/Eigen/AutoDiff>

#include <gtest/gtest.h>

#include <array>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

/// Scientific notation for recorded measurements.
std::string scientific(double value)
{
    std::ostringstream stream;
    stream << std::scientific << std::setprecision(2) << value;
    return stream.str();
}

using coopdyn::Dynamic;
using Matrix3d = Eigen::Matrix3d;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector3d = Eigen::Vector3d;
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Quaterniond = Eigen::Quaterniond;
using coopdyn_test::gaussian_quaternion;
using coopdyn_test::random_vector;

constexpr int directions = 7;
using AutoDiff = Eigen::AutoDiffScalar<Eigen::Matrix<double, directions, 1>>;

template <typename Scalar, int Arms, template <typename> class EndEffector = coopdyn::ImpedanceEndEffector>
using Model = coopdyn::Model<Scalar, Arms, EndEffector>;

// --- A fixed two-arm scenario, given in double -----------------------------------------------

struct Scenario {
    coopdyn::RigidBodyState<double> state;
    Eigen::Matrix<double, 3, 2> setpoint_positions;
    std::vector<Quaterniond> setpoint_orientations;
    Eigen::Matrix<double, 12, 1> setpoint_twists;
    Eigen::Matrix<double, 12, 1> setpoint_accelerations;
    Eigen::Matrix<double, 12, 1> setpoint_wrenches;
    Vector6d object_disturbance;
    Eigen::Matrix<double, 12, 1> end_effector_disturbances;
};

// random_vector(rng, scale) and gaussian_quaternion: sample_systems.hpp.

template <int Size> Eigen::Matrix<double, Size, 1> random_stack(std::mt19937& rng, double scale)
{
    Eigen::Matrix<double, Size, 1> result;
    for (int k = 0; k < Size; k += 3) {
        result.template segment<3>(k) = random_vector(rng, scale);
    }
    return result;
}

Scenario make_scenario(unsigned seed)
{
    std::mt19937 rng(seed);
    Scenario s;
    s.state.pose.position = random_vector(rng, 0.5);
    s.state.pose.orientation = gaussian_quaternion(rng);
    s.state.twist = random_stack<6>(rng, 1.5);
    s.setpoint_positions.col(0) = random_vector(rng, 0.6);
    s.setpoint_positions.col(1) = random_vector(rng, 0.6);
    s.setpoint_orientations = {gaussian_quaternion(rng), gaussian_quaternion(rng)};
    s.setpoint_twists = random_stack<12>(rng, 1.0);
    s.setpoint_accelerations = random_stack<12>(rng, 2.0);
    s.setpoint_wrenches = random_stack<12>(rng, 5.0);
    s.object_disturbance = random_stack<6>(rng, 3.0);
    s.end_effector_disturbances = random_stack<12>(rng, 3.0);
    return s;
}

/// A generic (non-symmetric) two-arm model, built from double values in any scalar.
template <typename Scalar, int Arms> Model<Scalar, Arms> make_impedance_model()
{
    coopdyn::RigidObject<Scalar> object;
    object.mass = Scalar(1.75);
    Matrix3d inertia;
    inertia << 0.06, 0.004, -0.002, 0.004, 0.02, 0.001, -0.002, 0.001, 0.05;
    object.inertia_body = inertia.cast<Scalar>();
    std::vector<coopdyn::Arm<coopdyn::ImpedanceEndEffector<Scalar>>> arms(2);
    const double masses[] = {10.0, 7.0};
    const double kappas[] = {50.0, 80.0};
    for (std::size_t i = 0; i < 2; ++i) {
        auto& ee = arms[i].end_effector;
        ee.mass = Scalar(masses[i]);
        Matrix3d j = (0.4 + 0.1 * static_cast<double>(i)) * Matrix3d::Identity();
        j(0, 2) = j(2, 0) = 0.03;
        ee.rotational_inertia = j.cast<Scalar>();
        ee.translational_damping = Scalar(180.0 + 20.0 * static_cast<double>(i));
        ee.rotational_damping = Scalar(10.0);
        ee.translational_stiffness = Scalar(300.0 - 50.0 * static_cast<double>(i));
        ee.rotational_stiffness = Scalar(kappas[i]);
    }
    arms[0].grasp_body.position = Vector3d(0.05, -0.4, 0.02).cast<Scalar>();
    arms[1].grasp_body.position = Vector3d(-0.03, 0.35, 0.0).cast<Scalar>();
    arms[1].grasp_body.orientation = Quaterniond(Eigen::AngleAxisd(2.5, Vector3d(0.2, 0.1, 1.0).normalized()))
                                         .cast<Scalar>();
    return Model<Scalar, Arms>(object, arms);
}

template <typename Scalar, int Arms> Model<Scalar, Arms, coopdyn::ResolvedAccelerationEndEffector> make_resolved_model()
{
    coopdyn::RigidObject<Scalar> object;
    object.mass = Scalar(2.0);
    object.inertia_body = Vector3d(0.05, 0.03, 0.04).asDiagonal().toDenseMatrix().cast<Scalar>();
    std::vector<coopdyn::Arm<coopdyn::ResolvedAccelerationEndEffector<Scalar>>> arms(2);
    for (std::size_t i = 0; i < 2; ++i) {
        Matrix6d lambda = (4.0 + static_cast<double>(i)) * Matrix6d::Identity();
        lambda(1, 5) = lambda(5, 1) = 0.4;
        lambda(0, 3) = lambda(3, 0) = -0.2;
        auto& ee = arms[i].end_effector;
        ee.apparent_inertia = lambda.cast<Scalar>();
        ee.derivative_gain = (30.0 * Matrix6d::Identity()).cast<Scalar>();
        ee.proportional_gain = (200.0 * Matrix6d::Identity()).cast<Scalar>();
        ee.proportional_gain(0, 1) = Scalar(5.0);
    }
    arms[0].grasp_body.position = Vector3d(0.0, -0.3, 0.1).cast<Scalar>();
    arms[1].grasp_body.position = Vector3d(0.1, 0.3, 0.0).cast<Scalar>();
    return Model<Scalar, Arms, coopdyn::ResolvedAccelerationEndEffector>(object, arms);
}

/// The scenario's inputs in the model's scalar type.
template <typename Scalar, int Arms> struct Inputs {
    coopdyn::RigidBodyState<Scalar> state;
    coopdyn::Setpoints<Scalar, Arms> setpoints{2};
    coopdyn::Disturbances<Scalar, Arms> disturbances{2};
};

template <typename Scalar, int Arms> Inputs<Scalar, Arms> cast_inputs(const Scenario& s)
{
    Inputs<Scalar, Arms> in;
    in.state.pose = s.state.pose.template cast<Scalar>();
    in.state.twist = s.state.twist.template cast<Scalar>();
    in.setpoints.positions = s.setpoint_positions.template cast<Scalar>();
    for (Eigen::Index i = 0; i < 2; ++i) {
        in.setpoints.orientations.col(i) =
            s.setpoint_orientations[static_cast<std::size_t>(i)].coeffs().template cast<Scalar>();
    }
    in.setpoints.twists = s.setpoint_twists.template cast<Scalar>();
    in.setpoints.accelerations = s.setpoint_accelerations.template cast<Scalar>();
    in.setpoints.wrenches = s.setpoint_wrenches.template cast<Scalar>();
    in.disturbances.object = s.object_disturbance.template cast<Scalar>();
    in.disturbances.end_effectors = s.end_effector_disturbances.template cast<Scalar>();
    return in;
}

/// h = [h_o; h_1; h_2] from one call of the per-tick algorithm, copied out as a dynamic vector.
template <typename ModelType, int Arms = ModelType::arms_at_compile_time>
Eigen::Matrix<typename ModelType::Scalar, Eigen::Dynamic, 1>
evaluate(const ModelType& model, const Inputs<typename ModelType::Scalar, Arms>& in)
{
    coopdyn::Data<ModelType> data(model);
    const auto& h = coopdyn::interaction_dynamics(model, data, in.state, in.setpoints, in.disturbances);
    return h;
}

Eigen::VectorXd evaluate_double(const Scenario& s)
{
    static const Model<double, 2> model = make_impedance_model<double, 2>();
    return evaluate(model, cast_inputs<double, 2>(s));
}

/// The perturbation of direction `direction` by `step`, applied to the double scenario (the
/// same seven inputs the autodiff test seeds).
Scenario perturbed(const Scenario& s, int direction, double step)
{
    Scenario p = s;
    switch (direction) {
    case 0: p.state.twist(4) += step; break;               // object angular velocity w_y
    case 1: p.state.twist(2) += step; break;               // object linear velocity v_z
    case 2: p.setpoint_positions(0, 1) += step; break;     // arm 1 setpoint position x
    case 3: p.end_effector_disturbances(1) += step; break; // arm 0 disturbance force y
    default: {                                             // object orientation exp(phi) (x) q
        const Vector3d axis = Vector3d::Unit(direction - 4);
        p.state.pose.orientation =
            Quaterniond(Eigen::AngleAxisd(step, axis)) * s.state.pose.orientation;
        break;
    }
    }
    return p;
}

/// Seeds the seven directions into autodiff inputs.
template <int Arms> void seed(Inputs<AutoDiff, Arms>& in)
{
    in.state.twist(4).derivatives() = Eigen::Matrix<double, directions, 1>::Unit(0);
    in.state.twist(2).derivatives() = Eigen::Matrix<double, directions, 1>::Unit(1);
    in.setpoints.positions(0, 1).derivatives() = Eigen::Matrix<double, directions, 1>::Unit(2);
    in.disturbances.end_effectors(1).derivatives() = Eigen::Matrix<double, directions, 1>::Unit(3);
    coopdyn::Vector3<AutoDiff> phi;
    for (int j = 0; j < 3; ++j) {
        phi(j) = AutoDiff(0.0, directions, 4 + j);
    }
    in.state.pose.orientation = coopdyn::quaternion_exp(phi) * in.state.pose.orientation;
}

// --- float ---------------------------------------------------------------------------------

template <int Arms> void check_float_against_double(const char* label)
{
    const Model<float, Arms> model_float = make_impedance_model<float, Arms>();
    const Model<double, Arms> model_double = make_impedance_model<double, Arms>();
    double worst = 0.0;
    for (unsigned seed_value = 1; seed_value <= 10; ++seed_value) {
        const Scenario s = make_scenario(seed_value);
        const Eigen::VectorXf h_float = evaluate(model_float, cast_inputs<float, Arms>(s));
        const Eigen::VectorXd h_double = evaluate(model_double, cast_inputs<double, Arms>(s));
        ASSERT_EQ(h_float.size(), 18);
        ASSERT_EQ(h_double.size(), 18);
        const double error = (h_float.cast<double>() - h_double).cwiseAbs().maxCoeff() /
                             std::max(1.0, h_double.cwiseAbs().maxCoeff());
        worst = std::max(worst, error);
        EXPECT_LT(error, 1e-4) << label << " seed " << seed_value;
    }
    ::testing::Test::RecordProperty(std::string(label) + "_worst_relative_error", scientific(worst));
}

TEST(ScalarGenericity, FloatFixedNMatchesDouble) { check_float_against_double<2>("fixed"); }
TEST(ScalarGenericity, FloatDynamicNMatchesDouble) { check_float_against_double<Dynamic>("dynamic"); }

TEST(ScalarGenericity, FloatResolvedAccelerationMatchesDouble)
{
    const auto model_float = make_resolved_model<float, 2>();
    const auto model_double = make_resolved_model<double, 2>();
    const auto model_float_dynamic = make_resolved_model<float, Dynamic>();
    for (unsigned seed_value = 11; seed_value <= 15; ++seed_value) {
        const Scenario s = make_scenario(seed_value);
        const Eigen::VectorXf h_float = evaluate(model_float, cast_inputs<float, 2>(s));
        const Eigen::VectorXf h_float_dynamic = evaluate(model_float_dynamic, cast_inputs<float, Dynamic>(s));
        const Eigen::VectorXd h_double = evaluate(model_double, cast_inputs<double, 2>(s));
        const double scale = std::max(1.0, h_double.cwiseAbs().maxCoeff());
        EXPECT_LT((h_float.cast<double>() - h_double).cwiseAbs().maxCoeff() / scale, 1e-4);
        EXPECT_LT((h_float_dynamic.cast<double>() - h_double).cwiseAbs().maxCoeff() / scale, 1e-4);
    }
}

// --- autodiff ------------------------------------------------------------------------------

template <int Arms> void check_autodiff_against_finite_differences(const char* label)
{
    const Model<AutoDiff, Arms> model = make_impedance_model<AutoDiff, Arms>();
    const char* names[directions] = {"w_o,y", "v_o,z", "p_2^d,x", "htilde_1,fy", "phi_x", "phi_y", "phi_z"};
    double worst = 0.0;
    for (unsigned seed_value = 21; seed_value <= 25; ++seed_value) {
        const Scenario s = make_scenario(seed_value);
        Inputs<AutoDiff, Arms> in = cast_inputs<AutoDiff, Arms>(s);
        seed(in);
        const auto h = evaluate(model, in);
        ASSERT_EQ(h.size(), 18);

        // Values equal the double evaluation.
        const Eigen::VectorXd reference = evaluate_double(s);
        for (Eigen::Index k = 0; k < 18; ++k) {
            EXPECT_NEAR(h(k).value(), reference(k), 1e-12 * std::max(1.0, reference.cwiseAbs().maxCoeff()));
        }

        const double step = 1e-6;
        for (int direction = 0; direction < directions; ++direction) {
            const Eigen::VectorXd fd =
                (evaluate_double(perturbed(s, direction, step)) - evaluate_double(perturbed(s, direction, -step))) /
                (2.0 * step);
            Eigen::VectorXd ad(18);
            for (Eigen::Index k = 0; k < 18; ++k) {
                ad(k) = h(k).derivatives()(direction);
            }
            const double scale = std::max(1.0, fd.cwiseAbs().maxCoeff());
            const double error = (ad - fd).cwiseAbs().maxCoeff() / scale;
            worst = std::max(worst, error);
            EXPECT_LT(error, 1e-6) << label << " seed " << seed_value << " d h / d " << names[direction];
            // Every direction actually moves h (the test is not vacuous).
            EXPECT_GT(fd.cwiseAbs().maxCoeff(), 1e-3) << names[direction];
        }
    }
    ::testing::Test::RecordProperty(std::string(label) + "_worst_relative_error", scientific(worst));
}

TEST(ScalarGenericity, AutoDiffFixedNMatchesFiniteDifferences)
{
    check_autodiff_against_finite_differences<2>("fixed");
}

TEST(ScalarGenericity, AutoDiffDynamicNMatchesFiniteDifferences)
{
    check_autodiff_against_finite_differences<Dynamic>("dynamic");
}

TEST(ScalarGenericity, AutoDiffResolvedAccelerationRuns)
{
    const auto model = make_resolved_model<AutoDiff, 2>();
    const auto model_double = make_resolved_model<double, 2>();
    const Scenario s = make_scenario(31);
    Inputs<AutoDiff, 2> in = cast_inputs<AutoDiff, 2>(s);
    seed(in);
    const auto h = evaluate(model, in);
    const Eigen::VectorXd reference = evaluate(model_double, cast_inputs<double, 2>(s));
    for (Eigen::Index k = 0; k < 18; ++k) {
        EXPECT_NEAR(h(k).value(), reference(k), 1e-12 * std::max(1.0, reference.cwiseAbs().maxCoeff()));
        EXPECT_TRUE(h(k).derivatives().allFinite());
    }
}

TEST(ScalarGenericity, QuaternionExpAutoDiffDerivativeAtZero)
{
    // d exp(phi) / d phi at 0 is [0; I3 / 2] (w unchanged to first order): the series branch
    // keeps the derivative where the closed form would divide 0 by 0.
    coopdyn::Vector3<AutoDiff> phi;
    for (int j = 0; j < 3; ++j) {
        phi(j) = AutoDiff(0.0, directions, j);
    }
    const auto q = coopdyn::quaternion_exp(phi);
    EXPECT_EQ(q.w().value(), 1.0);
    EXPECT_LT(q.w().derivatives().norm(), 1e-300);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            EXPECT_EQ(q.vec()(i).derivatives()(j), i == j ? 0.5 : 0.0);
        }
    }
}

// --- The formula kernels with float -----------------------------------------------------------

TEST(ScalarGenericity, KernelsCompileAndAgreeWithFloat)
{
    std::mt19937 rng(41);
    Matrix6d object_inertia = Matrix6d::Zero();
    object_inertia.topLeftCorner<3, 3>() = 2.0 * Matrix3d::Identity();
    object_inertia.bottomRightCorner<3, 3>() << 0.05, 0.01, 0.0, 0.01, 0.04, 0.0, 0.0, 0.0, 0.06;
    Eigen::Matrix<double, 6, 12> ee_inertia;
    for (int i = 0; i < 2; ++i) {
        Matrix6d a;
        for (int c = 0; c < 6; ++c) {
            a.col(c) << random_vector(rng), random_vector(rng);
        }
        ee_inertia.block<6, 6>(0, 6 * i) = a * a.transpose() + 2.0 * Matrix6d::Identity();
    }
    Eigen::Matrix<double, 3, 2> r;
    r << random_vector(rng, 0.5), random_vector(rng, 0.5);
    const Vector3d omega = random_vector(rng, 2.0);
    const Eigen::Matrix<double, 18, 1> h_sigma = random_stack<18>(rng, 10.0);

    const Eigen::Matrix<double, 18, 1> h_double =
        coopdyn::interaction_wrenches(object_inertia, ee_inertia, r, omega, h_sigma);
    const Eigen::Matrix<float, 18, 1> h_float =
        coopdyn::interaction_wrenches(object_inertia.cast<float>(), ee_inertia.cast<float>(), r.cast<float>(),
                                      omega.cast<float>(), h_sigma.cast<float>());
    const double scale = std::max(1.0, h_double.cwiseAbs().maxCoeff());
    EXPECT_LT((h_float.cast<double>() - h_double).cwiseAbs().maxCoeff() / scale, 1e-4);

    // Generic Udwadia-Kalaba on the dense problem, in float.
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(18, 18);
    M.topLeftCorner(6, 6) = object_inertia;
    M.block(6, 6, 6, 6) = ee_inertia.leftCols<6>();
    M.block(12, 12, 6, 6) = ee_inertia.rightCols<6>();
    const Eigen::MatrixXd A = coopdyn::constraint_matrix(r);
    const Eigen::VectorXd b = coopdyn::constraint_bias(r, omega);
    const Eigen::MatrixXf M_float = M.cast<float>();
    const Eigen::MatrixXf A_float = A.cast<float>();
    const Eigen::VectorXf b_float = b.cast<float>();
    const Eigen::VectorXf h_sigma_float = h_sigma.cast<float>();
    const Eigen::VectorXf h_uk_float = coopdyn::udwadia_kalaba(M_float, A_float, b_float, h_sigma_float);
    EXPECT_LT((h_uk_float.cast<double>() - h_double).cwiseAbs().maxCoeff() / scale, 1e-3);
    const Eigen::VectorXf xdd_float =
        coopdyn::udwadia_kalaba_accelerations(M_float, A_float, b_float, h_sigma_float);
    EXPECT_LT((A_float * xdd_float - b_float).cwiseAbs().maxCoeff(), 1e-3f * std::max(1.0f, b_float.cwiseAbs().maxCoeff()));

    // Block-diagonal kernel in float.
    const Eigen::Matrix<float, 2, 1> masses(3.0f, 4.0f);
    Eigen::Matrix<float, 3, 6> rotational;
    rotational << 0.5f * Eigen::Matrix3f::Identity(), 0.3f * Eigen::Matrix3f::Identity();
    const std::array<coopdyn::CentralInertia<float>, 2> ee_block{
        coopdyn::CentralInertia<float>(masses(0), Eigen::Matrix3f(rotational.block<3, 3>(0, 0))),
        coopdyn::CentralInertia<float>(masses(1), Eigen::Matrix3f(rotational.block<3, 3>(0, 3)))};
    const Eigen::Matrix<float, 18, 1> h_block = coopdyn::interaction_wrenches(
        coopdyn::CentralInertia<float>(2.0f, object_inertia.bottomRightCorner<3, 3>().cast<float>().eval()),
        ee_block, r.cast<float>(), omega.cast<float>(), h_sigma.cast<float>());
    EXPECT_TRUE(h_block.allFinite());
}

}  // namespace
