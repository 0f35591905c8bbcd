// The KDL adapter (include/coopdyn/adapters/kdl.hpp, kdl_urdf.hpp) on the shipped robots
// (examples/robots: UR5e, Franka Emika Panda), alone, as a heterogeneous pair of chains (K = 2,
// Q = 13) and as one tree whose two arms share a torso joint (Q = 14), at seeded random states
// with nonzero joint velocities. Each output is checked against something it is not computed from:
// - J: central differences of the contact poses;
// - Jdot qdot: central differences of J along qdot;
// - M (the adapter's composite-rigid-body algorithm): symmetric positive definite, and
//   M qdd = RNEA(q, 0, qdd) - RNEA(q, 0, 0) with KDL's tree RNEA; per arm, KDL's ChainDynParam;
// - h (the adapter's world-frame RNEA): KDL's tree RNEA; KDL's ChainDynParam per arm; the energy balance
//   qdot^T (h(q, qdot) - h(q, 0)) = qdot^T Mdot qdot / 2 and g = dV/dq by central differences;
// - M, h, J and the palm pose against MuJoCo 2.2.2 loading the same URDF files (to 1e-13 with
//   MuJoCo's compiled inertials; see ShippedRobotsAgainstMujoco for why not the URDF's own);
// and the refusals (InvalidModel) and the per-tick allocations of read().
#include "../allocation_counter.hpp"

#include "../malloc_counter.hpp"  // after allocation_counter.hpp: counts glibc malloc inside KDL too

#include "coopdyn/adapters/kdl.hpp"
#include "coopdyn/adapters/kdl_urdf.hpp"

#include <gtest/gtest.h>

#include <kdl/chaindynparam.hpp>
#include <kdl/treefksolverpos_recursive.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>

#include <mujoco/mujoco.h>

#include <Eigen/Dense>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstddef>
#include <array>
#include <cmath>
#include <iostream>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace {

using coopdyn::KdlArms;
using Input = coopdyn::ControllerInput<double>;
using Arms = KdlArms<>;

struct Robot {
    const char* name;
    int joints;
    std::string path() const { return std::string(COOPDYN_ROBOTS_DIR) + "/" + name + "/" + name + ".urdf"; }
    std::string palm() const { return std::string(name) + "_palm"; }
    std::string base() const { return std::string(name) + (joints == 6 ? "_base" : "_link0"); }
};
const std::array<Robot, 2> robots{{{"ur5e", 6}, {"panda", 7}}};

/// ||a - b|| / max(1, ||b||) (Frobenius).
double relative_error(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b)
{
    return (a - b).norm() / std::max(1.0, b.norm());
}

Eigen::VectorXd random_vector(std::mt19937& rng, Eigen::Index n, double scale)
{
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    Eigen::VectorXd v(n);
    for (Eigen::Index i = 0; i < n; ++i) {
        v[i] = scale * unit(rng);
    }
    return v;
}

/// The chain from a shipped robot's base link to its palm.
KDL::Chain robot_chain(const Robot& robot)
{
    const KDL::Tree tree = coopdyn::kdl_tree_from_urdf(robot.path());
    KDL::Chain chain;
    EXPECT_TRUE(tree.getChain(robot.base(), robot.palm(), chain));
    return chain;
}

/// The heterogeneous pair: the UR5e at y = -0.4 m, the Panda at y = +0.4 m turned to face it.
std::vector<KDL::Frame> pair_bases()
{
    return {KDL::Frame(KDL::Vector(0.0, -0.4, 0.0)), KDL::Frame(KDL::Rotation::RotZ(M_PI), KDL::Vector(0.0, 0.4, 0.0))};
}

