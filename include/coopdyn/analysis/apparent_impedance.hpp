/// \file
/// \brief Apparent object impedance of the cooperative system (Theorem 2, docs/analysis.md,
/// errata E3): inertia (31), damping (32), the exact linearised stiffness, the exact nonlinear
/// restoring wrench and the apparent Coriolis/centrifugal wrench of the reduced model (30).
///
/// Under ideal feedback linearisation, gravity compensated by (26), and constant setpoints x_i^d at
/// the grasp poses of an object equilibrium, the object obeys exactly
///
///     M xdd_o + (C_o xdot_o + sum_i G_i M_i b_i) + D xdot_o + h_o^K(x_o) = htilde_o      (30)
///
/// with M = M_o + sum G_i M_i G_i^T (31), D = sum G_i D_i G_i^T (32) and
/// h_o^K(x_o) = sum G_i h_i^K(x_i(x_o), x_i^d). Its linearisation in a twist displacement is
/// K = sum G_i diag(k_i I3, kappa_i I3) G_i^T, symmetric positive definite. The printed (33)-(34)
/// put k_i S(r_i)^T in the lower-left block and zero in the upper-right (E3); that is only right
/// when sum k_i r_i = 0.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/dynamics/cooperative_dynamics.hpp"
#include "coopdyn/dynamics/energy.hpp"
#include "coopdyn/model/cooperative_model.hpp"
#include "coopdyn/model/grasp.hpp"
#include "coopdyn/spatial/inertia.hpp"

#include <Eigen/Cholesky>

