// The dual-arm box's model as plain data, shared by both plants, the controller's experiment and
// the scenario files (docs/dual-arm-box.md): its sizes (two 7-joint arms, two palms, the 1 kHz
// period), what the controller gets of the arms each tick (ArmTerms), the palms' true friction and
// the grasp the experiments start from. Depends on Eigen and coopdyn only (no MuJoCo): with
// lwr4.hpp, lwr4_dynamics.hpp, box_scenario.hpp, box_scenario_loader.hpp and rigid_plant.hpp it is
// the part of the example that builds without MuJoCo (examples/box/CMakeLists.txt).
#pragma once

#include <coopdyn/spatial/pose.hpp>

#include <Eigen/Core>

#include <array>

namespace box_example {

constexpr int arm_joints = 7;
constexpr int joints = 2 * arm_joints;  ///< Q: left arm (qpos/qvel 0-6), right arm (7-13)
constexpr int palms = 2;                ///< K: 0 = left palm, 1 = right palm
/// The controller's period (s): one plant step per 1 kHz tick, so the MJCF's timestep.
constexpr double controller_period = 0.001;

using JointVector = Eigen::Matrix<double, joints, 1>;
using JointMatrix = Eigen::Matrix<double, joints, joints>;
using StackVector = Eigen::Matrix<double, 6 * palms, 1>;
using StackJacobian = Eigen::Matrix<double, 6 * palms, joints>;

/// What the controller gets of the arms at one state (q, qdot).
struct ArmTerms {
    JointMatrix inertia = JointMatrix::Identity();  ///< M(q)
    JointVector bias = JointVector::Zero();         ///< h(q, qdot) = C qdot + g
    StackJacobian jacobian = StackJacobian::Zero(); ///< J: palm i's contact-point twist [v; w] in {w}
    StackVector jacobian_rate_qdot = StackVector::Zero();  ///< Jdot qdot
    std::array<Eigen::Vector3d, palms> palm_position{};    ///< contact points in {w}
    std::array<Eigen::Matrix3d, palms> palm_rotation{};    ///< palm frames (z: outward normal, into the box)
};

using Vector6d = Eigen::Matrix<double, 6, 1>;

/// The palms' true friction in the plant (MuJoCo's pair friction, condim 4).
struct PlantFriction {
    double sliding = 0.5;      ///< Coulomb coefficient, both tangential directions
    double torsional = 0.005;  ///< MuJoCo's torsional coefficient (m): |t_z| <= torsional f_z
};

/// The box's pose and where the palms touch it when the experiment starts (the keyframe "hold").
struct Grasp {
    coopdyn::Pose<double> box{};
    std::array<Eigen::Vector3d, palms> palm_position{};
    std::array<Eigen::Matrix3d, palms> palm_rotation{};
    JointVector q = JointVector::Zero();
};

}  // namespace box_example
