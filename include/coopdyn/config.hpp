/// \file
/// \brief Common types and compile-time size helpers shared by every coopdyn header.
///
/// Sizes follow docs/conventions.md: the object and N end-effectors make N + 1 bodies; stacked
/// twists, accelerations and wrenches have 6(N + 1) entries, the end-effector part alone 6N.
/// `Eigen::Dynamic` (N chosen at run time) passes through every helper unchanged.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cassert>
#include <cstdio>
#include <cstdlib>
#include <type_traits>
#include <vector>

namespace coopdyn {

/// Index type used for arm numbers and sizes (Eigen's signed index).
using Index = Eigen::Index;

/// Marker for "number of arms chosen at run time".
inline constexpr int Dynamic = Eigen::Dynamic;

/// 6 * n, or Eigen::Dynamic when n is Eigen::Dynamic.
constexpr int times_six(int n) noexcept { return n == Eigen::Dynamic ? Eigen::Dynamic : 6 * n; }

/// 3 * n, or Eigen::Dynamic when n is Eigen::Dynamic.
constexpr int times_three(int n) noexcept { return n == Eigen::Dynamic ? Eigen::Dynamic : 3 * n; }

/// Number of rows of the end-effector stack h' = [h_1; ...; h_N]: 6N.
constexpr int end_effector_stack_size(int arms) noexcept { return times_six(arms); }

/// Number of rows of the full stack h = [h_o; h_1; ...; h_N]: 6(N + 1).
constexpr int full_stack_size(int arms) noexcept
{
    return arms == Eigen::Dynamic ? Eigen::Dynamic : 6 * (arms + 1);
}

/// pi in the precision of Scalar (double by default), the one definition every coopdyn file uses.
template <typename Scalar = double> constexpr Scalar pi() { return Scalar(3.141592653589793238462643383279502884L); }

template <typename Scalar> using Vector3 = Eigen::Matrix<Scalar, 3, 1>;
template <typename Scalar> using Vector4 = Eigen::Matrix<Scalar, 4, 1>;
template <typename Scalar> using Vector6 = Eigen::Matrix<Scalar, 6, 1>;
template <typename Scalar> using Matrix3 = Eigen::Matrix<Scalar, 3, 3>;
template <typename Scalar> using Matrix6 = Eigen::Matrix<Scalar, 6, 6>;
template <typename Scalar> using Quaternion = Eigen::Quaternion<Scalar>;

/// Stacked end-effector quantity, 6N (twists, wrenches, setpoint accelerations).
template <typename Scalar, int Arms>
using EndEffectorVector = Eigen::Matrix<Scalar, end_effector_stack_size(Arms), 1>;

/// Stacked quantity of all N + 1 bodies, 6(N + 1) (accelerations, hSigma, interaction wrenches).
template <typename Scalar, int Arms>
using FullStackVector = Eigen::Matrix<Scalar, full_stack_size(Arms), 1>;

/// One 3-vector per arm, side by side: 3 x N (grasp offsets r_i, positions).
template <typename Scalar, int Arms> using PerArmVector3 = Eigen::Matrix<Scalar, 3, Arms>;

/// One quaternion per arm, coefficients (x, y, z, w) side by side: 4 x N.
template <typename Scalar, int Arms> using PerArmQuaternion = Eigen::Matrix<Scalar, 4, Arms>;

/// Per-arm 6x6 matrices side by side: 6 x 6N (end-effector inertias M_i, dampings, stiffnesses).
template <typename Scalar, int Arms>
using PerArmMatrix6 = Eigen::Matrix<Scalar, 6, end_effector_stack_size(Arms)>;

/// Per-arm 3x3 matrices side by side: 3 x 3N (rotational inertias J_i).
template <typename Scalar, int Arms>
using PerArmMatrix3 = Eigen::Matrix<Scalar, 3, times_three(Arms)>;

/// One object per arm: std::array for a fixed N (no heap at all), std::vector for Dynamic.
template <typename T, int Arms>
using PerArm = std::conditional_t<Arms == Eigen::Dynamic, std::vector<T>, std::array<T, static_cast<std::size_t>(Arms == Eigen::Dynamic ? 0 : Arms)>>;

namespace detail {

/// Number of arms encoded by a compile-time column count of an r-like 3 x N argument.
template <typename Derived> constexpr int arms_of() noexcept { return Derived::ColsAtCompileTime; }

/// Number of arms encoded by a compile-time row count of a 6N stack (or Dynamic).
constexpr int arms_from_end_effector_rows(int rows) noexcept
{
    return rows == Eigen::Dynamic ? Eigen::Dynamic : rows / 6;
}

/// Number of arms encoded by a compile-time row count of a 6(N + 1) stack (or Dynamic).
constexpr int arms_from_full_rows(int rows) noexcept
{
    return rows == Eigen::Dynamic ? Eigen::Dynamic : rows / 6 - 1;
}

/// The first fixed value of a and b, Dynamic if both are dynamic.
constexpr int first_fixed(int a, int b) noexcept { return a != Eigen::Dynamic ? a : b; }

/// Compile-time check that two size values agree whenever both are fixed.
constexpr bool sizes_agree(int a, int b) noexcept
{
    return a == Eigen::Dynamic || b == Eigen::Dynamic || a == b;
}

}  // namespace detail

}  // namespace coopdyn

