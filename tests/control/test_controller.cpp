// Tests of the projected inverse-dynamics controller (include/coopdyn/control/controller.hpp,
// controller_model.hpp). References the controller was not derived from:
// - the exact constrained motion of the arms and a massless object with the contact wrenches as
//   unknowns (tests/common/arm_systems.hpp, solve_physical_model): the object obeys L(15), the
//   contacts apply the predicted wrenches, the posture torque moves neither;
// - closed forms of the contact QP for two opposed palms holding a weight (edge and facet of the
//   pyramid, torsion);
// - the least violation of a load no squeeze can hold, by hand;
// - named errors for bad parameters, statuses for bad per-tick inputs, no allocation per tick.

#include "../allocation_counter.hpp"

#include "coopdyn/control/controller.hpp"

#include "controller_cases.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace {

using coopdyn_test::JointSpaceSystem;
using coopdyn_test::MatrixXd;
using coopdyn_test::random_joint_space_system;
using coopdyn_test::random_vector;
using coopdyn_test::Rng;
using coopdyn_test::Vector3d;
using coopdyn_test::Vector6d;
using coopdyn_test::VectorXd;
using Index = Eigen::Index;
using coopdyn::Dynamic;
using Parameters = coopdyn::ControllerParameters<double>;
using Model = coopdyn::ControllerModel<double, Dynamic, Dynamic>;
using Data = coopdyn::ControllerData<double, Dynamic, Dynamic>;
using Input = coopdyn::ControllerInput<double, Dynamic, Dynamic>;
using Matrix3d = Eigen::Matrix3d;
using Quaterniond = Eigen::Quaterniond;

using Case = coopdyn_test::ControllerCase;
using coopdyn_test::frame_with_normal;
using coopdyn_test::palm_friction;

Case random_case(Index arms, bool torso, Rng& rng) { return coopdyn_test::random_controller_case(arms, torso, rng); }

double relative(const VectorXd& a, const VectorXd& b) { return (a - b).norm() / std::max(b.norm(), 1e-300); }

using ArmCase = coopdyn_test::ArmCase;
constexpr const auto& arm_cases = coopdyn_test::arm_cases;

TEST(Controller, TorquesGiveTheObjectL15AndTheContactsThePredictedWrenches)
{
    Rng rng(101);
    double worst_object = 0, worst_wrench = 0, worst_acceleration = 0, worst_residual = 0, worst_posture = 0;
    int solved = 0, ticks = 0;
    for (const ArmCase& a : arm_cases) {
        for (int trial = 0; trial < 3; ++trial) {
            const Case c = random_case(a.arms, a.torso, rng);
            const Model model(c.parameters);
            Data data(model);
            const VectorXd tau = coopdyn::controller_tick(model, data, c.input);
            ASSERT_TRUE(data.status == coopdyn::ControlStatus::ok ||
                        data.status == coopdyn::ControlStatus::friction_infeasible)
                << coopdyn::to_string(data.status);
            ++ticks;
            solved += data.status == coopdyn::ControlStatus::ok ? 1 : 0;
            ASSERT_TRUE(tau.allFinite());
            // The world: the arms, the massless object, the external wrench the controller estimated.
            const Vector6d F_x = data.external_wrench;
            const auto world = coopdyn_test::solve_physical_model(c.s, tau, F_x);
            worst_residual = std::max(worst_residual, world.residual);
            const Vector6d lhs = data.dynamics.task_inertia * world.object_acceleration + data.dynamics.task_bias;
            worst_object = std::max(worst_object, relative(lhs, data.motion_wrench + F_x));
            worst_wrench = std::max(worst_wrench, relative(world.applied, data.contact_wrenches));
            // The posture torque moves neither the object nor the contacts: without it, the same
            // object acceleration and contact wrenches, and qdd differs by M^-1 tau_n exactly.
            const auto without = coopdyn_test::solve_physical_model(c.s, tau - data.posture_torque, F_x);
            worst_posture = std::max({worst_posture,
                                      relative(without.object_acceleration, world.object_acceleration),
                                      relative(without.applied, world.applied)});
            worst_acceleration = std::max(worst_acceleration, relative(without.qdd, data.joint_acceleration));
            const VectorXd self_motion = c.s.M.llt().solve(VectorXd(data.posture_torque));
            worst_acceleration = std::max(worst_acceleration, relative(world.qdd - without.qdd, self_motion));
            EXPECT_GT(data.posture_torque.norm(), 1e-3);
        }
    }
    std::printf("[ controller vs exact constrained motion ] K = 2..4, %d of %d ticks friction-feasible: L(15) %.1e, "
                "contact wrenches %.1e, qdd %.1e, posture moves object/contacts by %.1e (solve residual %.1e)\n",
                solved, ticks, worst_object, worst_wrench, worst_acceleration, worst_posture, worst_residual);
    EXPECT_LT(worst_residual, 1e-12);
    EXPECT_LT(worst_object, 1e-9);
    EXPECT_LT(worst_wrench, 1e-9);
    EXPECT_LT(worst_acceleration, 1e-9);
    EXPECT_LT(worst_posture, 1e-9);
    EXPECT_GT(solved, 0);
}

