// The scene layer (examples/scenes, docs/scenes.md): each shipped scene loads, starts (its IK to
// 1e-9, each palm flat on its face of the object), its generated robot MJCF has the URDF's
// joint-space inertia (against KDL on the URDF where kdl_parser is found, and against MuJoCo's own
// URDF compilation), and a short hold in MuJoCo keeps the object with no slip and every QP tick
// feasible. The scene reader refuses malformed files naming the field.
#include "../box/scene_box.hpp"
#ifdef COOPDYN_HAVE_BOX_RUNS
#include "../box/box_runs.hpp"  // run_scene_world, compiled in box_example_runs
#endif
#include "scene_hold.hpp"
#include "scene_rigid.hpp"

#ifdef COOPDYN_SCENES_HAVE_KDL
#include <coopdyn/adapters/kdl_urdf.hpp>
#endif

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace {

const std::string scene_dir = COOPDYN_SCENES_DIR;
const std::string robot_dir = COOPDYN_ROBOTS_DIR;

class ShippedScene : public ::testing::TestWithParam<const char*> {
protected:
    std::string path() const { return scene_dir + "/" + GetParam() + ".json"; }
};

// The palm's contact frame lies on a face of the object's box geom (its origin in the face's plane,
// inside the face) and its z axis is that face's inward normal.
void expect_on_face(const scenes::SceneWorld& world, Eigen::Index i)
{
    const mjModel* model = world.model();
    const mjData* data = world.data();
    const int geom = world.object_geom(i);
    ASSERT_EQ(model->geom_type[geom], mjGEOM_BOX);
    const Eigen::Map<const Eigen::Vector3d> centre(data->geom_xpos + 3 * geom);
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> rotation(data->geom_xmat + 9 * geom);
    const Eigen::Map<const Eigen::Vector3d> size(model->geom_size + 3 * geom);
    const Eigen::Vector3d local = rotation.transpose() * (world.arms().contact_position(data, i) - centre);
    const Eigen::Vector3d normal = rotation.transpose() * world.arms().contact_rotation(data, i).col(2);
    Eigen::Index axis = 0;
    (local.cwiseAbs().cwiseQuotient(size)).maxCoeff(&axis);
    EXPECT_NEAR(std::abs(local(axis)), size(axis), 1e-9) << "contact " << i;
    for (Eigen::Index k = 0; k < 3; ++k) {
        if (k != axis) {
            EXPECT_LT(std::abs(local(k)), size(k)) << "contact " << i;
        }
    }
    Eigen::Vector3d inward = Eigen::Vector3d::Zero();
    inward(axis) = local(axis) > 0.0 ? -1.0 : 1.0;
    EXPECT_LT((normal - inward).norm(), 1e-9) << "contact " << i;
}

TEST_P(ShippedScene, StartsWithEachPalmOnTheObject)
{
    scenes::SceneWorld world(scenes::read_scene(path()));
    const scenes::StartReport start = world.start();
    if (start.inverse_kinematics) {
        EXPECT_TRUE(start.ik.converged());
        EXPECT_LT(start.ik.residual, 1e-9);
        EXPECT_LT(start.contact_position_error, 1e-9);
        EXPECT_LT(start.contact_orientation_error, 1e-9);
        std::printf("%s: IK residual %.2g after %d steps\n", GetParam(), start.ik.residual, start.ik.iterations);
    }
    for (Eigen::Index i = 0; i < world.arms().arms(); ++i) {
        expect_on_face(world, i);
    }
    // The controller's model builds from the start (contact points from the adapter).
    EXPECT_NO_THROW(coopdyn::ControllerModel<double>(world.controller_parameters({})));
}

// A short hold (1 s after 0.2 s of settling; scripts/scene_hold runs longer ones): no drop, slip
// well below 1 mm, every tick's QP feasible, the palms' normal forces at the QP's (and at least f_min).
TEST_P(ShippedScene, HoldsTheObjectInMujoco)
{
    scenes::SceneWorld world(scenes::read_scene(path()));
    world.start();
    scenes::HoldSettings settings;
    settings.seconds = 1.0;
    const scenes::HoldResult hold = scenes::run_hold(world, settings);
    EXPECT_FALSE(hold.dropped);
    EXPECT_LT(hold.max_slip, 1e-3);
    EXPECT_EQ(hold.ticks, 1000);
    EXPECT_EQ(hold.not_ok_ticks, 0);
    EXPECT_EQ(hold.fallback_ticks, 0);
    std::printf("%s: slip %.3g mm, real-time factor %.1f\n", GetParam(), 1e3 * hold.max_slip, hold.real_time_factor);
    for (std::size_t i = 0; i < hold.palms.size(); ++i) {
        const scenes::PalmHold& palm = hold.palms[i];
        EXPECT_GE(palm.min_contact_points, 1) << "palm " << i;
        EXPECT_GT(palm.final_normal_force, 0.99 * settings.controller.minimum_normal_force) << "palm " << i;
        EXPECT_NEAR(palm.final_normal_force, palm.predicted_normal_force, 0.02 * palm.predicted_normal_force) << "palm " << i;
        std::printf("  palm %zu: normal force %.2f N (QP %.2f N)\n", i, palm.final_normal_force, palm.predicted_normal_force);
    }
}

// The same hold on the rigid-grasp plant (scene_rigid.hpp: the palms welded where they touch, the
// object's true inertia), with its default integrator (semi-implicit Euler): the weld holds (its
// error is the integrator's first-order drift, which the Baumgarte terms pull back, the order test
// below: under 1 um and 1 urad, a thousandth of the 1 mm slip bound and a tenth of the least slip
// MuJoCo's soft contacts show; measured 0.03-0.08 um after 1 s, 0.2-0.4 um while the object
// settles, below), every tick ok, the
// welds' normal forces at the QP's; and the object settles where MuJoCo's does (the same
// controller; the object's largest excursion over 1 s, about 65-74 mm of sag under its unknown
// weight, agrees to 0.02, 0.06 and 0.11 mm on the three scenes: MuJoCo's soft contacts against the
// welds).
TEST_P(ShippedScene, HoldsTheObjectOnTheRigidPlant)
{
    scenes::SceneWorld world(scenes::read_scene(path()));
    world.start();
    scenes::HoldSettings settings;
    settings.seconds = 1.0;
    scenes::RigidScenePlant plant(world);
    const scenes::HoldResult hold = scenes::run_hold_on(world, plant, settings);
    const std::array<double, 2> weld = plant.weld_error();
    EXPECT_FALSE(hold.dropped);
    EXPECT_EQ(hold.ticks, 1000);
    EXPECT_EQ(hold.not_ok_ticks, 0);
    EXPECT_LT(weld[0], 1e-6);
    EXPECT_LT(weld[1], 1e-6);
    for (std::size_t i = 0; i < hold.palms.size(); ++i) {
        const scenes::PalmHold& palm = hold.palms[i];
        EXPECT_NEAR(palm.final_normal_force, palm.predicted_normal_force, 1e-3 * palm.predicted_normal_force) << "palm " << i;
    }
    world.start();
    const scenes::HoldResult mujoco = scenes::run_hold(world, settings);
    std::printf("%s: rigid plant real-time factor %.1f, weld error %.2g m, %.2g rad; object moved %.2f mm (MuJoCo: %.2f mm)\n",
                GetParam(), hold.real_time_factor, weld[0], weld[1], 1e3 * hold.max_position_error,
                1e3 * mujoco.max_position_error);
    EXPECT_NEAR(hold.max_position_error, mujoco.max_position_error, 3e-4);
}

// The rigid plant's two integrators (scene_rigid.hpp, coopdyn::Integrator) on the same 0.5 s hold, at
// the model's 1 ms and at 0.5 ms (the controller ticking at the plant's period): RK4 keeps the weld
// to rounding (1e-12), and semi-implicit Euler converges to RK4 at first order, its difference in
// the object's largest excursion halving with the step (ratio 1.5-2.5; RK4's own error, O(dt^4), is
// far below it), and so does its weld error, at least. A wrong rate or a stale evaluation in either
// would break the ratios.
TEST_P(ShippedScene, RigidPlantIntegratorsConvergeToEachOther)
{
    std::array<double, 2> difference{};
    std::array<double, 2> euler_weld{};
    for (std::size_t halvings = 0; halvings < 2; ++halvings) {
        std::array<scenes::HoldResult, 2> holds;
        for (const coopdyn::Integrator integrator : {coopdyn::Integrator::semi_implicit_euler,
                                                         coopdyn::Integrator::runge_kutta_4}) {
            scenes::SceneWorld world(scenes::read_scene(path()));
            world.model()->opt.timestep = halvings == 0 ? 1e-3 : 5e-4;
            world.start();
            scenes::HoldSettings settings;
            settings.seconds = 0.5;
            scenes::RigidScenePlant plant(world, integrator);
            const auto index = integrator == coopdyn::Integrator::runge_kutta_4 ? 1U : 0U;
            holds[index] = scenes::run_hold_on(world, plant, settings);
            EXPECT_EQ(holds[index].not_ok_ticks, 0);
            const std::array<double, 2> weld = plant.weld_error();
            if (integrator == coopdyn::Integrator::runge_kutta_4) {
                EXPECT_LT(weld[0], 1e-12);
                EXPECT_LT(weld[1], 1e-12);
            } else {
                euler_weld[halvings] = weld[0];
            }
        }
        difference[halvings] = std::abs(holds[0].max_position_error - holds[1].max_position_error) +
                               std::abs(holds[0].max_orientation_error - holds[1].max_orientation_error) * 0.1;
    }
    std::printf("%s: Euler against RK4, the object's excursion: %.3g at 1 ms, %.3g at 0.5 ms (ratio %.2f); Euler's weld "
                "error %.3g, %.3g m (ratio %.2f)\n", GetParam(), difference[0], difference[1], difference[0] / difference[1],
                euler_weld[0], euler_weld[1], euler_weld[0] / euler_weld[1]);
    EXPECT_GT(difference[0] / difference[1], 1.5);
    EXPECT_LT(difference[0] / difference[1], 2.5);
    EXPECT_GT(euler_weld[0] / euler_weld[1], 1.5);
}

// The rigid plant's own recursion (chain_dynamics.hpp, built from the model's constants) against
// what MuJoCo computes for the same arms (its stages mj_kinematics, mj_comPos, mj_crb, mj_comVel,
// mj_rne and the library's adapter's read), at random states of every shipped scene: joints up to
// 0.8 rad from the start posture, velocities up to 2 rad/s. M, h, J, Jdot qdot and the contact
// frames to rounding (1e-10 of each quantity's scale).
TEST_P(ShippedScene, OwnRecursionGivesMujocosArmTerms)
{
    scenes::SceneWorld world(scenes::read_scene(path()));
    world.start();
    const mjModel* model = world.model();
    mjData* data = world.data();
    const scenes::Arms& arms = world.arms();
    std::string why;
    const std::vector<scenes::ChainDynamics> chains = scenes::arm_chains(world, why);
    ASSERT_EQ(chains.size(), static_cast<std::size_t>(arms.arms())) << why;
    const Eigen::VectorXd start = world.start_positions();
    std::mt19937 generator(17);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    coopdyn::ControllerInput<double> mujoco(arms.arms(), arms.joints());
    coopdyn::ControllerInput<double> own(arms.arms(), arms.joints());
    std::array<double, 5> worst{};  // M, h, J, Jdot qdot, contact frames
    for (int sample = 0; sample < 5; ++sample) {
        Eigen::VectorXd q(arms.joints()), qdot(arms.joints());
        for (Eigen::Index j = 0; j < arms.joints(); ++j) {
            q(j) = start(j) + 0.8 * uniform(generator);
            qdot(j) = 2.0 * uniform(generator);
        }
        scenes::run_arm_stages(model, data, arms, q, qdot);
        arms.read(model, data, mujoco);
        std::vector<coopdyn::Pose<double>> contacts(chains.size());
        scenes::evaluate_chains(chains, q, qdot, own, contacts);
        for (Eigen::Index i = 0; i < arms.arms(); ++i) {
            const coopdyn::Pose<double>& contact = contacts[static_cast<std::size_t>(i)];
            worst[4] = std::max({worst[4], (contact.position - arms.contact_position(data, i)).norm(),
                                 (contact.orientation.toRotationMatrix() - arms.contact_rotation(data, i)).norm()});
        }
        worst[0] = std::max(worst[0], (own.inertia - mujoco.inertia).norm() / mujoco.inertia.norm());
        worst[1] = std::max(worst[1], (own.bias - mujoco.bias).norm() / mujoco.bias.norm());
        worst[2] = std::max(worst[2], (own.jacobian - mujoco.jacobian).norm() / mujoco.jacobian.norm());
        worst[3] = std::max(worst[3], (own.jacobian_rate_qdot - mujoco.jacobian_rate_qdot).norm() /
                                          mujoco.jacobian_rate_qdot.norm());
    }
    std::printf("%s: own recursion against MuJoCo, relative: M %.2g, h %.2g, J %.2g, Jdot qdot %.2g; contact frames %.2g\n",
                GetParam(), worst[0], worst[1], worst[2], worst[3], worst[4]);
    for (const double error : worst) {
        EXPECT_LT(error, 1e-10);
    }
}

// The rigid plant holds the same with either source of the arms' terms (0.3 s): the object's
// excursion and the welds' normal forces to rounding's growth over 500 ticks.
TEST_P(ShippedScene, RigidPlantHoldsTheSameWithEitherArmTerms)
{
    std::array<scenes::HoldResult, 2> holds;
    for (const scenes::ArmTermsSource source : {scenes::ArmTermsSource::own_recursion, scenes::ArmTermsSource::mujoco}) {
        scenes::SceneWorld world(scenes::read_scene(path()));
        world.start();
        scenes::HoldSettings settings;
        settings.seconds = 0.3;
        scenes::RigidScenePlant plant(world, coopdyn::Integrator::semi_implicit_euler, 50.0, source);
        EXPECT_EQ(plant.own_recursion(), source == scenes::ArmTermsSource::own_recursion) << plant.why_not_own_recursion();
        holds[source == scenes::ArmTermsSource::mujoco ? 1U : 0U] = scenes::run_hold_on(world, plant, settings);
    }
    EXPECT_NEAR(holds[0].max_position_error, holds[1].max_position_error, 1e-9);
    EXPECT_NEAR(holds[0].max_orientation_error, holds[1].max_orientation_error, 1e-9);
    for (std::size_t i = 0; i < holds[0].palms.size(); ++i) {
        EXPECT_NEAR(holds[0].palms[i].final_normal_force, holds[1].palms[i].final_normal_force,
                    1e-7 * holds[1].palms[i].final_normal_force) << "palm " << i;
    }
}

// An arm the own recursion does not model (here one joint made a slide) gets no chain, the reason
// names the joint, and the rigid plant falls back to MuJoCo's stages.
TEST(ChainDynamics, NamesWhatItDoesNotModelAndThePlantFallsBack)
{
    scenes::SceneWorld world(scenes::read_scene(scene_dir + "/ur5e_panda.json"));
    world.start();
    const int joint = world.arms().joint_id(8);
    world.model()->jnt_type[joint] = mjJNT_SLIDE;
    std::string why;
    EXPECT_FALSE(scenes::ChainDynamics::from_mujoco(world.model(), world.arms(), 1, 6, 7, why).has_value());
    EXPECT_NE(why.find(mj_id2name(world.model(), mjOBJ_JOINT, joint)), std::string::npos) << why;
    EXPECT_TRUE(scenes::ChainDynamics::from_mujoco(world.model(), world.arms(), 0, 0, 6, why).has_value());
    const scenes::RigidScenePlant plant(world);
    EXPECT_FALSE(plant.own_recursion());
    EXPECT_NE(plant.why_not_own_recursion().find("arm 1"), std::string::npos) << plant.why_not_own_recursion();
}

INSTANTIATE_TEST_SUITE_P(Scenes, ShippedScene, ::testing::Values("lwr4_pair", "ur5e_panda", "three_arms"));

// One robot of a generated scene: its joints (a block of q) and the URDF it was generated from.
struct Robot {
    const char* urdf;
    const char* root;   // the URDF's root link
    const char* mount;  // the scene body the robot's tree hangs from
    Eigen::Index first_joint;
    Eigen::Index joints;
};

const std::vector<Robot> three_arm_robots{{"ur5e/ur5e.urdf", "ur5e_base", "ur5e_mount", 0, 6},
                                          {"panda/panda.urdf", "panda_link0", "panda_mount", 6, 7},
                                          {"panda/panda.urdf", "panda_link0", "b_panda_mount", 13, 7}};

scenes::SceneWorld three_arm_world()
{
    scenes::SceneWorld world(scenes::read_scene(scene_dir + "/three_arms.json"));
    mj_resetData(world.model(), world.data());
    return world;
}

// The scene's M, h at (q, qdot) through the MuJoCo adapter.
void scene_terms(scenes::SceneWorld& world, const Eigen::VectorXd& q, const Eigen::VectorXd& qdot,
                 Eigen::MatrixXd& inertia, Eigen::VectorXd& bias)
{
    for (Eigen::Index j = 0; j < world.arms().joints(); ++j) {
        world.data()->qpos[world.arms().qpos_address(j)] = q(j);
        world.data()->qvel[world.arms().dof_address(j)] = qdot(j);
    }
    mj_forward(world.model(), world.data());
    inertia.resize(q.size(), q.size());
    bias.resize(q.size());
    world.arms().read_inertia(world.model(), world.data(), inertia);
    world.arms().read_bias(world.data(), bias);
}

// MuJoCo's own compilation of each URDF (mj_loadXML of the .urdf): the same M to MuJoCo's
// re-diagonalisation of the URDF's tensors (about 1e-7 relative; docs/adapters.md, "Tests").
TEST(GeneratedRobots, HaveTheJointSpaceInertiaOfMujocosUrdfCompilation)
{
    scenes::SceneWorld world = three_arm_world();
    std::mt19937 random(7);
    std::uniform_real_distribution<double> uniform(-1.5, 1.5);
    double worst = 0.0;
    for (const Robot& robot : three_arm_robots) {
        char error[1000] = "";
        scenes::ModelPointer urdf(mj_loadXML((robot_dir + "/" + robot.urdf).c_str(), nullptr, error, sizeof error));
        ASSERT_TRUE(urdf) << error;
        scenes::DataPointer urdf_data(mj_makeData(urdf.get()));
        ASSERT_EQ(urdf->nv, robot.joints);
        for (int trial = 0; trial < 5; ++trial) {
            Eigen::VectorXd q = Eigen::VectorXd::NullaryExpr(world.arms().joints(), [&] { return uniform(random); });
            Eigen::MatrixXd inertia;
            Eigen::VectorXd bias;
            scene_terms(world, q, Eigen::VectorXd::Zero(q.size()), inertia, bias);
            for (Eigen::Index j = 0; j < robot.joints; ++j) {
                urdf_data->qpos[j] = q(robot.first_joint + j);
            }
            mj_forward(urdf.get(), urdf_data.get());
            Eigen::MatrixXd reference(robot.joints, robot.joints);
            mj_fullM(urdf.get(), reference.data(), urdf_data->qM);  // symmetric: row or column major alike
            const Eigen::MatrixXd block = inertia.block(robot.first_joint, robot.first_joint, robot.joints, robot.joints);
            worst = std::max(worst, (block - reference).cwiseAbs().maxCoeff());
        }
    }
    std::printf("M, generated MJCF against MuJoCo's URDF compilation: %.3g\n", worst);
    EXPECT_LT(worst, 1e-7);  // measured 2.8e-8 (the Panda)
}

#ifdef COOPDYN_SCENES_HAVE_KDL
// KDL on the URDF files themselves (the KDL adapter, the robots mounted where the scene mounts
// them): the generated MJCF keeps the URDF's inertials to rounding, M and h (gravity included),
// and the palm site is the URDF's palm frame moved 0.02 m (the plate) along its normal.
TEST(GeneratedRobots, HaveTheUrdfsDynamicsByKdl)
{
    scenes::SceneWorld world = three_arm_world();
    std::vector<KDL::Chain> chains;
    std::vector<KDL::Frame> bases;
    for (const Robot& robot : three_arm_robots) {
        const KDL::Tree tree = coopdyn::kdl_tree_from_urdf(robot_dir + "/" + robot.urdf);
        KDL::Chain chain;
        const std::string palm = std::string(robot.root) == "ur5e_base" ? "ur5e_palm" : "panda_palm";
        ASSERT_TRUE(tree.getChain(robot.root, palm, chain));
        chains.push_back(chain);
        const int mount = mj_name2id(world.model(), mjOBJ_BODY, robot.mount);
        ASSERT_GE(mount, 0);
        const mjtNum* p = world.model()->body_pos + 3 * mount;
        const mjtNum* w = world.model()->body_quat + 4 * mount;
        bases.emplace_back(KDL::Rotation::Quaternion(w[1], w[2], w[3], w[0]), KDL::Vector(p[0], p[1], p[2]));
    }
    coopdyn::KdlArms<> kdl(chains, bases);
    ASSERT_EQ(kdl.joints(), world.arms().joints());
    coopdyn::ControllerInput<double> input(kdl.arms(), kdl.joints());
    std::mt19937 random(11);
    std::uniform_real_distribution<double> uniform(-1.5, 1.5);
    double worst_inertia = 0.0;
    double worst_bias = 0.0;
    double worst_palm = 0.0;
    for (int trial = 0; trial < 5; ++trial) {
        const Eigen::VectorXd q = Eigen::VectorXd::NullaryExpr(kdl.joints(), [&] { return uniform(random); });
        const Eigen::VectorXd qdot = Eigen::VectorXd::NullaryExpr(kdl.joints(), [&] { return uniform(random); });
        Eigen::MatrixXd inertia;
        Eigen::VectorXd bias;
        scene_terms(world, q, qdot, inertia, bias);
        ASSERT_TRUE(kdl.read(q, qdot, input));
        worst_inertia = std::max(worst_inertia, (inertia - input.inertia).cwiseAbs().maxCoeff());
        worst_bias = std::max(worst_bias, (bias - input.bias).cwiseAbs().maxCoeff());
        for (Eigen::Index i = 0; i < kdl.arms(); ++i) {
            const Eigen::Isometry3d flange = kdl.contact_pose(i);
            const Eigen::Vector3d site = flange * Eigen::Vector3d(0.0, 0.0, 0.02);
            worst_palm = std::max(worst_palm, (site - world.arms().contact_position(world.data(), i)).norm());
            worst_palm = std::max(worst_palm, (flange.linear() - world.arms().contact_rotation(world.data(), i))
                                                  .cwiseAbs()
                                                  .maxCoeff());
        }
    }
    std::printf("generated MJCF against KDL on the URDF: M %.3g, h %.3g, palm frames %.3g\n", worst_inertia,
                worst_bias, worst_palm);
    EXPECT_LT(worst_inertia, 1e-13);  // measured 1.2e-14
    EXPECT_LT(worst_bias, 1e-12);  // measured 1.6e-13
    EXPECT_LT(worst_palm, 5e-15);  // measured 6.7e-16
}
#endif

// The reader names the field of what is wrong.
void expect_scene_error(const std::string& text, const std::string& path_expected)
{
    try {
        scenes::parse_scene(text, "bad.json", ".");
        ADD_FAILURE() << "accepted: " << text;
    } catch (const example_common::ScenarioError& error) {
        EXPECT_EQ(error.path(), path_expected) << error.what();
    }
}

TEST(SceneReader, NamesTheFieldOfEachProblem)
{
    const std::string joints = R"("joints": ["a", "b", "c", "d", "e", "f", "g", "h", "i", "j", "k", "l"])";
    const std::string head = R"({"model": "m.xml", )" + joints + R"(, "contact_sites": ["l", "r"], )";
    const std::string object = R"("object": {"body": "box", "pose": {"position": [0, 0, 1], "orientation": [1, 0, 0, 0]}}, )";
    const std::string given = R"("start": {"positions": [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0]})";
    const scenes::Scene scene = scenes::parse_scene(head + object + given + "}", "good.json", "dir");
    EXPECT_EQ(scene.model_path, std::filesystem::path("dir") / "m.xml");
    EXPECT_EQ(scene.arms(), 2);
    EXPECT_EQ(scene.joints(), 12);
    ASSERT_TRUE(scene.start.positions);

    expect_scene_error(head + object + R"("start": {"positions": [0, 0]}})", "start.positions");
    expect_scene_error(head + object + R"("start": {}})", "start");
    // A start contact whose z (the inward normal) points out of the box is refused by the
    // controller's rule and words before the IK would chase it (docs/control.md, "Contact frames");
    // "check_contact_normals": false accepts it.
    const std::string z_plus_x = R"("orientation": [0.70710678118654752, 0, 0.70710678118654752, 0])";
    const std::string z_minus_x = R"("orientation": [0.70710678118654752, 0, -0.70710678118654752, 0])";
    const std::string outward = R"("start": {"contacts": [{"position": [0.15, 0, 0], )" + z_plus_x +
                                R"(}, {"position": [-0.15, 0, 0], )" + z_plus_x + "}]}";
    expect_scene_error(head + object + outward + "}", "start.contacts[0].orientation");
    try {
        scenes::parse_scene(head + object + outward + "}", "bad.json", ".");
    } catch (const example_common::ScenarioError& error) {
        EXPECT_NE(std::string(error.what()).find("points out of the object"), std::string::npos) << error.what();
    }
    EXPECT_NO_THROW(scenes::parse_scene(head + object + outward + R"(, "check_contact_normals": false})", "opt-out.json", "."));
    const std::string inward = R"("start": {"contacts": [{"position": [-0.15, 0, 0], )" + z_plus_x +
                               R"(}, {"position": [0.15, 0, 0], )" + z_minus_x + "}]}";
    EXPECT_NO_THROW(scenes::parse_scene(head + object + inward + "}", "good.json", "."));
    expect_scene_error(head + object + inward + R"(, "check_contact_normals": 1})", "check_contact_normals");
    expect_scene_error(head + object + R"("start": {"contacts": [{"position": [0, 0, 0], "orientation": [1, 0, 0, 0]}]}})",
                       "start.contacts");
    expect_scene_error(head + object +
                           R"("start": {"contacts": [{"position": [0, 0, 0], "orientation": [1, 0, 0, 0]},
                                                     {"position": [0, 0, 0], "orientation": [2, 0, 0, 0]}]}})",
                       "start.contacts[1].orientation");
    expect_scene_error(head + R"("object": {"body": "box"}, )" + given + "}", "object.pose");
    expect_scene_error(R"({"model": "m.xml", "joints": ["a", "b"], "contact_sites": ["l", "r"], )" + object + given + "}",
                       "joints");
    expect_scene_error(R"({"model": "m.xml", )" + joints + R"(, "contact_sites": ["l", "l"], )" + object + given + "}",
                       "contact_sites[1]");
    expect_scene_error(head + object + given + R"(, "posture": [1]})", "posture");
    expect_scene_error(head + object + given + R"(, "postur": [1]})", "postur");
}

