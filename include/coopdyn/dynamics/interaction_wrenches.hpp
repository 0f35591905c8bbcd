/// \file
/// \brief Structured O(N) interaction wrench of the rigid grasp (docs/dynamics.md): the
/// Udwadia-Kalaba solution (18) computed in the object's reduced coordinates.
///
/// With G_i = [[I3, 0], [S(r_i), I3]] and b_i = [S(w_o)^2 r_i; 0]:
///
///     Ma = M_o + sum_i G_i M_i G_i^T
///     Ma xdd_o = hSigma_o + sum_i G_i (hSigma_i - M_i b_i)
///     xdd_i = G_i^T xdd_o + b_i,   h_o = M_o xdd_o - hSigma_o,   h_i = M_i xdd_i - hSigma_i
///
/// This is (18) restricted to the constraint manifold A xdd = b: the accelerations are the
/// minimiser of Gauss's function (19), written in the N + 1 bodies' common rigid motion.
/// One 6x6 solve per tick; everything else is per-arm 3-vector algebra.
///
/// One overload set, `interaction_wrenches`, for every inertia structure; the inertias' types
/// choose the path at compile time:
/// - CentralInertia (diag(m I3, J) bodies, e.g. the impedance end-effector (1)) or
///   SpatialInertia: Ma is a rigid-body inertia, solved in closed form through its 3x3
///   rotational Schur complement (SpatialInertia::solve);
/// - ArticulatedInertia, or dense 6x6 matrices (general SPD, e.g. the resolved-acceleration
///   Lambda_i of (21)): Ma is a general SPD 6x6, factorised (ArticulatedInertia::solve).
/// End-effector inertias are passed as a 6 x 6N dense stack or as any random-access container of
/// CentralInertia / SpatialInertia / ArticulatedInertia (std::array, std::vector, Model::end_effector_inertia_list()).
///
/// Arguments follow the kernels' order (docs/conventions.md): inertias, geometry r, state omega_o,
/// inputs h_sigma, then outputs.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/spatial/inertia.hpp"
#include "coopdyn/spatial/spatial_vector.hpp"

#include <cstddef>
#include <type_traits>

