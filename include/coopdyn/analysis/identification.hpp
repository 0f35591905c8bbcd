/// \file
/// \brief Grey-box identification of the apparent object impedance from logged motion and
/// wrench (the experiment of the paper's section V; docs/analysis.md).
///
/// The identified model is the 1-DOF projection of the linearised object dynamics (52), i.e. of
/// the reduced model (30) without its Coriolis term (quadratic in the twist) and with the exact
/// restoring wrench replaced by its linearisation:
///
///     m pdd(t) + d pd(t) + k p(t) = f(t)
///
/// where p is the displacement of one object coordinate from its equilibrium (p = 0 when f = 0)
/// and f the disturbance force (or torque) along that coordinate. The data are uniformly sampled:
/// p[n] = p(n T), f[n] = f(n T), n = 0 .. N-1. Design/analysis-time code: it allocates, throws
/// on bad input and computes in double whatever the input scalar type.
///
/// Method (two steps):
/// 1. Equation error. Integrating the ODE twice from t = 0 gives an equation that is linear in
///    the unknowns and contains no derivative of the data:
///        m p(t) + d P1(t) + k P2(t) + a + c t = F2(t),
///    P1 = int p, P2 = int int p, F2 = int int f (cumulative trapezoidal rule), a = -m p(0),
///    c = -m pd(0) - d p(0). Integration averages measurement noise where differentiation
///    (central differences) would amplify it by 1/T and 1/T^2, and the initial state becomes two
///    extra linear unknowns instead of being read from a single noisy sample. The 5-column
///    regression is solved by Householder QR with column equilibration; its condition number
///    detects unexcited data. The result is slightly biased (trapezoidal rule, O((omega T)^2),
///    and integrated noise); it is the starting point of step 2. At a low signal-to-noise ratio
///    the noise on p (the regressor of m) biases m towards zero and can make it non-positive;
///    step 2 then starts from a search over the mass instead: for each m on a logarithmic grid
///    (a factor 10^6 either way of |m|, 2^(1/2) apart) the regression is solved for the other
///    unknowns with m fixed (it stays linear), and the candidate whose simulation fits the data
///    best is the start. Identification fails only if step 2 then does not converge.
/// 2. Output error. The model is simulated from an initial state (p0, v0) with the measured force
///    and sum_n (p_model[n] - p[n])^2 is minimised over (m, d, k) and, by default, (p0, v0), by
///    Levenberg-Marquardt (Marquardt's diagonal scaling, Nielsen's damping update). The simulation
///    is exact for the chosen interpolation of the force between samples: the ODE is linear and
///    time-invariant, so one step is z[n+1] = Phi z[n] + Gamma f_window, with Phi and Gamma read
///    off the matrix exponential of the state matrix augmented by a chain of integrators that
///    generates the interpolating polynomial (no step-size error, only rounding). The
///    sensitivities dp/dm, dp/dd, dp/dk obey the forward sensitivity equations
///    s' = A s + (dA/dtheta) x + (dB/dtheta) f, which are linear in the same input; they are
///    discretised exactly together with the state (an 8-state system), so the Jacobian is the
///    exact derivative of the simulated output. dp/dp0 and dp/dv0 are the columns of Phi^n.
///    Noise on p is handled here: it enters the cost additively, so the minimiser is unbiased and
///    the mean squared output error tends to the noise variance.
///
/// Force interpolation: `cubic` (default) fits the cubic through the four nearest samples
/// (one-sided at the two ends); its error for a smooth force is O((omega T)^4), so smoothly
/// varying (e.g. measured) forces are reproduced to ~1e-8 relative at omega T = 0.03. `linear`
/// (first-order hold) is exact for piecewise-linear forces; for smooth ones it lowers the gain of
/// the simulated input by about (omega T)^2 / 12 (8e-5 at 5 Hz and 1 kHz), which biases the
/// estimates slightly (6e-6 relative on the beam's multisine test data, against 1e-9 with cubic).
/// `zero_order_hold` is exact for forces held constant over each sample period (a disturbance
/// commanded by a sampled controller, f[n] applied on [nT, (n+1)T)).
#pragma once

