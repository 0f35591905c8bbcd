// The two-arm beam example's experiments as data and signals (paper Section V, docs/two-arm-beam.md):
// the three experiments, the run and sensor options, the disturbance wrench (a random-phase
// multisine or human-like pushes) and the force/torque sensor's low-pass. beam_experiment.hpp
// runs them.
#pragma once

#include <coopdyn/config.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
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

}  // namespace beam_example