// Names the model lacks are refused when the world is built, naming the scene file.
TEST(SceneWorld, RefusesAnObjectWithoutAFreeJoint)
{
    scenes::Scene scene = scenes::read_scene(scene_dir + "/ur5e_panda.json");
    scene.object_body = "panda_link3";
    EXPECT_THROW(scenes::SceneWorld{scene}, scenes::SceneError);
}


// ---- The least squeeze at rest on the scenes' arms (errata E13; docs/control.md, "The least squeeze") ----
//
// The controller models the object as massless (docs/control.md, "Inputs and sign conventions"):
// it learns the weight only through L(7), F_x = K_d (p - p_d) at rest, as the object sags m g / K_d
// below its desired pose (docs/scenes.md, "Holding"). So "the mass the controller knows" is set by
// raising the desired pose m g / K_d above the object, everything else at rest: q, qdot = 0 from
// the start, the object's twist and acceleration zero. The references are statics and the friction
// pyramid's geometry, not the controller's code:
// - two palms pressing along one horizontal line through the object's centre, their frames mirror
//   images through the plane midway between them (checked): the reflection maps the grasp, its
//   friction rows and the weight onto themselves, and the least squeeze's optimum is unique (its
//   Hessian I + moment_weight B_m^T B_m is positive definite), so it is mirror-symmetric: each palm
//   carries half the weight, m g / 2 up, and no tangential force across (the mirror flips it). The
//   normal forces are equal (the normals are opposite and nothing else pushes along them), and no
//   squeeze below max(f_min, need) satisfies friction, so that is each palm's normal force;
// - three arms (three_arms.json: the two side palms as above and a third below the centre pushing
//   up; the mirror plane holds it, and its pyramid is symmetric about that plane). The weight's
//   minimum-norm split G^+ F_x is a third at each palm, straight up, no moments: it balances the
//   weight (r_0 = -r_1, r_2 parallel to it) and lies in the range of G^T (f_i = lambda_f,
//   t_i = 0), so the internal part of a wrench is its difference from that split. A mirror-
//   symmetric candidate: each side palm squeezes n and carries s up, the bottom b = m g - 2 s. Its
//   difference from the split is internal, and its square is
//   (b - m g/3)^2 + 2 (s - m g/3)^2 + 2 n^2 = 6 (s - m g/3)^2 + 2 n^2 (no contact moments), to be
//   least subject to n >= f_min, b >= f_min, |s| <= c n (c: the vertical force a side pyramid
//   carries per newton of normal force). With a = m g/3, S = (m g - f_min)/2 (what each side must
//   carry with the bottom at f_min):
//     S <= 0 (f_min >= m g): s = S (any more push from below adds to both terms), n = max(f_min, |S|/c);
//     S > 0: n = max(f_min, min(n*, S/c)), n* = 3 c a / (3 c^2 + 1) (the two terms balanced when
//            friction binds), s = min(a, S, c n);
//   the bottom presses m g - 2 s. The test asserts all three palms against it; f_min >= m g, friction
//   binding at n = f_min, and the balanced n* > f_min all occur among its loads.

