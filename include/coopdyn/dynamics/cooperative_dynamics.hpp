/// \file
/// \brief Per-tick algorithms on the cooperative Model/Data: grasp kinematics and the
/// interaction dynamics (docs/model.md, docs/dynamics.md; the block scheme of paper Fig. 2).
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/dynamics/input_check.hpp"
#include "coopdyn/dynamics/interaction_wrenches.hpp"
#include "coopdyn/model/cooperative_model.hpp"
#include "coopdyn/model/grasp.hpp"


namespace coopdyn {

/// \brief Rigid-grasp kinematics (docs/model.md, paper (10)): from the object state, fill
/// data.object_state, object_rotation, object_rotational_inertia (J_o in {w}), grasp_offsets
/// (r_i = R(q_o) r_i_body), end-effector poses (p_i = p_o + r_i, q_i = q_o (x) dq_i) and twists
/// (xdot_i = G_i^T xdot_o). noexcept; allocation-free.
template <typename ModelType>
void grasp_kinematics(const ModelType& model, Data<ModelType>& data,
                      const RigidBodyState<typename ModelType::Scalar>& object_state) noexcept
{
    using Scalar = typename ModelType::Scalar;
    COOPDYN_REQUIRE_SHAPE(data.arms() == model.arms(), "Data was built for another model");
    COOPDYN_ASSERT_INPUTS(check_state(object_state));
    data.object_state = object_state;
    data.object_rotation = object_state.pose.orientation.toRotationMatrix();
    data.object_rotational_inertia = model.object().rotational_inertia(data.object_rotation);
    for (Index i = 0; i < model.arms(); ++i) {
        const GraspPoint<Scalar> point = grasp_point(model, i, data.object_rotation, object_state);
        data.grasp_offsets.col(i) = point.offset;
        data.end_effector_positions.col(i) = point.pose.position;
        data.end_effector_orientations.col(i) = point.pose.orientation.coeffs();
        data.end_effector_twists.template segment<6>(6 * i) = point.twist;
    }
}

/// \brief One tick of the cooperative dynamics: grasp kinematics, the end-effector motion
/// wrenches h_i^x (6) (or h_i^Pi (20)), hSigma_i = h_i^x - h_i^d + htilde_i (15), hSigma_o (16)
/// with gravity (E1), then the structured interaction solve of (18) (docs/dynamics.md).
///
/// Fills every field of `data`; returns data.wrenches = [h_o; h_1; ...; h_N]. The solver's path
/// is chosen at compile time from the end-effector model's inertia type.
/// noexcept; allocation-free (also for N = Dynamic, once `data` is built).
template <typename ModelType>
const FullStackVector<typename ModelType::Scalar, ModelType::arms_at_compile_time>&
interaction_dynamics(const ModelType& model, Data<ModelType>& data,
                     const RigidBodyState<typename ModelType::Scalar>& object_state,
                     const Setpoints<typename ModelType::Scalar, ModelType::arms_at_compile_time>& setpoints,
                     const Disturbances<typename ModelType::Scalar, ModelType::arms_at_compile_time>& disturbances) noexcept
{
    using Scalar = typename ModelType::Scalar;
    COOPDYN_REQUIRE_SHAPE(setpoints.arms() == model.arms(), "setpoints sized for another number of arms");
    COOPDYN_REQUIRE_SHAPE(disturbances.arms() == model.arms(), "disturbances sized for another number of arms");
    // Unit quaternions and finite values (docs/conventions.md); check_inputs() in Release.
    COOPDYN_ASSERT_INPUTS(check_inputs(model, object_state, setpoints, disturbances));
    grasp_kinematics(model, data, object_state);

    for (Index i = 0; i < model.arms(); ++i) {
        const Vector6<Scalar> motion_wrench = model.end_effector(i).motion_wrench(
            data.end_effector_pose(i), data.end_effector_twist(i), setpoints.pose(i), setpoints.twist(i),
            setpoints.acceleration(i));
        data.motion_wrenches.template segment<6>(6 * i) = motion_wrench;
        data.h_sigma.template segment<6>(6 * (i + 1)) =
            motion_wrench - setpoints.wrench(i) + disturbances.end_effector(i);
    }
    data.h_sigma.template head<6>() = model.object().h_sigma(
        data.object_rotational_inertia, object_state.twist, disturbances.object, model.gravity());

    // The inertias' types choose the solver's path (closed form for diag(m I3, J) bodies).
    interaction_wrenches(CentralInertia<Scalar>(model.object().mass, data.object_rotational_inertia),
                         model.end_effector_inertia_list(), data.grasp_offsets,
                         object_state.twist.template tail<3>(), data.h_sigma, data.accelerations, data.wrenches);
    return data.wrenches;
}

}  // namespace coopdyn
