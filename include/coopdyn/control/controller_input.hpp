/// \file
/// \brief ControllerInput: what the user's kinematics/dynamics library and state estimate give the
/// controller each tick, and the optional fault inputs (the object measurement's stale flag, the
/// contacts' poses). Included by controller_model.hpp; docs/control.md, "The input".
#pragma once

#include "coopdyn/config.hpp"
#include "coopdyn/control/controller_model.hpp"
#include "coopdyn/spatial/pose.hpp"
#include "coopdyn/spatial/spatial_vector.hpp"

#include <type_traits>

namespace coopdyn {

/// \brief What the user's kinematics/dynamics library and state estimate give the controller each
/// tick (docs/control.md, "Inputs and sign conventions"). Sized by the model; fill in place.
template <typename ScalarType, int ArmsAtCompileTime = Eigen::Dynamic, int JointsAtCompileTime = Eigen::Dynamic>
struct ControllerInput {
    using Scalar = ScalarType;
    static constexpr int Arms = ArmsAtCompileTime;
    static constexpr int Joints = JointsAtCompileTime;
    using JointVector = Eigen::Matrix<Scalar, Joints, 1>;

    ControllerInput(Index arms, Index joints)
        : inertia(Eigen::Matrix<Scalar, Joints, Joints>::Identity(joints, joints)),
          bias(JointVector::Zero(joints)),
          jacobian(Eigen::Matrix<Scalar, times_six(Arms), Joints>::Zero(6 * arms, joints)),
          jacobian_rate_qdot(Eigen::Matrix<Scalar, times_six(Arms), 1>::Zero(6 * arms)),
          positions(JointVector::Zero(joints)),
          velocities(JointVector::Zero(joints)),
          posture(JointVector::Zero(joints)),
          contact_positions(Eigen::Matrix<Scalar, 3, Arms>::Zero(3, arms)),
          contact_orientations(identity_quaternions(arms))
    {
    }
    template <int Edges>
    explicit ControllerInput(const ControllerModel<Scalar, Arms, Joints, Edges>& model)
        : ControllerInput(model.arms(), model.joints())
    {
    }
    /// The same input with other compile-time sizes (e.g. a Dynamic input into a fixed-size one;
    /// the run-time sizes must agree). Allocates for dynamic sizes: not for the tick.
    template <int OtherArms, int OtherJoints,
              std::enable_if_t<OtherArms != Arms || OtherJoints != Joints, int> = 0>
    explicit ControllerInput(const ControllerInput<Scalar, OtherArms, OtherJoints>& other)
        : inertia(other.inertia),
          bias(other.bias),
          jacobian(other.jacobian),
          jacobian_rate_qdot(other.jacobian_rate_qdot),
          positions(other.positions),
          velocities(other.velocities),
          object(other.object),
          object_acceleration(other.object_acceleration),
          desired_pose(other.desired_pose),
          desired_twist(other.desired_twist),
          desired_acceleration(other.desired_acceleration),
          posture(other.posture),
          object_stale(other.object_stale),
          contact_poses_filled(other.contact_poses_filled),
          contact_positions(other.contact_positions),
          contact_orientations(other.contact_orientations)
    {
    }

    Eigen::Matrix<Scalar, Joints, Joints> inertia;                 ///< M(q), Q x Q, SPD
    JointVector bias;                                              ///< h(q, qdot): Coriolis, centrifugal, gravity
    Eigen::Matrix<Scalar, times_six(Arms), Joints> jacobian;       ///< J, 6K x Q, contact points' twists [v; w] in {w}
    Eigen::Matrix<Scalar, times_six(Arms), 1> jacobian_rate_qdot;  ///< Jdot qdot, 6K
    JointVector positions;                                         ///< q (for the posture term)
    JointVector velocities;                                        ///< qdot
    RigidBodyState<Scalar> object{};                               ///< measured pose and twist of the object's centre, {w}
    /// Measured (on a robot: filtered) acceleration [a; alpha] of the object's centre, {w}, for the
    /// external-wrench estimate L(7).
    Vector6<Scalar> object_acceleration = Vector6<Scalar>::Zero();
    Pose<Scalar> desired_pose{};                                   ///< x_d
    Vector6<Scalar> desired_twist = Vector6<Scalar>::Zero();       ///< xdot_d
    Vector6<Scalar> desired_acceleration = Vector6<Scalar>::Zero();  ///< xdd_d
    JointVector posture;                                           ///< q_n, the posture the self-motion is pulled to

    // ---- optional: faults (docs/control.md, "Faults: dropout, safe hold, slip, torque limits") --
    /// The caller's flag that `object` and `object_acceleration` are an old measurement (e.g. the
    /// motion capture repeated its last frame): the tick predicts the object's state instead, as
    /// for a non-finite measurement.
    bool object_stale = false;
    /// Whether contact_positions and contact_orientations hold this tick's contact frames (from the
    /// arms' forward kinematics): they then predict the object's pose during a dropout and measure
    /// each contact's slip. false: ignored.
    bool contact_poses_filled = false;
    /// Column i: contact frame i's origin in {w} (m), the frame ContactPoint::frame describes in
    /// the object.
    Eigen::Matrix<Scalar, 3, Arms> contact_positions;
    /// Column i: contact frame i's orientation in {w}, a unit quaternion in Eigen's coeffs() order
    /// (x, y, z, w).
    Eigen::Matrix<Scalar, 4, Arms> contact_orientations;

private:
    static Eigen::Matrix<Scalar, 4, Arms> identity_quaternions(Index arms)
    {
        Eigen::Matrix<Scalar, 4, Arms> identity = Eigen::Matrix<Scalar, 4, Arms>::Zero(4, arms);
        identity.row(3).setOnes();
        return identity;
    }
};

}  // namespace coopdyn
