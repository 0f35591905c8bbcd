// The experiments of the two-arm beam example (paper Section V, docs/analysis.md): excitation
// signals, the sensor model, the simulation with its 1 kHz log, and the grey-box identification
// of the apparent impedance from the logged wrench and pose alone.
//
// Physics (Theorem 2's assumptions): the arms hold constant setpoints at the grasp poses of the
// object's equilibrium, and the object's weight is carried through the desired wrenches, h_o^d =
// h_g distributed by the non-squeezing load distribution (26) at every 1 ms controller tick from
// the pose at that tick. A disturbance wrench htilde_o (a multisine or human-like pushes) acts on
// the object. The simulation is coopdyn's Simulator (full model of docs/dynamics.md, RK4).
#pragma once

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

inline constexpr double pi = 3.14159265358979323846;

/// Axis names in the order of twists and wrenches.
inline const std::array<const char*, 6> axis_names{"x", "y", "z", "rot x", "rot y", "rot z"};

/// One of the paper's three experiments.
struct ExperimentSpec {
    std::string id;     ///< "x", "rot_z", "se3" (command line and file names)
    std::string title;  ///< for the tables and plots
    std::array<bool, 6> axes{};  ///< excited and identified axes
    std::string paper_nominal_equation;     ///< the paper's nominal values, e.g. "(56)"
    std::string paper_identified_equation;  ///< identified on the real robots, e.g. "(57)"
};

inline const std::vector<ExperimentSpec>& experiment_specs()
{
    static const std::vector<ExperimentSpec> specs{
        {"x", "translation along x", {true, false, false, false, false, false}, "(56)", "(57)"},
        {"rot_z", "rotation about z", {false, false, false, false, false, true}, "(59)", "(60)"},
        {"se3", "full SE(3)", {true, true, true, true, true, true}, "(61)", "(62)"},
    };
    return specs;
}

enum class ExcitationKind { multisine, push };

/// Sensor model: white noise on the logged wrench and pose, and the paper's first-order
/// low-pass on the force/torque signal.
struct SensorOptions {
    bool enabled = false;
    double force_rms = 0.1;       ///< N
    double torque_rms = 0.01;     ///< N m
    double position_rms = 1e-4;   ///< m
    double angle_rms = 1e-3;      ///< rad
    double lowpass_hz = 500.0;    ///< cut-off of the wrench low-pass; 0 = none
};

struct RunOptions {
    double duration = 20.0;  ///< s per experiment
    ExcitationKind excitation = ExcitationKind::multisine;
    double force = 0.0;   ///< N (0 = the scenario's default)
    double torque = 0.0;  ///< N m (0 = the scenario's default)
    unsigned long long seed = 1;
    SensorOptions sensors;
    /// Excitation runs per experiment, combined into the signals the identification uses
    /// (see run_experiment): 4 (default) = +u, -u, +2u, -2u: odd parts, extrapolated to zero
    /// amplitude; 2 = +u, -u: odd part; 1 = one run (--single-run).
    int runs = 4;
    bool progress = true;
};

// ---------------------------------------------------------------------------------------------
// Excitation