TEST(Controller, FeasibleTicksMeetEveryFrictionRowAndTheirReportedMargins)
{
    // The least squeeze torque (the default until the least squeeze, errata E13): z = 0 costs
    // nothing, so at its optimum some friction row binds (asserted below). The least squeeze's
    // rows and margins are checked against an independent QP in test_least_squeeze.cpp.
    Rng rng(102);
    int checked = 0;
    for (const ArmCase& a : arm_cases) {
        for (int trial = 0; trial < 4; ++trial) {
            Case c = random_case(a.arms, a.torso, rng);
            c.parameters.objective = coopdyn::SqueezeObjective<double>::least_torque_centred();
            const Model model(c.parameters);
            Data data(model);
            coopdyn::controller_tick(model, data, c.input);
            if (data.status != coopdyn::ControlStatus::ok) {
                continue;
            }
            ++checked;
            double tightest = 1e300;
            for (Index i = 0; i < a.arms; ++i) {
                // The wrench in the contact frame, rotated by hand.
                const Matrix3d R_ci = c.input.object.pose.orientation.toRotationMatrix() *
                                      model.contact(i).frame.orientation.toRotationMatrix();
                const Vector6d world = data.contact_wrenches.segment<6>(6 * i);
                Vector6d local;
                local << R_ci.transpose() * world.head<3>(), R_ci.transpose() * world.tail<3>();
                EXPECT_LT((local - data.contact_frame_wrenches.col(i)).norm(), 1e-12 * (1 + local.norm()));
                const double margin = coopdyn::friction_margin(model.contact(i).friction, local);
                EXPECT_NEAR(margin, data.friction_margins(i), 1e-9 * (1 + local.norm()));
                const auto split = coopdyn::friction_margins(model.contact(i).friction, local);
                EXPECT_NEAR(split.force, data.force_margins(i), 1e-9 * (1 + local.norm()));
                EXPECT_NEAR(split.moment, data.moment_margins(i), 1e-9 * (1 + local.norm()));
                EXPECT_EQ(std::min(split.force, split.moment), margin);
                EXPECT_GE(margin, -1e-9 * local.norm());
                EXPECT_GE(local(2), palm_friction().minimum_normal_force * (1 - 1e-12));
                tightest = std::min(tightest, margin);
            }
            EXPECT_NEAR(tightest, data.tightest_margin, 1e-9);
            // At the optimum some row binds: the objective would otherwise squeeze less.
            EXPECT_LT(data.tightest_margin, 1e-6);
        }
    }
    EXPECT_GT(checked, 5);
}

// ---- the contact QP against closed forms ---------------------------------------------------

/// Two opposed palms on the x axis hold an object: each "arm" is a free 6-DOF body at its contact
/// (J = I, M = I, h = 0, at rest), so the objective pays only for squeezing. The weight m g is the
/// external wrench the stiffness estimates from the object's sag: the object hangs mg/k below its
/// desired pose, F_x = K_d xtilde = [0, 0, -m g, ...]. `spin` turns both contact frames about their
/// normals away from "the weight along the pyramid's first edge" (spin = 0).
struct TwoPalms {
    Parameters parameters;
    Input input{2, 12};
};

constexpr double half_width = 0.15;  // m, the palms' distance from the centre
constexpr double stiffness = 1000.0;

