/// \file
/// \brief The cooperative Model / Data pair: an object rigidly grasped by N end-effectors
/// (docs/model.md), in the style of Pinocchio.
///
/// A Model holds what is constant: the object, the N end-effector models, the grasp (pose of
/// each end-effector frame in the object's body frame) and gravity. It is validated once, when
/// built. A Data, built from a Model, owns every buffer the per-tick algorithms write; after it is
/// built nothing allocates. Setpoints and Disturbances are the per-tick inputs.
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/detail/validation.hpp"
#include "coopdyn/model/impedance_end_effector.hpp"
#include "coopdyn/model/rigid_object.hpp"
#include "coopdyn/spatial/pose.hpp"
#include "coopdyn/spatial/spatial_vector.hpp"

#include <string>
#include <utility>
#include <vector>

namespace coopdyn {

/// \brief One arm of the cooperative system: its end-effector model and where it holds the object.
template <typename EndEffectorModel> struct Arm {
    using Scalar = typename EndEffectorModel::Scalar;
    EndEffectorModel end_effector{};
    /// Pose of the end-effector frame in the object's body frame: position r_i_body (from the
    /// object's centre of mass) and constant relative orientation dq_i, so that
    /// p_i = p_o + R(q_o) r_i_body and q_i = q_o (x) dq_i (the rigid grasp of (10)-(12),
    /// docs/model.md).
    Pose<Scalar> grasp_body{};
};

/// Standard gravity (0, 0, -9.81) m/s^2.
template <typename Scalar> Vector3<Scalar> standard_gravity() { return Vector3<Scalar>(0, 0, Scalar(-9.81)); }

/// \brief Constant part of the cooperative system.
/// \tparam ScalarType double, float or an autodiff scalar.
/// \tparam Arms number of arms N, or coopdyn::Dynamic to choose it at run time.
/// \tparam EndEffectorTemplate ImpedanceEndEffector (default) or ResolvedAccelerationEndEffector;
///         all arms share one model type.
template <typename ScalarType, int Arms = Dynamic,
          template <typename> class EndEffectorTemplate = ImpedanceEndEffector>
class Model {
public:
    static_assert(Arms == Dynamic || Arms >= 1, "a cooperative system needs at least one arm");
    using Scalar = ScalarType;
    using EndEffectorModel = EndEffectorTemplate<Scalar>;
    using ArmType = Arm<EndEffectorModel>;
    static constexpr int arms_at_compile_time = Arms;

    /// \brief Build and validate. Throws InvalidModel (naming the parameter and the arm) on
    /// invalid parameters, an empty arm list, a count that differs from a fixed N, non-finite
    /// grasp offsets or gravity, or a grasp orientation that is not a unit quaternion.
    Model(RigidObject<Scalar> object, std::vector<ArmType> arms,
          Vector3<Scalar> gravity = standard_gravity<Scalar>())
        : object_(std::move(object)), gravity_(std::move(gravity))
    {
        if (arms.empty()) {
            detail::fail(detail::model_context(), "arms", "must hold at least one arm (N = 0 given)");
        }
        if (Arms != Dynamic && static_cast<Index>(arms.size()) != Arms) {
            detail::fail(detail::model_context(), "arms",
                         "must hold exactly " + std::to_string(Arms) + " arms for this fixed-N model, got " +
                             std::to_string(arms.size()));
        }
        object_.validate();
        detail::require_finite(gravity_, detail::model_context(), "gravity");
        const Index count = static_cast<Index>(arms.size());
        grasp_offsets_body_.resize(3, count);
        grasp_orientations_body_.resize(4, count);
        end_effector_masses_.resize(count);
        end_effector_rotational_inertias_.resize(3, 3 * count);
        end_effector_inertias_.resize(6, 6 * count);
        if constexpr (Arms == Dynamic) {
            inertias_.resize(arms.size());
        }
        end_effectors_.resize(arms.size());
        for (Index i = 0; i < count; ++i) {
            const ArmType& arm = arms[static_cast<std::size_t>(i)];
            const detail::ErrorContext context = detail::arm_context(i);
            detail::require_finite(arm.grasp_body.position, context, "grasp_body.position");
            detail::require_unit_quaternion(arm.grasp_body.orientation, context, "grasp_body.orientation");
            grasp_offsets_body_.col(i) = arm.grasp_body.position;
            grasp_orientations_body_.col(i) = arm.grasp_body.orientation.coeffs();
            set_end_effector(i, arm.end_effector);
        }
    }

