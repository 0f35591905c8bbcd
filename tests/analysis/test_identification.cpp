// Tests of coopdyn/analysis/identification.hpp: grey-box identification of m pdd + d pd + k p = f.
//
// References are closed-form solutions of the damped linear oscillator, computed here with complex
// arithmetic and never with the header's discretisation:
// - multisine force: steady state sum Im(a_j H(i w_j) e^{i(w_j t + phi_j)}) plus the free response
//   C1 e^{s1 t} + C2 e^{s2 t} that matches the initial state;
// - piecewise-constant force: superposition of closed-form step responses;
// - piecewise-linear force: superposition of closed-form ramp responses.
#include "coopdyn/analysis/identification.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace {

using coopdyn::ForceInterpolation;
using coopdyn::IdentificationOptions;
using coopdyn::ImpedanceFit;
using coopdyn::ImpedanceParameters;
using Complex = std::complex<double>;

constexpr double kPi = 3.14159265358979323846;
constexpr double kPeriod = 1e-3;          // 1 kHz logging, as in the paper
constexpr Eigen::Index kSamples = 20001;  // 20 s

// ---------------------------------------------------------------------------------------------
// Closed-form reference solutions.

// Closed forms need distinct roots: not critically damped (d^2 != 4 m k).
struct Oscillator {
    double m, d, k;
    Complex s1() const { return (-d + std::sqrt(Complex(d * d - 4.0 * m * k))) / (2.0 * m); }
    Complex s2() const { return (-d - std::sqrt(Complex(d * d - 4.0 * m * k))) / (2.0 * m); }
    // Free response from (x0, v0): C1 e^{s1 t} + C2 e^{s2 t}.
    double free_response(double x0, double v0, double t) const
    {
        const Complex a = s1(), b = s2();
        const Complex c1 = (v0 - b * x0) / (a - b);
        const Complex c2 = x0 - c1;
        return (c1 * std::exp(a * t) + c2 * std::exp(b * t)).real();
    }
    // Response to a unit force step applied at t = 0, from rest.
    double step_response(double t) const
    {
        const Complex a = s1(), b = s2();
        const Complex c1 = b / (k * (a - b));
        const Complex c2 = -a / (k * (a - b));
        return 1.0 / k + (c1 * std::exp(a * t) + c2 * std::exp(b * t)).real();
    }
    // Response to a unit-slope force ramp starting at t = 0, from rest (integral of the step).
    double ramp_response(double t) const
    {
        const Complex a = s1(), b = s2();
        const Complex c1 = b / (k * (a - b));
        const Complex c2 = -a / (k * (a - b));
        return t / k + (c1 * (std::exp(a * t) - 1.0) / a + c2 * (std::exp(b * t) - 1.0) / b).real();
    }
};

struct Multisine {
    std::vector<double> amplitude;
    std::vector<double> omega;
    std::vector<double> phase;
    double operator()(double t) const
    {
        double sum = 0.0;
        for (std::size_t j = 0; j < omega.size(); ++j) {
            sum += amplitude[j] * std::sin(omega[j] * t + phase[j]);
        }
        return sum;
    }
};

// Multisine with components between 0.1 and 5 Hz, equal amplitudes and Schroeder phases
// (low crest factor), shifted in phase by `shift` to make different channels independent.
Multisine multisine(double amplitude, double shift = 0.0)
{
    const std::array<double, 11> frequencies{0.1, 0.2, 0.3, 0.5, 0.7, 1.0, 1.5, 2.0, 3.0, 4.0, 5.0};
    Multisine result;
    const double count = static_cast<double>(frequencies.size());
    for (std::size_t j = 0; j < frequencies.size(); ++j) {
        const double index = static_cast<double>(j + 1);
        result.amplitude.push_back(amplitude);
        result.omega.push_back(2.0 * kPi * frequencies[j]);
        result.phase.push_back(-kPi * index * (index - 1.0) / count + shift * index);
    }
    return result;
}

struct Record {
    Eigen::VectorXd position;
    Eigen::VectorXd force;
};

