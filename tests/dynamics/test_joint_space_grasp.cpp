// JointSpaceGrasp (coopdyn/dynamics/joint_space_grasp.hpp, docs/dynamics.md "Arms in joint
// space") against a dense KKT solve of the whole welded chain, which it never forms: K arms of
// different joint counts (fixed and dynamic sizes, K = 2 and 3), seeded random SPD M_i and random
// J_i, nonzero joint and object velocities, a Baumgarte term, a central and a general object
// inertia. Also: refusals (an indefinite M_i, a singular arm) and no allocation per solve.
// First: it defines EIGEN_RUNTIME_NO_MALLOC and eigen_assert before Eigen is included.
#include "../allocation_counter.hpp"

#include "sample_systems.hpp"

#include <coopdyn/dynamics/joint_space_grasp.hpp>
#include <coopdyn/spatial/skew.hpp>

#include <gtest/gtest.h>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace {

using coopdyn_test::MatrixXd;
using coopdyn_test::Rng;
using coopdyn_test::Vector3d;
using coopdyn_test::Vector6d;
using coopdyn_test::VectorXd;
using Eigen::Index;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// One random welded chain: per arm M_i, J_i, u_i = tau_i - c_i, Jdot_i qdot_i, beta_i; the
/// object's M_o (dense), its weld points r_i, angular velocity and unconstrained wrench.
struct Chain {
    std::vector<MatrixXd> inertia, jacobian;
    std::vector<VectorXd> free_torque;
    std::vector<Vector6d> rate, beta;
    Matrix6d object_inertia;
    Eigen::Matrix3Xd r;
    Vector3d omega;
    Vector6d object_h_sigma;
};

/// M_i's diagonal spans about 1e-2 to 10 kg m^2 (as a real arm's joint inertias do).
Chain random_chain(const std::vector<Index>& joints, Rng& rng, bool central_object)
{
    Chain chain;
    const auto arms = static_cast<Index>(joints.size());
    chain.r.resize(3, arms);
    for (Index i = 0; i < arms; ++i) {
        const Index n = joints[static_cast<std::size_t>(i)];
        const VectorXd scale = VectorXd::LinSpaced(n, 0.5, -1.0).unaryExpr([](double e) { return std::pow(10.0, e); });
        chain.inertia.push_back(scale.asDiagonal() * coopdyn_test::random_spd(n, rng, 2.0, 0.2) * scale.asDiagonal());
        // A palm Jacobian of an arm away from its singularities (smallest singular value order 1).
        MatrixXd jacobian = 0.5 * coopdyn_test::random_matrix(6, n, rng);
        jacobian.leftCols<6>() += Matrix6d::Identity();
        chain.jacobian.push_back(jacobian);
        chain.free_torque.push_back(coopdyn_test::random_vector(n, rng, -20.0, 20.0));
        chain.rate.push_back(coopdyn_test::random_vector6(rng, 3.0));
        chain.beta.push_back(coopdyn_test::random_vector6(rng, 0.5));
        chain.r.col(i) = coopdyn_test::random_vector(rng, 0.4);
    }
    chain.omega = coopdyn_test::random_vector(rng, 2.0);
    chain.object_h_sigma = coopdyn_test::random_vector6(rng, 10.0);
    if (central_object) {
        chain.object_inertia.setZero();
        chain.object_inertia.topLeftCorner<3, 3>() = coopdyn_test::uniform(rng, 0.5, 3.0) * Eigen::Matrix3d::Identity();
        chain.object_inertia.bottomRightCorner<3, 3>() = coopdyn_test::random_body_inertia(rng, 0.1);
    } else {
        chain.object_inertia = coopdyn_test::random_spd(6, rng, 1.0, 0.5);
    }
    return chain;
}

