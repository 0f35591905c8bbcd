// Benchmarks of one full controller tick (coopdyn/control/controller.hpp, coopdyn::controller_tick):
// input checks, M = L L^T, the grasp in {w}, the projected dynamics (Jx, Jc, B, P, Mc, Lambda_c, hc
// and the exact rate terms), the impedance law L(16) and the estimate F_x of L(7), the contact-wrench
// bias w_0 (E11), the contact QP in the internal-wrench coordinates z (E10), the predicted contact
// wrenches and friction margins, and the posture torque (E12). On the seeded random systems of
// tests/common/arm_systems.hpp, built like tests/control/test_controller.cpp's random_case (each
// contact normal pointing at the object's centre); the first seed whose tick is `ok` (the QP
// feasible, no fallback) is used, and a benchmark whose tick is not `ok` is skipped with an error.
//
//   ControllerTick/K2_Q14/{fixed,dynamic}         two 7-joint arms, ControllerModel<double, 2, 14>
//                                                 and <double, Dynamic, Dynamic>
//   ControllerTick/K2_Q15_torso/{fixed,dynamic}   the same with one torso joint shared by both arms
//   ControllerTick/K3_Q21/{fixed,dynamic}         three 7-joint arms
//   ControllerTick/K2_Q14/fixed_cold              parameters.qp.warm_start = false: the QP starts
//                                                 from the empty active set every tick
//   ControllerTick/K2_Q14/fixed_least_torque      SqueezeObjective::least_torque_centred(), the
//                                                 default before the least squeeze (errata E13)
//   ControllerTick/K2_Q14/fixed_paper_objective   SqueezeObjective::paper(): the paper's L(20)
//                                                 objective (plus the 1e-6 ridge), the same QP
//                                                 as LiteralTick's, for a like-for-like ratio
//   LiteralTick/K2_Q14                            the same tick written as a reader of the paper
//                                                 would: dense Eigen::MatrixXd, allocating, SVD
//                                                 pseudo-inverses, LU inverses, and the paper's QP
//                                                 in the stacked contact wrench w (6K variables,
//                                                 G w = -F_x as two inequalities per row)
//
// Every ControllerTick runs the same input every tick. With warm start (the default) the QP begins
// from the previous tick's active set, which is the optimal one here, so the warm numbers are the
// best case of a slowly changing input; fixed_cold is the worst case of the QP part. Counters:
// qp_iterations is the QP's steps in the last tick (a warm start counts re-adding the previous
// active rows as steps). LiteralTick's counters: qp_iterations of its QP in w, tau_u_error the
// relative difference of its tau_u = P Jx^T F from the library's data.motion_torque (checked
// < 1e-8 before timing), and wrench_error / torque_error the relative differences of its contact
// wrenches w and torque tau from a library tick with SqueezeObjective::paper() (the same minimiser: with
// w = w_0 + B z, |Jc^T (w - w_0)|^2 = |J^T B z|^2 and |w - w_0| = |z|).
//
// Reading the ratio: time(LiteralTick/K2_Q14) / time(ControllerTick/K2_Q14/fixed_paper_objective)
// is what the library's structure (closed-form basis + one 6(K-1) Cholesky instead of SVDs, no
// explicit inverses, fixed sizes, no allocation, the QP in 6(K-1) variables instead of 6K with
// 12 equality rows) buys for the same computation; against ControllerTick/K2_Q14/fixed (default
// objective, the least squeeze, the one users get) it also includes the objective's effect on the
// QP (other active sets), which is small. Both sides run the same number of ticks of identical input; the literal side has no
// warm start (a one-shot solve_qp), so compare it with fixed_cold for the QP part.

#include <coopdyn/control/controller.hpp>
#include <coopdyn/control/friction.hpp>
#include <coopdyn/numerics/qp_solver.hpp>

#include "controller_cases.hpp"

#include <benchmark/benchmark.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>