// Exact samples of the response to a multisine from the initial state (x0, v0).
Record multisine_record(const Oscillator& system, const Multisine& input, double x0 = 0.0, double v0 = 0.0,
                        Eigen::Index samples = kSamples)
{
    // Steady state: complex amplitudes a_j H(i w_j) e^{i phi_j}.
    std::vector<Complex> response(input.omega.size());
    double steady_position = 0.0, steady_velocity = 0.0;
    for (std::size_t j = 0; j < input.omega.size(); ++j) {
        const double w = input.omega[j];
        const Complex h = 1.0 / Complex(system.k - system.m * w * w, system.d * w);
        response[j] = input.amplitude[j] * h * std::exp(Complex(0.0, input.phase[j]));
        steady_position += response[j].imag();
        steady_velocity += (Complex(0.0, w) * response[j]).imag();
    }
    Record record{Eigen::VectorXd(samples), Eigen::VectorXd(samples)};
    for (Eigen::Index n = 0; n < samples; ++n) {
        const double t = static_cast<double>(n) * kPeriod;
        double p = system.free_response(x0 - steady_position, v0 - steady_velocity, t);
        for (std::size_t j = 0; j < input.omega.size(); ++j) {
            p += (response[j] * std::exp(Complex(0.0, input.omega[j] * t))).imag();
        }
        record.position(n) = p;
        record.force(n) = input(t);
    }
    return record;
}

// Breakpoints on the sample grid every `spacing` samples with seeded random values in [-amplitude,
// amplitude]; the record is the exact response from rest to the piecewise-constant (held) or the
// piecewise-linear (interpolated) force through them.
Record piecewise_record(const Oscillator& system, bool linear, double amplitude, Eigen::Index spacing,
                        unsigned seed)
{
    std::mt19937 generator(seed);
    std::uniform_real_distribution<double> value(-amplitude, amplitude);
    std::vector<Eigen::Index> breaks;
    std::vector<double> levels;
    for (Eigen::Index n = 0; n < kSamples + spacing; n += spacing) {
        breaks.push_back(n);
        levels.push_back(value(generator));
    }
    // Force changes: steps of the level (held) or of the slope (linear) at each breakpoint.
    std::vector<double> change(breaks.size(), 0.0);
    for (std::size_t j = 0; j < breaks.size(); ++j) {
        if (!linear) {
            change[j] = levels[j] - (j > 0 ? levels[j - 1] : 0.0);
        } else if (j + 1 < breaks.size()) {
            const double slope = (levels[j + 1] - levels[j]) / (static_cast<double>(spacing) * kPeriod);
            const double previous_slope =
                j > 0 ? (levels[j] - levels[j - 1]) / (static_cast<double>(spacing) * kPeriod) : 0.0;
            change[j] = slope - previous_slope;
        }
    }
    Record record{Eigen::VectorXd::Zero(kSamples), Eigen::VectorXd::Zero(kSamples)};
    for (Eigen::Index n = 0; n < kSamples; ++n) {
        const double t = static_cast<double>(n) * kPeriod;
        double p = linear ? levels[0] * system.step_response(t) : 0.0;
        double f = linear ? levels[0] : 0.0;
        for (std::size_t j = 0; j < breaks.size() && breaks[j] <= n; ++j) {
            const double tau = static_cast<double>(n - breaks[j]) * kPeriod;
            if (linear) {
                p += change[j] * system.ramp_response(tau);
                f += change[j] * tau;
            } else {
                p += change[j] * system.step_response(tau);
                f += change[j];
            }
        }
        record.position(n) = p;
        record.force(n) = f;
    }
    return record;
}

void add_noise(Record& record, double position_rms, double force_rms, unsigned seed)
{
    std::mt19937 generator(seed);
    std::normal_distribution<double> normal(0.0, 1.0);
    for (Eigen::Index n = 0; n < record.position.size(); ++n) {
        record.position(n) += position_rms * normal(generator);
        record.force(n) += force_rms * normal(generator);
    }
}

struct Errors {
    double mass, damping, stiffness;
    double largest() const { return std::max({std::abs(mass), std::abs(damping), std::abs(stiffness)}); }
};