using Objective = coopdyn::SqueezeObjective<double>;
constexpr double gravity = 9.81;  // the weight the tests tell the controller of, m g

/// The controller's tick at rest at the world's current state (after start()), told of `mass`
/// through the desired pose's lift m g / K_d.
struct Rest {
    coopdyn::ControlStatus status = coopdyn::ControlStatus::ok;
    coopdyn::Vector6<double> external_wrench;
    Eigen::Matrix<double, 6, Eigen::Dynamic> wrenches;  ///< column i: palm i's [f; t] in its contact frame
    std::vector<Eigen::Matrix3d> rotations;             ///< R_ci, {c_i} to {w}
    double normal(Eigen::Index i) const { return wrenches(2, i); }
};

Rest rest_tick(const scenes::SceneWorld& world, const scenes::ControllerSettings& settings, double mass,
               const Objective& objective)
{
    coopdyn::ControllerParameters<double> parameters = world.controller_parameters(settings);
    parameters.objective = objective;
    const coopdyn::ControllerModel<double> model(parameters);
    coopdyn::ControllerData<double> data(model);
    coopdyn::ControllerInput<double> input(model);
    world.arms().read(world.model(), world.data(), input);
    input.object = coopdyn::mujoco_object_state(world.model(), world.data(), world.object_body());
    input.posture = world.posture();
    input.desired_pose = input.object.pose;
    input.desired_pose.position.z() += mass * gravity / settings.translational_stiffness;
    coopdyn::controller_tick(model, data, input);
    Rest rest;
    rest.status = data.status;
    rest.external_wrench = data.external_wrench;
    rest.wrenches = data.contact_frame_wrenches;
    for (Eigen::Index i = 0; i < model.arms(); ++i) {
        rest.rotations.emplace_back(data.contact_rotations.middleCols<3>(3 * i));
    }
    return rest;
}

