/// \file
/// \brief Grey-box identification of the apparent object impedance from logged motion and
/// wrench (the experiment of the paper's section V; docs/analysis.md, "Identification").
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
/// InvalidArgument on bad input and computes in double whatever the input scalar type.
///
/// Method (two steps):
/// 1. Equation error (equation_error.hpp). Integrating the ODE twice from t = 0 gives
///        m p(t) + d P1(t) + k P2(t) + a + c t = F2(t),
///    P1 = int p, P2 = int int p, F2 = int int f, a = -m p(0), c = -m pd(0) - d p(0): linear in
///    the unknowns, free of derivatives of the data, and solved by equilibrated QR whose
///    condition number detects unexcited data. Slightly biased (trapezoidal rule, O((omega T)^2),
///    and integrated noise), it is the starting point of step 2. At a low signal-to-noise ratio
///    the noise on p (the regressor of m) biases m towards zero and can make it non-positive;
///    step 2 then starts from a search over the mass instead: for each m on a logarithmic grid
///    (a factor 10^6 either way of |m|, 2^(1/2) apart) the regression is solved for the other
///    unknowns with m fixed, and the candidate whose simulation fits the data best is the start.
///    Identification fails only if step 2 then does not converge.
/// 2. Output error. The model is simulated from an initial state (p0, v0) with the measured force
///    and sum_n (p_model[n] - p[n])^2 is minimised over (m, d, k) and, by default, (p0, v0), by
///    Levenberg-Marquardt (numerics/levenberg_marquardt.hpp). The simulation is exact for the
///    chosen interpolation of the force between samples: the ODE is linear and time-invariant, so
///    one step is x[n+1] = Phi x[n] + W f_window (numerics/linear_discretization.hpp; no
///    step-size error, only rounding). The Jacobian is the exact derivative of the simulated
///    output: the recurrence differentiated with respect to each parameter
///    (impedance_discretization.hpp). Noise on p is handled here: it enters the cost additively,
///    so the minimiser is unbiased and the mean squared output error tends to the noise variance.
///
/// Force interpolation: `cubic` (default) fits the cubic through the four nearest samples
/// (one-sided at the two ends); its error for a smooth force is O((omega T)^4), so smoothly
/// varying (e.g. measured) forces are reproduced to ~1e-8 relative at omega T = 0.03. `linear`
/// (first-order hold) is exact for piecewise-linear forces; for smooth ones it lowers the gain of
/// the simulated input by about (omega T)^2 / 12 (8e-5 at 5 Hz and 1 kHz), which biases the
/// estimates slightly (6e-6 relative on the beam's multisine test data, against 1e-9 with cubic).
/// `zero_order_hold` is exact for forces held constant over each sample period (a disturbance
/// commanded by a sampled controller, f[n] applied on [nT, (n+1)T)).
///
/// Reading order: the result types, the public entry points (simulate_impedance,
/// identify_impedance, identify_diagonal_impedance), then the steps they call, in order.
#pragma once

#include "coopdyn/analysis/apparent_impedance.hpp"
#include "coopdyn/analysis/equation_error.hpp"
#include "coopdyn/analysis/impedance_discretization.hpp"
#include "coopdyn/config.hpp"
#include "coopdyn/detail/validation.hpp"
#include "coopdyn/numerics/levenberg_marquardt.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

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

// The steps of the public entry points, defined below them.
template <typename Derived>
Eigen::VectorXd samples_of(const Eigen::MatrixBase<Derived>& samples, const ErrorContext& context,
                           const std::string& parameter);
COOPDYN_LAZY void check_options(const IdentificationOptions& options, const ErrorContext& context);
COOPDYN_LAZY void check_diagonal_shapes(Index displacement_rows, Index displacement_columns, Index wrench_rows,
                                  Index wrench_columns, const ErrorContext& context);
COOPDYN_LAZY ImpedanceFit identify_axis(const AxisRecord& record, double sample_period, const IdentificationOptions& options);

}  // namespace detail