Errors relative_errors(const ImpedanceParameters& estimate, const Oscillator& truth)
{
    return {(estimate.mass - truth.m) / truth.m, (estimate.damping - truth.d) / truth.d,
            (estimate.stiffness - truth.k) / truth.k};
}

void report(const char* name, const ImpedanceFit& fit, const Oscillator& truth)
{
    const Errors output = relative_errors(fit.parameters(), truth);
    const Errors equation = relative_errors(fit.equation_error, truth);
    std::printf("[%s] m %.7g d %.7g k %.7g | rel. err. m %+.2e d %+.2e k %+.2e | equation error: %+.2e %+.2e %+.2e"
                " | MSE %.4g (equation-error model %.4g) | %d iterations, converged %d\n",
                name, fit.mass, fit.damping, fit.stiffness, output.mass, output.damping, output.stiffness,
                equation.mass, equation.damping, equation.stiffness, fit.mean_squared_output_error,
                fit.equation_error_mean_squared_output_error, fit.iterations, fit.converged ? 1 : 0);
}

const Oscillator kBeamTranslation{21.75, 360.0, 600.0};  // docs/analysis.md, (56)-(61)
const Oscillator kBeamRotation{4.255, 77.6, 196.0};

// ---------------------------------------------------------------------------------------------
// 1. Exact data: the beam's nominal values to 4 significant digits (relative error < 5e-5).

TEST(Identification, ExactDataRecoversBeamTranslation)
{
    const Record record = multisine_record(kBeamTranslation, multisine(4.0));
    const ImpedanceFit fit = coopdyn::identify_impedance(record.position, record.force, kPeriod);
    report("exact, beam x", fit, kBeamTranslation);
    EXPECT_TRUE(fit.converged);
    EXPECT_LT(relative_errors(fit.parameters(), kBeamTranslation).largest(), 5e-5);
    EXPECT_NEAR(fit.initial_position, 0.0, 1e-8);
    EXPECT_NEAR(fit.initial_velocity, 0.0, 1e-6);
    EXPECT_LT(fit.mean_squared_output_error, 1e-14);
    // The equation-error start is already close (the trapezoidal rule's O((w T)^2) bias).
    EXPECT_LT(relative_errors(fit.equation_error, kBeamTranslation).largest(), 1e-2);
}

TEST(Identification, ExactDataRecoversBeamRotation)
{
    const Record record = multisine_record(kBeamRotation, multisine(1.5, 0.3));
    const ImpedanceFit fit = coopdyn::identify_impedance(record.position, record.force, kPeriod);
    report("exact, beam rot z", fit, kBeamRotation);
    EXPECT_TRUE(fit.converged);
    EXPECT_LT(relative_errors(fit.parameters(), kBeamRotation).largest(), 5e-5);
    EXPECT_LT(fit.mean_squared_output_error, 1e-14);
}

// ---------------------------------------------------------------------------------------------
// 2. Noisy data: within 5 %, output-error MSE close to the position noise variance.

TEST(Identification, NoisyDataTranslation)
{
    Record record = multisine_record(kBeamTranslation, multisine(4.0));
    const double position_rms = 1e-4;  // 0.1 mm
    add_noise(record, position_rms, 0.1, 2024u);
    const ImpedanceFit fit = coopdyn::identify_impedance(record.position, record.force, kPeriod);
    report("noisy, beam x", fit, kBeamTranslation);
    EXPECT_TRUE(fit.converged);
    EXPECT_LT(relative_errors(fit.parameters(), kBeamTranslation).largest(), 0.05);
    const double ratio = fit.mean_squared_output_error / (position_rms * position_rms);
    std::printf("[noisy, beam x] MSE / noise variance = %.4f\n", ratio);
    EXPECT_NEAR(ratio, 1.0, 0.05);
    EXPECT_LE(fit.mean_squared_output_error, fit.equation_error_mean_squared_output_error);
}