    /// \brief Replaces the end-effector model of arm `arm` (gain scheduling: new stiffness,
    /// damping or inertia between ticks), validated as at construction. Throws InvalidModel
    /// naming the arm and the parameter, and then leaves the model unchanged. Allocates nothing.
    /// A Simulator holding this model (by reference) uses the new parameters from its next step;
    /// a Data needs nothing (its sizes do not change).
    ///
    ///     auto arm = model.end_effector(0);
    ///     arm.translational_stiffness = 600.0;
    ///     model.set_end_effector(0, arm);
    void set_end_effector(Index arm, const EndEffectorModel& end_effector)
    {
        if (arm < 0 || arm >= arms()) {
            detail::fail(detail::model_context(), "arm", "index " + std::to_string(arm) + " is not an arm of this model");
        }
        end_effector.validate(arm);
        const auto index = static_cast<std::size_t>(arm);
        end_effectors_[index] = end_effector;
        inertias_[index] = end_effector.inertia();
        const Matrix6<Scalar> inertia = inertias_[index].matrix();
        end_effector_inertias_.template block<6, 6>(0, 6 * arm) = inertia;
        end_effector_masses_(arm) = inertia(0, 0);
        end_effector_rotational_inertias_.template block<3, 3>(0, 3 * arm) = inertia.template bottomRightCorner<3, 3>();
    }

