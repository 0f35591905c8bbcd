/// \file
/// \brief Squeeze monitoring: the component of the wrenches the arms apply to the object that lies
/// in the null space of the grasp matrix, relative to the non-squeezing distribution (25) of
/// their net wrench (the construction of the paper's reference [23]); docs/coordination.md,
/// "Squeeze monitoring".
///
///     hbar_sq = hbar - G+_M G hbar,      hbar_i = -h_i (the wrench arm i applies to the object)
///
/// G hbar_sq = 0 (G G+_M = I6), and hbar_sq = 0 exactly when the arms share their net wrench as
/// the load distribution with the same weights would. Unlike the internal wrench of (53), which
/// comes from the motion controllers' wrenches alone, hbar_sq contains every squeeze, whatever its
/// cause: a squeeze commanded through the desired wrenches h^d, load-distribution weights other
/// than the reference ones, disagreeing motion controllers. With the end-effector inertias as
/// weights and no disturbance,
///
///     hbar_sq = -h'_int + (I - G+_M G) hbar^d,      hbar^d = -h^d,
///
/// in every state (docs/coordination.md derives it; tests/coordination/test_grasp_squeeze.cpp
/// checks it).
///
/// Error policy as in load_distribution.hpp: `squeeze_wrenches` validates and throws,
/// `try_squeeze_wrenches` is noexcept and returns false on degenerate weights, the per-tick
/// `squeeze_wrenches(distribution, data, out)` uses weights validated by LoadDistribution.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/coordination/load_distribution.hpp"
#include "coopdyn/detail/validation.hpp"
#include "coopdyn/spatial/spatial_vector.hpp"

namespace coopdyn {
namespace detail {

/// hbar_sq = hbar - G+_M G hbar in O(N), without forming G or G+_M: the net wrench at the centre
/// of mass, its composite motion z under the weights, then hbar_i minus arm i's share M*_i G_i'^T z.
/// `squeeze_out` may alias `wrenches_on_object` (each arm's block is read before it is written).
template <typename Weights, typename DerivedR, typename DerivedWrenches, typename DerivedOut>
bool try_squeeze(const Weights& weights, const Eigen::MatrixBase<DerivedR>& r,
                 const Eigen::MatrixBase<DerivedWrenches>& wrenches_on_object,
                 const Eigen::MatrixBase<DerivedOut>& squeeze_out) noexcept
{
    using Scalar = typename DerivedR::Scalar;
    auto& squeeze = const_cast<Eigen::MatrixBase<DerivedOut>&>(squeeze_out);
    COOPDYN_ASSERT(wrenches_on_object.size() == 6 * r.cols() && squeeze.size() == 6 * r.cols(),
                   "the wrenches and the squeeze must have 6N entries");
    const WeightedGrasp<Scalar> grasp(weights, r);
    if (!grasp.valid) {
        return false;
    }
    const Motion<Scalar> motion = grasp.composite_motion(grasp_times(r, wrenches_on_object));  // G hbar (24)
    for (Index i = 0; i < r.cols(); ++i) {
        const Force<Scalar> applied = Force<Scalar>::from(wrenches_on_object.template segment<6>(6 * i));
        (applied - grasp.share(weights, r, i, motion)).write_to(squeeze.template segment<6>(6 * i));
    }
    return true;
}

}  // namespace detail

/// \brief Squeeze hbar_sq = hbar - G+_M G hbar (6N) of the wrenches `wrenches_on_object` (6N,
/// hbar_i = -h_i, at the grasp points, in {w}) relative to the weights' non-squeezing
/// distribution. Weights as in load_distribution(weights, r, ...): a list of CentralInertia
/// (e.g. model.end_effector_inertia_list()). noexcept: returns false, leaving `squeeze_out`
/// untouched, on degenerate weights (the test of try_distribute_load). May alias its input.
template <typename Weights, typename DerivedR, typename DerivedWrenches, typename DerivedOut,
          std::enable_if_t<detail::is_load_weight_list_v<Weights>, int> = 0>
bool try_squeeze_wrenches(const Weights& weights, const Eigen::MatrixBase<DerivedR>& r,
                          const Eigen::MatrixBase<DerivedWrenches>& wrenches_on_object,
                          const Eigen::MatrixBase<DerivedOut>& squeeze_out) noexcept
{
    COOPDYN_ASSERT(static_cast<Index>(weights.size()) == r.cols(), "one weight per arm");
    return detail::try_squeeze(weights, r, wrenches_on_object, squeeze_out);
}

/// \brief hbar_sq by value. Throws InvalidModel on invalid or degenerate weights (naming the
/// parameter and the arm, as load_distribution), InvalidArgument when `wrenches_on_object` does
/// not have 6N entries.
template <typename Weights, typename DerivedR, typename DerivedWrenches,
          std::enable_if_t<detail::is_load_weight_list_v<Weights>, int> = 0>
Eigen::Matrix<typename DerivedR::Scalar, times_six(DerivedR::ColsAtCompileTime), 1>
squeeze_wrenches(const Weights& weights, const Eigen::MatrixBase<DerivedR>& r,
                 const Eigen::MatrixBase<DerivedWrenches>& wrenches_on_object)
{
    detail::validate_load_weight_list(weights, r);
    if (wrenches_on_object.size() != 6 * r.cols()) {
        detail::fail(detail::argument_context("squeeze_wrenches"), "wrenches_on_object", "must have 6N entries");
    }
    using Result = Eigen::Matrix<typename DerivedR::Scalar, times_six(DerivedR::ColsAtCompileTime), 1>;
    Result result = Result::Zero(6 * r.cols());
    if (!detail::try_squeeze(weights, r, wrenches_on_object, result)) {
        detail::fail_degenerate_grasp();
    }
    return result;
}

/// \brief Per tick: the squeeze of the wrenches the arms apply to the object, hbar_i = -h_i with
/// h' = data.wrenches (after interaction_dynamics), relative to the weights of `distribution`
/// (by default the end-effector inertias), at the grasp configuration in `data`. Writes 6N
/// entries into `squeeze_out`. noexcept, allocation-free; the weights were validated when
/// `distribution` was built.
template <typename ModelType, typename DerivedOut>
void squeeze_wrenches(const LoadDistribution<ModelType>& distribution, const Data<ModelType>& data,
                      const Eigen::MatrixBase<DerivedOut>& squeeze_out) noexcept
{
    COOPDYN_REQUIRE_SHAPE(data.arms() == distribution.mass_weights().size(), "Data was built for another number of arms");
    COOPDYN_REQUIRE_SHAPE(squeeze_out.size() == 6 * data.arms(), "the squeeze must have 6N entries");
    const auto weights = detail::stacked_load_weights(distribution.mass_weights(), distribution.inertia_weights());
    const bool computed = detail::try_squeeze(weights, data.grasp_offsets, -data.end_effector_wrenches(), squeeze_out);
    COOPDYN_ASSERT(computed, "weights validated at construction cannot be degenerate");
    (void)computed;
}

}  // namespace coopdyn
