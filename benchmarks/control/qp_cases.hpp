// The QPs of benchmarks/control/bench_qp.cpp and qp_instructions.cpp (min 1/2 x^T H x + g^T x
// s.t. C x <= d, coopdyn/numerics/qp_solver.hpp), built once, in dynamic-size matrices:
//
//   contact_qp(C)     C point contacts with 3D forces (n = 3C), each with a 13-facet friction
//                     pyramid and 1 <= f_n <= 50 (15 rows per contact), tracking a desired force,
//                     outside the cone for some contacts, in the metric of a random SPD H of
//                     condition 100; plus 1000 ticks of slowly changing gradients
//   palm_qp(K)        the controller's own contact QP in the squeeze z (control/controller.hpp):
//                     K palms with the paper's 8-edge pyramid (15 rows each), 6 (K - 1)
//                     variables: K = 2 is 6 x 30, K = 3 is 12 x 45; H, g and d of the first tick
//                     of the first seeded case (tests/common/controller_cases.hpp) that is ok with
//                     a row active, C = ControllerModel::contact_qp_constraints
//   random_qp(n, m)   random dense rows, H of condition 100, 8 rows active at the optimum
#pragma once

#include <coopdyn/control/controller.hpp>

#include "controller_cases.hpp"

#include <Eigen/Geometry>
#include <Eigen/QR>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace coopdyn_bench {

using Eigen::Index;
using MatrixX = Eigen::MatrixXd;
using VectorX = Eigen::VectorXd;
using Rng = std::mt19937;

constexpr double two_pi = 6.283185307179586;

inline double uniform(Rng& rng, double low, double high) { return std::uniform_real_distribution<double>(low, high)(rng); }

inline MatrixX random_matrix(Index rows, Index cols, Rng& rng)
{
    MatrixX result(rows, cols);
    for (Index k = 0; k < result.size(); ++k) {
        result(k) = uniform(rng, -1, 1);
    }
    return result;
}

/// Q diag(1 .. condition, log-spaced) Q^T with a random orthogonal Q.
inline MatrixX random_spd(Index n, double condition, Rng& rng)
{
    const MatrixX q = Eigen::HouseholderQR<MatrixX>(random_matrix(n, n, rng)).householderQ();
    VectorX eigenvalues(n);
    for (Index i = 0; i < n; ++i) {
        eigenvalues(i) = std::pow(condition, static_cast<double>(i) / static_cast<double>(n - 1));
    }
    const MatrixX h = q * eigenvalues.asDiagonal() * q.transpose();
    return 0.5 * (h + h.transpose());
}

/// One QP, plus (contact_qp only) a sequence of slowly changing gradients.
struct ContactQp {
    MatrixX h;
    VectorX g;
    MatrixX c;
    VectorX d;
    std::vector<VectorX> sequence;  // g at successive 1 ms ticks
};

inline ContactQp contact_qp(Index contacts)
{
    Rng rng(static_cast<std::uint32_t>(1000 + contacts));
    const Index n = 3 * contacts;
    const Index facets = 13;
    ContactQp p;
    p.h = random_spd(n, 100.0, rng);
    p.c = MatrixX::Zero(15 * contacts, n);
    p.d = VectorX::Zero(15 * contacts);
    VectorX desired(n);
    for (Index k = 0; k < contacts; ++k) {
        const Eigen::Matrix3d frame =
            Eigen::Quaterniond(Eigen::Vector4d(random_matrix(4, 1, rng))).normalized().toRotationMatrix();
        const double friction = uniform(rng, 0.3, 0.8);
        for (Index j = 0; j < facets; ++j) {
            const double angle = two_pi * static_cast<double>(j) / static_cast<double>(facets);
            const Eigen::Vector3d local(std::cos(angle), std::sin(angle), -friction);
            p.c.block(15 * k + j, 3 * k, 1, 3) = (frame * local).transpose();
        }
        p.c.block(15 * k + 13, 3 * k, 1, 3) = frame.col(2).transpose();
        p.d(15 * k + 13) = 50.0;
        p.c.block(15 * k + 14, 3 * k, 1, 3) = -frame.col(2).transpose();
        p.d(15 * k + 14) = -1.0;
        const Eigen::Vector3d local(uniform(rng, -12, 12), uniform(rng, -12, 12), uniform(rng, 0, 10));
        desired.segment(3 * k, 3) = frame * local;
    }
    p.g = -p.h * desired;
    const VectorX phase = random_matrix(n, 1, rng) * 3.0;
    for (int tick = 0; tick < 1000; ++tick) {
        VectorX moving = desired;
        for (Index i = 0; i < n; ++i) {
            moving(i) += 4.0 * std::sin(two_pi * 1e-3 * tick + phase(i));
        }
        p.sequence.push_back(-p.h * moving);
    }
    return p;
}

