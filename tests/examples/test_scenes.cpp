// The scene layer (examples/scenes, docs/scenes.md): each shipped scene loads, starts (its IK to
// 1e-9, each palm flat on its face of the object), its generated robot MJCF has the URDF's
// joint-space inertia (against KDL on the URDF where kdl_parser is found, and against MuJoCo's own
// URDF compilation), and a short hold in MuJoCo keeps the object with no slip and every QP tick
// feasible. The scene reader refuses malformed files naming the field.
#include "../box/scene_box.hpp"
#include "scene_hold.hpp"
#include "scene_rigid.hpp"

#ifdef COOPDYN_SCENES_HAVE_KDL
#include <coopdyn/adapters/kdl_urdf.hpp>
#endif

#include <gtest/gtest.h>

#include <array>
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
// object's true inertia): the weld holds to rounding, every tick ok, the welds' normal forces at
// the QP's; and the object settles where MuJoCo's does (the same controller; the object's largest
// excursion over 1 s, about 65-74 mm of sag under its unknown weight, agrees to 0.02, 0.06 and
// 0.11 mm on the three scenes: MuJoCo's soft contacts against the welds).
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
    EXPECT_LT(weld[0], 1e-12);
    EXPECT_LT(weld[1], 1e-12);
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

// The box experiments' scene plants (examples/box/scene_box.hpp) on three arms, pushed (20 N
// down from 0.2 s) and loaded (0.25 kg at 0.5 s): each palm's measured wrench on the object, the
// push and gravity give the object's acceleration (Newton's second law, m a = m g + F_person +
// sum_i f_i, with the plant's current mass). In MuJoCo the contact forces are the constraint
// solver's (mj_contactForce) and the acceleration its qacc; on the rigid plant the weld's
// constraint wrenches and the solve's acceleration. A wrong sign, frame or palm in the measured
// wrenches, a push or mass not applied, breaks it by newtons.
TEST(SceneBoxPlants, MeasuredPalmWrenchesGiveTheObjectsAcceleration)
{
    const scenes::Scene scene = scenes::read_scene(scene_dir + "/three_arms.json");
    box_example::BoxScenario scenario;
    scenario.duration = 1.0;
    scenario.box_mass = 0.8;
    scenario.controller.minimum_normal_force = 30.0;
    scenario.push = box_example::Push{};
    scenario.push->start = 0.2;
    scenario.push->force = 20.0;
    scenario.push->ramp = 0.2;
    scenario.push->hold = 0.2;
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

}  // namespace
