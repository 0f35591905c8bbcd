/// \file
/// \brief The grasp's pseudo-inverses from one implementation (docs/model.md, "Grasp inverse"):
/// the weighted generalized inverse of (25) (errata E2),
///
///     G+_W = W G^T (G W G^T)^-1,   W = blkdiag(M*_1, ..., M*_K),   M*_i = diag(m*_i I3, J*_i),
///
/// which the load distribution uses with the weights of docs/coordination.md, and with unit
/// weights (M*_i = I6) the Moore-Penrose pseudo-inverse G^+ = G^T (G G^T)^-1 of the second paper's
/// projection (docs/control.md). The grasp Jacobians Jx = (G G^T)^-1 G J and Jc = (I - G^+ G) J
/// built on it are in grasp_jacobians.hpp.
///
/// Method (WeightedGrasp): G W G^T = sum_i G(r_i) M*_i G(r_i)^T is the composite inertia of the
/// weights placed at the grasp points (the shift of (31), SpatialInertia::add_shifted). About the
/// weights' centroid c = sum m*_i r_i / m*_o it is block diagonal, diag(m*_o I3, J*_o) with
/// J*_o = sum J*_i + sum m*_i S(r'_i) S(r'_i)^T, r'_i = r_i - c, so
///
///     (G W G^T)^-1 h = G(-c)^T z,   z = diag(m*_o I3, J*_o)^-1 G(-c) h,   (G+_W h)_i = M*_i G(r'_i)^T z:
///
/// one 3x3 factorisation (of J*_o) per grasp, then O(K) per right-hand side, G never formed. With
/// unit weights J*_o >= K I3, never singular.
///
/// `r` is 3 x K: column i is r_i, from the object's centre of mass to grasp point i, in {w}.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/model/grasp.hpp"
#include "coopdyn/numerics/fixed_ldlt.hpp"
#include "coopdyn/numerics/pivot_policy.hpp"
#include "coopdyn/spatial/inertia.hpp"
#include "coopdyn/spatial/spatial_vector.hpp"
#include "coopdyn/spatial/symmetric3.hpp"

#include <cstddef>