namespace coopdyn {

/// \brief Apparent object impedance M, D, K of Theorem 2, 6x6 each, in {w} about the object's
/// centre of mass.
template <typename Scalar> struct ApparentImpedance {
    Matrix6<Scalar> inertia = Matrix6<Scalar>::Zero();    ///< M (31)
    Matrix6<Scalar> damping = Matrix6<Scalar>::Zero();    ///< D (32)
    Matrix6<Scalar> stiffness = Matrix6<Scalar>::Zero();  ///< K, exact linearisation (E3)
};

namespace detail {

/// M, D and K of Theorem 2 as sums of shifted inertias: M = M_o + sum G_i M_i G_i^T (31),
/// D = sum G_i D_i G_i^T (32), K = sum G_i diag(k_i I3, kappa_i I3) G_i^T (E3). The congruence
/// G_i X G_i^T is the parallel-axis shift of the spatial layer (add_shifted), so the formula
/// exists once; `Inertia` is SpatialInertia for impedance end-effectors, ArticulatedInertia for
/// dense 6x6 blocks.
template <typename Inertia> struct ImpedanceSums {
    Inertia inertia;
    Inertia damping;
    Inertia stiffness;

    /// Adds arm i's M_i, D_i and stiffness, grasped at r_i.
    template <typename ArmInertia, typename ArmDamping, typename ArmStiffness, typename DerivedR>
    void add_arm(const ArmInertia& arm_inertia, const ArmDamping& arm_damping, const ArmStiffness& arm_stiffness,
                 const Eigen::MatrixBase<DerivedR>& r_i)
    {
        const Vector3<typename Inertia::Scalar> offset = r_i;
        inertia.add_shifted(arm_inertia, offset);
        damping.add_shifted(arm_damping, offset);
        stiffness.add_shifted(arm_stiffness, offset);
    }

    ApparentImpedance<typename Inertia::Scalar> matrices() const
    {
        ApparentImpedance<typename Inertia::Scalar> result;
        result.inertia = inertia.matrix();
        result.damping = damping.matrix();
        result.stiffness = stiffness.matrix();
        return result;
    }
};

/// Symmetric to a relative 1e-9 of the largest entry (on the values of autodiff scalars).
template <typename Derived> bool is_symmetric(const Eigen::MatrixBase<Derived>& matrix)
{
    const auto values = values_of(matrix).eval();
    return (values - values.transpose()).cwiseAbs().maxCoeff() <=
           tolerance_for<typename Derived::Scalar>(1e-9) * values.cwiseAbs().maxCoeff();
}

/// Block `arm` of a 6 x 6N stack as an ArticulatedInertia, which reads its lower triangle; the
/// block must be symmetric (asserted in debug builds).
template <typename Derived>
ArticulatedInertia<typename Derived::Scalar> symmetric_block(const Eigen::MatrixBase<Derived>& stack, Index arm) noexcept
{
    COOPDYN_ASSERT(is_symmetric(stack.template block<6, 6>(0, 6 * arm)),
                   "apparent_impedance reads the lower triangle of symmetric 6x6 blocks");
    return ArticulatedInertia<typename Derived::Scalar>(stack.template block<6, 6>(0, 6 * arm));
}

/// The sums of a Model of impedance end-effectors at the configuration in `data`.
template <typename ModelType>
ImpedanceSums<SpatialInertia<typename ModelType::Scalar>> apparent_impedance_sums(const ModelType& model,
                                                                                  const Data<ModelType>& data) noexcept
{
    COOPDYN_REQUIRE_SHAPE(data.arms() == model.arms(), "Data was built for another model");
    static_assert(is_impedance_end_effector_v<typename ModelType::EndEffectorModel>,
                  "the apparent impedance needs impedance end-effectors (damping() and stiffness())");
    ImpedanceSums<SpatialInertia<typename ModelType::Scalar>> sums;
    sums.inertia = model.object().inertia(data.object_rotation);
    for (Index i = 0; i < model.arms(); ++i) {
        const auto& arm = model.end_effector(i);
        sums.add_arm(model.end_effector_inertia(i), arm.damping(), arm.stiffness(), data.grasp_offsets.col(i));
    }
    return sums;
}

}  // namespace detail

/// \brief Apparent impedance (31), (32) and exact K of the cooperative system, from dense
/// matrices: the same sums of shifted inertias as the Model/Data overload, on ArticulatedInertia.
/// \param object_inertia M_o, 6x6 in {w}.
/// \param ee_inertia 6 x 6N, the M_i side by side.
/// \param ee_damping 6 x 6N, the D_i side by side (diag(d_i I3, delta_i I3) in (1)).
/// \param ee_stiffness 6 x 6N, the linearised stiffnesses side by side (diag(k_i I3, kappa_i I3)).
/// \param r 3 x N grasp offsets in {w}.
/// Precondition: every 6x6 block is symmetric, as the inertia, damping and stiffness of (1) are
/// (asserted in debug builds): ArticulatedInertia reads the lower triangle, so the upper triangle
/// of a non-symmetric block would be ignored. Symmetric blocks may be fully coupled.
template <typename DerivedObject, typename DerivedInertia, typename DerivedDamping, typename DerivedStiffness,
          typename DerivedR>
ApparentImpedance<typename DerivedObject::Scalar>
apparent_impedance(const Eigen::MatrixBase<DerivedObject>& object_inertia,
                   const Eigen::MatrixBase<DerivedInertia>& ee_inertia,
                   const Eigen::MatrixBase<DerivedDamping>& ee_damping,
                   const Eigen::MatrixBase<DerivedStiffness>& ee_stiffness, const Eigen::MatrixBase<DerivedR>& r) noexcept
{
    const Index arms = r.cols();
    COOPDYN_ASSERT(ee_inertia.cols() == 6 * arms && ee_damping.cols() == 6 * arms && ee_stiffness.cols() == 6 * arms,
                   "per-arm matrices must be 6 x 6N");
    detail::ImpedanceSums<ArticulatedInertia<typename DerivedObject::Scalar>> sums;
    sums.inertia = detail::symmetric_block(object_inertia, 0);
    for (Index i = 0; i < arms; ++i) {
        sums.add_arm(detail::symmetric_block(ee_inertia, i), detail::symmetric_block(ee_damping, i),
                     detail::symmetric_block(ee_stiffness, i), r.col(i));
    }
    return sums.matrices();
}

/// \brief Apparent impedance of a Model of impedance end-effectors at the configuration in
/// `data` (after grasp_kinematics or interaction_dynamics): r_i and J_o are taken from `data`.
/// M (31) and D (32) are exact at every configuration (1/2 xdot_o^T M xdot_o is the kinetic
/// energy of object and end-effectors, xdot_o^T D xdot_o the power of the dampers). K is the
/// Jacobian of restoring_wrench only where the springs are unloaded (x_o at the equilibrium
/// whose grasp poses are the setpoints); at a loaded configuration the Jacobian has further
/// load-dependent terms that this K does not contain.
template <typename ModelType>
ApparentImpedance<typename ModelType::Scalar> apparent_impedance(const ModelType& model,
                                                                 const Data<ModelType>& data) noexcept
{
    return detail::apparent_impedance_sums(model, data).matrices();
}

/// \brief Exact nonlinear restoring wrench h_o^K(x_o) = sum_i G_i h_i^K(x_i(x_o), x_i^d) at the
/// configuration in `data` (after grasp_kinematics), for the setpoint poses in `setpoints`.
template <typename ModelType>
Vector6<typename ModelType::Scalar> restoring_wrench(
    const ModelType& model, const Data<ModelType>& data,
    const Setpoints<typename ModelType::Scalar, ModelType::arms_at_compile_time>& setpoints) noexcept
{
    COOPDYN_REQUIRE_SHAPE(data.arms() == model.arms(), "Data was built for another model");
    COOPDYN_REQUIRE_SHAPE(setpoints.arms() == model.arms(), "setpoints sized for another number of arms");
    using Scalar = typename ModelType::Scalar;
    Vector6<Scalar> result = Vector6<Scalar>::Zero();
    for (Index i = 0; i < model.arms(); ++i) {
        result += grasp_map_wrench(data.grasp_offsets.col(i),
                                   model.end_effector(i).stiffness_wrench(data.end_effector_pose(i), setpoints.pose(i)));
    }
    return result;
}

/// \brief Apparent Coriolis/centrifugal wrench of (30): C_o xdot_o + sum_i G_i M_i b_i, at the
/// configuration and twist in `data`.
template <typename ModelType>
Vector6<typename ModelType::Scalar> apparent_coriolis_wrench(const ModelType& model, const Data<ModelType>& data) noexcept
{
    COOPDYN_REQUIRE_SHAPE(data.arms() == model.arms(), "Data was built for another model");
    using Scalar = typename ModelType::Scalar;
    const auto& twist = data.object_state.twist;
    const Vector3<Scalar> omega = twist.template tail<3>();
    Vector6<Scalar> result = model.object().coriolis_wrench(data.object_rotational_inertia, twist);
    for (Index i = 0; i < model.arms(); ++i) {
        const Vector3<Scalar> r_i = data.grasp_offsets.col(i);
        // G_i M_i b_i, b_i = [S(w_o)^2 r_i; 0]
        result += model.end_effector_inertia(i).apply_translation(centripetal_acceleration(r_i, omega)).shifted(r_i).vector();
    }
    return result;
}

/// \brief Object acceleration of the reduced 6-DOF model (30):
/// xdd_o = M^-1 (htilde_o - (C_o xdot_o + sum G_i M_i b_i) - D xdot_o - h_o^K(x_o)).
/// Fills the grasp kinematics of `data` for `object_state`. Valid under the assumptions of
/// Theorem 2: constant setpoints (setpoint twists and accelerations zero; they are not read) and
/// gravity compensated by the desired wrenches at the current configuration,
/// G(x_o) hbar^d = h_g. Desired wrenches held constant do that at every orientation only when
/// the torque sum_i r_i x f_i^d does not change as the r_i rotate (e.g. equal forces on a grasp
/// with sum_i r_i = 0, as for the Section V beam); otherwise the full model sees an extra
/// configuration-dependent torque that (30) does not contain. Without gravity and with zero
/// desired wrenches it is exact for any grasp.
template <typename ModelType>
Vector6<typename ModelType::Scalar> reduced_model_acceleration(
    const ModelType& model, Data<ModelType>& data, const RigidBodyState<typename ModelType::Scalar>& object_state,
    const Setpoints<typename ModelType::Scalar, ModelType::arms_at_compile_time>& setpoints,
    const Vector6<typename ModelType::Scalar>& object_disturbance) noexcept
{
    COOPDYN_REQUIRE_SHAPE(data.arms() == model.arms(), "Data was built for another model");
    COOPDYN_REQUIRE_SHAPE(setpoints.arms() == model.arms(), "setpoints sized for another number of arms");
    using Scalar = typename ModelType::Scalar;
    grasp_kinematics(model, data, object_state);
    const ApparentImpedance<Scalar> impedance = apparent_impedance(model, data);
    const Vector6<Scalar> wrench = object_disturbance - apparent_coriolis_wrench(model, data) -
                                   impedance.damping * object_state.twist - restoring_wrench(model, data, setpoints);
    return impedance.inertia.llt().solve(wrench);
}

/// \brief Storage function of Lemma 1 ((47) with gravity compensated, docs/analysis.md):
/// V = 1/2 xdot_o^T M xdot_o + sum_i U_i, at the state in `data`, for the setpoint poses: the
/// kinetic energy of the apparent inertia M (31) plus spring_potential_energy (the U_i of
/// ImpedanceEndEffector::potential_energy).
template <typename ModelType>
typename ModelType::Scalar storage_function(
    const ModelType& model, const Data<ModelType>& data,
    const Setpoints<typename ModelType::Scalar, ModelType::arms_at_compile_time>& setpoints) noexcept
{
    COOPDYN_REQUIRE_SHAPE(data.arms() == model.arms(), "Data was built for another model");
    COOPDYN_REQUIRE_SHAPE(setpoints.arms() == model.arms(), "setpoints sized for another number of arms");
    using Scalar = typename ModelType::Scalar;
    return detail::apparent_impedance_sums(model, data).inertia.kinetic_energy(Motion<Scalar>::from(data.object_state.twist)) +
           spring_potential_energy(model, data, setpoints);
}

}  // namespace coopdyn