/// The normal force that an n-edge pyramid needs to carry the tangential part of `force` (the
/// palm's force on the object, {w}): facet k, outward normal at 2 pi (k + 1/2) / n in the contact
/// plane, bounds the tangential force's component along it by mu cos(pi/n) f_z (docs/control.md,
/// "Friction constraints of one contact"; the pyramid inscribed in the cone, L(18)).
double pyramid_need(const Eigen::Matrix3d& contact_rotation, const Eigen::Vector3d& force,
                    const coopdyn::ContactFriction<double>& friction)
{
    const double pi = 3.14159265358979323846;
    const Eigen::Vector3d local = contact_rotation.transpose() * force;
    const int n = friction.pyramid_edges;
    double reach = 0.0;
    for (int k = 0; k < n; ++k) {
        const double angle = 2.0 * pi * (k + 0.5) / n;
        reach = std::max(reach, local.x() * std::cos(angle) + local.y() * std::sin(angle));
    }
    return reach / (friction.friction_coefficient * std::cos(pi / n));
}

coopdyn::ContactFriction<double> palm_friction(const scenes::ControllerSettings& settings)
{
    coopdyn::ContactFriction<double> friction;  // as SceneWorld::controller_parameters builds it
    friction.friction_coefficient = settings.friction;
    friction.minimum_normal_force = settings.minimum_normal_force;
    return friction;
}

