/// \file
/// \brief Matrix exponential of a small dense matrix: scaling and squaring with diagonal Pade
/// approximants (docs/numerics.md). The kernel of the exact discretisation of linear ODEs
/// (linear_discretization.hpp).
///
///     exp(A) = r_m(A / 2^s)^(2^s),    r_m(X) = q_m(X)^-1 p_m(X),
///     p_m(X) = sum_{j=0}^{m} c_j X^j,  q_m(X) = p_m(-X),  c_j = (2m - j)! m! / ((2m)! j! (m - j)!)
///
/// The degree m in {3, 5, 7, 9, 13} and the number of squarings s follow Higham, "The scaling and
/// squaring method for the matrix exponential revisited", SIAM J. Matrix Anal. Appl. 26(4),
/// 2005, Algorithm 2.3: the cheapest m whose backward error bound holds at ||A||_1 (Table 2.3,
/// theta_m), otherwise m = 13 after scaling ||A / 2^s||_1 below theta_13. The backward error is
/// then at most the unit roundoff of double.
#pragma once

#include "coopdyn/config.hpp"

#include <Eigen/Core>
#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

namespace coopdyn::numerics {

namespace detail {

/// Coefficients c_0 .. c_m of the numerator p_m of the [m/m] Pade approximant of exp(x), from
/// c_0 = 1 and c_j / c_{j-1} = (m - j + 1) / (j (2m - j + 1)).
inline std::array<double, 14> pade_coefficients(int degree) noexcept
{
    std::array<double, 14> coefficients{};
    coefficients[0] = 1.0;
    for (int j = 1; j <= degree; ++j) {
        const auto index = static_cast<std::size_t>(j);
        coefficients[index] = coefficients[index - 1] * static_cast<double>(degree - j + 1) /
                              static_cast<double>(j * (2 * degree - j + 1));
    }
    return coefficients;
}

/// r_m(x) = q_m(x)^-1 p_m(x) for m in {3, 5, 7, 9, 13}. With U the odd and V the even part of
/// p_m, p_m(x) = V + U and q_m(x) = V - U. Degree 13 uses Higham's evaluation from x^2, x^4, x^6
/// (six products instead of twelve).
COOPDYN_LAZY Eigen::MatrixXd pade_approximant(const Eigen::MatrixXd& x, int degree)
{
    const std::array<double, 14> c = pade_coefficients(degree);
    const Eigen::Index size = x.rows();
    const Eigen::MatrixXd identity = Eigen::MatrixXd::Identity(size, size);
    const Eigen::MatrixXd x2 = x * x;
    Eigen::MatrixXd odd;   // U / x
    Eigen::MatrixXd even;  // V
    if (degree == 13) {
        const Eigen::MatrixXd x4 = x2 * x2;
        const Eigen::MatrixXd x6 = x4 * x2;
        odd = x6 * (c[13] * x6 + c[11] * x4 + c[9] * x2) + c[7] * x6 + c[5] * x4 + c[3] * x2 + c[1] * identity;
        even = x6 * (c[12] * x6 + c[10] * x4 + c[8] * x2) + c[6] * x6 + c[4] * x4 + c[2] * x2 + c[0] * identity;
    } else {
        Eigen::MatrixXd power = identity;  // x^(2k)
        odd = c[1] * identity;
        even = c[0] * identity;
        for (int k = 1; 2 * k <= degree; ++k) {
            power = (power * x2).eval();
            odd += c[static_cast<std::size_t>(2 * k + 1)] * power;
            even += c[static_cast<std::size_t>(2 * k)] * power;
        }
    }
    const Eigen::MatrixXd u = x * odd;
    return (even - u).partialPivLu().solve(even + u);
}

}  // namespace detail

/// \brief exp(a) of a small dense square matrix, by scaling and squaring with Pade approximants
/// (Higham 2005, Algorithm 2.3; see the file comment).
/// \param a n x n, any n >= 0.
/// \return exp(a), n x n. All NaN when `a` is not finite; entries overflow to Inf (or become NaN)
///         when exp(a) is not representable. Relative error a small multiple of
///         cond(exp, a) * 1.1e-16 (measured in tests/numerics/test_matrix_exponential.cpp).
COOPDYN_LAZY Eigen::MatrixXd matrix_exponential(const Eigen::MatrixXd& a)
{
    const Eigen::Index size = a.rows();
    if (size == 0) {
        return a;
    }
    const double norm = a.cwiseAbs().colwise().sum().maxCoeff();  // ||a||_1
    if (!std::isfinite(norm)) {
        return Eigen::MatrixXd::Constant(size, size, std::numeric_limits<double>::quiet_NaN());
    }
    // theta_m of Higham (2005), Table 2.3: the largest ||X||_1 at which r_m(X) has a backward
    // error below 2^-53.
    constexpr std::array<double, 4> low_degree_theta{1.495585217958292e-2, 2.539398330063230e-1,
                                                     9.504178996162932e-1, 2.097847961257068e0};
    constexpr std::array<int, 4> low_degree{3, 5, 7, 9};
    for (std::size_t i = 0; i < low_degree.size(); ++i) {
        if (norm <= low_degree_theta[i]) {
            return detail::pade_approximant(a, low_degree[i]);
        }
    }
    constexpr double theta_13 = 5.371920351148152e0;
    const int squarings = std::max(0, static_cast<int>(std::ceil(std::log2(norm / theta_13))));
    Eigen::MatrixXd result = detail::pade_approximant(a * std::ldexp(1.0, -squarings), 13);
    for (int i = 0; i < squarings; ++i) {
        result = (result * result).eval();
    }
    return result;
}

}  // namespace coopdyn::numerics