TEST(Identification, NoisyDataRotation)
{
    Record record = multisine_record(kBeamRotation, multisine(1.5, 0.3));
    const double angle_rms = 1e-3;  // 1 mrad
    add_noise(record, angle_rms, 0.01, 77u);
    const ImpedanceFit fit = coopdyn::identify_impedance(record.position, record.force, kPeriod);
    report("noisy, beam rot z", fit, kBeamRotation);
    EXPECT_TRUE(fit.converged);
    EXPECT_LT(relative_errors(fit.parameters(), kBeamRotation).largest(), 0.05);
    const double ratio = fit.mean_squared_output_error / (angle_rms * angle_rms);
    std::printf("[noisy, beam rot z] MSE / noise variance = %.4f\n", ratio);
    EXPECT_NEAR(ratio, 1.0, 0.05);
}

TEST(Identification, NoisyDataSeveralSeeds)
{
    // The estimate is unbiased: over several noise realisations the errors scatter around zero.
    double worst = 0.0;
    for (unsigned seed = 1; seed <= 3; ++seed) {
        Record record = multisine_record(kBeamTranslation, multisine(4.0), 0.0, 0.0, 10001);
        add_noise(record, 1e-4, 0.1, seed);
        const ImpedanceFit fit = coopdyn::identify_impedance(record.position, record.force, kPeriod);
        const Errors errors = relative_errors(fit.parameters(), kBeamTranslation);
        std::printf("[noisy 10 s, seed %u] rel. err. m %+.2e d %+.2e k %+.2e\n", seed, errors.mass,
                    errors.damping, errors.stiffness);
        EXPECT_TRUE(fit.converged);
        worst = std::max(worst, errors.largest());
    }
    EXPECT_LT(worst, 0.05);
}

TEST(Identification, LowSignalToNoiseFallsBackToMassSearch)
{
    // 10 mm position noise on a 7.5 mm RMS response (SNR 0.75). The noise on p, the regressor of
    // m in the equation-error step, biases m towards zero, and for some noise realisations below
    // zero: that used to throw ("do not determine a positive mass"). Now the output-error step
    // starts from a search over the mass and must converge. Over 30 seeds the output-error
    // estimate scatters by about 7 % (m) and 2 % (d, k), so the bounds are 25 % on m and 6 % on
    // d and k per seed (about 3.5 standard deviations), and 10 % on the RMS of the mass errors.
    const double position_rms = 1e-2;
    int fallbacks = 0;
    double mass_squares = 0.0;
    const unsigned seeds = 30;
    for (unsigned seed = 1; seed <= seeds; ++seed) {
        Record record = multisine_record(kBeamTranslation, multisine(4.0));
        add_noise(record, position_rms, 0.1, seed);
        ImpedanceFit fit;
        ASSERT_NO_THROW(fit = coopdyn::identify_impedance(record.position, record.force, kPeriod)) << "seed " << seed;
        const Errors errors = relative_errors(fit.parameters(), kBeamTranslation);
        mass_squares += errors.mass * errors.mass;
        EXPECT_TRUE(fit.converged) << "seed " << seed;
        EXPECT_GT(fit.mass, 0.0);
        EXPECT_EQ(fit.equation_error_start, fit.equation_error.mass > 0.0);
        if (!fit.equation_error_start) {
            ++fallbacks;
            report(("low SNR, mass search, seed " + std::to_string(seed)).c_str(), fit, kBeamTranslation);
            EXPECT_LT(std::abs(errors.mass), 0.25) << "seed " << seed;
            EXPECT_LT(std::abs(errors.damping), 0.06) << "seed " << seed;
            EXPECT_LT(std::abs(errors.stiffness), 0.06) << "seed " << seed;
            EXPECT_NEAR(fit.mean_squared_output_error / (position_rms * position_rms), 1.0, 0.05) << "seed " << seed;
            EXPECT_TRUE(std::isinf(fit.equation_error_mean_squared_output_error));
        }
    }
    const double mass_rms = std::sqrt(mass_squares / seeds);
    std::printf("[low SNR] %d of %u seeds gave a non-positive equation-error mass; RMS mass error %.3f\n", fallbacks,
                seeds, mass_rms);
    EXPECT_GE(fallbacks, 3);  // the fallback path is exercised (seeds 6, 11, 13, 19, 30)
    EXPECT_LT(mass_rms, 0.10);
}