/// Put before a function defined in a header whose body uses Eigen's decompositions or large
/// products (QR, SVD, LU, eigen-solvers, GEMM), instead of `inline`: it makes the function a
/// template with one defaulted parameter, called exactly as before. Why: a non-template inline
/// function is compiled, with every Eigen template it uses, in every file that includes its header,
/// called or not (including analysis.hpp cost about 19 s of g++ -O2 user CPU); a template is
/// instantiated only in the files that call it. Callers of such a function that are themselves
/// non-template must use it too. docs/performance.md, "Compile time".
#define COOPDYN_LAZY template <typename CompiledWhereUsed = void>
/// The definition of a COOPDYN_LAZY function declared earlier (the default is given once).
#define COOPDYN_LAZY_DEFINITION template <typename CompiledWhereUsed>

/// Forces inlining of the small 3-vector helpers of the per-tick path (cross products, scalings,
/// the shift of a motion or force). Why: g++ 12 keeps some of them out of line; their 3-vector
/// arguments then travel through memory, stored as scalars and reloaded by its SLP vectoriser as
/// 2-wide packets that straddle those stores (a store-to-load forwarding stall per call). Inlined,
/// the operands stay in registers. clang++ inlines them anyway. See docs/performance.md.
#define COOPDYN_INLINE EIGEN_ALWAYS_INLINE

/// Unrolls the next loop by two (g++, clang++; a no-op elsewhere). Why: g++ 12 does not unroll
/// the per-arm loops of the interaction solve, so each iteration's 3-vectors cross the loop's
/// back edge through the stack and its SLP vectoriser reloads them as packets (store-to-load
/// forwarding stalls). Unrolled by two (N = 2 completely), the N = 2 solve went from about 85 to
/// 62 ns, level with clang++, which unrolls it anyway (docs/performance.md).
#if defined(__GNUC__)
#define COOPDYN_UNROLL_BY_2 _Pragma("GCC unroll 2")
#else
#define COOPDYN_UNROLL_BY_2
#endif

namespace coopdyn::detail {
/// Stops the program with `message` on stderr: the per-tick functions' answer to a caller error
/// that would otherwise corrupt memory (a Data or input sized for another model). Cold and out of
/// line so that the check costs one comparison on the hot path.
[[noreturn]] inline void stop_on_misuse(const char* function, const char* message, Index arm = -1) noexcept
{
    if (arm >= 0) {
        std::fprintf(stderr, "coopdyn: %s: arm %lld: %s\n", function, static_cast<long long>(arm), message);
    } else {
        std::fprintf(stderr, "coopdyn: %s: %s\n", function, message);
    }
    std::abort();
}
}  // namespace coopdyn::detail

/// Always-on check of a caller error that would be undefined behaviour (a buffer sized for another
/// model), in Release too: fails fast with a message instead of corrupting memory. Used only
/// for shape checks, which cost one integer comparison per tick (none for a fixed N).
#define COOPDYN_REQUIRE_SHAPE(condition, message)                            \
    do {                                                                     \
        if (!(condition)) {                                                  \
            ::coopdyn::detail::stop_on_misuse(__func__, message);            \
        }                                                                    \
    } while (false)

/// Debug-only check inside noexcept per-tick code. Define COOPDYN_DISABLE_ASSERTS to remove them
/// from debug builds too; NDEBUG removes them as usual.
#if defined(COOPDYN_DISABLE_ASSERTS)
#define COOPDYN_ASSERT(condition, message) ((void)0)
#else
#define COOPDYN_ASSERT(condition, message) assert((condition) && message)
#endif