/// Disturbance wrench on the object, independent per axis: a random-phase multisine or a
/// sequence of human-like pushes. Deterministic for a given seed.
class Excitation {
public:
    /// \param amplitudes per axis: RMS of the multisine, or the largest peak of the pushes (N, N m).
    Excitation(ExcitationKind kind, const std::array<bool, 6>& axes, const std::array<double, 6>& amplitudes,
               double duration, unsigned long long seed)
        : kind_(kind)
    {
        std::mt19937_64 random(seed);
        std::uniform_real_distribution<double> unit(0.0, 1.0);
        for (std::size_t axis = 0; axis < 6; ++axis) {
            if (!axes[axis]) {
                continue;
            }
            const double amplitude = amplitudes[axis];
            Channel channel;
            channel.axis = axis;
            if (kind == ExcitationKind::multisine) {
                // Up to 11 lines between f_lo and 5 Hz (the band of the arms' dynamics and of a
                // human's hand), log-spaced, each on an odd harmonic of f0 = 1 / duration: the
                // record holds whole periods, and products of two lines (the second-order
                // nonlinearities of the rotational dynamics: gyroscopic terms, the geometry of
                // the springs) fall on even harmonics, which are orthogonal to the excitation, so
                // they do not bias the fit. The axes' log grids are shifted against each other.
                // Random phases; RMS = amplitude.
                constexpr int targets = 11;
                const double fundamental = 1.0 / duration;
                const double low = std::max(0.1, fundamental);
                const double high = 5.0;
                const double ratio = std::pow(high / low, 1.0 / (targets - 1));
                const double shift = std::pow(ratio, static_cast<double>(axis) / 6.0 - 0.5);
                std::vector<long long> harmonics;
                for (int k = 0; k < targets; ++k) {
                    const double frequency = std::clamp(low * std::pow(ratio, k) * shift, low, high);
                    long long harmonic = 2 * std::llround((frequency / fundamental - 1.0) / 2.0) + 1;
                    harmonic = std::max(harmonic, 1LL);
                    if (std::find(harmonics.begin(), harmonics.end(), harmonic) == harmonics.end()) {
                        harmonics.push_back(harmonic);
                    }
                }
                const double line_amplitude = amplitude * std::sqrt(2.0 / static_cast<double>(harmonics.size()));
                for (const long long harmonic : harmonics) {
                    const double frequency = static_cast<double>(harmonic) * fundamental;
                    channel.lines.push_back({2.0 * pi * frequency, 2.0 * pi * unit(random), line_amplitude});
                }
            } else {
                // Pushes: raised-cosine ramp up (0.15-0.4 s), hold (0-1 s), ramp down, pause
                // (0.3-1.2 s); peak 40-100 % of the amplitude, either direction.
                double t = 0.2 + 0.5 * unit(random);
                while (true) {
                    Push push;
                    push.start = t;
                    push.ramp = 0.15 + 0.25 * unit(random);
                    push.hold = 1.0 * unit(random);
                    push.peak = amplitude * (0.4 + 0.6 * unit(random)) * (unit(random) < 0.5 ? -1.0 : 1.0);
                    const double end = push.start + 2.0 * push.ramp + push.hold;
                    if (end > duration - 0.2) {
                        break;
                    }
                    channel.pushes.push_back(push);
                    t = end + 0.3 + 0.9 * unit(random);
                }
            }
            channels_.push_back(channel);
        }
    }

    /// htilde_o(t), [f; t] in {w}.
    coopdyn::Vector6<double> operator()(double time) const noexcept
    {
        coopdyn::Vector6<double> wrench = coopdyn::Vector6<double>::Zero();
        for (const Channel& channel : channels_) {
            double value = 0.0;
            if (kind_ == ExcitationKind::multisine) {
                for (const Line& line : channel.lines) {
                    value += line.amplitude * std::sin(line.omega * time + line.phase);
                }
            } else {
                for (const Push& push : channel.pushes) {
                    value += push(time);
                }
            }
            wrench(static_cast<Eigen::Index>(channel.axis)) = value;
        }
        return wrench;
    }

private:
    struct Line {
        double omega, phase, amplitude;
    };
    struct Push {
        double start = 0, ramp = 0, hold = 0, peak = 0;
        double operator()(double time) const noexcept
        {
            const double s = time - start;
            if (s <= 0.0 || s >= 2.0 * ramp + hold) {
                return 0.0;
            }
            if (s < ramp) {
                return peak * 0.5 * (1.0 - std::cos(pi * s / ramp));
            }
            if (s > ramp + hold) {
                return peak * 0.5 * (1.0 - std::cos(pi * (2.0 * ramp + hold - s) / ramp));
            }
            return peak;
        }
    };
    struct Channel {
        std::size_t axis = 0;
        std::vector<Line> lines;
        std::vector<Push> pushes;
    };

    ExcitationKind kind_;
    std::vector<Channel> channels_;
};

// ---------------------------------------------------------------------------------------------
// Sensor model