/// The whole chain as one constrained system, z = [qdd_1; ...; qdd_K; xdd_o]:
///     Mbar z = F + A^T lambda,  A z = c,
/// A_i = [0 .. J_i .. 0, -G_i^T], c_i = b_i + beta_i - Jdot_i qdot_i, b_i = [w x (w x r_i); 0],
/// G_i^T xdd_o = [a + alpha x r_i; alpha], solved densely (the KKT matrix by full-pivot LU).
/// lambda_i = h_i, the object's wrench on palm i. Returns [z; lambda].
VectorXd kkt_solution(const Chain& chain)
{
    const auto arms = static_cast<Index>(chain.inertia.size());
    Index n = 0;
    for (const MatrixXd& m : chain.inertia) {
        n += m.rows();
    }
    const Index size = n + 6, rows = 6 * arms;
    MatrixXd kkt = MatrixXd::Zero(size + rows, size + rows);
    VectorXd rhs = VectorXd::Zero(size + rows);
    Index joint = 0;
    for (Index i = 0; i < arms; ++i) {
        const auto k = static_cast<std::size_t>(i);
        const Index n_i = chain.inertia[k].rows();
        const Vector3d r = chain.r.col(i);
        Eigen::Matrix<double, 6, 6> g_transpose = Matrix6d::Identity();
        g_transpose.topRightCorner<3, 3>() = -coopdyn::skew(r);  // a + alpha x r = a - S(r) alpha
        MatrixXd a_i = MatrixXd::Zero(6, size);
        a_i.block(0, joint, 6, n_i) = chain.jacobian[k];
        a_i.rightCols<6>() = -g_transpose;
        kkt.block(0, 0, size, size).block(joint, joint, n_i, n_i) = chain.inertia[k];
        kkt.block(0, size + 6 * i, size, 6) = -a_i.transpose();
        kkt.block(size + 6 * i, 0, 6, size) = a_i;
        rhs.segment(joint, n_i) = chain.free_torque[k];
        Vector6d c = chain.beta[k] - chain.rate[k];
        c.head<3>() += chain.omega.cross(chain.omega.cross(r));
        rhs.segment(size + 6 * i, 6) = c;
        joint += n_i;
    }
    kkt.block<6, 6>(n, n) = chain.object_inertia;
    rhs.segment<6>(n) = chain.object_h_sigma;
    return kkt.fullPivLu().solve(rhs);
}

struct Errors {
    double acceleration = 0.0, wrench = 0.0;
};

/// Loads `chain` into `grasp`, solves, and returns the relative errors against the KKT solve.
template <typename Grasp, typename ObjectInertia>
Errors compare(Grasp& grasp, const Chain& chain, const ObjectInertia& object_inertia)
{
    const auto arms = static_cast<Index>(chain.inertia.size());
    for (Index i = 0; i < arms; ++i) {
        const auto k = static_cast<std::size_t>(i);
        EXPECT_TRUE(grasp.set_arm(i, chain.inertia[k], chain.jacobian[k], chain.free_torque[k], chain.rate[k], chain.beta[k]));
    }
    VectorXd qdd(grasp.total_joints());
    EXPECT_TRUE(grasp.solve(object_inertia, chain.r, chain.omega, chain.object_h_sigma, qdd));
    const VectorXd expected = kkt_solution(chain);
    const Index n = grasp.total_joints();
    VectorXd acceleration(n + 6);
    acceleration << qdd, grasp.object_acceleration();
    VectorXd wrenches(6 * arms);
    for (Index i = 0; i < arms; ++i) {
        wrenches.segment<6>(6 * i) = grasp.palm_wrench(i);
    }
    Errors errors;
    errors.acceleration = (acceleration - expected.head(n + 6)).norm() / (1.0 + expected.head(n + 6).norm());
    errors.wrench = (wrenches - expected.tail(6 * arms)).norm() / (1.0 + expected.tail(6 * arms).norm());
    // The object's wrench h_o = M_o xdd_o - hSigma_o is the palms' -sum G_i h_i (Newton's third law).
    Vector6d reaction = Vector6d::Zero();
    for (Index i = 0; i < arms; ++i) {
        const Vector6d h = expected.segment<6>(n + 6 + 6 * i);
        reaction.head<3>() -= h.head<3>();
        reaction.tail<3>() -= Vector3d(chain.r.col(i)).cross(h.head<3>()) + h.tail<3>();
    }
    errors.wrench = std::max(errors.wrench, (grasp.object_wrench() - reaction).norm() / (1.0 + reaction.norm()));
    return errors;
}

template <typename Grasp> void expect_matches_kkt(const std::vector<Index>& joints, bool central_object, unsigned seed,
                                                  const char* name)
{
    Rng rng(seed);
    Errors worst;
    for (int trial = 0; trial < 50; ++trial) {
        const Chain chain = random_chain(joints, rng, central_object);
        Grasp grasp(joints);
        Errors errors;
        if (central_object) {
            errors = compare(grasp, chain,
                             coopdyn::CentralInertia<double>(chain.object_inertia(0, 0),
                                                             Eigen::Matrix3d(chain.object_inertia.bottomRightCorner<3, 3>())));
        } else {
            errors = compare(grasp, chain, chain.object_inertia);
        }
        worst.acceleration = std::max(worst.acceleration, errors.acceleration);
        worst.wrench = std::max(worst.wrench, errors.wrench);
    }
    // Relative to the solution's size; M_i's condition (about 1e6) costs digits of both solves.
    EXPECT_LT(worst.acceleration, 1e-9) << name;
    EXPECT_LT(worst.wrench, 1e-9) << name;
    std::printf("%s: against the dense KKT solve, accelerations %.2g, wrenches %.2g (relative, worst of 50)\n", name,
                worst.acceleration, worst.wrench);
}