/// Both arms on one torso that turns about z (a joint both arms share, q[0]), through a gear (KDL's
/// joint scale 2 and offset 0.1 rad: the adapter must take both from KDL).
KDL::Tree torso_tree()
{
    KDL::Tree tree("world");
    tree.addSegment(KDL::Segment("torso", KDL::Joint("torso_joint", KDL::Joint::RotZ, 2.0, 0.1), KDL::Frame(KDL::Vector(0, 0, 0.6)),
                                 KDL::RigidBodyInertia(15.0, KDL::Vector(0.02, 0.0, -0.2),
                                                       KDL::RotationalInertia(0.4, 0.3, 0.2, 0.01, 0.0, 0.0))),
                    "world");
    const std::vector<KDL::Frame> bases = pair_bases();
    for (std::size_t i = 0; i < 2; ++i) {
        const std::string mount = std::string(robots[i].name) + "_mount";
        tree.addSegment(KDL::Segment(mount, KDL::Joint(KDL::Joint::None), bases[i]), "torso");
        tree.addChain(robot_chain(robots[i]), mount);
    }
    return tree;
}

struct Errors {
    double jacobian = 0, rate = 0, inertia = 0, rnea = 0, power = 0, gravity = 0;
};

/// J against central differences of the contact poses, Jdot qdot against central differences of J
/// along qdot.
void check_kinematics(Arms& arms, const Eigen::VectorXd& q, const Eigen::VectorXd& qdot, Errors& e)
{
    const Eigen::Index n = q.size();
    const Eigen::Index k = arms.arms();
    Input input(k, n), plus(k, n), minus(k, n);
    ASSERT_TRUE(arms.read(q, qdot, input));
    const double step = 1e-6;
    Eigen::MatrixXd numeric(6 * k, n);
    for (Eigen::Index c = 0; c < n; ++c) {
        const Eigen::VectorXd dq = step * Eigen::VectorXd::Unit(n, c);
        std::vector<Eigen::Isometry3d> up, down;
        arms.read(q + dq, qdot, plus);
        for (Eigen::Index i = 0; i < k; ++i) up.push_back(arms.contact_pose(i));
        arms.read(q - dq, qdot, minus);
        for (Eigen::Index i = 0; i < k; ++i) down.push_back(arms.contact_pose(i));
        for (std::size_t i = 0; i < up.size(); ++i) {
            const Eigen::AngleAxisd turn(up[i].linear() * down[i].linear().transpose());
            numeric.block<3, 1>(6 * static_cast<Eigen::Index>(i), c) = (up[i].translation() - down[i].translation()) / (2 * step);
            numeric.block<3, 1>(6 * static_cast<Eigen::Index>(i) + 3, c) = turn.angle() * turn.axis() / (2 * step);
        }
    }
    e.jacobian = std::max(e.jacobian, relative_error(input.jacobian, numeric));
    arms.read(q + step * qdot, qdot, plus);
    arms.read(q - step * qdot, qdot, minus);
    const Eigen::VectorXd rate = (plus.jacobian - minus.jacobian) / (2 * step) * qdot;
    e.rate = std::max(e.rate, relative_error(input.jacobian_rate_qdot, rate));
}

/// Potential energy -sum m g . c of every segment, from KDL's tree forward kinematics.
double potential_energy(const KDL::Tree& tree, const Eigen::VectorXd& q)
{
    KDL::TreeFkSolverPos_recursive fk(tree);
    KDL::JntArray joints(static_cast<unsigned int>(q.size()));
    joints.data = q;
    double v = 0.0;
    for (const auto& [name, element] : tree.getSegments()) {
        const KDL::RigidBodyInertia& inertia = GetTreeElementSegment(element).getInertia();
        KDL::Frame pose;
        if (name == tree.getRootSegment()->first || fk.JntToCart(joints, pose, name) < 0) {
            continue;
        }
        v += inertia.getMass() * 9.81 * (pose * inertia.getCOG()).z();
    }
    return v;
}

