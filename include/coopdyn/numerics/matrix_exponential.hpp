/// \file
/// \brief Matrix exponential of small dense matrices (the exact discretisation of the
/// identification's linear ODE, docs/numerics.md).
///
/// Scaling and squaring (Moler and Van Loan, "Nineteen dubious ways to compute the exponential
/// of a matrix", 2003; Higham 2005) with a Taylor series on the scaled matrix: with the 1-norm
/// scaled to at most 1/2 the series converges fast and is truncated where the next term falls
/// below double rounding.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <limits>

namespace coopdyn::numerics {

/// \brief exp(a) of a small square matrix: scaling and squaring with a Taylor series, truncated when
/// the next term is below double rounding (the scaled norm is at most 1/2). Returns a matrix of
/// NaN when a is not finite or exp(a) would overflow.
inline Eigen::MatrixXd matrix_exponential(const Eigen::MatrixXd& a)
{
    const Eigen::Index size = a.rows();
    const Eigen::MatrixXd failed = Eigen::MatrixXd::Constant(size, size, std::numeric_limits<double>::quiet_NaN());
    const double norm = a.cwiseAbs().rowwise().sum().maxCoeff();
    if (!std::isfinite(norm)) {
        return failed;
    }
    int squarings = 0;
    if (norm > 0.5) {
        std::frexp(norm / 0.5, &squarings);  // norm / 2^squarings < 0.5
    }
    if (squarings > 1100) {
        return failed;
    }
    const Eigen::MatrixXd scaled = a * std::ldexp(1.0, -squarings);
    Eigen::MatrixXd term = Eigen::MatrixXd::Identity(size, size);
    Eigen::MatrixXd result = term;
    for (int order = 1; order <= 30; ++order) {
        term = (term * scaled) / static_cast<double>(order);
        result += term;
        if (term.cwiseAbs().maxCoeff() <= 1e-18 * result.cwiseAbs().maxCoeff()) {
            break;
        }
    }
    for (int i = 0; i < squarings; ++i) {
        result = (result * result).eval();
    }
    return result;
}

}  // namespace coopdyn::numerics
