// Tests of the contact-wrench bias (include/coopdyn/control/contact_wrenches.hpp), Lin et al.
// L(23)-(24) with errata E11. The reference is a physical model the formulas were not derived
// from: the arms, a massless object held by a rigid grasp and an external wrench F_x on it, with
// the contact wrenches as explicit unknowns,
//
//     M qdd + h = tau + J^T f            (f: the wrenches the object applies to the hands)
//     G (-f) + F_x = 0                   (the massless object is in balance)
//     J qdd + Jdot qdot = G^T a_o + b    (each contact moves with the object; b_i = [w x (w x r_i); 0])
//
// one square linear system in (qdd, f, a_o), solved densely (tests/common/arm_systems.hpp,
// solve_physical_model). The hands apply w = -f to the object.

#include "coopdyn/control/contact_wrenches.hpp"

#include "arm_systems.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

namespace {

using coopdyn_test::JointSpaceSystem;
using coopdyn_test::PhysicalSolution;
using coopdyn_test::solve_physical_model;
using coopdyn_test::MatrixXd;
using coopdyn_test::random_joint_space_system;
using coopdyn_test::random_vector;
using coopdyn_test::Rng;
using coopdyn_test::Vector3d;
using coopdyn_test::Vector6d;
using coopdyn_test::VectorXd;
using Index = Eigen::Index;
using Dynamics = coopdyn::ProjectedDynamics<double, coopdyn::Dynamic, coopdyn::Dynamic>;

struct Bias {
    VectorXd qdd, w0;
};

Bias library_bias(Dynamics& d, const JointSpaceSystem& s, const VectorXd& tau_u, const Vector6d& external)
{
    Bias bias{VectorXd(s.joints), VectorXd(6 * s.arms)};
    VectorXd scratch(s.joints);
    coopdyn::contact_wrench_bias(d, s.M, s.h, tau_u, external, bias.qdd, bias.w0, scratch);
    return bias;
}

using Case = coopdyn_test::ArmCase;
constexpr const auto& cases = coopdyn_test::arm_cases;

TEST(ContactWrenches, BiasPlusSqueezeEqualsThePhysicalContactWrenches)
{
    Rng rng(21);
    double worst_w = 0, worst_qdd = 0, worst_object = 0, worst_squeeze_motion = 0;
    for (const Case& c : cases) {
        for (int trial = 0; trial < 3; ++trial) {
            const JointSpaceSystem s = random_joint_space_system(c.arms, c.torso, rng);
            Dynamics d(c.arms, s.joints);
            ASSERT_EQ(d.compute(s.M, s.h, s.J, VectorXd(s.Jdot * s.qdot), s.qdot, s.r), coopdyn::ProjectionStatus::ok);
            const Vector6d F = 20.0 * Vector6d(random_vector(6, rng));
            const Vector6d F_x = 20.0 * Vector6d(random_vector(6, rng));
            const VectorXd tau_u = d.projector * d.object_jacobian.transpose() * F;
            const VectorXd z = 30.0 * random_vector(6 * (c.arms - 1), rng);
            const VectorXd tau_c = s.J.transpose() * d.internal_basis * z;
            const Bias bias = library_bias(d, s, tau_u, F_x);

            const PhysicalSolution with_squeeze = solve_physical_model(s, tau_u + tau_c, F_x);
            const PhysicalSolution without = solve_physical_model(s, tau_u, F_x);
            EXPECT_LT(std::max(with_squeeze.residual, without.residual), 1e-12);
            const VectorXd predicted = bias.w0 + d.internal_basis * z;
            worst_w = std::max(worst_w, (predicted - with_squeeze.applied).norm() / with_squeeze.applied.norm());
            worst_qdd = std::max(worst_qdd, (bias.qdd - without.qdd).norm() / without.qdd.norm());
            // The squeeze changes no acceleration (P J^T B = 0).
            worst_squeeze_motion =
                std::max(worst_squeeze_motion, (with_squeeze.qdd - without.qdd).norm() / without.qdd.norm());
            // The object obeys L(15) with the physical acceleration.
            const Vector6d lhs = d.task_inertia * with_squeeze.object_acceleration + d.task_bias;
            worst_object = std::max(worst_object, (lhs - (F + F_x)).norm() / (F + F_x).norm());
        }
    }
    std::printf("[ contact wrenches vs physical model ] K = 2..4: w_0 + B z %.1e, qdd %.1e, squeeze moves qdd by "
                "%.1e, L(15) residual %.1e\n",
                worst_w, worst_qdd, worst_squeeze_motion, worst_object);
    EXPECT_LT(worst_w, 1e-9);
    EXPECT_LT(worst_qdd, 1e-9);
    EXPECT_LT(worst_squeeze_motion, 1e-9);
    EXPECT_LT(worst_object, 1e-9);
}

TEST(ContactWrenches, PrintedEtaWithoutTheExternalWrenchTermIsWrong)
{
    // Errata E11: the printed qdd = Mc^-1 (tau_u - P h + Pdot qdot) in eta leaves out P Jx^T F_x.
    Rng rng(22);
    double worst_corrected = 0, smallest_printed = 1e9;
    for (const Case& c : cases) {
        const JointSpaceSystem s = random_joint_space_system(c.arms, c.torso, rng);
        Dynamics d(c.arms, s.joints);
        d.compute(s.M, s.h, s.J, VectorXd(s.Jdot * s.qdot), s.qdot, s.r);
        const Vector6d F = 20.0 * Vector6d(random_vector(6, rng));
        const Vector6d F_x = 20.0 * Vector6d(random_vector(6, rng));
        const VectorXd tau_u = d.projector * d.object_jacobian.transpose() * F;
        const PhysicalSolution truth = solve_physical_model(s, tau_u, F_x);
        EXPECT_LT(truth.residual, 1e-12);
        const Bias bias = library_bias(d, s, tau_u, F_x);
        worst_corrected = std::max(worst_corrected, (bias.w0 - truth.applied).norm() / truth.applied.norm());

        // The printed eta, written out with dense pseudo-inverses.
        const MatrixXd I = MatrixXd::Identity(s.joints, s.joints);
        const VectorXd qdd_printed =
            d.constrained_inertia.inverse() * (tau_u - d.projector * s.h + d.projector_rate_qdot);
        const VectorXd eta_printed = coopdyn_test::pseudo_inverse(MatrixXd(d.constraint_jacobian.transpose())) *
                                     (I - d.projector) * (s.M * qdd_printed + s.h - d.object_jacobian.transpose() * F_x);
        const MatrixXd G = coopdyn_test::literal_grasp_matrix(s.r);
        const VectorXd w0_printed = -G.transpose() * (G * G.transpose()).inverse() * F_x - eta_printed;
        smallest_printed = std::min(smallest_printed, (w0_printed - truth.applied).norm() / truth.applied.norm());
    }
    std::printf("[ E11 ] relative error of w_0: corrected eta %.1e, printed eta at least %.2f\n", worst_corrected,
                smallest_printed);
    EXPECT_LT(worst_corrected, 1e-9);
    EXPECT_GT(smallest_printed, 0.05);
}

}  // namespace
