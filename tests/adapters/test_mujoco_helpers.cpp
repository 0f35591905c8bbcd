// The MuJoCo adapter's construction checks and helpers (coopdyn/adapters/mujoco.hpp,
// docs/adapters.md): every refused selection named, fixed and dynamic sizes giving the same
// input, the contact points in the object's frame (where the palms touch the box's faces), the
// object's state against its free joint, and the inverse kinematics (reachable targets to 1e-9,
// unreachable ones reported, joint ranges kept). The conformance of read() is in
// test_mujoco_adapter.cpp.
#include <coopdyn/adapters/mujoco.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace {

using coopdyn::Index;

using ModelPointer = coopdyn::MujocoModelPointer;
using DataPointer = coopdyn::MujocoDataPointer;

ModelPointer load(const std::string& path)
{
    char error[1000] = {0};
    ModelPointer model(mj_loadXML(path.c_str(), nullptr, error, sizeof error));
    EXPECT_TRUE(model) << path << ": " << error;
    return model;
}

std::vector<std::string> box_joints()
{
    std::vector<std::string> names;
    for (const char* side : {"left", "right"}) {
        for (int j = 1; j <= 7; ++j) {
            names.push_back(std::string(side) + "_joint" + std::to_string(j));
        }
    }
    return names;
}
const std::vector<std::string> palms{"left_palm", "right_palm"};
const std::vector<std::string> torso_joints{"torso_lift",  "left_shoulder", "left_elbow",  "left_extend",
                                            "left_wrist",  "right_shoulder", "right_elbow", "right_wrist"};

/// The InvalidModel a construction throws (fails the test when none).
template <int K = Eigen::Dynamic, int Q = Eigen::Dynamic>
coopdyn::InvalidModel refusal(const mjModel* model, const std::vector<std::string>& joints,
                              const std::vector<std::string>& contacts)
{
    try {
        const coopdyn::MujocoArms<K, Q> arms(model, joints, contacts);
    } catch (const coopdyn::InvalidModel& error) {
        std::printf("    refused: %s\n", error.what());
        return error;
    }
    ADD_FAILURE() << "not refused";
    return coopdyn::InvalidModel("", "", coopdyn::no_arm, "");
}

TEST(MujocoArmsConstruction, RefusesEachBadSelectionNamingIt)
{
    const ModelPointer box = load(COOPDYN_BOX_MJCF);
    const ModelPointer torso = load(COOPDYN_ADAPTER_DIR "/torso_arms.xml");
    ASSERT_TRUE(box && torso);

    std::vector<std::string> joints = box_joints();
    joints[3] = "left_joint9";
    auto error = refusal(box.get(), joints, palms);
    EXPECT_EQ(error.parameter(), "joint_names[3]");
    EXPECT_NE(std::string(error.what()).find("left_joint9"), std::string::npos);

    error = refusal(box.get(), box_joints(), {"left_palm", "right_hand"});
    EXPECT_EQ(error.parameter(), "contact_sites[1]");
    EXPECT_EQ(error.arm(), 1);
    EXPECT_NE(std::string(error.what()).find("right_hand"), std::string::npos);

    joints = box_joints();
    joints.push_back("box_free");
    error = refusal(box.get(), joints, palms);
    EXPECT_EQ(error.parameter(), "joint_names[14]");
    EXPECT_NE(std::string(error.what()).find("free joint"), std::string::npos);

    joints = box_joints();
    joints[13] = "left_joint2";
    error = refusal(box.get(), joints, palms);
    EXPECT_EQ(error.parameter(), "joint_names[13]");
    EXPECT_NE(std::string(error.what()).find("joint_names[1]"), std::string::npos);

    error = refusal<2, 14>(box.get(), box_joints(), {"left_palm", "right_palm", "box_centre"});
    EXPECT_EQ(error.parameter(), "contact_sites");
    error = refusal<2, 13>(box.get(), box_joints(), palms);
    EXPECT_EQ(error.parameter(), "joint_names");

    // An arm joint without the torso it hangs from: M and h would miss the coupling.
    error = refusal(torso.get(), {"left_shoulder", "left_elbow", "left_extend", "left_wrist"}, {"left_tip"});
    EXPECT_EQ(error.parameter(), "joint_names[0]");
    EXPECT_NE(std::string(error.what()).find("torso_lift"), std::string::npos);

    // A contact below a joint left out (the finger): J would miss its column.
    error = refusal(torso.get(), torso_joints, {"left_tip", "finger_tip"});
    EXPECT_EQ(error.parameter(), "contact_sites[1]");
    EXPECT_EQ(error.arm(), 1);
    EXPECT_NE(std::string(error.what()).find("left_finger_hinge"), std::string::npos);

    error = refusal(nullptr, box_joints(), palms);
    EXPECT_EQ(error.parameter(), "model");
    error = refusal(box.get(), {}, palms);
    EXPECT_EQ(error.parameter(), "joint_names");
    error = refusal(box.get(), box_joints(), {});
    EXPECT_EQ(error.parameter(), "contact_sites");
}

