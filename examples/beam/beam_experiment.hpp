// The experiments of the two-arm beam example (paper Section V, docs/analysis.md): the simulation
// with its 1 kHz log, the runs combined for the identification, and the grey-box identification of
// the apparent impedance from the logged wrench and pose alone (the excitation signals and the
// sensor model: beam_signals.hpp).
//
// Physics (Theorem 2's assumptions): the arms hold constant setpoints at the grasp poses of the
// object's equilibrium, and the object's weight is carried through the desired wrenches, h_o^d =
// h_g distributed by the non-squeezing load distribution (26) at every 1 ms controller tick from
// the pose at that tick. A disturbance wrench htilde_o (a multisine or human-like pushes) acts on
// the object. The simulation is coopdyn's Simulator (full model of docs/dynamics.md, RK4).
#pragma once

#include "beam_signals.hpp"
#include "scenario.hpp"

#include "../common/progress.hpp"

#include <coopdyn/coopdyn.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace beam_example {

/// Rotation vector theta u of a unit quaternion (the logarithm map), shortest rotation.
inline Eigen::Vector3d rotation_vector(const Eigen::Quaterniond& q)
{
    const double sign = q.w() < 0.0 ? -1.0 : 1.0;
    const Eigen::Vector3d v = sign * q.vec();
    const double w = sign * q.w();
    const double s = v.norm();
    if (s < 1e-12) {
        return 2.0 * v;  // theta u to third order
    }
    return (2.0 * std::atan2(s, w) / s) * v;
}

/// Everything one experiment logs, one column per 1 kHz sample (SI units).
struct ExperimentLog {
    Eigen::RowVectorXd time;             ///< s
    Eigen::Matrix<double, 6, Eigen::Dynamic> applied;       ///< htilde_o [N, N m]
    Eigen::Matrix<double, 6, Eigen::Dynamic> measured_wrench;  ///< htilde_o as logged (noise, low-pass)
    Eigen::Matrix<double, 7, Eigen::Dynamic> pose;          ///< p_o [m], q_o (x, y, z, w)
    Eigen::Matrix<double, 6, Eigen::Dynamic> twist;         ///< [v_o; w_o] [m/s, rad/s]
    Eigen::Matrix<double, 6, Eigen::Dynamic> displacement;  ///< p_o - p_eq [m]; log(q_o q_eq^-1) [rad]
    Eigen::Matrix<double, 6, Eigen::Dynamic> measured_displacement;  ///< as logged (noise)
    /// The signals the identification used: the combination of the runs' measured signals (see
    /// run_experiment), or the measured signals themselves with --single-run.
    Eigen::Matrix<double, 6, Eigen::Dynamic> identification_wrench;
    Eigen::Matrix<double, 6, Eigen::Dynamic> identification_displacement;
    Eigen::Matrix<double, 6, Eigen::Dynamic> model_displacement;     ///< identified model's prediction (NaN: not identified)
    /// Per arm i, rows 18 i .. 18 i + 17: total wrench h_i ON arm i, internal part (53), external
    /// part (54); each [f; t] in {w}, N and N m.
    Eigen::MatrixXd arm_wrenches;

    void resize(Eigen::Index samples, Eigen::Index arms)
    {
        time.resize(samples);
        applied.resize(6, samples);
        measured_wrench.resize(6, samples);
        pose.resize(7, samples);
        twist.resize(6, samples);
        displacement.resize(6, samples);
        measured_displacement.resize(6, samples);
        identification_wrench.resize(6, samples);
        identification_displacement.resize(6, samples);
        model_displacement.setConstant(6, samples, std::numeric_limits<double>::quiet_NaN());
        arm_wrenches.resize(18 * arms, samples);
    }
    Eigen::Index samples() const { return time.size(); }
};

/// Off-diagonal coupling of a symmetric 6x6 matrix: max_{i != j} |X_ij| / sqrt(X_ii X_jj).
inline double coupling(const coopdyn::Matrix6<double>& matrix)
{
    double worst = 0.0;
    for (Eigen::Index i = 0; i < 6; ++i) {
        for (Eigen::Index j = 0; j < 6; ++j) {
            if (i != j) {
                worst = std::max(worst, std::abs(matrix(i, j)) / std::sqrt(std::abs(matrix(i, i) * matrix(j, j))));
            }
        }
    }
    return worst;
}