/// The symmetry the closed forms rest on, from the world's state (not the controller's): palms 0
/// and 1 press along one horizontal line through the object's centre of mass, and palm 1's
/// frame is palm 0's mirrored through the plane midway between them (x reflected, y reflected and
/// reversed: the reflection turns a right-handed frame into a left-handed one).
void expect_mirror_pair(const scenes::SceneWorld& world)
{
    const Eigen::Vector3d centre = coopdyn::mujoco_object_pose(world.model(), world.data(), world.object_body()).position;
    const Eigen::Vector3d r0 = world.arms().contact_position(world.data(), 0) - centre;
    const Eigen::Vector3d r1 = world.arms().contact_position(world.data(), 1) - centre;
    const Eigen::Matrix3d R0 = world.arms().contact_rotation(world.data(), 0);
    const Eigen::Matrix3d R1 = world.arms().contact_rotation(world.data(), 1);
    const Eigen::Vector3d n = R0.col(2);
    const Eigen::Matrix3d mirror = Eigen::Matrix3d::Identity() - 2.0 * n * n.transpose();
    EXPECT_LT((r0 + r1).norm(), 1e-9);
    EXPECT_LT(r0.cross(n).norm(), 1e-9);
    EXPECT_LT(std::abs(n.z()), 1e-9);
    EXPECT_LT((R1.col(2) + n).norm(), 1e-9);
    EXPECT_LT((R1.col(0) - mirror * R0.col(0)).norm(), 1e-9);
    EXPECT_LT((R1.col(1) + mirror * R0.col(1)).norm(), 1e-9);
}