    /// N.
    Index arms() const noexcept { return grasp_offsets_body_.cols(); }
    const RigidObject<Scalar>& object() const noexcept { return object_; }
    const EndEffectorModel& end_effector(Index arm) const noexcept
    {
        COOPDYN_ASSERT(arm >= 0 && arm < arms(), "arm index out of range");
        return end_effectors_[static_cast<std::size_t>(arm)];
    }
    const Vector3<Scalar>& gravity() const noexcept { return gravity_; }
    /// r_i_body side by side, 3 x N.
    const PerArmVector3<Scalar, Arms>& grasp_offsets_body() const noexcept { return grasp_offsets_body_; }
    /// dq_i of arm i.
    Eigen::Map<const Quaternion<Scalar>> grasp_orientation_body(Index arm) const noexcept
    {
        return Eigen::Map<const Quaternion<Scalar>>(grasp_orientations_body_.col(arm).data());
    }
    /// M_i of arm i, in the end-effector model's inertia type (CentralInertia for impedance
    /// end-effectors, ArticulatedInertia for resolved-acceleration ones).
    const typename EndEffectorModel::Inertia& end_effector_inertia(Index arm) const noexcept
    {
        COOPDYN_ASSERT(arm >= 0 && arm < arms(), "arm index out of range");
        return inertias_[static_cast<std::size_t>(arm)];
    }
    /// All M_i, one per arm (a std::array for fixed N), as the interaction kernels take them.
    const PerArm<typename EndEffectorModel::Inertia, Arms>& end_effector_inertia_list() const noexcept
    {
        return inertias_;
    }
    /// M_i side by side, 6 x 6N (the dense form the matrix kernels take).
    const PerArmMatrix6<Scalar, Arms>& end_effector_inertias() const noexcept { return end_effector_inertias_; }
    /// m_i (the (0, 0) entry of M_i), N; meaningful for block-diagonal end-effector inertias.
    const Eigen::Matrix<Scalar, Arms, 1>& end_effector_masses() const noexcept { return end_effector_masses_; }
    /// J_i side by side, 3 x 3N; meaningful for block-diagonal end-effector inertias.
    const PerArmMatrix3<Scalar, Arms>& end_effector_rotational_inertias() const noexcept
    {
        return end_effector_rotational_inertias_;
    }

private:
    RigidObject<Scalar> object_;
    Vector3<Scalar> gravity_;
    std::vector<EndEffectorModel> end_effectors_;
    PerArm<typename EndEffectorModel::Inertia, Arms> inertias_{};
    PerArmVector3<Scalar, Arms> grasp_offsets_body_;
    PerArmQuaternion<Scalar, Arms> grasp_orientations_body_;
    Eigen::Matrix<Scalar, Arms, 1> end_effector_masses_;
    PerArmMatrix3<Scalar, Arms> end_effector_rotational_inertias_;
    PerArmMatrix6<Scalar, Arms> end_effector_inertias_;
};

/// \brief Where grasp point i is on a rigidly held object: its offset r_i from the object's
/// centre of mass, its pose and its twist, all in {w}.
template <typename Scalar> struct GraspPoint {
    Vector3<Scalar> offset;   ///< r_i = R(q_o) r_i_body
    Pose<Scalar> pose;        ///< p_i = p_o + r_i, q_i = q_o (x) dq_i
    Vector6<Scalar> twist;    ///< xdot_i = G_i^T xdot_o (10)
};

/// \brief Rigid-grasp forward kinematics of arm `arm` for an object state (docs/model.md, (10),
/// (38)); `object_rotation` is R(q_o), passed in so that callers looping over the arms compute
/// it once. The one implementation behind grasp_kinematics (actual state) and
/// coordinate_setpoints (desired state). noexcept; allocation-free.
template <typename ModelType>
GraspPoint<typename ModelType::Scalar> grasp_point(const ModelType& model, Index arm,
                                                   const Matrix3<typename ModelType::Scalar>& object_rotation,
                                                   const RigidBodyState<typename ModelType::Scalar>& object) noexcept
{
    using Scalar = typename ModelType::Scalar;
    COOPDYN_ASSERT(arm >= 0 && arm < model.arms(), "arm index out of range");
    GraspPoint<Scalar> point;
    point.offset = object_rotation * model.grasp_offsets_body().col(arm);
    point.pose.position = object.pose.position + point.offset;
    point.pose.orientation = object.pose.orientation * model.grasp_orientation_body(arm);
    point.twist = Motion<Scalar>::from(object.twist).at_point(point.offset).vector();
    return point;
}

namespace detail {
/// The arm count of an input buffer: `arms` >= 1, and equal to a fixed N. Throws InvalidArgument.
template <int Arms> Index checked_arm_count(Index arms, const char* component)
{
    if (arms < 1 || (Arms != Dynamic && arms != Arms)) {
        fail(argument_context(component), "arms",
             "must be " + (Arms == Dynamic ? std::string("at least 1") : std::to_string(Arms) + " (the fixed N)") +
                 ", got " + std::to_string(arms));
    }
    return arms;
}
/// `arm`, asserted (debug builds) to be an arm index of a container of `arms` arms.
inline Index checked_arm(Index arm, Index arms) noexcept
{
    COOPDYN_ASSERT(arm >= 0 && arm < arms, "arm index out of range");
    (void)arms;
    return arm;
}
}  // namespace detail

/// \brief Per-tick inputs of the end-effector controllers: desired poses x_i^d, twists
/// xdot_i^d, accelerations xdd_i^d and wrenches h_i^d (1). Sized once.
template <typename Scalar, int Arms> struct Setpoints {
    PerArmVector3<Scalar, Arms> positions;         ///< p_i^d side by side, 3 x N
    PerArmQuaternion<Scalar, Arms> orientations;   ///< q_i^d coefficients (x, y, z, w), 4 x N
    EndEffectorVector<Scalar, Arms> twists;        ///< xdot_i^d stacked, 6N
    EndEffectorVector<Scalar, Arms> accelerations; ///< xdd_i^d stacked, 6N
    EndEffectorVector<Scalar, Arms> wrenches;      ///< h_i^d stacked, 6N (desired wrench ON arm i)

    /// Zero motion and wrench, identity orientations, for a fixed N. A dynamic-N Setpoints has no
    /// default constructor: it would have no arms.
    template <int A = Arms, std::enable_if_t<A != Dynamic, int> = 0> Setpoints() : Setpoints(Index(Arms)) {}
    /// Zero motion and wrench, identity orientations, for `arms` arms. Throws InvalidArgument
    /// ("setpoints", "arms") unless arms >= 1 and, for a fixed N, arms == N.
    explicit Setpoints(Index arms)
        : positions(PerArmVector3<Scalar, Arms>::Zero(3, detail::checked_arm_count<Arms>(arms, "setpoints"))),
          orientations(PerArmQuaternion<Scalar, Arms>::Zero(4, arms)),
          twists(EndEffectorVector<Scalar, Arms>::Zero(6 * arms)),
          accelerations(EndEffectorVector<Scalar, Arms>::Zero(6 * arms)),
          wrenches(EndEffectorVector<Scalar, Arms>::Zero(6 * arms))
    {
        orientations.row(3).setOnes();
    }

    Index arms() const noexcept { return positions.cols(); }
    Pose<Scalar> pose(Index arm) const noexcept
    {
        COOPDYN_ASSERT(arm >= 0 && arm < arms(), "arm index out of range");
        return Pose<Scalar>{positions.col(arm), Quaternion<Scalar>(orientations.col(arm))};
    }
    void set_pose(Index arm, const Pose<Scalar>& pose) noexcept
    {
        COOPDYN_ASSERT(arm >= 0 && arm < arms(), "arm index out of range");
        positions.col(arm) = pose.position;
        orientations.col(arm) = pose.orientation.coeffs();
    }
    auto twist(Index arm) noexcept { return twists.template segment<6>(6 * checked(arm)); }
    auto twist(Index arm) const noexcept { return twists.template segment<6>(6 * checked(arm)); }
    auto acceleration(Index arm) noexcept { return accelerations.template segment<6>(6 * checked(arm)); }
    auto acceleration(Index arm) const noexcept { return accelerations.template segment<6>(6 * checked(arm)); }
    auto wrench(Index arm) noexcept { return wrenches.template segment<6>(6 * checked(arm)); }
    auto wrench(Index arm) const noexcept { return wrenches.template segment<6>(6 * checked(arm)); }

private:
    Index checked(Index arm) const noexcept { return detail::checked_arm(arm, arms()); }
};

/// \brief Disturbance wrenches: htilde_o on the object (8) and htilde_i on each end-effector (1).
template <typename Scalar, int Arms> struct Disturbances {
    Vector6<Scalar> object = Vector6<Scalar>::Zero();
    EndEffectorVector<Scalar, Arms> end_effectors;

    /// Zero disturbances for a fixed N (a dynamic-N Disturbances has no default constructor).
    template <int A = Arms, std::enable_if_t<A != Dynamic, int> = 0> Disturbances() : Disturbances(Index(Arms)) {}
    /// Zero disturbances for `arms` arms. Throws InvalidArgument ("disturbances", "arms") unless
    /// arms >= 1 and, for a fixed N, arms == N.
    explicit Disturbances(Index arms)
        : end_effectors(EndEffectorVector<Scalar, Arms>::Zero(6 * detail::checked_arm_count<Arms>(arms, "disturbances")))
    {
    }
    Index arms() const noexcept { return end_effectors.size() / 6; }
    auto end_effector(Index arm) noexcept { return end_effectors.template segment<6>(6 * checked(arm)); }
    auto end_effector(Index arm) const noexcept { return end_effectors.template segment<6>(6 * checked(arm)); }

private:
    Index checked(Index arm) const noexcept { return detail::checked_arm(arm, arms()); }
};

/// \brief Buffers and results of the per-tick algorithms for one Model. Build once, reuse every
/// tick: nothing is allocated afterwards.
template <typename ModelType> struct Data {
    using Scalar = typename ModelType::Scalar;
    static constexpr int Arms = ModelType::arms_at_compile_time;

    explicit Data(const ModelType& model)
        : grasp_offsets(PerArmVector3<Scalar, Arms>::Zero(3, model.arms())),
          end_effector_positions(PerArmVector3<Scalar, Arms>::Zero(3, model.arms())),
          end_effector_orientations(PerArmQuaternion<Scalar, Arms>::Zero(4, model.arms())),
          end_effector_twists(EndEffectorVector<Scalar, Arms>::Zero(6 * model.arms())),
          motion_wrenches(EndEffectorVector<Scalar, Arms>::Zero(6 * model.arms())),
          h_sigma(FullStackVector<Scalar, Arms>::Zero(6 * (model.arms() + 1))),
          accelerations(FullStackVector<Scalar, Arms>::Zero(6 * (model.arms() + 1))),
          wrenches(FullStackVector<Scalar, Arms>::Zero(6 * (model.arms() + 1)))
    {
        end_effector_orientations.row(3).setOnes();
    }

    // --- Grasp kinematics (grasp_kinematics) ---
    RigidBodyState<Scalar> object_state{};                               ///< the state last used
    Matrix3<Scalar> object_rotation = Matrix3<Scalar>::Identity();       ///< R(q_o)
    Matrix3<Scalar> object_rotational_inertia = Matrix3<Scalar>::Zero(); ///< J_o in {w} (9)
    PerArmVector3<Scalar, Arms> grasp_offsets;                           ///< r_i in {w}, 3 x N
    PerArmVector3<Scalar, Arms> end_effector_positions;                  ///< p_i, 3 x N
    PerArmQuaternion<Scalar, Arms> end_effector_orientations;            ///< q_i, (x, y, z, w), 4 x N
    EndEffectorVector<Scalar, Arms> end_effector_twists;                 ///< xdot_i stacked, 6N

    // --- Dynamics (interaction_dynamics) ---
    EndEffectorVector<Scalar, Arms> motion_wrenches;  ///< h_i^x (6) or h_i^Pi (20), stacked, 6N
    FullStackVector<Scalar, Arms> h_sigma;            ///< [hSigma_o; hSigma_1; ...] (15)-(16)
    FullStackVector<Scalar, Arms> accelerations;      ///< [xdd_o; xdd_1; ...]
    FullStackVector<Scalar, Arms> wrenches;           ///< [h_o; h_1; ...], wrench ON each body

    /// N of the model this Data was built for (the per-tick functions stop the program with a
    /// message, also in Release, when it differs from their model's).
    Index arms() const noexcept { return grasp_offsets.cols(); }
    Pose<Scalar> end_effector_pose(Index arm) const noexcept
    {
        return Pose<Scalar>{end_effector_positions.col(checked(arm)),
                            Quaternion<Scalar>(end_effector_orientations.col(arm))};
    }
    auto end_effector_twist(Index arm) const noexcept
    {
        return end_effector_twists.template segment<6>(6 * checked(arm));
    }
    auto object_acceleration() const noexcept { return accelerations.template head<6>(); }
    auto end_effector_acceleration(Index arm) const noexcept
    {
        return accelerations.template segment<6>(6 * (checked(arm) + 1));
    }
    /// h_o, the wrench the end-effectors exert on the object (= -G h', (23)).
    auto object_wrench() const noexcept { return wrenches.template head<6>(); }
    /// h_i, the wrench the object exerts on end-effector i.
    auto end_effector_wrench(Index arm) const noexcept
    {
        return wrenches.template segment<6>(6 * (checked(arm) + 1));
    }
    /// -h_i: the wrench end-effector i exerts on the object, at grasp point i (force, and torque
    /// about the grasp point), in {w}.
    Vector6<Scalar> wrench_on_object(Index arm) const noexcept { return -end_effector_wrench(arm); }
    /// G_i (-h_i) (24): the same wrench moved to the object's centre of mass (torque about it).
    /// The N of them sum to h_o.
    Vector6<Scalar> wrench_on_object_at_centre(Index arm) const noexcept
    {
        return Force<Scalar>::from(wrench_on_object(arm)).shifted(grasp_offsets.col(arm)).vector();
    }
    /// The end-effector part h' = [h_1; ...; h_N] (6N).
    auto end_effector_wrenches() const noexcept
    {
        if constexpr (Arms == Dynamic) {
            return wrenches.tail(6 * arms());
        } else {
            return wrenches.template tail<end_effector_stack_size(Arms)>();
        }
    }

private:
    Index checked(Index arm) const noexcept { return detail::checked_arm(arm, arms()); }
};

template <typename Scalar, int Arms, template <typename> class EndEffectorTemplate>
Data(const Model<Scalar, Arms, EndEffectorTemplate>&) -> Data<Model<Scalar, Arms, EndEffectorTemplate>>;

/// Common instantiations.
template <int Arms> using ImpedanceModel = Model<double, Arms, ImpedanceEndEffector>;
using ImpedanceModel2 = ImpedanceModel<2>;
using ImpedanceModelX = ImpedanceModel<Dynamic>;

}  // namespace coopdyn