/// \brief Simulates m pdd + d pd + k p = f on the sample grid, exactly for the chosen
/// interpolation of the force (see the file comment).
/// \param parameters m > 0, d, k (finite).
/// \param initial_position p(0); \param initial_velocity pd(0).
/// \param force f[n] = f(nT), a vector of N samples (N >= 1, >= 2 for linear, >= 4 for cubic).
/// \param sample_period T > 0, seconds.
/// \return p(nT), n = 0 .. N-1. Throws InvalidArgument on invalid arguments.
template <typename DerivedF>
Eigen::VectorXd simulate_impedance(const ImpedanceParameters& parameters, double initial_position,
                                   double initial_velocity, const Eigen::MatrixBase<DerivedF>& force,
                                   double sample_period,
                                   ForceInterpolation interpolation = ForceInterpolation::cubic)
{
    const detail::ErrorContext context = detail::argument_context("impedance simulation");
    detail::require_positive(parameters.mass, context, "parameters.mass");
    detail::require_positive(sample_period, context, "sample_period");
    if (!std::isfinite(parameters.damping) || !std::isfinite(parameters.stiffness)) {
        detail::fail(context, "parameters", "damping and stiffness must be finite");
    }
    if (!std::isfinite(initial_position) || !std::isfinite(initial_velocity)) {
        detail::fail(context, "initial_position/initial_velocity", "must be finite");
    }
    const Eigen::VectorXd samples = detail::samples_of(force, context, "force");
    const int points = detail::interpolation_points(interpolation);
    if (points == 0) {
        detail::fail(context, "interpolation", "is not a ForceInterpolation value");
    }
    if (samples.size() < points) {
        detail::fail(context, "force", "needs at least " + std::to_string(points) + " samples for this interpolation");
    }
    const std::optional<detail::DiscreteImpedance> model = detail::discretize_impedance(
        parameters.mass, parameters.damping, parameters.stiffness, sample_period, interpolation);
    if (!model) {
        detail::fail(context, "parameters", "give a transition matrix that is not finite over one sample period");
    }
    return detail::simulated_positions(*model, samples, Eigen::Vector2d(initial_position, initial_velocity));
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
///         estimate. Throws InvalidArgument (a coopdyn::Error, a std::invalid_argument) naming the
///         argument when the sizes differ, N < 10, T or the data are not finite, the force is
///         identically zero, or the data do not excite the dynamics (singular regression; or no
///         positive mass: step 1 gives m <= 0 and step 2, started from a search over the mass,
///         does not converge).
template <typename DerivedP, typename DerivedF>
ImpedanceFit identify_impedance(const Eigen::MatrixBase<DerivedP>& position, const Eigen::MatrixBase<DerivedF>& force,
                                double sample_period, const IdentificationOptions& options = {})
{
    const detail::ErrorContext context = detail::argument_context("identification");
    detail::require_positive(sample_period, context, "sample_period");
    detail::check_options(options, context);
    const detail::AxisRecord record{detail::samples_of(position, context, "position"),
                                    detail::samples_of(force, context, "force"), context, "position", "force"};
    return detail::identify_axis(record, sample_period, options);
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
/// Throws InvalidArgument naming the axis and the argument (see identify_impedance).
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
    const std::string component = "diagonal identification";
    detail::require_positive(sample_period, component, "sample_period");
    detail::check_options(options, component);
    detail::check_diagonal_shapes(displacement.rows(), displacement.cols(), wrench.rows(), wrench.cols(), component);
    static const std::array<const char*, 6> names{"translation x", "translation y", "translation z",
                                                  "rotation x",    "rotation y",    "rotation z"};
    DiagonalImpedanceFit result;
    for (Index axis = 0; axis < 6; ++axis) {
        const auto index = static_cast<std::size_t>(axis);
        if (!axes[index]) {
            continue;
        }
        const detail::ErrorContext context = detail::argument_context(
            component + ", axis " + std::to_string(axis) + " (" + names[index] + ")");
        const std::string position_name = "displacement row " + std::to_string(axis);
        const std::string force_name = "wrench row " + std::to_string(axis);
        const detail::AxisRecord record{detail::samples_of(displacement.row(axis), context, position_name),
                                        detail::samples_of(wrench.row(axis), context, force_name), context,
                                        position_name, force_name};
        result.axes[index] = detail::identify_axis(record, sample_period, options);
        result.identified[index] = true;
        result.inertia(axis) = result.axes[index].mass;
        result.damping(axis) = result.axes[index].damping;
        result.stiffness(axis) = result.axes[index].stiffness;
    }
    return result;
}

namespace detail {

/// Fewest samples accepted by the identification.
inline constexpr Index identification_minimum_samples = 10;

/// The samples of a vector argument as doubles; throws (naming `parameter`) unless it is a
/// finite vector.
template <typename Derived>
Eigen::VectorXd samples_of(const Eigen::MatrixBase<Derived>& samples, const ErrorContext& context,
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
    for (Index i = 0; i < samples.size(); ++i) {
        result(i) = static_cast<double>(samples.derived().coeff(i));
    }
    if (!result.allFinite()) {
        fail(context, parameter, "must be finite (contains NaN or Inf)");
    }
    return result;
}

COOPDYN_LAZY_DEFINITION void check_options(const IdentificationOptions& options, const ErrorContext& context)
{
    if (options.max_iterations < 0) {
        fail(context, "options.max_iterations", "must be non-negative, got " + std::to_string(options.max_iterations));
    }
    require_positive(options.tolerance, context, "options.tolerance");
    if (interpolation_points(options.force_interpolation) == 0) {
        fail(context, "options.force_interpolation", "is not a ForceInterpolation value");
    }
}

COOPDYN_LAZY_DEFINITION void check_diagonal_shapes(Index displacement_rows, Index displacement_columns, Index wrench_rows,
                                  Index wrench_columns, const ErrorContext& context)
{
    if (displacement_rows != 6) {
        fail(context, "displacement", "must be 6 x N, got " + std::to_string(displacement_rows) + " rows");
    }
    if (wrench_rows != 6) {
        fail(context, "wrench", "must be 6 x N, got " + std::to_string(wrench_rows) + " rows");
    }
    if (wrench_columns != displacement_columns) {
        fail(context, "wrench", "must have as many samples (columns) as displacement (" +
                                    std::to_string(displacement_columns) + "), got " + std::to_string(wrench_columns));
    }
}

/// What step 2 fits for one axis: the impedance and the initial state of the simulation.
struct AxisModel {
    ImpedanceParameters impedance;
    double initial_position = 0.0;
    double initial_velocity = 0.0;
};

class OutputErrorProblem;
COOPDYN_LAZY void check_record(const AxisRecord& record);
COOPDYN_LAZY AxisModel model_from(const EquationErrorEstimate& estimate);
COOPDYN_LAZY AxisModel mass_search_start(const EquationErrorRegression& regression, const EquationErrorEstimate& step1,
                                   const OutputErrorProblem& problem, const AxisRecord& record, double sample_period);
COOPDYN_LAZY ImpedanceFit fit_from(const EquationErrorEstimate& step1, bool equation_error_start, const AxisModel& estimate,
                             const numerics::LevenbergMarquardtResult& refined, Index samples);

/// Step 2's least-squares problem for one axis: theta = (m, d, k, p0, v0), or (m, d, k) with the
/// initial state held at (p[0], 0); the cost is the output error sum_n (p_model[n] - p[n])^2,
/// +inf where the model cannot be simulated (impedance_discretization.hpp).
class OutputErrorProblem {
public:
    OutputErrorProblem(const AxisRecord& record, double sample_period, const IdentificationOptions& options)
        : record_(record), sample_period_(sample_period), options_(options)
    {
    }

    Eigen::VectorXd parameters_of(const AxisModel& model) const
    {
        Eigen::VectorXd theta(options_.estimate_initial_state ? 5 : 3);
        theta.head<3>() << model.impedance.mass, model.impedance.damping, model.impedance.stiffness;
        if (options_.estimate_initial_state) {
            theta.tail<2>() << model.initial_position, model.initial_velocity;
        }
        return theta;
    }

    AxisModel model_of(const Eigen::VectorXd& theta) const
    {
        const Eigen::Vector2d state = initial_state_of(theta);
        return {{theta(0), theta(1), theta(2)}, state(0), state(1)};
    }

    COOPDYN_LAZY double cost(const Eigen::VectorXd& theta) const
    {
        const std::optional<DiscreteImpedance> model = discretize(theta);
        return model ? output_error_cost(*model, record_.force, record_.position, initial_state_of(theta))
                     : std::numeric_limits<double>::infinity();
    }

    COOPDYN_LAZY numerics::NormalEquations linearise(const Eigen::VectorXd& theta) const
    {
        const std::optional<DiscreteImpedance> model = discretize(theta);
        if (!model) {
            return {std::numeric_limits<double>::infinity(), {}, {}};
        }
        return output_error_normal_equations(*model, record_.force, record_.position, initial_state_of(theta),
                                             theta.size());
    }

private:
    COOPDYN_LAZY std::optional<DiscreteImpedance> discretize(const Eigen::VectorXd& theta) const
    {
        return discretize_impedance(theta(0), theta(1), theta(2), sample_period_, options_.force_interpolation);
    }

    Eigen::Vector2d initial_state_of(const Eigen::VectorXd& theta) const
    {
        return theta.size() == 5 ? Eigen::Vector2d(theta(3), theta(4)) : Eigen::Vector2d(record_.position(0), 0.0);
    }

    const AxisRecord& record_;
    double sample_period_;
    const IdentificationOptions& options_;
};

/// Steps 1 and 2 for one axis (see the file comment).
COOPDYN_LAZY_DEFINITION ImpedanceFit identify_axis(const AxisRecord& record, double sample_period, const IdentificationOptions& options)
{
    check_record(record);
    const EquationErrorRegression regression = equation_error_regression(record, sample_period);
    const EquationErrorEstimate step1 = equation_error_estimate(regression, record);
    const OutputErrorProblem problem(record, sample_period, options);
    const bool equation_error_start = step1.mass > 0.0;
    const AxisModel start = equation_error_start ? model_from(step1)
                                                 : mass_search_start(regression, step1, problem, record, sample_period);

    const numerics::LevenbergMarquardtResult refined = numerics::levenberg_marquardt(
        problem.parameters_of(start), [&](const Eigen::VectorXd& theta) { return problem.cost(theta); },
        [&](const Eigen::VectorXd& theta) { return problem.linearise(theta); },
        numerics::LevenbergMarquardtOptions{options.tolerance, options.max_iterations});
    if (!std::isfinite(refined.initial_cost)) {
        fail(record.context, record.data_name(),
             "give an equation-error model whose simulation is not finite; the data do not fit m pdd + d pd + k p = f");
    }
    if (!equation_error_start && !refined.converged) {
        std::ostringstream problem_text;
        problem_text << "do not determine a positive mass: the equation-error estimate is m = " << step1.mass
                     << " and the output-error fit started from a mass search did not converge in "
                     << refined.iterations << " iterations (the inertia is not excited, or the noise is too large)";
        fail(record.context, record.data_name(), problem_text.str());
    }
    return fit_from(step1, equation_error_start, problem.model_of(refined.parameters), refined,
                    record.position.size());
}

/// Enough samples, equal lengths, and a force that sets the scale of m, d and k.
COOPDYN_LAZY_DEFINITION void check_record(const AxisRecord& record)
{
    const Index samples = record.position.size();
    if (samples < identification_minimum_samples) {
        fail(record.context, record.position_name, "needs at least " + std::to_string(identification_minimum_samples) +
                                                       " samples, got " + std::to_string(samples));
    }
    if (record.force.size() != samples) {
        fail(record.context, record.force_name, "must have as many samples as " + record.position_name + " (" +
                                                    std::to_string(samples) + "), got " +
                                                    std::to_string(record.force.size()));
    }
    if (!(record.force.cwiseAbs().maxCoeff() > 0.0)) {
        fail(record.context, record.force_name, "is identically zero: the scale of m, d and k is not determined");
    }
}

/// The model a regression solution describes, with its initial state (m != 0).
COOPDYN_LAZY_DEFINITION AxisModel model_from(const EquationErrorEstimate& estimate)
{
    return {{estimate.mass, estimate.damping, estimate.stiffness}, estimate.initial_position(),
            estimate.initial_velocity()};
}

/// Step 2's start when step 1 gives no positive mass: the candidate of the mass profile
/// (equation_error.hpp) with the smallest output error. Throws when none can be simulated.
COOPDYN_LAZY_DEFINITION AxisModel mass_search_start(const EquationErrorRegression& regression, const EquationErrorEstimate& step1,
                                   const OutputErrorProblem& problem, const AxisRecord& record, double sample_period)
{
    AxisModel best;
    double best_cost = std::numeric_limits<double>::infinity();
    for (const EquationErrorEstimate& candidate : mass_profile(regression, step1, record, sample_period)) {
        const Eigen::VectorXd theta = problem.parameters_of(model_from(candidate));
        const double cost = theta.allFinite() ? problem.cost(theta) : std::numeric_limits<double>::infinity();
        if (cost < best_cost) {
            best_cost = cost;
            best = problem.model_of(theta);
        }
    }
    if (!std::isfinite(best_cost)) {
        fail(record.context, record.data_name(),
             "do not determine a positive mass: step 1 gives m <= 0 and no positive mass gives a finite simulation");
    }
    return best;
}

/// The public result from both steps' estimates.
COOPDYN_LAZY_DEFINITION ImpedanceFit fit_from(const EquationErrorEstimate& step1, bool equation_error_start, const AxisModel& estimate,
                             const numerics::LevenbergMarquardtResult& refined, Index samples)
{
    const double count = static_cast<double>(samples);
    ImpedanceFit fit;
    fit.mass = estimate.impedance.mass;
    fit.damping = estimate.impedance.damping;
    fit.stiffness = estimate.impedance.stiffness;
    fit.initial_position = estimate.initial_position;
    fit.initial_velocity = estimate.initial_velocity;
    fit.mean_squared_output_error = refined.cost / count;
    fit.iterations = refined.iterations;
    fit.converged = refined.converged;
    fit.equation_error = {step1.mass, step1.damping, step1.stiffness};
    fit.equation_error_start = equation_error_start;
    fit.equation_error_mean_squared_output_error =
        equation_error_start ? refined.initial_cost / count : std::numeric_limits<double>::infinity();
    return fit;
}

}  // namespace detail
}  // namespace coopdyn
