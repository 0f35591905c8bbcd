// Tests of the projected dynamics (include/coopdyn/control/projected_dynamics.hpp), Lin et al.
// L(4), (13), (15), (26) with errata E10. References the code was not derived from:
//  - the printed formulas evaluated densely with SVD pseudo-inverses (arm_systems.hpp);
//  - central finite differences of Jx, Jc and P along an explicit motion (the object rotating with
//    the angular velocity that qdot gives it, J(t) = J + t Jdot);
//  - the joint-space KKT system M qdd + h = tau + Jc^T lambda + Jx^T F_x, Jc qdd = -Jcdot qdot,
//    solved directly: the object must obey L(15), Lambda_c xdd_o + hc = F + F_x, under
//    tau = P Jx^T F;
//  - identities: P symmetric idempotent, P Jc^T = 0, G B = 0, B^T B = I, rank Jc = 6K - 6.
// Seeded random systems of K = 2, 3, 4 arms with 7 joints each, with and without a shared torso.

// First: it defines EIGEN_RUNTIME_NO_MALLOC and eigen_assert before Eigen is included.
#include "../allocation_counter.hpp"

#include "coopdyn/control/projected_dynamics.hpp"

#include "arm_systems.hpp"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

namespace {

using coopdyn_test::JointSpaceSystem;
using coopdyn_test::literal_grasp;
using coopdyn_test::LiteralGrasp;
using coopdyn_test::MatrixXd;
using coopdyn_test::pseudo_inverse;
using coopdyn_test::random_joint_space_system;
using coopdyn_test::random_vector;
using coopdyn_test::Rng;
using coopdyn_test::Vector3d;
using coopdyn_test::Vector6d;
using coopdyn_test::VectorXd;
using Index = Eigen::Index;

using Dynamics = coopdyn::ProjectedDynamics<double, coopdyn::Dynamic, coopdyn::Dynamic>;

double relative(const MatrixXd& value, const MatrixXd& reference)
{
    return (value - reference).norm() / std::max(reference.norm(), 1e-300);
}

/// The printed L(4), (15), (26) with SVD pseudo-inverses.
struct LiteralProjection {
    MatrixXd P, Mc, Lambda;
};

LiteralProjection literal_projection(const JointSpaceSystem& s, const LiteralGrasp& grasp)
{
    LiteralProjection result;
    const MatrixXd identity = MatrixXd::Identity(s.joints, s.joints);
    result.P = identity - pseudo_inverse(grasp.Jc) * grasp.Jc;
    result.Mc = result.P * s.M + identity - result.P;
    result.Lambda = (grasp.Jx * result.Mc.inverse() * result.P * grasp.Jx.transpose()).inverse();
    return result;
}

using Case = coopdyn_test::ArmCase;
constexpr const auto& cases = coopdyn_test::arm_cases;

TEST(ProjectedDynamics, KernelsMatchThePrintedFormulasWithPseudoInverses)
{
    Rng rng(1);
    double worst_jx = 0, worst_jc = 0, worst_p = 0, worst_mc = 0, worst_lambda = 0;
    for (const Case& c : cases) {
        for (int trial = 0; trial < 4; ++trial) {
            const JointSpaceSystem s = random_joint_space_system(c.arms, c.torso, rng);
            const LiteralGrasp grasp = literal_grasp(s.r, s.J);
            const LiteralProjection literal = literal_projection(s, grasp);
            worst_jx = std::max(worst_jx, relative(coopdyn::object_jacobian(s.r, s.J), grasp.Jx));
            worst_jc = std::max(worst_jc, relative(coopdyn::constraint_jacobian(s.r, s.J), grasp.Jc));
            Dynamics d = coopdyn::projected_dynamics(s.M, s.h, s.J, VectorXd(s.Jdot * s.qdot), s.qdot, s.r);
            ASSERT_EQ(d.status, coopdyn::ProjectionStatus::ok);
            worst_p = std::max(worst_p, relative(d.projector, literal.P));
            worst_mc = std::max(worst_mc, relative(d.constrained_inertia, literal.Mc));
            worst_lambda = std::max(worst_lambda, relative(d.task_inertia, literal.Lambda));
            EXPECT_LT(relative(d.object_jacobian, grasp.Jx), 1e-12);
            EXPECT_LT(relative(d.constraint_jacobian, grasp.Jc), 1e-12);
        }
    }
    std::printf("[ projected dynamics vs printed formulas + SVD ] K = 2..4, torso or not: Jx %.1e, Jc %.1e, P %.1e, "
                "Mc %.1e, Lambda_c %.1e\n",
                worst_jx, worst_jc, worst_p, worst_mc, worst_lambda);
    EXPECT_LT(worst_jx, 1e-12);
    EXPECT_LT(worst_jc, 1e-12);
    EXPECT_LT(worst_p, 1e-10);
    EXPECT_LT(worst_mc, 1e-10);
    EXPECT_LT(worst_lambda, 1e-9);
}

TEST(ProjectedDynamics, IdentitiesOfTheProjectionAndTheBasis)
{
    Rng rng(2);
    for (const Case& c : cases) {
        const JointSpaceSystem s = random_joint_space_system(c.arms, c.torso, rng);
        Dynamics d = coopdyn::projected_dynamics(s.M, s.h, s.J, VectorXd(s.Jdot * s.qdot), s.qdot, s.r);
        const MatrixXd& P = d.projector;
        const MatrixXd G = coopdyn_test::literal_grasp_matrix(s.r);
        const MatrixXd B = coopdyn::internal_wrench_basis(s.r);
        const Index internal = 6 * (c.arms - 1);
        EXPECT_LT((P - P.transpose()).norm(), 1e-13);
        EXPECT_LT((P * P - P).norm(), 1e-12);
        EXPECT_LT((P * d.constraint_jacobian.transpose()).norm() / d.constraint_jacobian.norm(), 1e-13);
        EXPECT_LT((G * B).norm(), 1e-14);
        EXPECT_LT((B.transpose() * B - MatrixXd::Identity(internal, internal)).norm(), 1e-14);
        EXPECT_LT((d.internal_basis - B).norm(), 1e-14) << "the workspace builds the same basis";
        EXPECT_EQ(coopdyn_test::numerical_rank(d.constraint_jacobian), internal) << "errata E10";
        // Jc = B B^T J: the rows of Jc lie in null(G).
        EXPECT_LT((d.constraint_jacobian - B * B.transpose() * s.J).norm() / s.J.norm(), 1e-13);
        // qdot on the manifold moves the object as Jx qdot.
        EXPECT_LT((d.constraint_jacobian * s.qdot).norm(), 1e-12 * s.qdot.norm());
        // The pseudo-inverse products against SVD.
        const VectorXd x = random_vector(6 * c.arms, rng);
        const VectorXd y = random_vector(s.joints, rng);
        VectorXd out_q(s.joints), out_w(6 * c.arms);
        d.constraint_pseudo_inverse_times(x, out_q);
        d.constraint_transpose_pseudo_inverse_times(y, out_w);
        const MatrixXd Jc_pinv = pseudo_inverse(d.constraint_jacobian);
        EXPECT_LT(relative(out_q, Jc_pinv * x), 1e-10);
        EXPECT_LT(relative(out_w, Jc_pinv.transpose() * y), 1e-10);
        EXPECT_LT((G * out_w).norm() / out_w.norm(), 1e-13) << "(Jc^T)^+ y lies in null(G)";
    }
}

TEST(ProjectedDynamics, GraspPseudoInverseProductIsTheMoorePenroseInverse)
{
    // out -= G^+ F per tick (the unit-weight inverse of model/grasp_inverse.hpp) against an SVD
    // pseudo-inverse of the literal G (24), and against the matrix grasp_pseudo_inverse forms.
    Rng rng(9);
    double worst_svd = 0.0, worst_matrix = 0.0;
    for (const Case& c : cases) {
        const JointSpaceSystem s = random_joint_space_system(c.arms, c.torso, rng);
        Dynamics d = coopdyn::projected_dynamics(s.M, s.h, s.J, VectorXd(s.Jdot * s.qdot), s.qdot, s.r);
        const MatrixXd G = coopdyn_test::literal_grasp_matrix(s.r);
        const Vector6d wrench = coopdyn_test::random_vector6(rng, 10.0);
        const VectorXd start = random_vector(6 * c.arms, rng);
        VectorXd out = start;
        d.subtract_grasp_pseudo_inverse_times(wrench, out);
        const VectorXd applied = start - out;
        worst_svd = std::max(worst_svd, relative(applied, pseudo_inverse(G) * wrench));
        worst_matrix = std::max(worst_matrix, relative(applied, coopdyn::grasp_pseudo_inverse(s.r) * wrench));
    }
    std::printf("G^+ F per tick: against SVD %.2e, against grasp_pseudo_inverse %.2e\n", worst_svd, worst_matrix);
    EXPECT_LT(worst_svd, 5e-15);
    EXPECT_LT(worst_matrix, 1e-15);
}

/// Jx, Jc, P along the motion r(t) = R(omega t) r, J(t) = J + t Jdot.
struct AlongMotion {
    MatrixXd Jx, Jc, P;
};

AlongMotion at_time(const JointSpaceSystem& s, const Vector3d& omega, double t)
{
    const MatrixXd r = coopdyn_test::rotation_exponential(omega * t).toRotationMatrix() * s.r;
    const MatrixXd J = s.J + t * s.Jdot;
    const LiteralGrasp grasp = literal_grasp(r, J);
    AlongMotion result{grasp.Jx, grasp.Jc, MatrixXd()};
    result.P = MatrixXd::Identity(s.joints, s.joints) - pseudo_inverse(grasp.Jc) * grasp.Jc;
    return result;
}

TEST(ProjectedDynamics, RateTermsMatchCentralDifferencesAlongAnExplicitMotion)
{
    Rng rng(3);
    double worst_jx = 0, worst_jc = 0, worst_p = 0;
    for (const Case& c : cases) {
        const JointSpaceSystem s = random_joint_space_system(c.arms, c.torso, rng);
        Dynamics d = coopdyn::projected_dynamics(s.M, s.h, s.J, VectorXd(s.Jdot * s.qdot), s.qdot, s.r);
        const Vector3d omega = d.object_twist.tail<3>();
        ASSERT_GT(omega.norm(), 0.1) << "the object must rotate for the test to have teeth";
        const double step = 1e-5;
        const AlongMotion ahead = at_time(s, omega, step);
        const AlongMotion behind = at_time(s, omega, -step);
        const VectorXd jx_rate = (ahead.Jx - behind.Jx) / (2 * step) * s.qdot;
        const VectorXd jc_rate = (ahead.Jc - behind.Jc) / (2 * step) * s.qdot;
        const VectorXd p_rate = (ahead.P - behind.P) / (2 * step) * s.qdot;
        worst_jx = std::max(worst_jx, relative(d.object_jacobian_rate_qdot, jx_rate));
        worst_jc = std::max(worst_jc, relative(d.constraint_jacobian_rate_qdot, jc_rate));
        worst_p = std::max(worst_p, relative(d.projector_rate_qdot, p_rate));
    }
    std::printf("[ rates vs central differences, step 1e-5 ] Jxdot qdot %.1e, Jcdot qdot %.1e, Pdot qdot %.1e\n",
                worst_jx, worst_jc, worst_p);
    // Central differences: truncation ~ step^2 times the third derivative, rounding ~ eps / step.
    EXPECT_LT(worst_jx, 1e-8);
    EXPECT_LT(worst_jc, 1e-8);
    EXPECT_LT(worst_p, 1e-7);
}

TEST(ProjectedDynamics, ObjectObeysEquation15InTheJointSpaceKktSolution)
{
    // tau = P Jx^T F; M qdd + h = tau + Jc^T lambda + Jx^T F_x, Jc qdd = -Jcdot qdot, solved as one
    // (rank-deficient but consistent) linear system; the object's acceleration Jx qdd + Jxdot qdot
    // must satisfy Lambda_c xdd_o + hc = F + F_x (L(15)).
    Rng rng(4);
    double worst = 0;
    for (const Case& c : cases) {
        for (int trial = 0; trial < 3; ++trial) {
            const JointSpaceSystem s = random_joint_space_system(c.arms, c.torso, rng);
            Dynamics d = coopdyn::projected_dynamics(s.M, s.h, s.J, VectorXd(s.Jdot * s.qdot), s.qdot, s.r);
            const Vector6d F = 20.0 * Vector6d(random_vector(6, rng));
            const Vector6d F_x = 20.0 * Vector6d(random_vector(6, rng));
            const VectorXd tau = d.projector * d.object_jacobian.transpose() * F;
            const Index q = s.joints;
            const Index m = 6 * c.arms;
            MatrixXd kkt = MatrixXd::Zero(q + m, q + m);
            kkt.topLeftCorner(q, q) = s.M;
            kkt.topRightCorner(q, m) = -d.constraint_jacobian.transpose();
            kkt.bottomLeftCorner(m, q) = d.constraint_jacobian;
            VectorXd rhs(q + m);
            rhs.head(q) = tau + d.object_jacobian.transpose() * F_x - s.h;
            rhs.tail(m) = -d.constraint_jacobian_rate_qdot;
            const VectorXd solution = kkt.completeOrthogonalDecomposition().solve(rhs);
            ASSERT_LT((kkt * solution - rhs).norm(), 1e-9 * rhs.norm()) << "consistent system";
            const VectorXd qdd = solution.head(q);
            const Vector6d xdd = d.object_jacobian * qdd + d.object_jacobian_rate_qdot;
            const Vector6d lhs = d.task_inertia * xdd + d.task_bias;
            const double error = (lhs - (F + F_x)).norm() / (F + F_x).norm();
            worst = std::max(worst, error);
            EXPECT_LT(error, 1e-9) << "K = " << c.arms << (c.torso ? " with torso" : "");
        }
    }
    std::printf("[ L(15) in the joint-space KKT solution ] K = 2..4: worst relative residual %.1e\n", worst);
}

TEST(ProjectedDynamics, SingularArmsAreAStatusNotANan)
{
    Rng rng(5);
    // Arm 2 loses a direction (two equal rows of its Jacobian): the grasp can still be kept, but
    // the object can no longer be moved in every direction, so Lambda_c does not exist.
    JointSpaceSystem s = random_joint_space_system(2, false, rng);
    s.J.row(7) = s.J.row(6);
    Dynamics d(2, s.joints);
    EXPECT_EQ(d.compute(s.M, s.h, s.J, VectorXd(s.Jdot * s.qdot), s.qdot, s.r), coopdyn::ProjectionStatus::singular_task);
    EXPECT_TRUE(d.projector.allFinite());
    EXPECT_TRUE(d.task_inertia.allFinite());

    // Neither arm can push along x, and the contacts lie on a line along x: the squeeze along
    // that line, a wrench in null(G), is out of reach of both arms, so Jr Jr^T is singular.
    s = random_joint_space_system(2, false, rng);
    s.J.row(0).setZero();
    s.J.row(6).setZero();
    s.r.col(1) = s.r.col(0) + Vector3d(0.6, 0.0, 0.0);
    EXPECT_EQ(d.compute(s.M, s.h, s.J, VectorXd(s.Jdot * s.qdot), s.qdot, s.r),
              coopdyn::ProjectionStatus::singular_constraint);
    EXPECT_TRUE(d.projector.allFinite());
}

// The controller's path: the basis of the body-frame offsets p, built once, rotated into {w}
// (B = blkdiag(R, ..., R) B(p), r = R p) instead of a Householder QR of r's closed-form basis each
// tick. It is another basis of the same null(G), so every projection must agree with compute()'s;
// and without P and Mc formed, nothing else changes (P x by project() agrees with P).
TEST(ProjectedDynamics, ABasisRotatedFromTheBodyFrameGivesTheSameProjection)
{
    Rng rng(7);
    double worst = 0.0;
    for (const Case& c : cases) {
        const JointSpaceSystem s = random_joint_space_system(c.arms, c.torso, rng);
        const Eigen::Matrix3d rotation =
            Eigen::Quaterniond(Eigen::Vector4d(random_vector(4, rng))).normalized().toRotationMatrix();
        const MatrixXd body_offsets = rotation.transpose() * s.r;
        const MatrixXd body_basis = coopdyn::internal_wrench_basis(body_offsets);
        MatrixXd basis(body_basis.rows(), body_basis.cols());
        for (Index block = 0; block < 2 * c.arms; ++block) {
            basis.middleRows<3>(3 * block) = rotation * body_basis.middleRows<3>(3 * block);
        }
        const VectorXd jdot_qdot = s.Jdot * s.qdot;
        Dynamics reference(c.arms, s.joints), rotated(c.arms, s.joints);
        reference.compute(s.M, s.h, s.J, jdot_qdot, s.qdot, s.r);
        rotated.form_projection_matrices = false;
        const auto counts = allocation_counter::count_allocations(
            [&] { rotated.compute_with_basis(s.M, s.h, s.J, jdot_qdot, s.qdot, s.r, basis); });
        EXPECT_EQ(counts.operator_new + counts.eigen, 0);
        EXPECT_GT((rotated.internal_basis - reference.internal_basis).norm(), 1e-3) << "a different basis";
        const MatrixXd null_projector = basis * basis.transpose();
        worst = std::max({worst, relative(null_projector, reference.internal_basis * reference.internal_basis.transpose()),
                          relative(rotated.object_jacobian, reference.object_jacobian),
                          relative(rotated.task_inertia, reference.task_inertia),
                          relative(rotated.task_bias, reference.task_bias),
                          relative(rotated.projector_rate_qdot, reference.projector_rate_qdot)});
        EXPECT_EQ(rotated.constrained_inertia, MatrixXd::Identity(s.joints, s.joints)) << "Mc not formed";
        EXPECT_EQ(rotated.projector, MatrixXd::Identity(s.joints, s.joints)) << "P not formed";
        worst = std::max(worst, relative(rotated.reduced_jacobian_transpose, s.J.transpose() * basis));
        const VectorXd x = random_vector(s.joints, rng);
        VectorXd projected(s.joints);
        rotated.project(x, projected);
        worst = std::max(worst, relative(projected, reference.projector * x));
    }
    std::printf("rotated body-frame basis against compute(): worst relative difference %.1e\n", worst);
    EXPECT_LT(worst, 1e-13);
}

// E12's posture projection N^T tau = tau - J^T (J M^-1 J^T)^-1 J M^-1 tau from the projection's own
// factors (no J M^-1 J^T) against the printed formula with dense inverses, for every arm case
// (shared torso, K = 2..4) and torques of several scales.
TEST(ProjectedDynamics, SelfMotionProjectionIsTheDynamicallyConsistentNullSpaceProjector)
{
    Rng rng(8);
    double worst = 0.0, worst_motion = 0.0;
    for (const Case& c : cases) {
        const JointSpaceSystem s = random_joint_space_system(c.arms, c.torso, rng);
        Dynamics d = coopdyn::projected_dynamics(s.M, s.h, s.J, VectorXd(s.Jdot * s.qdot), s.qdot, s.r);
        ASSERT_EQ(d.status, coopdyn::ProjectionStatus::ok);
        const MatrixXd M_inverse = s.M.inverse();
        const MatrixXd literal = MatrixXd::Identity(s.joints, s.joints) -
                                 s.J.transpose() * (s.J * M_inverse * s.J.transpose()).inverse() * s.J * M_inverse;
        for (const double scale : {1.0, 100.0}) {
            const VectorXd tau = scale * random_vector(s.joints, rng);
            VectorXd projected(s.joints);
            d.self_motion_projection(tau, projected);
            worst = std::max(worst, relative(projected, literal * tau));
            // It moves no contact point: J M^-1 N^T tau = 0.
            worst_motion = std::max(worst_motion, (s.J * M_inverse * projected).norm() / (M_inverse * tau).norm());
        }
    }
    std::printf("N^T tau against the printed projector: %.1e; J M^-1 N^T tau %.1e\n", worst, worst_motion);
    EXPECT_LT(worst, 1e-11);
    EXPECT_LT(worst_motion, 1e-14);
}

TEST(ProjectedDynamics, FixedSizesAgreeWithDynamicAndAllocateNothing)
{
    Rng rng(6);
    const JointSpaceSystem s = random_joint_space_system(2, false, rng);
    const Eigen::Matrix<double, 14, 14> M = s.M;
    const Eigen::Matrix<double, 14, 1> h = s.h;
    const Eigen::Matrix<double, 12, 14> J = s.J;
    const Eigen::Matrix<double, 12, 1> Jdot_qdot = s.Jdot * s.qdot;
    const Eigen::Matrix<double, 14, 1> qdot = s.qdot;
    const Eigen::Matrix<double, 3, 2> r = s.r;
    coopdyn::ProjectedDynamics<double, 2, 14> fixed;
    Dynamics dynamic(2, 14);
    const auto fixed_counts = allocation_counter::count_allocations([&] { fixed.compute(M, h, J, Jdot_qdot, qdot, r); });
    EXPECT_EQ(fixed_counts.operator_new + fixed_counts.eigen, 0);
    const VectorXd jdot_qdot_dynamic = Jdot_qdot;
    const auto dynamic_counts = allocation_counter::count_allocations(
        [&] { dynamic.compute(s.M, s.h, s.J, jdot_qdot_dynamic, s.qdot, s.r); });
    EXPECT_EQ(dynamic_counts.operator_new + dynamic_counts.eigen, 0);
    EXPECT_LT(relative(MatrixXd(fixed.task_inertia), dynamic.task_inertia), 1e-13);
    EXPECT_LT(relative(VectorXd(fixed.task_bias), dynamic.task_bias), 1e-13);
    EXPECT_LT(relative(MatrixXd(fixed.projector), dynamic.projector), 1e-13);
    static_assert(noexcept(fixed.compute(M, h, J, Jdot_qdot, qdot, r)), "per tick");
}

}  // namespace

// Every member compiles (fixed and dynamic sizes, double and float).
template class coopdyn::ProjectedDynamics<double, 2, 14>;
template class coopdyn::ProjectedDynamics<double, 3, 22>;
template class coopdyn::ProjectedDynamics<float, 2, 15>;
template class coopdyn::ProjectedDynamics<double, coopdyn::Dynamic, coopdyn::Dynamic>;