/// M: symmetric positive definite, M qdd = RNEA(q, 0, qdd) - RNEA(q, 0, 0). h: KDL's tree RNEA
/// (TreeIdSolver_RNE, a different implementation, in local frames), the power balance
/// qdot^T (h(q, qdot) - h(q, 0)) = qdot^T Mdot qdot / 2 and g(q) = h(q, 0) = dV/dq.
void check_dynamics(Arms& arms, const Eigen::VectorXd& q, const Eigen::VectorXd& qdot, std::mt19937& rng, Errors& e)
{
    const Eigen::Index n = q.size();
    const Eigen::Index k = arms.arms();
    Input input(k, n), at_rest(k, n), plus(k, n), minus(k, n);
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
    ASSERT_TRUE(arms.read(q, qdot, input));
    EXPECT_EQ((input.inertia - input.inertia.transpose()).norm(), 0.0);
    EXPECT_EQ(input.inertia.llt().info(), Eigen::Success);

    KDL::TreeIdSolver_RNE rnea(arms.tree(), KDL::Vector(0.0, 0.0, -9.81));
    KDL::JntArray kq(static_cast<unsigned int>(n)), kzero(static_cast<unsigned int>(n)),
        kqdd(static_cast<unsigned int>(n)), with(static_cast<unsigned int>(n)), without(static_cast<unsigned int>(n));
    kq.data = q;
    kqdd.data = random_vector(rng, n, 3.0);
    rnea.CartToJnt(kq, kzero, kqdd, KDL::WrenchMap(), with);
    rnea.CartToJnt(kq, kzero, kzero, KDL::WrenchMap(), without);
    e.inertia = std::max(e.inertia, relative_error(input.inertia * kqdd.data, with.data - without.data));
    KDL::JntArray kqdot(static_cast<unsigned int>(n)), bias(static_cast<unsigned int>(n));
    kqdot.data = qdot;
    rnea.CartToJnt(kq, kqdot, kzero, KDL::WrenchMap(), bias);
    e.rnea = std::max(e.rnea, relative_error(input.bias, bias.data));

    const double step = 1e-6;
    arms.read(q, zero, at_rest);
    arms.read(q + step * qdot, zero, plus);
    arms.read(q - step * qdot, zero, minus);
    const double half_mdot = 0.5 * qdot.dot((plus.inertia - minus.inertia) / (2 * step) * qdot);
    e.power = std::max(e.power, std::abs(qdot.dot(input.bias - at_rest.bias) - half_mdot) / std::max(1.0, std::abs(half_mdot)));
    Eigen::VectorXd gravity(n);
    for (Eigen::Index c = 0; c < n; ++c) {
        const Eigen::VectorXd dq = 1e-5 * Eigen::VectorXd::Unit(n, c);
        gravity[c] = (potential_energy(arms.tree(), q + dq) - potential_energy(arms.tree(), q - dq)) / 2e-5;
    }
    e.gravity = std::max(e.gravity, relative_error(at_rest.bias, gravity));
}

Errors check_all(Arms& arms, std::uint32_t seed, int samples)
{
    std::mt19937 rng(seed);
    Errors e;
    for (int s = 0; s < samples; ++s) {
        const Eigen::VectorXd q = random_vector(rng, arms.joints(), M_PI);
        const Eigen::VectorXd qdot = random_vector(rng, arms.joints(), 2.0);
        check_kinematics(arms, q, qdot, e);
        check_dynamics(arms, q, qdot, rng, e);
    }
    std::cout << arms.arms() << " arm(s), Q = " << arms.joints() << ", worst over " << samples
              << " states: J vs FD " << e.jacobian << ", Jdot qdot vs FD " << e.rate << ", M qdd vs RNEA "
              << e.inertia << ", h vs RNEA " << e.rnea << ", power balance " << e.power << ", g vs dV/dq " << e.gravity << "\n";
    EXPECT_LT(e.jacobian, 1e-9);
    EXPECT_LT(e.rate, 1e-9);
    EXPECT_LT(e.inertia, 3e-14);
    EXPECT_LT(e.rnea, 1e-14);
    EXPECT_LT(e.power, 2e-8);
    EXPECT_LT(e.gravity, 2e-9);
    return e;
}

