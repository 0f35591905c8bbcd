// The dynamics of one arm of the dual-arm box example, straight from lwr4.hpp's Denavit-Hartenberg
// parameters and link inertias, without MuJoCo: what the rigid plant evaluates four times per
// RK4 step (docs/dual-arm-box.md, "The rigid plant"). Depends on Eigen and coopdyn's spatial types.
//
// At one state (q, qdot) of one arm it gives, in the world frame:
//   M(q) (7 x 7), h(q, qdot) = C qdot + g (7), the palm contact point's Jacobian J (6 x 7, rows
//   [v; w]), Jdot qdot (6) and the palm frame (position, rotation).
//
// Method (revolute joints, everything in {w}). Joint i turns link i about the unit axis u_i = z_{i-1}
// through the point p_i = o_{i-1} (DH frame i-1's origin). One outward pass with qdd = 0 and no
// gravity gives the links' angular velocities w_i, the velocity-product accelerations of their
// frames' origins and angular accelerations (Luh-Walker-Paul):
//
//     w_i = w_{i-1} + u_i qdot_i,    alpha_i = alpha_{i-1} + w_{i-1} x u_i qdot_i,
//     a(o_i) = a(o_{i-1}) + alpha_i x (o_i - o_{i-1}) + w_i x (w_i x (o_i - o_{i-1}))
//
// (o_{i-1} lies on joint i's axis, so it moves the same on links i-1 and i). The palm point's
// acceleration from it is Jdot qdot. Uniform gravity is a base acceleration -g added to every
// linear acceleration, so the inward pass, with F_i = m_i (a(c_i) - g) and
// N_i = I_i alpha_i + w_i x I_i w_i, gives h_i = u_i . n_i (n_i: the moment about p_i of
// everything beyond joint i). M comes from the composite inertias (CRBA) about the world origin,
// in coopdyn's spatial algebra (SpatialInertia, Motion, Force), twist S_i = [p_i x u_i; u_i]:
// M_ij = S_i^T I^C_max(i,j) S_j. One inward pass gives both h and the composite inertias; the
// seven joints' sines and cosines come at once from sin_cos() below.
//
// This header belongs to the examples, not to the library.
#pragma once

#include "lwr4.hpp"

#include <coopdyn/spatial/inertia.hpp>
#include <coopdyn/spatial/spatial_vector.hpp>
#include <coopdyn/spatial/symmetric3.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace box_example {

/// sin and cos of N angles at once: the recursion's joint angles. Why not std::sin and std::cos:
/// fourteen library calls per evaluation of an arm, about a fifth of its time; here the angles'
/// work has neither calls nor branches and is independent, so it overlaps (about 4 times faster).
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

/// What the rigid plant needs of one arm at one state, world frame.
struct Lwr4ArmTerms {
    Eigen::Matrix<double, 7, 7> inertia;        ///< M(q)
    Eigen::Matrix<double, 7, 1> bias;           ///< h(q, qdot) = C qdot + g
    Eigen::Matrix<double, 6, 7> jacobian;       ///< the palm contact point's [v; w]
    Eigen::Matrix<double, 6, 1> jacobian_rate_qdot;  ///< Jdot qdot
    Eigen::Vector3d palm_position;              ///< the palm's contact point
    Eigen::Matrix3d palm_rotation;              ///< the palm frame (z: outward normal)
};

/// One arm of lwr4.hpp (arm_links(): the palm lumped into link 7) on its base, under gravity.
class Lwr4Dynamics {
public:
    using JointVector = Eigen::Matrix<double, 7, 1>;

    explicit Lwr4Dynamics(Side side, const Eigen::Vector3d& gravity = Eigen::Vector3d(0.0, 0.0, -9.81))
        : links_(arm_links()), base_(base_transform(side)), gravity_(gravity), palm_point_(palm().contact_point)
    {
        for (std::size_t i = 0; i < links_.size(); ++i) {
            cos_alpha_[i] = std::cos(links_[i].alpha);
            sin_alpha_[i] = std::sin(links_[i].alpha);
            const Eigen::Matrix3d& inertia = links_[i].inertia;
            diagonal_inertia_[i] = inertia(1, 0) == 0.0 && inertia(2, 0) == 0.0 && inertia(2, 1) == 0.0;
            link_inertia_[i] = coopdyn::Symmetric3<double>(inertia);
            principal_moments_[i] = inertia.diagonal();
        }
    }

