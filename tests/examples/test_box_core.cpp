// The dual-arm box example's MuJoCo-free core (examples/box, docs/dual-arm-box.md) against what it
// was not derived from; builds without MuJoCo (tests/examples/test_box_plants.cpp has the checks
// against MuJoCo):
// - the shipped scenarios load; the experiment's friction rows against coopdyn::friction_margin,
//   its tremor's statistics;
// - the arms' own sin and cos (lwr4_dynamics.hpp) against the standard library's;
// - the rigid plant from lwr4.hpp's hold configuration: the box obeys Newton-Euler under the
//   reported palm wrenches, and each arm obeys M qdd + h = tau - J^T w under them; its structured
//   (coopdyn::JointSpaceGrasp) and constraint-space weld solves agree with the generic
//   pseudo-inverse form of (18); a step allocates nothing.
// First: it defines EIGEN_RUNTIME_NO_MALLOC and eigen_assert before Eigen is included.
#include "../allocation_counter.hpp"

#include "box_experiment.hpp"
#include "box_scenario_loader.hpp"
#include "lwr4_dynamics.hpp"
#include "rigid_plant.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <utility>

namespace {

using namespace box_example;

TEST(BoxScenarioLoader, ShippedScenariosLoad)
{
    // The loader needs no MuJoCo: each shipped experiment's file loads as that experiment.
    for (const char* name : {"hold", "push", "add_mass", "circle"}) {
        const BoxScenario scenario = load_box_scenario(std::string(COOPDYN_BOX_DIR) + "/scenarios/" + name + ".json");
        EXPECT_EQ(std::string(to_string(scenario.experiment)), name);
        EXPECT_GT(scenario.duration, 0.0) << name;
        EXPECT_FALSE(scenario.scene.has_value()) << name;  // the LWR 4 pair at its fixed sizes
        // Every other shipped scene's: its scene file, resolved against the scenario's folder.
        for (const std::string scene : {"ur5e_panda", "three_arms"}) {
            const std::string folder = std::string(COOPDYN_BOX_DIR) + "/scenarios/" + scene;
            const BoxScenario on_scene = load_box_scenario(folder + "/" + name + ".json");
            EXPECT_EQ(std::string(to_string(on_scene.experiment)), name) << scene;
            ASSERT_TRUE(on_scene.scene.has_value()) << scene << " " << name;
            EXPECT_TRUE(std::filesystem::equivalent(*on_scene.scene, std::string(COOPDYN_BOX_DIR) + "/../scenes/" +
                                                                         scene + ".json"))
                << *on_scene.scene;
        }
    }
    const auto refused = [](const std::string& scene) -> std::string {
        try {
            parse_box_scenario("{\"name\": \"x\", \"scene\": " + scene +
                                   ", \"experiment\": \"hold\", \"duration\": 1, \"box_mass\": 1, "
                                   "\"plant_friction\": {\"sliding\": 0.5, \"torsional\": 0}}",
                               "dir/s.json");
        } catch (const ScenarioError& error) {
            return error.what();
        }
        return "accepted";
    };
    EXPECT_EQ(refused("\"\""), "dir/s.json: scene: must name a scene file (examples/scenes/*.json)");
    EXPECT_EQ(refused("3"), "dir/s.json: scene: expected a string, got number");
}

// The ranges the command line applies to --duration and --friction hold for the scenario's fields
// too (one definition each: experiment_duration_range, friction_range), and the message names the
// field and the range.
TEST(BoxScenarioLoader, ValuesOutOfTheCommandLinesRangeAreRefused)
{
    const std::string hold = example_common::read_text_file(std::string(COOPDYN_BOX_DIR) + "/scenarios/hold.json");
    const auto refused = [&](const std::string& from, const std::string& to) -> std::string {
        std::string text = hold;
        const std::size_t at = text.find(from);
        EXPECT_NE(at, std::string::npos) << from;
        try {
            parse_box_scenario(text.replace(at, from.size(), to), "edited.json");
        } catch (const ScenarioError& error) {
            return error.what();
        }
        return "accepted";
    };
    EXPECT_EQ(refused("\"friction\": 0.2", "\"friction\": 100"),
              "edited.json: controller.friction: must be between 0.01 and 2, got 100");
    EXPECT_EQ(refused("\"sliding\": 0.5", "\"sliding\": 1e9"),
              "edited.json: plant_friction.sliding: must be between 0.01 and 2, got 1e+09");
    EXPECT_EQ(refused("\"duration\": 4.0", "\"duration\": 0.5"),
              "edited.json: duration: must be between 1 and 3600, got 0.5");
    EXPECT_EQ(friction_range.low, 0.01);
    EXPECT_EQ(friction_range.high, 2.0);
    EXPECT_EQ(example_common::experiment_duration_range.low, 1.0);
    EXPECT_EQ(example_common::experiment_duration_range.high, 3600.0);
    // At the limits they load.
    std::string limits = hold;
    limits.replace(limits.find("\"friction\": 0.2"), 15, "\"friction\": 2.0");
    limits.replace(limits.find("\"duration\": 4.0"), 15, "\"duration\": 1.0");
    const BoxScenario scenario = parse_box_scenario(limits, "limits.json");
    EXPECT_EQ(scenario.controller.friction, 2.0);
    EXPECT_EQ(scenario.duration, 1.0);
}

TEST(BoxScenarioLoader, ObjectivePresetsAndWeights)
{
    const std::string hold = example_common::read_text_file(std::string(COOPDYN_BOX_DIR) + "/scenarios/hold.json");
    // The shipped scenario names no preset: the library's default, the least squeeze (one default,
    // docs/dual-arm-box.md, "The objective"), with its moment weight written out.
    const std::string shipped = "\"moment_weight\": 10000.0";
    ASSERT_NE(hold.find(shipped), std::string::npos);
    ASSERT_EQ(hold.find("\"objective\""), std::string::npos);
    {
        const BoxScenario scenario = parse_box_scenario(hold, "hold.json");
        const coopdyn::SqueezeObjective<double> library{};
        EXPECT_EQ(scenario.controller.objective.internal_weight, library.internal_weight);
        EXPECT_EQ(scenario.controller.objective.torque_weight, library.torque_weight);
        EXPECT_EQ(scenario.controller.objective.moment_weight, library.moment_weight);
        EXPECT_EQ(scenario.controller.objective.squeeze_weight, library.squeeze_weight);
    }
    const auto edited = [&](const std::string& objective) {
        std::string text = hold;
        return text.replace(text.find(shipped), shipped.size(), objective);
    };
    // Each preset gives the library's weights (docs/control.md, "The least squeeze").
    using Objective = coopdyn::SqueezeObjective<double>;
    const std::pair<const char*, Objective> presets[] = {{"least_squeeze", Objective::least_squeeze()},
                                                         {"least_torque_centred", Objective::least_torque_centred()},
                                                         {"paper", Objective::paper()}};
    for (const auto& [name, expected] : presets) {
        const BoxScenario scenario =
            parse_box_scenario(edited("\"objective\": \"" + std::string(name) + "\""), "preset.json");
        EXPECT_EQ(scenario.controller.objective.internal_weight, expected.internal_weight) << name;
        EXPECT_EQ(scenario.controller.objective.torque_weight, expected.torque_weight) << name;
        EXPECT_EQ(scenario.controller.objective.moment_weight, expected.moment_weight) << name;
        EXPECT_EQ(scenario.controller.objective.squeeze_weight, expected.squeeze_weight) << name;
    }
    // A weight given after the preset replaces the preset's.
    const BoxScenario weighted =
        parse_box_scenario(edited("\"objective\": \"paper\", \"moment_weight\": 50"), "weighted.json");
    EXPECT_EQ(weighted.controller.objective.moment_weight, 50.0);
    EXPECT_EQ(weighted.controller.objective.torque_weight, Objective::paper().torque_weight);
    // An unknown preset and an objective without a positive definite term are refused, naming the field.
    const auto refusal = [&](const std::string& objective) -> std::string {
        try {
            parse_box_scenario(edited(objective), "edited.json");
        } catch (const ScenarioError& error) {
            return error.what();
        }
        return "accepted";
    };
    EXPECT_EQ(refusal("\"objective\": \"least_force\""),
              "edited.json: controller.objective: must be one of least_squeeze, least_torque_centred, paper, got "
              "\"least_force\"");
    EXPECT_NE(refusal("\"objective\": \"least_squeeze\", \"internal_weight\": 0").find("controller.squeeze_weight"),
              std::string::npos);
}

TEST(BoxExperiment, UnitRowsGiveTheLibrarysMargin)
{
    // FrictionRows' margin (rows scaled to unit length once) against coopdyn::friction_margin
    // (each row divided by its norm per call) for the true friction's 64-edge pyramid, on wrenches
    // inside, near and outside it.
    const coopdyn::ContactFriction<double> friction = true_friction(PlantFriction{}, 0.03);
    const FrictionRows rows(friction);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    double worst = 0.0;
    for (int trial = 0; trial < 1000; ++trial) {
        Vector6d wrench;
        for (Eigen::Index k = 0; k < 6; ++k) {
            wrench(k) = uniform(rng);
        }
        wrench.head<2>() *= 10.0;
        wrench(2) = 20.0 * uniform(rng);  // negative: pulling, outside
        const double expected = coopdyn::friction_margin(friction, wrench);
        worst = std::max(worst, std::abs(rows.margin(wrench) - expected) / std::max(1.0, std::abs(expected)));
    }
    EXPECT_LT(worst, 1e-14);
}

TEST(BoxExperiment, TremorIsLowPassedNormalNoiseOfTheGivenRms)
{
    // The tremor's samples: zero mean and the requested RMS per axis (the low-pass of standard
    // normal noise scaled by sqrt((2 - gain) / gain)), and the same sequence from the same seed.
    constexpr double rms = 2.0;
    Tremor tremor(rms, 5, controller_period), same_seed(rms, 5, controller_period);
    constexpr int samples = 400000;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero(), sum_of_squares = Eigen::Vector3d::Zero();
    for (int k = 0; k < samples; ++k) {
        const Eigen::Vector3d value = tremor.next();
        ASSERT_EQ(value, same_seed.next());
        sum += value;
        sum_of_squares += value.cwiseProduct(value);
    }
    const Eigen::Vector3d mean = sum / samples;
    const Eigen::Vector3d measured_rms = (sum_of_squares / samples - mean.cwiseProduct(mean)).cwiseSqrt();
    std::printf("tremor: mean (%.3f, %.3f, %.3f), rms (%.3f, %.3f, %.3f), requested %.1f\n", mean(0), mean(1), mean(2),
                measured_rms(0), measured_rms(1), measured_rms(2), rms);
    // 400 s of noise correlated over ~1/(2 pi 5 Hz): about 12 000 independent samples, so the
    // mean's standard error is ~0.02 and the RMS's ~1 %.
    EXPECT_LT(mean.cwiseAbs().maxCoeff(), 0.1);
    EXPECT_LT((measured_rms.array() / rms - 1.0).abs().maxCoeff(), 0.05);
}

TEST(Lwr4Dynamics, SinCosIsTheLibrarysToRounding)
{
    // The recursion's own sin and cos (lwr4_dynamics.hpp) against std::sin and std::cos: within
    // two units of 2^-53 (the reduction's and the polynomials' rounding) up to the reduction
    // limit, the library's own beyond it, and NaN for NaN.
    std::mt19937_64 rng(14);
    double worst = 0.0;
    for (const double range : {1.0, 4.0, 10.0, 1e3, 1e5}) {
        std::uniform_real_distribution<double> uniform(-range, range);
        for (int trial = 0; trial < 20000; ++trial) {
            std::array<double, 8> angle;
            for (double& value : angle) {
                value = uniform(rng);
            }
            const SinCos<8> result = sin_cos(angle);
            for (std::size_t i = 0; i < angle.size(); ++i) {
                worst = std::max({worst, std::abs(result.sine[i] - std::sin(angle[i])),
                                  std::abs(result.cosine[i] - std::cos(angle[i]))});
            }
        }
    }
    EXPECT_LE(worst, 2.0 * std::numeric_limits<double>::epsilon());
    const double quarter = 0.25 * lwr4_pi;
    const std::array<double, 8> special{0.0, -0.0, quarter, 2.0 * quarter, -4.0 * quarter, 6.0 * quarter, 1e7,
                                        std::numeric_limits<double>::quiet_NaN()};
    const SinCos<8> result = sin_cos(special);
    for (std::size_t i = 0; i + 1 < special.size(); ++i) {
        EXPECT_LE(std::abs(result.sine[i] - std::sin(special[i])), 2.0 * std::numeric_limits<double>::epsilon()) << special[i];
        EXPECT_LE(std::abs(result.cosine[i] - std::cos(special[i])), 2.0 * std::numeric_limits<double>::epsilon()) << special[i];
    }
    EXPECT_TRUE(std::isnan(result.sine[7]) && std::isnan(result.cosine[7]));
    std::printf("sin_cos vs std::sin, std::cos: %.3g\n", worst);
}


/// Random joint torques (|tau_j| < 20 N m) and a random wrench on the box (30 N, 3 N m).
std::pair<JointVector, Vector6d> random_drive(std::mt19937_64& rng)
{
    std::uniform_real_distribution<double> torque(-20.0, 20.0), force(-30.0, 30.0);
    JointVector tau;
    for (int j = 0; j < joints; ++j) {
        tau(j) = torque(rng);
    }
    Vector6d push;
    push << force(rng), force(rng), force(rng), 0.1 * force(rng), 0.1 * force(rng), 0.1 * force(rng);
    return {tau, push};
}

TEST(RigidGraspPlant, PalmWrenchesSatisfyNewtonEulerOfBoxAndArms)
{
    RigidGraspPlant plant(hold_state(), box_inertia(1.3));
    std::mt19937_64 rng(5);
    double worst_box = 0.0, worst_arms = 0.0;
    for (int tick = 0; tick < 200; ++tick) {
        const auto [tau, push] = random_drive(rng);
        const PlantState state = plant.state();
        const ArmTerms terms = plant.arm_terms();
        plant.end_tick(tau, push);
        const RigidGraspSolution& solution = plant.solution();
        // The box: m a = m g + F + sum f_i; I alpha + w x I w = T + sum (r_i x f_i + t_i).
        const BoxInertia& box = plant.box();
        const Eigen::Matrix3d rotation = state.box_orientation.toRotationMatrix();
        const Eigen::Matrix3d inertia = rotation * box.inertia * rotation.transpose();
        const Eigen::Vector3d& w = state.box_angular_velocity;
        Eigen::Vector3d force_sum = box.mass * Eigen::Vector3d(0, 0, -9.81) + push.head<3>();
        Eigen::Vector3d moment_sum = push.tail<3>();
        JointVector arm_side = terms.inertia * solution.joint_acceleration + terms.bias - tau;
        for (std::size_t i = 0; i < palms; ++i) {
            const Vector6d& wrench = solution.contact_wrench[i];
            force_sum += wrench.head<3>();
            moment_sum += (terms.palm_position[i] - state.box_position).cross(wrench.head<3>()) + wrench.tail<3>();
            arm_side += terms.jacobian.middleRows<6>(static_cast<Eigen::Index>(6 * i)).transpose() * wrench;
        }
        const Vector6d& a = solution.box_acceleration;
        worst_box = std::max(worst_box, (box.mass * a.head<3>() - force_sum).norm() / (1.0 + force_sum.norm()));
        worst_box = std::max(worst_box, (inertia * a.tail<3>() + w.cross(inertia * w) - moment_sum).norm() /
                                            (1.0 + moment_sum.norm()));
        worst_arms = std::max(worst_arms, arm_side.norm() / (1.0 + tau.norm()));
    }
    // Relative residuals; the 20-coordinate weld system's conditioning (joint inertias from 1e-3
    // to 10 kg m^2) costs a few digits of the 1e-16 rounding.
    EXPECT_LT(worst_box, 1e-7);
    EXPECT_LT(worst_arms, 1e-7);
    std::printf("Newton-Euler residual: box %.3g, arms %.3g (relative)\n", worst_box, worst_arms);
}

TEST(RigidGraspPlant, StructuredConstraintSpaceAndGenericWeldSolversAgree)
{
    // The plant's per-tick path (each palm as a body of its operational-space inertia, solved by
    // the first paper's structured kernel) and the constraint-space form on the stacked system,
    // both against the generic pseudo-inverse form of (18) with multipliers from a QR of A^T,
    // along a driven motion with a heavier box than the controller assumes.
    RigidGraspPlant plant(hold_state(), box_inertia(2.1));
    std::mt19937_64 rng(8);
    using Solver = RigidGraspPlant::WeldSolver;
    std::array<double, 2> worst_acceleration{0.0, 0.0}, worst_wrench{0.0, 0.0};
    for (int tick = 0; tick < 100; ++tick) {
        const auto [tau, push] = random_drive(rng);
        RigidGraspSolution generic;
        plant.solve(plant.state(), plant.arm_terms(), tau, push, generic, true, Solver::generic);
        Eigen::Matrix<double, plant_velocities, 1> generic_acceleration;
        generic_acceleration << generic.joint_acceleration, generic.box_acceleration;
        const std::array<Solver, 2> fast_solvers{Solver::structured, Solver::constraint_space};
        for (std::size_t s = 0; s < fast_solvers.size(); ++s) {
            RigidGraspSolution fast;
            plant.solve(plant.state(), plant.arm_terms(), tau, push, fast, true, fast_solvers[s]);
            Eigen::Matrix<double, plant_velocities, 1> fast_acceleration;
            fast_acceleration << fast.joint_acceleration, fast.box_acceleration;
            worst_acceleration[s] = std::max(worst_acceleration[s], (fast_acceleration - generic_acceleration).norm() /
                                                                        (1.0 + generic_acceleration.norm()));
            for (std::size_t i = 0; i < palms; ++i) {
                worst_wrench[s] = std::max(worst_wrench[s], (fast.contact_wrench[i] - generic.contact_wrench[i]).norm() /
                                                                (1.0 + generic.contact_wrench[i].norm()));
            }
        }
        plant.end_tick(tau, push);
    }
    for (std::size_t s = 0; s < 2; ++s) {
        EXPECT_LT(worst_acceleration[s], 1e-9) << (s == 0 ? "structured" : "constraint space");
        EXPECT_LT(worst_wrench[s], 1e-9) << (s == 0 ? "structured" : "constraint space");
    }
    std::printf("weld solves vs generic: structured accelerations %.3g, wrenches %.3g; constraint space %.3g, %.3g "
                "(relative)\n",
                worst_acceleration[0], worst_wrench[0], worst_acceleration[1], worst_wrench[1]);
}

TEST(RigidGraspPlant, AStepAllocatesNothing)
{
    // The plant's per-tick path (four evaluations of the arms' own dynamics, four structured weld
    // solves) on the heap: neither operator new nor Eigen's malloc.
    RigidGraspPlant plant(hold_state(), box_inertia(0.7));
    std::mt19937_64 rng(9);
    // Not a structured binding: a lambda may not capture one in C++17 (clang++ refuses it).
    const auto drive = random_drive(rng);
    const auto& tau = drive.first;
    const auto& push = drive.second;
    const auto counts = allocation_counter::count_allocations([&] {
        for (int tick = 0; tick < 10; ++tick) {
            plant.end_tick(tau, push);
        }
    });
    EXPECT_EQ(counts.operator_new, 0);
    EXPECT_EQ(counts.eigen, 0);
}


}  // namespace