TwoPalms two_palms(const coopdyn::ContactFriction<double>& friction, double weight, double spin,
                   double twist_about_normal = 0.0)
{
    TwoPalms t;
    Parameters& p = t.parameters;
    p.joints = 12;
    // Contact 1 at -x pushes along +x, contact 2 at +x along -x; the contact x axes point up (world
    // z), so the palms' upward tangential force lies along the pyramid's edge at angle 0.
    Matrix3d left, right;
    left << 0, 0, 1, 0, -1, 0, 1, 0, 0;  // columns x_c = +z, y_c = -y, z_c = +x
    right << 0, 0, -1, 0, 1, 0, 1, 0, 0;  // columns x_c = +z, y_c = +y, z_c = -x
    const Quaterniond spin_about_normal(Eigen::AngleAxisd(spin, Vector3d::UnitZ()));
    coopdyn::ContactPoint<double> a, b;
    a.frame = {Vector3d(-half_width, 0, 0), (Quaterniond(left) * spin_about_normal).normalized()};
    b.frame = {Vector3d(half_width, 0, 0), (Quaterniond(right) * spin_about_normal).normalized()};
    a.friction = b.friction = friction;
    p.contacts = {a, b};
    p.stiffness = stiffness * coopdyn_test::Matrix6d::Identity();
    p.damping = coopdyn_test::Matrix6d::Zero();
    p.posture_stiffness = VectorXd::Zero(12);
    p.posture_damping = VectorXd::Zero(12);

    Input& in = t.input;
    in.inertia = MatrixXd::Identity(12, 12);
    in.jacobian = MatrixXd::Identity(12, 12);
    // Sagged by its weight, and turned about x (the palms' normals) by a torque the palms resist.
    in.object.pose = {Vector3d(0, 0, -weight / stiffness),
                      Quaterniond(Eigen::AngleAxisd(twist_about_normal, Vector3d::UnitX()))};
    return t;
}

coopdyn::ContactFriction<double> rubber(double f_min)
{
    coopdyn::ContactFriction<double> friction;
    friction.friction_coefficient = 0.5;
    friction.torsional_coefficient = 0.01;
    friction.patch_half_length_x = 0.04;
    friction.patch_half_length_y = 0.04;
    friction.minimum_normal_force = f_min;
    friction.pyramid_edges = 8;
    return friction;
}

TEST(ContactQp, TwoPalmsSqueezeMgOverTwoMuAlongAnEdgeAndMoreAlongAFacet)
{
    const double pi = coopdyn::pi<double>();
    const double weight = 2.0 * 9.81;
    for (const double f_min : {1.0, 30.0}) {
        for (const bool facet : {false, true}) {
            const auto friction = rubber(f_min);
            const double spin = facet ? pi / 8 : 0.0;
            const TwoPalms t = two_palms(friction, weight, spin);
            const Model model(t.parameters);
            Data data(model);
            coopdyn::controller_tick(model, data, t.input);
            ASSERT_EQ(data.status, coopdyn::ControlStatus::ok);
            EXPECT_LT((data.external_wrench - Vector6d(0, 0, -weight, 0, 0, 0)).norm(), 1e-12 * weight);
            const double reach = facet ? 0.5 * std::cos(pi / 8) : 0.5;
            const double expected = std::max(f_min, weight / (2.0 * reach));
            for (Index i = 0; i < 2; ++i) {
                const Vector6d w = data.contact_frame_wrenches.col(i);
                EXPECT_NEAR(w(2), expected, 1e-9 * expected) << "f_min " << f_min << " facet " << facet;
                EXPECT_NEAR(std::hypot(w(0), w(1)), weight / 2, 1e-9 * weight);
                EXPECT_LT(w.tail<3>().norm(), 1e-9 * weight);  // no moment: the centre of pressure is central
            }
        }
    }
}