    /// Fills `out` at (q, qdot). Allocates nothing.
    void evaluate(const JointVector& q, const JointVector& qdot, Lwr4ArmTerms& out) const noexcept
    {
        LinkKinematics pass;
        outward_pass(q, qdot, pass, out);
        inward_pass(pass, out);
    }

private:
    static constexpr int n = 7;

    /// Per link, world frame (column i: link i's, joint i's quantity): the joint axis and its pivot,
    /// the centre of mass, the angular velocity and acceleration, the centre of mass's
    /// velocity-product acceleration (no gravity), the inertia about the centre of mass.
    struct LinkKinematics {
        Eigen::Matrix<double, 3, n> axis, pivot, com, angular_velocity, angular_acceleration, com_acceleration;
        std::array<coopdyn::Symmetric3<double>, n> inertia_world;
    };

    /// The outward pass: frames, axes, velocities, velocity-product accelerations; then the palm's
    /// frame, Jacobian and Jdot qdot into `out`.
    void outward_pass(const JointVector& q, const JointVector& qdot, LinkKinematics& pass, Lwr4ArmTerms& out) const noexcept
    {
        using Eigen::Vector3d;
        std::array<double, n + 1> angle{};  // and one padding angle
        for (int i = 0; i < n; ++i) {
            angle[link_index(i)] = q(i);
        }
        const SinCos<n + 1> joint = sin_cos(angle);
        auto& [axis, pivot, com, angular_velocity, angular_acceleration, com_acceleration, inertia_world] = pass;
        Eigen::Matrix3d rotation = base_.linear();
        Vector3d origin = base_.translation();
        Vector3d w = Vector3d::Zero(), alpha = Vector3d::Zero(), origin_acceleration = Vector3d::Zero();
        for (int i = 0; i < n; ++i) {
            const Lwr4Link& link = links_[link_index(i)];
            axis.col(i) = rotation.col(2);
            pivot.col(i) = origin;
            // T_{i-1,i} = RotZ(q_i) TransZ(d_i) TransX(a_i) RotX(alpha_i) (lwr4.hpp's dh_transform).
            const double c = joint.cosine[link_index(i)], s = joint.sine[link_index(i)];
            const Vector3d x = c * rotation.col(0) + s * rotation.col(1);
            const Vector3d y = -s * rotation.col(0) + c * rotation.col(1);
            const double ca = cos_alpha_[link_index(i)], sa = sin_alpha_[link_index(i)];
            const Vector3d next_origin = origin + link.d * axis.col(i) + link.a * x;
            rotation.col(0) = x;
            rotation.col(1) = ca * y + sa * axis.col(i);
            rotation.col(2) = -sa * y + ca * axis.col(i);

            const Vector3d spin = axis.col(i) * qdot(i);
            alpha += w.cross(spin);
            w += spin;
            const Vector3d step = next_origin - origin;
            origin_acceleration += alpha.cross(step) + w.cross(w.cross(step));
            origin = next_origin;

            com.col(i) = origin + rotation * link.com;
            const Vector3d to_com = com.col(i) - origin;
            com_acceleration.col(i) = origin_acceleration + alpha.cross(to_com) + w.cross(w.cross(to_com));
            angular_velocity.col(i) = w;
            angular_acceleration.col(i) = alpha;
            // R I R^T in six entries (Symmetric3::rotated, 45 multiply-adds instead of the dense
            // product's 54); 27 for a diagonal I (R diag(d) R^T).
            inertia_world[link_index(i)] =
                diagonal_inertia_[link_index(i)]
                    ? coopdyn::Symmetric3<double>::rotated_diagonal(principal_moments_[link_index(i)], rotation)
                    : link_inertia_[link_index(i)].rotated(rotation);
        }
        // The palm: its contact point is fixed in frame 7, axes parallel to it.
        out.palm_rotation = rotation;
        out.palm_position = origin + rotation * palm_point_;
        const Vector3d to_palm = out.palm_position - origin;
        out.jacobian_rate_qdot << origin_acceleration + alpha.cross(to_palm) + w.cross(w.cross(to_palm)), alpha;
        for (int i = 0; i < n; ++i) {
            out.jacobian.col(i) << axis.col(i).cross(out.palm_position - pivot.col(i)), axis.col(i);
        }

    }

