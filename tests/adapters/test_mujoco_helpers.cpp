// The MuJoCo adapter's construction checks and helpers (coopdyn/adapters/mujoco.hpp,
// docs/adapters.md): every refused selection named, fixed and dynamic sizes giving the same
// input, the contact points in the object's frame (where the palms touch the box's faces), the
// object's state against its free joint, the inverse kinematics (reachable targets to 1e-9,
// unreachable ones reported, joint ranges kept, bad targets and options refused), a wrench applied
// at a point against MuJoCo's mj_applyFT, and the palms' contact wrenches against Newton and Euler
// on a pushed, squeezed box. The conformance of read() is in
// test_mujoco_adapter.cpp.
#include <coopdyn/adapters/mujoco.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <random>
#include <string>
#include <utility>
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

// --- Applied wrenches and contact forces (coopdyn/adapters/mujoco_forces.hpp, docs/adapters.md) ---

/// The accelerations mj_forward gives (all dofs).
Eigen::VectorXd forward_acceleration(const mjModel* model, mjData* data)
{
    mj_forward(model, data);
    return Eigen::Map<const Eigen::VectorXd>(data->qacc, model->nv);
}

TEST(MujocoForces, AWrenchAtAPointIsMujocosOwnForceAtThatPoint)
{
    // The reference is MuJoCo's mj_applyFT (a force and torque at a point of a body, as joint
    // forces), on the torso model's free object (its centre of mass off its frame) and on an arm's
    // hand, at a random state with the object turned.
    const ModelPointer torso = load(COOPDYN_ADAPTER_DIR "/torso_arms.xml");
    ASSERT_TRUE(torso);
    const DataPointer data(mj_makeData(torso.get()));
    std::mt19937 random(7);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (int k = 7; k < torso->nq; ++k) {
        data->qpos[k] += 0.3 * unit(random);
    }
    for (int k = 0; k < torso->nv; ++k) {
        data->qvel[k] = unit(random);
    }
    const Eigen::Quaterniond turn(Eigen::AngleAxisd(0.8, Eigen::Vector3d(1, -2, 0.5).normalized()));
    data->qpos[3] = turn.w();
    data->qpos[4] = turn.x();
    data->qpos[5] = turn.y();
    data->qpos[6] = turn.z();
    double worst = 0.0;
    for (const char* name : {"object", "left_hand"}) {
        const int body = mj_name2id(torso.get(), mjOBJ_BODY, name);
        coopdyn::Vector6<double> wrench;
        wrench << 3.0 * unit(random), 3.0 * unit(random), 3.0 * unit(random), unit(random), unit(random), unit(random);
        mj_kinematics(torso.get(), data.get());
        const Eigen::Vector3d point = Eigen::Map<const Eigen::Vector3d>(data->xpos + 3 * body) +
                                      0.2 * Eigen::Vector3d(unit(random), unit(random), unit(random));
        coopdyn::mujoco_set_applied_wrench(torso.get(), data.get(), body, wrench, point);
        const Eigen::VectorXd ours = forward_acceleration(torso.get(), data.get());
        coopdyn::mujoco_clear_applied_wrenches(torso.get(), data.get());
        EXPECT_EQ(coopdyn::mujoco_applied_wrench(torso.get(), data.get(), body).norm(), 0.0);
        mju_zero(data->qfrc_applied, torso->nv);
        mj_applyFT(torso.get(), data.get(), wrench.data(), wrench.data() + 3, point.data(), body, data->qfrc_applied);
        const Eigen::VectorXd mujocos = forward_acceleration(torso.get(), data.get());
        mju_zero(data->qfrc_applied, torso->nv);
        worst = std::max(worst, (ours - mujocos).norm() / mujocos.norm());
        // At the centre of mass the point form is the plain one.
        coopdyn::mujoco_set_applied_wrench(torso.get(), data.get(), body, wrench,
                                           Eigen::Vector3d(Eigen::Map<const Eigen::Vector3d>(data->xipos + 3 * body)));
        EXPECT_EQ((coopdyn::mujoco_applied_wrench(torso.get(), data.get(), body) - wrench).norm(), 0.0);
        coopdyn::mujoco_clear_applied_wrenches(torso.get(), data.get());
    }
    EXPECT_LT(worst, 1e-14);
    std::printf("applied wrench at a point against mj_applyFT: %.2g (relative, accelerations)\n", worst);
}