struct ExperimentResult {
    ExperimentSpec spec;
    ExperimentLog log;
    coopdyn::DiagonalImpedanceFit fit;
    coopdyn::ApparentImpedance<double> nominal;  ///< Theorem 2 at the equilibrium
    double nominal_coupling = 0.0;               ///< max coupling of M, D, K (0: Corollary 1)
    /// Motion in the axes that were not excited, relative to the excited ones (RMS ratio; only
    /// for single-axis experiments, else NaN): 0 when the axes are decoupled.
    double cross_axis_motion = std::numeric_limits<double>::quiet_NaN();
    double excitation_force = 0.0, excitation_torque = 0.0;  ///< --force, --torque (or the scenario's)
    std::array<double, 6> amplitudes{};                       ///< per axis, as applied
    int runs = 4;                         ///< excitation runs combined for the identification (RunOptions::runs)
    double simulated_seconds = 0.0;       ///< simulated time, warm-up and every run included
    double warmup_seconds = 0.0;          ///< simulated before the log starts (multisine only)
    double simulation_seconds = 0.0;      ///< wall clock of the simulation
    double identification_seconds = 0.0;  ///< wall clock of the identification
};

using example_common::Progress;  // examples/common/progress.hpp

/// Fills `result`'s settings and Theorem 2's impedance at the equilibrium (`controller` holds the
/// grasp kinematics there): the amplitudes, --force on every excited translation and --torque on
/// every excited rotation.
template <typename ModelType>
void start_result(const Scenario& scenario, const ModelType& model, const ExperimentSpec& spec, const RunOptions& options,
                  coopdyn::Data<ModelType>& controller, ExperimentResult& result)
{
    result.spec = spec;
    result.excitation_force = options.force > 0.0 ? options.force : scenario.excitation.force;
    result.excitation_torque = options.torque > 0.0 ? options.torque : scenario.excitation.torque;
    result.nominal = coopdyn::apparent_impedance(model, controller);
    result.nominal_coupling = std::max({coupling(result.nominal.inertia), coupling(result.nominal.damping),
                                        coupling(result.nominal.stiffness)});
    for (std::size_t axis = 0; axis < 6; ++axis) {
        result.amplitudes[axis] = axis < 3 ? result.excitation_force : result.excitation_torque;
    }
}

/// Steps simulated before the log starts. A multisine is logged in periodic steady state: whole
/// periods are simulated first, until the slowest mode of the linearised dynamics has decayed by
/// e^-20 (its rate from the diagonal of Theorem 2's M, D, K at the equilibrium). Pushes start at
/// rest.
inline coopdyn::Index warmup_steps(const coopdyn::ApparentImpedance<double>& nominal, const RunOptions& options,
                                   coopdyn::Index steps)
{
    if (options.excitation != ExcitationKind::multisine) {
        return 0;
    }
    double slowest = std::numeric_limits<double>::infinity();  // decay rate, 1/s
    for (coopdyn::Index axis = 0; axis < 6; ++axis) {
        const double m = nominal.inertia(axis, axis);
        const double d = nominal.damping(axis, axis);
        const double k = nominal.stiffness(axis, axis);
        const double discriminant = d * d - 4.0 * m * k;
        const double rate = discriminant > 0.0 ? (d - std::sqrt(discriminant)) / (2.0 * m) : d / (2.0 * m);
        slowest = std::min(slowest, rate);
    }
    const double periods = std::ceil(20.0 / slowest / options.duration);
    return static_cast<coopdyn::Index>(periods) * steps;
}

/// The sensors of one logged run: the wrench passes the low-pass, then noise is added to wrench
/// and pose, from its own noise realisation (`noise_seed`).
inline void apply_sensors(const SensorOptions& sensors, double dt, unsigned long long noise_seed, ExperimentLog& log)
{
    log.measured_wrench = log.applied;
    log.measured_displacement = log.displacement;
    if (!sensors.enabled) {
        return;
    }
    std::mt19937_64 random(noise_seed);
    std::normal_distribution<double> normal(0.0, 1.0);
    for (coopdyn::Index axis = 0; axis < 6; ++axis) {
        lowpass_in_place(log.measured_wrench.row(axis), sensors.lowpass_hz, dt);
        const double wrench_rms = axis < 3 ? sensors.force_rms : sensors.torque_rms;
        const double pose_rms = axis < 3 ? sensors.position_rms : sensors.angle_rms;
        for (coopdyn::Index k = 0; k < log.samples(); ++k) {
            log.measured_wrench(axis, k) += wrench_rms * normal(random);
            log.measured_displacement(axis, k) += pose_rms * normal(random);
        }
    }
}

