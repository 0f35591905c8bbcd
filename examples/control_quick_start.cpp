// Two palms squeeze a 2 kg box just hard enough for friction to hold it (the controller of
// Lin et al., docs/control.md). Each "arm" is a free 6-DOF hand at its palm (J = I), so the
// example needs no robot model.
#include <coopdyn/control.hpp>
#include <iostream>

int main()
{
    using namespace coopdyn;
    ControllerParameters<double> parameters;
    parameters.joints = 12;
    ContactPoint<double> left, right;  // palms on the faces x = -0.15 m and x = +0.15 m
    Eigen::Matrix3d left_frame, right_frame;  // columns: contact x (up), y, z (the inward normal)
    left_frame << 0, 0, 1, 0, -1, 0, 1, 0, 0;
    right_frame << 0, 0, -1, 0, 1, 0, 1, 0, 0;
    left.frame = {Eigen::Vector3d(-0.15, 0, 0), Eigen::Quaterniond(left_frame)};
    right.frame = {Eigen::Vector3d(0.15, 0, 0), Eigen::Quaterniond(right_frame)};
    left.friction.friction_coefficient = right.friction.friction_coefficient = 0.5;
    parameters.contacts = {left, right};
    parameters.stiffness = 1000.0 * Matrix6<double>::Identity();
    parameters.damping = 100.0 * Matrix6<double>::Identity();
    parameters.posture_stiffness = parameters.posture_damping = Eigen::VectorXd::Zero(12);
    const ControllerModel<double, 2, 12> model(parameters);
    ControllerData<double, 2, 12> data(model);
    ControllerInput<double, 2, 12> input(model);

    // Every tick: M, h, J, Jdot qdot, q, qdot from your dynamics library, the box's measured pose,
    // twist and acceleration, and the desired motion (here: hold it at the origin).
    input.inertia = 2.0 * Eigen::Matrix<double, 12, 12>::Identity();  // 2 kg hands
    input.bias << 0, 0, 2 * 9.81, 0, 0, 0, 0, 0, 2 * 9.81, 0, 0, 0;   // their weight
    input.jacobian.setIdentity();
    input.object.pose.position << 0, 0, -2 * 9.81 / 1000;  // the box sags by m g / K: F_x = its weight
    const auto& tau = controller_tick(model, data, input);
    std::cout << "status: " << to_string(data.status) << '\n'
              << "normal force per palm: " << data.contact_frame_wrenches.row(2) << " N\n"
              << "torques: " << tau.transpose() << '\n';
}