/// The dual-arm box at its hold, the box 1 mm wider (each palm pressed 0.5 mm into it), pushed.
struct SqueezedBox : BoxAtHold {
    int box = mj_name2id(model.get(), mjOBJ_BODY, "box");
    coopdyn::Vector6<double> push = (coopdyn::Vector6<double>() << 2.0, -1.0, -3.0, 0.05, 0.1, -0.02).finished();
    SqueezedBox()
    {
        const int geom = mj_name2id(model.get(), mjOBJ_GEOM, "box_geom");
        model->geom_size[3 * geom + 1] += 0.0005;
        model->geom_rbound[geom] = Eigen::Map<const Eigen::Vector3d>(model->geom_size + 3 * geom).norm();
        coopdyn::mujoco_set_applied_wrench(model.get(), data.get(), box, push);
        mj_forward(model.get(), data.get());
    }
};

/// Newton and Euler for the box (at rest: no gyroscopic term): the palms' wrenches, its weight and
/// the push against m a and I alpha, from MuJoCo's qacc; the worst residual (N, N m).
template <int K>
double box_balance(const SqueezedBox& box, const coopdyn::MujocoArms<K, 14>& arms, const coopdyn::MujocoContactWrenches<K>& measured)
{
    const mjModel* model = box.model.get();
    const mjData* data = box.data.get();
    const double mass = model->body_mass[box.box];
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> frame(data->xmat + 9 * box.box);
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> inertial(data->ximat + 9 * box.box);
    const Eigen::Vector3d centre = Eigen::Map<const Eigen::Vector3d>(data->xipos + 3 * box.box);
    const Eigen::Vector3d origin = Eigen::Map<const Eigen::Vector3d>(data->xpos + 3 * box.box);
    const Eigen::Vector3d alpha = frame * Eigen::Map<const Eigen::Vector3d>(data->qacc + 17);  // free joint: body axes
    const Eigen::Vector3d acceleration = Eigen::Map<const Eigen::Vector3d>(data->qacc + 14) + alpha.cross(centre - origin);
    const Eigen::Matrix3d inertia =
        inertial * Eigen::Map<const Eigen::Vector3d>(model->body_inertia + 3 * box.box).asDiagonal() * inertial.transpose();
    Eigen::Vector3d force = mass * Eigen::Map<const Eigen::Vector3d>(model->opt.gravity) + box.push.head<3>();
    Eigen::Vector3d moment = box.push.tail<3>();
    for (Index i = 0; i < 2; ++i) {
        force += measured.world.template block<3, 1>(0, i);
        moment += measured.world.template block<3, 1>(3, i) +
                  (arms.contact_position(data, i) - centre).cross(measured.world.template block<3, 1>(0, i));
    }
    return std::max((mass * acceleration - force).norm(), (inertia * alpha - moment).norm());
}

