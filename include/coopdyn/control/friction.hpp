/// \file
/// \brief Friction constraints of one flat contact (a palm on the object), Lin et al. L(17)-(19)
/// with errata E9, as linear rows acting on the contact's wrench; docs/control.md.
///
/// Contact frame {c_i}: z is the object's inward surface normal at contact i, x and y tangential;
/// R_ci rotates {c_i} to {w}. The wrench w_i = [f; t] the hand applies ON the object about the
/// contact point, expressed in {c_i}, must satisfy
///
///     f_z >= f_min                                    unilateral, L(17) (f_min >= 0: a margin)
///     c_k f_x + s_k f_y <= mu cos(pi/n) f_z           n-edge pyramid inscribed in the cone L(18),
///                                                     (c_k, s_k) = (cos, sin) 2 pi (k + 1/2) / n
///     |t_z| <= gamma f_z                              torsion, L(19)
///     |t_x| <= delta_y f_z,  |t_y| <= delta_x f_z     centre of pressure in the 2 delta_x x 2 delta_y patch (E9)
///
/// n + 7 rows (15 for the paper's n = 8). The pyramid's edges lie on the cone |f_t| = mu f_z, at
/// the angles 2 pi k / n; its facets are at mu cos(pi/n) f_z. Errata E9: the printed L(19) bounds
/// the moment about x by the half-extent along x; a force f_z at the patch's edge y = delta_y
/// gives t_x = delta_y f_z, so t_x is bounded by delta_y (and t_y by delta_x).
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/detail/validation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace coopdyn {

/// The force rows of one contact come first: the unilateral row and the n pyramid facets, n + 1
/// rows on f (their margins in N). contact_frame_friction_rows' order is the one owner of this.
constexpr int friction_force_rows(int edges) noexcept { return edges == Eigen::Dynamic ? Eigen::Dynamic : edges + 1; }

/// The moment rows follow the force rows: torsion (+, -), t_x (+, -), t_y (+, -), 6 rows bounding
/// the moments by multiples of f_z (their margins in N m).
inline constexpr int friction_moment_rows = 6;

/// Rows of one contact's friction constraints: n + 7 (Dynamic passes through).
constexpr int friction_rows(int edges) noexcept
{
    return edges == Eigen::Dynamic ? Eigen::Dynamic : friction_force_rows(edges) + friction_moment_rows;
}

/// The largest pyramid a contact may use (ContactFriction::validate): 64 edges approximate the
/// cone to 0.12 % (cos(pi/64)), and the bound lets friction_margin work without the heap.
inline constexpr int max_pyramid_edges = 64;

/// \brief Friction parameters of one contact. Validated by validate(contact) (the controller model
/// does it at construction).
template <typename ScalarType> struct ContactFriction {
    using Scalar = ScalarType;
    Scalar friction_coefficient = Scalar(0.5);   ///< mu > 0, Coulomb
    Scalar torsional_coefficient = Scalar(0);    ///< gamma >= 0 [m]: |t_z| <= gamma f_z
    Scalar patch_half_length_x = Scalar(0.05);   ///< delta_x > 0 [m], patch along the contact's x
    Scalar patch_half_length_y = Scalar(0.05);   ///< delta_y > 0 [m], patch along the contact's y
    Scalar minimum_normal_force = Scalar(0);     ///< f_min >= 0 [N]
    int pyramid_edges = 8;                       ///< n >= 3, the pyramid inscribed in the cone

    /// Throws InvalidModel naming the parameter and the contact.
    void validate(Index contact) const
    {
        const detail::ErrorContext context{detail::ErrorKind::model, "contact", contact};
        detail::require_positive(friction_coefficient, context, "friction_coefficient");
        detail::require_non_negative(torsional_coefficient, context, "torsional_coefficient");
        detail::require_positive(patch_half_length_x, context, "patch_half_length_x");
        detail::require_positive(patch_half_length_y, context, "patch_half_length_y");
        detail::require_non_negative(minimum_normal_force, context, "minimum_normal_force");
        if (pyramid_edges < 3 || pyramid_edges > max_pyramid_edges) {
            detail::fail(context, "pyramid_edges",
                         "must be between 3 and " + std::to_string(max_pyramid_edges) + ", got " +
                             std::to_string(pyramid_edges));
        }
    }
};

/// \brief The rows A (n + 7 x 6) and bounds b of one contact's constraints A [f; t] <= b on its
/// wrench in the contact frame {c_i}. Edges: n at compile time, or Dynamic to take
/// friction.pyramid_edges (the outputs must then have n + 7 rows). noexcept; no allocation.
/// Row order: unilateral, the n pyramid facets, torsion (+, -), centre of pressure (t_x +, -;
/// t_y +, -).
template <typename Scalar, typename DerivedRows, typename DerivedBounds>
void contact_frame_friction_rows(const ContactFriction<Scalar>& friction, const Eigen::MatrixBase<DerivedRows>& rows_out,
                                 const Eigen::MatrixBase<DerivedBounds>& bounds_out) noexcept
{
    using std::cos;
    using std::sin;
    auto& rows = const_cast<Eigen::MatrixBase<DerivedRows>&>(rows_out);
    auto& bounds = const_cast<Eigen::MatrixBase<DerivedBounds>&>(bounds_out);
    const int edges = friction.pyramid_edges;
    COOPDYN_ASSERT(rows.rows() == edges + 7 && rows.cols() == 6 && bounds.size() == edges + 7,
                   "friction rows: n + 7 rows of 6 columns");
    rows.setZero();
    bounds.setZero();
    // f, t = columns 0-2, 3-5.
    rows(0, 2) = Scalar(-1);  // -f_z <= -f_min
    bounds(0) = -friction.minimum_normal_force;
    const Scalar facet_reach = friction.friction_coefficient * cos(pi<Scalar>() / Scalar(edges));
    for (int k = 0; k < edges; ++k) {
        const Scalar angle = Scalar(2) * pi<Scalar>() * (Scalar(k) + Scalar(0.5)) / Scalar(edges);
        rows(1 + k, 0) = cos(angle);
        rows(1 + k, 1) = sin(angle);
        rows(1 + k, 2) = -facet_reach;
    }
    const Index torsion = friction_force_rows(edges);  // the moment rows follow the force rows
    for (int sign = 0; sign < 2; ++sign) {
        const Scalar s = sign == 0 ? Scalar(1) : Scalar(-1);
        rows(torsion + sign, 5) = s;  // +-t_z - gamma f_z <= 0
        rows(torsion + sign, 2) = -friction.torsional_coefficient;
        rows(torsion + 2 + sign, 3) = s;  // +-t_x - delta_y f_z <= 0 (E9)
        rows(torsion + 2 + sign, 2) = -friction.patch_half_length_y;
        rows(torsion + 4 + sign, 4) = s;  // +-t_y - delta_x f_z <= 0 (E9)
        rows(torsion + 4 + sign, 2) = -friction.patch_half_length_x;
    }
}

/// \brief The same constraints acting on the contact's wrench in {w}: A_w = A blkdiag(R_ci^T, R_ci^T),
/// so that A_w w_i <= b. contact_rotation is R_ci ({c_i} to {w}).
template <typename Scalar, typename DerivedRows, typename DerivedBounds>
void friction_rows(const ContactFriction<Scalar>& friction, const Matrix3<Scalar>& contact_rotation,
                   const Eigen::MatrixBase<DerivedRows>& rows_out, const Eigen::MatrixBase<DerivedBounds>& bounds_out) noexcept
{
    auto& rows = const_cast<Eigen::MatrixBase<DerivedRows>&>(rows_out);
    contact_frame_friction_rows(friction, rows, bounds_out);
    for (Index row = 0; row < rows.rows(); ++row) {
        const Vector3<Scalar> force = rows.row(row).template head<3>().transpose();
        const Vector3<Scalar> moment = rows.row(row).template tail<3>().transpose();
        rows.row(row).template head<3>() = (contact_rotation * force).transpose();
        rows.row(row).template tail<3>() = (contact_rotation * moment).transpose();
    }
}

/// \brief The friction margin of a wrench w = [f; t] (contact frame) under constraint rows A w <= b
/// built once with contact_frame_friction_rows: min_k (b_k - a_k^T w) / |a_k|. For a caller that
/// evaluates many wrenches of one contact (a log, every tick) without rebuilding the rows.
/// noexcept; no allocation.
template <typename DerivedRows, typename DerivedBounds, typename DerivedWrench>
typename DerivedRows::Scalar friction_margin(const Eigen::MatrixBase<DerivedRows>& rows,
                                             const Eigen::MatrixBase<DerivedBounds>& bounds,
                                             const Eigen::MatrixBase<DerivedWrench>& wrench) noexcept
{
    using Scalar = typename DerivedRows::Scalar;
    EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(DerivedWrench, 6);
    COOPDYN_ASSERT(rows.cols() == 6 && bounds.size() == rows.rows(), "friction_margin: rows m x 6, bounds m");
    const Vector6<Scalar> w = wrench;
    Scalar margin = std::numeric_limits<Scalar>::infinity();
    for (Index k = 0; k < rows.rows(); ++k) {
        margin = std::min(margin, (bounds(k) - rows.row(k).dot(w)) / rows.row(k).norm());
    }
    return margin;
}

/// \brief A contact's friction margin split by the rows' units: `force`, the smallest of the force
/// rows' (unilateral and pyramid, the first friction_force_rows(n)) normalised slacks, in N;
/// `moment`, the smallest of the moment rows' (torsion and centre of pressure, the last
/// friction_moment_rows), in N m. friction_margin is the smaller of the two.
template <typename ScalarType> struct FrictionMargins {
    using Scalar = ScalarType;
    Scalar force = Scalar(0);   ///< N: distance to the nearest force boundary (< 0: slips, or pulls)
    Scalar moment = Scalar(0);  ///< N m: distance to the nearest moment boundary (< 0: twists or rolls)
};

/// \brief friction_margin split into the force and the moment rows' margins (FrictionMargins), on
/// rows and bounds built once with contact_frame_friction_rows (n + 7 rows, in its order).
/// noexcept; no allocation.
template <typename DerivedRows, typename DerivedBounds, typename DerivedWrench>
FrictionMargins<typename DerivedRows::Scalar> friction_margins(const Eigen::MatrixBase<DerivedRows>& rows,
                                                               const Eigen::MatrixBase<DerivedBounds>& bounds,
                                                               const Eigen::MatrixBase<DerivedWrench>& wrench) noexcept
{
    using Scalar = typename DerivedRows::Scalar;
    EIGEN_STATIC_ASSERT_VECTOR_SPECIFIC_SIZE(DerivedWrench, 6);
    COOPDYN_ASSERT(rows.cols() == 6 && bounds.size() == rows.rows() && rows.rows() > friction_moment_rows,
                   "friction_margins: rows m x 6 (m = n + 7), bounds m");
    const Vector6<Scalar> w = wrench;
    const Index force_rows = rows.rows() - friction_moment_rows;
    FrictionMargins<Scalar> margins{std::numeric_limits<Scalar>::infinity(), std::numeric_limits<Scalar>::infinity()};
    for (Index k = 0; k < rows.rows(); ++k) {
        Scalar& margin = k < force_rows ? margins.force : margins.moment;
        margin = std::min(margin, (bounds(k) - rows.row(k).dot(w)) / rows.row(k).norm());
    }
    return margins;
}

/// \brief The force and moment rows' margins of one contact's wrench [f; t] in its contact frame
/// (see the overload above; this one builds the rows on every call).
template <typename Scalar, typename DerivedWrench>
FrictionMargins<Scalar> friction_margins(const ContactFriction<Scalar>& friction,
                                         const Eigen::MatrixBase<DerivedWrench>& wrench) noexcept
{
    constexpr int most_rows = friction_rows(max_pyramid_edges);
    COOPDYN_ASSERT(friction.pyramid_edges >= 3 && friction.pyramid_edges <= max_pyramid_edges,
                   "friction_margins: pyramid_edges out of range");
    const Index count = friction_rows(friction.pyramid_edges);
    Eigen::Matrix<Scalar, Eigen::Dynamic, 6, 0, most_rows, 6> rows(count, 6);
    Eigen::Matrix<Scalar, Eigen::Dynamic, 1, 0, most_rows, 1> bounds(count);
    contact_frame_friction_rows(friction, rows, bounds);
    return friction_margins(rows, bounds, wrench);
}

/// \brief The friction margin of one contact: the smallest slack of its rows, each divided by the
/// row's norm, min_k (b_k - a_k^T w) / |a_k|, for the wrench w = [f; t] in the contact frame {c_i}.
/// It is the distance from w to the nearest constraint boundary (in newtons for the force rows,
/// newton-metres for the moment rows; friction_margins reports the two separately): positive
/// inside, zero on the boundary, negative when a constraint is violated (the grasp would slip,
/// twist or roll there). noexcept; no allocation (friction.pyramid_edges <= max_pyramid_edges). It builds the rows on every call (n sines and
/// cosines); the overload on rows and bounds reuses them.
template <typename Scalar, typename DerivedWrench>
Scalar friction_margin(const ContactFriction<Scalar>& friction, const Eigen::MatrixBase<DerivedWrench>& wrench) noexcept
{
    constexpr int most_rows = friction_rows(max_pyramid_edges);
    COOPDYN_ASSERT(friction.pyramid_edges >= 3 && friction.pyramid_edges <= max_pyramid_edges,
                   "friction_margin: pyramid_edges out of range");
    const Index count = friction_rows(friction.pyramid_edges);
    Eigen::Matrix<Scalar, Eigen::Dynamic, 6, 0, most_rows, 6> rows(count, 6);
    Eigen::Matrix<Scalar, Eigen::Dynamic, 1, 0, most_rows, 1> bounds(count);
    contact_frame_friction_rows(friction, rows, bounds);
    return friction_margin(rows, bounds, wrench);
}

}  // namespace coopdyn
