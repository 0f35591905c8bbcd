// The box experiments on any scene (docs/dual-arm-box.md, "Scenes"): a scenario that names a scene
// (examples/scenes, docs/scenes.md) runs the same experiment loop as the LWR 4 pair
// (box_experiment.hpp, run_experiment_on) at dynamic sizes, K palms and Q joints read from the
// scene, on the scene's MuJoCo plant (MujocoScenePlant) or its rigid-grasp plant
// (RigidScenePlant, the library's coopdyn::JointSpaceGrasp). SceneBoxPlant gives either the box
// plants' interface; make_scene_setup the controller's parameters from the scene's contact points
// and the scenario's settings.
//
// Each run gets a world of its own (SceneWorld): the MuJoCo plant writes the scenario's mass and
// friction into its model.
//
// This header belongs to the examples (it depends on MuJoCo), not to the library.
#pragma once

#include "box_experiment.hpp"

#include "../scenes/scene_hold.hpp"
#include "../scenes/scene_rigid.hpp"

#include <limits>
#include <string>
#include <vector>

namespace box_example {

/// What the experiment loop reads of the arms each tick (box_model.hpp's ArmTerms at run-time
/// sizes): M, h, J, Jdot qdot are views of the scene plant's input (read by the adapter once a tick,
/// not copied again), the palms' frames its own.
struct SceneArmTerms {
    using Input = coopdyn::ControllerInput<double>;
    explicit SceneArmTerms(const Input& input, std::size_t palm_count)
        : inertia(input.inertia), bias(input.bias), jacobian(input.jacobian),
          jacobian_rate_qdot(input.jacobian_rate_qdot), palm_position(palm_count, Eigen::Vector3d::Zero()),
          palm_rotation(palm_count, Eigen::Matrix3d::Identity())
    {
    }
    const decltype(Input::inertia)& inertia;
    const decltype(Input::bias)& bias;
    const decltype(Input::jacobian)& jacobian;
    const decltype(Input::jacobian_rate_qdot)& jacobian_rate_qdot;
    std::vector<Eigen::Vector3d> palm_position;  ///< contact points in {w}
    std::vector<Eigen::Matrix3d> palm_rotation;  ///< contact frames (z: into the object)
};

/// A scene plant (scenes::MujocoScenePlant or scenes::RigidScenePlant) behind the interface
/// run_experiment_on reads (the box plants'). Allocates nothing per tick. Not copyable: its terms
/// view its own input.
template <typename ScenePlant> class SceneBoxPlant {
public:
    SceneBoxPlant(const scenes::SceneWorld& world, ScenePlant& plant)
        : plant_(plant), input_(world.arms().arms(), world.arms().joints()),
          terms_(input_, static_cast<std::size_t>(world.arms().arms()))
    {
    }
    SceneBoxPlant(const SceneBoxPlant&) = delete;
    SceneBoxPlant& operator=(const SceneBoxPlant&) = delete;

    void begin_tick()
    {
        plant_.begin_tick(input_);
        for (std::size_t i = 0; i < terms_.palm_position.size(); ++i) {
            const coopdyn::Pose<double> palm = plant_.contact_pose(static_cast<Eigen::Index>(i));
            terms_.palm_position[i] = palm.position;
            terms_.palm_rotation[i] = palm.orientation.toRotationMatrix();
        }
    }
    const SceneArmTerms& arm_terms() const noexcept { return terms_; }
    const Eigen::VectorXd& joint_positions() const noexcept { return input_.positions; }
    const Eigen::VectorXd& joint_velocities() const noexcept { return input_.velocities; }
    const Eigen::Vector3d& box_position() const noexcept { return input_.object.pose.position; }
    const Eigen::Quaterniond& box_orientation() const noexcept { return input_.object.pose.orientation; }
    const Vector6d& box_twist() const noexcept { return input_.object.twist; }
    /// The plant's last step's (after end_tick: this tick's).
    const Vector6d& box_acceleration() const noexcept { return plant_.object_acceleration(); }
    template <typename Torque> void end_tick(const Torque& tau, const Vector6d& box_wrench)
    {
        plant_.end_tick(tau, box_wrench);
    }
    const Vector6d& measured_contact_wrench(int palm) const noexcept
    {
        return plant_.measured_contact_wrench(static_cast<Eigen::Index>(palm));
    }
    double box_mass() const noexcept { return plant_.object_mass(); }
    void set_box_mass(double mass) { plant_.set_object_mass(mass); }

private:
    ScenePlant& plant_;
    coopdyn::ControllerInput<double> input_;
    SceneArmTerms terms_;
};

/// A palm's name in the log: its contact site's name less a trailing "_palm_contact" or "_palm"
/// ("ur5e_palm_contact": "ur5e"; "left_palm": "left"), else "palm<i>".
inline std::vector<std::string> scene_palm_names(const scenes::Scene& scene)
{
    std::vector<std::string> names;
    for (std::size_t i = 0; i < scene.contact_sites.size(); ++i) {
        std::string name = scene.contact_sites[i];
        for (const std::string suffix : {"_palm_contact", "_palm"}) {
            if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
                name.erase(name.size() - suffix.size());
                break;
            }
        }
        for (const std::string& earlier : names) {
            if (earlier == name) {
                name.clear();
            }
        }
        names.push_back(name.empty() || name == scene.contact_sites[i] ? "palm" + std::to_string(i + 1) : name);
    }
    return names;
}