TEST(MujocoForces, PalmWrenchesBalanceThePushedBoxInEitherGeomOrder)
{
    SqueezedBox box;
    const coopdyn::MujocoArms<2, 14> fixed(box.model.get(), box_joints(), palms);
    const coopdyn::MujocoArms<> dynamic(box.model.get(), box_joints(), palms);
    coopdyn::MujocoContactWrenches<2> measured;
    coopdyn::MujocoContactWrenches<> measured_dynamic(2);
    fixed.read_contact_wrenches(box.model.get(), box.data.get(), box.box, measured);
    dynamic.read_contact_wrenches(box.model.get(), box.data.get(), box.box, measured_dynamic);
    EXPECT_EQ((measured.world - measured_dynamic.world).norm(), 0.0);
    EXPECT_EQ((measured.contact_frame - measured_dynamic.contact_frame).norm(), 0.0);
    const double balance = box_balance(box, fixed, measured);
    double normal_gap = 0.0;
    for (Index i = 0; i < 2; ++i) {
        EXPECT_EQ(measured.points(i), 4) << i;  // MuJoCo's box-box contact: the palm's four corners
        EXPECT_GT(measured.contact_frame(2, i), 10.0) << i;
        // The palms lie flat on the faces: their z is MuJoCo's contact normal.
        normal_gap = std::max(normal_gap, std::abs(measured.contact_frame(2, i) - measured.normal_forces(i)));
        // Back from the contact frame: [R f; R t] is the world wrench.
        const Eigen::Matrix3d rotation = fixed.contact_rotation(box.data.get(), i);
        EXPECT_LT((rotation * measured.contact_frame.block<3, 1>(0, i) - measured.world.block<3, 1>(0, i)).norm(), 1e-12);
    }
    EXPECT_LT(balance, 1e-12);
    EXPECT_LT(normal_gap, 1e-12);
    std::printf("pushed box: normal forces %.2f, %.2f N; Newton-Euler residual %.2g; contact z against MuJoCo's "
                "normals %.2g N\n",
                measured.contact_frame(2, 0), measured.contact_frame(2, 1), balance, normal_gap);

    // The left pair with its geoms swapped (box first): the same physics, the other sign in the sum.
    const int pair = 0;
    std::swap(box.model->pair_geom1[pair], box.model->pair_geom2[pair]);
    mj_forward(box.model.get(), box.data.get());
    coopdyn::MujocoContactWrenches<2> swapped;
    fixed.read_contact_wrenches(box.model.get(), box.data.get(), box.box, swapped);
    const double swapped_balance = box_balance(box, fixed, swapped);
    const double change = (swapped.world - measured.world).norm() / measured.world.norm();
    EXPECT_LT(swapped_balance, 1e-12);
    EXPECT_LT(change, 1e-12);
    std::printf("left pair's geoms swapped: Newton-Euler residual %.2g, wrenches changed by %.2g (relative)\n",
                swapped_balance, change);

    // A body no hand touches: zero.
    coopdyn::MujocoContactWrenches<2> none;
    fixed.read_contact_wrenches(box.model.get(), box.data.get(), mj_name2id(box.model.get(), mjOBJ_BODY, "left_link3"), none);
    EXPECT_EQ(none.world.norm(), 0.0);
    EXPECT_EQ(none.points.sum(), 0);
}

TEST(MujocoArmsInverseKinematics, RefusesNonFiniteTargetsAndBadOptionsNamingThem)
{
    BoxAtHold box;
    const coopdyn::MujocoArms<2, 14> arms(box.model.get(), box_joints(), palms);
    std::vector<coopdyn::Pose<double>> targets{arms.contact_pose(box.data.get(), 0), arms.contact_pose(box.data.get(), 1)};
    const auto refused = [&](const std::vector<coopdyn::Pose<double>>& poses, const coopdyn::InverseKinematicsOptions& options) {
        try {
            arms.place_hands(box.model.get(), box.data.get(), poses, options);
        } catch (const coopdyn::InvalidArgument& error) {
            return error.parameter();
        }
        return std::string("not refused");
    };
    targets[1].position.y() = std::nan("");
    EXPECT_EQ(refused(targets, {}), "targets[1]");
    targets[1] = arms.contact_pose(box.data.get(), 1);
    targets[0].orientation.coeffs().setZero();
    EXPECT_EQ(refused(targets, {}), "targets[0]");
    targets[0] = arms.contact_pose(box.data.get(), 0);
    coopdyn::InverseKinematicsOptions options;
    options.max_step = 0.0;
    EXPECT_EQ(refused(targets, options), "options.max_step");
    options = {};
    options.damping = -1.0;
    EXPECT_EQ(refused(targets, options), "options.damping");
    options = {};
    options.iteration_limit = -1;
    EXPECT_EQ(refused(targets, options), "options.iteration_limit");
}

}  // namespace