/// What every run of one experiment shares: the model and its equilibrium, the controller's
/// setpoints and load distribution, the disturbance, the step counts and the progress display.
template <typename ModelType> struct RunSetting {
    using SetpointsType = coopdyn::Setpoints<double, ModelType::arms_at_compile_time>;
    using DisturbancesType = coopdyn::Disturbances<double, ModelType::arms_at_compile_time>;
    const ModelType& model;
    const coopdyn::RigidBodyState<double>& initial;
    const SetpointsType& setpoints_at_equilibrium;  ///< the end-effector poses at the equilibrium
    const coopdyn::LoadDistribution<ModelType>& distribution;
    const coopdyn::Vector6<double>& gravity_wrench;  ///< h_g
    const Excitation& excitation;
    const Scenario& scenario;
    const RunOptions& options;
    double dt;
    coopdyn::Index steps, warmup_steps;
    double warmup_time;
    std::string label;
    Progress& progress;
};

/// One run with the disturbance sign * u(t), logged into `log`, then the sensor model with its
/// own noise realisation (`noise_seed`): the runs' noises are independent.
template <typename ModelType>
void simulate_run(const RunSetting<ModelType>& setting, double sign, int run, ExperimentLog& log,
                  unsigned long long noise_seed)
{
    using namespace coopdyn;
    using SetpointsType = typename RunSetting<ModelType>::SetpointsType;
    using DisturbancesType = typename RunSetting<ModelType>::DisturbancesType;
    const ModelType& model = setting.model;
    const Eigen::Vector3d p_eq = setting.scenario.equilibrium.position;
    const Eigen::Quaterniond q_eq_inverse = setting.scenario.equilibrium.orientation.conjugate();
    Simulator<ModelType> simulator(model, setting.dt, setting.initial, Integrator::runge_kutta_4);
    for (Index i = 0; i < model.arms(); ++i) {
        simulator.setpoints().set_pose(i, setting.setpoints_at_equilibrium.pose(i));
    }
    Data<ModelType> tick(model);
    // The load distribution is a digital controller: it runs once per 1 ms tick, on the state
    // the step starts from, and its output is held through the step (a zero-order hold). The
    // excitation is a continuous input, sampled at every integrator stage. The first call of
    // a step is the tick (steps() counts the steps taken, so it changes once per step).
    Index distributed_at_step = -1;
    const auto inputs = [&](double time, SetpointsType& setpoints, DisturbancesType& disturbances) {
        if (simulator.steps() != distributed_at_step) {
            distributed_at_step = simulator.steps();
            grasp_kinematics(model, tick, simulator.state());
            setting.distribution.distribute(tick, setting.gravity_wrench, setpoints);
        }
        disturbances.object = sign * setting.excitation(time);
    };

    log.resize(setting.steps, model.arms());
    WrenchDecomposition<ModelType> decomposition(model);
    Index n = 0;
    const auto observer = [&](double time, const RigidBodyState<double>& state, const Data<ModelType>& data) {
        log.time(n) = time - setting.warmup_time;
        log.applied.col(n) = sign * setting.excitation(time);
        log.pose.col(n).template head<3>() = state.pose.position;
        log.pose.col(n).template tail<4>() = state.pose.orientation.coeffs();
        log.twist.col(n) = state.twist;
        log.displacement.col(n).template head<3>() = state.pose.position - p_eq;
        log.displacement.col(n).template tail<3>() = rotation_vector(state.pose.orientation * q_eq_inverse);
        decompose_wrenches(model, data, decomposition);
        for (Index i = 0; i < model.arms(); ++i) {
            log.arm_wrenches.col(n).template segment<6>(18 * i) = data.end_effector_wrench(i);
            log.arm_wrenches.col(n).template segment<6>(18 * i + 6) = decomposition.internal_wrench(i);
            log.arm_wrenches.col(n).template segment<6>(18 * i + 12) = decomposition.external_wrench(i);
        }
        ++n;
    };

    const Index total = setting.options.runs * (setting.warmup_steps + setting.steps);
    const Index before = run * (setting.warmup_steps + setting.steps);
    for (Index done = 0; done < setting.warmup_steps;) {
        const Index chunk = std::min<Index>(1000, setting.warmup_steps - done);
        simulator.run(chunk, inputs, [](double, const RigidBodyState<double>&, const Data<ModelType>&) {});
        done += chunk;
        setting.progress.update(setting.label, static_cast<double>(before + done) / static_cast<double>(total));
    }
    for (Index done = 0; done < setting.steps;) {
        const Index chunk = std::min<Index>(1000, setting.steps - done);
        simulator.run(chunk, inputs, observer);
        done += chunk;
        setting.progress.update(setting.label,
                                static_cast<double>(before + setting.warmup_steps + done) / static_cast<double>(total));
    }
    apply_sensors(setting.options.sensors, setting.dt, noise_seed, log);
}

