/// \file
/// \brief Step 1 of the impedance identification (identification.hpp; docs/analysis.md,
/// "Identification"): the equation-error estimate of m pdd + d pd + k p = f by double
/// integration, and the mass profile that replaces it at a low signal-to-noise ratio.
///
/// Integrating the ODE twice from t = 0 gives an equation that is linear in the unknowns and
/// contains no derivative of the data:
///
///     m p(t) + d P1(t) + k P2(t) + a + c t = F2(t),
///
/// P1 = int p, P2 = int int p, F2 = int int f (cumulative trapezoidal rule), a = -m p(0),
/// c = -m pd(0) - d p(0). Integration averages measurement noise where differentiation (central
/// differences) would amplify it by 1/T and 1/T^2, and the initial state becomes two extra linear
/// unknowns instead of being read from a single noisy sample. The 5-column regression is solved
/// by Householder QR with column equilibration; its condition number detects unexcited data. The
/// result is slightly biased (trapezoidal rule, O((omega T)^2), and integrated noise).
///
/// At a low signal-to-noise ratio the noise on p (the regressor of m) biases m towards zero and
/// can make it non-positive. The mass profile then offers candidates instead: for a fixed m the
/// regression F2 - m p = d P1 + k P2 + a + c t stays linear in the other unknowns, and its
/// solution is affine in m, so every m on a logarithmic grid gets its least-squares d, k, a, c.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/detail/validation.hpp"

#include <Eigen/QR>
#include <Eigen/SVD>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace coopdyn {
namespace detail {

/// One axis' record: the validated samples, and the names that error messages give them.
struct AxisRecord {
    Eigen::VectorXd position;
    Eigen::VectorXd force;
    ErrorContext context;
    std::string position_name;
    std::string force_name;

    /// Both series, for failures that belong to the pair ("position/force do not excite ...").
    std::string data_name() const { return position_name + "/" + force_name; }
};

/// The regression: columns [p, P1, P2, 1, t] and right-hand side F2.
struct EquationErrorRegression {
    Eigen::MatrixXd regressor;
    Eigen::VectorXd rhs;
};

/// A solution (m, d, k, a, c) of the regression, with the initial state it implies (m != 0).
struct EquationErrorEstimate {
    double mass = 0.0;
    double damping = 0.0;
    double stiffness = 0.0;
    double offset = 0.0;  ///< a = -m p0
    double slope = 0.0;   ///< c = -m v0 - d p0

    double initial_position() const { return -offset / mass; }
    double initial_velocity() const { return -(slope + damping * initial_position()) / mass; }
};

/// The regression's columns and right-hand side, integrals by the cumulative trapezoidal rule.
COOPDYN_LAZY EquationErrorRegression equation_error_regression(const AxisRecord& record, double sample_period)
{
    const Eigen::VectorXd& position = record.position;
    const Eigen::VectorXd& force = record.force;
    const Index samples = position.size();
    const double half_period = 0.5 * sample_period;
    EquationErrorRegression regression{Eigen::MatrixXd(samples, 5), Eigen::VectorXd(samples)};
    double p1 = 0.0, p2 = 0.0, f1 = 0.0, f2 = 0.0;  // P1, P2, F1 = int f, F2 at sample n
    for (Index n = 0; n < samples; ++n) {
        if (n > 0) {
            const double p1_next = p1 + half_period * (position(n - 1) + position(n));
            const double f1_next = f1 + half_period * (force(n - 1) + force(n));
            p2 += half_period * (p1 + p1_next);
            f2 += half_period * (f1 + f1_next);
            p1 = p1_next;
            f1 = f1_next;
        }
        regression.regressor.row(n) << position(n), p1, p2, 1.0, static_cast<double>(n) * sample_period;
        regression.rhs(n) = f2;
    }
    return regression;
}

/// Least squares on columns scaled to unit norm (column equilibration), so that the QR's
/// condition number measures excitation rather than units.
class EquilibratedLeastSquares {
public:
    COOPDYN_LAZY explicit EquilibratedLeastSquares(const Eigen::MatrixXd& regressor)
        : norms_(regressor.colwise().norm().transpose())
    {
        if (usable()) {
            qr_.compute(regressor * norms_.cwiseInverse().asDiagonal());
        }
    }

    /// false when a column is zero or not finite (the QR is then not computed).
    bool usable() const { return norms_.minCoeff() > 0.0 && norms_.allFinite(); }

