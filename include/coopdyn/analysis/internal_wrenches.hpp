/// \file
/// \brief Internal and external end-effector wrenches (paper (53)-(54), docs/analysis.md,
/// errata E5).
///
/// The internal wrench is the part of the end-effector wrenches that squeezes the object without
/// moving it. It is the constraint wrench of the reduced system: the N end-effectors without the
/// object, driven by their motion wrenches h_i^x (6) alone and constrained to move as one rigid
/// body,
///
///     h'_int = M'^(1/2) (A' M'^(-1/2))^+ (b' - A' M'^-1 h'^x),     h'_ext = h' - h'_int   (53)-(54)
///
/// with 6(N-1) relative constraints A' xdd' = b' (E5). It is computed here in the structured form:
/// the rigid motion is parameterised by a virtual acceleration a_v of the object's reference point,
/// xdd_i = G_i^T a_v + b_i, so that
///
///     (sum_i G_i M_i G_i^T) a_v = sum_i G_i (h_i^x - M_i b_i),    h_int,i = M_i (G_i^T a_v + b_i) - h_i^x.
///
/// This is exactly the object-free case of the interaction solve (docs/dynamics.md), so it
/// reuses that code. Properties: G h'_int = 0 (internal wrenches do no work on rigid motions,
/// Definition 1); h'_int = 0 whenever the commanded motion is rigid; G h'_ext = G h'.
///
/// Entry points: the kernels `internal_wrenches` (any inertia structure, chosen by the inertias'
/// type) and `external_wrenches`; for a Model, `decompose_wrenches` after
/// interaction_dynamics (allocation-free, into a WrenchDecomposition workspace).
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/dynamics/interaction_wrenches.hpp"
#include "coopdyn/model/cooperative_model.hpp"

#include <type_traits>