// ---------------------------------------------------------------------------------------------
// 3. Diagonal 6-DOF fit.

TEST(Identification, DiagonalSixAxes)
{
    const std::array<Oscillator, 6> truth{Oscillator{21.75, 360.0, 600.0}, Oscillator{15.0, 250.0, 900.0},
                                          Oscillator{30.0, 120.0, 1500.0}, Oscillator{4.255, 77.6, 196.0},
                                          Oscillator{1.0, 24.0, 100.0},    Oscillator{2.8, 73.0, 148.0}};
    const std::array<double, 6> amplitude{4.0, 4.0, 6.0, 1.5, 0.5, 1.0};
    const Eigen::Index samples = 10001;
    Eigen::Matrix<double, 6, Eigen::Dynamic> displacement(6, samples);
    Eigen::Matrix<double, 6, Eigen::Dynamic> wrench(6, samples);
    for (Eigen::Index axis = 0; axis < 6; ++axis) {
        const auto index = static_cast<std::size_t>(axis);
        const double shift = 0.7 * static_cast<double>(axis);
        const Record record = multisine_record(truth[index], multisine(amplitude[index], shift),
                                               1e-3 * static_cast<double>(axis), 0.0, samples);
        displacement.row(axis) = record.position.transpose();
        wrench.row(axis) = record.force.transpose();
    }
    const coopdyn::DiagonalImpedanceFit fit = coopdyn::identify_diagonal_impedance(displacement, wrench, kPeriod);
    const char* names[6] = {"6-DOF x", "6-DOF y", "6-DOF z", "6-DOF rot x", "6-DOF rot y", "6-DOF rot z"};
    for (std::size_t axis = 0; axis < 6; ++axis) {
        report(names[axis], fit.axes[axis], truth[axis]);
        EXPECT_TRUE(fit.identified[axis]);
        EXPECT_TRUE(fit.axes[axis].converged);
        EXPECT_LT(relative_errors(fit.axes[axis].parameters(), truth[axis]).largest(), 5e-5);
        const auto i = static_cast<Eigen::Index>(axis);
        EXPECT_EQ(fit.inertia(i), fit.axes[axis].mass);
        EXPECT_EQ(fit.damping(i), fit.axes[axis].damping);
        EXPECT_EQ(fit.stiffness(i), fit.axes[axis].stiffness);
    }
    const coopdyn::ApparentImpedance<double> matrices = fit.matrices();
    EXPECT_EQ(matrices.inertia.diagonal(), fit.inertia);
    EXPECT_EQ(matrices.stiffness.diagonal(), fit.stiffness);
    EXPECT_EQ((matrices.damping - Eigen::Matrix<double, 6, 6>(fit.damping.asDiagonal())).norm(), 0.0);
}

TEST(Identification, DiagonalSubsetOfAxes)
{
    // The paper's experiment: force along x and torque about z only; the other rows are at rest.
    const Eigen::Index samples = 5001;
    const Record x = multisine_record(kBeamTranslation, multisine(4.0), 0.0, 0.0, samples);
    const Record rz = multisine_record(kBeamRotation, multisine(1.5, 0.3), 0.0, 0.0, samples);
    Eigen::MatrixXd displacement = Eigen::MatrixXd::Zero(6, samples);
    Eigen::MatrixXd wrench = Eigen::MatrixXd::Zero(6, samples);
    displacement.row(0) = x.position.transpose();
    wrench.row(0) = x.force.transpose();
    displacement.row(5) = rz.position.transpose();
    wrench.row(5) = rz.force.transpose();

    const coopdyn::DiagonalImpedanceFit fit = coopdyn::identify_diagonal_impedance(
        displacement, wrench, kPeriod, IdentificationOptions{}, {true, false, false, false, false, true});
    report("subset x", fit.axes[0], kBeamTranslation);
    report("subset rot z", fit.axes[5], kBeamRotation);
    EXPECT_TRUE(fit.identified[0]);
    EXPECT_TRUE(fit.identified[5]);
    for (std::size_t axis = 1; axis < 5; ++axis) {
        EXPECT_FALSE(fit.identified[axis]);
    }
    EXPECT_EQ(fit.inertia.segment<4>(1).norm(), 0.0);
    EXPECT_LT(relative_errors(fit.axes[0].parameters(), kBeamTranslation).largest(), 5e-5);
    EXPECT_LT(relative_errors(fit.axes[5].parameters(), kBeamRotation).largest(), 5e-5);

    // Without the mask the first unexcited axis is reported by name.
    try {
        (void)coopdyn::identify_diagonal_impedance(displacement, wrench, kPeriod);
        ADD_FAILURE() << "unexcited axis accepted";
    } catch (const coopdyn::InvalidArgument& error) {
        std::printf("[subset] without mask: %s\n", error.what());
        EXPECT_NE(std::string(error.what()).find("axis 1 (translation y)"), std::string::npos) << error.what();
        EXPECT_NE(std::string(error.what()).find("wrench row 1"), std::string::npos) << error.what();
    }
}

