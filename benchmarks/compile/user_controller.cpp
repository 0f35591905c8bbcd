// A user's controller file, as docs/adapters.md ("MuJoCo") and examples/control_quick_start.cpp
// lead one to write it for their own arms: the MuJoCo adapter, the inverse kinematics for the start
// posture (place_hands), the controller built from parameters and the control loop around mj_step.
// scripts/compile-cost compiles it (with -c, no link) next to the Eigen baseline
// (docs/performance.md, "Compile time and CI"). It also runs, on the dual-arm box:
//
//     g++ -std=c++17 -O2 -Iinclude -isystem /usr/include/eigen3 -o user_controller
//         benchmarks/compile/user_controller.cpp -lmujoco && ./user_controller
#include <coopdyn/adapters/mujoco.hpp>
#include <coopdyn/control.hpp>

#include <mujoco/mujoco.h>

#include <cmath>
#include <iostream>
#include <string>
#include <vector>

int main(int argc, char** argv)
{
    constexpr int arms_count = 2;
    constexpr int joint_count = 14;
    const char* path = argc > 1 ? argv[1] : "examples/box/dual_arm_box.xml";
    char error[1000] = "";
    const coopdyn::MujocoModelPointer model(mj_loadXML(path, nullptr, error, sizeof error));
    if (!model) {
        std::cerr << path << ": " << error << '\n';
        return 1;
    }
    const coopdyn::MujocoDataPointer data(mj_makeData(model.get()));
    std::vector<std::string> joints;
    for (const char* side : {"left", "right"}) {
        for (int j = 1; j <= 7; ++j) {
            joints.push_back(std::string(side) + "_joint" + std::to_string(j));
        }
    }
    const coopdyn::MujocoArms<arms_count, joint_count> arms(model.get(), joints, {"left_palm", "right_palm"});

    // The start posture: the palms on the box's faces y = +/- 0.15 m, each palm's z (the contact
    // normal) into the box, found by the inverse kinematics from a pre-grasp posture (the keyframe's
    // arms bent by 0.1 rad).
    const int box = mj_name2id(model.get(), mjOBJ_BODY, "box");
    mj_resetDataKeyframe(model.get(), data.get(), mj_name2id(model.get(), mjOBJ_KEY, "hold"));
    for (int j = 0; j < joint_count; ++j) {
        data->qpos[arms.qpos_address(j)] += 0.1;
    }
    mj_forward(model.get(), data.get());
    const Eigen::Vector3d centre = coopdyn::mujoco_object_pose(model.get(), data.get(), box).position;
    Eigen::Matrix3d left_frame, right_frame;  // columns: x, y, z (the inward normal)
    left_frame << -1, 0, 0, 0, 0, -1, 0, -1, 0;
    right_frame << -1, 0, 0, 0, 0, 1, 0, 1, 0;
    const std::vector<coopdyn::Pose<double>> targets{
        {centre + Eigen::Vector3d(0, 0.15, 0), Eigen::Quaterniond(left_frame)},
        {centre - Eigen::Vector3d(0, 0.15, 0), Eigen::Quaterniond(right_frame)}};
    const coopdyn::InverseKinematicsResult ik = arms.place_hands(model.get(), data.get(), targets);
    std::cout << "inverse kinematics: " << coopdyn::numerics::to_string(ik.status) << ", residual " << ik.residual
              << " after " << ik.iterations << " steps\n";
    mj_forward(model.get(), data.get());

    // The controller, built once from parameters: the grasp as the adapter measures it.
    coopdyn::ContactFriction<double> friction;
    friction.friction_coefficient = 0.2;  // MuJoCo's is 0.5: a margin
    friction.torsional_coefficient = 0.002;
    friction.patch_half_length_x = friction.patch_half_length_y = 0.04;  // 8 x 8 cm palms
    friction.minimum_normal_force = 30.0;
    coopdyn::ControllerParameters<double> parameters;
    parameters.joints = joint_count;
    parameters.contacts = arms.contact_points(model.get(), data.get(), "box", friction);
    parameters.stiffness.diagonal() << 100, 100, 100, 30, 30, 30;
    parameters.damping.diagonal() << 60, 60, 60, 4, 4, 4;
    parameters.posture_stiffness = Eigen::VectorXd::Constant(joint_count, 20.0);
    parameters.posture_damping = Eigen::VectorXd::Constant(joint_count, 4.0);
    parameters.torque_limits = Eigen::VectorXd::Constant(joint_count, 200.0);
    const coopdyn::ControllerModel<double, arms_count, joint_count> controller(parameters);
    coopdyn::ControllerData<double, arms_count, joint_count> controller_data(controller);
    coopdyn::ControllerInput<double, arms_count, joint_count> input(controller);
    arms.read_positions(data.get(), input.posture);
    input.desired_pose = coopdyn::mujoco_object_pose(model.get(), data.get(), box);
    input.desired_pose.position.z() += 0.07;  // the impedance sags by m g / K_d: 6.9 N at 100 N/m

    // The loop: one controller tick per MuJoCo step, the step split around it. The object's
    // acceleration: its free joint's qacc in the last step (linear in {w}, angular in its body
    // frame), low-passed at 20 Hz as on a robot.
    const int box_dof = model->jnt_dofadr[model->body_jntadr[box]];
    const double step = model->opt.timestep;
    const double gain = 1.0 - std::exp(-2.0 * 3.141592653589793 * 20.0 * step);
    coopdyn::Vector6<double> acceleration = coopdyn::Vector6<double>::Zero();
    int not_ok_ticks = 0;
    for (int tick = 0; tick < 2000; ++tick) {
        mj_step1(model.get(), data.get());
        arms.read(model.get(), data.get(), input);
        input.object = coopdyn::mujoco_object_state(model.get(), data.get(), box);
        input.object_acceleration = acceleration;
        const auto& tau = coopdyn::controller_tick(controller, controller_data, input);
        not_ok_ticks += controller_data.status != coopdyn::ControlStatus::ok ? 1 : 0;
        for (int j = 0; j < joint_count; ++j) {
            data->qfrc_applied[arms.dof_address(j)] = tau(j);
        }
        mj_step2(model.get(), data.get());
        const mjtNum* qacc = data->qacc + box_dof;
        coopdyn::Vector6<double> measured;
        measured << qacc[0], qacc[1], qacc[2], input.object.pose.orientation * Eigen::Vector3d(qacc[3], qacc[4], qacc[5]);
        acceleration += gain * (measured - acceleration);
    }
    const coopdyn::Pose<double> object = coopdyn::mujoco_object_pose(model.get(), data.get(), box);
    std::cout << "after " << 2000 * step << " s: " << not_ok_ticks << " ticks not ok, box at "
              << object.position.transpose() << " (desired " << input.desired_pose.position.transpose() << "), "
              << "normal forces " << controller_data.contact_frame_wrenches.row(2) << " N\n";
}
