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
/// Entry points: the kernels `internal_wrenches` (general SPD M_i), `internal_wrenches_block_diagonal`
/// (M_i = diag(m_i I3, J_i)) and `external_wrenches`; for a Model, `decompose_wrenches` after
/// interaction_dynamics (allocation-free, into a WrenchDecomposition workspace).
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/dynamics/interaction_wrenches.hpp"
#include "coopdyn/model/cooperative_model.hpp"

#include <type_traits>

namespace coopdyn {

namespace detail {

/// The reduced-system solve of (53) with the given end-effector inertia structure: writes
/// h'_int (6N) and the commanded rigid accelerations xdd_i = G_i^T a_v + b_i (6N).
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
    SpatialPair<Scalar> no_object_wrench;
    const SpatialPair<Scalar> zero{Vector3<Scalar>::Zero(), Vector3<Scalar>::Zero()};
    solve_interaction(NoObject<Scalar>{}, end_effectors, r, omega_o, zero, h_motion, rigid_accelerations_out,
                      internal_out, no_object_wrench);
}

}  // namespace detail

/// \brief Internal end-effector wrenches h'_int of paper (53), structured O(N) form, general SPD
/// end-effector inertias.
/// \param ee_inertia 6 x 6N, the end-effector inertias M_i side by side (SPD each).
/// \param r 3 x N grasp offsets r_i in {w} (from the object's reference point).
/// \param omega_o object angular velocity in {w} (3); b_i = [w_o x (w_o x r_i); 0].
/// \param h_motion 6N, the motion wrenches h_i^x of (6) (or h_i^Pi of (20)) stacked.
/// \return h'_int, 6N; the internal wrench acting ON end-effector i is the block i.
/// Does not allocate when the arguments are fixed-size.
template <typename DerivedInertia, typename DerivedR, typename DerivedOmega, typename DerivedMotion>
EndEffectorVector<typename DerivedMotion::Scalar,
                  detail::first_fixed(DerivedR::ColsAtCompileTime,
                                      detail::arms_from_end_effector_rows(DerivedMotion::RowsAtCompileTime))>
internal_wrenches(const Eigen::MatrixBase<DerivedInertia>& ee_inertia, const Eigen::MatrixBase<DerivedR>& r,
                  const Eigen::MatrixBase<DerivedOmega>& omega_o, const Eigen::MatrixBase<DerivedMotion>& h_motion)
{
    constexpr int arms = detail::first_fixed(DerivedR::ColsAtCompileTime,
                                             detail::arms_from_end_effector_rows(DerivedMotion::RowsAtCompileTime));
    static_assert(detail::sizes_agree(DerivedR::ColsAtCompileTime,
                                      detail::arms_from_end_effector_rows(DerivedMotion::RowsAtCompileTime)),
                  "r (3 x N) and h_motion (6N) disagree on N");
    static_assert(detail::sizes_agree(DerivedInertia::ColsAtCompileTime, times_six(arms)),
                  "ee_inertia must be 6 x 6N");
    COOPDYN_ASSERT(ee_inertia.rows() == 6 && ee_inertia.cols() == 6 * r.cols(), "ee_inertia must be 6 x 6N");
    using Result = EndEffectorVector<typename DerivedMotion::Scalar, arms>;
    Result rigid_accelerations = Result::Zero(h_motion.size());
    Result internal = Result::Zero(h_motion.size());
    detail::solve_internal_wrenches(detail::GeneralEndEffectorInertias<DerivedInertia>{ee_inertia}, r, omega_o,
                                    h_motion, rigid_accelerations, internal);
    return internal;
}

/// \brief Internal end-effector wrenches h'_int of paper (53) for block-diagonal end-effector
/// inertias M_i = diag(m_i I3, J_i) (the impedance end-effector (1)): same result as
/// internal_wrenches with those matrices, through one 3x3 factorisation instead of a 6x6 one.
/// \param ee_masses N masses m_i > 0.
/// \param ee_rotational_inertias 3 x 3N, the J_i side by side (SPD each).
/// Other parameters as in internal_wrenches. Does not allocate when the arguments are fixed-size.
template <typename DerivedMasses, typename DerivedRotational, typename DerivedR, typename DerivedOmega,
          typename DerivedMotion>
EndEffectorVector<typename DerivedMotion::Scalar,
                  detail::first_fixed(DerivedR::ColsAtCompileTime,
                                      detail::arms_from_end_effector_rows(DerivedMotion::RowsAtCompileTime))>
