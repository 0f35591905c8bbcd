/// \file
/// \brief The rigidly grasped object (docs/model.md, paper (8)-(9), (16) with errata E1).
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/detail/validation.hpp"
#include "coopdyn/spatial/inertia.hpp"

namespace coopdyn {

/// \brief Rigid object with reference point at its centre of mass:
/// M_o xdd_o + C_o xdot_o + h_g = h_o + htilde_o (8).
template <typename Scalar> struct RigidObject {
    /// m_o, kg.
    Scalar mass = Scalar(0);
    /// J_o in the body frame about the centre of mass, kg m^2; symmetric positive semi-definite
    /// (a zero moment about one axis, the paper's idealised thin beam, is accepted).
    Matrix3<Scalar> inertia_body = Matrix3<Scalar>::Zero();

    /// World-frame rotational inertia J_o = R(q) J_o_body R(q)^T (9).
    Matrix3<Scalar> rotational_inertia(const Matrix3<Scalar>& rotation) const
    {
        return inertia(rotation).rotational().matrix();
    }

    /// M_o = diag(m_o I3, J_o) (9) in {w}, about the centre of mass.
    CentralInertia<Scalar> inertia(const Matrix3<Scalar>& rotation) const
    {
        return CentralInertia<Scalar>(mass, inertia_body).rotated(rotation);
    }

    /// M_o = diag(m_o I3, J_o) (9), the dense 6x6 matrix in {w}.
    Matrix6<Scalar> spatial_inertia(const Matrix3<Scalar>& rotation) const { return inertia(rotation).matrix(); }

    /// C_o xdot_o = [0; w_o x (J_o w_o)] (9), with J_o in {w}.
    template <typename Derived>
    Vector6<Scalar> coriolis_wrench(const Matrix3<Scalar>& world_rotational_inertia,
                                    const Eigen::MatrixBase<Derived>& twist) const noexcept
    {
        Vector6<Scalar> result;
        const Vector3<Scalar> omega = twist.template tail<3>();
        result.template head<3>().setZero();
        result.template tail<3>() = omega.cross(world_rotational_inertia * omega);
        return result;
    }

    /// h_g = [-m_o g; 0] (9); g points down, e.g. (0, 0, -9.81).
    Vector6<Scalar> gravity_wrench(const Vector3<Scalar>& gravity) const noexcept
    {
        Vector6<Scalar> result;
        result.template head<3>() = -mass * gravity;
        result.template tail<3>().setZero();
        return result;
    }

    /// hSigma_o = htilde_o - C_o xdot_o - h_g of (16), gravity included (errata E1).
    template <typename DerivedTwist, typename DerivedDisturbance>
    Vector6<Scalar> h_sigma(const Matrix3<Scalar>& world_rotational_inertia,
                            const Eigen::MatrixBase<DerivedTwist>& twist,
                            const Eigen::MatrixBase<DerivedDisturbance>& disturbance,
                            const Vector3<Scalar>& gravity) const noexcept
    {
        return disturbance - coriolis_wrench(world_rotational_inertia, twist) - gravity_wrench(gravity);
    }

    /// Throws InvalidModel naming the parameter if mass or inertia_body is invalid: mass positive,
    /// inertia_body symmetric positive semi-definite with principal moments that satisfy the
    /// triangle inequality (a rigid body's; docs/model.md, "Degenerate parameters").
    void validate() const
    {
        detail::require_positive(mass, detail::object_context(), "mass");
        detail::require_symmetric_positive(inertia_body, detail::object_context(), "inertia_body",
                                           /*allow_semidefinite=*/true);
        detail::require_triangle_inequality(inertia_body, detail::object_context(), "inertia_body");
    }
};

}  // namespace coopdyn
