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
// acceleration from it is Jdot qdot. The inward pass (h by Newton-Euler, gravity as a base
// acceleration; M by the composite-rigid-body algorithm about the world origin) and the palm's J
// and Jdot qdot are examples/common/chain_recursion.hpp's, shared with the scenes' MuJoCo chains.
// The seven joints' sines and cosines come at once from sin_cos() (examples/common/sin_cos.hpp).
//
// This header belongs to the examples, not to the library.
#pragma once

#include "lwr4.hpp"
#include "../common/chain_recursion.hpp"
#include "../common/sin_cos.hpp"

#include <coopdyn/spatial/symmetric3.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cmath>

namespace box_example {

// The joints' sines and cosines at once (examples/common/sin_cos.hpp).
using example_common::sin_cos;
using example_common::SinCos;

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
            mass_[i] = links_[i].mass;
        }
    }

    /// Fills `out` at (q, qdot). Allocates nothing.
    void evaluate(const JointVector& q, const JointVector& qdot, Lwr4ArmTerms& out) const noexcept
    {
        LinkKinematics pass;
        outward_pass(q, qdot, pass, out);
        example_common::chain_inward_pass(pass, mass_, gravity_, out.inertia, out.bias);
    }

private:
    static constexpr int n = 7;

    /// Per link, world frame: joint axis and pivot, centre of mass, velocities and accelerations,
    /// inertia (examples/common/chain_recursion.hpp).
    using LinkKinematics = example_common::ChainKinematics<n>;

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
        example_common::chain_contact_terms(pass, out.palm_position, origin, origin_acceleration, out.jacobian,
                                            out.jacobian_rate_qdot);
    }

    static std::size_t link_index(int i) noexcept { return static_cast<std::size_t>(i); }

    std::array<Lwr4Link, 7> links_;
    std::array<double, 7> cos_alpha_{}, sin_alpha_{};  // of each link's DH twist
    std::array<bool, 7> diagonal_inertia_{};           // in its DH frame (all of lwr4.hpp's links)
    std::array<coopdyn::Symmetric3<double>, 7> link_inertia_{};  // about the com, DH axes
    std::array<double, 7> mass_{};
    std::array<Eigen::Vector3d, 7> principal_moments_{};         // its diagonal
    Eigen::Isometry3d base_;
    Eigen::Vector3d gravity_;
    Eigen::Vector3d palm_point_;
};

}  // namespace box_example