/// The logged (+u) run into `log`, and the signals the identification uses: paired excitation
/// and amplitude extrapolation. The response of the (smooth, time-invariant) cooperative system to
/// the disturbance s u(t) expands in Volterra terms
///     y(s u) = s y1 + s^2 y2 + s^3 y3 + s^4 y4 + s^5 y5 + ...,
/// y1 the response of the linearisation (52) that the identification fits. The even-order terms
/// (gyroscopic torques, the rotation-vector kinematics, the springs' geometry, all quadratic in
/// the motion) do not change sign with s, so the odd part
///     z(s) = (y(+s u) - y(-s u)) / 2 = s y1 + s^3 y3 + s^5 y5 + ...
/// is free of every even-order distortion, exactly. The third-order terms (sin theta of the
/// springs, products of three rotations) remain and make the best linear fit depend on the
/// amplitude, in proportion to s^2; Richardson extrapolation over the amplitudes 1 and 2,
///     (4 z(1) - z(2) / 2) / 3 = y1 - 4 y5 + ...,
/// removes them too. The identification uses this combination of the measured signals (wrench
/// and displacement, each as measured in its run: noise and low-pass included, the low-pass is
/// linear). Runs: 4 = +u, -u, +2u, -2u (default); 2 = +u, -u, the odd part z(1); 1 = +u only. The
/// combination's noise gain (RMS, against one run's noise) is sqrt(2 (2/3)^2 + 2 (1/12)^2) = 0.95
/// with 4 runs, sqrt(1/2) with 2.
template <typename ModelType>
void simulate_runs(const RunSetting<ModelType>& setting, unsigned long long noise_seed, ExperimentLog& log)
{
    simulate_run(setting, 1.0, 0, log, noise_seed);
    log.identification_wrench = log.measured_wrench;
    log.identification_displacement = log.measured_displacement;
    if (setting.options.runs <= 1) {
        return;
    }
    // Independent noise realisations per run.
    const auto combine = [&](double sign, int run, double weight) {
        ExperimentLog other;
        simulate_run(setting, sign, run, other, noise_seed ^ (0x9E3779B97F4A7C15ULL * static_cast<unsigned long long>(run)));
        log.identification_wrench += weight * other.measured_wrench;
        log.identification_displacement += weight * other.measured_displacement;
    };
    if (setting.options.runs == 2) {
        combine(-1.0, 1, -1.0);  // z(1) = (y(+u) - y(-u)) / 2
        log.identification_wrench *= 0.5;
        log.identification_displacement *= 0.5;
    } else {
        // (4 z(1) - z(2) / 2) / 3 = (2/3) (y(+u) - y(-u)) - (1/12) (y(+2u) - y(-2u))
        combine(-1.0, 1, -1.0);
        log.identification_wrench *= 2.0 / 3.0;
        log.identification_displacement *= 2.0 / 3.0;
        combine(2.0, 2, -1.0 / 12.0);
        combine(-2.0, 3, 1.0 / 12.0);
    }
}

/// Cross-axis motion (single-axis experiments): RMS of the other axes' displacement over the
/// excited axis's, each translation scaled by K_ii so forces and torques compare. NaN otherwise.
inline double cross_axis_motion(const ExperimentResult& result)
{
    const std::array<bool, 6>& axes = result.spec.axes;
    if (std::count(axes.begin(), axes.end(), true) != 1) {
        return std::numeric_limits<double>::quiet_NaN();
    }
    double own = 0.0, other = 0.0;
    for (coopdyn::Index axis = 0; axis < 6; ++axis) {
        const double energy = result.nominal.stiffness(axis, axis) * result.log.displacement.row(axis).squaredNorm();
        (axes[static_cast<std::size_t>(axis)] ? own : other) += energy;
    }
    return std::sqrt(other / own);
}