// ---------------------------------------------------------------------------------------------
// 4. Bad input.

template <typename Call> std::string error_of(Call&& call)
{
    try {
        call();
    } catch (const std::invalid_argument& error) {
        return error.what();
    }
    return "<no exception>";
}

void expect_error(const std::string& message, const std::string& expected)
{
    std::printf("[bad input] %s\n", message.c_str());
    EXPECT_NE(message.find(expected), std::string::npos) << message;
}

TEST(Identification, BadInputThrowsWithParameterName)
{
    const Record record = multisine_record(kBeamTranslation, multisine(4.0), 0.0, 0.0, 2001);
    const Eigen::VectorXd& p = record.position;
    const Eigen::VectorXd& f = record.force;
    using coopdyn::identify_impedance;

    expect_error(error_of([&] { (void)identify_impedance(p.head(9), f.head(9), kPeriod); }),
                 "'position' needs at least 10");
    expect_error(error_of([&] { (void)identify_impedance(p, f.head(2000), kPeriod); }),
                 "'force' must have as many samples");
    expect_error(error_of([&] { (void)identify_impedance(p, f, 0.0); }), "'sample_period' must be positive");
    expect_error(error_of([&] { (void)identify_impedance(p, f, -1e-3); }), "'sample_period'");
    expect_error(error_of([&] { (void)identify_impedance(p, f, std::nan("")); }), "'sample_period'");
    expect_error(error_of([&] { (void)identify_impedance(p, f, INFINITY); }), "'sample_period'");
    Eigen::VectorXd bad = p;
    bad(1000) = std::nan("");
    expect_error(error_of([&] { (void)identify_impedance(bad, f, kPeriod); }), "'position' must be finite");
    bad = f;
    bad(3) = INFINITY;
    expect_error(error_of([&] { (void)identify_impedance(p, bad, kPeriod); }), "'force' must be finite");
    expect_error(error_of([&] { (void)identify_impedance(Eigen::MatrixXd::Ones(3, 20), f.head(20), kPeriod); }),
                 "'position' must be a vector");

    // Unexcited data: at rest, a constant force with constant position (static), zero force.
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(2001);
    const Eigen::VectorXd constant = Eigen::VectorXd::Constant(2001, 0.01);
    expect_error(error_of([&] { (void)identify_impedance(zero, zero, kPeriod); }), "'force' is identically zero");
    expect_error(error_of([&] { (void)identify_impedance(p, zero, kPeriod); }), "'force' is identically zero");
    expect_error(error_of([&] { (void)identify_impedance(constant, (600.0 * constant).eval(), kPeriod); }),
                 "do not excite the dynamics");
    expect_error(error_of([&] { (void)identify_impedance(zero, f, kPeriod); }), "do not excite the dynamics");

    // Options.
    IdentificationOptions options;
    options.tolerance = 0.0;
    expect_error(error_of([&] { (void)identify_impedance(p, f, kPeriod, options); }), "'options.tolerance'");
    options = IdentificationOptions{};
    options.max_iterations = -1;
    expect_error(error_of([&] { (void)identify_impedance(p, f, kPeriod, options); }), "'options.max_iterations'");

    // 6-DOF shapes.
    const Eigen::MatrixXd five = Eigen::MatrixXd::Ones(5, 100);
    const Eigen::MatrixXd six = Eigen::MatrixXd::Ones(6, 100);
    const Eigen::MatrixXd short_six = Eigen::MatrixXd::Ones(6, 99);
    using coopdyn::identify_diagonal_impedance;
    expect_error(error_of([&] { (void)identify_diagonal_impedance(five, six, kPeriod); }), "'displacement' must be 6 x N");
    expect_error(error_of([&] { (void)identify_diagonal_impedance(six, five, kPeriod); }), "'wrench' must be 6 x N");
    expect_error(error_of([&] { (void)identify_diagonal_impedance(six, short_six, kPeriod); }), "as many samples");

    // Every failure is a coopdyn::InvalidArgument (a coopdyn::Error, a std::invalid_argument).
    EXPECT_THROW((void)identify_impedance(p.head(5), f.head(5), kPeriod), coopdyn::InvalidArgument);

    // simulate_impedance validates too.
    expect_error(error_of([&] { (void)coopdyn::simulate_impedance({0.0, 1.0, 1.0}, 0.0, 0.0, f, kPeriod); }),
                 "'parameters.mass'");
    expect_error(error_of([&] { (void)coopdyn::simulate_impedance({1.0, 1.0, 1.0}, 0.0, 0.0, f.head(3), kPeriod); }),
                 "'force' needs at least 4");
}