#include "coopdyn/analysis/apparent_impedance.hpp"
#include "coopdyn/config.hpp"
#include "coopdyn/detail/validation.hpp"
#include "coopdyn/numerics/levenberg_marquardt.hpp"
#include "coopdyn/analysis/impedance_discretization.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SVD>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>

namespace coopdyn {


/// \brief Options of identify_impedance and identify_diagonal_impedance.
struct IdentificationOptions {
    /// Interpolation of the force between samples in the output-error simulation.
    ForceInterpolation force_interpolation = ForceInterpolation::cubic;
    /// true: the initial position and velocity are estimated with (m, d, k). false: the
    /// record must start at rest at the measured p[0] (p0 = p[0], v0 = 0 are held fixed).
    bool estimate_initial_state = true;
    /// Maximum number of Levenberg-Marquardt iterations (each solves one linear system).
    int max_iterations = 100;
    /// Relative tolerance of the convergence tests (cost reduction, scaled step, and the cosine
    /// between residual and each Jacobian column), > 0.
    double tolerance = 1e-10;
};

/// \brief Mass (or moment of inertia), damping and stiffness of one axis.
struct ImpedanceParameters {
    double mass = 0.0;       ///< m, kg (or J, kg m^2 for a rotation)
    double damping = 0.0;    ///< d, N s/m (or delta, N m s/rad)
    double stiffness = 0.0;  ///< k, N/m (or kappa, N m/rad)
};

/// \brief Result of identify_impedance. Every field is finite.
struct ImpedanceFit {
    double mass = 0.0;               ///< m, output-error estimate
    double damping = 0.0;            ///< d, output-error estimate
    double stiffness = 0.0;          ///< k, output-error estimate
    double initial_position = 0.0;   ///< p0 of the simulation (estimated, or p[0])
    double initial_velocity = 0.0;   ///< v0 of the simulation (estimated, or 0)
    /// (1/N) sum_n (p_model[n] - p[n])^2 at the estimate (m^2, or rad^2 for a rotation).
    double mean_squared_output_error = 0.0;
    int iterations = 0;              ///< Levenberg-Marquardt iterations performed
    /// true when a convergence test was met; false when max_iterations was reached or no
    /// decrease of the cost could be found (the estimate is then the best point found).
    bool converged = false;
    /// Step 1: the equation-error (double integration) estimate, the starting point of step 2
    /// when its mass is positive. At a low signal-to-noise ratio its mass can be <= 0.
    ImpedanceParameters equation_error;
    /// true: step 2 started from the equation-error estimate. false: that estimate had m <= 0 and
    /// step 2 started from the best point of a search over the mass (see the file comment).
    bool equation_error_start = true;
    /// Mean squared output error of the equation-error model (with its initial state); +inf when
    /// equation_error_start is false (a model with m <= 0 cannot be simulated).
    double equation_error_mean_squared_output_error = 0.0;

    /// The output-error estimate alone.
    ImpedanceParameters parameters() const { return {mass, damping, stiffness}; }
};

/// \brief Result of identify_diagonal_impedance: diagonal M, D, K in the order
/// (x, y, z, rotation x, rotation y, rotation z). Axes that were not requested hold zeros and
/// identified[i] = false.
struct DiagonalImpedanceFit {
    Vector6<double> inertia = Vector6<double>::Zero();    ///< diagonal of M
    Vector6<double> damping = Vector6<double>::Zero();    ///< diagonal of D
    Vector6<double> stiffness = Vector6<double>::Zero();  ///< diagonal of K
    std::array<bool, 6> identified{};                     ///< which axes were fitted
    std::array<ImpedanceFit, 6> axes{};                   ///< the per-axis fits