scenes::SceneWorld world_at(const std::string& name, const coopdyn::Pose<double>* object = nullptr)
{
    scenes::Scene scene = scenes::read_scene(scene_dir + "/" + name + ".json");
    if (object != nullptr) {
        scene.object_pose = *object;
    }
    scenes::SceneWorld world(scene);
    const scenes::StartReport start = world.start();  // throws when the IK does not converge
    EXPECT_LT(start.contact_position_error, 1e-9) << name;
    EXPECT_LT(start.contact_orientation_error, 1e-9) << name;
    return world;
}

// Issue 21: the UR5e + Panda pair (6 + 7 joints, arms of different weights) at rest, the object at
// four poses reached by the IK (the start; moved and turned about the vertical; turned about the
// line between the palms, which turns the load in each palm's plane: pi/8 puts it on a facet's
// normal, the start on an edge, 0.3 rad between), six loads with f_min or friction binding.
TEST(LeastSqueezeAtRest, UrPandaPalmsPressMaxOfFminAndWhatFrictionNeeds)
{
    const double pi = 3.14159265358979323846;
    const auto turned = [](double yaw, double about_grasp_line) {
        return Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                                  Eigen::AngleAxisd(about_grasp_line, Eigen::Vector3d::UnitY()));
    };
    const coopdyn::Pose<double> poses[] = {{Eigen::Vector3d(0.5, 0.0, 0.5), turned(0.0, 0.0)},
                                           {Eigen::Vector3d(0.45, 0.05, 0.6), turned(0.25, pi / 8)},
                                           {Eigen::Vector3d(0.55, -0.05, 0.42), turned(0.0, 0.3)},
                                           {Eigen::Vector3d(0.5, 0.0, 0.55), turned(-0.2, -pi / 8)}};
    struct Load {
        double mass, mu, f_min;
    };
    // f_min binds in the first, second and fifth (need m g / (2 mu) = 12.3, 19.6 and 9.8 N along an
    // edge, 8 % more along a facet's normal, against 30, 30 and 15 N), friction in the others (73.6,
    // 19.6 and 24.5 N against 30, 5 and 20 N). mu 0.2 and f_min 30 N are the scenes' settings.
    const Load loads[] = {{0.5, 0.2, 30.0}, {0.8, 0.2, 30.0}, {3.0, 0.2, 30.0},
                          {2.0, 0.5, 5.0},  {1.0, 0.5, 15.0}, {4.0, 0.8, 20.0}};
    double worst = 0.0;
    // Per load, the range of paper() / least and least_torque_centred() / least over poses and palms.
    std::array<std::array<double, 4>, 6> ratios;
    ratios.fill({1e300, 0.0, 1e300, 0.0});
    int friction_bound = 0, minimum_bound = 0;
    for (const coopdyn::Pose<double>& pose : poses) {
        const scenes::SceneWorld world = world_at("ur5e_panda", &pose);
        expect_mirror_pair(world);
        for (std::size_t l = 0; l < ratios.size(); ++l) {
            const Load& load = loads[l];
            scenes::ControllerSettings settings;
            settings.friction = load.mu;
            settings.minimum_normal_force = load.f_min;
            const coopdyn::ContactFriction<double> friction = palm_friction(settings);
            const Rest least = rest_tick(world, settings, load.mass, Objective::least_squeeze());
            const Rest paper = rest_tick(world, settings, load.mass, Objective::paper());
            const Rest centred = rest_tick(world, settings, load.mass, Objective::least_torque_centred());
            ASSERT_EQ(least.status, coopdyn::ControlStatus::ok);
            ASSERT_EQ(paper.status, coopdyn::ControlStatus::ok);
            ASSERT_EQ(centred.status, coopdyn::ControlStatus::ok);
            // L(7) at rest: F_x is the weight the test told of.
            ASSERT_LT((least.external_wrench - coopdyn::Vector6<double>(0, 0, -load.mass * gravity, 0, 0, 0)).norm(),
                      1e-9 * load.mass);
            for (Eigen::Index i = 0; i < 2; ++i) {
                const double need =
                    pyramid_need(least.rotations[static_cast<std::size_t>(i)], Eigen::Vector3d(0, 0, load.mass * gravity / 2), friction);
                const double expected = std::max(load.f_min, need);
                worst = std::max(worst, std::abs(least.normal(i) - expected) / expected);
                // 1 % is the issue's requirement; measured 1.1e-11 (the IK's 1e-10 leaves the grasp
                // that far from the mirror symmetry).
                EXPECT_NEAR(least.normal(i), expected, 1e-9 * expected)
                    << "mass " << load.mass << " mu " << load.mu << " f_min " << load.f_min << " object at "
                    << pose.position.transpose() << " palm " << i;
                (need > load.f_min ? friction_bound : minimum_bound) += 1;
                // The other objectives cannot press less: in any feasible wrench the two normal
                // forces are equal and the vertical loads sum to m g, and the pyramid's need is convex
                // and even across the mirror, so it is at least that of m g / 2 each. They press more
                // where the internal wrench they keep from w_0 exceeds what friction needs.
                EXPECT_GE(paper.normal(i), least.normal(i) * (1 - 1e-9)) << "palm " << i;
                EXPECT_GE(centred.normal(i), least.normal(i) * (1 - 1e-9)) << "palm " << i;
                std::array<double, 4>& ratio = ratios[l];
                ratio[0] = std::min(ratio[0], paper.normal(i) / least.normal(i));
                ratio[1] = std::max(ratio[1], paper.normal(i) / least.normal(i));
                ratio[2] = std::min(ratio[2], centred.normal(i) / least.normal(i));
                ratio[3] = std::max(ratio[3], centred.normal(i) / least.normal(i));
            }
        }
    }
    std::printf("[ UR5e + Panda at rest, least squeeze ] %d palms where friction binds, %d where f_min does: normal "
                "force = max(f_min, need) to %.1e (relative)\n",
                friction_bound, minimum_bound, worst);
    for (std::size_t l = 0; l < ratios.size(); ++l) {
        std::printf("  %.1f kg, mu %.1f, f_min %2.0f N: paper() presses %.2f-%.2fx the least squeeze, "
                    "least_torque_centred() %.2f-%.2fx\n",
                    loads[l].mass, loads[l].mu, loads[l].f_min, ratios[l][0], ratios[l][1], ratios[l][2], ratios[l][3]);
    }
    EXPECT_GT(friction_bound, 0);
    EXPECT_GT(minimum_bound, 0);
}