// ---------------------------------------------------------------------------------------------
// 5. Underdamped and overdamped systems, started away from rest.

TEST(Identification, UnderdampedWithInitialState)
{
    const Oscillator system{2.0, 4.0, 800.0};  // zeta = 0.05, resonance 3.2 Hz inside the band
    const Record record = multisine_record(system, multisine(2.0), 2e-3, -5e-2);
    const ImpedanceFit fit = coopdyn::identify_impedance(record.position, record.force, kPeriod);
    report("underdamped", fit, system);
    EXPECT_TRUE(fit.converged);
    EXPECT_LT(relative_errors(fit.parameters(), system).largest(), 5e-5);
    EXPECT_NEAR(fit.initial_position, 2e-3, 1e-8);
    EXPECT_NEAR(fit.initial_velocity, -5e-2, 1e-6);
}

TEST(Identification, OverdampedWithInitialState)
{
    const Oscillator system{1.0, 200.0, 100.0};  // zeta = 10: poles at -0.5 and -199.5 rad/s
    const Record record = multisine_record(system, multisine(5.0), -1e-2, 3e-2);
    const ImpedanceFit fit = coopdyn::identify_impedance(record.position, record.force, kPeriod);
    report("overdamped", fit, system);
    EXPECT_TRUE(fit.converged);
    EXPECT_LT(relative_errors(fit.parameters(), system).largest(), 5e-5);
    EXPECT_NEAR(fit.initial_position, -1e-2, 1e-8);
}

TEST(Identification, UnderdampedAndOverdampedWithNoise)
{
    const std::array<Oscillator, 2> systems{Oscillator{2.0, 4.0, 800.0}, Oscillator{1.0, 200.0, 100.0}};
    const std::array<double, 2> amplitudes{2.0, 5.0};
    for (std::size_t i = 0; i < 2; ++i) {
        Record record = multisine_record(systems[i], multisine(amplitudes[i]), 1e-3, 0.0, 10001);
        add_noise(record, 1e-4, 0.1, 99u + static_cast<unsigned>(i));
        const ImpedanceFit fit = coopdyn::identify_impedance(record.position, record.force, kPeriod);
        report(i == 0 ? "noisy underdamped" : "noisy overdamped", fit, systems[i]);
        EXPECT_TRUE(fit.converged);
        EXPECT_LT(relative_errors(fit.parameters(), systems[i]).largest(), 0.05);
    }
}

// ---------------------------------------------------------------------------------------------
// Force interpolation: each option is exact for the forces it assumes.