TEST(KdlAdapter, ShippedRobotsAgainstFiniteDifferencesAndRnea)
{
    for (const Robot& robot : robots) {
        Arms arms = coopdyn::kdl_arms_from_urdf(robot.path(), {robot.palm()});
        ASSERT_EQ(arms.joints(), robot.joints) << robot.name;
        check_all(arms, 2026u + static_cast<std::uint32_t>(robot.joints), 10);
    }
}

TEST(KdlAdapter, HeterogeneousPairOfChains)
{
    Arms arms({robot_chain(robots[0]), robot_chain(robots[1])}, pair_bases());
    ASSERT_EQ(arms.arms(), 2);
    ASSERT_EQ(arms.joints(), 13);
    EXPECT_EQ(arms.joint_names().front(), "arm0/0");
    EXPECT_EQ(arms.joint_names().back(), "arm1/6");
    check_all(arms, 613u, 10);

    // Per arm, against KDL's chain algorithms (no shared joint: M is block diagonal).
    std::mt19937 rng(77u);
    Input input(2, 13);
    const Eigen::VectorXd q = random_vector(rng, 13, M_PI);
    const Eigen::VectorXd qdot = random_vector(rng, 13, 2.0);
    ASSERT_TRUE(arms.read(q, qdot, input));
    EXPECT_EQ(input.inertia.block(0, 6, 6, 7).norm(), 0.0);
    Eigen::Index offset = 0;
    for (std::size_t i = 0; i < 2; ++i) {
        const KDL::Chain chain = robot_chain(robots[i]);
        const auto n = static_cast<Eigen::Index>(chain.getNrOfJoints());
        KDL::ChainDynParam dynamics(chain, pair_bases()[i].M.Inverse(KDL::Vector(0.0, 0.0, -9.81)));
        KDL::JntArray kq(chain.getNrOfJoints()), kqdot(chain.getNrOfJoints()), coriolis(chain.getNrOfJoints()),
            gravity(chain.getNrOfJoints());
        KDL::JntSpaceInertiaMatrix mass(static_cast<int>(chain.getNrOfJoints()));
        kq.data = q.segment(offset, n);
        kqdot.data = qdot.segment(offset, n);
        dynamics.JntToMass(kq, mass);
        dynamics.JntToCoriolis(kq, kqdot, coriolis);
        dynamics.JntToGravity(kq, gravity);
        const double e_mass = relative_error(input.inertia.block(offset, offset, n, n), mass.data);
        const double e_bias = relative_error(input.bias.segment(offset, n), coriolis.data + gravity.data);
        std::cout << robots[i].name << " vs KDL's ChainDynParam: M " << e_mass << ", h " << e_bias << "\n";
        EXPECT_LT(e_mass, 1e-14) << robots[i].name;
        EXPECT_LT(e_bias, 1e-14) << robots[i].name;
        offset += n;
    }
}

TEST(KdlAdapter, TreeWithSharedTorsoJoint)
{
    KdlArms<2, 14> fixed(torso_tree(), {"ur5e_palm", "panda_palm"});
    Arms arms(torso_tree(), {"ur5e_palm", "panda_palm"});
    ASSERT_EQ(arms.joints(), 14);
    EXPECT_EQ(arms.joint_names().front(), "torso");
    check_all(arms, 99u, 10);
    // The torso joint moves both contacts; the fixed-size adapter reads the same numbers.
    std::mt19937 rng(5u);
    const Eigen::VectorXd q = random_vector(rng, 14, M_PI);
    const Eigen::VectorXd qdot = random_vector(rng, 14, 2.0);
    Input input(2, 14);
    KdlArms<2, 14>::Input fixed_input(2, 14);
    ASSERT_TRUE(arms.read(q, qdot, input));
    ASSERT_TRUE(fixed.read(q, qdot, fixed_input));
    EXPECT_GT(input.jacobian.block(0, 0, 6, 1).norm(), 0.1);
    EXPECT_GT(input.jacobian.block(6, 0, 6, 1).norm(), 0.1);
    EXPECT_EQ(input.jacobian.block(0, 7, 6, 7).norm(), 0.0);
    EXPECT_EQ(relative_error(fixed_input.inertia, input.inertia), 0.0);
    EXPECT_EQ(relative_error(fixed_input.bias, input.bias), 0.0);
    EXPECT_EQ(relative_error(fixed_input.jacobian, input.jacobian), 0.0);
    EXPECT_EQ(relative_error(fixed_input.jacobian_rate_qdot, input.jacobian_rate_qdot), 0.0);
}

