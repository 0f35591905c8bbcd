/// \file
/// \brief Energy and momentum of the cooperative system (object plus end-effectors), evaluated
/// on a Data filled by grasp_kinematics or interaction_dynamics. Used to check simulations
/// against physical invariants and for the storage function of Lemma 1 (docs/analysis.md).
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/model/cooperative_model.hpp"
#include "coopdyn/spatial/inertia.hpp"

namespace coopdyn {

/// M_o = diag(m_o I3, J_o) at the configuration in `data` (J_o in {w} from grasp_kinematics).
template <typename ModelType>
CentralInertia<typename ModelType::Scalar> object_inertia(const ModelType& model, const Data<ModelType>& data) noexcept
{
    return CentralInertia<typename ModelType::Scalar>(model.object().mass, data.object_rotational_inertia);
}

/// \brief Kinetic energy 1/2 xdot_o^T M_o xdot_o + sum_i 1/2 xdot_i^T M_i xdot_i.
template <typename ModelType>
typename ModelType::Scalar kinetic_energy(const ModelType& model, const Data<ModelType>& data) noexcept
{
    COOPDYN_REQUIRE_SHAPE(data.arms() == model.arms(), "Data was built for another model");
    using Scalar = typename ModelType::Scalar;
    Scalar energy = object_inertia(model, data).kinetic_energy(Motion<Scalar>::from(data.object_state.twist));
    for (Index i = 0; i < model.arms(); ++i) {
        energy += model.end_effector_inertia(i).kinetic_energy(Motion<Scalar>::from(data.end_effector_twist(i)));
    }
    return energy;
}

/// \brief Spring potential sum_i U_i of the end-effector stiffnesses (39), for the setpoints
/// (the springs' potential of Lemma 1, docs/analysis.md). Only for impedance end-effectors
/// (is_impedance_end_effector_v).
template <typename ModelType>
typename ModelType::Scalar spring_potential_energy(
    const ModelType& model, const Data<ModelType>& data,
    const Setpoints<typename ModelType::Scalar, ModelType::arms_at_compile_time>& setpoints) noexcept
{
    COOPDYN_REQUIRE_SHAPE(data.arms() == model.arms(), "Data was built for another model");
    COOPDYN_REQUIRE_SHAPE(setpoints.arms() == model.arms(), "setpoints sized for another number of arms");
    static_assert(is_impedance_end_effector_v<typename ModelType::EndEffectorModel>,
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
    COOPDYN_REQUIRE_SHAPE(data.arms() == model.arms(), "Data was built for another model");
    using Scalar = typename ModelType::Scalar;
    Vector3<Scalar> momentum = (object_inertia(model, data) * Motion<Scalar>::from(data.object_state.twist)).linear;
    for (Index i = 0; i < model.arms(); ++i) {
        momentum += (model.end_effector_inertia(i) * Motion<Scalar>::from(data.end_effector_twist(i))).linear;
    }
    return momentum;
}

/// \brief Total angular momentum about the world origin: for every body, its spatial momentum
/// M xdot (about its reference point) carried to the origin, p x (linear) + angular.
template <typename ModelType>
Vector3<typename ModelType::Scalar> angular_momentum(const ModelType& model, const Data<ModelType>& data) noexcept
{
    COOPDYN_REQUIRE_SHAPE(data.arms() == model.arms(), "Data was built for another model");
    using Scalar = typename ModelType::Scalar;
    const Force<Scalar> object_momentum =
        object_inertia(model, data) * Motion<Scalar>::from(data.object_state.twist);
    Vector3<Scalar> momentum = object_momentum.shifted(data.object_state.pose.position).angular;
    for (Index i = 0; i < model.arms(); ++i) {
        const Force<Scalar> arm_momentum = model.end_effector_inertia(i) * Motion<Scalar>::from(data.end_effector_twist(i));
        momentum += arm_momentum.shifted(Vector3<Scalar>(data.end_effector_positions.col(i))).angular;
    }
    return momentum;
}

}  // namespace coopdyn
