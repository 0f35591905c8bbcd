// Seeded random test systems and literal (library-independent) references for the dynamics
// tests: SPD inertias, non-symmetric grasps, and the constraint matrix A (14), bias b (13) and
// grasp matrix G (24) written out from docs/model.md without calling coopdyn.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include <random>

namespace coopdyn_test {

using Eigen::Index;
using Eigen::Matrix3d;
using Eigen::MatrixXd;
using Eigen::Vector3d;
using Eigen::VectorXd;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Rng = std::mt19937;

inline double uniform(Rng& rng, double low, double high)
{
    return std::uniform_real_distribution<double>(low, high)(rng);
}

inline MatrixXd random_matrix(Index rows, Index cols, Rng& rng, double low = -1.0, double high = 1.0)
{
    MatrixXd result(rows, cols);
    for (Index j = 0; j < cols; ++j) {
        for (Index i = 0; i < rows; ++i) {
            result(i, j) = uniform(rng, low, high);
        }
    }
    return result;
}

inline VectorXd random_vector(Index size, Rng& rng, double low = -1.0, double high = 1.0)
{
    return random_matrix(size, 1, rng, low, high);
}

/// General (fully coupled) SPD matrix: scale * (B B^T + floor I), B uniform in [-1, 1].
inline MatrixXd random_spd(Index size, Rng& rng, double scale = 1.0, double floor = 0.5)
{
    const MatrixXd factor = random_matrix(size, size, rng);
    return scale * (factor * factor.transpose() + floor * MatrixXd::Identity(size, size));
}

inline Eigen::Quaterniond random_unit_quaternion(Rng& rng)
{
    std::normal_distribution<double> normal(0.0, 1.0);
    Eigen::Vector4d v;
    do {
        for (Index k = 0; k < 4; ++k) {
            v(k) = normal(rng);
        }
    } while (v.norm() < 0.1);
    v.normalize();
    return Eigen::Quaterniond(v(3), v(0), v(1), v(2));
}

/// Grasp offsets r (3 x N), each column of length 0.2..1 in a random direction: no symmetry.
inline MatrixXd random_offsets(Index arms, Rng& rng)
{
    MatrixXd r(3, arms);
    for (Index i = 0; i < arms; ++i) {
        Vector3d direction;
        do {
            direction = random_vector(3, rng);
        } while (direction.norm() < 0.1);
        r.col(i) = uniform(rng, 0.2, 1.0) * direction.normalized();
    }
    return r;
}

/// S(a), written out.
inline Matrix3d hat(const Vector3d& a)
{
    Matrix3d s;
    s << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
    return s;
}

/// a with S(a) = (m - m^T) / 2 (the axial vector of the skew part).
inline Vector3d vee_skew_part(const Matrix3d& m)
{
    return 0.5 * Vector3d(m(2, 1) - m(1, 2), m(0, 2) - m(2, 0), m(1, 0) - m(0, 1));
}

/// blkdiag(m I3, J).
inline Matrix6d block_diagonal_inertia(double mass, const Matrix3d& rotational)
{
    Matrix6d result = Matrix6d::Zero();
    result.topLeftCorner<3, 3>() = mass * Matrix3d::Identity();
    result.bottomRightCorner<3, 3>() = rotational;
    return result;
}

/// blkdiag(M_o, M_1, ..., M_N) from the 6x6 object inertia and the 6 x 6N stack.
inline MatrixXd assemble_inertia(const MatrixXd& object_inertia, const MatrixXd& ee_inertia)
{
    const Index arms = ee_inertia.cols() / 6;
    MatrixXd result = MatrixXd::Zero(6 * (arms + 1), 6 * (arms + 1));
    result.topLeftCorner(6, 6) = object_inertia;
    for (Index i = 0; i < arms; ++i) {
        result.block(6 * (i + 1), 6 * (i + 1), 6, 6) = ee_inertia.block(0, 6 * i, 6, 6);
    }
    return result;
}

/// A of (14), docs/model.md, block row i: [[-I3, S(r_i)], [0, -I3]] | I6 in arm i's columns.
inline MatrixXd literal_constraint_matrix(const MatrixXd& r)
{
    const Index arms = r.cols();
    MatrixXd a = MatrixXd::Zero(6 * arms, 6 * (arms + 1));
    for (Index i = 0; i < arms; ++i) {
        a.block(6 * i, 0, 3, 3) = -Matrix3d::Identity();
        a.block(6 * i, 3, 3, 3) = hat(r.col(i));
        a.block(6 * i + 3, 3, 3, 3) = -Matrix3d::Identity();
        a.block(6 * i, 6 * (i + 1), 6, 6).setIdentity();
    }
    return a;
}

/// b of (13), docs/model.md: b_i = [S(w)^2 r_i; 0].
inline VectorXd literal_constraint_bias(const MatrixXd& r, const Vector3d& omega)
{
    const Index arms = r.cols();
    VectorXd b = VectorXd::Zero(6 * arms);
    const Matrix3d s = hat(omega);
    for (Index i = 0; i < arms; ++i) {
        b.segment(6 * i, 3) = s * s * Vector3d(r.col(i));
    }
    return b;
}

/// G = [G_1 ... G_N], G_i = [[I3, 0], [S(r_i), I3]].
inline MatrixXd literal_grasp_matrix(const MatrixXd& r)
{
    const Index arms = r.cols();
    MatrixXd g = MatrixXd::Zero(6, 6 * arms);
    for (Index i = 0; i < arms; ++i) {
        g.block(0, 6 * i, 3, 3).setIdentity();
        g.block(3, 6 * i, 3, 3) = hat(r.col(i));
        g.block(3, 6 * i + 3, 3, 3).setIdentity();
    }
    return g;
}

/// |a - b| / |b|.
template <typename DerivedA, typename DerivedB>
double relative_error(const Eigen::MatrixBase<DerivedA>& a, const Eigen::MatrixBase<DerivedB>& b)
{
    return static_cast<double>((a - b).norm() / b.norm());
}

// Literal (53), shared by the coordination tests: the reduced system's constraint wrench from
// explicit relative constraints.

/// A' of (53): 6(N-1) x 6N relative constraints of arm 1 (index 0) against arm i. From the rigid
/// grasp (11)-(12) with d_i = r_i - r_1: pdd_i - pdd_1 + S(d_i) wd_1 = w x (w x d_i),
/// wd_i - wd_1 = 0 (errata E5: 6(N-1) rows).
inline MatrixXd relative_constraint_matrix(const MatrixXd& r)
{
    const Index arms = r.cols();
    MatrixXd a = MatrixXd::Zero(6 * (arms - 1), 6 * arms);
    for (Index i = 1; i < arms; ++i) {
        const Index row = 6 * (i - 1);
        a.block(row, 0, 3, 3) = -Matrix3d::Identity();
        a.block(row, 3, 3, 3) = hat(r.col(i) - r.col(0));
        a.block(row + 3, 3, 3, 3) = -Matrix3d::Identity();
        a.block(row, 6 * i, 6, 6).setIdentity();
    }
    return a;
}

/// b' of (53), 6(N-1): [w x (w x (r_i - r_1)); 0].
inline VectorXd relative_constraint_bias(const MatrixXd& r, const Vector3d& omega)
{
    const Index arms = r.cols();
    VectorXd b = VectorXd::Zero(6 * (arms - 1));
    for (Index i = 1; i < arms; ++i) {
        b.segment(6 * (i - 1), 3) = omega.cross(omega.cross(Vector3d(r.col(i) - r.col(0))));
    }
    return b;
}

/// Literal (53): the constraint wrench of the reduced system (end-effectors only, inertia
/// blkdiag(M_i) given as 6 x 6N) driven by `commanded` (6N), from the KKT conditions of Gauss'
/// principle: M' xdd - A'^T mu = commanded, A' xdd = b'; h'_int = M' xdd - commanded.
inline VectorXd literal_internal_wrench(const MatrixXd& ee_inertia, const MatrixXd& r, const Vector3d& omega,
                                 const VectorXd& commanded)
{
    const Index arms = r.cols();
    const Index n = 6 * arms;
    const Index m = 6 * (arms - 1);
    const MatrixXd a = relative_constraint_matrix(r);
    MatrixXd kkt = MatrixXd::Zero(n + m, n + m);
    for (Index i = 0; i < arms; ++i) {
        kkt.block(6 * i, 6 * i, 6, 6) = ee_inertia.block(0, 6 * i, 6, 6);
    }
    const MatrixXd inertia = kkt.topLeftCorner(n, n);
    kkt.topRightCorner(n, m) = -a.transpose();
    kkt.bottomLeftCorner(m, n) = a;
    VectorXd rhs(n + m);
    rhs << commanded, relative_constraint_bias(r, omega);
    const VectorXd solution = kkt.fullPivLu().solve(rhs);
    return inertia * solution.head(n) - commanded;
}

}  // namespace coopdyn_test