/// The controller's contact QP for `arms` palms (see the file comment); empty when no seed of 200
/// gives an ok tick with a row active.
inline ContactQp palm_qp(Index arms)
{
    using coopdyn::Dynamic;
    for (unsigned seed = 2024; seed < 2024 + 200; ++seed) {
        coopdyn_test::Rng rng(seed);
        const coopdyn_test::ControllerCase c = coopdyn_test::random_controller_case(arms, false, rng);
        const coopdyn::ControllerModel<double, Dynamic, Dynamic> model(c.parameters);
        coopdyn::ControllerData<double, Dynamic, Dynamic> data(model);
        coopdyn::controller_tick(model, data, c.input);
        if (data.status == coopdyn::ControlStatus::ok && data.qp.result().active_count > 0) {
            ContactQp p;
            p.h = data.hessian;
            p.g = data.gradient;
            p.c = model.contact_qp_constraints();
            p.d = data.bounds;
            return p;
        }
    }
    return {};
}

/// Random rows (entries in [-1, 1]), H of condition 100, a known minimiser with 8 rows active
/// (multipliers 0.5 .. 2) and the others slack by 0.1 .. 1 of their norm.
inline ContactQp random_qp(Index n, Index m)
{
    Rng rng(static_cast<std::uint32_t>(7000 + 100 * n + m));
    const Index active = 8;
    ContactQp p;
    p.h = random_spd(n, 100.0, rng);
    p.c = random_matrix(m, n, rng);
    const VectorX x_star = random_matrix(n, 1, rng);
    VectorX lambda = VectorX::Zero(m);
    p.d = p.c * x_star;
    for (Index i = 0; i < m; ++i) {
        if (i < active) {
            lambda(i) = uniform(rng, 0.5, 2.0);
        } else {
            p.d(i) += uniform(rng, 0.1, 1.0) * p.c.row(i).norm();
        }
    }
    p.g = -p.h * x_star - p.c.transpose() * lambda;
    return p;
}

/// A QP in matrices of compile-time sizes (N, M fixed or Eigen::Dynamic).
template <int N, int M> struct SizedQp {
    Eigen::Matrix<double, N, N> h;
    Eigen::Matrix<double, N, 1> g;
    Eigen::Matrix<double, M, N> c;
    Eigen::Matrix<double, M, 1> d;

    explicit SizedQp(const ContactQp& p) : h(p.h), g(p.g), c(p.c), d(p.d) {}
};

/// Relative KKT residuals (stationarity, feasibility, complementarity; dual feasibility and the
/// status apart) of a solve: true when all are below 1e-9.
template <typename Result> bool satisfies_kkt(const ContactQp& p, const VectorX& g, const Result& result)
{
    const VectorX x = result.x;
    const VectorX lambda = result.multipliers;
    const double scale = p.h.norm() * x.norm() + g.norm() + p.c.norm() * lambda.norm();
    const double stationarity = (p.h * x + g + p.c.transpose() * lambda).norm() / scale;
    const VectorX slack = p.c * x - p.d;
    const double feasibility = slack.maxCoeff() / (p.c.norm() * x.norm() + p.d.norm());
    const double complementarity = lambda.cwiseProduct(slack).cwiseAbs().maxCoeff() / scale;
    return result.status == coopdyn::QpStatus::solved && stationarity <= 1e-9 && feasibility <= 1e-9 &&
           complementarity <= 1e-9 && lambda.minCoeff() >= 0;
}

}  // namespace coopdyn_bench
