// Construction-time validation of coopdyn::Model (model/cooperative_model.hpp,
// detail/validation.hpp) and coopdyn::Simulator (dynamics/simulator.hpp): every invalid model
// parameter is refused with coopdyn::InvalidModel, every invalid simulator input (time step,
// initial state) with coopdyn::InvalidArgument, whose message names the parameter and the body
// ("object", "arm i", "model", "simulator"); valid parameters are kept exactly as given (nothing
// clamped or normalised).

#include "coopdyn/dynamics/simulator.hpp"
#include "coopdyn/model/cooperative_model.hpp"
#include "coopdyn/model/resolved_acceleration_end_effector.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <initializer_list>
#include <limits>
#include <string>
#include <utility>
#include <vector>

// Every member of the class templates compiles.
template class coopdyn::Model<double, 2, coopdyn::ImpedanceEndEffector>;
template class coopdyn::Model<double, coopdyn::Dynamic, coopdyn::ImpedanceEndEffector>;
template class coopdyn::Model<double, 2, coopdyn::ResolvedAccelerationEndEffector>;
template class coopdyn::Model<float, 3, coopdyn::ImpedanceEndEffector>;
template struct coopdyn::RigidObject<double>;

namespace {

using Matrix3d = Eigen::Matrix3d;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector3d = Eigen::Vector3d;
using Quaterniond = Eigen::Quaterniond;

using Impedance = coopdyn::ImpedanceEndEffector<double>;
using Resolved = coopdyn::ResolvedAccelerationEndEffector<double>;
using ImpedanceArm = coopdyn::Arm<Impedance>;
using ResolvedArm = coopdyn::Arm<Resolved>;
using Model2 = coopdyn::Model<double, 2, coopdyn::ImpedanceEndEffector>;
using ModelX = coopdyn::Model<double, coopdyn::Dynamic, coopdyn::ImpedanceEndEffector>;
using ResolvedModel2 = coopdyn::Model<double, 2, coopdyn::ResolvedAccelerationEndEffector>;
using ResolvedModelX = coopdyn::Model<double, coopdyn::Dynamic, coopdyn::ResolvedAccelerationEndEffector>;

constexpr double nan = std::numeric_limits<double>::quiet_NaN();
constexpr double inf = std::numeric_limits<double>::infinity();

coopdyn::RigidObject<double> valid_object()
{
    coopdyn::RigidObject<double> object;
    object.mass = 1.75;
    object.inertia_body = Eigen::Vector3d(0.055, 0.02, 0.045).asDiagonal();
    return object;
}

/// diag(moments) in axes rotated by a fixed, generic rotation (symmetrised).
Matrix3d rotated_diagonal(const Vector3d& moments)
{
    const Matrix3d rotation = Eigen::AngleAxisd(0.9, Vector3d(-1.0, 2.0, 0.5).normalized()).toRotationMatrix();
    const Matrix3d inertia = rotation * moments.asDiagonal() * rotation.transpose();
    return 0.5 * (inertia + inertia.transpose());
}

std::vector<ImpedanceArm> valid_impedance_arms()
{
    std::vector<ImpedanceArm> arms(2);
    for (std::size_t i = 0; i < 2; ++i) {
        Impedance& ee = arms[i].end_effector;
        ee.mass = 10.0 + static_cast<double>(i);
        ee.rotational_inertia = 0.5 * Matrix3d::Identity();
        ee.rotational_inertia(0, 1) = ee.rotational_inertia(1, 0) = 0.05;
        ee.translational_damping = 180.0;
        ee.rotational_damping = 10.0;
        ee.translational_stiffness = 300.0;
        ee.rotational_stiffness = 50.0;
    }
    arms[0].grasp_body.position = Vector3d(0.0, -0.4, 0.0);
    arms[1].grasp_body.position = Vector3d(0.0, 0.4, 0.0);
    arms[1].grasp_body.orientation = Quaterniond(Eigen::AngleAxisd(3.0, Vector3d::UnitZ()));
    return arms;
}

std::vector<ResolvedArm> valid_resolved_arms()
{
    std::vector<ResolvedArm> arms(2);
    for (std::size_t i = 0; i < 2; ++i) {
        Resolved& ee = arms[i].end_effector;
        Matrix6d lambda = Matrix6d::Identity() * 5.0;
        lambda(0, 4) = lambda(4, 0) = 0.3;
        ee.apparent_inertia = lambda;
        ee.derivative_gain = 20.0 * Matrix6d::Identity();
        ee.proportional_gain = 100.0 * Matrix6d::Identity();
    }
    arms[0].grasp_body.position = Vector3d(0.1, -0.4, 0.0);
    arms[1].grasp_body.position = Vector3d(0.0, 0.4, 0.2);
    return arms;
}

/// Runs `build`, expects `Expected` (InvalidModel unless given) whose what() contains every string
/// in `needles`.
template <typename Expected = coopdyn::InvalidModel, typename Build>
void expect_invalid(Build&& build, std::initializer_list<const char*> needles, const char* label)
{
    try {
        build();
        ADD_FAILURE() << label << ": no exception thrown";
    } catch (const Expected& error) {
        const std::string message = error.what();
        for (const char* needle : needles) {
            EXPECT_NE(message.find(needle), std::string::npos)
                << label << ": message \"" << message << "\" does not contain \"" << needle << "\"";
        }
    } catch (const std::exception& error) {
        ADD_FAILURE() << label << ": wrong exception type, what() = " << error.what();
    }
}

// --- Object ----------------------------------------------------------------------------------

TEST(ModelValidation, RefusesInvalidObjectMass)
{
    for (const double mass : {0.0, -1.0, -0.0, nan, inf, -inf}) {
        auto object = valid_object();
        object.mass = mass;
        expect_invalid([&] { Model2 model(object, valid_impedance_arms()); }, {"object", "'mass'"},
                       ("object mass " + std::to_string(mass)).c_str());
        expect_invalid([&] { ModelX model(object, valid_impedance_arms()); }, {"object", "'mass'"},
                       ("dynamic, object mass " + std::to_string(mass)).c_str());
    }
}

TEST(ModelValidation, RefusesInvalidObjectInertia)
{
    struct Case {
        const char* label;
        Matrix3d inertia;
        const char* problem;
    };
    Matrix3d indefinite = Vector3d(0.05, -0.01, 0.05).asDiagonal();
    Matrix3d asymmetric = Vector3d(0.05, 0.05, 0.05).asDiagonal();
    asymmetric(0, 1) = 0.01;
    Matrix3d with_nan = Vector3d(0.05, 0.05, 0.05).asDiagonal();
    with_nan(2, 1) = nan;
    Matrix3d with_inf = Vector3d(0.05, 0.05, 0.05).asDiagonal();
    with_inf(0, 0) = inf;
    // Negative beyond rounding: -1e-6 on a scale of 0.05 is not a semi-definite thin beam.
    Matrix3d slightly_negative = Vector3d(0.055, -1e-6, 0.055).asDiagonal();
    const Case cases[] = {{"indefinite", indefinite, "definite"},
                          {"asymmetric", asymmetric, "symmetric"},
                          {"NaN", with_nan, "finite"},
                          {"Inf", with_inf, "finite"},
                          {"slightly negative", slightly_negative, "definite"},
                          {"negative definite", -Matrix3d::Identity(), "definite"},
                          // Positive definite, but no rigid body has J_xx > J_yy + J_zz.
                          {"triangle inequality", rotated_diagonal(Vector3d(0.1, 0.03, 0.05)), "triangle inequality"}};
    for (const Case& c : cases) {
        auto object = valid_object();
        object.inertia_body = c.inertia;
        expect_invalid([&] { Model2 model(object, valid_impedance_arms()); },
                       {"object", "'inertia_body'", c.problem}, c.label);
    }
}

TEST(ModelValidation, AcceptsThinBeamWithZeroPrincipalMoment)
{
    // The paper's idealised beam along y: J_o_body = diag(0.055, 0, 0.055), also rotated.
    auto object = valid_object();
    object.inertia_body = Vector3d(0.055, 0.0, 0.055).asDiagonal();
    EXPECT_NO_THROW({ Model2 model(object, valid_impedance_arms()); });
    const Matrix3d rotation =
        Eigen::AngleAxisd(0.7, Vector3d(1.0, 2.0, 3.0).normalized()).toRotationMatrix();
    object.inertia_body = rotation * object.inertia_body * rotation.transpose();
    object.inertia_body = (0.5 * (object.inertia_body + object.inertia_body.transpose())).eval();
    EXPECT_NO_THROW({ Model2 model(object, valid_impedance_arms()); });
    const Model2 model(object, valid_impedance_arms());
    EXPECT_EQ(model.object().inertia_body, object.inertia_body);
}

TEST(ModelValidation, TriangleInequalityAcceptsItsLimitsAndAppliesToTheObjectOnly)
{
    // Equality is a real limit: a flat plate (J_zz = J_xx + J_yy) and a thin rod, in any axes.
    auto object = valid_object();
    for (const Vector3d& moments : {Vector3d(0.103, 0.103, 0.206), Vector3d(0.0, 0.055, 0.055),
                                    Vector3d(0.03, 0.07, 0.1)}) {
        object.inertia_body = rotated_diagonal(moments);
        EXPECT_NO_THROW({ Model2 model(object, valid_impedance_arms()); }) << moments.transpose();
    }
    // Just beyond it (by 1e-6 relative) is refused.
    object.inertia_body = rotated_diagonal(Vector3d(0.03, 0.07, 0.1 * (1.0 + 1e-6)));
    expect_invalid([&] { Model2 model(object, valid_impedance_arms()); },
                   {"object", "'inertia_body'", "triangle inequality"}, "plate beyond the limit");
    // The end-effector's J_i is the desired apparent inertia of a controller, not a body: any
    // symmetric positive definite J_i is accepted (docs/model.md).
    auto arms = valid_impedance_arms();
    arms[1].end_effector.rotational_inertia = rotated_diagonal(Vector3d(0.1, 0.01, 1.0));
    EXPECT_NO_THROW({ Model2 model(valid_object(), arms); });
}

// --- End-effectors ---------------------------------------------------------------------------

TEST(ModelValidation, RefusesInvalidEndEffectorMassOnArm1)
{
    for (const double mass : {0.0, -2.0, nan, inf}) {
        auto arms = valid_impedance_arms();
        arms[1].end_effector.mass = mass;
        expect_invalid([&] { Model2 model(valid_object(), arms); }, {"arm 1", "'mass'"},
                       ("arm 1 mass " + std::to_string(mass)).c_str());
        expect_invalid([&] { ModelX model(valid_object(), arms); }, {"arm 1", "'mass'"},
                       ("dynamic, arm 1 mass " + std::to_string(mass)).c_str());
    }
}

TEST(ModelValidation, RefusesNonSpdRotationalInertiaOnArm0)
{
    Matrix3d indefinite = Vector3d(0.5, -0.1, 0.5).asDiagonal();
    Matrix3d singular = Vector3d(0.5, 0.0, 0.5).asDiagonal();  // end-effectors need definite J_i
    Matrix3d asymmetric = 0.5 * Matrix3d::Identity();
    asymmetric(2, 0) = 0.2;
    Matrix3d with_nan = 0.5 * Matrix3d::Identity();
    with_nan(1, 1) = nan;
    const std::pair<const char*, Matrix3d> cases[] = {
        {"indefinite", indefinite}, {"singular", singular}, {"asymmetric", asymmetric}, {"NaN", with_nan}};
    for (const auto& c : cases) {
        auto arms = valid_impedance_arms();
        arms[0].end_effector.rotational_inertia = c.second;
        expect_invalid([&] { Model2 model(valid_object(), arms); }, {"arm 0", "'rotational_inertia'"}, c.first);
    }
}

TEST(ModelValidation, RefusesNegativeOrNonFiniteGains)
{
    struct Case {
        const char* parameter;
        double Impedance::*member;
    };
    const Case cases[] = {{"'translational_damping'", &Impedance::translational_damping},
                          {"'rotational_damping'", &Impedance::rotational_damping},
                          {"'translational_stiffness'", &Impedance::translational_stiffness},
                          {"'rotational_stiffness'", &Impedance::rotational_stiffness}};
    for (const Case& c : cases) {
        for (const double value : {-1.0, -1e-12, nan, inf}) {
            for (std::size_t arm = 0; arm < 2; ++arm) {
                auto arms = valid_impedance_arms();
                arms[arm].end_effector.*c.member = value;
                const std::string context = "arm " + std::to_string(arm);
                const std::string label = std::string(c.parameter) + " = " + std::to_string(value) + " on " + context;
                expect_invalid([&] { Model2 model(valid_object(), arms); }, {context.c_str(), c.parameter},
                               label.c_str());
            }
        }
        // Zero is allowed (a free or undamped direction) and kept.
        auto arms = valid_impedance_arms();
        arms[1].end_effector.*c.member = 0.0;
        EXPECT_NO_THROW({ Model2 model(valid_object(), arms); }) << c.parameter;
    }
}

// --- Grasp -----------------------------------------------------------------------------------

TEST(ModelValidation, RefusesNonFiniteGraspOffset)
{
    for (const double bad : {nan, inf, -inf}) {
        auto arms = valid_impedance_arms();
        arms[1].grasp_body.position.y() = bad;
        expect_invalid([&] { Model2 model(valid_object(), arms); }, {"arm 1", "'grasp_body.position'"},
                       "grasp offset");
    }
}

TEST(ModelValidation, RefusesNonUnitOrZeroGraspQuaternion)
{
    const Quaterniond cases[] = {Quaterniond(0.0, 0.0, 0.0, 0.0), Quaterniond(1.0, 1.0, 0.0, 0.0),
                                 Quaterniond(0.9, 0.0, 0.0, 0.0), Quaterniond(1.0 + 1e-7, 0.0, 0.0, 0.0),
                                 Quaterniond(nan, 0.0, 0.0, 0.0)};
    for (const Quaterniond& q : cases) {
        for (std::size_t arm = 0; arm < 2; ++arm) {
            auto arms = valid_impedance_arms();
            arms[arm].grasp_body.orientation = q;
            const std::string context = "arm " + std::to_string(arm);
            expect_invalid([&] { Model2 model(valid_object(), arms); },
                           {context.c_str(), "'grasp_body.orientation'"}, "grasp quaternion");
        }
    }
}

// --- Arm count -------------------------------------------------------------------------------

TEST(ModelValidation, RefusesEmptyArmList)
{
    expect_invalid([] { ModelX model(valid_object(), {}); }, {"'arms'", "N = 0"}, "dynamic, no arms");
    expect_invalid([] { Model2 model(valid_object(), {}); }, {"'arms'"}, "fixed N = 2, no arms");
    expect_invalid([] { ResolvedModelX model(valid_object(), {}); }, {"'arms'"}, "resolved, no arms");
}

TEST(ModelValidation, RefusesWrongArmCountForFixedN)
{
    auto three = valid_impedance_arms();
    three.push_back(three[0]);
    expect_invalid([&] { Model2 model(valid_object(), three); }, {"'arms'", "exactly 2", "got 3"}, "3 arms for N = 2");
    auto one = valid_impedance_arms();
    one.pop_back();
    expect_invalid([&] { Model2 model(valid_object(), one); }, {"'arms'", "exactly 2", "got 1"}, "1 arm for N = 2");
    // Dynamic N takes any positive count.
    EXPECT_NO_THROW({ ModelX model(valid_object(), three); });
    EXPECT_NO_THROW({ ModelX model(valid_object(), one); });
}

// --- Gravity ---------------------------------------------------------------------------------

TEST(ModelValidation, RefusesNonFiniteGravity)
{
    for (const double bad : {nan, inf, -inf}) {
        expect_invalid([&] { Model2 model(valid_object(), valid_impedance_arms(), Vector3d(0.0, bad, -9.81)); },
                       {"model", "'gravity'"}, "gravity");
    }
    // Zero gravity (space) is valid.
    EXPECT_NO_THROW({ Model2 model(valid_object(), valid_impedance_arms(), Vector3d::Zero()); });
}

// --- Resolved-acceleration end-effectors -----------------------------------------------------

TEST(ModelValidation, ResolvedAccelerationRefusesNonSpdApparentInertia)
{
    Matrix6d indefinite = Matrix6d::Identity();
    indefinite(3, 3) = -0.5;
    Matrix6d asymmetric = Matrix6d::Identity();
    asymmetric(0, 5) = 0.4;
    Matrix6d with_nan = Matrix6d::Identity();
    with_nan(2, 2) = nan;
    const std::pair<const char*, Matrix6d> cases[] = {{"indefinite", indefinite},
                                                      {"asymmetric", asymmetric},
                                                      {"NaN", with_nan},
                                                      {"zero", Matrix6d::Zero()}};
    for (const auto& c : cases) {
        auto arms = valid_resolved_arms();
        arms[1].end_effector.apparent_inertia = c.second;
        expect_invalid([&] { ResolvedModel2 model(valid_object(), arms); }, {"arm 1", "'apparent_inertia'"},
                       c.first);
        expect_invalid([&] { ResolvedModelX model(valid_object(), arms); }, {"arm 1", "'apparent_inertia'"},
                       c.first);
    }
}

TEST(ModelValidation, ResolvedAccelerationRefusesNonFiniteGains)
{
    auto arms = valid_resolved_arms();
    arms[0].end_effector.derivative_gain(1, 2) = nan;
    expect_invalid([&] { ResolvedModel2 model(valid_object(), arms); }, {"arm 0", "'derivative_gain'"}, "K_D");
    arms = valid_resolved_arms();
    arms[1].end_effector.proportional_gain(5, 5) = inf;
    expect_invalid([&] { ResolvedModel2 model(valid_object(), arms); }, {"arm 1", "'proportional_gain'"}, "K_P");
}

TEST(ModelValidation, ResolvedAccelerationRefusesNegativeGains)
{
    // docs/model.md: negative gains are refused. K_P = -100 I and a K_D with one negative
    // eigenvalue used to be accepted.
    auto arms = valid_resolved_arms();
    arms[1].end_effector.proportional_gain = -100.0 * Matrix6d::Identity();
    expect_invalid([&] { ResolvedModel2 model(valid_object(), arms); }, {"arm 1", "'proportional_gain'", "negative"},
                   "K_P < 0");
    arms = valid_resolved_arms();
    arms[0].end_effector.derivative_gain(3, 3) = -0.5;
    expect_invalid([&] { ResolvedModel2 model(valid_object(), arms); }, {"arm 0", "'derivative_gain'", "-0.5"},
                   "one negative K_D entry");
    // Non-symmetric gains with positive eigenvalues (Lambda^-1 D of a matched impedance) and zero
    // gains (a free-floating end-effector) are accepted.
    arms = valid_resolved_arms();
    Matrix6d damping = 30.0 * Matrix6d::Identity();
    damping(0, 1) = damping(1, 0) = 5.0;
    arms[0].end_effector.derivative_gain = arms[0].end_effector.apparent_inertia.inverse() * damping;
    arms[1].end_effector.proportional_gain.setZero();
    EXPECT_NO_THROW(ResolvedModel2(valid_object(), arms));
}

TEST(ModelValidation, NamedConstructionSetsEachFieldByName)
{
    const Matrix3d inertia = Eigen::Vector3d(0.4, 0.5, 0.6).asDiagonal();
    const auto named = coopdyn::ImpedanceEndEffector<double>()
                           .with_mass(10.0)
                           .with_rotational_inertia(inertia)
                           .with_translational_damping(180.0)
                           .with_rotational_damping(10.0)
                           .with_translational_stiffness(300.0)
                           .with_rotational_stiffness(50.0);
    EXPECT_EQ(named.mass, 10.0);
    EXPECT_EQ(named.rotational_inertia, inertia);
    EXPECT_EQ(named.translational_damping, 180.0);
    EXPECT_EQ(named.rotational_damping, 10.0);
    EXPECT_EQ(named.translational_stiffness, 300.0);
    EXPECT_EQ(named.rotational_stiffness, 50.0);
}

TEST(ModelValidation, SetEndEffectorValidatesNamesTheArmAndKeepsTheModelOnError)
{
    Model2 model(valid_object(), valid_impedance_arms());
    const Eigen::Matrix<double, 6, 12> before = model.end_effector_inertias();
    auto arm = model.end_effector(1);
    arm.rotational_stiffness = -1.0;
    expect_invalid([&] { model.set_end_effector(1, arm); }, {"arm 1", "'rotational_stiffness'"}, "kappa < 0");
    arm = model.end_effector(1);
    arm.mass = 0.0;
    expect_invalid([&] { model.set_end_effector(1, arm); }, {"arm 1", "'mass'"}, "m = 0");
    expect_invalid([&] { model.set_end_effector(2, model.end_effector(0)); }, {"'arm'"}, "arm 2 of 2");
    EXPECT_EQ(model.end_effector_inertias(), before);
    EXPECT_EQ(model.end_effector(1).mass, valid_impedance_arms()[1].end_effector.mass);

    // A valid replacement updates every cached form of M_i.
    arm = model.end_effector(0).with_mass(7.5).with_rotational_inertia(Matrix3d::Identity() * 0.25);
    model.set_end_effector(0, arm);
    EXPECT_EQ(model.end_effector_masses()(0), 7.5);
    EXPECT_EQ(model.end_effector_inertia(0).mass(), 7.5);
    EXPECT_EQ(model.end_effector_inertias()(0, 0), 7.5);
    EXPECT_EQ(model.end_effector_inertias()(4, 4), 0.25);
    EXPECT_EQ(model.end_effector_rotational_inertias()(2, 2), 0.25);
}

TEST(ModelValidation, ResolvedAccelerationObjectChecksApplyToo)
{
    auto object = valid_object();
    object.mass = -1.0;
    expect_invalid([&] { ResolvedModel2 model(object, valid_resolved_arms()); }, {"object", "'mass'"}, "object mass");
}

// --- Nothing is clamped or normalised --------------------------------------------------------

TEST(ModelValidation, ValidModelKeepsExactParameterValues)
{
    const auto object = valid_object();
    auto arms = valid_impedance_arms();
    // A grasp quaternion that is unit to 1e-10 but not exactly: accepted and kept as given.
    arms[0].grasp_body.orientation = Quaterniond(Eigen::Vector4d(0.1, 0.2, 0.3, 0.927361849549570).normalized() *
                                                 (1.0 + 5e-11));
    const Vector3d gravity(0.1, -0.2, -9.7);
    const Model2 model(object, arms, gravity);
    EXPECT_EQ(model.arms(), 2);
    EXPECT_EQ(model.object().mass, object.mass);
    EXPECT_EQ(model.object().inertia_body, object.inertia_body);
    EXPECT_EQ(model.gravity(), gravity);
    for (Eigen::Index i = 0; i < 2; ++i) {
        const auto& given = arms[static_cast<std::size_t>(i)];
        const Impedance& kept = model.end_effector(i);
        EXPECT_EQ(kept.mass, given.end_effector.mass);
        EXPECT_EQ(kept.rotational_inertia, given.end_effector.rotational_inertia);
        EXPECT_EQ(kept.translational_damping, given.end_effector.translational_damping);
        EXPECT_EQ(kept.rotational_damping, given.end_effector.rotational_damping);
        EXPECT_EQ(kept.translational_stiffness, given.end_effector.translational_stiffness);
        EXPECT_EQ(kept.rotational_stiffness, given.end_effector.rotational_stiffness);
        EXPECT_EQ(Vector3d(model.grasp_offsets_body().col(i)), given.grasp_body.position);
        EXPECT_EQ(Eigen::Vector4d(model.grasp_orientation_body(i).coeffs()), given.grasp_body.orientation.coeffs());
        EXPECT_EQ(model.end_effector_masses()(i), given.end_effector.mass);
        EXPECT_EQ(Matrix3d(model.end_effector_rotational_inertias().block<3, 3>(0, 3 * i)),
                  given.end_effector.rotational_inertia);
        EXPECT_EQ(Matrix6d(model.end_effector_inertias().block<6, 6>(0, 6 * i)), given.end_effector.inertia().matrix());
    }
    // Default gravity is (0, 0, -9.81).
    const Model2 default_gravity(object, arms);
    EXPECT_EQ(default_gravity.gravity(), Vector3d(0.0, 0.0, -9.81));
}

TEST(ModelValidation, ResolvedModelKeepsExactParameterValues)
{
    const auto arms = valid_resolved_arms();
    const ResolvedModel2 model(valid_object(), arms);
    for (Eigen::Index i = 0; i < 2; ++i) {
        const auto& given = arms[static_cast<std::size_t>(i)].end_effector;
        EXPECT_EQ(model.end_effector(i).apparent_inertia, given.apparent_inertia);
        EXPECT_EQ(model.end_effector(i).derivative_gain, given.derivative_gain);
        EXPECT_EQ(model.end_effector(i).proportional_gain, given.proportional_gain);
        EXPECT_EQ(Matrix6d(model.end_effector_inertias().block<6, 6>(0, 6 * i)), given.apparent_inertia);
    }
}

// --- Tolerances follow the scalar type ------------------------------------------------------

TEST(ModelValidation, FloatModelAcceptsFloatRoundedQuaternionAndInertia)
{
    // A quaternion normalised in float has |norm - 1| ~ 1e-7, far above the double tolerance
    // 1e-9; a thin-beam inertia rotated in float has rounding of the same relative size. Both are
    // valid float parameters and must be accepted; a clearly non-unit quaternion is still refused.
    using ModelF = coopdyn::Model<float, 2, coopdyn::ImpedanceEndEffector>;
    coopdyn::RigidObject<float> object;
    object.mass = 1.75f;
    const Eigen::Matrix3f rotation =
        Eigen::AngleAxisf(0.7f, Eigen::Vector3f(1.0f, 2.0f, 3.0f).normalized()).toRotationMatrix();
    object.inertia_body = rotation * Eigen::Vector3f(0.055f, 0.0f, 0.055f).asDiagonal() * rotation.transpose();
    std::vector<coopdyn::Arm<coopdyn::ImpedanceEndEffector<float>>> arms(2);
    int worst_index = 0;
    double worst_deviation = 0.0;
    for (int k = 0; k < 200; ++k) {
        const float angle = 0.01f * static_cast<float>(k);
        const Eigen::Quaternionf q(Eigen::AngleAxisf(angle, Eigen::Vector3f(0.3f, -0.5f, 0.8f).normalized()));
        const double deviation = std::abs(q.coeffs().cast<double>().norm() - 1.0);
        if (deviation > worst_deviation) {
            worst_deviation = deviation;
            worst_index = k;
        }
    }
    for (std::size_t i = 0; i < 2; ++i) {
        auto& ee = arms[i].end_effector;
        ee.mass = 10.0f;
        ee.rotational_inertia = 0.5f * Eigen::Matrix3f::Identity();
        ee.translational_damping = 180.0f;
        ee.rotational_damping = 10.0f;
        ee.translational_stiffness = 300.0f;
        ee.rotational_stiffness = 50.0f;
        arms[i].grasp_body.position = Eigen::Vector3f(0.0f, i == 0 ? -0.4f : 0.4f, 0.0f);
    }
    arms[1].grasp_body.orientation = Eigen::Quaternionf(
        Eigen::AngleAxisf(0.01f * static_cast<float>(worst_index), Eigen::Vector3f(0.3f, -0.5f, 0.8f).normalized()));
    ASSERT_GT(worst_deviation, 1e-8);  // the case is real: far above the double tolerance 1e-9
    EXPECT_NO_THROW({ ModelF model(object, arms); }) << "norm deviation " << worst_deviation;
    const ModelF model(object, arms);
    EXPECT_EQ(model.grasp_orientation_body(1).coeffs(), arms[1].grasp_body.orientation.coeffs());
    arms[1].grasp_body.orientation = Eigen::Quaternionf(1.001f, 0.0f, 0.0f, 0.0f);
    expect_invalid([&] { ModelF bad(object, arms); }, {"arm 1", "'grasp_body.orientation'"}, "float non-unit");
}

// --- Simulator -------------------------------------------------------------------------------

TEST(SimulatorValidation, RefusesNonPositiveTimeStep)
{
    const Model2 model(valid_object(), valid_impedance_arms());
    const coopdyn::RigidBodyState<double> state{};
    for (const double dt : {0.0, -1e-3, nan, inf}) {
        expect_invalid<coopdyn::InvalidArgument>([&] { coopdyn::Simulator<Model2> simulator(model, dt, state); },
                                                 {"simulator", "'time_step'"},
                                                 ("time step " + std::to_string(dt)).c_str());
    }
    EXPECT_NO_THROW({ coopdyn::Simulator<Model2> simulator(model, 1e-3, state); });
}

TEST(SimulatorValidation, RefusesNonUnitInitialQuaternion)
{
    const ModelX model(valid_object(), valid_impedance_arms());
    for (const Quaterniond& q : {Quaterniond(1.0, 1.0, 0.0, 0.0), Quaterniond(0.0, 0.0, 0.0, 0.0),
                                 Quaterniond(nan, 0.0, 0.0, 0.0)}) {
        coopdyn::RigidBodyState<double> state{};
        state.pose.orientation = q;
        expect_invalid<coopdyn::InvalidArgument>([&] { coopdyn::Simulator<ModelX> simulator(model, 1e-3, state); },
                                                 {"simulator", "'state.pose.orientation'"}, "initial quaternion");
    }
    coopdyn::RigidBodyState<double> state{};
    state.twist(4) = nan;
    expect_invalid<coopdyn::InvalidArgument>([&] { coopdyn::Simulator<ModelX> simulator(model, 1e-3, state); },
                                             {"simulator", "'state.twist'"}, "initial twist");
}

}  // namespace
