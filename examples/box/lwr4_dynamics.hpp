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
// M_ij = S_i^T I^C_max(i,j) S_j.
//
// This header belongs to the examples, not to the library.
#pragma once

#include "lwr4.hpp"

#include <coopdyn/spatial/inertia.hpp>
#include <coopdyn/spatial/spatial_vector.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cmath>

namespace box_example {

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
        }
    }

    /// Fills `out` at (q, qdot). Allocates nothing.
    void evaluate(const JointVector& q, const JointVector& qdot, Lwr4ArmTerms& out) const noexcept
    {
        using Eigen::Vector3d;
        constexpr int n = 7;
        // Outward pass: frames, axes, velocities, velocity-product accelerations (no gravity).
        // Column i: link i's (joint i's) quantity.
        Eigen::Matrix<double, 3, n> axis, pivot, com, angular_velocity, angular_acceleration, com_acceleration;
        std::array<Eigen::Matrix3d, n> inertia_world;  // index: link(i)
        Eigen::Matrix3d rotation = base_.linear();
        Vector3d origin = base_.translation();
        Vector3d w = Vector3d::Zero(), alpha = Vector3d::Zero(), origin_acceleration = Vector3d::Zero();
        for (int i = 0; i < n; ++i) {
            const Lwr4Link& link = links_[link_index(i)];
            axis.col(i) = rotation.col(2);
            pivot.col(i) = origin;
            // T_{i-1,i} = RotZ(q_i) TransZ(d_i) TransX(a_i) RotX(alpha_i) (lwr4.hpp's dh_transform).
            const double c = std::cos(q(i)), s = std::sin(q(i));
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
            inertia_world[link_index(i)] = rotation * link.inertia * rotation.transpose();
        }
        // The palm: its contact point is fixed in frame 7, axes parallel to it.
        out.palm_rotation = rotation;
        out.palm_position = origin + rotation * palm_point_;
        const Vector3d to_palm = out.palm_position - origin;
        out.jacobian_rate_qdot << origin_acceleration + alpha.cross(to_palm) + w.cross(w.cross(to_palm)), alpha;
        for (int i = 0; i < n; ++i) {
            out.jacobian.col(i) << axis.col(i).cross(out.palm_position - pivot.col(i)), axis.col(i);
        }

        // Inward pass: h_i = u_i . n_i.
        Vector3d force = Vector3d::Zero(), moment = Vector3d::Zero();  // beyond joint i + 1, about its pivot
        for (int i = n - 1; i >= 0; --i) {
            const Lwr4Link& link = links_[link_index(i)];
            const Vector3d link_force = link.mass * (com_acceleration.col(i) - gravity_);
            const Vector3d link_moment = inertia_world[link_index(i)] * angular_acceleration.col(i) +
                                         angular_velocity.col(i).cross(inertia_world[link_index(i)] * angular_velocity.col(i));
            const Vector3d lever_next = i + 1 < n ? Vector3d(pivot.col(i + 1) - pivot.col(i)) : Vector3d::Zero();
            moment += lever_next.cross(force) + (com.col(i) - pivot.col(i)).cross(link_force) + link_moment;
            force += link_force;
            out.bias(i) = axis.col(i).dot(moment);
        }

        // CRBA about the world origin (coopdyn's spatial algebra, [linear; angular]):
        // I^C_j = sum_{k >= j} I_k, M_ij = S_i . (I^C_j S_j) for i <= j.
        std::array<coopdyn::Motion<double>, n> twists;
        for (int i = 0; i < n; ++i) {
            twists[link_index(i)] = coopdyn::Motion<double>::make(pivot.col(i).cross(axis.col(i)), axis.col(i));
        }
        coopdyn::SpatialInertia<double> composite = coopdyn::SpatialInertia<double>::Zero();
        for (int j = n - 1; j >= 0; --j) {
            composite += coopdyn::SpatialInertia<double>::from_centre(
                links_[link_index(j)].mass, com.col(j), coopdyn::Symmetric3<double>(inertia_world[link_index(j)]));
            const coopdyn::Force<double> momentum = composite * twists[link_index(j)];
            for (int i = 0; i <= j; ++i) {
                const double entry = twists[link_index(i)].dot(momentum);
                out.inertia(i, j) = entry;
                out.inertia(j, i) = entry;
            }
        }
    }

private:
    static std::size_t link_index(int i) noexcept { return static_cast<std::size_t>(i); }

    std::array<Lwr4Link, 7> links_;
    std::array<double, 7> cos_alpha_{}, sin_alpha_{};  // of each link's DH twist
    Eigen::Isometry3d base_;
    Eigen::Vector3d gravity_;
    Eigen::Vector3d palm_point_;
};

}  // namespace box_example