internal_wrenches_block_diagonal(const Eigen::MatrixBase<DerivedMasses>& ee_masses,
                                 const Eigen::MatrixBase<DerivedRotational>& ee_rotational_inertias,
                                 const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedOmega>& omega_o,
                                 const Eigen::MatrixBase<DerivedMotion>& h_motion)
{
    constexpr int arms = detail::first_fixed(DerivedR::ColsAtCompileTime,
                                             detail::arms_from_end_effector_rows(DerivedMotion::RowsAtCompileTime));
    static_assert(detail::sizes_agree(DerivedR::ColsAtCompileTime,
                                      detail::arms_from_end_effector_rows(DerivedMotion::RowsAtCompileTime)),
                  "r (3 x N) and h_motion (6N) disagree on N");
    static_assert(detail::sizes_agree(DerivedMasses::SizeAtCompileTime, arms), "ee_masses must have N entries");
    static_assert(detail::sizes_agree(DerivedRotational::ColsAtCompileTime, times_three(arms)),
                  "ee_rotational_inertias must be 3 x 3N");
    COOPDYN_ASSERT(ee_masses.size() == r.cols(), "ee_masses must have N entries");
    COOPDYN_ASSERT(ee_rotational_inertias.rows() == 3 && ee_rotational_inertias.cols() == 3 * r.cols(),
                   "ee_rotational_inertias must be 3 x 3N");
    using Result = EndEffectorVector<typename DerivedMotion::Scalar, arms>;
    Result rigid_accelerations = Result::Zero(h_motion.size());
    Result internal = Result::Zero(h_motion.size());
    detail::solve_internal_wrenches(
        detail::BlockDiagonalEndEffectorInertias<DerivedMasses, DerivedRotational>{ee_masses, ee_rotational_inertias},
        r, omega_o, h_motion, rigid_accelerations, internal);
    return internal;
}

/// \brief External end-effector wrenches h'_ext = h' - h'_int of paper (54).
/// \param h_end_effectors 6N, the wrenches h' = [h_1; ...; h_N] acting on the end-effectors.
/// Other arguments as in internal_wrenches.
template <typename DerivedInertia, typename DerivedR, typename DerivedOmega, typename DerivedMotion,
          typename DerivedWrenches>
auto external_wrenches(const Eigen::MatrixBase<DerivedInertia>& ee_inertia, const Eigen::MatrixBase<DerivedR>& r,
                       const Eigen::MatrixBase<DerivedOmega>& omega_o, const Eigen::MatrixBase<DerivedMotion>& h_motion,
                       const Eigen::MatrixBase<DerivedWrenches>& h_end_effectors)
{
    COOPDYN_ASSERT(h_end_effectors.size() == h_motion.size(), "h' and h_motion must both have 6N entries");
    auto result = internal_wrenches(ee_inertia, r, omega_o, h_motion);
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
/// configuration in `data`. The block-diagonal fast path is chosen at compile time from the
/// end-effector model, as in interaction_dynamics. noexcept; allocation-free.
template <typename ModelType>
const WrenchDecomposition<ModelType>& decompose_wrenches(const ModelType& model, const Data<ModelType>& data,
                                                         WrenchDecomposition<ModelType>& decomposition) noexcept
{
    COOPDYN_ASSERT(decomposition.arms() == model.arms(), "decomposition sized for another number of arms");
    const auto omega_o = data.object_state.twist.template tail<3>();
    if constexpr (ModelType::EndEffectorModel::has_block_diagonal_inertia) {
        using Masses = std::decay_t<decltype(model.end_effector_masses())>;
        using Rotational = std::decay_t<decltype(model.end_effector_rotational_inertias())>;
        detail::solve_internal_wrenches(
            detail::BlockDiagonalEndEffectorInertias<Masses, Rotational>{model.end_effector_masses(),
                                                                         model.end_effector_rotational_inertias()},
            data.grasp_offsets, omega_o, data.motion_wrenches, decomposition.rigid_accelerations,
            decomposition.internal);
    } else {
        using Inertias = std::decay_t<decltype(model.end_effector_inertias())>;
        detail::solve_internal_wrenches(detail::GeneralEndEffectorInertias<Inertias>{model.end_effector_inertias()},
                                        data.grasp_offsets, omega_o, data.motion_wrenches,
                                        decomposition.rigid_accelerations, decomposition.internal);
    }
    decomposition.external = data.end_effector_wrenches() - decomposition.internal;
    return decomposition;
}

}  // namespace coopdyn