    /// The inward pass: the bias h by Newton-Euler and M by the composite-rigid-body algorithm.
    void inward_pass(const LinkKinematics& pass, Lwr4ArmTerms& out) const noexcept
    {
        using Eigen::Vector3d;
        const auto& [axis, pivot, com, angular_velocity, angular_acceleration, com_acceleration, inertia_world] = pass;
        // One inward pass for both h and the composite inertias.
        // Newton-Euler: h_i = u_i . n_i.
        // CRBA about the world origin (coopdyn's spatial algebra, [linear; angular]):
        // I^C_j = sum_{k >= j} I_k, F_j = I^C_j S_j, M_ij = S_i . F_j for i <= j, all the
        // products at once as one matrix product (the twists as rows, plus a zero row: columns of
        // eight fill the vector registers).
        Eigen::Matrix<double, n + 1, 6> twists;
        twists.row(n).setZero();
        Eigen::Matrix<double, 6, n> momenta;
        Vector3d force = Vector3d::Zero(), moment = Vector3d::Zero();  // beyond joint i + 1, about its pivot
        coopdyn::SpatialInertia<double> composite = coopdyn::SpatialInertia<double>::Zero();
        for (int i = n - 1; i >= 0; --i) {
            const Lwr4Link& link = links_[link_index(i)];
            const coopdyn::Symmetric3<double>& link_inertia = inertia_world[link_index(i)];
            const Vector3d link_force = link.mass * (com_acceleration.col(i) - gravity_);
            const Vector3d link_moment = link_inertia * angular_acceleration.col(i) +
                                         angular_velocity.col(i).cross(link_inertia * angular_velocity.col(i));
            const Vector3d lever_next = i + 1 < n ? Vector3d(pivot.col(i + 1) - pivot.col(i)) : Vector3d::Zero();
            moment += lever_next.cross(force) + (com.col(i) - pivot.col(i)).cross(link_force) + link_moment;
            force += link_force;
            out.bias(i) = axis.col(i).dot(moment);

            composite += coopdyn::SpatialInertia<double>::from_centre(link.mass, com.col(i), link_inertia);
            const auto twist = coopdyn::Motion<double>::make(pivot.col(i).cross(axis.col(i)), axis.col(i));
            twists.row(i) = twist.vector().transpose();
            momenta.col(i) = (composite * twist).vector();
        }
        // As six rank-one updates: each a multiply-add of whole columns (Eigen's lazy product
        // at this size runs slower, element by element).
        Eigen::Matrix<double, n + 1, n> products = twists.col(0) * momenta.row(0);
        for (int c = 1; c < 6; ++c) {
            products.noalias() += twists.col(c) * momenta.row(c);
        }
        out.inertia.triangularView<Eigen::Upper>() = products.topRows<n>();
        out.inertia.triangularView<Eigen::StrictlyLower>() = products.topRows<n>().transpose();
    }

    static std::size_t link_index(int i) noexcept { return static_cast<std::size_t>(i); }

    std::array<Lwr4Link, 7> links_;
    std::array<double, 7> cos_alpha_{}, sin_alpha_{};  // of each link's DH twist
    std::array<bool, 7> diagonal_inertia_{};           // in its DH frame (all of lwr4.hpp's links)
    std::array<coopdyn::Symmetric3<double>, 7> link_inertia_{};  // about the com, DH axes
    std::array<Eigen::Vector3d, 7> principal_moments_{};         // its diagonal
    Eigen::Isometry3d base_;
    Eigen::Vector3d gravity_;
    Eigen::Vector3d palm_point_;
};

}  // namespace box_example
