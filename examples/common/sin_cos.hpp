// sin and cos of several angles at once, branch-free (the example recursions' joint angles).
// Tested against the standard library in tests/examples/test_box_core.cpp
// (Lwr4Dynamics.SinCosIsTheLibrarysToRounding). No dependencies.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace example_common {

/// sin and cos of N angles at once: a recursion's joint angles (the LWR 4 arm's, examples/box/
/// lwr4_dynamics.hpp; a MuJoCo chain's, examples/scenes/chain_dynamics.hpp). Why not std::sin and
/// std::cos: fourteen library calls per evaluation of an LWR 4 arm, about a fifth of its time; here
/// the angles' work has neither calls nor branches and is independent, so it overlaps (about 4
/// times faster).
///
/// Method (Cody and Waite's argument reduction; Muller, Elementary Functions, ch. 11):
/// x = k pi/2 + r with k = nearest(2 x / pi), |r| <= pi/4, pi/2 split into three parts of which the
/// first two have 32 significant bits, so that k times them is exact for |k| < 2^21; the Taylor
/// series of sin r and cos r to degrees 17 and 16 (truncation below 1e-18 for |r| <= pi/4); and
/// k mod 4 picks and signs them. The result differs from the library's by rounding (about one
/// ulp). Angles beyond 1e6 rad (or NaN) go to std::sin and std::cos.
template <std::size_t N> struct SinCos {
    std::array<double, N> sine, cosine;
};
template <std::size_t N> inline SinCos<N> sin_cos(const std::array<double, N>& angle) noexcept
{
    constexpr double two_over_pi = 0.63661977236758134308;
    constexpr double half_pi_high = 0x1.921fb544p0, half_pi_mid = 0x1.0b4611a6p-34, half_pi_low = 0x1.3198a2e037073p-69;
    // Adding 1.5 * 2^52 rounds to an integer (in the default rounding mode) and leaves it in the
    // low bits of the sum's representation, whence the quadrant.
    constexpr double round_to_integer = 0x1.8p52;
    constexpr double reduction_limit = 1e6;
    // 1 / n!, exact integers rounded once.
    constexpr double s3 = -1.0 / 6.0, s5 = 1.0 / 120.0, s7 = -1.0 / 5040.0, s9 = 1.0 / 362880.0,
                     s11 = -1.0 / 39916800.0, s13 = 1.0 / 6227020800.0, s15 = -1.0 / 1307674368000.0,
                     s17 = 1.0 / 355687428096000.0;
    constexpr double c2 = -0.5, c4 = 1.0 / 24.0, c6 = -1.0 / 720.0, c8 = 1.0 / 40320.0, c10 = -1.0 / 3628800.0,
                     c12 = 1.0 / 479001600.0, c14 = -1.0 / 87178291200.0, c16 = 1.0 / 20922789888000.0;
    SinCos<N> result;
    for (std::size_t i = 0; i < N; ++i) {
        const double x = angle[i];
        const double shifted = x * two_over_pi + round_to_integer;
        const double k = shifted - round_to_integer;
        std::uint64_t bits;
        std::memcpy(&bits, &shifted, sizeof bits);
        const std::uint64_t quadrant = bits & 3u;
        const double r = ((x - k * half_pi_high) - k * half_pi_mid) - k * half_pi_low;
        const double r2 = r * r;
        const double s = r + r * r2 * (s3 + r2 * (s5 + r2 * (s7 + r2 * (s9 + r2 * (s11 + r2 * (s13 + r2 * (s15 + r2 * s17)))))));
        const double c = 1.0 + r2 * (c2 + r2 * (c4 + r2 * (c6 + r2 * (c8 + r2 * (c10 + r2 * (c12 + r2 * (c14 + r2 * c16)))))));
        // sin x = s, c, -s, -c and cos x = c, -s, -c, s for k mod 4 = 0, 1, 2, 3.
        const double sin_magnitude = (quadrant & 1u) != 0 ? c : s;
        const double cos_magnitude = (quadrant & 1u) != 0 ? s : c;
        result.sine[i] = (quadrant & 2u) != 0 ? -sin_magnitude : sin_magnitude;
        result.cosine[i] = ((quadrant + 1u) & 2u) != 0 ? -cos_magnitude : cos_magnitude;
    }
    for (std::size_t i = 0; i < N; ++i) {
        if (!(std::abs(angle[i]) <= reduction_limit)) {
            result.sine[i] = std::sin(angle[i]);
            result.cosine[i] = std::cos(angle[i]);
        }
    }
    return result;
}

}  // namespace example_common
