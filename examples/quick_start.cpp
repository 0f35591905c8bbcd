#include <coopdyn/coopdyn.hpp>
#include <iostream>

int main()
{
    using namespace coopdyn;
    // The paper's beam (docs/analysis.md): 1.75 kg, held by two impedance-controlled arms.
    const auto arm = ImpedanceEndEffector<double>()
                         .with_mass(10.0)
                         .with_rotational_inertia(0.5 * Eigen::Matrix3d::Identity())
                         .with_translational_damping(180.0)
                         .with_rotational_damping(10.0)
                         .with_translational_stiffness(300.0)
                         .with_rotational_stiffness(50.0);
    const RigidObject<double> beam{1.75, Eigen::Vector3d(0.055, 0.0, 0.055).asDiagonal()};
    const ImpedanceModel2 model(beam, {{arm, {Eigen::Vector3d(0, -0.4, 0)}}, {arm, {Eigen::Vector3d(0, 0.4, 0)}}});
    Data data(model);

    RigidBodyState<double> state;  // beam at rest at the origin
    Setpoints<double, 2> setpoints;
    Disturbances<double, 2> disturbances;
    for (Index i = 0; i < 2; ++i) {
        setpoints.set_pose(i, {model.grasp_offsets_body().col(i)});   // hold the grasp pose
        setpoints.wrench(i) << 0, 0, -0.5 * 1.75 * 9.81, 0, 0, 0;     // each arm carries half the weight
    }
    disturbances.object << 10, 0, 0, 0, 0, 0;                          // a 10 N push along x
    interaction_dynamics(model, data, state, setpoints, disturbances);
    std::cout << "object acceleration: " << data.object_acceleration().transpose() << '\n'
              << "wrench on arm 0:     " << data.end_effector_wrench(0).transpose() << '\n';
}