struct ModelDeleter {
    void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
    void operator()(mjData* d) const { mj_deleteData(d); }
};

/// \p tree with each segment's inertia replaced by the one MuJoCo compiled for the body of the
/// same name. MuJoCo stores a body's inertia as principal moments in a principal frame
/// (body_inertia, body_iquat) found by its own 3x3 eigen-solver, which reproduces a URDF's full
/// tensor only to about 1e-7 relative (measured below): comparing KDL on the URDF's numbers with
/// MuJoCo would measure that solver, not the adapter's conventions.
KDL::Tree with_mujoco_inertials(const KDL::Tree& tree, const mjModel* m)
{
    const std::string root = tree.getRootSegment()->first;
    KDL::Tree out(root);
    std::vector<KDL::SegmentMap::const_iterator> stack{tree.getRootSegment()};
    while (!stack.empty()) {
        const auto element = stack.back();
        stack.pop_back();
        for (const auto& child : GetTreeElementChildren(element->second)) {
            const KDL::Segment& s = GetTreeElementSegment(child->second);
            const int b = mj_name2id(m, mjOBJ_BODY, s.getName().c_str());
            EXPECT_GE(b, 0) << s.getName();
            const Eigen::Quaterniond iquat(m->body_iquat[4 * b], m->body_iquat[4 * b + 1], m->body_iquat[4 * b + 2],
                                           m->body_iquat[4 * b + 3]);
            const Eigen::Matrix3d r = iquat.toRotationMatrix();
            const Eigen::Matrix3d i = r * Eigen::Map<const Eigen::Vector3d>(m->body_inertia + 3 * b).asDiagonal() * r.transpose();
            const KDL::RigidBodyInertia inertia(
                m->body_mass[b], KDL::Vector(m->body_ipos[3 * b], m->body_ipos[3 * b + 1], m->body_ipos[3 * b + 2]),
                KDL::RotationalInertia(i(0, 0), i(1, 1), i(2, 2), i(0, 1), i(0, 2), i(1, 2)));
            out.addSegment(KDL::Segment(s.getName(), s.getJoint(), s.getFrameToTip(), inertia), element->first);
            stack.push_back(child);
        }
    }
    return out;
}

struct MujocoErrors {
    double inertia = 0, bias = 0, jacobian = 0, pose = 0;
};