namespace coopdyn {
namespace detail {

/// Smallest over largest pivot of the diagonally pivoted L D L^T factorisation of a symmetric 3x3
/// matrix; not positive when the matrix is not positive definite (or holds NaN). The largest pivot
/// is the largest diagonal entry (it is chosen first), so the ratio is the pivot policy's
/// d_min / max_i A_ii (numerics/pivot_policy.hpp).
///
/// Why pivoted: for a symmetric positive semi-definite matrix every pivot lies between the
/// extreme eigenvalues, and with the largest remaining diagonal entry chosen first the last pivot
/// is within a small factor of the smallest eigenvalue (rank revealing: over random 3x3 matrices
/// the ratio returned here was between 1 and 16 times lambda_min / lambda_max, never below
/// it). The unpivoted factor is not: for a matrix that is
/// singular up to rounding (two grasp points with zero rotational weights) its smallest pivot can
/// stay far above the rounding level, or come out positive by chance, and the singular J*_o was
/// then inverted (it happened for about half of random degenerate two-arm grasps).
template <typename Scalar> Scalar pivot_ratio(const Matrix3<Scalar>& matrix) noexcept
{
    int first = 0;
    if (matrix(1, 1) > matrix(first, first)) {
        first = 1;
    }
    if (matrix(2, 2) > matrix(first, first)) {
        first = 2;
    }
    const int second = (first + 1) % 3;
    const int third = (first + 2) % 3;
    const Scalar largest = matrix(first, first);
    if (!(largest > Scalar(0))) {
        return Scalar(0);
    }
    // Schur complement of the first pivot on the remaining two indices.
    const Scalar s22 = matrix(second, second) - matrix(second, first) * matrix(second, first) / largest;
    const Scalar s33 = matrix(third, third) - matrix(third, first) * matrix(third, first) / largest;
    const Scalar s23 = matrix(second, third) - matrix(second, first) * matrix(third, first) / largest;
    const bool second_first = s22 >= s33;
    const Scalar middle = second_first ? s22 : s33;
    const Scalar other = second_first ? s33 : s22;
    if (!(middle > Scalar(0))) {
        return Scalar(0);
    }
    return (other - s23 * s23 / middle) / largest;
}

/// The unit weights M*_i = I6 of K arms, as a list of CentralInertia (the interface of the load
/// distribution's weights): with them WeightedGrasp is the Moore-Penrose pseudo-inverse G^+.
template <typename Scalar> struct UnitGraspWeights {
    Index arms;
    CentralInertia<Scalar> operator[](std::size_t) const noexcept
    {
        return CentralInertia<Scalar>(Scalar(1), Symmetric3<Scalar>::scaled_identity(Scalar(1)));
    }
    std::size_t size() const noexcept { return static_cast<std::size_t>(arms); }
};

/// The weights M*_i = diag(m*_i I3, J*_i) placed at the grasp points r_i, seen from the point
/// `about`: the composite sum_i G(r_i - about) M*_i G(r_i - about)^T (SpatialInertia::add_shifted).
/// Its mass is m*_o and, about the weighted centroid, its rotational inertia is J*_o of (25).
template <typename Weights, typename DerivedR>
SpatialInertia<typename DerivedR::Scalar> composite_of_weights(const Weights& weights, const Eigen::MatrixBase<DerivedR>& r,
                                                               const Vector3<typename DerivedR::Scalar>& about) noexcept
{
    SpatialInertia<typename DerivedR::Scalar> composite;
    for (Index i = 0; i < r.cols(); ++i) {
        composite.add_shifted(weights[static_cast<std::size_t>(i)], r.col(i).template head<3>() - about);
    }
    return composite;
}

/// G G^T = G I6 G^T as a spatial inertia about the object's centre: the composite of unit masses
/// with unit rotational inertia at the contacts, G_i G_i^T = [[I, S(r_i)^T], [S(r_i), I + S(r_i)
/// S(r_i)^T]], the shift of (31).
template <typename DerivedR>
SpatialInertia<typename DerivedR::Scalar> grasp_gram_inertia(const Eigen::MatrixBase<DerivedR>& r) noexcept
{
    using Scalar = typename DerivedR::Scalar;
    return composite_of_weights(UnitGraspWeights<Scalar>{r.cols()}, r, Vector3<Scalar>::Zero());
}

/// The weighted grasp of (25), the one implementation of G+_W and G^+ (the file comment): the
/// composite of the weights about their centroid c (mass m*_o, rotational inertia J*_o) and the
/// factor of J*_o. `valid` is false when a mass weight is not positive or J*_o is singular by the
/// pivot policy (numerics/pivot_policy.hpp; checked on pivot_ratio).
///
/// The distribution is the rigid motion of that composite body: the object wrench shifted to c
/// gives it the motion z = (M*_o)^-1 h_c = [f / m*_o; (J*_o)^-1 t_c], and arm i takes
/// hbar_i = M*_i G(r'_i)^T z, r'_i = r_i - c (the least-norm W G^T (G W G^T)^-1 h_o, block row i
/// of (25) with E2). J*_o is accumulated about c itself rather than taken from the composite
/// about the centre of mass (rotational_about_centre), which would subtract m*_o S(c) S(c)^T from
/// a sum that contains it and lose the digits of a nearly singular J*_o.
template <typename Scalar> struct WeightedGrasp {
    Vector3<Scalar> centroid = Vector3<Scalar>::Zero();  // c, relative to the object's centre of mass
    CentralInertia<Scalar> composite;                     // diag(m*_o I3, J*_o) about c
    FixedLdlt<Scalar, 3> rotational_factor;               // of J*_o
    bool valid = false;

    /// Storage for compute() (a workspace member, e.g. ProjectedDynamics's); not valid.
    WeightedGrasp() = default;

    template <typename Weights, typename DerivedR>
    WeightedGrasp(const Weights& weights, const Eigen::MatrixBase<DerivedR>& r) noexcept
    {
        compute(weights, r);
    }

    /// The composite and its factor for these weights and grasp points; returns valid.
    template <typename Weights, typename DerivedR>
    bool compute(const Weights& weights, const Eigen::MatrixBase<DerivedR>& r) noexcept
    {
        bool positive_masses = true;
        for (Index i = 0; i < r.cols(); ++i) {
            positive_masses = positive_masses && weights[static_cast<std::size_t>(i)].mass() > Scalar(0);
        }
        const SpatialInertia<Scalar> about_centre_of_mass = composite_of_weights(weights, r, Vector3<Scalar>::Zero());
        centroid = about_centre_of_mass.centre();
        composite = CentralInertia<Scalar>(about_centre_of_mass.mass(),
                                           composite_of_weights(weights, r, centroid).rotational());
        const Matrix3<Scalar> rotational = composite.rotational().matrix();
        const bool factored = rotational_factor.compute(rotational);
        // The pivot policy on the pivoted factorisation (the ratio is already relative: scale 1).
        valid = positive_masses && factored && regular_pivot(pivot_ratio(rotational), Scalar(1));
        return valid;
    }

    /// z = [f / m*_o; (J*_o)^-1 t_c] with t_c = t_o - c x f, for the object wrench h_o at the
    /// object's centre of mass: the composite's motion, about c.
    Motion<Scalar> composite_motion(const Force<Scalar>& object_wrench) const noexcept
    {
        const Force<Scalar> at_centroid = object_wrench.shifted(Vector3<Scalar>(-centroid));
        return Motion<Scalar>::make(at_centroid.linear / composite.mass(),
                                    rotational_factor.solve(at_centroid.angular));
    }

    /// (G W G^T)^-1 h_o = G(-c)^T z: the composite's motion about the object's centre of mass (for
    /// unit weights the object twist of the least-squares rigid motion, Jx's column solve).
    Motion<Scalar> solve(const Force<Scalar>& object_wrench) const noexcept
    {
        return composite_motion(object_wrench).at_point(Vector3<Scalar>(-centroid));
    }

    /// hbar_i = M*_i G(r_i - c)^T z: arm i's share of the object wrench whose composite motion is z.
    template <typename Weights, typename DerivedR>
    Force<Scalar> share(const Weights& weights, const Eigen::MatrixBase<DerivedR>& r, Index arm,
                        const Motion<Scalar>& motion) const noexcept
    {
        return weights[static_cast<std::size_t>(arm)] * motion.at_point(Vector3<Scalar>(r.col(arm).template head<3>() - centroid));
    }

    /// out -= G+_W h_o (6K; `out` may hold anything of that size).
    template <typename Weights, typename DerivedR, typename DerivedOut>
    void subtract_inverse_times(const Weights& weights, const Eigen::MatrixBase<DerivedR>& r,
                                const Force<Scalar>& object_wrench, const Eigen::MatrixBase<DerivedOut>& out_) const noexcept
    {
        auto& out = const_cast<Eigen::MatrixBase<DerivedOut>&>(out_);
        const Motion<Scalar> motion = composite_motion(object_wrench);
        for (Index i = 0; i < r.cols(); ++i) {
            out.template segment<6>(6 * i) -= share(weights, r, i, motion).vector();
        }
    }

    /// G+_W (6K x 6) column by column into caller storage: column k is the distribution of the
    /// unit wrench e_k.
    template <typename Weights, typename DerivedR, typename DerivedOut>
    void write_inverse(const Weights& weights, const Eigen::MatrixBase<DerivedR>& r,
                       const Eigen::MatrixBase<DerivedOut>& inverse_out) const noexcept
    {
        auto& inverse = const_cast<Eigen::MatrixBase<DerivedOut>&>(inverse_out);
        for (int column = 0; column < 6; ++column) {
            const Motion<Scalar> motion = composite_motion(Force<Scalar>::from(Vector6<Scalar>::Unit(column)));
            for (Index i = 0; i < r.cols(); ++i) {
                share(weights, r, i, motion).write_to(inverse.col(column).template segment<6>(6 * i));
            }
        }
    }
};

}  // namespace detail

/// \brief Moore-Penrose pseudo-inverse G^+ = G^T (G G^T)^-1 of the grasp matrix (24), 6K x 6: the
/// least-norm contact wrenches G^+ F whose net wrench on the object is F, G G^+ = I6. The weighted
/// inverse of (25) with unit weights (the file comment); per tick, ProjectedDynamics applies it
/// without forming it (subtract_grasp_pseudo_inverse_times).
/// \param r 3 x K contact points relative to the object's centre, {w}.
template <typename DerivedR>
Eigen::Matrix<typename DerivedR::Scalar, times_six(DerivedR::ColsAtCompileTime), 6>
grasp_pseudo_inverse(const Eigen::MatrixBase<DerivedR>& r)
{
    using Scalar = typename DerivedR::Scalar;
    COOPDYN_ASSERT(r.rows() == 3 && r.cols() >= 1, "r must be 3 x K");
    const detail::UnitGraspWeights<Scalar> unit{r.cols()};
    const detail::WeightedGrasp<Scalar> grasp(unit, r);
    Eigen::Matrix<Scalar, times_six(DerivedR::ColsAtCompileTime), 6> result(6 * r.cols(), 6);
    grasp.write_inverse(unit, r, result);
    return result;
}

}  // namespace coopdyn
