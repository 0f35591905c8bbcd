// The error policy (docs/conventions.md, "Errors"): model parameters are refused with
// coopdyn::InvalidModel, other run-time inputs with coopdyn::InvalidArgument; both are a
// coopdyn::Error (a std::invalid_argument) whose fields name the component, the parameter and
// the arm, so that a caller never parses what().
#include <coopdyn/coopdyn.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

struct Expected {
    bool model;  ///< InvalidModel (true) or InvalidArgument (false)
    std::string component;
    std::string parameter;
    coopdyn::Index arm;
};

void expect_refused(const std::function<void()>& action, const Expected& expected, const char* label)
{
    try {
        action();
        ADD_FAILURE() << label << ": nothing thrown";
    } catch (const coopdyn::Error& error) {
        const bool is_model = dynamic_cast<const coopdyn::InvalidModel*>(&error) != nullptr;
        const bool is_argument = dynamic_cast<const coopdyn::InvalidArgument*>(&error) != nullptr;
        EXPECT_EQ(is_model, expected.model) << label << ": " << error.what();
        EXPECT_EQ(is_argument, !expected.model) << label << ": " << error.what();
        EXPECT_EQ(error.component(), expected.component) << label;
        EXPECT_EQ(error.parameter(), expected.parameter) << label;
        EXPECT_EQ(error.arm(), expected.arm) << label;
        EXPECT_EQ(error.has_arm(), expected.arm != coopdyn::no_arm) << label;
        const std::string what = error.what();
        EXPECT_NE(what.find("'" + expected.parameter + "'"), std::string::npos) << what;
        if (expected.arm != coopdyn::no_arm) {
            EXPECT_NE(what.find("arm " + std::to_string(expected.arm)), std::string::npos) << what;
        }
        EXPECT_NE(what.find(error.problem()), std::string::npos) << what;
        // Still catchable as the standard exception it always was.
        EXPECT_NO_THROW((void)static_cast<const std::invalid_argument&>(error).what());
    } catch (...) {
        ADD_FAILURE() << label << ": not a coopdyn::Error";
    }
}

coopdyn::ImpedanceEndEffector<double> arm()
{
    return {10.0, 0.5 * Matrix3d::Identity(), 180.0, 10.0, 300.0, 50.0};
}

coopdyn::RigidObject<double> beam()
{
    return {1.75, Vector3d(0.055, 0.0, 0.055).asDiagonal()};
}

using Arms = std::vector<coopdyn::Arm<coopdyn::ImpedanceEndEffector<double>>>;

Arms two_arms()
{
    return {{arm(), {Vector3d(0, -0.4, 0)}}, {arm(), {Vector3d(0, 0.4, 0)}}};
}

TEST(Errors, ModelParametersAreInvalidModelWithTheirArm)
{
    coopdyn::RigidObject<double> light = beam();
    light.mass = -1.0;
    expect_refused([&] { coopdyn::ImpedanceModelX(light, two_arms()); }, {true, "object", "mass", coopdyn::no_arm},
                   "object mass");

    Arms arms = two_arms();
    arms[1].end_effector.rotational_inertia(2, 2) = -1.0;
    expect_refused([&] { coopdyn::ImpedanceModelX(beam(), arms); }, {true, "end effector", "rotational_inertia", 1},
                   "arm 1 rotational inertia");

    arms = two_arms();
    arms[0].grasp_body.orientation.coeffs() << 0, 0, 0, 2;
    expect_refused([&] { coopdyn::ImpedanceModelX(beam(), arms); },
                   {true, "end effector", "grasp_body.orientation", 0}, "arm 0 grasp orientation");

    expect_refused([&] { coopdyn::ImpedanceModel<3>(beam(), two_arms()); }, {true, "model", "arms", coopdyn::no_arm},
                   "fixed arm count");
    expect_refused([&] { coopdyn::ImpedanceModelX(beam(), two_arms(), Vector3d(0, 0, NAN)); },
                   {true, "model", "gravity", coopdyn::no_arm}, "gravity");
}

TEST(Errors, LoadDistributionWeightsAreInvalidModelWithTheirArm)
{
    const coopdyn::ImpedanceModel2 model(beam(), two_arms());
    expect_refused(
        [&] { coopdyn::LoadDistribution<coopdyn::ImpedanceModel2> refused(model, Eigen::Vector2d(1.0, -1.0),
                                                                          model.end_effector_rotational_inertias()); },
        {true, "load distribution", "mass_weights", 1}, "negative mass weight");
}

TEST(Errors, OtherInputsAreInvalidArgument)
{
    const coopdyn::ImpedanceModel2 model(beam(), two_arms());
    expect_refused([&] { coopdyn::Simulator<coopdyn::ImpedanceModel2> refused(model, 0.0, {}); },
                   {false, "simulator", "time_step", coopdyn::no_arm}, "time step");
    const Eigen::VectorXd samples = Eigen::VectorXd::LinSpaced(50, 0.0, 1.0);
    expect_refused([&] { (void)coopdyn::identify_impedance(samples, samples, -1e-3); },
                   {false, "identification", "sample_period", coopdyn::no_arm}, "sample period");
    expect_refused([&] { (void)coopdyn::synthesize_gains(Eigen::MatrixXd::Zero(2, 3), Eigen::Matrix<double, 6, 6>::Identity()); },
                   {false, "impedance synthesis", "r", coopdyn::no_arm}, "synthesis offsets");
}

}  // namespace