// Issue 21: each shipped scene at its start, the normal force per palm under each preset next to
// the closed form (docs/control.md, "The least squeeze", "On the scenes' arms", is this test's
// table). Loads: the scene's own object mass (from its MJCF) with the scenes' settings (mu 0.2,
// f_min 30 N); 3 kg with f_min 10 N (friction binds); the own mass with the box test's mu 0.5 and
// f_min 2 N, where the internal wrench w_0 holds from the arms' weight is more than the load needs.
TEST(LeastSqueezeAtRest, NormalForcesPerSceneAndObjective)
{
    double worst = 0.0;
    std::printf("| scene | load | palm | closed form | `least_squeeze()` | `least_torque_centred()` | `paper()` |\n"
                "|---|---|---|---|---|---|---|\n");
    for (const char* name : {"lwr4_pair", "ur5e_panda", "three_arms"}) {
        const scenes::SceneWorld world = world_at(name);
        const double own_mass = world.model()->body_mass[world.object_body()];
        expect_mirror_pair(world);
        const Eigen::Index K = world.arms().arms();
        // {mass, mu, f_min}
        for (const std::array<double, 3>& load : {std::array<double, 3>{own_mass, 0.2, 30.0}, std::array<double, 3>{3.0, 0.2, 10.0},
                                                  std::array<double, 3>{own_mass, 0.5, 2.0}}) {
            const double mass = load[0];
            const double weight = mass * gravity;
            const double f_min = load[2];
            scenes::ControllerSettings settings;
            settings.friction = load[1];
            settings.minimum_normal_force = f_min;
            const coopdyn::ContactFriction<double> friction = palm_friction(settings);
            const Rest least = rest_tick(world, settings, mass, Objective::least_squeeze());
            const Rest centred = rest_tick(world, settings, mass, Objective::least_torque_centred());
            const Rest paper = rest_tick(world, settings, mass, Objective::paper());
            ASSERT_EQ(least.status, coopdyn::ControlStatus::ok);
            ASSERT_EQ(centred.status, coopdyn::ControlStatus::ok);
            ASSERT_EQ(paper.status, coopdyn::ControlStatus::ok);
            Eigen::VectorXd expected(K);
            if (K == 2) {
                for (Eigen::Index i = 0; i < 2; ++i) {
                    expected(i) = std::max(f_min, pyramid_need(least.rotations[static_cast<std::size_t>(i)],
                                                                 Eigen::Vector3d(0, 0, weight / 2), friction));
                }
            } else {
                EXPECT_LT((least.rotations[2].col(2) - Eigen::Vector3d::UnitZ()).norm(), 1e-9);  // pushes up
                const double up = 1.0 / pyramid_need(least.rotations[0], Eigen::Vector3d::UnitZ(), friction);  // c
                const double down = 1.0 / pyramid_need(least.rotations[0], -Eigen::Vector3d::UnitZ(), friction);
                const double share = weight / 3;
                const double most = (weight - f_min) / 2;
                double squeeze = 0.0, carried = 0.0;
                if (most <= 0.0) {
                    carried = most;
                    squeeze = std::max(f_min, -most / down);
                } else {
                    squeeze = std::max(f_min, std::min(3 * up * share / (3 * up * up + 1), most / up));
                    carried = std::min({share, most, up * squeeze});
                }
                expected << squeeze, squeeze, weight - 2 * carried;
            }
            for (Eigen::Index i = 0; i < K; ++i) {
                EXPECT_NEAR(least.normal(i), expected(i), 1e-9 * expected(i)) << name << " palm " << i;
                worst = std::max(worst, std::abs(least.normal(i) - expected(i)) / expected(i));
                std::printf("| %s | %.2f kg, mu %.1f, f_min %.0f N | %lld | %.3f | %.3f | %.3f (%.2fx) | %.3f (%.2fx) |\n", name,
                            mass, load[1], f_min, static_cast<long long>(i), expected(i), least.normal(i), centred.normal(i),
                            centred.normal(i) / least.normal(i), paper.normal(i), paper.normal(i) / least.normal(i));
                if (K == 2) {  // the pairs: no feasible squeeze is below the closed form
                    EXPECT_LE(least.normal(i), centred.normal(i) * (1 + 1e-9)) << name << " palm " << i;
                    EXPECT_LE(least.normal(i), paper.normal(i) * (1 + 1e-9)) << name << " palm " << i;
                }
            }
        }
    }
    std::printf("least squeeze against the closed forms: %.1e (relative)\n", worst);
}