/// The run's setup on a scene's world at its start (world.start() called): the controller's
/// contact points where the palms touch the object, the scenario's settings, q_n, the hold pose
/// (the object's centre), the scene's torque limits (none: infinite) and the palms' names.
inline ExperimentSetup make_scene_setup(const scenes::SceneWorld& world, const BoxScenario& scenario)
{
    const Eigen::Index K = world.arms().arms();
    const Eigen::Index Q = world.arms().joints();
    if (K > max_scene_palms || Q > max_scene_joints) {
        throw scenes::SceneError(world.scene().source + ": the box experiments log at most " +
                                 std::to_string(max_scene_palms) + " palms and " + std::to_string(max_scene_joints) +
                                 " joints (box_experiment.hpp, max_scene_palms, max_scene_joints)");
    }
    ExperimentSetup setup;
    setup.parameters.joints = Q;
    setup.parameters.joint_names = world.scene().joint_names;
    setup.parameters.check_contact_normals = world.scene().check_contact_normals;
    // The contacts' friction is the scenario's (apply_controller_settings), not the adapter's.
    setup.parameters.contacts = world.arms().contact_points(world.model(), world.data(), world.scene().object_body,
                                                            coopdyn::ContactFriction<double>{});
    apply_controller_settings(scenario.controller, setup.parameters);
    setup.posture = world.posture();
    setup.hold = coopdyn::mujoco_object_pose(world.model(), world.data(), world.object_body());
    setup.torque_limit = world.scene().torque_limits
                             ? *world.scene().torque_limits
                             : Eigen::VectorXd::Constant(Q, std::numeric_limits<double>::infinity());
    setup.palm_names = scene_palm_names(world.scene());
    return setup;
}

/// The scenario's true friction on every palm-object <pair> of the world's model (MuJoCo's
/// sliding, sliding, torsional coefficients), as MujocoPlant does for the LWR 4 pair.
inline void set_palm_friction(scenes::SceneWorld& world, const PlantFriction& friction)
{
    mjModel* model = world.model();
    for (Eigen::Index i = 0; i < world.arms().arms(); ++i) {
        for (int pair = 0; pair < model->npair; ++pair) {
            const int first = model->pair_geom1[pair];
            const int second = model->pair_geom2[pair];
            const int palm = world.palm_geom(i);
            const int object = world.object_geom(i);
            if ((first == palm && second == object) || (first == object && second == palm)) {
                mjtNum* coefficients = model->pair_friction + 5 * pair;
                coefficients[0] = coefficients[1] = friction.sliding;
                coefficients[2] = friction.torsional;
            }
        }
    }
}

using SceneRun = ExperimentRunOf<Eigen::Dynamic, Eigen::Dynamic>;

/// Whether a scene's experiments run the controller at fixed sizes (box_experiment.hpp,
/// fixed_scene_palms and fixed_scene_joints; box_runs.cpp's run_scene_world dispatches).
inline bool fixed_size_scene(const scenes::Scene& scene) noexcept
{
    return scene.arms() == fixed_scene_palms && scene.joints() == fixed_scene_joints;
}

/// Runs `scenario` on its scene (scenario.scene) on one plant, "mujoco" or "rigid" (integrated by
/// `integrator`), from the scene's start (a world of its own: the IK or the given posture), the
/// controller at sizes ControllerK, ControllerQ (Dynamic by default; the scene's own otherwise).
template <int ControllerK = Eigen::Dynamic, int ControllerQ = Eigen::Dynamic>
SceneRun run_scene_experiment(const scenes::Scene& scene, const BoxScenario& scenario, bool rigid,
                              unsigned long long seed = 1, const std::function<void(double)>& progress = {},
                              coopdyn::Integrator integrator = coopdyn::Integrator::semi_implicit_euler)
{
    scenes::SceneWorld world(scene);
    world.start();
    const ExperimentSetup setup = make_scene_setup(world, scenario);
    if (rigid) {
        scenes::RigidScenePlant plant(world, integrator);
        plant.set_object_mass(scenario.box_mass);
        SceneBoxPlant<scenes::RigidScenePlant> box_plant(world, plant);
        return run_experiment_on<Eigen::Dynamic, Eigen::Dynamic, SceneBoxPlant<scenes::RigidScenePlant>, NoFaults,
                                 ControllerK, ControllerQ>(box_plant, scenario, setup, seed, progress);
    }
    set_palm_friction(world, scenario.plant_friction);
    scenes::MujocoScenePlant plant(world);
    plant.set_object_mass(scenario.box_mass);
    SceneBoxPlant<scenes::MujocoScenePlant> box_plant(world, plant);
    return run_experiment_on<Eigen::Dynamic, Eigen::Dynamic, SceneBoxPlant<scenes::MujocoScenePlant>, NoFaults, ControllerK,
                             ControllerQ>(box_plant, scenario, setup, seed, progress);
}

}  // namespace box_example