namespace coopdyn {

namespace detail {

/// The reduced-system solve of (53): the interaction solve without an object (a zero object
/// inertia and wrench). Writes h'_int (6N) and the commanded rigid accelerations
/// xdd_i = G_i^T a_v + b_i (6N).
template <typename EndEffectorInertias, typename DerivedR, typename DerivedOmega, typename DerivedMotion,
          typename DerivedAcceleration, typename DerivedInternal>
void solve_internal_wrenches(const EndEffectorInertias& end_effectors, const Eigen::MatrixBase<DerivedR>& r,
                             const Eigen::MatrixBase<DerivedOmega>& omega_o,
                             const Eigen::MatrixBase<DerivedMotion>& h_motion,
                             const Eigen::MatrixBase<DerivedAcceleration>& rigid_accelerations_out,
                             const Eigen::MatrixBase<DerivedInternal>& internal_out) noexcept
{
    using Scalar = typename DerivedMotion::Scalar;
    COOPDYN_ASSERT(h_motion.size() == 6 * r.cols(), "h_motion must have 6N entries");
    // Written by the solve; zeroed only because g++ cannot see that (-Wmaybe-uninitialized).
    Vector6<Scalar> virtual_acceleration = Vector6<Scalar>::Zero();  // a_v of (53)
    Vector6<Scalar> no_object_wrench = Vector6<Scalar>::Zero();
    solve_interaction(element_inertia_t<EndEffectorInertias>::Zero(), end_effectors, r, omega_o,
                      Force<Scalar>::Zero(), h_motion, rigid_accelerations_out, internal_out, virtual_acceleration,
                      no_object_wrench);
}

/// Number of arms of an internal-wrench call, fixed when r or h_motion fixes it.
template <typename DerivedR, typename DerivedMotion> constexpr int internal_arms() noexcept
{
    static_assert(sizes_agree(DerivedR::ColsAtCompileTime, arms_from_end_effector_rows(DerivedMotion::RowsAtCompileTime)),
                  "r (3 x N) and h_motion (6N) disagree on N");
    return first_fixed(DerivedR::ColsAtCompileTime, arms_from_end_effector_rows(DerivedMotion::RowsAtCompileTime));
}

}  // namespace detail

/// \brief Internal end-effector wrenches h'_int of paper (53), structured O(N) form, written into
/// caller storage with the commanded rigid accelerations. Never allocates; noexcept.
/// \param ee_inertias the M_i: a container of CentralInertia, SpatialInertia or ArticulatedInertia
///        (one per arm), or a dense 6 x 6N stack of SPD blocks; the inertias' type chooses the solver's path.
/// \param r 3 x N grasp offsets r_i in {w} (from the object's reference point).
/// \param omega_o object angular velocity in {w} (3); b_i = [w_o x (w_o x r_i); 0].
/// \param h_motion 6N, the motion wrenches h_i^x of (6) (or h_i^Pi of (20)) stacked.
/// \param rigid_accelerations_out 6N, xdd_i = G_i^T a_v + b_i of the reduced system (written).
/// \param internal_out 6N, h'_int: block i is the internal wrench acting ON end-effector i (written).
template <typename EndEffectorInertias, typename DerivedR, typename DerivedOmega, typename DerivedMotion,
          typename DerivedAcceleration, typename DerivedInternal>
void internal_wrenches(const EndEffectorInertias& ee_inertias, const Eigen::MatrixBase<DerivedR>& r,
                       const Eigen::MatrixBase<DerivedOmega>& omega_o, const Eigen::MatrixBase<DerivedMotion>& h_motion,
                       const Eigen::MatrixBase<DerivedAcceleration>& rigid_accelerations_out,
                       const Eigen::MatrixBase<DerivedInternal>& internal_out) noexcept
{
    (void)detail::internal_arms<DerivedR, DerivedMotion>();
    detail::solve_internal_wrenches(detail::as_inertia_sequence(ee_inertias), r, omega_o, h_motion,
                                    rigid_accelerations_out, internal_out);
}

/// \brief Internal end-effector wrenches h'_int of paper (53), returned (6N). Arguments as in the
/// overload with outputs. Does not allocate when the arguments are fixed-size.
template <typename EndEffectorInertias, typename DerivedR, typename DerivedOmega, typename DerivedMotion>
EndEffectorVector<typename DerivedMotion::Scalar, detail::internal_arms<DerivedR, DerivedMotion>()>
internal_wrenches(const EndEffectorInertias& ee_inertias, const Eigen::MatrixBase<DerivedR>& r,
                  const Eigen::MatrixBase<DerivedOmega>& omega_o, const Eigen::MatrixBase<DerivedMotion>& h_motion)
{
    using Result = EndEffectorVector<typename DerivedMotion::Scalar, detail::internal_arms<DerivedR, DerivedMotion>()>;
    // Zero-initialised although every entry is written: GCC 12 cannot see that through the solve.
    Result rigid_accelerations = Result::Zero(h_motion.size());
    Result internal = Result::Zero(h_motion.size());
    internal_wrenches(ee_inertias, r, omega_o, h_motion, rigid_accelerations, internal);
    return internal;
}

/// \brief External end-effector wrenches h'_ext = h' - h'_int of paper (54).
/// \param h_end_effectors 6N, the wrenches h' = [h_1; ...; h_N] acting on the end-effectors.
/// Other arguments as in internal_wrenches.
template <typename EndEffectorInertias, typename DerivedR, typename DerivedOmega, typename DerivedMotion,
          typename DerivedWrenches>
auto external_wrenches(const EndEffectorInertias& ee_inertias, const Eigen::MatrixBase<DerivedR>& r,
                       const Eigen::MatrixBase<DerivedOmega>& omega_o, const Eigen::MatrixBase<DerivedMotion>& h_motion,
                       const Eigen::MatrixBase<DerivedWrenches>& h_end_effectors)
{
    COOPDYN_ASSERT(h_end_effectors.size() == h_motion.size(), "h' and h_motion must both have 6N entries");
    auto result = internal_wrenches(ee_inertias, r, omega_o, h_motion);
    result = h_end_effectors - result;
    return result;
}

/// \brief Per-tick split of every arm's wrench into internal and external parts for a Model
/// (the workspace of decompose_wrenches). Sized once from the Model; nothing allocates later.
template <typename ModelType> struct WrenchDecomposition {
    using Scalar = typename ModelType::Scalar;
    static constexpr int Arms = ModelType::arms_at_compile_time;

    explicit WrenchDecomposition(const ModelType& model)
        : internal(EndEffectorVector<Scalar, Arms>::Zero(6 * model.arms())),
          external(EndEffectorVector<Scalar, Arms>::Zero(6 * model.arms())),
          rigid_accelerations(EndEffectorVector<Scalar, Arms>::Zero(6 * model.arms()))
    {
    }

    EndEffectorVector<Scalar, Arms> internal;             ///< h'_int (53), 6N
    EndEffectorVector<Scalar, Arms> external;             ///< h'_ext = h' - h'_int (54), 6N
    EndEffectorVector<Scalar, Arms> rigid_accelerations;  ///< G_i^T a_v + b_i of the reduced system, 6N

    Index arms() const noexcept { return internal.size() / 6; }
    auto internal_wrench(Index arm) const noexcept { return internal.template segment<6>(6 * arm); }
    auto external_wrench(Index arm) const noexcept { return external.template segment<6>(6 * arm); }
};

/// \brief Split the end-effector wrenches h' in `data` (after interaction_dynamics) into internal
/// (53) and external (54) parts, from the motion wrenches data.motion_wrenches at the grasp
/// configuration in `data`. The solver's path is chosen at compile time from the end-effector
/// model's inertia type, as in interaction_dynamics. noexcept; allocation-free.
template <typename ModelType>
const WrenchDecomposition<ModelType>& decompose_wrenches(const ModelType& model, const Data<ModelType>& data,
                                                         WrenchDecomposition<ModelType>& decomposition) noexcept
{
    COOPDYN_REQUIRE_SHAPE(decomposition.arms() == model.arms(), "decomposition sized for another number of arms");
    internal_wrenches(model.end_effector_inertia_list(), data.grasp_offsets, data.object_state.twist.template tail<3>(),
                      data.motion_wrenches, decomposition.rigid_accelerations, decomposition.internal);
    decomposition.external = data.end_effector_wrenches() - decomposition.internal;
    return decomposition;
}

}  // namespace coopdyn
