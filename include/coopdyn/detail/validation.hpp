/// \file
/// \brief Construction-time checks of model parameters. Each failure throws coopdyn::InvalidModel
/// with a message naming the body (object or arm index), the parameter and what is wrong.
#pragma once

#include "coopdyn/config.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

namespace coopdyn {

/// \brief Thrown when a model is built from invalid parameters. what() names the body, the
/// parameter and the problem, e.g. "coopdyn: arm 1: 'mass' must be positive and finite, got -2".
class InvalidModel : public std::invalid_argument {
public:
    using std::invalid_argument::invalid_argument;
};

namespace detail {

/// Numerical value of a scalar as double: the value itself for arithmetic types, value() for
/// autodiff-like scalars (recursively). Parameters are validated on their values only.
template <typename Scalar> double value_of(const Scalar& scalar)
{
    if constexpr (std::is_arithmetic_v<Scalar>) {
        return static_cast<double>(scalar);
    } else {
        return value_of(scalar.value());
    }
}

template <typename Derived>
Eigen::Matrix<double, Derived::RowsAtCompileTime, Derived::ColsAtCompileTime>
values_of(const Eigen::MatrixBase<Derived>& matrix)
{
    return matrix.unaryExpr([](const typename Derived::Scalar& x) { return value_of(x); });
}

/// Machine epsilon of the arithmetic type underlying a scalar (float, double, or the value type of
/// an autodiff-like scalar, recursively).
template <typename Scalar> double epsilon_of()
{
    if constexpr (std::is_arithmetic_v<Scalar>) {
        return static_cast<double>(std::numeric_limits<Scalar>::epsilon());
    } else {
        return epsilon_of<std::decay_t<decltype(std::declval<const Scalar&>().value())>>();
    }
}

/// A relative tolerance of at least `tolerance`, widened to 16 ulps of the scalar type, so that
/// values rounded to float (a normalised quaternion, a rotated inertia) are not refused.
template <typename Scalar> double tolerance_for(double tolerance)
{
    return std::max(tolerance, 16.0 * epsilon_of<Scalar>());
}

/// Where a parameter lives: "object", "arm 3", "model".
inline std::string object_context() { return "object"; }
inline std::string arm_context(Index arm) { return "arm " + std::to_string(arm); }

[[noreturn]] inline void fail(const std::string& context, const std::string& parameter,
                              const std::string& problem)
{
    throw InvalidModel("coopdyn: " + context + ": '" + parameter + "' " + problem);
}

template <typename Scalar>
void require_positive(const Scalar& scalar, const std::string& context, const std::string& parameter)
{
    const double value = value_of(scalar);
    if (!std::isfinite(value) || !(value > 0.0)) {
        std::ostringstream problem;
        problem << "must be positive and finite, got " << value;
        fail(context, parameter, problem.str());
    }
}

template <typename Scalar>
void require_non_negative(const Scalar& scalar, const std::string& context, const std::string& parameter)
{
    const double value = value_of(scalar);
    if (!std::isfinite(value) || !(value >= 0.0)) {
        std::ostringstream problem;
        problem << "must be non-negative and finite, got " << value;
        fail(context, parameter, problem.str());
    }
}

template <typename Derived>
void require_finite(const Eigen::MatrixBase<Derived>& matrix, const std::string& context,
                    const std::string& parameter)
{
    if (!values_of(matrix).allFinite()) {
        fail(context, parameter, "must be finite (contains NaN or Inf)");
    }
}

/// Symmetric to relative 1e-9 of its largest entry, and positive definite (or, with
/// allow_semidefinite, positive semi-definite to the same relative tolerance).
template <typename Derived>
void require_symmetric_positive(const Eigen::MatrixBase<Derived>& matrix, const std::string& context,
                                const std::string& parameter, bool allow_semidefinite = false)
{
    require_finite(matrix, context, parameter);
    using Scalar = typename Derived::Scalar;
    const auto values = values_of(matrix).eval();
    const double scale = values.cwiseAbs().maxCoeff();
    if ((values - values.transpose()).cwiseAbs().maxCoeff() > tolerance_for<Scalar>(1e-9) * scale) {
        fail(context, parameter, "must be symmetric");
    }
    using Dense = Eigen::Matrix<double, Derived::RowsAtCompileTime, Derived::ColsAtCompileTime>;
    const Eigen::SelfAdjointEigenSolver<Dense> eigen(values);
    const double smallest = eigen.eigenvalues().minCoeff();
    const bool acceptable =
        allow_semidefinite ? smallest >= -tolerance_for<Scalar>(1e-12) * scale : smallest > 0.0;
    if (!acceptable) {
        std::ostringstream problem;
        problem << "must be symmetric positive " << (allow_semidefinite ? "semi-" : "")
                << "definite, smallest eigenvalue " << smallest;
        fail(context, parameter, problem.str());
    }
}

/// A unit quaternion to 1e-9 (a quaternion is never normalised silently).
template <typename Scalar>
void require_unit_quaternion(const Quaternion<Scalar>& quaternion, const std::string& context,
                             const std::string& parameter)
{
    require_finite(quaternion.coeffs(), context, parameter);
    const double norm = values_of(quaternion.coeffs()).norm();
    if (!(std::abs(norm - 1.0) <= tolerance_for<Scalar>(1e-9))) {
        std::ostringstream problem;
        problem << "must be a unit quaternion, has norm " << std::setprecision(17) << norm;
        fail(context, parameter, problem.str());
    }
}

}  // namespace detail
}  // namespace coopdyn