TEST(ContactQp, ATorqueAboutTheNormalsBindsTheTorsionRow)
{
    const double weight = 2.0 * 9.81;
    const double angle = 0.002;  // rad: F_x's moment about x is k sin(angle) = 2.0 N m
    const auto friction = rubber(1.0);
    const TwoPalms t = two_palms(friction, weight, 0.0, angle);
    const Model model(t.parameters);
    Data data(model);
    coopdyn::controller_tick(model, data, t.input);
    ASSERT_EQ(data.status, coopdyn::ControlStatus::ok);
    const double torque = stiffness * std::sin(angle);
    EXPECT_NEAR(data.external_wrench(3), torque, 1e-12 * torque);
    for (Index i = 0; i < 2; ++i) {
        const Vector6d w = data.contact_frame_wrenches.col(i);
        // Each palm resists half the torque about its own normal, and squeezes just hard enough.
        EXPECT_NEAR(std::abs(w(5)), torque / 2, 1e-9 * torque);
        EXPECT_NEAR(friction.torsional_coefficient * w(2), std::abs(w(5)), 1e-9 * torque);
        EXPECT_GT(w(2), weight / (2 * 0.5));  // the torsion row, not the pyramid, sets the squeeze
    }
}

/// Both palms on the face x = -a, pushing along +x, on free 6-DOF hands (J = I); the object
/// pulled away from them along +x by `pull` (its pose error times the stiffness).
TwoPalms pulled_away_from_one_face(double pull, double f_min)
{
    TwoPalms t;
    Parameters& p = t.parameters;
    p.joints = 12;
    coopdyn::ContactPoint<double> a, b;
    const Quaterniond normal_x = frame_with_normal(Vector3d::UnitX(), 0.0);
    a.frame = {Vector3d(-half_width, 0.1, 0), normal_x};
    b.frame = {Vector3d(-half_width, -0.1, 0), normal_x};
    a.friction = b.friction = rubber(f_min);
    p.contacts = {a, b};
    p.stiffness = stiffness * coopdyn_test::Matrix6d::Identity();
    p.posture_stiffness = p.posture_damping = VectorXd::Zero(12);
    t.input.inertia = MatrixXd::Identity(12, 12);
    t.input.jacobian = MatrixXd::Identity(12, 12);
    t.input.object.pose = {Vector3d(pull / stiffness, 0, 0), Quaterniond::Identity()};
    return t;
}

TEST(ContactQp, ALoadNoSqueezeCanHoldGetsTheLeastViolatingSqueeze)
{
    // Both palms on the face x = -a, pushing along +x; the object is pulled away from them along +x
    // by F = 40 N. The hands' net force must be -F_x, so f_1z + f_2z = -F: no f_z >= f_min exists.
    // The least violation of the worst row is that of the unilateral rows at the equal split,
    // f_min + F/2 (the other rows' normalised violations are smaller).
    const double pull = 40.0;
    const double f_min = 3.0;
    const TwoPalms t = pulled_away_from_one_face(pull, f_min);
    const Input& in = t.input;
    const Model model(t.parameters);
    Data data(model);
    const VectorXd tau = coopdyn::controller_tick(model, data, in);
    EXPECT_EQ(data.status, coopdyn::ControlStatus::friction_infeasible);
    EXPECT_EQ(data.qp_status, coopdyn::QpStatus::infeasible);
    EXPECT_TRUE(data.fallback_used);
    EXPECT_TRUE(tau.allFinite());
    EXPECT_NEAR(data.fallback_violation, f_min + pull / 2, 1e-8 * pull);
    EXPECT_NEAR(data.tightest_margin, -(f_min + pull / 2), 1e-8 * pull);
    for (Index i = 0; i < 2; ++i) {
        EXPECT_NEAR(data.contact_frame_wrenches(2, i), -pull / 2, 1e-8 * pull);
    }
    // The fallback's wrenches are still what the arms apply.
    JointSpaceSystem s;
    s.arms = 2;
    s.joints = 12;
    s.M = in.inertia;
    s.h = VectorXd::Zero(12);
    s.J = in.jacobian;
    s.Jdot = MatrixXd::Zero(12, 12);
    s.qdot = VectorXd::Zero(12);
    s.r = data.dynamics.contact_offsets;
    const auto world = coopdyn_test::solve_physical_model(s, tau, data.external_wrench);
    EXPECT_LT(relative(world.applied, data.contact_wrenches), 1e-12);
}