/// First-order low-pass y' = (u - y) / tau, tau = 1 / (2 pi f_c), discretised exactly for an
/// input that is linear between samples (first-order hold):
///     y[n] = a y[n-1] + b1 u[n-1] + b0 u[n],   a = exp(-T/tau),
///     b0 = 1 - (1 - a) tau / T,   b1 = (1 - a) tau / T - a   (a + b0 + b1 = 1, unit DC gain).
/// With f_c = 500 Hz and T = 1 ms: a = exp(-pi) = 0.0432, b0 = 0.6955, b1 = 0.2613. Starts at
/// rest at the first input sample.
inline void lowpass_in_place(Eigen::Ref<Eigen::RowVectorXd, 0, Eigen::InnerStride<>> signal, double cutoff_hz, double sample_period)
{
    if (cutoff_hz <= 0.0 || signal.size() == 0) {
        return;
    }
    const double tau = 1.0 / (2.0 * pi * cutoff_hz);
    const double a = std::exp(-sample_period / tau);
    const double ratio = (1.0 - a) * tau / sample_period;
    const double b0 = 1.0 - ratio;
    const double b1 = ratio - a;
    double previous_input = signal(0);
    double output = signal(0);
    for (Eigen::Index n = 1; n < signal.size(); ++n) {
        const double input = signal(n);
        output = a * output + b1 * previous_input + b0 * input;
        previous_input = input;
        signal(n) = output;
    }
}

// ---------------------------------------------------------------------------------------------
// Simulation log

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

