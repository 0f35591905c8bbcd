// Tests of coopdyn::Simulator (include/coopdyn/dynamics/simulator.hpp) against physical
// invariants and closed forms that the implementation was not derived from (docs/conventions.md,
// docs/model.md, docs/dynamics.md, docs/analysis.md): energy conservation (with the potential
// -m_o g^T p_o of errata E7), free fall, momentum conservation, the rigid-grasp constraint, the
// order of convergence of both integrators, the steady state of the Section V beam ((61)), and
// the observer contract of Simulator::run.
//
// Set-ups are deliberately non-symmetric: three arms at asymmetric (seeded random) offsets with
// different masses, inertias and gains, a rotated anisotropic object and a tumbling initial twist.

#include "coopdyn/dynamics/cooperative_dynamics.hpp"
#include "coopdyn/dynamics/energy.hpp"
#include "coopdyn/dynamics/simulator.hpp"
#include "coopdyn/model/cooperative_model.hpp"
#include "coopdyn/model/impedance_end_effector.hpp"
#include "coopdyn/model/rigid_object.hpp"

#include "sample_systems.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cmath>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

namespace {

using coopdyn::Index;
using coopdyn::Integrator;
using coopdyn_test::ArmParameters;
using coopdyn_test::asymmetric_arms;
using coopdyn_test::asymmetric_object;
using coopdyn_test::axis_angle;
using coopdyn_test::BeamParameters;
using coopdyn_test::gaussian_quaternion_wxyz;
using coopdyn_test::make_model;
using coopdyn_test::make_state;
using coopdyn_test::rotation_angle_between;
using coopdyn_test::rotation_matrix;
using coopdyn_test::section_five_beam;
using Vec3 = Eigen::Vector3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;
using Model3 = coopdyn::Model<double, 3>;
using Model2 = coopdyn::Model<double, 2>;
using Sim3 = coopdyn::Simulator<Model3>;
using Sim2 = coopdyn::Simulator<Model2>;
using State = coopdyn::RigidBodyState<double>;
using Setpoints3 = coopdyn::Setpoints<double, 3>;
using Disturbances3 = coopdyn::Disturbances<double, 3>;
using Data3 = coopdyn::Data<Model3>;

constexpr double kPi = 3.14159265358979323846;
const Vec3 kGravity(0.0, 0.0, -9.81);

// ---------------------------------------------------------------------------------------------
// Helpers (written independently of the library's own kinematics).
// ---------------------------------------------------------------------------------------------

// gaussian_quaternion_wxyz, axis_angle (unit axis), rotation_matrix and rotation_angle_between
// (written out), ArmParameters, the three asymmetric_arms, asymmetric_object, make_model and
// make_state: sample_systems.hpp.

Vec6 tumbling_twist()
{
    Vec6 twist;
    twist << 0.10, -0.20, 0.05, 1.2, -0.8, 1.5;  // linear m/s, angular rad/s
    return twist;
}

double total_mass(const Model3& model)
{
    return model.object().mass + model.end_effector_masses().sum();
}

/// Centre of mass of object plus end-effectors (end-effectors as point masses at p_i).
template <typename ModelType>
Vec3 composite_centre_of_mass(const ModelType& model, const coopdyn::Data<ModelType>& data)
{
    Vec3 weighted = model.object().mass * data.object_state.pose.position;
    double mass = model.object().mass;
    for (Index i = 0; i < model.arms(); ++i) {
        weighted += model.end_effector_masses()(i) * data.end_effector_positions.col(i);
        mass += model.end_effector_masses()(i);
    }
    return weighted / mass;
}

/// Distance between two states: position + rotation angle + twist (SI units mixed on purpose;
/// every term is O(1) here and shrinks at the same rate).
double state_distance(const State& a, const State& b)
{
    return (a.pose.position - b.pose.position).norm() +
           rotation_angle_between(a.pose.orientation, b.pose.orientation) + (a.twist - b.twist).norm();
}

template <typename ModelType> double total_energy(const ModelType& model, const coopdyn::Data<ModelType>& data,
                                                  const coopdyn::Setpoints<double, ModelType::arms_at_compile_time>& sp)
{
    return coopdyn::kinetic_energy(model, data) + coopdyn::spring_potential_energy(model, data, sp) +
           coopdyn::gravity_potential_energy(model, data);
}

/// The three-arm model with springs, without dampers (section 1 of the tests), and constant
/// setpoints that load every translational and rotational spring.
struct ConservativeSystem {
    Model3 model;
    Setpoints3 setpoints;
    State initial;

