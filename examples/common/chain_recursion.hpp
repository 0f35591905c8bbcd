// The half of a serial arm's recursive dynamics that does not depend on how its links are described,
// shared by the example plants' own recursions: the LWR 4 arm's Denavit-Hartenberg chain
// (examples/box/lwr4_dynamics.hpp) and any MuJoCo chain of hinge joints
// (examples/scenes/chain_dynamics.hpp). Each fills ChainKinematics in one outward pass at
// (q, qdot) with qdd = 0 (Luh-Walker-Paul); from it, in the world frame {w}:
//
//   h(q, qdot) = C qdot + g by Newton-Euler, gravity as a base acceleration: the inward pass with
//     F_i = m_i (a(c_i) - g), N_i = I_i alpha_i + w_i x I_i w_i gives h_i = u_i . n_i (n_i: the
//     moment about joint i's pivot p_i of everything beyond joint i);
//   M(q) by the composite-rigid-body algorithm about the world origin, in coopdyn's spatial algebra
//     (SpatialInertia, Motion, Force): I^C_j = sum_{k >= j} I_k, F_j = I^C_j S_j, M_ij = S_i . F_j
//     with the twists S_i = [p_i x u_i; u_i] (one inward pass gives both h and the composites);
//   a contact point p fixed in the last link: its Jacobian J (6 x n, rows [v; w]; column i
//     [u_i x (p - p_i); u_i]) and Jdot qdot = [a(o) + alpha x d + w x (w x d); alpha], d = p - o,
//     from a point o of the last link and its velocity-product acceleration a(o): the point's
//     classical acceleration at zero joint acceleration, without gravity.
//
// N is the joint count (fixed, or Eigen::Dynamic up to Capacity at run time). Allocates nothing.
// Depends on Eigen and coopdyn's spatial types.
#pragma once

#include <coopdyn/spatial/inertia.hpp>
#include <coopdyn/spatial/spatial_vector.hpp>
#include <coopdyn/spatial/symmetric3.hpp>

#include <Eigen/Core>

#include <array>
#include <cstddef>

namespace example_common {

/// N + 1, Dynamic staying Dynamic.
constexpr int one_more(int n) noexcept { return n == Eigen::Dynamic ? Eigen::Dynamic : n + 1; }

/// Per link i (column i), in {w}: joint i's unit axis u_i and its pivot p_i (a point on the axis),
/// the link's centre of mass c_i, angular velocity w_i and acceleration alpha_i, the centre of
/// mass's velocity-product acceleration a(c_i) (qdd = 0, no gravity) and the link's rotational
/// inertia about c_i. What an outward pass fills, what chain_inward_pass reads.
template <int N, int Capacity = N> struct ChainKinematics {
    using Columns = Eigen::Matrix<double, 3, N, 0, 3, Capacity>;
    explicit ChainKinematics(Eigen::Index n = N)
        : axis(3, n), pivot(3, n), com(3, n), angular_velocity(3, n), angular_acceleration(3, n), com_acceleration(3, n)
    {
    }
    Eigen::Index joints() const noexcept { return axis.cols(); }
    Columns axis, pivot, com, angular_velocity, angular_acceleration, com_acceleration;
    std::array<coopdyn::Symmetric3<double>, Capacity> inertia_world{};
};

/// h and M (the file comment) of a chain whose link i has mass mass[i] (an array), into `bias` (n) and
/// `inertia` (n x n, both triangles). `gravity`: g in {w}.
template <int N, int Capacity, typename Masses, typename Inertia, typename Bias>
void chain_inward_pass(const ChainKinematics<N, Capacity>& pass, const Masses& mass, const Eigen::Vector3d& gravity,
                       Inertia&& inertia, Bias&& bias) noexcept
{
    using Eigen::Vector3d;
    const auto& [axis, pivot, com, angular_velocity, angular_acceleration, com_acceleration, inertia_world] = pass;
    const Eigen::Index n = pass.joints();
    // The twists as rows, plus a zero row: columns of eight fill the vector registers.
    Eigen::Matrix<double, one_more(N), 6, 0, Capacity + 1, 6> twists(n + 1, 6);
    twists.row(n).setZero();
    Eigen::Matrix<double, 6, N, 0, 6, Capacity> momenta(6, n);
    Vector3d force = Vector3d::Zero(), moment = Vector3d::Zero();  // beyond joint i + 1, about its pivot
    coopdyn::SpatialInertia<double> composite = coopdyn::SpatialInertia<double>::Zero();
    for (Eigen::Index i = n - 1; i >= 0; --i) {
        const auto link = static_cast<std::size_t>(i);
        const coopdyn::Symmetric3<double>& link_inertia = inertia_world[link];
        const Vector3d link_force = mass[link] * (com_acceleration.col(i) - gravity);
        const Vector3d link_moment =
            link_inertia * angular_acceleration.col(i) + angular_velocity.col(i).cross(link_inertia * angular_velocity.col(i));
        const Vector3d lever_next = i + 1 < n ? Vector3d(pivot.col(i + 1) - pivot.col(i)) : Vector3d::Zero();
        moment += lever_next.cross(force) + (com.col(i) - pivot.col(i)).cross(link_force) + link_moment;
        force += link_force;
        bias(i) = axis.col(i).dot(moment);

        composite += coopdyn::SpatialInertia<double>::from_centre(mass[link], com.col(i), link_inertia);
        const auto twist = coopdyn::Motion<double>::make(pivot.col(i).cross(axis.col(i)), axis.col(i));
        twists.row(i) = twist.vector().transpose();
        momenta.col(i) = (composite * twist).vector();
    }
    // M_ij = S_i . F_j for i <= j, as six rank-one updates: each a multiply-add of whole columns
    // (Eigen's lazy product at this size runs slower, element by element).
    Eigen::Matrix<double, one_more(N), N, 0, Capacity + 1, Capacity> products = twists.col(0) * momenta.row(0);
    for (int c = 1; c < 6; ++c) {
        products.noalias() += twists.col(c) * momenta.row(c);
    }
    inertia.template triangularView<Eigen::Upper>() = products.template topRows<N>(n);
    inertia.template triangularView<Eigen::StrictlyLower>() = products.template topRows<N>(n).transpose();
}

/// J (6 x n) and Jdot qdot (6) of the point `point` fixed in the last link (the file comment), with
/// `link_point` a point of the last link and `link_point_acceleration` its velocity-product
/// acceleration.
template <int N, int Capacity, typename Jacobian, typename Rate>
void chain_contact_terms(const ChainKinematics<N, Capacity>& pass, const Eigen::Vector3d& point,
                         const Eigen::Vector3d& link_point, const Eigen::Vector3d& link_point_acceleration,
                         Jacobian&& jacobian, Rate&& jacobian_rate_qdot) noexcept
{
    const Eigen::Index last = pass.joints() - 1;
    const Eigen::Vector3d w = pass.angular_velocity.col(last);
    const Eigen::Vector3d alpha = pass.angular_acceleration.col(last);
    const Eigen::Vector3d to_point = point - link_point;
    jacobian_rate_qdot << link_point_acceleration + alpha.cross(to_point) + w.cross(w.cross(to_point)), alpha;
    for (Eigen::Index i = 0; i <= last; ++i) {
        jacobian.col(i) << pass.axis.col(i).cross(point - pass.pivot.col(i)), pass.axis.col(i);
    }
}

}  // namespace example_common