/// Identification from the logged (measured) force and pose alone: the combination of the runs
/// (or the single run). The model's prediction is driven by the logged (+u) run's measured wrench,
/// for comparison with its measured displacement.
inline void identify(double dt, ExperimentResult& result)
{
    ExperimentLog& log = result.log;
    result.fit = coopdyn::identify_diagonal_impedance(log.identification_displacement, log.identification_wrench, dt,
                                                      coopdyn::IdentificationOptions{}, result.spec.axes);
    for (coopdyn::Index axis = 0; axis < 6; ++axis) {
        const auto index = static_cast<std::size_t>(axis);
        if (!result.fit.identified[index]) {
            continue;
        }
        const coopdyn::ImpedanceFit& fit = result.fit.axes[index];
        log.model_displacement.row(axis) = coopdyn::simulate_impedance(fit.parameters(), fit.initial_position,
                                                                       fit.initial_velocity, log.measured_wrench.row(axis), dt)
                                               .transpose();
    }
}

/// Runs one experiment on `model` (built from `scenario`): simulation, sensor model,
/// identification from the logged (measured) wrench and displacement, and the identified
/// model's predicted displacement. Throws coopdyn::InvalidArgument if the identification fails.
template <typename ModelType>
ExperimentResult run_experiment(const Scenario& scenario, const ModelType& model, const ExperimentSpec& spec,
                                const RunOptions& options, Progress& progress, unsigned long long seed_offset)
{
    using namespace coopdyn;
    using Clock = std::chrono::steady_clock;
    const double dt = scenario.time_step;
    const auto steps = static_cast<Index>(std::llround(options.duration / dt));
    RigidBodyState<double> initial;
    initial.pose = scenario.equilibrium;

    // Setpoints at the grasp poses of the equilibrium (38), and Theorem 2's impedance there.
    ExperimentResult result;
    Data<ModelType> controller(model);
    grasp_kinematics(model, controller, initial);
    start_result(scenario, model, spec, options, controller, result);
    const Excitation excitation(options.excitation, spec.axes, result.amplitudes, static_cast<double>(steps) * dt,
                                options.seed * 1000003ULL + seed_offset);
    const Index warmup = warmup_steps(result.nominal, options, steps);
    const double warmup_time = static_cast<double>(warmup) * dt;

    // Setpoints: the end-effector poses at the equilibrium, held constant in every run.
    typename RunSetting<ModelType>::SetpointsType setpoints_at_equilibrium(model.arms());
    for (Index i = 0; i < model.arms(); ++i) {
        setpoints_at_equilibrium.set_pose(i, controller.end_effector_pose(i));
    }
    const LoadDistribution<ModelType> distribution =
        scenario.has_custom_weights()
            ? LoadDistribution<ModelType>(model, typename LoadDistribution<ModelType>::MassWeights(scenario.mass_weights),
                                          typename LoadDistribution<ModelType>::InertiaWeights(scenario.inertia_weights))
            : LoadDistribution<ModelType>(model);
    const Vector6<double> gravity_wrench = model.object().gravity_wrench(model.gravity());  // h_g
    const RunSetting<ModelType> setting{model,     initial,  setpoints_at_equilibrium, distribution, gravity_wrench,
                                        excitation, scenario, options, dt, steps, warmup, warmup_time,
                                        "simulating " + spec.title, progress};

    const auto simulation_start = Clock::now();
    simulate_runs(setting, options.seed * 7919ULL + seed_offset + 17ULL, result.log);
    result.runs = options.runs;
    result.simulation_seconds = std::chrono::duration<double>(Clock::now() - simulation_start).count();
    result.simulated_seconds = static_cast<double>(options.runs * (warmup + steps)) * dt;
    result.warmup_seconds = warmup_time;
    result.cross_axis_motion = cross_axis_motion(result);

    progress.update("identifying " + spec.title, 1.0);
    const auto identification_start = Clock::now();
    identify(dt, result);
    result.identification_seconds = std::chrono::duration<double>(Clock::now() - identification_start).count();
    progress.finish();
    return result;
}

}  // namespace beam_example