    static ConservativeSystem build(unsigned seed)
    {
        std::mt19937 rng(seed);
        auto arms = asymmetric_arms(rng, /*isotropic_inertia=*/false);
        for (ArmParameters& arm : arms) {
            arm.damping = 0.0;
            arm.rotational_damping = 0.0;
        }
        const coopdyn::RigidObject<double> object = asymmetric_object(rng);
        Model3 model = make_model<Model3>(object, arms, kGravity);
        const State initial = make_state(Vec3(0.1, -0.05, 0.2), gaussian_quaternion_wxyz(rng), tumbling_twist());
        // Setpoints: each arm's grasp pose at the initial object pose, displaced by 4-6 cm and
        // rotated by 0.3-0.5 rad about a random axis, so every spring starts loaded.
        Setpoints3 setpoints(3);
        Data3 data(model);
        coopdyn::grasp_kinematics(model, data, initial);
        std::uniform_real_distribution<double> unit(-1.0, 1.0);
        for (Index i = 0; i < 3; ++i) {
            const Vec3 shift = Vec3(unit(rng), unit(rng), unit(rng)).normalized() * (0.04 + 0.01 * double(i));
            const Quat twist_q =
                axis_angle(0.3 + 0.1 * double(i), Vec3(unit(rng), unit(rng), unit(rng)).normalized());
            const coopdyn::Pose<double> pose = data.end_effector_pose(i);
            setpoints.set_pose(i, coopdyn::Pose<double>(Vec3(pose.position + shift), twist_q * pose.orientation));
        }
        return ConservativeSystem{std::move(model), setpoints, initial};
    }
};

// ---------------------------------------------------------------------------------------------
// 1. Energy
// ---------------------------------------------------------------------------------------------

struct EnergyRecord {
    double initial = 0.0;
    double max_deviation = 0.0;
    double max_deviation_first_half = 0.0;
    double max_deviation_second_half = 0.0;
    double mean_first_second = 0.0;
    double mean_last_second = 0.0;
};

EnergyRecord record_energy(const ConservativeSystem& system, Integrator integrator, double dt, Index steps)
{
    Sim3 sim(system.model, dt, system.initial, integrator);
    sim.setpoints() = system.setpoints;
    EnergyRecord record;
    Data3 data(system.model);
    coopdyn::grasp_kinematics(system.model, data, system.initial);
    record.initial = total_energy(system.model, data, system.setpoints);
    const Index per_second = static_cast<Index>(std::lround(1.0 / dt));
    double sum_first = 0.0;
    double sum_last = 0.0;
    auto account = [&](Index k, const Data3& d) {
        const double deviation = total_energy(system.model, d, system.setpoints) - record.initial;
        record.max_deviation = std::max(record.max_deviation, std::abs(deviation));
        if (k < steps / 2) {
            record.max_deviation_first_half = std::max(record.max_deviation_first_half, std::abs(deviation));
        } else {
            record.max_deviation_second_half = std::max(record.max_deviation_second_half, std::abs(deviation));
        }
        if (k < per_second) {
            sum_first += deviation;
        }
        if (k >= steps - per_second) {
            sum_last += deviation;
        }
    };
    Index k = 0;
    sim.run(steps, [](double, Setpoints3&, Disturbances3&) {},
            [&](double, const State&, const Data3& d) { account(k++, d); });
    coopdyn::grasp_kinematics(system.model, data, sim.state());
    account(steps, data);  // the final state too
    record.mean_first_second = sum_first / double(per_second);
    record.mean_last_second = sum_last / double(per_second);
    return record;
}

TEST(SimulatorEnergy, RungeKutta4ConservesTotalEnergyOfUndampedSprings)
{
    const ConservativeSystem system = ConservativeSystem::build(2024u);
    // Sanity: the initial energy is not dominated by one term (gravity potential is measured from
    // the world origin; p_o starts 0.2 m above it), so a relative bound is meaningful.
    Data3 data(system.model);
    coopdyn::grasp_kinematics(system.model, data, system.initial);
    const double kinetic = coopdyn::kinetic_energy(system.model, data);
    const double spring = coopdyn::spring_potential_energy(system.model, data, system.setpoints);
    const double gravity = coopdyn::gravity_potential_energy(system.model, data);
    EXPECT_GT(kinetic, 0.1);
    EXPECT_GT(spring, 0.1);
    EXPECT_GT(std::abs(gravity), 0.1);

    const EnergyRecord record = record_energy(system, Integrator::runge_kutta_4, 1e-3, 10000);
    const double relative = record.max_deviation / std::abs(record.initial);
    RecordProperty("rk4_relative_energy_drift", std::to_string(relative));
    std::printf("[ energy ] E0 = %.6f J (T %.4f, U_spring %.4f, U_grav %.4f); RK4 1 ms 10 s: "
                "max|E-E0|/|E0| = %.3e\n",
                record.initial, kinetic, spring, gravity, relative);
    EXPECT_LT(relative, 1e-6);
}

TEST(SimulatorEnergy, SemiImplicitEulerEnergyErrorStaysBounded)
{
    const ConservativeSystem system = ConservativeSystem::build(2024u);
    // Bound: symplectic Euler on an oscillator of frequency w conserves a modified energy
    // H~ = E - (h/2) w^2 x v, so |E - H~| / E <= h w / 2 without growth. Linearised about the loaded
    // state, the fastest mode of this system is below ~20 rad/s (K of Theorem 2, docs/analysis.md,
    // against the composite inertia; checked below), so h w / 2 < 1e-2 at h = 1 ms. The tumbling object
    // and the rotations make the scheme only approximately symplectic, hence we also require the
    // error not to grow: the worst deviation over the second five seconds is at most twice that of
    // the first five, and the mean deviation over the last second is within the oscillation band.
    const Model3& model = system.model;
    Data3 data(model);
    coopdyn::grasp_kinematics(model, data, system.initial);
    Eigen::Matrix<double, 6, 6> mass_matrix = model.object().spatial_inertia(data.object_rotation);
    Eigen::Matrix<double, 6, 6> stiffness_matrix = Eigen::Matrix<double, 6, 6>::Zero();
    for (Index i = 0; i < 3; ++i) {
        Eigen::Matrix<double, 6, 6> g = Eigen::Matrix<double, 6, 6>::Identity();
        const Vec3 r = data.grasp_offsets.col(i);
        Mat3 s;
        s << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
        g.bottomLeftCorner<3, 3>() = s;
        Eigen::Matrix<double, 6, 6> k = Eigen::Matrix<double, 6, 6>::Zero();
        k.topLeftCorner<3, 3>() = model.end_effector(i).translational_stiffness * Mat3::Identity();
        k.bottomRightCorner<3, 3>() = model.end_effector(i).rotational_stiffness * Mat3::Identity();
        mass_matrix += g * model.end_effector(i).inertia().matrix() * g.transpose();
        stiffness_matrix += g * k * g.transpose();
    }
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> modes(stiffness_matrix, mass_matrix);
    const double fastest = std::sqrt(modes.eigenvalues().maxCoeff());
    EXPECT_LT(fastest, 20.0);

    const EnergyRecord record = record_energy(system, Integrator::semi_implicit_euler, 1e-3, 10000);
    const double relative = record.max_deviation / std::abs(record.initial);
    std::printf("[ energy ] semi-implicit Euler 1 ms 10 s: fastest mode %.2f rad/s, max|E-E0|/|E0| = %.3e "
                "(first half %.3e, second half %.3e, mean first s %.3e, mean last s %.3e)\n",
                fastest, relative, record.max_deviation_first_half / std::abs(record.initial),
                record.max_deviation_second_half / std::abs(record.initial),
                record.mean_first_second / std::abs(record.initial),
                record.mean_last_second / std::abs(record.initial));
    EXPECT_LT(relative, 1e-2);
    EXPECT_LT(record.max_deviation_second_half, 2.0 * record.max_deviation_first_half);
    EXPECT_LT(std::abs(record.mean_last_second), record.max_deviation_first_half);
}

// ---------------------------------------------------------------------------------------------
// 2. Free fall
// ---------------------------------------------------------------------------------------------
//
// In the model only the object carries gravity (h_g in hSigma_o, docs/model.md); the
// impedance end-effectors (1) have no gravity term (gravity-compensated arms). Two closed forms:
//  (a) pure model, zero stiffness and damping: the only external force on the assembly is m_o g,
//      so its centre of mass accelerates at m_o g / (m_o + sum m_i) -- not at g. If the
//      end-effectors' mass-weighted grasp offsets balance (sum m_i r_i = 0) the object's centre of
//      mass is the assembly's, gravity exerts no torque about it, and the object itself translates
//      at that acceleration without rotating.
//  (b) physical free fall: give every end-effector its own weight, either as a disturbance
//      htilde_i = [m_i g; 0] (a gravity-uncompensated arm) or as a desired wrench
//      h_i^d = -[m_i g; 0] (hSigma_i contains -h_i^d). Then every body feels its own weight in a
//      uniform field, the assembly falls at exactly g from rest without rotating, every body
//      accelerates at [g; 0] and the bodies exert no wrench on each other.

Model3 free_fall_model(std::mt19937& rng, bool balanced)
{
    auto arms = asymmetric_arms(rng, /*isotropic_inertia=*/false);
    for (ArmParameters& arm : arms) {
        arm.damping = arm.rotational_damping = arm.stiffness = arm.rotational_stiffness = 0.0;
    }
    if (balanced) {
        // sum m_i r_i = 0 with three different masses and non-symmetric offsets.
        arms[2].offset_body = -(arms[0].mass * arms[0].offset_body + arms[1].mass * arms[1].offset_body) /
                              arms[2].mass;
    }
    return make_model<Model3>(asymmetric_object(rng), arms, kGravity);
}

TEST(SimulatorFreeFall, GravityCompensatedArmsSlowTheAssemblyToMassRatioTimesG)
{
    std::mt19937 rng(7u);
    for (const bool balanced : {false, true}) {
        SCOPED_TRACE(balanced ? "balanced grasp" : "unbalanced grasp");
        const Model3 model = free_fall_model(rng, balanced);
        const double m = total_mass(model);
        const Vec3 a = model.object().mass / m * kGravity;
        const State initial = make_state(Vec3(0.3, -0.2, 1.0), gaussian_quaternion_wxyz(rng), Vec6::Zero());
        const double dt = 1e-3;
        Sim3 sim(model, dt, initial, Integrator::runge_kutta_4);
        Data3 data(model);
        coopdyn::grasp_kinematics(model, data, initial);
        const Vec3 c0 = composite_centre_of_mass(model, data);
        double worst_acceleration = 0.0;
        sim.run(500, [](double, Setpoints3&, Disturbances3&) {},
                [&](double, const State&, const Data3& d) {
                    // Total external force / total mass, from the per-body accelerations.
                    Vec3 momentum_rate = model.object().mass * d.object_acceleration().head<3>();
                    for (Index i = 0; i < 3; ++i) {
                        momentum_rate += model.end_effector_masses()(i) * d.end_effector_acceleration(i).head<3>();
                    }
                    worst_acceleration = std::max(worst_acceleration, (momentum_rate / m - a).norm());
                    // Newton's third law: the interaction forces cancel.
                    Vec3 force = d.object_wrench().head<3>();
                    for (Index i = 0; i < 3; ++i) {
                        force += d.end_effector_wrench(i).head<3>();
                    }
                    EXPECT_LT(force.norm(), 1e-12);
                });
        const double t = sim.time();
        coopdyn::grasp_kinematics(model, data, sim.state());
        const Vec3 c = composite_centre_of_mass(model, data);
        const double error = (c - (c0 + 0.5 * a * t * t)).norm();
        std::printf("[ free fall ] %s, pure model: |a_c - m_o g/M| <= %.2e, |c(0.5 s) - closed form| = %.2e, "
                    "|w_o(0.5 s)| = %.2e\n",
                    balanced ? "balanced" : "unbalanced", worst_acceleration, error,
                    sim.state().twist.tail<3>().norm());
        EXPECT_LT(worst_acceleration, 1e-12);
        EXPECT_LT(error, 1e-9);
        if (balanced) {
            // No torque about the common centre of mass: the object translates at a, no rotation.
            const Vec3 expected = initial.pose.position + 0.5 * a * t * t;
            EXPECT_LT((sim.state().pose.position - expected).norm(), 1e-9);
            EXPECT_LT(sim.state().twist.tail<3>().norm(), 1e-12);
            EXPECT_LT(rotation_angle_between(sim.state().pose.orientation, initial.pose.orientation), 1e-12);
        } else {
            // The object's own weight acts off the assembly's centre of mass: it must rotate.
            EXPECT_GT(sim.state().twist.tail<3>().norm(), 1e-2);
        }
    }
}

TEST(SimulatorFreeFall, ArmsCarryingTheirWeightFallAtGWithoutInteraction)
{
    std::mt19937 rng(11u);
    const Model3 model = free_fall_model(rng, /*balanced=*/false);
    for (const bool via_disturbance : {true, false}) {
        SCOPED_TRACE(via_disturbance ? "weight as disturbance htilde_i" : "weight as desired wrench h_i^d");
        const State initial = make_state(Vec3(-0.4, 0.25, 2.0), gaussian_quaternion_wxyz(rng), Vec6::Zero());
        const double dt = 1e-3;
        Sim3 sim(model, dt, initial, Integrator::runge_kutta_4);
        for (Index i = 0; i < 3; ++i) {
            Vec6 weight = Vec6::Zero();
            weight.head<3>() = model.end_effector_masses()(i) * kGravity;
            if (via_disturbance) {
                sim.disturbances().end_effector(i) = weight;
            } else {
                sim.setpoints().wrench(i) = -weight;
            }
        }
        Vec6 g6 = Vec6::Zero();
        g6.head<3>() = kGravity;
        double worst_acceleration = 0.0;
        double worst_wrench = 0.0;
        sim.run(500, [](double, Setpoints3&, Disturbances3&) {},
                [&](double, const State&, const Data3& d) {
                    worst_acceleration = std::max(worst_acceleration, (d.object_acceleration() - g6).norm());
                    for (Index i = 0; i < 3; ++i) {
                        worst_acceleration =
                            std::max(worst_acceleration, (d.end_effector_acceleration(i) - g6).norm());
                    }
                    worst_wrench = std::max(worst_wrench, d.wrenches.cwiseAbs().maxCoeff());
                });
        const double t = sim.time();
        const Vec3 expected = initial.pose.position + 0.5 * kGravity * t * t;
        const double error = (sim.state().pose.position - expected).norm();
        std::printf("[ free fall ] weight via %s: |xdd - [g;0]| <= %.2e, max |h| = %.2e N, "
                    "|p_o(0.5 s) - (p0 + g t^2/2)| = %.2e m\n",
                    via_disturbance ? "htilde_i" : "h_i^d", worst_acceleration, worst_wrench, error);
        EXPECT_NEAR(t, 0.5, 1e-12);
        EXPECT_LT(worst_acceleration, 1e-12);
        EXPECT_LT(worst_wrench, 1e-11);  // weights are ~50 N; rounding only
        EXPECT_LT(error, 1e-9);
        EXPECT_LT((sim.state().twist.head<3>() - kGravity * t).norm(), 1e-10);
        EXPECT_LT(sim.state().twist.tail<3>().norm(), 1e-12);
        EXPECT_LT(rotation_angle_between(sim.state().pose.orientation, initial.pose.orientation), 1e-12);
    }
}

// ---------------------------------------------------------------------------------------------
// 3. Momentum
// ---------------------------------------------------------------------------------------------

TEST(SimulatorMomentum, FreeTumblingAssemblyConservesMomentaAndKineticEnergy)
{
    // No springs, dampers or gravity: the assembly is a free rigid body (isotropic J_i, so each
    // end-effector is a sphere whose world inertia does not change as it rotates). The only
    // wrenches are the interaction wrenches, which obey Newton's third law and do no work on the
    // constrained motion, so P, L (about the world origin) and T are constants of motion.
    // RK4 at 1 ms, 2 s; |w_o| = 2.1 rad/s.
    std::mt19937 rng(99u);
    auto arms = asymmetric_arms(rng, /*isotropic_inertia=*/true);
    for (ArmParameters& arm : arms) {
        arm.damping = arm.rotational_damping = arm.stiffness = arm.rotational_stiffness = 0.0;
    }
    const Model3 model = make_model<Model3>(asymmetric_object(rng), arms, Vec3::Zero());
    const State initial = make_state(Vec3(0.5, -0.3, 0.8), gaussian_quaternion_wxyz(rng), tumbling_twist());
    Sim3 sim(model, 1e-3, initial, Integrator::runge_kutta_4);
    Data3 data(model);
    coopdyn::grasp_kinematics(model, data, initial);
    const Vec3 p0 = coopdyn::linear_momentum(model, data);
    const Vec3 l0 = coopdyn::angular_momentum(model, data);
    const double t0 = coopdyn::kinetic_energy(model, data);
    const Vec3 c0 = composite_centre_of_mass(model, data);
    double dp = 0.0, dl = 0.0, dt_energy = 0.0;
    auto account = [&](const Data3& d) {
        dp = std::max(dp, (coopdyn::linear_momentum(model, d) - p0).norm() / p0.norm());
        dl = std::max(dl, (coopdyn::angular_momentum(model, d) - l0).norm() / l0.norm());
        dt_energy = std::max(dt_energy, std::abs(coopdyn::kinetic_energy(model, d) - t0) / t0);
    };
    sim.run(2000, [](double, Setpoints3&, Disturbances3&) {}, [&](double, const State&, const Data3& d) { account(d); });
    coopdyn::grasp_kinematics(model, data, sim.state());
    account(data);
    // The composite centre of mass moves uniformly at P / M (independent closed form).
    const Vec3 c = composite_centre_of_mass(model, data);
    const double c_error = (c - (c0 + p0 / total_mass(model) * sim.time())).norm();
    std::printf("[ momentum ] RK4 1 ms 2 s: |dP|/|P| = %.2e, |dL|/|L| = %.2e, |dT|/T = %.2e, centre of mass "
                "error %.2e m\n",
                dp, dl, dt_energy, c_error);
    EXPECT_LT(dp, 1e-10);
    EXPECT_LT(dl, 1e-10);
    EXPECT_LT(dt_energy, 1e-10);
    EXPECT_LT(c_error, 1e-10);
}

// ---------------------------------------------------------------------------------------------
// 4. Constraint satisfaction
// ---------------------------------------------------------------------------------------------

TEST(SimulatorConstraints, EveryStepSatisfiesTheRigidGraspExactly)
{
    const ConservativeSystem system = ConservativeSystem::build(31u);
    for (const Integrator integrator : {Integrator::runge_kutta_4, Integrator::semi_implicit_euler}) {
        Sim3 sim(system.model, 1e-3, system.initial, integrator);
        sim.setpoints() = system.setpoints;
        double position_error = 0.0, norm_error = 0.0, orientation_error = 0.0, twist_error = 0.0;
        sim.run(1000, [](double, Setpoints3&, Disturbances3&) {},
                [&](double, const State& s, const Data3& d) {
                    const Quat& q = s.pose.orientation;
                    norm_error = std::max(norm_error, std::abs(q.norm() - 1.0));
                    const Mat3 r = rotation_matrix(q);
                    const Vec3 w = s.twist.tail<3>();
                    for (Index i = 0; i < 3; ++i) {
                        const Vec3 ri = r * system.model.grasp_offsets_body().col(i);
                        position_error = std::max(
                            position_error, (d.end_effector_positions.col(i) - s.pose.position - ri).norm());
                        const Quat qi = d.end_effector_pose(i).orientation;
                        norm_error = std::max(norm_error, std::abs(qi.norm() - 1.0));
                        orientation_error = std::max(
                            orientation_error,
                            rotation_angle_between(qi, q * system.model.grasp_orientation_body(i)));
                        Vec6 expected_twist;
                        expected_twist << s.twist.head<3>() + w.cross(ri), w;
                        twist_error = std::max(twist_error, (d.end_effector_twist(i) - expected_twist).norm());
                    }
                });
        std::printf("[ constraints ] %s: |p_i - p_o - R r_i| <= %.1e, ||q|-1| <= %.1e, angle(q_i, q_o dq_i) "
                    "<= %.1e, twist <= %.1e\n",
                    integrator == Integrator::runge_kutta_4 ? "RK4" : "Euler", position_error, norm_error,
                    orientation_error, twist_error);
        EXPECT_LT(position_error, 1e-15);
        EXPECT_LE(norm_error, 1e-15);
        EXPECT_LT(orientation_error, 1e-14);
        EXPECT_LT(twist_error, 1e-14);
    }
}

// ---------------------------------------------------------------------------------------------
// 5. Order of convergence, with time-varying inputs evaluated at the stage times
// ---------------------------------------------------------------------------------------------

/// Multisine disturbance on the object and on arm 1, plus a moving setpoint for arm 0.
struct MultisineInputs {
    void operator()(double t, Setpoints3& setpoints, Disturbances3& disturbances) const
    {
        const double w1 = 2 * kPi * 0.7, w2 = 2 * kPi * 1.9, w3 = 2 * kPi * 3.1;
        disturbances.object << 4.0 * std::sin(w1 * t) + 2.0 * std::sin(w3 * t + 0.4),
            -3.0 * std::cos(w2 * t + 1.0), 2.5 * std::sin(w2 * t) - 1.5 * std::cos(w1 * t),
            0.4 * std::sin(w3 * t + 0.2), 0.3 * std::cos(w1 * t) + 0.2 * std::sin(w2 * t), -0.5 * std::sin(w1 * t + 0.7);
        disturbances.end_effector(1) << 1.5 * std::cos(w3 * t), 0.0, 2.0 * std::sin(w1 * t + 0.3), 0.1 * std::sin(w2 * t),
            0.0, 0.2 * std::cos(w2 * t);
        // A sinusoidal setpoint trajectory (pose, twist and acceleration consistent).
        const double amplitude = 0.03;
        setpoints.positions.col(0) = base_position + Vec3(amplitude * std::sin(w1 * t), 0.0, 0.0);
        setpoints.twist(0).head<3>() = Vec3(amplitude * w1 * std::cos(w1 * t), 0.0, 0.0);
        setpoints.acceleration(0).head<3>() = Vec3(-amplitude * w1 * w1 * std::sin(w1 * t), 0.0, 0.0);
    }
    Vec3 base_position;
};

struct ConvergenceSystem {
    Model3 model;
    Setpoints3 setpoints;
    State initial;
    MultisineInputs inputs;
};

ConvergenceSystem convergence_system()
{
    std::mt19937 rng(4242u);
    const auto arms = asymmetric_arms(rng, /*isotropic_inertia=*/false);  // damped, springs on
    Model3 model = make_model<Model3>(asymmetric_object(rng), arms, kGravity);
    const State initial = make_state(Vec3(0.0, 0.1, 0.3), gaussian_quaternion_wxyz(rng), tumbling_twist());
    Setpoints3 setpoints(3);
    Data3 data(model);
    coopdyn::grasp_kinematics(model, data, initial);
    for (Index i = 0; i < 3; ++i) {
        setpoints.set_pose(i, coopdyn::Pose<double>(Vec3(data.end_effector_positions.col(i) + Vec3(0.02, -0.03, 0.01)),
                                                    axis_angle(0.2, Vec3(1, 2, 3).normalized()) * data.end_effector_pose(i).orientation));
    }
    MultisineInputs inputs{Vec3(setpoints.positions.col(0))};
    return ConvergenceSystem{std::move(model), setpoints, initial, inputs};
}

State simulate(const ConvergenceSystem& system, Integrator integrator, double dt, double duration)
{
    Sim3 sim(system.model, dt, system.initial, integrator);
    sim.setpoints() = system.setpoints;
    const Index steps = static_cast<Index>(std::lround(duration / dt));
    for (Index k = 0; k < steps; ++k) {
        sim.step(system.inputs);
    }
    return sim.state();
}

TEST(SimulatorConvergence, RungeKutta4IsFourthOrderAndSemiImplicitEulerFirstOrder)
{
    const ConvergenceSystem system = convergence_system();
    const double duration = 0.512;  // a whole number of steps for every dt below
    const std::array<double, 3> steps{8e-3, 4e-3, 2e-3};
    // Reference: RK4 at dt_min / 16 (its own error is ~16^4 smaller than the RK4 error at dt_min).
    const State reference = simulate(system, Integrator::runge_kutta_4, steps.back() / 16, duration);
    // The state moved substantially (the comparison is not against a trivial solution).
    ASSERT_GT(state_distance(reference, system.initial), 0.1);

    for (const Integrator integrator : {Integrator::runge_kutta_4, Integrator::semi_implicit_euler}) {
        const bool rk4 = integrator == Integrator::runge_kutta_4;
        std::array<double, 3> errors{};
        for (std::size_t j = 0; j < steps.size(); ++j) {
            errors[j] = state_distance(simulate(system, integrator, steps[j], duration), reference);
        }
        const double ratio1 = errors[0] / errors[1];
        const double ratio2 = errors[1] / errors[2];
        std::printf("[ convergence ] %s: errors %.3e %.3e %.3e (dt = 8, 4, 2 ms), ratios %.2f %.2f\n",
                    rk4 ? "RK4" : "semi-implicit Euler", errors[0], errors[1], errors[2], ratio1, ratio2);
        if (rk4) {
            // Fourth order: 2^4 = 16 per halving (asymptotic regime; allow +-25%).
            EXPECT_GT(ratio1, 12.0);
            EXPECT_LT(ratio1, 20.0);
            EXPECT_GT(ratio2, 12.0);
            EXPECT_LT(ratio2, 20.0);
        } else {
            // First order: 2 per halving.
            EXPECT_GT(ratio1, 1.7);
            EXPECT_LT(ratio1, 2.3);
            EXPECT_GT(ratio2, 1.7);
            EXPECT_LT(ratio2, 2.3);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// 6. The Section V beam ((56), (59), (61), docs/analysis.md), held still and pushed
// ---------------------------------------------------------------------------------------------

struct Beam {
    Model2 model;
    State equilibrium;
    coopdyn::Setpoints<double, 2> setpoints;
};

Beam section9_beam()
{
    const BeamParameters beam = section_five_beam(1e-4);  // J_o invertible for the simulation
    Model2 model = make_model<Model2>(beam.object, beam.arms, kGravity);
    const State equilibrium = make_state(Vec3(0.2, 0.0, 1.0), Quat::Identity(), Vec6::Zero());
    coopdyn::Setpoints<double, 2> setpoints(2);
    coopdyn::Data<Model2> data(model);
    coopdyn::grasp_kinematics(model, data, equilibrium);
    for (Index i = 0; i < 2; ++i) {
        setpoints.set_pose(i, data.end_effector_pose(i));  // x_i^d at the grasp poses (38)
        // Gravity compensation (h_o^d = h_g = [-m_o g; 0] distributed equally by (26)): the arms
        // must push UP on the object, hbar_i = -(1/2) m_o g (g points down), so the wrench ON arm i
        // is h_i = -hbar_i = +(1/2) [m_o g; 0], pointing down. At rest at the setpoint (1) gives
        // h_i = h_i^d, hence h_i^d = +(1/2) [m_o g; 0] = (0, 0, -8.584 N; 0).
        setpoints.wrench(i).head<3>() = 0.5 * beam.object.mass * kGravity;
    }
    return Beam{std::move(model), equilibrium, setpoints};
}

State beam_steady_state(const Beam& beam, const Vec6& disturbance, double duration)
{
    Sim2 sim(beam.model, 1e-3, beam.equilibrium, Integrator::runge_kutta_4);
    sim.setpoints() = beam.setpoints;
    sim.disturbances().object = disturbance;
    const Index steps = static_cast<Index>(std::lround(duration / 1e-3));
    for (Index k = 0; k < steps; ++k) {
        sim.step();
    }
    return sim.state();
}

TEST(SimulatorBeam, GravityCompensatedBeamIsHeldStill)
{
    const Beam beam = section9_beam();
    const State s = beam_steady_state(beam, Vec6::Zero(), 0.5);
    std::printf("[ beam ] no disturbance, 0.5 s: |p_o - p_eq| = %.2e m, |xdot_o| = %.2e\n",
                (s.pose.position - beam.equilibrium.pose.position).norm(), s.twist.norm());
    EXPECT_LT((s.pose.position - beam.equilibrium.pose.position).norm(), 1e-12);
    EXPECT_LT(s.twist.norm(), 1e-12);
    EXPECT_LT(rotation_angle_between(s.pose.orientation, beam.equilibrium.pose.orientation), 1e-12);
}

TEST(SimulatorBeam, PushedBeamSettlesAtTheApparentStiffness)
{
    const Beam beam = section9_beam();
    // K = diag(600 I3, 196, 100, 196) ((61), docs/analysis.md): K_xx = 2 k = 600,
    // K_zz = 2 kappa + 2 k 0.4^2 = 196. A 10 N force in x and a 1 Nm torque about z are applied
    // together: for this symmetric grasp (r_1 = -r_2, equal arms) a translation d and a rotation
    // about z do not couple in the restoring wrench (sum k (R - I) r_i = 0 and
    // sum R r_i x k d = 0), so each steady state is the single-load one.
    // Slowest modes: translation (M 21.75, D 360, K 600) has real poles -1.88 and -14.7 1/s,
    // rotation about z (4.255, 77.6, 196) -3.0 and -15.2 1/s. After 6.5 s the translational
    // transient is below 1.15 * (10/600) * exp(-1.88 * 6.5) ~ 1e-7 m. (RK4 at 1 ms; the fixed point
    // of the integrator is the equilibrium itself, independent of the step.)
    Vec6 load = Vec6::Zero();
    load(0) = 10.0;  // N along x
    load(5) = 1.0;   // N m about z
    const State pushed = beam_steady_state(beam, load, 6.5);
    const Vec3 displacement = pushed.pose.position - beam.equilibrium.pose.position;
    // The restoring force is exactly linear in a pure translation, so 10/600 is exact.
    std::printf("[ beam ] 10 N in x: displacement %.9f m (10/600 = %.9f), error %.2e; |y, z| %.1e\n",
                displacement.x(), 10.0 / 600.0, std::abs(displacement.x() - 10.0 / 600.0),
                displacement.tail<2>().norm());
    EXPECT_NEAR(displacement.x(), 10.0 / 600.0, 1e-6);
    EXPECT_LT(displacement.tail<2>().norm(), 1e-12);

    const Quat e = pushed.pose.orientation * beam.equilibrium.pose.orientation.conjugate();
    const double angle = 2.0 * std::atan2(e.z(), e.w());  // signed angle about z
    // Exact restoring torque for a rotation theta about z: each rotational spring gives
    // kappa sin(theta); each translational spring, stretched by (R - I) r_i, gives k |r_i|^2 sin(theta)
    // about the centre (the forces cancel since r_1 = -r_2). So 196 sin(theta) = 1 in steady state.
    // The small-angle value 1/196 differs from asin(1/196) by theta^3/6 = 2.2e-8 rad.
    std::printf("[ beam ] 1 Nm about z: angle %.10f rad, asin(1/196) = %.10f, 1/196 = %.10f, error vs asin "
                "%.2e\n",
                angle, std::asin(1.0 / 196.0), 1.0 / 196.0, std::abs(angle - std::asin(1.0 / 196.0)));
    EXPECT_NEAR(angle, std::asin(1.0 / 196.0), 1e-9);
    EXPECT_NEAR(angle, 1.0 / 196.0, 5e-8);       // small-angle K_zz = 196, tolerance > theta^3 / 6
    EXPECT_LT(std::hypot(e.x(), e.y()), 1e-12);  // no rotation about x or y
    EXPECT_LT(pushed.twist.norm(), 1e-6);        // at rest
}

// ---------------------------------------------------------------------------------------------
// 7. Observer contract of Simulator::run
// ---------------------------------------------------------------------------------------------

TEST(SimulatorObserver, ReceivesStepStartStateAndItsEvaluation)
{
    const ConvergenceSystem system = convergence_system();
    for (const Integrator integrator : {Integrator::runge_kutta_4, Integrator::semi_implicit_euler}) {
        const double dt = 2e-3;
        Sim3 sim(system.model, dt, system.initial, integrator);
        sim.setpoints() = system.setpoints;
        Setpoints3 setpoints = system.setpoints;
        Disturbances3 disturbances(3);
        Data3 check(system.model);
        State previous_end = system.initial;
        Index calls = 0;
        double worst = 0.0;
        // The reference state sequence: the same simulator stepped by step() alone.
        Sim3 twin(system.model, dt, system.initial, integrator);
        twin.setpoints() = system.setpoints;
        sim.run(
            200, system.inputs,
            [&](double t, const State& s, const Data3& d) {
                EXPECT_NEAR(t, double(calls) * dt, 1e-15);  // time_ += dt accumulates rounding
                // The state the step started from: where the previous step ended, bit for bit.
                EXPECT_EQ(s.pose.position, previous_end.pose.position);
                EXPECT_EQ(s.pose.orientation.coeffs(), previous_end.pose.orientation.coeffs());
                EXPECT_EQ(s.twist, previous_end.twist);
                // The evaluation at that state and the inputs at that time.
                system.inputs(t, setpoints, disturbances);
                coopdyn::interaction_dynamics(system.model, check, s, setpoints, disturbances);
                worst = std::max(worst, (d.wrenches - check.wrenches).norm() / check.wrenches.norm());
                worst = std::max(worst, (d.accelerations - check.accelerations).norm() /
                                            check.accelerations.norm());
                EXPECT_EQ(d.object_state.pose.position, s.pose.position);
                twin.step(system.inputs);
                previous_end = twin.state();
                ++calls;
            });
        std::printf("[ observer ] %s: worst relative difference to a separate interaction_dynamics: %.1e\n",
                    integrator == Integrator::runge_kutta_4 ? "RK4" : "Euler", worst);
        EXPECT_EQ(calls, 200);
        EXPECT_LE(worst, 1e-14);
        EXPECT_EQ(sim.state().twist, twin.state().twist);
        EXPECT_NEAR(sim.time(), 200 * dt, 1e-12);
        // data() after the run is the evaluation at the start of the last step.
        EXPECT_EQ(sim.data().wrenches, check.wrenches);
    }
}

TEST(SimulatorObserver, InputsAreSampledAtTheStageTimes)
{
    // RK4 samples the inputs at t, t + dt/2 (twice) and t + dt; semi-implicit Euler at t only.
    const ConvergenceSystem system = convergence_system();
    const double dt = 4e-3;
    for (const Integrator integrator : {Integrator::runge_kutta_4, Integrator::semi_implicit_euler}) {
        Sim3 sim(system.model, dt, system.initial, integrator);
        sim.setpoints() = system.setpoints;
        std::vector<double> times;
        for (int k = 0; k < 3; ++k) {
            sim.step([&](double t, Setpoints3& sp, Disturbances3& d) {
                times.push_back(t);
                system.inputs(t, sp, d);
            });
        }
        if (integrator == Integrator::runge_kutta_4) {
            ASSERT_EQ(times.size(), 12u);
            for (std::size_t k = 0; k < 3; ++k) {
                const double t0 = double(k) * dt;
                EXPECT_NEAR(times[4 * k], t0, 1e-15);
                EXPECT_NEAR(times[4 * k + 1], t0 + dt / 2, 1e-15);
                EXPECT_NEAR(times[4 * k + 2], t0 + dt / 2, 1e-15);
                EXPECT_NEAR(times[4 * k + 3], t0 + dt, 1e-15);
            }
        } else {
            ASSERT_EQ(times.size(), 3u);
            for (std::size_t k = 0; k < 3; ++k) {
                EXPECT_NEAR(times[k], double(k) * dt, 1e-15);
            }
        }
    }
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// 8. Feedback inputs, zero-order hold, time from a step count, non-finite states.
// ---------------------------------------------------------------------------------------------
namespace {

/// The Section V beam (zero gravity) moving along x, with arm damping d_i = translational_damping.
Model2 translating_beam_model(double translational_damping)
{
    BeamParameters beam = section_five_beam(1e-4);
    for (ArmParameters& arm : beam.arms) {
        arm.damping = translational_damping;
    }
    return make_model<Model2>(beam.object, beam.arms, Vec3::Zero());
}

/// Setpoints at the grasp poses of the beam at rest at the origin.
coopdyn::Setpoints<double, 2> beam_setpoints(const Model2& model, const State& rest)
{
    coopdyn::Setpoints<double, 2> setpoints;
    coopdyn::Data<Model2> data(model);
    coopdyn::grasp_kinematics(model, data, rest);
    for (Index i = 0; i < 2; ++i) {
        setpoints.set_pose(i, data.end_effector_pose(i));
    }
    return setpoints;
}

}  // namespace

TEST(SimulatorFeedback, StageStateFeedbackEqualsTheSameTermBuiltIntoTheModel)
{
    // A drag -c v_o on the object, fed back from the stage state, is the same ODE as c / 2 more
    // translational damping on each of the two arms while the beam only translates (v_i = v_o):
    // RK4 must give the same trajectory up to rounding. Fed back from the step's start state
    // (all that the old callback could see) it is a first-order error in dt.
    const double c = 400.0;
    const double base_damping = 180.0;
    const Model2 built_in = translating_beam_model(base_damping + c / 2);
    const Model2 plain = translating_beam_model(base_damping);
    const State rest = make_state(Vec3::Zero(), Quat::Identity(), Vec6::Zero());
    Vec6 initial_twist = Vec6::Zero();
    initial_twist(0) = 0.3;
    const State initial = make_state(Vec3::Zero(), Quat::Identity(), initial_twist);

    Sim2 reference(built_in, 1e-3, initial);
    reference.setpoints() = beam_setpoints(built_in, rest);
    Sim2 feedback(plain, 1e-3, initial);
    feedback.setpoints() = beam_setpoints(plain, rest);
    Sim2 step_start(plain, 1e-3, initial);
    step_start.setpoints() = beam_setpoints(plain, rest);
    for (Index k = 0; k < 200; ++k) {
        reference.step();
        feedback.step([&](double, const State& state, coopdyn::Setpoints<double, 2>&, coopdyn::Disturbances<double, 2>& d) {
            d.object.head<3>() = -c * state.twist.head<3>();
        });
        step_start.step([&](double, coopdyn::Setpoints<double, 2>&, coopdyn::Disturbances<double, 2>& d) {
            d.object.head<3>() = -c * step_start.state().twist.head<3>();
        });
    }
    const double feedback_error = state_distance(feedback.state(), reference.state());
    const double step_start_error = state_distance(step_start.state(), reference.state());
    std::printf("[ feedback ] stage state: %.2e, step start state: %.2e\n", feedback_error, step_start_error);
    EXPECT_GT(reference.state().pose.position(0), 1e-3);  // the beam did move
    EXPECT_LT(feedback_error, 1e-13);
    EXPECT_GT(step_start_error, 1e-6);
}

TEST(SimulatorFeedback, SmoothStateFeedbackKeepsFourthOrder)
{
    // A nonlinear feedback wrench on the tumbling three-arm system: the error against a fine
    // reference falls 16x per halving of dt.
    const ConservativeSystem system = ConservativeSystem::build(11);
    const auto feedback = [](double time, const State& state, Setpoints3&, Disturbances3& d) {
        d.object.head<3>() = -3.0 * state.twist.head<3>() * (1.0 + state.twist.head<3>().squaredNorm());
        d.object.tail<3>() = -0.5 * state.twist.tail<3>() + Vec3(std::sin(5.0 * time), 0.0, 0.2);
    };
    const double duration = 0.4;
    const auto simulate = [&](double dt) {
        Sim3 sim(system.model, dt, system.initial);
        sim.setpoints() = system.setpoints;
        const Index steps = static_cast<Index>(std::lround(duration / dt));
        for (Index k = 0; k < steps; ++k) {
            sim.step(feedback);
        }
        return sim.state();
    };
    const State reference = simulate(duration / 3200);
    double previous = 0.0;
    for (const double dt : {duration / 25, duration / 50, duration / 100}) {
        const double error = state_distance(simulate(dt), reference);
        if (previous > 0.0) {
            std::printf("[ feedback ] dt %.4f: error %.3e, ratio %.1f\n", dt, error, previous / error);
            EXPECT_GT(previous / error, 12.0);
            EXPECT_LT(previous / error, 20.0);
        }
        previous = error;
    }
}

TEST(SimulatorFeedback, ZeroOrderHoldSamplesOncePerStepAtItsStart)
{
    const ConservativeSystem system = ConservativeSystem::build(5);
    const double dt = 1e-3;
    for (const Integrator integrator : {Integrator::runge_kutta_4, Integrator::semi_implicit_euler}) {
        Sim3 sim(system.model, dt, system.initial, integrator, coopdyn::InputHold::zero_order);
        std::vector<double> times;
        std::vector<State> states;
        for (Index k = 0; k < 5; ++k) {
            states.push_back(sim.state());
            sim.step([&](double time, const State& state, Setpoints3&, Disturbances3& d) {
                times.push_back(time);
                EXPECT_EQ(state.pose.position, states.back().pose.position);
                d.object(0) = time;
            });
        }
        ASSERT_EQ(times.size(), 5u);
        for (std::size_t k = 0; k < times.size(); ++k) {
            EXPECT_EQ(times[k], static_cast<double>(k) * dt);
        }
    }
}

TEST(SimulatorTime, IsTheStepCountTimesTheStepInFloat)
{
    // t += dt in float read 99.957 after 100 s; the step count gives 100 to float rounding.
    using ModelF = coopdyn::Model<float, 2>;
    const BeamParameters beam = section_five_beam(1e-4);
    const Model2 model_double = make_model<Model2>(beam.object, beam.arms, Vec3::Zero());
    std::vector<coopdyn::Arm<coopdyn::ImpedanceEndEffector<float>>> arms(2);
    for (Index i = 0; i < 2; ++i) {
        const auto& e = model_double.end_effector(i);
        auto& arm = arms[static_cast<std::size_t>(i)];
        arm.end_effector.mass = float(e.mass);
        arm.end_effector.rotational_inertia = e.rotational_inertia.cast<float>();
        arm.end_effector.translational_damping = float(e.translational_damping);
        arm.end_effector.rotational_damping = float(e.rotational_damping);
        arm.end_effector.translational_stiffness = float(e.translational_stiffness);
        arm.end_effector.rotational_stiffness = float(e.rotational_stiffness);
        arm.grasp_body.position = model_double.grasp_offsets_body().col(i).cast<float>();
    }
    coopdyn::RigidObject<float> object{1.75f, beam.object.inertia_body.cast<float>()};
    const ModelF model(object, arms, Eigen::Vector3f::Zero());
    coopdyn::RigidBodyState<float> rest;
    coopdyn::Simulator<ModelF> sim(model, 1e-3f, rest, Integrator::semi_implicit_euler);
    coopdyn::Data<ModelF> data(model);
    coopdyn::grasp_kinematics(model, data, rest);
    for (Index i = 0; i < 2; ++i) {
        sim.setpoints().set_pose(i, data.end_effector_pose(i));
    }
    for (Index k = 0; k < 100000; ++k) {
        sim.step();
    }
    EXPECT_EQ(sim.steps(), 100000);
    EXPECT_NEAR(sim.time(), 100.0f, 1e-5f);
    sim.reset(rest, 5.0f);
    EXPECT_EQ(sim.steps(), 0);
    EXPECT_EQ(sim.time(), 5.0f);
}

TEST(SimulatorStatus, ADivergingSimulationStopsAtTheLastFiniteStateAndSaysWhen)
{
    // k = 1e8 N/m at dt = 1 ms is far outside RK4's stability region (omega dt ~ 3): the state
    // grows without bound and would overflow to Inf and NaN.
    BeamParameters beam = section_five_beam(1e-4);
    for (ArmParameters& arm : beam.arms) {
        arm.stiffness = 1e8;
    }
    const Model2 model = make_model<Model2>(beam.object, beam.arms, Vec3::Zero());
    const State rest = make_state(Vec3::Zero(), Quat::Identity(), Vec6::Zero());
    const State displaced = make_state(Vec3(1e-3, 0.0, 0.0), Quat::Identity(), Vec6::Zero());
    Sim2 sim(model, 1e-3, displaced);
    sim.setpoints() = beam_setpoints(model, rest);
    Index observed = 0;
    const auto& status = sim.run(
        2000, [](double, coopdyn::Setpoints<double, 2>&, coopdyn::Disturbances<double, 2>&) {},
        [&](double, const State& state, const coopdyn::Data<Model2>&) {
            EXPECT_TRUE(state.twist.allFinite());
            ++observed;
        });
    std::printf("[ status ] diverged at step %lld, t = %.3f s\n", static_cast<long long>(status.failed_step),
                status.failed_time);
    ASSERT_FALSE(status.ok);
    EXPECT_GT(status.failed_step, 10);
    EXPECT_LT(status.failed_step, 2000);
    EXPECT_EQ(sim.steps(), status.failed_step);
    EXPECT_EQ(observed, status.failed_step);
    EXPECT_DOUBLE_EQ(status.failed_time, static_cast<double>(status.failed_step) * 1e-3);
    EXPECT_TRUE(sim.state().pose.position.allFinite() && sim.state().twist.allFinite());
    const State stuck = sim.state();
    EXPECT_FALSE(sim.step().ok);  // later steps do nothing
    EXPECT_EQ(sim.state().pose.position, stuck.pose.position);
    sim.reset(displaced);
    EXPECT_TRUE(sim.status().ok);
}

TEST(SimulatorStatus, NanInputFailsTheFirstStepAndKeepsTheState)
{
    const ConservativeSystem system = ConservativeSystem::build(3);
    Sim3 sim(system.model, 1e-3, system.initial);
    sim.setpoints() = system.setpoints;
    const auto& status = sim.step([](double, Setpoints3&, Disturbances3& d) { d.object(2) = std::nan(""); });
    EXPECT_FALSE(status.ok);
    EXPECT_EQ(status.failed_step, 0);
    EXPECT_EQ(status.failed_time, 0.0);
    EXPECT_EQ(status.input.problem, coopdyn::InputProblem::object_disturbance);
    EXPECT_EQ(sim.state().pose.position, system.initial.pose.position);
    EXPECT_EQ(sim.state().twist, system.initial.twist);
}

TEST(SimulatorStatus, ANonUnitSetpointQuaternionFailsItsStepInEveryBuild)
{
    // The inputs are checked before the dynamics see them, so a debug build reports the status
    // instead of stopping on the dynamics' input assertion.
    const ConservativeSystem system = ConservativeSystem::build(3);
    Sim3 sim(system.model, 1e-3, system.initial);
    sim.setpoints() = system.setpoints;
    const auto inputs = [&](double, Setpoints3& setpoints, Disturbances3&) {
        if (sim.steps() >= 5) {
            setpoints.orientations.col(1) *= 3.0;
        }
    };
    EXPECT_TRUE(sim.run(5, inputs, [](double, const State&, const auto&) {}).ok);
    const auto& status = sim.step(inputs);
    EXPECT_FALSE(status.ok);
    EXPECT_EQ(status.failed_step, 5);
    EXPECT_EQ(status.input.problem, coopdyn::InputProblem::setpoint_orientation);
    EXPECT_EQ(status.input.arm, 1);
    sim.reset(system.initial);
    EXPECT_TRUE(sim.status().ok);
    EXPECT_TRUE(sim.status().input.ok());
}

TEST(SimulatorLifetime, ATemporaryModelDoesNotCompile)
{
    // The simulator keeps a reference to its model: the rvalue overload is deleted.
    static_assert(std::is_constructible_v<Sim2, const Model2&, double, const State&>);
    static_assert(!std::is_constructible_v<Sim2, Model2&&, double, const State&>);
    static_assert(!std::is_constructible_v<Sim2, Model2, double, const State&>);
    SUCCEED();
}

TEST(SimulatorGainScheduling, ASimulatorUsesStiffnessSetOnItsModelBetweenSteps)
{
    // Pushed with 10 N along x, the beam settles at 10 / (k_1 + k_2) = 10/600 m; after both
    // stiffnesses are raised to 900 N/m on the model the simulator holds (Model::set_end_effector,
    // no rebuild), it settles at 10/1800 m (the restoring force is exactly linear in translation).
    Beam beam = section9_beam();
    Vec6 load = Vec6::Zero();
    load(0) = 10.0;
    Sim2 sim(beam.model, 1e-3, beam.equilibrium, Integrator::runge_kutta_4);
    sim.setpoints() = beam.setpoints;
    sim.disturbances().object = load;
    for (Index k = 0; k < 6500; ++k) {
        sim.step();
    }
    EXPECT_NEAR((sim.state().pose.position - beam.equilibrium.pose.position).x(), 10.0 / 600.0, 1e-6);
    for (Index i = 0; i < 2; ++i) {
        beam.model.set_end_effector(i, beam.model.end_effector(i).with_translational_stiffness(900.0));
    }
    for (Index k = 0; k < 6500; ++k) {  // slowest pole with k = 900: about -2.7 1/s
        sim.step();
    }
    const double displacement = (sim.state().pose.position - beam.equilibrium.pose.position).x();
    std::printf("[ gains ] after k -> 900 N/m: displacement %.9f m (10/1800 = %.9f)\n", displacement, 10.0 / 1800.0);
    EXPECT_NEAR(displacement, 10.0 / 1800.0, 1e-7);
}
