/// \file
/// \brief Impedance-controlled end-effector (docs/model.md, paper (1), (5), (6), (15)).
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/detail/validation.hpp"
#include "coopdyn/spatial/inertia.hpp"
#include "coopdyn/spatial/pose.hpp"
#include "coopdyn/spatial/quaternion.hpp"

#include <string>
#include <type_traits>
#include <utility>

namespace coopdyn {

/// \brief Target dynamics of an impedance-controlled end-effector (1):
/// M_i (xdd_i - xdd_i^d) + D_i (xdot_i - xdot_i^d) + h_i^K = h_i - h_i^d + htilde_i,
/// with M_i = diag(m_i I3, J_i), D_i = diag(d_i I3, delta_i I3) and the stiffness wrench (5).
///
/// All gains are the paper's scalars. J_i is a controller parameter, constant in {w} (it does not
/// rotate with the end-effector). Written as M_i xdd_i = hSigma_i + h_i (15), the inertia is
/// block-diagonal, which the interaction solver exploits at compile time.
template <typename ScalarType> struct ImpedanceEndEffector {
    using Scalar = ScalarType;
    /// The inertia type of inertia(): diag(m_i I3, J_i), the interaction solver's fast path.
    using Inertia = CentralInertia<Scalar>;
    static constexpr bool has_block_diagonal_inertia = true;

    Scalar mass = Scalar(0);                                          ///< m_i, kg
    Matrix3<Scalar> rotational_inertia = Matrix3<Scalar>::Zero();     ///< J_i in {w}, kg m^2, SPD
    Scalar translational_damping = Scalar(0);                         ///< d_i, N s/m
    Scalar rotational_damping = Scalar(0);                            ///< delta_i, N m s/rad
    Scalar translational_stiffness = Scalar(0);                       ///< k_i, N/m
    Scalar rotational_stiffness = Scalar(0);                          ///< kappa_i, N m/rad

    /// Named construction, so that the four scalar gains cannot be swapped unnoticed:
    ///
    ///     const auto arm = ImpedanceEndEffector<double>()
    ///                          .with_mass(10.0)
    ///                          .with_rotational_inertia(0.5 * Eigen::Matrix3d::Identity())
    ///                          .with_translational_damping(180.0)
    ///                          .with_rotational_damping(10.0)
    ///                          .with_translational_stiffness(300.0)
    ///                          .with_rotational_stiffness(50.0);
    ///
    /// Each returns a copy with one field set (the aggregate's fields can also be set by name).
    ImpedanceEndEffector with_mass(const Scalar& value) const { return with(&ImpedanceEndEffector::mass, value); }
    template <typename Derived> ImpedanceEndEffector with_rotational_inertia(const Eigen::MatrixBase<Derived>& value) const
    {
        ImpedanceEndEffector result = *this;
        result.rotational_inertia = value;
        return result;
    }
    ImpedanceEndEffector with_translational_damping(const Scalar& value) const
    {
        return with(&ImpedanceEndEffector::translational_damping, value);
    }
    ImpedanceEndEffector with_rotational_damping(const Scalar& value) const
    {
        return with(&ImpedanceEndEffector::rotational_damping, value);
    }
    ImpedanceEndEffector with_translational_stiffness(const Scalar& value) const
    {
        return with(&ImpedanceEndEffector::translational_stiffness, value);
    }
    ImpedanceEndEffector with_rotational_stiffness(const Scalar& value) const
    {
        return with(&ImpedanceEndEffector::rotational_stiffness, value);
    }

    /// M_i = diag(m_i I3, J_i) of (1).
    Inertia inertia() const { return Inertia(mass, rotational_inertia); }

    /// D_i = diag(d_i I3, delta_i I3) of (1). Held in the central-inertia type because its
    /// congruence G_i D_i G_i^T (32) is the same parallel-axis shift as the inertia's (31).
    CentralInertia<Scalar> damping() const
    {
        return CentralInertia<Scalar>(translational_damping, Symmetric3<Scalar>::scaled_identity(rotational_damping));
    }

    /// diag(k_i I3, kappa_i I3): the stiffness of (5) linearised about x_i = x_i^d, whose
    /// congruence gives the apparent K of Theorem 2 (errata E3).
    CentralInertia<Scalar> stiffness() const
    {
        return CentralInertia<Scalar>(translational_stiffness, Symmetric3<Scalar>::scaled_identity(rotational_stiffness));
    }

    /// h_i^K = [k_i (p_i - p_i^d); 2 d_eta kappa_i d_eps] (5), dq = q_i (x) (q_i^d)^-1.
    Vector6<Scalar> stiffness_wrench(const Pose<Scalar>& pose, const Pose<Scalar>& desired) const noexcept
    {
        Vector6<Scalar> result;
        result.template head<3>() = translational_stiffness * (pose.position - desired.position);
        result.template tail<3>() = rotational_stiffness_torque(
            orientation_error(pose.orientation, desired.orientation), rotational_stiffness);
        return result;
    }

    /// Motion wrench h_i^x = M_i xdd_i^d - D_i (xdot_i - xdot_i^d) - h_i^K (6).
    template <typename DerivedTwist, typename DerivedDesiredTwist, typename DerivedDesiredAcceleration>
    Vector6<Scalar> motion_wrench(const Pose<Scalar>& pose, const Eigen::MatrixBase<DerivedTwist>& twist,
                                  const Pose<Scalar>& desired,
                                  const Eigen::MatrixBase<DerivedDesiredTwist>& desired_twist,
                                  const Eigen::MatrixBase<DerivedDesiredAcceleration>& desired_acceleration)
        const noexcept
    {
        const Vector6<Scalar> velocity_error = twist - desired_twist;
        Vector6<Scalar> result = -stiffness_wrench(pose, desired);
        result.template head<3>() += mass * desired_acceleration.template head<3>() -
                                     translational_damping * velocity_error.template head<3>();
        result.template tail<3>() += rotational_inertia * desired_acceleration.template tail<3>() -
                                     rotational_damping * velocity_error.template tail<3>();
        return result;
    }

    /// U_i = 1/2 k_i |p_i - p_i^d|^2 + 2 kappa_i |d_eps_i|^2 (docs/analysis.md, (39)):
    /// stiffness_wrench is its gradient.
    Scalar potential_energy(const Pose<Scalar>& pose, const Pose<Scalar>& desired) const noexcept
    {
        return Scalar(0.5) * translational_stiffness * (pose.position - desired.position).squaredNorm() +
               rotational_potential(orientation_error(pose.orientation, desired.orientation),
                                    rotational_stiffness);
    }

    /// Throws InvalidModel naming the arm and the parameter: mass > 0, J_i SPD, gains >= 0, all
    /// finite.
    void validate(Index arm) const
    {
        const detail::ErrorContext context = detail::arm_context(arm);
        detail::require_positive(mass, context, "mass");
        detail::require_symmetric_positive(rotational_inertia, context, "rotational_inertia");
        detail::require_non_negative(translational_damping, context, "translational_damping");
        detail::require_non_negative(rotational_damping, context, "rotational_damping");
        detail::require_non_negative(translational_stiffness, context, "translational_stiffness");
        detail::require_non_negative(rotational_stiffness, context, "rotational_stiffness");
    }

private:
    ImpedanceEndEffector with(Scalar ImpedanceEndEffector::*field, const Scalar& value) const
    {
        ImpedanceEndEffector result = *this;
        result.*field = value;
        return result;
    }
};

/// \brief The impedance concept: an end-effector model with damping() and stiffness() (D_i and the
/// linearised stiffness of (1), (5)) and a spring potential potential_energy(pose, desired).
/// The apparent impedance (Theorem 2), the storage function (Lemma 1) and impedance synthesis
/// accept exactly these models.
template <typename EndEffector, typename = void> struct is_impedance_end_effector : std::false_type {};
template <typename EndEffector>
struct is_impedance_end_effector<
    EndEffector,
    std::void_t<decltype(std::declval<const EndEffector&>().damping()),
                decltype(std::declval<const EndEffector&>().stiffness()),
                decltype(std::declval<const EndEffector&>().potential_energy(
                    std::declval<const Pose<typename EndEffector::Scalar>&>(),
                    std::declval<const Pose<typename EndEffector::Scalar>&>()))>> : std::true_type {};
template <typename EndEffector>
inline constexpr bool is_impedance_end_effector_v = is_impedance_end_effector<EndEffector>::value;

}  // namespace coopdyn
