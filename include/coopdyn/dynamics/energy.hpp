/// \file
/// \brief Energy and momentum of the cooperative system (object plus end-effectors), evaluated
/// on a Data filled by grasp_kinematics or interaction_dynamics. Used to check simulations
/// against physical invariants and for the storage function of docs/analysis.md.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/model/cooperative_model.hpp"

namespace coopdyn {

/// \brief Kinetic energy 1/2 xdot_o^T M_o xdot_o + sum_i 1/2 xdot_i^T M_i xdot_i.
template <typename ModelType>
typename ModelType::Scalar kinetic_energy(const ModelType& model, const Data<ModelType>& data) noexcept
{
    using Scalar = typename ModelType::Scalar;
    const auto& twist = data.object_state.twist;
    const Vector3<Scalar> omega = twist.template tail<3>();
    Scalar energy = Scalar(0.5) * model.object().mass * twist.template head<3>().squaredNorm() +
                    Scalar(0.5) * omega.dot(data.object_rotational_inertia * omega);
    for (Index i = 0; i < model.arms(); ++i) {
        const Vector6<Scalar> arm_twist = data.end_effector_twist(i);
        energy += Scalar(0.5) *
                  arm_twist.dot(model.end_effector_inertias().template block<6, 6>(0, 6 * i) * arm_twist);
    }
    return energy;
}

/// \brief Spring potential sum_i U_i of the end-effector stiffnesses (39), for the setpoints.
/// Only for end-effector models whose stiffness has a potential (ImpedanceEndEffector).
template <typename ModelType>
typename ModelType::Scalar spring_potential_energy(
    const ModelType& model, const Data<ModelType>& data,
    const Setpoints<typename ModelType::Scalar, ModelType::arms_at_compile_time>& setpoints) noexcept
{
    static_assert(ModelType::EndEffectorModel::has_potential_energy,
                  "this end-effector model's stiffness has no potential");
    using Scalar = typename ModelType::Scalar;
    Scalar energy(0);
    for (Index i = 0; i < model.arms(); ++i) {
        energy += model.end_effector(i).potential_energy(data.end_effector_pose(i), setpoints.pose(i));
    }
    return energy;
}

/// \brief Gravitational potential of the object, -m_o g^T p_o (7) with errata E7. The
/// impedance-controlled end-effectors are gravity-compensated and carry none.
template <typename ModelType>
typename ModelType::Scalar gravity_potential_energy(const ModelType& model, const Data<ModelType>& data) noexcept
{
    return -model.object().mass * model.gravity().dot(data.object_state.pose.position);
}

/// \brief Total linear momentum m_o v_o + sum_i (M_i xdot_i)_linear.
template <typename ModelType>
Vector3<typename ModelType::Scalar> linear_momentum(const ModelType& model, const Data<ModelType>& data) noexcept
{
    using Scalar = typename ModelType::Scalar;
    Vector3<Scalar> momentum = model.object().mass * data.object_state.twist.template head<3>();
    for (Index i = 0; i < model.arms(); ++i) {
        momentum += model.end_effector_inertias().template block<3, 6>(0, 6 * i) * data.end_effector_twist(i);
    }
    return momentum;
}

/// \brief Total angular momentum about the world origin: for every body, p x (linear momentum)
/// plus its angular momentum about its own reference point.
template <typename ModelType>
Vector3<typename ModelType::Scalar> angular_momentum(const ModelType& model, const Data<ModelType>& data) noexcept
{
    using Scalar = typename ModelType::Scalar;
    const auto& state = data.object_state;
    const Vector3<Scalar> omega = state.twist.template tail<3>();
    Vector3<Scalar> momentum =
        state.pose.position.cross(model.object().mass * state.twist.template head<3>()) +
        data.object_rotational_inertia * omega;
    for (Index i = 0; i < model.arms(); ++i) {
        const Vector6<Scalar> spatial_momentum =
            model.end_effector_inertias().template block<6, 6>(0, 6 * i) * data.end_effector_twist(i);
        momentum += Vector3<Scalar>(data.end_effector_positions.col(i)).cross(spatial_momentum.template head<3>()) +
                    spatial_momentum.template tail<3>();
    }
    return momentum;
}

}  // namespace coopdyn
