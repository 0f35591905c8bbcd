// The C++ side of the Python bindings' per-call overhead (docs/python.md, "Speed"): the same three
// calls as python/benchmarks/overhead.py, on the same inputs, with the same sizes chosen at run
// time (Eigen::Dynamic) as the bindings use. Prints microseconds per call (the median of 7 runs).
//
//   cmake --build build/release --target coopdyn_python_overhead -j1
//   build/release/python/coopdyn_python_overhead
//   PYTHONPATH=build/release/python /usr/bin/python3 python/benchmarks/overhead.py
#include <coopdyn/control.hpp>
#include <coopdyn/core.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

namespace {

template <typename Call> double microseconds_per_call(Call&& call, int calls)
{
    std::vector<double> runs;
    for (int run = 0; run < 7; ++run) {
        const auto start = std::chrono::steady_clock::now();
        for (int k = 0; k < calls; ++k) {
            call();
        }
        const std::chrono::duration<double, std::micro> elapsed = std::chrono::steady_clock::now() - start;
        runs.push_back(elapsed.count() / calls);
    }
    std::sort(runs.begin(), runs.end());
    return runs[3];
}

constexpr int X = Eigen::Dynamic;

double controller_tick_time()
{
    using namespace coopdyn;
    ControllerParameters<double> parameters;
    parameters.joints = 12;
    ContactPoint<double> left, right;
    Eigen::Matrix3d left_frame, right_frame;
    left_frame << 0, 0, 1, 0, -1, 0, 1, 0, 0;
    right_frame << 0, 0, -1, 0, 1, 0, 1, 0, 0;
    left.frame = {Eigen::Vector3d(-0.15, 0, 0), Eigen::Quaterniond(left_frame)};
    right.frame = {Eigen::Vector3d(0.15, 0, 0), Eigen::Quaterniond(right_frame)};
    left.friction.friction_coefficient = right.friction.friction_coefficient = 0.5;
    parameters.contacts = {left, right};
    parameters.stiffness = 1000.0 * Matrix6<double>::Identity();
    parameters.damping = 100.0 * Matrix6<double>::Identity();
    parameters.posture_stiffness = parameters.posture_damping = Eigen::VectorXd::Zero(12);
    const ControllerModel<double, X, X, X> model(parameters);
    ControllerData<double, X, X, X> data(model);
    ControllerInput<double, X, X> input(model);
    input.inertia = 2.0 * Eigen::MatrixXd::Identity(12, 12);
    input.bias = Eigen::VectorXd::Zero(12);
    input.bias(2) = input.bias(8) = 2 * 9.81;
    input.jacobian.setIdentity();
    input.object.pose.position << 0, 0, -2 * 9.81 / 1000;
    controller_tick(model, data, input);
    std::printf("controller_tick status %s, normal forces %.6f %.6f\n", to_string(data.status),
                data.contact_frame_wrenches(2, 0), data.contact_frame_wrenches(2, 1));
    return microseconds_per_call([&] { controller_tick(model, data, input); }, 20000);
}

double interaction_dynamics_time()
{
    using namespace coopdyn;
    const auto arm = ImpedanceEndEffector<double>()
                         .with_mass(10.0)
                         .with_rotational_inertia(0.5 * Eigen::Matrix3d::Identity())
                         .with_translational_damping(180.0)
                         .with_rotational_damping(10.0)
                         .with_translational_stiffness(300.0)
                         .with_rotational_stiffness(50.0);
    const RigidObject<double> beam{1.75, Eigen::Vector3d(0.055, 0.0, 0.055).asDiagonal()};
    const ImpedanceModelX model(beam, {{arm, {Eigen::Vector3d(0, -0.4, 0)}}, {arm, {Eigen::Vector3d(0, 0.4, 0)}}});
    Data<ImpedanceModelX> data(model);
    const RigidBodyState<double> state;
    const Setpoints<double, X> setpoints(2);
    const Disturbances<double, X> disturbances(2);
    return microseconds_per_call([&] { interaction_dynamics(model, data, state, setpoints, disturbances); }, 50000);
}

double solve_qp_time()
{
    // The problem of overhead.py: H = 2 I, g_j = cos(j), C_ij = sin(7 i + 3 j), d = 1.
    const Eigen::Index n = 6, m = 30;
    const Eigen::MatrixXd hessian = 2.0 * Eigen::MatrixXd::Identity(n, n);
    Eigen::VectorXd gradient(n);
    Eigen::MatrixXd constraints(m, n);
    for (Eigen::Index j = 0; j < n; ++j) {
        gradient(j) = std::cos(static_cast<double>(j));
        for (Eigen::Index i = 0; i < m; ++i) {
            constraints(i, j) = std::sin(static_cast<double>(7 * i + 3 * j));
        }
    }
    const Eigen::VectorXd bounds = Eigen::VectorXd::Ones(m);
    // As the binding does: a solver sized for the problem, then one cold solve.
    return microseconds_per_call(
        [&] {
            coopdyn::QpSolver<double, X, X> solver(n, m);
            const auto& result = solver.solve(hessian, gradient, constraints, bounds);
            if (result.status != coopdyn::QpStatus::solved) {
                std::printf("solve_qp: not solved\n");
            }
        },
        20000);
}

}  // namespace

int main()
{
    const double tick = controller_tick_time();
    const double dynamics = interaction_dynamics_time();
    const double qp = solve_qp_time();
    std::printf("C++ us per call: controller_tick K=2 Q=12 %.2f, interaction_dynamics N=2 %.2f, solve_qp 6x30 %.2f\n",
                tick, dynamics, qp);
}
