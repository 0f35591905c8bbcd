// The error policy (docs/conventions.md, "Errors"): model parameters are refused with
// coopdyn::InvalidModel, other run-time inputs with coopdyn::InvalidArgument; both are a
// coopdyn::Error (a std::invalid_argument) whose fields name the component, the parameter and
// the arm, so that a caller never parses what().
#include <coopdyn/coopdyn.hpp>

#include "sample_systems.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using coopdyn_test::Matrix6d;
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
            EXPECT_NE(what.find("coopdyn: arm " + std::to_string(expected.arm) + ": "), std::string::npos) << what;
        } else {
            EXPECT_NE(what.find("coopdyn: " + expected.component + ": "), std::string::npos) << what;
        }
        EXPECT_NE(what.find(error.problem()), std::string::npos) << what;
        EXPECT_FALSE(error.problem().empty()) << label;
    } catch (...) {
        ADD_FAILURE() << label << ": not a coopdyn::Error";
    }
    // Still catchable as the standard exception it always was.
    bool standard = false;
    try {
        action();
    } catch (const std::invalid_argument&) {
        standard = true;
    } catch (...) {
    }
    EXPECT_TRUE(standard) << label << ": not a std::invalid_argument";
}

using coopdyn_test::BeamParameters;
using coopdyn_test::make_model;
using coopdyn_test::section_five_beam;

TEST(Errors, ModelParametersAreInvalidModelWithTheirArm)
{
    BeamParameters light = section_five_beam();
    light.object.mass = -1.0;
    expect_refused([&] { (void)make_model<coopdyn::ImpedanceModelX>(light.object, light.arms); },
                   {true, "object", "mass", coopdyn::no_arm}, "object mass");

    BeamParameters beam = section_five_beam();
    beam.arms[1].inertia(2, 2) = -1.0;
    expect_refused([&] { (void)make_model<coopdyn::ImpedanceModelX>(beam.object, beam.arms); },
                   {true, "end effector", "rotational_inertia", 1}, "arm 1 rotational inertia");

    beam = section_five_beam();
    beam.arms[0].grasp_orientation.coeffs() << 0, 0, 0, 2;
    expect_refused([&] { (void)make_model<coopdyn::ImpedanceModelX>(beam.object, beam.arms); },
                   {true, "end effector", "grasp_body.orientation", 0}, "arm 0 grasp orientation");

    beam = section_five_beam();
    expect_refused([&] { (void)make_model<coopdyn::ImpedanceModel<3>>(beam.object, beam.arms); },
                   {true, "model", "arms", coopdyn::no_arm}, "fixed arm count");
    expect_refused([&] { (void)make_model<coopdyn::ImpedanceModelX>(beam.object, beam.arms, Vector3d(0, 0, NAN)); },
                   {true, "model", "gravity", coopdyn::no_arm}, "gravity");
}

TEST(Errors, LoadDistributionWeightsAreInvalidModelWithTheirArm)
{
    const auto model = coopdyn_test::section_five_beam_model<coopdyn::ImpedanceModel2>();
    expect_refused(
        [&] { coopdyn::LoadDistribution<coopdyn::ImpedanceModel2> refused(model, Eigen::Vector2d(1.0, -1.0),
                                                                          model.end_effector_rotational_inertias()); },
        {true, "load distribution", "mass_weights", 1}, "negative mass weight");
}

TEST(Errors, OtherInputsAreInvalidArgument)
{
    const auto model = coopdyn_test::section_five_beam_model<coopdyn::ImpedanceModel2>();
    expect_refused([&] { coopdyn::Simulator<coopdyn::ImpedanceModel2> refused(model, 0.0, {}); },
                   {false, "simulator", "time_step", coopdyn::no_arm}, "time step");

    const Eigen::VectorXd samples = Eigen::VectorXd::LinSpaced(50, 0.0, 1.0);
    expect_refused([&] { (void)coopdyn::identify_impedance(samples, samples, -1e-3); },
                   {false, "identification", "sample_period", coopdyn::no_arm}, "sample period");
    expect_refused([&] { (void)coopdyn::identify_impedance(samples, samples.head(40), 1e-3); },
                   {false, "identification", "force", coopdyn::no_arm}, "log sizes");

    Matrix6d not_finite = Matrix6d::Identity();
    not_finite(2, 3) = NAN;
    expect_refused([&] { (void)coopdyn::synthesize_gains(Eigen::MatrixXd::Zero(2, 3), Matrix6d::Identity()); },
                   {false, "impedance synthesis", "r", coopdyn::no_arm}, "synthesis offsets");
    expect_refused([&] { (void)coopdyn::synthesize_gains(Eigen::MatrixXd::Zero(3, 2), not_finite); },
                   {false, "impedance synthesis", "target", coopdyn::no_arm}, "synthesis target");

    // Gains are arguments too: refused naming the arm they belong to.
    coopdyn::Data<coopdyn::ImpedanceModel2> data(model);
    coopdyn::grasp_kinematics(model, data, coopdyn::RigidBodyState<double>{});
    coopdyn::SynthesisResult<double> gains =
        coopdyn::synthesize_stiffness(model, data, coopdyn::apparent_impedance(model, data).stiffness);
    ASSERT_TRUE(gains.achievable);
    gains.translational(1) = -1.0;
    expect_refused([&] { (void)coopdyn::arms_with_stiffness(model, gains); },
                   {false, "impedance synthesis", "gains.translational", 1}, "negative stiffness gain of arm 1");
    gains.achievable = false;
    expect_refused([&] { (void)coopdyn::with_stiffness(model, gains); },
                   {false, "impedance synthesis", "gains", coopdyn::no_arm}, "unachievable stiffness");
}

}  // namespace