TEST(MujocoArmsConstruction, AcceptsAnUnchosenFingerBelowTheArmsAndABodyAsContact)
{
    const ModelPointer torso = load(COOPDYN_ADAPTER_DIR "/torso_arms.xml");
    ASSERT_TRUE(torso);
    const coopdyn::MujocoArms<> arms(torso.get(), torso_joints, {"left_tip", "right_hand"});
    EXPECT_TRUE(arms.contact(0).is_site);
    EXPECT_FALSE(arms.contact(1).is_site);  // no site is called right_hand: its body's frame
    EXPECT_EQ(arms.arms(), 2);
    EXPECT_EQ(arms.joints(), 8);
}

// A hand's body named where its palm's site was meant (the box's right_link7 carries the site
// right_palm 0.02 m out on the palm's surface): accepted by default but described as a body frame,
// naming the site; refused with sites_only.
TEST(MujocoArmsConstruction, SaysWhetherAContactIsASiteOrABodyAndCanRequireSites)
{
    const ModelPointer box = load(COOPDYN_BOX_MJCF);
    ASSERT_TRUE(box);
    const coopdyn::MujocoArms<> arms(box.get(), box_joints(), {"left_palm", "right_link7"});
    EXPECT_EQ(arms.contact_frame_kind(0), coopdyn::MujocoFrameKind::site);
    EXPECT_EQ(arms.contact_frame_kind(1), coopdyn::MujocoFrameKind::body);
    EXPECT_EQ(arms.contact_description(0), "site 'left_palm' on body 'left_link7'");
    EXPECT_EQ(arms.contact_description(1), "body 'right_link7' (no site has that name: the contact frame is the body's "
                                           "own frame, not a point on its surface; sites on this body: 'right_palm')");
    const DataPointer data(mj_makeData(box.get()));
    mj_forward(box.get(), data.get());
    const coopdyn::MujocoArms<> sites(box.get(), box_joints(), palms, coopdyn::MujocoContactFrames::sites_only);
    EXPECT_NEAR((sites.contact_position(data.get(), 1) - arms.contact_position(data.get(), 1)).norm(), 0.02, 1e-15);

    try {
        const coopdyn::MujocoArms<> refused(box.get(), box_joints(), {"left_palm", "right_link7"},
                                            coopdyn::MujocoContactFrames::sites_only);
        ADD_FAILURE() << "a body accepted with sites_only";
    } catch (const coopdyn::InvalidModel& error) {
        std::printf("    refused: %s\n", error.what());
        EXPECT_EQ(error.parameter(), "contact_sites[1]");
        EXPECT_EQ(error.arm(), 1);
        EXPECT_NE(std::string(error.what()).find("'right_link7' is a body"), std::string::npos);
        EXPECT_NE(std::string(error.what()).find("'right_palm'"), std::string::npos);
    }
}

TEST(MujocoArms, FixedAndDynamicSizesReadTheSameInput)
{
    const ModelPointer box = load(COOPDYN_BOX_MJCF);
    ASSERT_TRUE(box);
    const DataPointer data(mj_makeData(box.get()));
    mj_resetDataKeyframe(box.get(), data.get(), mj_name2id(box.get(), mjOBJ_KEY, "hold"));
    for (int j = 0; j < 14; ++j) {
        data->qvel[j] = 0.1 * (j - 6);
    }
    mj_forward(box.get(), data.get());
    const coopdyn::MujocoArms<2, 14> fixed(box.get(), box_joints(), palms);
    const coopdyn::MujocoArms<> dynamic(box.get(), box_joints(), palms);
    coopdyn::ControllerInput<double, 2, 14> a(2, 14);
    coopdyn::ControllerInput<double> b(2, 14);
    fixed.read(box.get(), data.get(), a);
    dynamic.read(box.get(), data.get(), b);
    EXPECT_EQ((a.inertia - b.inertia).norm(), 0.0);
    EXPECT_EQ((a.bias - b.bias).norm(), 0.0);
    EXPECT_EQ((a.jacobian - b.jacobian).norm(), 0.0);
    EXPECT_EQ((a.jacobian_rate_qdot - b.jacobian_rate_qdot).norm(), 0.0);
    EXPECT_EQ((a.positions - b.positions).norm(), 0.0);
    EXPECT_EQ((a.velocities - b.velocities).norm(), 0.0);
    EXPECT_GT(a.jacobian_rate_qdot.norm(), 0.0);
}