/// KDL adapter (on \p tree) against MuJoCo's M (mj_fullM), h (qfrc_bias), the palm body's origin
/// Jacobian (mj_jacBody) and pose, at 20 seeded random states.
MujocoErrors compare_with_mujoco(const KDL::Tree& tree, const Robot& robot, const mjModel* m, mjData* d)
{
    using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    Arms arms(tree, {robot.palm()});
    Input input(1, robot.joints);
    const int palm = mj_name2id(m, mjOBJ_BODY, robot.palm().c_str());
    std::mt19937 rng(31u);
    MujocoErrors e;
    for (int sample = 0; sample < 20; ++sample) {
        const Eigen::VectorXd q = random_vector(rng, robot.joints, M_PI);
        const Eigen::VectorXd qdot = random_vector(rng, robot.joints, 2.0);
        mj_resetData(m, d);
        Eigen::Map<Eigen::VectorXd>(d->qpos, m->nq) = q;
        Eigen::Map<Eigen::VectorXd>(d->qvel, m->nv) = qdot;
        mj_forward(m, d);
        RowMatrix mass(m->nv, m->nv), jacp(3, m->nv), jacr(3, m->nv);
        mj_fullM(m, mass.data(), d->qM);
        mj_jacBody(m, d, jacp.data(), jacr.data(), palm);
        Eigen::MatrixXd jacobian(6, m->nv);
        jacobian << jacp, jacr;
        EXPECT_TRUE(arms.read(q, qdot, input));
        const Eigen::Isometry3d pose = arms.contact_pose(0);
        const Eigen::Map<const Eigen::Vector3d> position(d->xpos + 3 * palm);
        const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> rotation(d->xmat + 9 * palm);
        e.inertia = std::max(e.inertia, relative_error(input.inertia, mass));
        e.bias = std::max(e.bias, relative_error(input.bias, Eigen::Map<const Eigen::VectorXd>(d->qfrc_bias, m->nv)));
        e.jacobian = std::max(e.jacobian, relative_error(input.jacobian, jacobian));
        e.pose = std::max(e.pose, (pose.translation() - position).norm() + (pose.linear() - Eigen::Matrix3d(rotation)).norm());
        // The contact's pose read into the input (for the controller's faults), against MuJoCo's too.
        EXPECT_TRUE(input.contact_poses_filled);
        const Eigen::Quaterniond read_orientation(Eigen::Vector4d(input.contact_orientations.col(0)));
        e.pose = std::max(e.pose, (Eigen::Vector3d(input.contact_positions.col(0)) - position).norm() +
                                      (read_orientation.toRotationMatrix() - Eigen::Matrix3d(rotation)).norm());
    }
    return e;
}

// MuJoCo reads the same URDF files (their <mujoco><compiler> element keeps the palm body, adds no
// armature and takes the inertials as written). With MuJoCo's compiled inertials the two agree
// to 2e-15 (measured); with the URDF's own numbers only as well as MuJoCo's eigen-solver
// reproduces the full inertia tensors (M 3e-8, h 7e-9 relative for the Panda, measured).
TEST(KdlAdapter, ShippedRobotsAgainstMujoco)
{
    for (const Robot& robot : robots) {
        std::array<char, 1000> error{};
        const std::unique_ptr<mjModel, ModelDeleter> model(
            mj_loadXML(robot.path().c_str(), nullptr, error.data(), static_cast<int>(error.size())));
        ASSERT_TRUE(model) << robot.path() << ": " << error.data();
        const mjModel* m = model.get();
        ASSERT_EQ(m->nv, robot.joints);
        ASSERT_GE(mj_name2id(m, mjOBJ_BODY, robot.palm().c_str()), 0) << robot.name << ": palm fused into its parent";
        for (int j = 0; j < m->nv; ++j) {
            EXPECT_EQ(m->dof_armature[j], 0.0);
            EXPECT_EQ(m->dof_damping[j], 0.0);
        }
        const std::unique_ptr<mjData, DataDeleter> data(mj_makeData(m));
        const KDL::Tree urdf = coopdyn::kdl_tree_from_urdf(robot.path());
        const MujocoErrors same = compare_with_mujoco(with_mujoco_inertials(urdf, m), robot, m, data.get());
        const MujocoErrors exact = compare_with_mujoco(urdf, robot, m, data.get());
        std::cout << robot.name << ": KDL adapter vs MuJoCo over 20 states (MuJoCo's inertials): M " << same.inertia
                  << ", h " << same.bias << ", J " << same.jacobian << ", palm pose " << same.pose
                  << "; with the URDF's own inertials: M " << exact.inertia << ", h " << exact.bias << "\n";
        EXPECT_LT(same.inertia, 1e-13) << robot.name;
        EXPECT_LT(same.bias, 1e-13) << robot.name;
        EXPECT_LT(same.jacobian, 1e-13) << robot.name;
        EXPECT_LT(same.pose, 1e-13) << robot.name;
        EXPECT_LT(exact.inertia, 1e-7) << robot.name;
        EXPECT_LT(exact.bias, 3e-8) << robot.name;
    }
}