// The box experiments' scene plants (examples/box/scene_box.hpp) on three arms, pushed (20 N
// down from 0.2 s) and loaded (0.25 kg at 0.5 s): each palm's measured wrench on the object, the
// push and gravity give the object's acceleration (Newton's second law, m a = m g + F_person +
// sum_i f_i, with the plant's current mass). In MuJoCo the contact forces are the constraint
// solver's (mj_contactForce) and the acceleration its qacc; on the rigid plant the weld's
// constraint wrenches and the solve's acceleration. A wrong sign, frame or palm in the measured
// wrenches, a push or mass not applied, breaks it by newtons.
// The three-arm scene's box, pushed 20 N down from 0.2 s (ramp and hold 0.2 s each).
box_example::BoxScenario pushed_three_arm_box(double duration)
{
    box_example::BoxScenario scenario;
    scenario.duration = duration;
    scenario.box_mass = 0.8;
    scenario.controller.minimum_normal_force = 30.0;
    scenario.push = box_example::Push{};
    scenario.push->start = 0.2;
    scenario.push->force = 20.0;
    scenario.push->ramp = 0.2;
    scenario.push->hold = 0.2;
    return scenario;
}

TEST(SceneBoxPlants, MeasuredPalmWrenchesGiveTheObjectsAcceleration)
{
    const scenes::Scene scene = scenes::read_scene(scene_dir + "/three_arms.json");
    box_example::BoxScenario scenario = pushed_three_arm_box(1.0);
    scenario.added_mass = box_example::AddedMass{0.5, 0.25, 2.0, 0.25};
    for (const bool rigid : {false, true}) {
        const box_example::SceneRun run = box_example::run_scene_experiment(scene, scenario, rigid);
        ASSERT_FALSE(run.dropped) << rigid;
        ASSERT_EQ(run.palm_count(), 3u);
        double worst = 0.0;
        for (const auto& row : run.log) {
            Eigen::Vector3d force = row.box_mass * Eigen::Vector3d(0, 0, -9.81) + row.disturbance.head<3>();
            for (std::size_t i = 0; i < run.palm_count(); ++i) {
                force += row.measured_world[i].head<3>();
            }
            worst = std::max(worst, (row.box_mass * row.box_acceleration - force).norm());
        }
        EXPECT_NEAR(run.log.back().box_mass, 1.05, 1e-12) << rigid;
        EXPECT_LT(worst, 1e-6) << rigid;
        std::printf("%s plant: Newton's second law of the object from the measured palm wrenches: %.3g N\n",
                    rigid ? "rigid" : "MuJoCo", worst);
    }
}

#ifdef COOPDYN_HAVE_BOX_RUNS
// The box program's three-arm runs (box_runs.cpp, run_scene_world) tick the controller at the
// scene's fixed sizes (K = 3, Q = 20; box_experiment.hpp, fixed_scene_palms); scene_box.hpp's
// run_scene_experiment at Dynamic sizes. Same controller, other instantiation: over 1.5 s of the
// push, on both plants, every logged torque, contact wrench and box position agrees to the
// solvers' rounding (relative 1e-9; measured below), and the QP takes the same steps.
TEST(SceneBoxPlants, TheFixedSizeThreeArmRunIsTheDynamicOne)
{
    const scenes::Scene scene = scenes::read_scene(scene_dir + "/three_arms.json");
    ASSERT_TRUE(box_example::fixed_size_scene(scene));
    const box_example::BoxScenario scenario = pushed_three_arm_box(1.5);
    for (const bool rigid : {false, true}) {
        const box_example::SceneRun fixed = box_example::run_scene_world(scene, scenario, rigid, 1);
        const box_example::SceneRun dynamic = box_example::run_scene_experiment(scene, scenario, rigid, 1);
        ASSERT_EQ(fixed.log.size(), dynamic.log.size());
        double worst = 0.0;
        for (std::size_t row = 0; row < fixed.log.size(); ++row) {
            const auto& a = fixed.log[row];
            const auto& b = dynamic.log[row];
            EXPECT_EQ(a.qp_iterations, b.qp_iterations) << row;
            worst = std::max(worst, (a.box_position - b.box_position).norm());
            worst = std::max(worst, (a.motion_torque + a.squeeze_torque - b.motion_torque - b.squeeze_torque).norm() /
                                        (b.motion_torque + b.squeeze_torque).norm());
            for (std::size_t i = 0; i < 3; ++i) {
                worst = std::max(worst, (a.predicted[i] - b.predicted[i]).norm() / b.predicted[i].norm());
                worst = std::max(worst, (a.measured[i] - b.measured[i]).norm() / b.measured[i].norm());
            }
        }
        std::printf("%s plant: the fixed-size three-arm run against the Dynamic one: %.2g\n", rigid ? "rigid" : "MuJoCo",
                    worst);
        EXPECT_LT(worst, 1e-9) << rigid;
    }
}
#endif

}  // namespace
