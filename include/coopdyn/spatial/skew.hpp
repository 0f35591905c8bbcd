/// \file
/// \brief The skew-symmetric cross-product matrix S(a) and products with it, docs/conventions.md.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/spatial/symmetric3.hpp"

namespace coopdyn {

/// \brief Skew-symmetric matrix S(a) with S(a) b = a x b (docs/conventions.md, paper (11)).
/// \param a 3-vector (any Eigen expression).
/// \return 3x3 matrix [[0, -a_z, a_y], [a_z, 0, -a_x], [-a_y, a_x, 0]].
template <typename Derived>
Matrix3<typename Derived::Scalar> skew(const Eigen::MatrixBase<Derived>& a) noexcept
{
    EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(Derived, 3);
    using Scalar = typename Derived::Scalar;
    Matrix3<Scalar> result;
    const Scalar zero(0);
    // clang-format off
    result << zero,   -a(2),  a(1),
              a(2),   zero,  -a(0),
             -a(1),   a(0),   zero;
    // clang-format on
    return result;
}

/// \brief S(a) S(a)^T = |a|^2 I3 - a a^T, the parallel-axis term of paper (25) and (31).
/// \param a 3-vector.
/// \return symmetric positive semi-definite 3x3 matrix.
template <typename Derived>
Matrix3<typename Derived::Scalar> skew_gram(const Eigen::MatrixBase<Derived>& a) noexcept
{
    return Symmetric3<typename Derived::Scalar>::skew_square(a).matrix();
}

}  // namespace coopdyn