/// Largest centre-of-pressure offset over the contacts, as a fraction of the patch's half-size:
/// max(|t_x| / (delta_y f_z), |t_y| / (delta_x f_z)); 1 is the patch's edge.
double centre_of_pressure_offset(const Data& data, const coopdyn::ContactFriction<double>& friction)
{
    double offset = 0;
    for (Index i = 0; i < data.arms(); ++i) {
        const Vector6d w = data.contact_frame_wrenches.col(i);
        offset = std::max({offset, std::abs(w(3)) / (friction.patch_half_length_y * w(2)),
                           std::abs(w(4)) / (friction.patch_half_length_x * w(2))});
    }
    return offset;
}

TEST(ContactQp, TheMomentWeightKeepsTheCentreOfPressureCentral)
{
    // Two random (weightless) arms hold an object at rest between opposed contacts (r_2 = -r_1)
    // against its weight alone: no contact moment is needed. The paper's objective |tau_c|^2 still leans on
    // the contact moments (they save joint torque) until the centre of pressure reaches the
    // patch's edge; weighted, the moments stay small.
    Rng rng(103);
    const double weight = 3.0 * 9.81;
    double paper_worst = 0, paper_mean = 0, weighted_worst = 0, weighted_mean = 0, least_worst = 0, least_mean = 0;
    int count = 0;
    for (int trial = 0; trial < 20; ++trial) {
        JointSpaceSystem s = random_joint_space_system(2, trial % 2 == 1, rng);
        s.r.col(1) = -s.r.col(0);
        s.qdot.setZero();
        s.h.setZero();  // weightless arms: the object's weight is the only load
        Case c = coopdyn_test::make_controller_case(s, rng);
        c.parameters.stiffness = 500.0 * coopdyn_test::Matrix6d::Identity();
        c.input.object.twist.setZero();
        c.input.object_acceleration.setZero();
        c.input.desired_twist.setZero();
        c.input.desired_acceleration.setZero();
        c.input.desired_pose = {Vector3d(c.input.object.pose.position + Vector3d(0, 0, weight / 500.0)),
                                c.input.object.pose.orientation};
        // The measurement that chose moment_weight = 1e4 next to the paper's squeeze torque (the
        // default until the least squeeze, errata E13).
        c.parameters.objective = coopdyn::SqueezeObjective<double>::least_torque_centred();
        const Model weighted(c.parameters);
        c.parameters.objective = coopdyn::SqueezeObjective<double>::paper();  // |tau_c|^2 alone
        const Model paper(c.parameters);
        c.parameters.objective = coopdyn::SqueezeObjective<double>::least_squeeze();  // the default
        const Model least(c.parameters);
        Data weighted_data(weighted), paper_data(paper), least_data(least);
        coopdyn::controller_tick(weighted, weighted_data, c.input);
        coopdyn::controller_tick(paper, paper_data, c.input);
        coopdyn::controller_tick(least, least_data, c.input);
        if (weighted_data.status != coopdyn::ControlStatus::ok || paper_data.status != coopdyn::ControlStatus::ok ||
            least_data.status != coopdyn::ControlStatus::ok) {
            continue;
        }
        ++count;
        const double p = centre_of_pressure_offset(paper_data, palm_friction());
        const double w = centre_of_pressure_offset(weighted_data, palm_friction());
        paper_worst = std::max(paper_worst, p);
        weighted_worst = std::max(weighted_worst, w);
        paper_mean += p;
        weighted_mean += w;
        const double l = centre_of_pressure_offset(least_data, palm_friction());
        least_worst = std::max(least_worst, l);
        least_mean += l;
        // Optimality of each: the weighted squeeze never has larger contact moments than the paper's.
        EXPECT_LE(weighted_data.contact_frame_wrenches.bottomRows<3>().squaredNorm(),
                  paper_data.contact_frame_wrenches.bottomRows<3>().squaredNorm() * (1 + 1e-9) + 1e-12);
    }
    ASSERT_GT(count, 10);
    paper_mean /= count;
    weighted_mean /= count;
    least_mean /= count;
    std::printf("[ centre of pressure / patch half-size ] %d objects at rest: paper's objective mean %.2f worst "
                "%.2f; least_torque_centred (moment_weight 1e4) mean %.3f worst %.3f; least_squeeze (the default) "
                "mean %.2e worst %.2e\n",
                count, paper_mean, paper_worst, weighted_mean, weighted_worst, least_mean, least_worst);
    EXPECT_GT(paper_worst, 0.999);  // the paper's objective puts it on the patch's edge
    EXPECT_LT(weighted_worst, 0.15);
    EXPECT_LT(least_worst, 0.15);
}