namespace {

using coopdyn::Dynamic;
using coopdyn_test::Index;
using coopdyn_test::Matrix3d;
using coopdyn_test::MatrixXd;
using coopdyn_test::Rng;
using coopdyn_test::Vector3d;
using coopdyn_test::VectorXd;
using Parameters = coopdyn::ControllerParameters<double>;
using DynamicInput = coopdyn::ControllerInput<double, Dynamic, Dynamic>;
using Quaterniond = Eigen::Quaterniond;

// ---- the seeded case (tests/common/controller_cases.hpp) ---------------------------------------

using Case = coopdyn_test::ControllerCase;

Case random_case(Index arms, bool torso, unsigned seed)
{
    Rng rng(seed);
    return coopdyn_test::random_controller_case(arms, torso, rng);
}

/// The first case from seed 2024 on whose tick (dynamic sizes, default parameters) is ok.
Case feasible_case(Index arms, bool torso)
{
    for (unsigned seed = 2024; seed < 2024 + 200; ++seed) {
        Case c = random_case(arms, torso, seed);
        const coopdyn::ControllerModel<double, Dynamic, Dynamic> model(c.parameters);
        coopdyn::ControllerData<double, Dynamic, Dynamic> data(model);
        coopdyn::controller_tick(model, data, c.input);
        if (data.status == coopdyn::ControlStatus::ok) {
            return c;
        }
    }
    return random_case(arms, torso, 2024);  // not ok: the benchmark reports the error
}

enum class Variant { warm, cold, least_torque, paper_objective };

template <int Arms, int Joints, bool Torso, bool FixedSizes, Variant V = Variant::warm>
void BM_ControllerTick(benchmark::State& state)
{
    constexpr int K = FixedSizes ? Arms : Dynamic;
    constexpr int Q = FixedSizes ? Joints : Dynamic;
    Case c = feasible_case(Arms, Torso);
    if constexpr (V == Variant::cold) {
        c.parameters.qp.warm_start = false;
    }
    if constexpr (V == Variant::least_torque) {
        c.parameters.objective = coopdyn::SqueezeObjective<double>::least_torque_centred();
    }
    if constexpr (V == Variant::paper_objective) {
        c.parameters.objective = coopdyn::SqueezeObjective<double>::paper();
    }
    const coopdyn::ControllerModel<double, K, Q> model(c.parameters);
    coopdyn::ControllerData<double, K, Q> data(model);
    const coopdyn::ControllerInput<double, K, Q> input(c.input);
    coopdyn::controller_tick(model, data, input);  // the warm start's first active set
    for (auto _ : state) {
        const auto& tau = coopdyn::controller_tick(model, data, input);
        benchmark::DoNotOptimize(tau.data());
        benchmark::ClobberMemory();
    }
    if (data.status != coopdyn::ControlStatus::ok) {
        state.SkipWithError(coopdyn::to_string(data.status));
        return;
    }
    state.counters["qp_iterations"] = data.qp_iterations;
}

// ---- the literal baseline --------------------------------------------------------------------

struct LiteralTick {
    VectorXd tau, tau_u, tau_c, tau_n, w, margins;
    coopdyn::QpStatus qp_status = coopdyn::QpStatus::solved;
    int qp_iterations = 0;
};

/// One tick from the printed formulas, dense and allocating (MatrixXd throughout; no coopdyn
/// kernel but the friction rows and the QP solver).
LiteralTick literal_tick(const Parameters& p, const DynamicInput& in)
{
    const Index K = static_cast<Index>(p.contacts.size());
    const Index Q = p.joints;
    const Index m = 6 * K;
    const MatrixXd& M = in.inertia;
    const VectorXd& h = in.bias;
    const MatrixXd& J = in.jacobian;
    const VectorXd& qdot = in.velocities;
    const MatrixXd I_Q = MatrixXd::Identity(Q, Q);
    const MatrixXd I_m = MatrixXd::Identity(m, m);

    // The grasp: r_i = R_o p_i, G (24), G^+ = G^T (G G^T)^-1, N = I - G^+ G.
    const Matrix3d R_o = in.object.pose.orientation.toRotationMatrix();
    Eigen::Matrix3Xd r(3, K);
    for (Index i = 0; i < K; ++i) {
        r.col(i) = R_o * p.contacts[static_cast<std::size_t>(i)].frame.position;
    }
    const MatrixXd G = coopdyn_test::literal_grasp_matrix(MatrixXd(r));
    const MatrixXd A_inv = (G * G.transpose()).inverse();
    const MatrixXd G_pinv = G.transpose() * A_inv;
    const MatrixXd N = I_m - G_pinv * G;

    // L(13), L(4), L(15), L(26): Jc = N J, Jx = (G G^T)^-1 G J, P = I - Jc^+ Jc, Mc = P M + I - P,
    // Lambda_c = (Jx Mc^-1 P Jx^T)^-1.
    const MatrixXd Jc = N * J;
    const MatrixXd Jx = A_inv * G * J;
    const MatrixXd Jc_pinv = coopdyn_test::pseudo_inverse(Jc);
    const MatrixXd P = I_Q - Jc_pinv * Jc;
    const MatrixXd Mc = P * M + I_Q - P;
    const MatrixXd Mc_inv = Mc.partialPivLu().inverse();
    const MatrixXd Lambda = (Jx * Mc_inv * P * Jx.transpose()).inverse();

    // The rates (docs/control.md, "The rates in closed form"), Gdot_i = [[0, 0], [S(omega x r_i), 0]].
    const VectorXd v = J * qdot;
    const VectorXd y = Jx * qdot;
    const Vector3d omega = y.tail<3>();
    MatrixXd Gdot = MatrixXd::Zero(6, m);
    for (Index i = 0; i < K; ++i) {
        Gdot.block(3, 6 * i, 3, 3) = coopdyn_test::hat(omega.cross(Vector3d(r.col(i))));
    }
    const VectorXd& Jdot_qdot = in.jacobian_rate_qdot;
    const VectorXd Jxdot_qdot =
        A_inv * (G * Jdot_qdot + Gdot * v - Gdot * G.transpose() * y - G * Gdot.transpose() * y);
    const VectorXd Jcdot_qdot = Jdot_qdot - Gdot.transpose() * y - G.transpose() * Jxdot_qdot;
    const VectorXd Pdot_qdot = -Jc_pinv * Jcdot_qdot;

    // L(15): hc = Lambda_c (Jx Mc^-1 (P h - Pdot qdot) - Jxdot qdot).
    const VectorXd hc = Lambda * (Jx * Mc_inv * (P * h - Pdot_qdot) - Jxdot_qdot);

    // L(16) and L(7): xtilde = [p - p_d; 2 d_eta d_eps], dq = q q_d^-1.
    const Quaterniond dq = in.object.pose.orientation * in.desired_pose.orientation.conjugate();
    VectorXd xt(6);
    xt << in.object.pose.position - in.desired_pose.position, 2.0 * dq.w() * dq.vec();
    const VectorXd xtd = in.object.twist - in.desired_twist;
    const VectorXd F = hc + Lambda * in.desired_acceleration - p.damping * xtd - p.stiffness * xt;
    LiteralTick out;
    out.tau_u = P * Jx.transpose() * F;
    const VectorXd F_x = Lambda * (in.object_acceleration - in.desired_acceleration) + p.damping * xtd + p.stiffness * xt;

    // L(22)-(24) with E11: qdd = Mc^-1 (tau_u + P Jx^T F_x - P h + Pdot qdot),
    // eta = (Jc^T)^+ (I - P)(M qdd + h - Jx^T F_x), w_0 = -G^+ F_x - eta.
    const VectorXd qdd = Mc_inv * (out.tau_u + P * Jx.transpose() * F_x - P * h + Pdot_qdot);
    const MatrixXd JcT_pinv = coopdyn_test::pseudo_inverse(Jc.transpose());
    const VectorXd eta = JcT_pinv * (I_Q - P) * (M * qdd + h - Jx.transpose() * F_x);
    const VectorXd w0 = -G_pinv * F_x - eta;

    // L(20)-(25) in w: min |Jc^T (w - w_0)|^2 + 1e-6 |w - w_0|^2 s.t. G w = -F_x (two inequalities
    // per row) and the friction rows of each contact in {w}.
    const MatrixXd H = 2.0 * (Jc * Jc.transpose() + 1e-6 * I_m);
    const VectorXd g = -H * w0;
    Index friction_total = 0;
    for (const auto& contact : p.contacts) {
        friction_total += coopdyn::friction_rows(contact.friction.pyramid_edges);
    }
    MatrixXd C = MatrixXd::Zero(friction_total + 12, m);
    VectorXd d = VectorXd::Zero(friction_total + 12);
    Index row = 0;
    for (Index i = 0; i < K; ++i) {
        const coopdyn::ContactPoint<double>& contact = p.contacts[static_cast<std::size_t>(i)];
        const Index count = coopdyn::friction_rows(contact.friction.pyramid_edges);
        const Matrix3d R_ci = R_o * contact.frame.orientation.toRotationMatrix();
        MatrixXd rows(count, 6);
        VectorXd bounds(count);
        coopdyn::friction_rows(contact.friction, R_ci, rows, bounds);
        C.block(row, 6 * i, count, 6) = rows;
        d.segment(row, count) = bounds;
        row += count;
    }
    C.middleRows(row, 6) = G;
    d.segment(row, 6) = -F_x;
    C.middleRows(row + 6, 6) = -G;
    d.segment(row + 6, 6) = F_x;
    const auto result = coopdyn::solve_qp(H, g, C, d);
    out.qp_status = result.status;
    out.qp_iterations = result.iterations;
    out.w = result.x;
    out.tau_c = Jc.transpose() * (out.w - w0);
    out.margins = VectorXd::Constant(K, std::numeric_limits<double>::infinity());
    for (Index i = 0, k = 0; i < K; ++i) {
        const Index count = coopdyn::friction_rows(p.contacts[static_cast<std::size_t>(i)].friction.pyramid_edges);
        for (Index j = 0; j < count; ++j, ++k) {
            const double slack = d(k) - C.row(k).dot(out.w);
            out.margins(i) = std::min(out.margins(i), slack / C.row(k).norm());
        }
    }

    // E12: tau_n = (I - J^T (J M^-1 J^T)^-1 J M^-1) (h - K_n (q - q_n) - D_n qdot).
    const MatrixXd M_inv = M.partialPivLu().inverse();
    const VectorXd tau_0 = h - p.posture_stiffness.asDiagonal() * (in.positions - in.posture) -
                           p.posture_damping.asDiagonal() * qdot;
    const MatrixXd N_T = I_Q - J.transpose() * (J * M_inv * J.transpose()).inverse() * J * M_inv;
    out.tau_n = N_T * tau_0;
    out.tau = out.tau_u + out.tau_c + out.tau_n;
    return out;
}

double relative(const VectorXd& a, const VectorXd& b) { return (a - b).norm() / std::max(b.norm(), 1e-300); }

void BM_LiteralTick(benchmark::State& state)
{
    const Case c = feasible_case(2, false);
    // The library's tick (default objective) for tau_u, and with the paper's objective for w and tau.
    const coopdyn::ControllerModel<double, Dynamic, Dynamic> model(c.parameters);
    coopdyn::ControllerData<double, Dynamic, Dynamic> data(model);
    coopdyn::controller_tick(model, data, c.input);
    Parameters paper = c.parameters;
    paper.objective = coopdyn::SqueezeObjective<double>::paper();
    const coopdyn::ControllerModel<double, Dynamic, Dynamic> paper_model(paper);
    coopdyn::ControllerData<double, Dynamic, Dynamic> paper_data(paper_model);
    coopdyn::controller_tick(paper_model, paper_data, c.input);

    LiteralTick check = literal_tick(c.parameters, c.input);
    const double tau_u_error = relative(check.tau_u, data.motion_torque);
    if (!(tau_u_error < 1e-8)) {
        state.SkipWithError("the literal tau_u differs from the library's motion_torque");
        return;
    }
    if (check.qp_status != coopdyn::QpStatus::solved || paper_data.status != coopdyn::ControlStatus::ok) {
        state.SkipWithError("the literal QP (or the library's with the paper's objective) did not solve");
        return;
    }
    for (auto _ : state) {
        LiteralTick tick = literal_tick(c.parameters, c.input);
        benchmark::DoNotOptimize(tick.tau.data());
        benchmark::ClobberMemory();
    }
    state.counters["qp_iterations"] = check.qp_iterations;
    state.counters["tau_u_error"] = tau_u_error;
    state.counters["wrench_error"] = relative(check.w, paper_data.contact_wrenches);
    state.counters["torque_error"] = relative(check.tau, paper_data.torque);
}

BENCHMARK_TEMPLATE(BM_ControllerTick, 2, 14, false, true)->Name("ControllerTick/K2_Q14/fixed");
BENCHMARK_TEMPLATE(BM_ControllerTick, 2, 14, false, false)->Name("ControllerTick/K2_Q14/dynamic");
BENCHMARK_TEMPLATE(BM_ControllerTick, 2, 15, true, true)->Name("ControllerTick/K2_Q15_torso/fixed");
BENCHMARK_TEMPLATE(BM_ControllerTick, 2, 15, true, false)->Name("ControllerTick/K2_Q15_torso/dynamic");
BENCHMARK_TEMPLATE(BM_ControllerTick, 3, 21, false, true)->Name("ControllerTick/K3_Q21/fixed");
BENCHMARK_TEMPLATE(BM_ControllerTick, 3, 21, false, false)->Name("ControllerTick/K3_Q21/dynamic");
BENCHMARK_TEMPLATE(BM_ControllerTick, 2, 14, false, true, Variant::cold)->Name("ControllerTick/K2_Q14/fixed_cold");
BENCHMARK_TEMPLATE(BM_ControllerTick, 2, 14, false, true, Variant::least_torque)
    ->Name("ControllerTick/K2_Q14/fixed_least_torque");
BENCHMARK_TEMPLATE(BM_ControllerTick, 2, 14, false, true, Variant::paper_objective)
    ->Name("ControllerTick/K2_Q14/fixed_paper_objective");
BENCHMARK(BM_LiteralTick)->Name("LiteralTick/K2_Q14");

}  // namespace