/// The dual-arm box at its keyframe "hold" (mj_forward run).
struct BoxAtHold {
    ModelPointer model = load(COOPDYN_BOX_MJCF);
    DataPointer data{mj_makeData(model.get())};
    BoxAtHold()
    {
        mj_resetDataKeyframe(model.get(), data.get(), mj_name2id(model.get(), mjOBJ_KEY, "hold"));
        mj_forward(model.get(), data.get());
    }
};

TEST(MujocoArms, ContactPointsAreOnTheBoxFacesWithTheNormalInward)
{
    BoxAtHold box;
    const coopdyn::MujocoArms<2, 14> arms(box.model.get(), box_joints(), palms);
    coopdyn::ContactFriction<double> friction;
    friction.friction_coefficient = 0.7;
    const auto points = arms.contact_points(box.model.get(), box.data.get(), "box", friction);
    ASSERT_EQ(points.size(), 2u);
    const double half_width = box.model->geom_size[3 * mj_name2id(box.model.get(), mjOBJ_GEOM, "box_geom") + 1];
    for (const auto& point : points) {
        const Eigen::Vector3d normal = point.frame.orientation * Eigen::Vector3d::UnitZ();
        // On a face y = +-half_width, the contact z axis along -position (inward), to rounding.
        EXPECT_NEAR(std::abs(point.frame.position.y()), half_width, 1e-9);
        EXPECT_NEAR(normal.dot(-point.frame.position.normalized()), 1.0, 1e-9);
        EXPECT_EQ(point.friction.friction_coefficient, 0.7);
    }
    // Back to {w}: r_i = R_o p_i + c, R_ci = R_o R_i (ContactPoint's convention).
    const int body = mj_name2id(box.model.get(), mjOBJ_BODY, "box");
    const coopdyn::Pose<double> object = coopdyn::mujoco_object_pose(box.model.get(), box.data.get(), body);
    for (Index i = 0; i < 2; ++i) {
        const auto& frame = points[static_cast<std::size_t>(i)].frame;
        EXPECT_LT((object.transform_point(frame.position) - arms.contact_position(box.data.get(), i)).norm(), 1e-14);
        EXPECT_LT(((object.orientation * frame.orientation).toRotationMatrix() - arms.contact_rotation(box.data.get(), i)).norm(),
                  1e-14);
    }
    EXPECT_THROW(arms.contact_points(box.model.get(), box.data.get(), "crate"), coopdyn::InvalidArgument);
}