TEST(Identification, ZeroOrderHoldIsExactForHeldForce)
{
    const Record record = piecewise_record(kBeamTranslation, false, 20.0, 150, 5u);
    IdentificationOptions options;
    options.force_interpolation = ForceInterpolation::zero_order_hold;
    const ImpedanceFit fit = coopdyn::identify_impedance(record.position, record.force, kPeriod, options);
    report("held force, zero-order hold", fit, kBeamTranslation);
    EXPECT_TRUE(fit.converged);
    EXPECT_LT(relative_errors(fit.parameters(), kBeamTranslation).largest(), 1e-7);
}

TEST(Identification, LinearInterpolationIsExactForPiecewiseLinearForce)
{
    const Record record = piecewise_record(kBeamRotation, true, 3.0, 120, 6u);
    IdentificationOptions options;
    options.force_interpolation = ForceInterpolation::linear;
    options.estimate_initial_state = false;  // the record starts at rest
    const ImpedanceFit fit = coopdyn::identify_impedance(record.position, record.force, kPeriod, options);
    report("piecewise-linear force, linear", fit, kBeamRotation);
    EXPECT_TRUE(fit.converged);
    EXPECT_LT(relative_errors(fit.parameters(), kBeamRotation).largest(), 1e-7);
    EXPECT_EQ(fit.initial_position, record.position(0));
    EXPECT_EQ(fit.initial_velocity, 0.0);
}

TEST(Identification, LinearInterpolationBiasOnSmoothForce)
{
    // First-order hold on a smooth force: small O((w T)^2) bias, larger than the cubic's.
    const Record record = multisine_record(kBeamTranslation, multisine(4.0));
    IdentificationOptions options;
    options.force_interpolation = ForceInterpolation::linear;
    const ImpedanceFit fit = coopdyn::identify_impedance(record.position, record.force, kPeriod, options);
    report("smooth force, linear", fit, kBeamTranslation);
    EXPECT_LT(relative_errors(fit.parameters(), kBeamTranslation).largest(), 1e-3);
}

TEST(Identification, SimulationMatchesClosedForm)
{
    const Record record = multisine_record(kBeamRotation, multisine(1.5, 0.3), 3e-3, -2e-2);
    const Eigen::VectorXd simulated = coopdyn::simulate_impedance(
        {kBeamRotation.m, kBeamRotation.d, kBeamRotation.k}, 3e-3, -2e-2, record.force, kPeriod);
    const double error = (simulated - record.position).cwiseAbs().maxCoeff();
    const double scale = record.position.cwiseAbs().maxCoeff();
    std::printf("[simulation, cubic] max |p_sim - p_exact| = %.3e (max |p| = %.3e)\n", error, scale);
    EXPECT_LT(error, 1e-7 * scale);
}

TEST(Identification, FloatSamplesAndRowVectors)
{
    const Record record = multisine_record(kBeamTranslation, multisine(4.0), 0.0, 0.0, 5001);
    const Eigen::RowVectorXf position = record.position.transpose().cast<float>();
    const Eigen::RowVectorXf force = record.force.transpose().cast<float>();
    const ImpedanceFit fit = coopdyn::identify_impedance(position, force, kPeriod);
    report("float samples", fit, kBeamTranslation);
    EXPECT_LT(relative_errors(fit.parameters(), kBeamTranslation).largest(), 1e-3);
}

TEST(Identification, ZeroIterationsReturnsEquationErrorEstimate)
{
    const Record record = multisine_record(kBeamTranslation, multisine(4.0), 0.0, 0.0, 2001);
    IdentificationOptions options;
    options.max_iterations = 0;
    const ImpedanceFit fit = coopdyn::identify_impedance(record.position, record.force, kPeriod, options);
    EXPECT_EQ(fit.iterations, 0);
    EXPECT_FALSE(fit.converged);
    EXPECT_EQ(fit.mass, fit.equation_error.mass);
    EXPECT_EQ(fit.damping, fit.equation_error.damping);
    EXPECT_EQ(fit.stiffness, fit.equation_error.stiffness);
    EXPECT_EQ(fit.mean_squared_output_error, fit.equation_error_mean_squared_output_error);
}

}  // namespace