// ---- warm start, fixed sizes, allocation ---------------------------------------------------

TEST(Controller, WarmStartGivesTheColdAnswerOverASequenceOfTicks)
{
    Rng rng(104);
    Case c = random_case(2, false, rng);
    const Model warm_model(c.parameters);
    c.parameters.qp.warm_start = false;
    const Model cold_model(c.parameters);
    Data warm(warm_model), cold(cold_model);
    int warm_steps = 0, cold_steps = 0;
    for (int tick = 0; tick < 50; ++tick) {
        c.input.object_acceleration(2) += 0.05;  // a slowly growing load
        coopdyn::controller_tick(warm_model, warm, c.input);
        coopdyn::controller_tick(cold_model, cold, c.input);
        ASSERT_EQ(warm.status, cold.status);
        EXPECT_LT(relative(warm.torque, cold.torque), 1e-10);
        warm_steps += warm.qp_iterations;
        cold_steps += cold.qp_iterations;
    }
    std::printf("[ warm start ] 50 ticks: %d QP steps warm, %d cold\n", warm_steps, cold_steps);
    EXPECT_LE(warm_steps, cold_steps);
}

TEST(Controller, FixedSizesAgreeWithDynamicAndNoTickAllocates)
{
    Rng rng(105);
    const Case c = random_case(2, false, rng);
    using FixedModel = coopdyn::ControllerModel<double, 2, 14>;
    using FixedInput = coopdyn::ControllerInput<double, 2, 14>;
    const FixedModel fixed_model(c.parameters);
    coopdyn::ControllerData<double, 2, 14> fixed(fixed_model);
    const FixedInput fixed_input(c.input);
    const Model dynamic_model(c.parameters);
    Data dynamic(dynamic_model);
    static_assert(noexcept(coopdyn::controller_tick(fixed_model, fixed, fixed_input)), "per tick");

    for (int tick = 0; tick < 3; ++tick) {  // cold, then warm
        const auto fixed_counts =
            allocation_counter::count_allocations([&] { coopdyn::controller_tick(fixed_model, fixed, fixed_input); });
        const auto dynamic_counts =
            allocation_counter::count_allocations([&] { coopdyn::controller_tick(dynamic_model, dynamic, c.input); });
        EXPECT_EQ(fixed_counts.operator_new + fixed_counts.eigen, 0);
        EXPECT_EQ(dynamic_counts.operator_new + dynamic_counts.eigen, 0);
        EXPECT_EQ(fixed.status, dynamic.status);
        EXPECT_LT(relative(VectorXd(fixed.torque), dynamic.torque), 1e-12);
        EXPECT_LT(relative(VectorXd(fixed.contact_wrenches), dynamic.contact_wrenches), 1e-12);
    }
}

TEST(Controller, TheFallbackAllocatesNothingEither)
{
    const TwoPalms t = pulled_away_from_one_face(50.0, 1.0);  // dynamic sizes
    const Model model(t.parameters);
    Data data(model);
    const Input& in = t.input;
    const auto counts = allocation_counter::count_allocations([&] { coopdyn::controller_tick(model, data, in); });
    EXPECT_EQ(data.status, coopdyn::ControlStatus::friction_infeasible);
    EXPECT_EQ(counts.operator_new + counts.eigen, 0);
}

}  // namespace

// Every member compiles (fixed and dynamic sizes, float, a dynamic pyramid).
template class coopdyn::ControllerModel<double, 2, 14>;
template class coopdyn::ControllerModel<float, 3, 21>;
template class coopdyn::ControllerModel<double, coopdyn::Dynamic, coopdyn::Dynamic, coopdyn::Dynamic>;
template struct coopdyn::ControllerData<double, 2, 15>;
template struct coopdyn::ControllerData<float, 3, 21>;
template struct coopdyn::ControllerData<double, coopdyn::Dynamic, coopdyn::Dynamic, coopdyn::Dynamic>;