TEST(JointSpaceGrasp, TwoArmsOfSixAndSevenJointsMatchTheKktSolve)
{
    expect_matches_kkt<coopdyn::JointSpaceGrasp<double>>({6, 7}, false, 1, "K = 2 (6, 7), dynamic");
    expect_matches_kkt<coopdyn::JointSpaceGrasp<double, 2>>({7, 6}, true, 2, "K = 2 (7, 6), fixed K");
}

TEST(JointSpaceGrasp, TwoFixedSevenJointArmsMatchTheKktSolve)
{
    // The rigid plant's shape (examples/box): everything fixed-size, FixedLdlt throughout.
    expect_matches_kkt<coopdyn::JointSpaceGrasp<double, 2, 7>>({7, 7}, true, 3, "K = 2 (7, 7), fixed");
    expect_matches_kkt<coopdyn::JointSpaceGrasp<double, 2, 7>>({7, 7}, false, 4, "K = 2 (7, 7), fixed, dense M_o");
}

TEST(JointSpaceGrasp, ThreeArmsMatchTheKktSolve)
{
    expect_matches_kkt<coopdyn::JointSpaceGrasp<double>>({6, 7, 9}, true, 5, "K = 3 (6, 7, 9), dynamic");
    expect_matches_kkt<coopdyn::JointSpaceGrasp<double, 3>>({7, 6, 6}, false, 6, "K = 3 (7, 6, 6), fixed K");
    expect_matches_kkt<coopdyn::JointSpaceGrasp<double, 3, 6>>({6, 6, 6}, true, 7, "K = 3 (6, 6, 6), fixed");
}

TEST(JointSpaceGrasp, RefusesAnIndefiniteArmInertiaAndASingularArm)
{
    Rng rng(11);
    const Chain chain = random_chain({7, 6}, rng, false);
    coopdyn::JointSpaceGrasp<double> grasp({7, 6});
    MatrixXd indefinite = chain.inertia[0];
    indefinite(3, 3) = -1.0;
    EXPECT_FALSE(grasp.set_arm(0, indefinite, chain.jacobian[0], chain.free_torque[0], chain.rate[0], chain.beta[0]));

    // A palm that cannot turn about one axis: J_i's last row zero, J_i M_i^-1 J_i^T singular.
    MatrixXd singular = chain.jacobian[1];
    singular.row(5).setZero();
    ASSERT_TRUE(grasp.set_arm(0, chain.inertia[0], chain.jacobian[0], chain.free_torque[0], chain.rate[0], chain.beta[0]));
    ASSERT_TRUE(grasp.set_arm(1, chain.inertia[1], singular, chain.free_torque[1], chain.rate[1], chain.beta[1]));
    VectorXd qdd = VectorXd::Constant(13, 7.0);
    EXPECT_FALSE(grasp.solve(chain.object_inertia, chain.r, chain.omega, chain.object_h_sigma, qdd));
    EXPECT_TRUE((qdd.array() == 7.0).all());  // nothing written
}

TEST(JointSpaceGrasp, SolvingAllocatesNothing)
{
    Rng rng(12);
    const Chain chain = random_chain({6, 7, 7}, rng, false);
    coopdyn::JointSpaceGrasp<double> dynamic({6, 7, 7});
    VectorXd qdd(20);
    const auto counts = allocation_counter::count_allocations([&] {
        for (Index i = 0; i < 3; ++i) {
            const auto k = static_cast<std::size_t>(i);
            dynamic.set_arm(i, chain.inertia[k], chain.jacobian[k], chain.free_torque[k], chain.rate[k], chain.beta[k]);
        }
        dynamic.solve(chain.object_inertia, chain.r, chain.omega, chain.object_h_sigma, qdd);
    });
    EXPECT_EQ(counts.operator_new, 0);
    EXPECT_EQ(counts.eigen, 0);

    const Chain seven = random_chain({7, 7}, rng, false);
    coopdyn::JointSpaceGrasp<double, 2, 7> fixed;
    const Eigen::Matrix<double, 7, 7> m0 = seven.inertia[0], m1 = seven.inertia[1];
    const Eigen::Matrix<double, 6, 7> j0 = seven.jacobian[0], j1 = seven.jacobian[1];
    const Eigen::Matrix<double, 7, 1> u0 = seven.free_torque[0], u1 = seven.free_torque[1];
    const Eigen::Matrix<double, 3, 2> r2 = seven.r;
    Eigen::Matrix<double, 14, 1> qdd14;
    const auto fixed_counts = allocation_counter::count_allocations([&] {
        fixed.set_arm(0, m0, j0, u0, seven.rate[0], seven.beta[0]);
        fixed.set_arm(1, m1, j1, u1, seven.rate[1], seven.beta[1]);
        fixed.solve(seven.object_inertia, r2, seven.omega, seven.object_h_sigma, qdd14);
    });
    EXPECT_EQ(fixed_counts.operator_new, 0);
    EXPECT_EQ(fixed_counts.eigen, 0);
}

}  // namespace
