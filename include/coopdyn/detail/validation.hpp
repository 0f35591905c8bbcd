/// \file
/// \brief Construction-time checks of parameters. Each failure throws an exception of
/// coopdyn/errors.hpp naming the component (object, arm index, ...), the parameter and what is
/// wrong: InvalidModel for a model context (object_context, arm_context, model_context,
/// load_distribution_context), InvalidArgument for any other named component.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/errors.hpp"
#include "coopdyn/numerics/symmetric_eigenvalues.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>

namespace coopdyn {
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

/// Which exception a failed check throws.
enum class ErrorKind { model, argument };

/// Where a parameter lives: the kind of input, the component and the arm (or no_arm).
/// A plain string converts to an argument context: only the *_context functions below make
/// model contexts, so the exception type is decided in one visible place.
struct ErrorContext {
    ErrorKind kind = ErrorKind::argument;
    std::string component;
    Index arm = no_arm;

    ErrorContext(ErrorKind kind_, std::string component_, Index arm_ = no_arm)
        : kind(kind_), component(std::move(component_)), arm(arm_)
    {
    }
    ErrorContext(std::string component_) : component(std::move(component_)) {}  // NOLINT: implicit on purpose
    ErrorContext(const char* component_) : component(component_) {}              // NOLINT: implicit on purpose
};

inline ErrorContext object_context() { return {ErrorKind::model, "object"}; }
inline ErrorContext arm_context(Index arm) { return {ErrorKind::model, "end effector", arm}; }
inline ErrorContext model_context() { return {ErrorKind::model, "model"}; }
inline ErrorContext load_distribution_context(Index arm = no_arm)
{
    return {ErrorKind::model, "load distribution", arm};
}
inline ErrorContext argument_context(std::string component, Index arm = no_arm)
{
    return {ErrorKind::argument, std::move(component), arm};
}

// The require_* checks take the parameter's name as a C string and build strings only when they
// fail, so that a check that passes allocates nothing (Model::set_end_effector runs them at run
// time, between ticks).

[[noreturn]] inline void fail(const ErrorContext& context, const std::string& parameter, const std::string& problem)
{
    if (context.kind == ErrorKind::model) {
        throw InvalidModel(context.component, parameter, context.arm, problem);
    }
    throw InvalidArgument(context.component, parameter, context.arm, problem);
}

template <typename Scalar>
void require_positive(const Scalar& scalar, const ErrorContext& context, const char* parameter)
{
    const double value = value_of(scalar);
    if (!std::isfinite(value) || !(value > 0.0)) {
        std::ostringstream problem;
        problem << "must be positive and finite, got " << value;
        fail(context, parameter, problem.str());
    }
}

template <typename Scalar>
void require_non_negative(const Scalar& scalar, const ErrorContext& context, const char* parameter)
{
    const double value = value_of(scalar);
    if (!std::isfinite(value) || !(value >= 0.0)) {
        std::ostringstream problem;
        problem << "must be non-negative and finite, got " << value;
        fail(context, parameter, problem.str());
    }
}

template <typename Derived>
void require_finite(const Eigen::MatrixBase<Derived>& matrix, const ErrorContext& context,
                    const char* parameter)
{
    if (!values_of(matrix).allFinite()) {
        fail(context, parameter, "must be finite (contains NaN or Inf)");
    }
}

/// Symmetric to relative 1e-9 of its largest entry, and positive definite (or, with
/// allow_semidefinite, positive semi-definite to the same relative tolerance).
template <typename Derived>
void require_symmetric_positive(const Eigen::MatrixBase<Derived>& matrix, const ErrorContext& context,
                                const char* parameter, bool allow_semidefinite = false)
{
    require_finite(matrix, context, parameter);
    using Scalar = typename Derived::Scalar;
    const auto values = values_of(matrix).eval();
    const double scale = values.cwiseAbs().maxCoeff();
    if ((values - values.transpose()).cwiseAbs().maxCoeff() > tolerance_for<Scalar>(1e-9) * scale) {
        fail(context, parameter, "must be symmetric");
    }
    const double smallest = numerics::symmetric_eigenvalues(values).minCoeff();
    const bool acceptable =
        allow_semidefinite ? smallest >= -tolerance_for<Scalar>(1e-12) * scale : smallest > 0.0;
    if (!acceptable) {
        std::ostringstream problem;
        problem << "must be symmetric positive " << (allow_semidefinite ? "semi-" : "")
                << "definite, smallest eigenvalue " << smallest;
        fail(context, parameter, problem.str());
    }
}

/// The rotational inertia of a real rigid body: its principal moments (eigenvalues) satisfy the
/// triangle inequality, largest <= sum of the other two (to relative 1e-9): J = tr(S) I - S for
/// the body's second moment of mass S >= 0, so J_xx = S_yy + S_zz <= J_yy + J_zz. Equality is a
/// thin rod or a flat plate. Call after require_symmetric_positive.
template <typename Derived>
void require_triangle_inequality(const Eigen::MatrixBase<Derived>& matrix, const ErrorContext& context,
                                 const char* parameter)
{
    using Scalar = typename Derived::Scalar;
    const Eigen::Matrix3d values = values_of(matrix);
    const Eigen::Vector3d moments = numerics::symmetric_eigenvalues(values);
    if (moments(2) > moments(0) + moments(1) + tolerance_for<Scalar>(1e-9) * moments(2)) {
        std::ostringstream problem;
        problem << "is not the inertia of a rigid body: its largest principal moment " << moments(2)
                << " exceeds the sum of the other two, " << moments(0) << " + " << moments(1)
                << " (triangle inequality)";
        fail(context, parameter, problem.str());
    }
}

/// A gain matrix with no negative gain: every eigenvalue has a non-negative real part (to
/// relative 1e-12 of its largest entry). Gains need not be symmetric (e.g. Lambda^-1 D), but a
/// direction in which the gain pushes the error away instead of back is refused.
template <typename Derived>
void require_non_negative_gain(const Eigen::MatrixBase<Derived>& matrix, const ErrorContext& context,
                               const char* parameter)
{
    require_finite(matrix, context, parameter);
    using Scalar = typename Derived::Scalar;
    using Dense = Eigen::Matrix<double, Derived::RowsAtCompileTime, Derived::ColsAtCompileTime>;
    const Dense values = values_of(matrix);
    const double scale = values.cwiseAbs().maxCoeff();
    const Eigen::EigenSolver<Dense> eigen(values, /*computeEigenvectors=*/false);
    const double smallest = eigen.eigenvalues().real().minCoeff();
    if (smallest < -tolerance_for<Scalar>(1e-12) * scale) {
        std::ostringstream problem;
        problem << "must not be negative: an eigenvalue has real part " << smallest;
        fail(context, parameter, problem.str());
    }
}

/// A unit quaternion to 1e-9 (a quaternion is never normalised silently).
template <typename Scalar>
void require_unit_quaternion(const Quaternion<Scalar>& quaternion, const ErrorContext& context,
                             const char* parameter)
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

/// |norm - 1| a per-tick quaternion may have: 1e-6, or 100 ulps for float.
template <typename Scalar> double unit_quaternion_tolerance() noexcept
{
    return std::max(1e-6, 100.0 * detail::epsilon_of<Scalar>());
}

namespace detail {
/// Every entry finite (on the values of autodiff scalars); allocation-free.
template <typename Derived> bool all_finite(const Eigen::MatrixBase<Derived>& matrix) noexcept
{
    for (Index column = 0; column < matrix.cols(); ++column) {
        for (Index row = 0; row < matrix.rows(); ++row) {
            if (!std::isfinite(value_of(matrix(row, column)))) {
                return false;
            }
        }
    }
    return true;
}

/// Finite and of unit norm within unit_quaternion_tolerance; `coefficients` in any order.
template <typename Derived> bool is_unit_quaternion(const Eigen::MatrixBase<Derived>& coefficients) noexcept
{
    using Scalar = typename Derived::Scalar;
    if (!all_finite(coefficients)) {
        return false;
    }
    double squared_norm = 0.0;
    for (Index k = 0; k < 4; ++k) {
        const double value = value_of(coefficients(k));
        squared_norm += value * value;
    }
    return std::abs(std::sqrt(squared_norm) - 1.0) <= unit_quaternion_tolerance<Scalar>();
}
}  // namespace detail
}  // namespace coopdyn