    /// M, D, K as 6x6 diagonal matrices, comparable with apparent_impedance() (Theorem 2).
    ApparentImpedance<double> matrices() const
    {
        ApparentImpedance<double> result;
        result.inertia = inertia.asDiagonal();
        result.damping = damping.asDiagonal();
        result.stiffness = stiffness.asDiagonal();
        return result;
    }
};

namespace detail {

/// Fewest samples accepted by the identification.
inline constexpr Eigen::Index identification_minimum_samples = 10;

/// The samples of a vector argument as doubles; throws (naming `parameter`) unless it is a
/// finite vector.
template <typename Derived>
Eigen::VectorXd identification_samples(const Eigen::MatrixBase<Derived>& samples, const std::string& context,
                                       const std::string& parameter)
{
    static_assert(std::is_arithmetic_v<typename Derived::Scalar>,
                  "identification works on real (arithmetic) samples; it computes in double");
    if (samples.rows() != 1 && samples.cols() != 1) {
        std::ostringstream problem;
        problem << "must be a vector of samples, got " << samples.rows() << " x " << samples.cols();
        fail(context, parameter, problem.str());
    }
    Eigen::VectorXd result(samples.size());
    for (Eigen::Index i = 0; i < samples.size(); ++i) {
        result(i) = static_cast<double>(samples.derived().coeff(i));
    }
    if (!result.allFinite()) {
        fail(context, parameter, "must be finite (contains NaN or Inf)");
    }
    return result;
}

inline void check_identification_options(const IdentificationOptions& options, const std::string& context)
{
    if (options.max_iterations < 0) {
        fail(context, "options.max_iterations", "must be non-negative, got " + std::to_string(options.max_iterations));
    }
    require_positive(options.tolerance, context, "options.tolerance");
    const int points = interpolation_points(options.force_interpolation);
    if (points < 1 || points > 4) {
        fail(context, "options.force_interpolation", "is not a ForceInterpolation value");
    }
}

/// The equation-error regression of step 1: columns [p, int p, int int p, 1, t] and the
/// right-hand side int int f (cumulative trapezoidal rule, see the file comment).
inline void equation_error_regression(const Eigen::VectorXd& position, const Eigen::VectorXd& force,
                                      double sample_period, Eigen::MatrixXd& regressor, Eigen::VectorXd& rhs)
{
    const Eigen::Index samples = position.size();
    const double half_period = 0.5 * sample_period;
    regressor.resize(samples, 5);
    rhs.resize(samples);
    double p1 = 0.0, p2 = 0.0, f1 = 0.0, f2 = 0.0;
    for (Eigen::Index n = 0; n < samples; ++n) {
        if (n > 0) {
            const double p1_next = p1 + half_period * (position(n - 1) + position(n));
            const double f1_next = f1 + half_period * (force(n - 1) + force(n));
            p2 += half_period * (p1 + p1_next);
            f2 += half_period * (f1 + f1_next);
            p1 = p1_next;
            f1 = f1_next;
        }
        regressor(n, 0) = position(n);
        regressor(n, 1) = p1;
        regressor(n, 2) = p2;
        regressor(n, 3) = 1.0;
        regressor(n, 4) = static_cast<double>(n) * sample_period;
        rhs(n) = f2;
    }
}

/// (m, d, k, a, c) -> (m, d, k, p0, v0) with a = -m p0, c = -m v0 - d p0 (m != 0).
inline Eigen::Matrix<double, 5, 1> initial_state_from_regression(double mass, double damping, double stiffness,
                                                                 double offset, double slope)
{
    const double initial_position = -offset / mass;
    const double initial_velocity = -(slope + damping * initial_position) / mass;
    Eigen::Matrix<double, 5, 1> estimate;
    estimate << mass, damping, stiffness, initial_position, initial_velocity;
    return estimate;
}

/// Step 1: equation-error estimate by double integration (see the file comment). Returns the
/// regression's solution (m, d, k, a, c); m may be <= 0 (low signal-to-noise ratio: noise on p
/// biases the coefficient of p towards zero). Throws when the regression is singular
/// (unexcited data) or its solution is not finite.
inline Eigen::Matrix<double, 5, 1> equation_error_estimate(const Eigen::VectorXd& position,
                                                           const Eigen::VectorXd& force, double sample_period,
                                                           const std::string& context,
                                                           const std::string& position_name,
                                                           const std::string& force_name)
{
    Eigen::MatrixXd regressor;
    Eigen::VectorXd rhs;
    equation_error_regression(position, force, sample_period, regressor, rhs);
    // Dynamic-size small matrices below: fixed 5x5 SVDs trip GCC 12's -Warray-bounds false positives.
    const Eigen::VectorXd norms = regressor.colwise().norm().transpose();
    const char* const unexcited =
        "do not excite the dynamics: the equation-error regression [p, int p, int int p, 1, t] is singular "
        "(constant or zero motion, or motion that does not separate m, d and k)";
    if (!(norms.minCoeff() > 0.0) || !norms.allFinite() || !rhs.allFinite()) {
        fail(context, position_name + "/" + force_name, unexcited);
    }
    const Eigen::MatrixXd equilibrated = regressor * norms.cwiseInverse().asDiagonal();
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(equilibrated);
    const Eigen::MatrixXd r = qr.matrixQR().topLeftCorner(5, 5).triangularView<Eigen::Upper>();
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(r);
    const Eigen::VectorXd singular_values = svd.singularValues();
    if (!(singular_values(4) > 1e-10 * singular_values(0))) {
        std::ostringstream problem;
        problem << unexcited << "; condition number " << singular_values(0) / singular_values(4);
        fail(context, position_name + "/" + force_name, problem.str());
    }
    const Eigen::VectorXd solution = qr.solve(rhs).cwiseQuotient(norms);
    if (!solution.allFinite()) {
        fail(context, position_name + "/" + force_name, "give an equation-error estimate that is not finite");
    }
    Eigen::Matrix<double, 5, 1> result;
    for (Eigen::Index i = 0; i < 5; ++i) {
        result(i) = solution(i);
    }
    return result;
}

/// Starting point of step 2 when step 1 gives no positive mass (low signal-to-noise ratio).
/// Profile over the mass: for a fixed m the equation-error regression is linear in the other
/// unknowns, F2 - m p = d P1 + k P2 + a + c t, so every mass on a logarithmic grid
/// m_j = m_ref 2^(j/2), j = -40 .. 40 (a factor 10^6 either way) gets its least-squares d, k and
/// initial state, and the candidate whose simulated output fits the data best (the output-error
/// cost `cost_of`, which is +inf for unusable models) is returned. m_ref = |m| of step 1, or, if
/// that is 0, |k| / omega^2 at the geometric mean of the record's lowest and the Nyquist
/// frequency. Throws when no candidate gives a finite simulation.
template <typename CostFunction>
Eigen::Matrix<double, 5, 1> mass_search_start(const Eigen::VectorXd& position, const Eigen::VectorXd& force,
                                              double sample_period, const Eigen::Matrix<double, 5, 1>& step1,
                                              bool estimate_initial_state, const CostFunction& cost_of,
                                              const std::string& context, const std::string& what)
{
    Eigen::MatrixXd regressor;
    Eigen::VectorXd rhs;
    equation_error_regression(position, force, sample_period, regressor, rhs);
    const Eigen::Index samples = position.size();
    const Eigen::MatrixXd reduced = regressor.rightCols(4);
    const Eigen::VectorXd norms = reduced.colwise().norm().transpose();
    const Eigen::MatrixXd equilibrated = reduced * norms.cwiseInverse().asDiagonal();
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(equilibrated);
    // beta(m) = beta_f - m beta_p: the reduced solution is affine in the mass.
    const Eigen::VectorXd beta_f = qr.solve(rhs).cwiseQuotient(norms);
    const Eigen::VectorXd beta_p = qr.solve(regressor.col(0)).cwiseQuotient(norms);

    double reference = std::abs(step1(0));
    if (!(reference > 0.0)) {
        const double lowest = 2.0 * 3.14159265358979323846 / (static_cast<double>(samples) * sample_period);
        const double nyquist = 3.14159265358979323846 / sample_period;
        reference = std::abs(step1(2)) / (lowest * nyquist);
    }
    if (!(reference > 0.0) || !std::isfinite(reference)) {
        fail(context, what, "do not determine the scale of the mass: step 1 gives m = 0 and k = 0");
    }
    Eigen::Matrix<double, 5, 1> best = Eigen::Matrix<double, 5, 1>::Zero();
    double best_cost = std::numeric_limits<double>::infinity();
    for (int j = -40; j <= 40; ++j) {
        const double mass = reference * std::exp2(0.5 * static_cast<double>(j));
        const Eigen::VectorXd beta = beta_f - mass * beta_p;
        Eigen::Matrix<double, 5, 1> candidate =
            initial_state_from_regression(mass, beta(0), beta(1), beta(2), beta(3));
        if (!estimate_initial_state) {
            candidate(3) = position(0);
            candidate(4) = 0.0;
        }
        if (!candidate.allFinite()) {
            continue;
        }
        const double cost = cost_of(candidate);
        if (cost < best_cost) {
            best_cost = cost;
            best = candidate;
        }
    }
    if (!std::isfinite(best_cost)) {
        fail(context, what,
             "do not determine a positive mass: step 1 gives m <= 0 and no positive mass gives a finite simulation");
    }
    return best;
}

/// Steps 1 and 2 on validated samples.
inline ImpedanceFit identify_impedance_samples(const Eigen::VectorXd& position, const Eigen::VectorXd& force,
                                               double sample_period, const IdentificationOptions& options,
                                               const std::string& context, const std::string& position_name,
                                               const std::string& force_name)
{
    const Eigen::Index samples = position.size();
    if (samples < identification_minimum_samples) {
        fail(context, position_name, "needs at least " + std::to_string(identification_minimum_samples) +
                                         " samples, got " + std::to_string(samples));
    }
    if (force.size() != samples) {
        fail(context, force_name, "must have as many samples as " + position_name + " (" + std::to_string(samples) +
                                      "), got " + std::to_string(force.size()));
    }
    if (!(force.cwiseAbs().maxCoeff() > 0.0)) {
        fail(context, force_name, "is identically zero: the scale of m, d and k is not determined");
    }

    const Eigen::Matrix<double, 5, 1> step1 =
        equation_error_estimate(position, force, sample_period, context, position_name, force_name);
    const int parameters = options.estimate_initial_state ? 5 : 3;

    const double* const p = position.data();
    const double* const f = force.data();
    const ForceInterpolation interpolation = options.force_interpolation;
    const auto cost_at = [&](const Eigen::Matrix<double, 5, 1>& candidate) {
        ImpedanceDiscretization model;
        if (!discretize_impedance(candidate(0), candidate(1), candidate(2), sample_period, interpolation, model)) {
            return std::numeric_limits<double>::infinity();
        }
        return simulate_discretized(model, f, samples, candidate(3), candidate(4), p, nullptr);
    };
    Eigen::Matrix<double, 5, 5> normal;
    Eigen::Matrix<double, 5, 1> gradient;
    const auto linearise_at = [&](const Eigen::Matrix<double, 5, 1>& candidate) {
        ImpedanceDiscretization model;
        if (!discretize_impedance(candidate(0), candidate(1), candidate(2), sample_period, interpolation, model)) {
            return std::numeric_limits<double>::infinity();
        }
        return output_error_normal_equations(model, f, p, samples, candidate(3), candidate(4), parameters, normal,
                                             gradient);
    };

    ImpedanceFit fit;
    fit.equation_error = {step1(0), step1(1), step1(2)};
    fit.equation_error_start = step1(0) > 0.0;
    Eigen::Matrix<double, 5, 1> theta;
    if (fit.equation_error_start) {
        theta = initial_state_from_regression(step1(0), step1(1), step1(2), step1(3), step1(4));
        if (!options.estimate_initial_state) {
            theta(3) = position(0);
            theta(4) = 0.0;
        }
    } else {
        theta = mass_search_start(position, force, sample_period, step1, options.estimate_initial_state, cost_at,
                                  context, position_name + "/" + force_name);
    }
    double cost = linearise_at(theta);
    if (!std::isfinite(cost)) {
        fail(context, position_name + "/" + force_name,
             "give an equation-error model whose simulation is not finite; the data do not fit m pdd + d pd + k p = f");
    }
    fit.equation_error_mean_squared_output_error =
        (fit.equation_error_start ? cost : std::numeric_limits<double>::infinity()) / static_cast<double>(samples);

    // Output-error refinement (see the file comment).
    const numerics::LevenbergMarquardtResult refined = numerics::levenberg_marquardt(
        theta, cost, parameters, cost_at, linearise_at, normal, gradient, options.tolerance, options.max_iterations);
    cost = refined.cost;
    const bool converged = refined.converged;
    const int iteration = refined.iterations;
    if (!fit.equation_error_start && !converged) {
        std::ostringstream problem;
        problem << "do not determine a positive mass: the equation-error estimate is m = " << step1(0)
                << " and the output-error fit started from a mass search did not converge in " << iteration
                << " iterations (the inertia is not excited, or the noise is too large)";
        fail(context, position_name + "/" + force_name, problem.str());
    }
    fit.mass = theta(0);
    fit.damping = theta(1);
    fit.stiffness = theta(2);
    fit.initial_position = theta(3);
    fit.initial_velocity = theta(4);
    fit.mean_squared_output_error = cost / static_cast<double>(samples);
    fit.iterations = iteration;
    fit.converged = converged;
    return fit;
}

}  // namespace detail

/// \brief Simulates m pdd + d pd + k p = f on the sample grid, exactly for the chosen
/// interpolation of the force (see the file comment).
/// \param parameters m > 0, d, k (finite).
/// \param initial_position p(0); \param initial_velocity pd(0).
/// \param force f[n] = f(nT), a vector of N samples (N >= 1, >= 2 for linear, >= 4 for cubic).
/// \param sample_period T > 0, seconds.
/// \return p(nT), n = 0 .. N-1. Throws InvalidModel on invalid arguments.
template <typename DerivedF>
Eigen::VectorXd simulate_impedance(const ImpedanceParameters& parameters, double initial_position,
                                   double initial_velocity, const Eigen::MatrixBase<DerivedF>& force,
                                   double sample_period,
                                   ForceInterpolation interpolation = ForceInterpolation::cubic)
{
    const std::string context = "impedance simulation";
    detail::require_positive(parameters.mass, context, "parameters.mass");
    detail::require_positive(sample_period, context, "sample_period");
    if (!std::isfinite(parameters.damping) || !std::isfinite(parameters.stiffness)) {
        detail::fail(context, "parameters", "damping and stiffness must be finite");
    }
    if (!std::isfinite(initial_position) || !std::isfinite(initial_velocity)) {
        detail::fail(context, "initial_position/initial_velocity", "must be finite");
    }
    const Eigen::VectorXd samples = detail::identification_samples(force, context, "force");
    const int points = detail::interpolation_points(interpolation);
    if (samples.size() < points) {
        detail::fail(context, "force", "needs at least " + std::to_string(points) + " samples for this interpolation");
    }
    detail::ImpedanceDiscretization model;
    if (!detail::discretize_impedance(parameters.mass, parameters.damping, parameters.stiffness, sample_period,
                                      interpolation, model)) {
        detail::fail(context, "parameters", "give a transition matrix that is not finite over one sample period");
    }
    Eigen::VectorXd result(samples.size());
    detail::simulate_discretized(model, samples.data(), samples.size(), initial_position, initial_velocity, nullptr,
                                 result.data());
    return result;
}

/// \brief Grey-box identification of one axis of the apparent impedance: fits
/// m pdd + d pd + k p = f (the 1-DOF projection of (30)/(52), docs/analysis.md) to uniformly
/// sampled data by equation error (double integration) followed by output-error
/// Levenberg-Marquardt (see the file comment for the method).
/// \param position p[n], N >= 10 samples (vector), displacement from the equilibrium (metres, or
///        radians for a rotation).
/// \param force f[n], N samples (vector), force (or torque) along the same axis.
/// \param sample_period T > 0, seconds (1e-3 in the paper's experiment).
/// \param options interpolation of the force, initial-state handling, iteration limit.
/// \return the output-error estimate, its mean squared output error and the equation-error
///         estimate. Throws InvalidModel (a std::invalid_argument) naming the argument when the
///         sizes differ, N < 10, T or the data are not finite, the force is identically zero, or
///         the data do not excite the dynamics (singular regression; or no positive mass: step 1
///         gives m <= 0 and step 2, started from a search over the mass, does not converge).
template <typename DerivedP, typename DerivedF>
ImpedanceFit identify_impedance(const Eigen::MatrixBase<DerivedP>& position, const Eigen::MatrixBase<DerivedF>& force,
                                double sample_period, const IdentificationOptions& options = {})
{
    const std::string context = "identification";
    detail::require_positive(sample_period, context, "sample_period");
    detail::check_identification_options(options, context);
    const Eigen::VectorXd p = detail::identification_samples(position, context, "position");
    const Eigen::VectorXd f = detail::identification_samples(force, context, "force");
    return detail::identify_impedance_samples(p, f, sample_period, options, context, "position", "force");
}

/// \brief Diagonal 6-DOF identification: fits each axis of M xdd + D xd + K x = h (the
/// linearisation (52) of (30)) independently with identify_impedance, giving diagonal M, D, K.
///
/// Valid when the apparent impedance is diagonal in the chosen axes: Corollary 1 set-ups
/// (homogeneous arms, sum r_i = 0) decouple translation from rotation, and the axes must also be
/// principal axes of each 3x3 block (e.g. the paper's beam: M = diag(21.75 I3, 4.255, 1, 4.255)).
/// The rotation coordinates must be small angles (components of the rotation vector theta u, or
/// 2 d_eps, from the equilibrium orientation): the stiffness torque is kappa sin(theta) u, linear
/// to 0.2 % for |theta| < 0.1 rad, and the Coriolis term of (30), quadratic in the twist, is
/// neglected. Coupled set-ups need a full multivariable fit instead.
/// \param displacement 6 x N: rows (x, y, z, rotation x, rotation y, rotation z) of the object's
///        displacement from equilibrium, N >= 10.
/// \param wrench 6 x N: rows (f_x, f_y, f_z, t_x, t_y, t_z) of the disturbance wrench.
/// \param sample_period T > 0, seconds.
/// \param axes which axes to fit (e.g. only x and rotation z when only those were excited);
///        the others are left at zero with identified[i] = false.
/// Throws InvalidModel naming the axis and the argument (see identify_impedance).
template <typename DerivedX, typename DerivedH>
DiagonalImpedanceFit identify_diagonal_impedance(const Eigen::MatrixBase<DerivedX>& displacement,
                                                 const Eigen::MatrixBase<DerivedH>& wrench, double sample_period,
                                                 const IdentificationOptions& options = {},
                                                 const std::array<bool, 6>& axes = {true, true, true, true, true, true})
{
    static_assert(std::is_arithmetic_v<typename DerivedX::Scalar> && std::is_arithmetic_v<typename DerivedH::Scalar>,
                  "identification works on real (arithmetic) samples; it computes in double");
    static_assert(detail::sizes_agree(DerivedX::RowsAtCompileTime, 6) &&
                      detail::sizes_agree(DerivedH::RowsAtCompileTime, 6),
                  "displacement and wrench must have 6 rows");
    const std::string context = "diagonal identification";
    detail::require_positive(sample_period, context, "sample_period");
    detail::check_identification_options(options, context);
    if (displacement.rows() != 6) {
        detail::fail(context, "displacement", "must be 6 x N, got " + std::to_string(displacement.rows()) + " rows");
    }
    if (wrench.rows() != 6) {
        detail::fail(context, "wrench", "must be 6 x N, got " + std::to_string(wrench.rows()) + " rows");
    }
    if (wrench.cols() != displacement.cols()) {
        detail::fail(context, "wrench", "must have as many samples (columns) as displacement (" +
                                            std::to_string(displacement.cols()) + "), got " +
                                            std::to_string(wrench.cols()));
    }
    static const std::array<const char*, 6> names{"translation x", "translation y", "translation z",
                                                  "rotation x",    "rotation y",    "rotation z"};
    DiagonalImpedanceFit result;
    for (Eigen::Index axis = 0; axis < 6; ++axis) {
        const auto index = static_cast<std::size_t>(axis);
        if (!axes[index]) {
            continue;
        }
        const std::string axis_context = context + ", axis " + std::to_string(axis) + " (" + names[index] + ")";
        const std::string position_name = "displacement row " + std::to_string(axis);
        const std::string force_name = "wrench row " + std::to_string(axis);
        const Eigen::VectorXd p = detail::identification_samples(displacement.row(axis), axis_context, position_name);
        const Eigen::VectorXd f = detail::identification_samples(wrench.row(axis), axis_context, force_name);
        const ImpedanceFit fit =
            detail::identify_impedance_samples(p, f, sample_period, options, axis_context, position_name, force_name);
        result.axes[index] = fit;
        result.identified[index] = true;
        result.inertia(axis) = fit.mass;
        result.damping(axis) = fit.damping;
        result.stiffness(axis) = fit.stiffness;
    }
    return result;
}

}  // namespace coopdyn