namespace coopdyn {
namespace detail {

template <typename T> struct is_spatial_inertia : std::false_type {};
template <typename Scalar> struct is_spatial_inertia<SpatialInertia<Scalar>> : std::true_type {};
template <typename Scalar> struct is_spatial_inertia<ArticulatedInertia<Scalar>> : std::true_type {};
template <typename Scalar> struct is_spatial_inertia<CentralInertia<Scalar>> : std::true_type {};

/// Rigid-body inertias (central or not) sum to a rigid-body inertia.
template <typename T> struct is_rigid_body_inertia : std::false_type {};
template <typename Scalar> struct is_rigid_body_inertia<SpatialInertia<Scalar>> : std::true_type {};
template <typename Scalar> struct is_rigid_body_inertia<CentralInertia<Scalar>> : std::true_type {};

/// An object inertia argument as a spatial type: dense 6x6 matrices become ArticulatedInertia.
template <typename Derived>
ArticulatedInertia<typename Derived::Scalar> as_inertia(const Eigen::MatrixBase<Derived>& matrix) noexcept
{
    COOPDYN_ASSERT(matrix.rows() == 6 && matrix.cols() == 6, "an inertia must be 6x6");
    return ArticulatedInertia<typename Derived::Scalar>(matrix.template topLeftCorner<6, 6>());
}
template <typename Inertia, std::enable_if_t<is_spatial_inertia<Inertia>::value, int> = 0>
const Inertia& as_inertia(const Inertia& inertia) noexcept
{
    return inertia;
}

/// The end-effector inertias of a dense 6 x 6N stack, read block by block as ArticulatedInertia.
template <typename Derived> struct DenseInertiaStack {
    const Eigen::MatrixBase<Derived>& stack;
    ArticulatedInertia<typename Derived::Scalar> operator[](std::size_t arm) const noexcept
    {
        return ArticulatedInertia<typename Derived::Scalar>(stack.template block<6, 6>(0, 6 * static_cast<Index>(arm)));
    }
    std::size_t size() const noexcept { return static_cast<std::size_t>(stack.cols() / 6); }
};

/// End-effector inertia arguments as an indexable sequence of spatial inertias.
template <typename Derived> DenseInertiaStack<Derived> as_inertia_sequence(const Eigen::MatrixBase<Derived>& stack) noexcept
{
    COOPDYN_ASSERT(stack.rows() == 6 && stack.cols() % 6 == 0, "end-effector inertias must be 6 x 6N");
    return DenseInertiaStack<Derived>{stack};
}
template <typename Container,
          std::enable_if_t<is_spatial_inertia<std::decay_t<decltype(std::declval<const Container&>()[std::size_t(0)])>>::value,
                           int> = 0>
const Container& as_inertia_sequence(const Container& inertias) noexcept
{
    return inertias;
}

/// The inertia type of one element of an inertia sequence.
template <typename Sequence>
using element_inertia_t = std::decay_t<decltype(std::declval<const Sequence&>()[std::size_t(0)])>;

/// The composite inertia's type: a rigid-body inertia when every part is one, general otherwise.
template <typename ObjectInertia, typename EndEffectorInertia>
using composite_inertia_t =
    std::conditional_t<is_rigid_body_inertia<ObjectInertia>::value && is_rigid_body_inertia<EndEffectorInertia>::value,
                       SpatialInertia<typename ObjectInertia::Scalar>, ArticulatedInertia<typename ObjectInertia::Scalar>>;

template <typename Composite, typename Inertia> Composite composite_from(const Inertia& inertia) noexcept
{
    if constexpr (std::is_same_v<Composite, Inertia>) {
        return inertia;
    } else {
        return Composite(inertia);
    }
}

/// The structured solve (docs/dynamics.md), for any inertia structure. Writes the arms'
/// accelerations and wrenches (6N each) and the object's acceleration and wrench (6 each, as
/// stacked 6-vectors). The object's acceleration is a local written out at the end: returned as a
/// Motion, it lived in the caller's memory, and g++ 12 reloaded its scalar stores with packet loads
/// that straddle them (a store-forwarding stall per arm, and one more in the caller).
template <typename ObjectInertia, typename EndEffectorInertias, typename DerivedR, typename DerivedOmega,
          typename DerivedSigma, typename DerivedAcceleration, typename DerivedWrench, typename DerivedObjectAcceleration,
          typename DerivedObjectWrench>
void solve_interaction(const ObjectInertia& object, const EndEffectorInertias& end_effectors,
                  const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedOmega>& omega_o,
                  const Force<typename DerivedSigma::Scalar>& object_h_sigma,
                  const Eigen::MatrixBase<DerivedSigma>& arm_h_sigma,
                  const Eigen::MatrixBase<DerivedAcceleration>& arm_accelerations_out,
                  const Eigen::MatrixBase<DerivedWrench>& arm_wrenches_out,
                  const Eigen::MatrixBase<DerivedObjectAcceleration>& object_acceleration_out,
                  const Eigen::MatrixBase<DerivedObjectWrench>& object_wrench_out) noexcept
{
    using Scalar = typename DerivedSigma::Scalar;
    using Composite = composite_inertia_t<ObjectInertia, element_inertia_t<EndEffectorInertias>>;
    // Eigen's documented idiom for writable expression arguments (blocks, maps, matrices).
    auto& arm_accelerations = const_cast<Eigen::MatrixBase<DerivedAcceleration>&>(arm_accelerations_out);
    auto& arm_wrenches = const_cast<Eigen::MatrixBase<DerivedWrench>&>(arm_wrenches_out);
    const Index arms = r.cols();
    COOPDYN_ASSERT(arms >= 1, "at least one arm");
    COOPDYN_ASSERT(static_cast<Index>(end_effectors.size()) == arms, "one end-effector inertia per arm");
    COOPDYN_ASSERT(arm_h_sigma.size() == 6 * arms, "h_sigma must have 6(N+1) entries");
    COOPDYN_ASSERT(arm_accelerations_out.size() == 6 * arms, "accelerations must have 6(N+1) entries");
    COOPDYN_ASSERT(arm_wrenches_out.size() == 6 * arms, "wrenches must have 6(N+1) entries");

    // 3-vectors are built from scalars on this path (see detail::cross for why).
    const Vector3<Scalar> omega(omega_o(0), omega_o(1), omega_o(2));
    Composite composite = composite_from<Composite>(object);
    Force<Scalar> rhs = object_h_sigma;
    COOPDYN_UNROLL_BY_2
    for (Index i = 0; i < arms; ++i) {
        const Vector3<Scalar> r_i(r(0, i), r(1, i), r(2, i));
        const auto& inertia = end_effectors[static_cast<std::size_t>(i)];
        composite.add_shifted(inertia, r_i);
        // G_i (hSigma_i - M_i b_i), b_i = [S(w_o)^2 r_i; 0]
        rhs += (Force<Scalar>::from(arm_h_sigma.template segment<6>(6 * i)) -
                inertia.apply_translation(centripetal_acceleration(r_i, omega)))
                   .shifted(r_i);
    }

    const Motion<Scalar> object_acceleration = composite.solve(rhs);
    COOPDYN_UNROLL_BY_2
    for (Index i = 0; i < arms; ++i) {
        const Vector3<Scalar> r_i(r(0, i), r(1, i), r(2, i));
        // xdd_i = G_i^T xdd_o + b_i, h_i = M_i xdd_i - hSigma_i
        Motion<Scalar> acceleration = object_acceleration.at_point(r_i);
        acceleration += Motion<Scalar>::make(centripetal_acceleration(r_i, omega), Vector3<Scalar>::Zero());
        acceleration.write_to(arm_accelerations.template segment<6>(6 * i));
        (end_effectors[static_cast<std::size_t>(i)] * acceleration - Force<Scalar>::from(arm_h_sigma.template segment<6>(6 * i)))
            .write_to(arm_wrenches.template segment<6>(6 * i));
    }
    object_acceleration.write_to(object_acceleration_out);
    (object * object_acceleration - object_h_sigma).write_to(object_wrench_out);
}

/// The end-effector part (last 6N entries) of a 6(N+1) stack, fixed-size when N is.
template <int Arms, typename Stack> auto arm_part(Stack& stack) noexcept
{
    if constexpr (Arms == Eigen::Dynamic) {
        return stack.tail(stack.size() - 6);
    } else {
        return stack.template tail<6 * Arms>();
    }
}

/// Number of arms of a kernel call, fixed when any argument fixes it.
template <typename DerivedR, typename DerivedSigma> constexpr int kernel_arms() noexcept
{
    static_assert(sizes_agree(DerivedR::ColsAtCompileTime, arms_from_full_rows(DerivedSigma::RowsAtCompileTime)),
                  "r (3 x N) and h_sigma (6(N+1)) disagree on N");
    return first_fixed(DerivedR::ColsAtCompileTime, arms_from_full_rows(DerivedSigma::RowsAtCompileTime));
}

}  // namespace detail

/// \brief Accelerations and interaction wrenches of the rigid grasp, written into caller-owned
/// storage (docs/dynamics.md; equals (18)). Never allocates; noexcept.
/// \param object_inertia M_o in {w}: a CentralInertia (diag(m_o I3, J_o), (9)), a
///        SpatialInertia, an ArticulatedInertia, or a dense 6x6 SPD matrix.
/// \param ee_inertias the M_i: a container of CentralInertia, SpatialInertia or
///        ArticulatedInertia (one per arm), or a dense 6 x 6N stack of SPD blocks; the inertias'
///        type chooses the solver's path (CentralInertia throughout is the fast one).
/// \param r 3 x N grasp offsets r_i in {w}.
/// \param omega_o object angular velocity in {w} (3).
/// \param h_sigma 6(N+1): [hSigma_o; hSigma_1; ...; hSigma_N] of (15)-(16).
/// \param accelerations_out 6(N+1): xdd = [xdd_o; xdd_1; ...] (written).
/// \param wrenches_out 6(N+1): h = [h_o; h_1; ...], the wrenches acting on each body (written).
template <typename ObjectInertia, typename EndEffectorInertias, typename DerivedR, typename DerivedOmega,
          typename DerivedSigma, typename DerivedAcceleration, typename DerivedWrench>
void interaction_wrenches(const ObjectInertia& object_inertia, const EndEffectorInertias& ee_inertias,
                          const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedOmega>& omega_o,
                          const Eigen::MatrixBase<DerivedSigma>& h_sigma,
                          const Eigen::MatrixBase<DerivedAcceleration>& accelerations_out,
                          const Eigen::MatrixBase<DerivedWrench>& wrenches_out) noexcept
{
    using Scalar = typename DerivedSigma::Scalar;
    constexpr int arms = detail::kernel_arms<DerivedR, DerivedSigma>();
    COOPDYN_ASSERT(h_sigma.size() == 6 * (r.cols() + 1), "h_sigma must have 6(N+1) entries");
    COOPDYN_ASSERT(accelerations_out.size() == 6 * (r.cols() + 1), "accelerations must have 6(N+1) entries");
    COOPDYN_ASSERT(wrenches_out.size() == 6 * (r.cols() + 1), "wrenches must have 6(N+1) entries");
    // Eigen's documented idiom for writable expression arguments (blocks, maps, matrices).
    auto& accelerations = const_cast<Eigen::MatrixBase<DerivedAcceleration>&>(accelerations_out);
    auto& wrenches = const_cast<Eigen::MatrixBase<DerivedWrench>&>(wrenches_out);
    detail::solve_interaction(detail::as_inertia(object_inertia), detail::as_inertia_sequence(ee_inertias), r, omega_o,
                              Force<Scalar>::from(h_sigma.template head<6>()), detail::arm_part<arms>(h_sigma),
                              detail::arm_part<arms>(accelerations), detail::arm_part<arms>(wrenches),
                              accelerations.template head<6>(), wrenches.template head<6>());
}

/// \brief Interaction wrenches h = [h_o; h_1; ...; h_N] (6(N+1)) of the rigid grasp: the
/// structured O(N) form of (18), docs/dynamics.md. Arguments as in the overload with outputs.
/// Does not allocate when the arguments are fixed-size.
template <typename ObjectInertia, typename EndEffectorInertias, typename DerivedR, typename DerivedOmega,
          typename DerivedSigma>
FullStackVector<typename DerivedSigma::Scalar, detail::kernel_arms<DerivedR, DerivedSigma>()>
interaction_wrenches(const ObjectInertia& object_inertia, const EndEffectorInertias& ee_inertias,
                     const Eigen::MatrixBase<DerivedR>& r, const Eigen::MatrixBase<DerivedOmega>& omega_o,
                     const Eigen::MatrixBase<DerivedSigma>& h_sigma)
{
    using Result = FullStackVector<typename DerivedSigma::Scalar, detail::kernel_arms<DerivedR, DerivedSigma>()>;
    Result accelerations(h_sigma.size());
    Result wrenches(h_sigma.size());
    interaction_wrenches(object_inertia, ee_inertias, r, omega_o, h_sigma, accelerations, wrenches);
    return wrenches;
}

}  // namespace coopdyn