/// Runs one experiment on `model` (built from `scenario`): simulation, sensor model,
/// identification from the logged (measured) wrench and displacement, and the identified
/// model's predicted displacement. Throws coopdyn::InvalidArgument if the identification fails.
template <typename ModelType>
ExperimentResult run_experiment(const Scenario& scenario, const ModelType& model, const ExperimentSpec& spec,
                                const RunOptions& options, Progress& progress, unsigned long long seed_offset)
{
    using namespace coopdyn;
    using Clock = std::chrono::steady_clock;
    ExperimentResult result;
    result.spec = spec;
    result.excitation_force = options.force > 0.0 ? options.force : scenario.excitation.force;
    result.excitation_torque = options.torque > 0.0 ? options.torque : scenario.excitation.torque;

    const double dt = scenario.time_step;
    const auto steps = static_cast<Index>(std::llround(options.duration / dt));
    RigidBodyState<double> initial;
    initial.pose = scenario.equilibrium;

    // Setpoints at the grasp poses of the equilibrium (38), and Theorem 2's impedance there.
    Data<ModelType> controller(model);
    grasp_kinematics(model, controller, initial);
    result.nominal = apparent_impedance(model, controller);
    result.nominal_coupling = std::max({coupling(result.nominal.inertia), coupling(result.nominal.damping),
                                        coupling(result.nominal.stiffness)});

    // Amplitudes: --force on every excited translation, --torque on every excited rotation.
    std::array<double, 6> amplitudes{};
    for (std::size_t axis = 0; axis < 6; ++axis) {
        amplitudes[axis] = axis < 3 ? result.excitation_force : result.excitation_torque;
    }
    result.amplitudes = amplitudes;
    const Excitation excitation(options.excitation, spec.axes, amplitudes, static_cast<double>(steps) * dt,
                                options.seed * 1000003ULL + seed_offset);

    // A multisine is logged in periodic steady state: whole periods are simulated first, until
    // the slowest mode of the linearised dynamics has decayed by e^-20 (its rate from the
    // diagonal of Theorem 2's M, D, K at the equilibrium). Pushes start at rest.
    Index warmup_steps = 0;
    double warmup_time = 0.0;
    if (options.excitation == ExcitationKind::multisine) {
        double slowest = std::numeric_limits<double>::infinity();  // decay rate, 1/s
        for (Index axis = 0; axis < 6; ++axis) {
            const double m = result.nominal.inertia(axis, axis);
            const double d = result.nominal.damping(axis, axis);
            const double k = result.nominal.stiffness(axis, axis);
            const double discriminant = d * d - 4.0 * m * k;
            const double rate = discriminant > 0.0 ? (d - std::sqrt(discriminant)) / (2.0 * m) : d / (2.0 * m);
            slowest = std::min(slowest, rate);
        }
        const double periods = std::ceil(20.0 / slowest / options.duration);
        warmup_steps = static_cast<Index>(periods) * steps;
        warmup_time = static_cast<double>(warmup_steps) * dt;
    }

    using SetpointsType = Setpoints<double, ModelType::arms_at_compile_time>;
    using DisturbancesType = Disturbances<double, ModelType::arms_at_compile_time>;
    // Setpoints: the end-effector poses at the equilibrium, held constant in every run.
    SetpointsType setpoints_at_equilibrium(model.arms());
    for (Index i = 0; i < model.arms(); ++i) {
        setpoints_at_equilibrium.set_pose(i, controller.end_effector_pose(i));
    }
    const LoadDistribution<ModelType> distribution =
        scenario.has_custom_weights()
            ? LoadDistribution<ModelType>(model, typename LoadDistribution<ModelType>::MassWeights(scenario.mass_weights),
                                          typename LoadDistribution<ModelType>::InertiaWeights(scenario.inertia_weights))
            : LoadDistribution<ModelType>(model);
    const Vector6<double> gravity_wrench = model.object().gravity_wrench(model.gravity());  // h_g
    const Eigen::Vector3d p_eq = scenario.equilibrium.position;
    const Eigen::Quaterniond q_eq_inverse = scenario.equilibrium.orientation.conjugate();
    const std::string label = "simulating " + spec.title;
    const int runs = options.runs;

    // One run with the disturbance sign * u(t), logged into `log`, then the sensor model with
    // its own noise realisation (`noise_seed`): the runs' noises are independent.
    const auto simulate = [&](double sign, int run, ExperimentLog& log, unsigned long long noise_seed) {
        Simulator<ModelType> simulator(model, dt, initial, Integrator::runge_kutta_4);
        for (Index i = 0; i < model.arms(); ++i) {
            simulator.setpoints().set_pose(i, setpoints_at_equilibrium.pose(i));
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
                distribution.distribute(tick, gravity_wrench, setpoints);
            }
            disturbances.object = sign * excitation(time);
        };

        log.resize(steps, model.arms());
        WrenchDecomposition<ModelType> decomposition(model);
        Index n = 0;
        const auto observer = [&](double time, const RigidBodyState<double>& state, const Data<ModelType>& data) {
            log.time(n) = time - warmup_time;
            log.applied.col(n) = sign * excitation(time);
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

        const Index total = runs * (warmup_steps + steps);
        const Index before = run * (warmup_steps + steps);
        for (Index done = 0; done < warmup_steps;) {
            const Index chunk = std::min<Index>(1000, warmup_steps - done);
            simulator.run(chunk, inputs, [](double, const RigidBodyState<double>&, const Data<ModelType>&) {});
            done += chunk;
            progress.update(label, static_cast<double>(before + done) / static_cast<double>(total));
        }
        for (Index done = 0; done < steps;) {
            const Index chunk = std::min<Index>(1000, steps - done);
            simulator.run(chunk, inputs, observer);
            done += chunk;
            progress.update(label, static_cast<double>(before + warmup_steps + done) / static_cast<double>(total));
        }

        // Sensors: the wrench passes the low-pass, then noise is added to wrench and pose.
        log.measured_wrench = log.applied;
        log.measured_displacement = log.displacement;
        if (options.sensors.enabled) {
            std::mt19937_64 random(noise_seed);
            std::normal_distribution<double> normal(0.0, 1.0);
            for (Index axis = 0; axis < 6; ++axis) {
                lowpass_in_place(log.measured_wrench.row(axis), options.sensors.lowpass_hz, dt);
                const double wrench_rms = axis < 3 ? options.sensors.force_rms : options.sensors.torque_rms;
                const double pose_rms = axis < 3 ? options.sensors.position_rms : options.sensors.angle_rms;
                for (Index k = 0; k < steps; ++k) {
                    log.measured_wrench(axis, k) += wrench_rms * normal(random);
                    log.measured_displacement(axis, k) += pose_rms * normal(random);
                }
            }
        }
    };

    // Paired excitation and amplitude extrapolation. The response of the (smooth,
    // time-invariant) cooperative system to the disturbance s u(t) expands in Volterra terms
    //     y(s u) = s y1 + s^2 y2 + s^3 y3 + s^4 y4 + s^5 y5 + ...,
    // y1 the response of the linearisation (52) that the identification fits. The even-order
    // terms (gyroscopic torques, the rotation-vector kinematics, the springs' geometry, all
    // quadratic in the motion) do not change sign with s, so the odd part
    //     z(s) = (y(+s u) - y(-s u)) / 2 = s y1 + s^3 y3 + s^5 y5 + ...
    // is free of every even-order distortion, exactly. The third-order terms (sin theta of the
    // springs, products of three rotations) remain and make the best linear fit depend on the
    // amplitude, in proportion to s^2; Richardson extrapolation over the amplitudes 1 and 2,
    //     (4 z(1) - z(2) / 2) / 3 = y1 - 4 y5 + ...,
    // removes them too. The identification uses this combination of the measured signals
    // (wrench and displacement, each as measured in its run: noise and low-pass included, the
    // low-pass is linear). Runs: 4 = +u, -u, +2u, -2u (default); 2 = +u, -u, the odd part z(1);
    // 1 = +u only. The logged run is +u. The combination's noise gain (RMS, against one run's
    // noise) is sqrt(2 (2/3)^2 + 2 (1/12)^2) = 0.95 with 4 runs, sqrt(1/2) with 2.
    ExperimentLog& log = result.log;
    const unsigned long long noise_seed = options.seed * 7919ULL + seed_offset + 17ULL;
    const auto simulation_start = Clock::now();
    simulate(1.0, 0, log, noise_seed);
    log.identification_wrench = log.measured_wrench;
    log.identification_displacement = log.measured_displacement;
    if (options.runs > 1) {
        // Independent noise realisations per run.
        const auto combine = [&](double sign, int run, double weight) {
            ExperimentLog other;
            simulate(sign, run, other, noise_seed ^ (0x9E3779B97F4A7C15ULL * static_cast<unsigned long long>(run)));
            log.identification_wrench += weight * other.measured_wrench;
            log.identification_displacement += weight * other.measured_displacement;
        };
        if (options.runs == 2) {
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
    result.runs = runs;
    result.simulation_seconds = std::chrono::duration<double>(Clock::now() - simulation_start).count();
    result.simulated_seconds = static_cast<double>(runs * (warmup_steps + steps)) * dt;
    result.warmup_seconds = warmup_time;

    // Cross-axis motion (single-axis experiments): RMS of the other axes' displacement over the
    // excited axis's, each translation scaled by K_ii so forces and torques compare.
    const int excited = static_cast<int>(std::count(spec.axes.begin(), spec.axes.end(), true));
    if (excited == 1) {
        double own = 0.0, other = 0.0;
        for (Index axis = 0; axis < 6; ++axis) {
            const double energy = result.nominal.stiffness(axis, axis) * log.displacement.row(axis).squaredNorm();
            (spec.axes[static_cast<std::size_t>(axis)] ? own : other) += energy;
        }
        result.cross_axis_motion = std::sqrt(other / own);
    }

    // Identification from the logged (measured) force and pose alone: the combination of the
    // runs (or the single run). The model's prediction is driven by the logged (+u) run's
    // measured wrench, for comparison with its measured displacement.
    progress.update("identifying " + spec.title, 1.0);
    const auto identification_start = Clock::now();
    result.fit = identify_diagonal_impedance(log.identification_displacement, log.identification_wrench, dt,
                                             IdentificationOptions{}, spec.axes);
    for (Index axis = 0; axis < 6; ++axis) {
        const auto index = static_cast<std::size_t>(axis);
        if (!result.fit.identified[index]) {
            continue;
        }
        const ImpedanceFit& fit = result.fit.axes[index];
        log.model_displacement.row(axis) = simulate_impedance(fit.parameters(), fit.initial_position,
                                                              fit.initial_velocity, log.measured_wrench.row(axis), dt)
                                               .transpose();
    }
    result.identification_seconds = std::chrono::duration<double>(Clock::now() - identification_start).count();
    progress.finish();
    return result;
}

}  // namespace beam_example
