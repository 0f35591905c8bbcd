// Joint-space systems of K arms holding one object, for the tests and benchmarks of
// include/coopdyn/control/: random (seeded) joint inertias, biases and contact Jacobians with the
// block structure of real arms (each arm's contact depends on its own joints and, optionally, on a
// shared torso joint), and dense references built from the printed formulas with SVD
// pseudo-inverses (no coopdyn calls).
#pragma once

#include "sample_systems.hpp"

#include <Eigen/Dense>
#include <Eigen/SVD>

namespace coopdyn_test {

/// Everything the controller gets per tick from a kinematics/dynamics library.
struct JointSpaceSystem {
    MatrixXd M;          // Q x Q, SPD
    VectorXd h;          // Q
    MatrixXd J;          // 6K x Q
    MatrixXd Jdot;       // 6K x Q (the explicit motion J(t) = J + t Jdot of the derivative tests)
    VectorXd qdot;       // Q, on the constraint manifold: Jc qdot = 0
    MatrixXd r;          // 3 x K, contact points relative to the object's centre, {w}
    Index arms = 0;
    Index joints = 0;
};

/// The shapes the control tests sweep: K = 2, 3, 4 arms of 7 joints, with and without a shared
/// torso joint.
struct ArmCase {
    Index arms;
    bool torso;
};
inline constexpr ArmCase arm_cases[] = {{2, false}, {2, true}, {3, false}, {3, true}, {4, false}, {4, true}};

/// Moore-Penrose pseudo-inverse by SVD, singular values below 1e-10 of the largest dropped.
COOPDYN_LAZY MatrixXd pseudo_inverse(const MatrixXd& matrix)
{
    const Eigen::JacobiSVD<MatrixXd> svd(matrix, Eigen::ComputeThinU | Eigen::ComputeThinV);
    const VectorXd& values = svd.singularValues();
    VectorXd inverted = VectorXd::Zero(values.size());
    for (Index i = 0; i < values.size(); ++i) {
        if (values(i) > 1e-10 * values(0)) {
            inverted(i) = 1.0 / values(i);
        }
    }
    return svd.matrixV() * inverted.asDiagonal() * svd.matrixU().transpose();
}

/// Numerical rank by SVD (relative threshold 1e-10).
COOPDYN_LAZY Index numerical_rank(const MatrixXd& matrix)
{
    const Eigen::JacobiSVD<MatrixXd> svd(matrix);
    const VectorXd& values = svd.singularValues();
    Index rank = 0;
    for (Index i = 0; i < values.size(); ++i) {
        rank += values(i) > 1e-10 * values(0) ? 1 : 0;
    }
    return rank;
}

/// The printed formulas, dense: G, N = I - G^+ G, Jc = N J (L(13)), Jx = (G G^T)^-1 G J.
struct LiteralGrasp {
    MatrixXd G, G_pinv, N, Jc, Jx;
};

COOPDYN_LAZY LiteralGrasp literal_grasp(const MatrixXd& r, const MatrixXd& J)
{
    LiteralGrasp grasp;
    grasp.G = literal_grasp_matrix(r);
    const MatrixXd gram = grasp.G * grasp.G.transpose();
    grasp.G_pinv = grasp.G.transpose() * gram.inverse();
    grasp.N = MatrixXd::Identity(J.rows(), J.rows()) - grasp.G_pinv * grasp.G;
    grasp.Jc = grasp.N * J;
    grasp.Jx = gram.inverse() * grasp.G * J;
    return grasp;
}

/// A random system: 7 joints per arm (plus one torso joint shared by all arms when `torso`),
/// contact Jacobians with entries in [-1, 1] on the arm's own (and the torso's) columns, a
/// random SPD joint inertia (condition ~ 10-100), contact points 0.1-0.5 m from the centre, and
/// qdot projected onto the constraint manifold with the literal P.
COOPDYN_LAZY JointSpaceSystem random_joint_space_system(Index arms, bool torso, Rng& rng)
{
    JointSpaceSystem system;
    system.arms = arms;
    const Index per_arm = 7;
    const Index first = torso ? 1 : 0;
    system.joints = first + per_arm * arms;
    const Index joints = system.joints;
    system.J = MatrixXd::Zero(6 * arms, joints);
    system.Jdot = MatrixXd::Zero(6 * arms, joints);
    for (Index i = 0; i < arms; ++i) {
        system.J.block(6 * i, first + per_arm * i, 6, per_arm) = random_matrix(6, per_arm, rng);
        system.Jdot.block(6 * i, first + per_arm * i, 6, per_arm) = random_matrix(6, per_arm, rng);
        if (torso) {
            system.J.block(6 * i, 0, 6, 1) = random_matrix(6, 1, rng);
            system.Jdot.block(6 * i, 0, 6, 1) = random_matrix(6, 1, rng);
        }
    }
    system.M = random_spd(joints, rng, uniform(rng, 0.5, 2.0), 0.1);
    system.h = 10.0 * random_vector(joints, rng);
    system.r = MatrixXd(3, arms);
    for (Index i = 0; i < arms; ++i) {
        const Vector3d direction = random_vector(rng).normalized();
        system.r.col(i) = uniform(rng, 0.1, 0.5) * direction;
    }
    const LiteralGrasp grasp = literal_grasp(system.r, system.J);
    const MatrixXd projector = MatrixXd::Identity(joints, joints) - pseudo_inverse(grasp.Jc) * grasp.Jc;
    system.qdot = projector * random_vector(joints, rng);
    return system;
}

/// The exact constrained motion of the arms holding a massless object with an external wrench on
/// it, the contact wrenches as explicit unknowns (a physical model the controller's formulas were
/// not derived from):
///
///     M qdd + h = tau + J^T f            (f: the wrenches the object applies to the hands)
///     G (-f) + F_x = 0                   (the massless object is in balance)
///     J qdd + Jdot qdot = G^T a_o + b    (each contact moves with the object; b_i = [w x (w x r_i); 0])
///
/// one square linear system in (qdd, f, a_o), solved densely. `applied` = -f, the hands' wrenches
/// on the object; `residual` the relative residual of the solve.
struct PhysicalSolution {
    VectorXd qdd;
    VectorXd applied;
    Vector6d object_acceleration;
    double residual = 0;
};

COOPDYN_LAZY PhysicalSolution solve_physical_model(const JointSpaceSystem& s, const VectorXd& tau, const Vector6d& external)
{
    const Index q = s.joints;
    const Index m = 6 * s.arms;
    const MatrixXd G = literal_grasp_matrix(s.r);
    // The object's angular velocity from the contacts' motion (qdot is on the manifold).
    const Vector6d object_twist = (G * G.transpose()).inverse() * G * s.J * s.qdot;
    const Vector3d omega = object_twist.tail<3>();
    VectorXd centripetal = VectorXd::Zero(m);
    for (Index i = 0; i < s.arms; ++i) {
        centripetal.segment<3>(6 * i) = omega.cross(omega.cross(Vector3d(s.r.col(i))));
    }
    MatrixXd system = MatrixXd::Zero(q + m + 6, q + m + 6);
    VectorXd rhs = VectorXd::Zero(q + m + 6);
    system.block(0, 0, q, q) = s.M;
    system.block(0, q, q, m) = -s.J.transpose();
    rhs.head(q) = tau - s.h;
    system.block(q, q, 6, m) = G;  // G f = F_x
    rhs.segment<6>(q) = external;
    system.block(q + 6, 0, m, q) = s.J;
    system.block(q + 6, q + m, m, 6) = -G.transpose();
    rhs.tail(m) = centripetal - s.Jdot * s.qdot;
    const VectorXd solution = system.partialPivLu().solve(rhs);
    return {solution.head(q), -solution.segment(q, m), solution.tail<6>(),
            (system * solution - rhs).norm() / rhs.norm()};
}

}  // namespace coopdyn_test