    /// Condition number of the equilibrated regressor (largest / smallest singular value of R).
    COOPDYN_LAZY double condition_number() const
    {
        const Index columns = norms_.size();
        // Dynamic-size R: a fixed 5x5 SVD trips GCC 12's -Warray-bounds false positives.
        const Eigen::MatrixXd r = qr_.matrixQR().topLeftCorner(columns, columns).triangularView<Eigen::Upper>();
        const Eigen::VectorXd singular_values = Eigen::JacobiSVD<Eigen::MatrixXd>(r).singularValues();
        return singular_values(0) / singular_values(columns - 1);
    }

    COOPDYN_LAZY Eigen::VectorXd solve(const Eigen::VectorXd& rhs) const { return qr_.solve(rhs).cwiseQuotient(norms_); }

private:
    Eigen::VectorXd norms_;
    Eigen::HouseholderQR<Eigen::MatrixXd> qr_;
};

/// The regression's least-squares solution; m may be <= 0 (low signal-to-noise ratio). Throws
/// InvalidArgument when the regression is singular (unexcited data) or its solution not finite.
COOPDYN_LAZY EquationErrorEstimate equation_error_estimate(const EquationErrorRegression& regression,
                                                     const AxisRecord& record)
{
    const char* const unexcited =
        "do not excite the dynamics: the equation-error regression [p, int p, int int p, 1, t] is singular "
        "(constant or zero motion, or motion that does not separate m, d and k)";
    const EquilibratedLeastSquares least_squares(regression.regressor);
    if (!least_squares.usable() || !regression.rhs.allFinite()) {
        fail(record.context, record.data_name(), unexcited);
    }
    const double condition_number = least_squares.condition_number();
    if (!(condition_number < 1e10)) {
        std::ostringstream problem;
        problem << unexcited << "; condition number " << condition_number;
        fail(record.context, record.data_name(), problem.str());
    }
    const Eigen::VectorXd solution = least_squares.solve(regression.rhs);
    if (!solution.allFinite()) {
        fail(record.context, record.data_name(), "give an equation-error estimate that is not finite");
    }
    return {solution(0), solution(1), solution(2), solution(3), solution(4)};
}

/// The mass that centres the profile's grid: |m| of `estimate`, or, if that is 0, |k| / omega^2
/// at the geometric mean of the record's lowest and the Nyquist frequency. Throws when both are 0.
COOPDYN_LAZY double mass_profile_reference(const EquationErrorEstimate& estimate, const AxisRecord& record,
                                     double sample_period)
{
    constexpr double pi = 3.14159265358979323846;
    double reference = std::abs(estimate.mass);
    if (!(reference > 0.0)) {
        const double lowest = 2.0 * pi / (static_cast<double>(record.position.size()) * sample_period);
        const double nyquist = pi / sample_period;
        reference = std::abs(estimate.stiffness) / (lowest * nyquist);
    }
    if (!(reference > 0.0) || !std::isfinite(reference)) {
        fail(record.context, record.data_name(), "do not determine the scale of the mass: step 1 gives m = 0 and k = 0");
    }
    return reference;
}

/// The mass profile (see the file comment): for m_j = m_ref 2^(j/2), j = -40 .. 40 (a factor
/// 10^6 either way of m_ref, mass_profile_reference), the least-squares (d, k, a, c) with m = m_j
/// fixed. With beta_f and beta_p the solutions for the right-hand sides F2 and p over the
/// columns [P1, P2, 1, t], (d, k, a, c)(m) = beta_f - m beta_p.
COOPDYN_LAZY std::vector<EquationErrorEstimate> mass_profile(const EquationErrorRegression& regression,
                                                       const EquationErrorEstimate& estimate,
                                                       const AxisRecord& record, double sample_period)
{
    const EquilibratedLeastSquares others(regression.regressor.rightCols(4));
    const Eigen::VectorXd beta_f = others.solve(regression.rhs);
    const Eigen::VectorXd beta_p = others.solve(regression.regressor.col(0));
    const double reference = mass_profile_reference(estimate, record, sample_period);
    std::vector<EquationErrorEstimate> profile;
    for (int j = -40; j <= 40; ++j) {
        const double mass = reference * std::exp2(0.5 * static_cast<double>(j));
        const Eigen::VectorXd beta = beta_f - mass * beta_p;
        profile.push_back({mass, beta(0), beta(1), beta(2), beta(3)});
    }
    return profile;
}

}  // namespace detail
}  // namespace coopdyn