/// Runs f, expects an InvalidModel whose parameter and arm are the given ones.
template <typename F> void expect_refusal(F&& f, const std::string& parameter, coopdyn::Index arm)
{
    try {
        f();
        ADD_FAILURE() << "no InvalidModel for " << parameter;
    } catch (const coopdyn::InvalidModel& e) {
        EXPECT_EQ(e.parameter(), parameter) << e.what();
        EXPECT_EQ(e.arm(), arm) << e.what();
    }
}

TEST(KdlAdapter, RefusesMissingSegmentsAndWrongSizes)
{
    const KDL::Tree tree = torso_tree();
    expect_refusal([&] { Arms(tree, {"ur5e_palm", "gripper"}); }, "tip_segments", 1);
    expect_refusal([&] { Arms(tree, {}); }, "tip_segments", coopdyn::no_arm);
    expect_refusal([&] { KdlArms<3, 14>(tree, {"ur5e_palm", "panda_palm"}); }, "tip_segments", coopdyn::no_arm);
    expect_refusal([&] { KdlArms<2, 13>(tree, {"ur5e_palm", "panda_palm"}); }, "tree", coopdyn::no_arm);
    expect_refusal([&] { Arms({robot_chain(robots[0])}, pair_bases()); }, "bases", coopdyn::no_arm);
    expect_refusal([&] { coopdyn::kdl_tree_from_urdf("/nonexistent/robot.urdf"); }, "urdf_path", coopdyn::no_arm);
    // An MJCF file is XML but no URDF.
    expect_refusal([&] { coopdyn::kdl_tree_from_urdf(std::string(COOPDYN_ROBOTS_DIR) + "/../box/dual_arm_box.xml"); },
                   "urdf_path", coopdyn::no_arm);
    try {
        Arms(tree, {"ur5e_palm", "gripper"});
    } catch (const coopdyn::InvalidModel& e) {
        EXPECT_NE(std::string(e.what()).find("'gripper'"), std::string::npos) << e.what();
    }
}

// read() after construction: operator new (std::vector, std::string, KDL's own containers in the
// solvers), Eigen's heap allocations in the inlined code (the JntArray and Jacobian assignments)
// and, where counted, every malloc, also inside liborocos-kdl (docs/adapters.md, "KDL").
TEST(KdlAdapter, ReadAllocatesNothing)
{
    KdlArms<2, 13> arms({robot_chain(robots[0]), robot_chain(robots[1])}, pair_bases());
    KdlArms<2, 13>::Input input(2, 13);
    std::mt19937 rng(8u);
    const Eigen::Matrix<double, 13, 1> q = random_vector(rng, 13, M_PI);
    const Eigen::Matrix<double, 13, 1> qdot = random_vector(rng, 13, 2.0);
    bool ok = arms.read(q, qdot, input);
    const allocation_counter::Allocations counted =
        allocation_counter::count_allocations([&] { ok = arms.read(q, qdot, input) && ok; });
    EXPECT_TRUE(ok);
    std::cout << "read(): operator new " << counted.operator_new << ", Eigen heap " << counted.eigen << "\n";
    EXPECT_EQ(counted.operator_new, 0);
    EXPECT_EQ(counted.eigen, 0);
#ifdef COOPDYN_COUNT_MALLOC
    // The counter sees a malloc (two JntArrays, built inside liborocos-kdl), then none in read().
    malloc_counter::calls = 0;
    allocation_counter::count_allocations([] { const KDL::JntArray probe(7); });
    EXPECT_GE(malloc_counter::calls.load(), 1);
    malloc_counter::calls = 0;
    allocation_counter::count_allocations([&] { ok = arms.read(q, qdot, input) && ok; });
    std::cout << "read(): malloc " << malloc_counter::calls.load() << "\n";
    EXPECT_EQ(malloc_counter::calls.load(), 0);
    EXPECT_TRUE(ok);
#endif
}

}  // namespace