TEST(MujocoArms, ObjectStateIsTheFreeJointsPoseAndTwist)
{
    BoxAtHold box;
    const int body = mj_name2id(box.model.get(), mjOBJ_BODY, "box");
    const double twist[6] = {0.1, -0.2, 0.3, 0.4, -0.5, 0.6};  // free joint: v in {w}, w in the body frame
    Eigen::Quaterniond orientation(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
    mjtNum* qpos = box.data->qpos + 14;
    qpos[3] = orientation.w();
    qpos[4] = orientation.x();
    qpos[5] = orientation.y();
    qpos[6] = orientation.z();
    for (int k = 0; k < 6; ++k) {
        box.data->qvel[14 + k] = twist[k];
    }
    mj_forward(box.model.get(), box.data.get());
    const coopdyn::RigidBodyState<double> state = coopdyn::mujoco_object_state(box.model.get(), box.data.get(), body);
    EXPECT_LT((state.pose.position - Eigen::Vector3d(qpos[0], qpos[1], qpos[2])).norm(), 1e-14);  // centre at the frame
    EXPECT_LT(state.pose.orientation.angularDistance(orientation), 1e-12);
    EXPECT_LT((state.twist.head<3>() - Eigen::Vector3d(twist[0], twist[1], twist[2])).norm(), 1e-12);
    EXPECT_LT((state.twist.tail<3>() - orientation * Eigen::Vector3d(twist[3], twist[4], twist[5])).norm(), 1e-12);
}

TEST(MujocoArmsInverseKinematics, ReachesReachableTargetsOnTheBoxTo1e9)
{
    BoxAtHold box;
    const coopdyn::MujocoArms<2, 14> arms(box.model.get(), box_joints(), palms);
    const DataPointer goal(mj_makeData(box.model.get()));
    std::mt19937 random(21);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    int worst_iterations = 0;
    double worst_residual = 0.0;
    for (int trial = 0; trial < 10; ++trial) {
        // Targets: the palms at a random posture near the hold; start: the hold.
        mj_copyData(goal.get(), box.model.get(), box.data.get());
        for (int j = 0; j < 14; ++j) {
            goal->qpos[j] += 0.4 * unit(random);
        }
        mj_kinematics(box.model.get(), goal.get());
        const std::vector<coopdyn::Pose<double>> targets{arms.contact_pose(goal.get(), 0), arms.contact_pose(goal.get(), 1)};
        const DataPointer data(mj_copyData(nullptr, box.model.get(), box.data.get()));
        const coopdyn::InverseKinematicsResult result = arms.place_hands(box.model.get(), data.get(), targets);
        ASSERT_TRUE(result.converged()) << coopdyn::numerics::to_string(result.status) << ", residual " << result.residual;
        for (Index i = 0; i < 2; ++i) {
            const auto& target = targets[static_cast<std::size_t>(i)];
            EXPECT_LT((arms.contact_position(data.get(), i) - target.position).norm(), 1e-9);
            EXPECT_LT((arms.contact_rotation(data.get(), i) - target.rotation()).norm(), 1e-9);
        }
        worst_iterations = std::max(worst_iterations, result.iterations);
        worst_residual = std::max(worst_residual, result.residual);
        EXPECT_EQ(std::memcmp(data->qpos + 14, box.data->qpos + 14, 7 * sizeof(mjtNum)), 0);  // the box stays
    }
    std::printf("inverse kinematics: at most %d iterations, residual <= %.3g\n", worst_iterations, worst_residual);
}

TEST(MujocoArmsInverseKinematics, ReportsUnreachableTargetsAndKeepsJointRanges)
{
    const ModelPointer torso = load(COOPDYN_ADAPTER_DIR "/torso_arms.xml");
    ASSERT_TRUE(torso);
    const DataPointer data(mj_makeData(torso.get()));
    mj_forward(torso.get(), data.get());
    const coopdyn::MujocoArms<> arms(torso.get(), torso_joints, {"left_tip", "right_tip"});
    std::vector<coopdyn::Pose<double>> targets{arms.contact_pose(data.get(), 0), arms.contact_pose(data.get(), 1)};
    targets[0].position += Eigen::Vector3d(0.0, 2.0, 1.0);  // 2.2 m beyond an arm of 0.7 m
    const coopdyn::InverseKinematicsResult result = arms.place_hands(torso.get(), data.get(), targets);
    EXPECT_FALSE(result.converged());
    EXPECT_GT(result.residual, 1.0);
    for (Index j = 0; j < arms.joints(); ++j) {
        const int id = arms.joint_id(j);
        if (torso->jnt_limited[id]) {
            EXPECT_GE(data->qpos[arms.qpos_address(j)], torso->jnt_range[2 * id]);
            EXPECT_LE(data->qpos[arms.qpos_address(j)], torso->jnt_range[2 * id + 1]);
        }
    }
    // Pulled up and out as far as the torso slide (0.3 m) and the arm's slide (0.1 m) allow.
    EXPECT_NEAR(data->qpos[arms.qpos_address(0)], 0.3, 1e-12);
    std::printf("unreachable target: %s after %d iterations, residual %.3g\n", coopdyn::numerics::to_string(result.status),
                result.iterations, result.residual);
    EXPECT_THROW(arms.place_hands(torso.get(), data.get(), {targets[0]}), coopdyn::InvalidArgument);
}

TEST(DampedLeastSquares, SolvesASmallNonlinearSystemAndReportsAnInconsistentOne)
{
    // x^2 + y^2 = 4, x - y = 1 from (1, 0): converges; x^2 + y^2 = -1 cannot: stalls or runs out.
    const auto circle = [](double radius_squared) {
        return [radius_squared](const Eigen::VectorXd& x, Eigen::VectorXd& e, Eigen::MatrixXd& jacobian) {
            e.resize(2);
            jacobian.resize(2, 2);
            e << radius_squared - x.squaredNorm(), 1.0 - (x(0) - x(1));
            jacobian << 2 * x(0), 2 * x(1), 1, -1;
        };
    };
    const auto none = [](Eigen::VectorXd&) {};
    Eigen::VectorXd x = Eigen::Vector2d(1.0, 0.0);
    auto result = coopdyn::numerics::damped_least_squares(circle(4.0), none, x);
    EXPECT_TRUE(result.converged());
    EXPECT_NEAR(x.squaredNorm(), 4.0, 1e-10);
    EXPECT_NEAR(x(0) - x(1), 1.0, 1e-10);
    x = Eigen::Vector2d(1.0, 0.0);
    result = coopdyn::numerics::damped_least_squares(circle(-1.0), none, x);
    EXPECT_FALSE(result.converged());
    EXPECT_GT(result.residual, 1.0);
}

}  // namespace
