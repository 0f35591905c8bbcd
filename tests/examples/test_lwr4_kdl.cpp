// Cross-check of the dual-arm box example's MuJoCo model (examples/box/dual_arm_box.xml) against an
// independent KDL model of each arm built from examples/box/lwr4.hpp: joint-space inertia M, bias
// forces h = C(q, qdot) qdot + g(q) and the 6 x 7 palm-point Jacobian, at 20 seeded random
// configurations with nonzero joint velocities, to 1e-9 relative. Also: the MJCF's naming contract
// (joints, bodies, sites, geoms, actuators, keyframe, qpos/qvel layout), its inertials against
// lwr4.hpp, the hold keyframe (palms at the box face centres) and the torque limits in the hold.
//
// The KDL model keeps the palm as a separate fixed segment with lwr4.hpp's Palm data on top of the
// bare link 7, whereas the MJCF lumps the palm into link 7 (arm_links()): the comparison also
// checks that lumping and the numbers written into the MJCF.
#include "lwr4.hpp"

#include <gtest/gtest.h>

#include <kdl/chain.hpp>
#include <kdl/chaindynparam.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/frames.hpp>
#include <kdl/jacobian.hpp>
#include <kdl/jntarray.hpp>
#include <kdl/jntspaceinertiamatrix.hpp>
#include <kdl/rigidbodyinertia.hpp>
#include <kdl/rotationalinertia.hpp>
#include <kdl/segment.hpp>

#include <mujoco/mujoco.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace {

using box_example::Side;
using Vector7 = Eigen::Matrix<double, 7, 1>;
using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

const char* const mjcf_path = COOPDYN_BOX_MJCF;
constexpr double tolerance = 1e-9;

struct ModelDeleter {
    void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
    void operator()(mjData* d) const { mj_deleteData(d); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

ModelPtr load_model()
{
    std::array<char, 1000> error{};
    ModelPtr model(mj_loadXML(mjcf_path, nullptr, error.data(), static_cast<int>(error.size())));
    EXPECT_TRUE(model) << "mj_loadXML(" << mjcf_path << "): " << error.data();
    return model;
}

const char* side_name(Side side) { return side == Side::left ? "left" : "right"; }
int dof_offset(Side side) { return side == Side::left ? 0 : 7; }

/// ||a - b|| / max(1, ||b||) (Frobenius).
double relative_error(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b)
{
    return (a - b).norm() / std::max(1.0, b.norm());
}

KDL::Vector to_kdl(const Eigen::Vector3d& v) { return KDL::Vector(v.x(), v.y(), v.z()); }

KDL::RotationalInertia to_kdl_inertia(const Eigen::Matrix3d& i)
{
    return KDL::RotationalInertia(i(0, 0), i(1, 1), i(2, 2), i(0, 1), i(0, 2), i(1, 2));
}

/// One arm in KDL, in its base frame (DH frame 0): seven RotZ segments with Frame::DH and the
/// bare lwr4_links() inertias, then the palm plate as a fixed segment (tip at the plate's centre,
/// carrying its inertia), then a massless fixed segment to the palm's contact point.
KDL::Chain kdl_arm()
{
    KDL::Chain chain;
    for (const box_example::Lwr4Link& link : box_example::lwr4_links()) {
        chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::RotZ),
                                      KDL::Frame::DH(link.a, link.alpha, link.d, 0.0),
                                      KDL::RigidBodyInertia(link.mass, to_kdl(link.com),
                                                            to_kdl_inertia(link.inertia))));
    }
    const box_example::Palm palm = box_example::palm();
    chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), KDL::Frame(to_kdl(palm.centre)),
                                  KDL::RigidBodyInertia(palm.mass, KDL::Vector::Zero(),
                                                        to_kdl_inertia(palm.inertia()))));
    chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None),
                                  KDL::Frame(to_kdl(Eigen::Vector3d(palm.contact_point - palm.centre)))));
    return chain;
}

/// KDL's M, h = C qdot + g and the palm Jacobian ([v; w], world axes, reference point = the palm's
/// contact point) of one arm.
struct KdlResult {
    Eigen::MatrixXd mass;
    Eigen::VectorXd bias;
    Eigen::MatrixXd jacobian;
    Eigen::VectorXd gravity;
};

KdlResult kdl_dynamics(Side side, const Vector7& q, const Vector7& qdot)
{
    const KDL::Chain chain = kdl_arm();
    const Eigen::Isometry3d base = box_example::base_transform(side);
    const Eigen::Matrix3d r = base.linear();
    const Eigen::Vector3d gravity_base = r.transpose() * Eigen::Vector3d(0.0, 0.0, -9.81);

    KDL::JntArray kq(7), kqdot(7), coriolis(7), gravity(7);
    kq.data = q;
    kqdot.data = qdot;
    KDL::JntSpaceInertiaMatrix mass(7);
    KDL::ChainDynParam dyn(chain, to_kdl(gravity_base));
    EXPECT_GE(dyn.JntToMass(kq, mass), 0);
    EXPECT_GE(dyn.JntToCoriolis(kq, kqdot, coriolis), 0);
    EXPECT_GE(dyn.JntToGravity(kq, gravity), 0);

    KDL::Jacobian jac(7);
    KDL::ChainJntToJacSolver jac_solver(chain);
    EXPECT_GE(jac_solver.JntToJac(kq, jac), 0);
    // KDL: base-frame axes, reference point at the chain's tip (the contact point).
    Eigen::MatrixXd jacobian(6, 7);
    jacobian.topRows(3) = r * jac.data.topRows(3);
    jacobian.bottomRows(3) = r * jac.data.bottomRows(3);

    return {mass.data, coriolis.data + gravity.data, jacobian, gravity.data};
}

/// MuJoCo's M (dense nv x nv) after mj_forward.
Eigen::MatrixXd mujoco_mass(const mjModel* m, const mjData* d)
{
    RowMatrix dense(m->nv, m->nv);
    mj_fullM(m, dense.data(), d->qM);
    return dense;
}

/// MuJoCo's 6 x 7 Jacobian of one arm's palm site, [linear; angular] in world axes.
Eigen::MatrixXd mujoco_palm_jacobian(const mjModel* m, const mjData* d, Side side)
{
    const int site = mj_name2id(m, mjOBJ_SITE, (std::string(side_name(side)) + "_palm").c_str());
    RowMatrix jacp(3, m->nv), jacr(3, m->nv);
    mj_jacSite(m, d, jacp.data(), jacr.data(), site);
    Eigen::MatrixXd j(6, 7);
    j.topRows(3) = jacp.middleCols(dof_offset(side), 7);
    j.bottomRows(3) = jacr.middleCols(dof_offset(side), 7);
    return j;
}

TEST(Lwr4Mjcf, NamingContractAndLayout)
{
    const ModelPtr model = load_model();
    ASSERT_TRUE(model);
    const mjModel* m = model.get();
    EXPECT_EQ(m->nq, 21);
    EXPECT_EQ(m->nv, 20);
    EXPECT_EQ(m->nu, 14);
    for (Side side : {Side::left, Side::right}) {
        const std::string s = side_name(side);
        for (int i = 0; i < 7; ++i) {
            const std::string n = std::to_string(i + 1);
            const int joint = mj_name2id(m, mjOBJ_JOINT, (s + "_joint" + n).c_str());
            ASSERT_GE(joint, 0) << s << "_joint" << n;
            EXPECT_EQ(m->jnt_type[joint], mjJNT_HINGE);
            EXPECT_EQ(m->jnt_qposadr[joint], dof_offset(side) + i);
            EXPECT_EQ(m->jnt_dofadr[joint], dof_offset(side) + i);
            EXPECT_EQ(m->jnt_limited[joint], 0);
            EXPECT_EQ(m->dof_damping[dof_offset(side) + i], 0.0);
            EXPECT_EQ(m->dof_armature[dof_offset(side) + i], 0.0);
            EXPECT_EQ(m->dof_frictionloss[dof_offset(side) + i], 0.0);
            const int body = mj_name2id(m, mjOBJ_BODY, (s + "_link" + n).c_str());
            ASSERT_GE(body, 0) << s << "_link" << n;
            EXPECT_EQ(m->jnt_bodyid[joint], body);
            const int motor = mj_name2id(m, mjOBJ_ACTUATOR, (s + "_joint" + n + "_motor").c_str());
            ASSERT_GE(motor, 0) << s << "_joint" << n << "_motor";
            EXPECT_EQ(m->actuator_trnid[2 * motor], joint);
            EXPECT_EQ(m->actuator_gear[6 * motor], 1.0);
            EXPECT_EQ(m->actuator_ctrllimited[motor], 0);
        }
        EXPECT_GE(mj_name2id(m, mjOBJ_SITE, (s + "_palm").c_str()), 0);
        EXPECT_GE(mj_name2id(m, mjOBJ_GEOM, (s + "_palm_geom").c_str()), 0);
    }
    const int box_joint = mj_name2id(m, mjOBJ_JOINT, "box_free");
    ASSERT_GE(box_joint, 0);
    EXPECT_EQ(m->jnt_type[box_joint], mjJNT_FREE);
    EXPECT_EQ(m->jnt_qposadr[box_joint], 14);
    EXPECT_EQ(m->jnt_dofadr[box_joint], 14);
    const int box = mj_name2id(m, mjOBJ_BODY, "box");
    ASSERT_GE(box, 0);
    EXPECT_EQ(m->jnt_bodyid[box_joint], box);
    EXPECT_NEAR(m->body_mass[box], box_example::box_spec().mass, 1e-12);
    EXPECT_GE(mj_name2id(m, mjOBJ_SITE, "box_centre"), 0);
    EXPECT_GE(mj_name2id(m, mjOBJ_GEOM, "box_geom"), 0);
    EXPECT_GE(mj_name2id(m, mjOBJ_KEY, "hold"), 0);
    EXPECT_EQ(m->npair, 2);
    EXPECT_DOUBLE_EQ(m->opt.timestep, 0.001);
    EXPECT_EQ(m->opt.cone, mjCONE_ELLIPTIC);
    // Only the explicit palm-box pairs collide.
    for (int g = 0; g < m->ngeom; ++g) {
        EXPECT_EQ(m->geom_contype[g], 0) << mj_id2name(m, mjOBJ_GEOM, g);
        EXPECT_EQ(m->geom_conaffinity[g], 0) << mj_id2name(m, mjOBJ_GEOM, g);
    }
}

TEST(Lwr4Mjcf, InertialsEqualLwr4Header)
{
    const ModelPtr model = load_model();
    ASSERT_TRUE(model);
    const mjModel* m = model.get();
    const std::array<box_example::Lwr4Link, 7> links = box_example::arm_links();
    for (Side side : {Side::left, Side::right}) {
        for (int i = 0; i < 7; ++i) {
            const std::string name = std::string(side_name(side)) + "_link" + std::to_string(i + 1);
            const int body = mj_name2id(m, mjOBJ_BODY, name.c_str());
            ASSERT_GE(body, 0);
            const box_example::Lwr4Link& link = links[static_cast<std::size_t>(i)];
            EXPECT_NEAR(m->body_mass[body], link.mass, 1e-14 * link.mass) << name;
            const Eigen::Map<const Eigen::Vector3d> ipos(m->body_ipos + 3 * body);
            EXPECT_LT((ipos - link.com).norm(), 1e-15) << name;
            // body_inertia is the principal inertia in the frame body_iquat.
            const Eigen::Quaterniond iquat(m->body_iquat[4 * body], m->body_iquat[4 * body + 1],
                                           m->body_iquat[4 * body + 2], m->body_iquat[4 * body + 3]);
            const Eigen::Map<const Eigen::Vector3d> principal(m->body_inertia + 3 * body);
            const Eigen::Matrix3d r = iquat.toRotationMatrix();
            const Eigen::Matrix3d inertia = r * principal.asDiagonal() * r.transpose();
            EXPECT_LT((inertia - link.inertia).norm(), 1e-14 * link.inertia.norm()) << name;
        }
    }
}

// The independent KDL model against MuJoCo, both arms, 20 seeded random states.
TEST(Lwr4Kdl, MassBiasAndPalmJacobianMatchMujoco)
{
    const ModelPtr model = load_model();
    ASSERT_TRUE(model);
    const mjModel* m = model.get();
    const DataPtr data(mj_makeData(m));
    mjData* d = data.get();

    std::mt19937 rng(20240611u);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const Vector7 limits = box_example::joint_position_limits();

    double worst_mass = 0.0;
    double worst_bias = 0.0;
    double worst_jacobian = 0.0;
    double worst_coupling = 0.0;
    for (int sample = 0; sample < 20; ++sample) {
        mj_resetData(m, d);
        std::array<Vector7, 2> q, qdot;
        for (int a = 0; a < 2; ++a) {
            for (Eigen::Index i = 0; i < 7; ++i) {
                q[static_cast<std::size_t>(a)][i] = limits[i] * unit(rng);
                qdot[static_cast<std::size_t>(a)][i] = 2.0 * unit(rng);  // rad/s
            }
        }
        for (int i = 0; i < 7; ++i) {
            d->qpos[i] = q[0][i];
            d->qpos[7 + i] = q[1][i];
            d->qvel[i] = qdot[0][i];
            d->qvel[7 + i] = qdot[1][i];
        }
        // The box far away, at rest (its free joint does not couple to the arms anyway).
        d->qpos[14] = 10.0;
        d->qpos[15] = 10.0;
        d->qpos[16] = 10.0;
        d->qpos[17] = 1.0;
        mj_forward(m, d);
        const Eigen::MatrixXd mass = mujoco_mass(m, d);
        const Eigen::Map<const Eigen::VectorXd> bias(d->qfrc_bias, m->nv);

        // The arms and the box are dynamically decoupled.
        worst_coupling = std::max(worst_coupling, mass.block(0, 7, 7, 13).norm());
        worst_coupling = std::max(worst_coupling, mass.block(7, 14, 7, 6).norm());

        for (Side side : {Side::left, Side::right}) {
            const auto a = static_cast<std::size_t>(side == Side::left ? 0 : 1);
            const int o = dof_offset(side);
            const KdlResult kdl = kdl_dynamics(side, q[a], qdot[a]);
            const double e_mass = relative_error(mass.block(o, o, 7, 7), kdl.mass);
            const double e_bias = relative_error(bias.segment(o, 7), kdl.bias);
            const double e_jac = relative_error(mujoco_palm_jacobian(m, d, side), kdl.jacobian);
            EXPECT_LT(e_mass, tolerance) << side_name(side) << " sample " << sample;
            EXPECT_LT(e_bias, tolerance) << side_name(side) << " sample " << sample;
            EXPECT_LT(e_jac, tolerance) << side_name(side) << " sample " << sample;
            worst_mass = std::max(worst_mass, e_mass);
            worst_bias = std::max(worst_bias, e_bias);
            worst_jacobian = std::max(worst_jacobian, e_jac);
        }
    }
    EXPECT_EQ(worst_coupling, 0.0);
    std::cout << "max relative error over 20 states x 2 arms: M " << worst_mass << ", h "
              << worst_bias << ", palm Jacobian " << worst_jacobian << "\n";
}

// The hold keyframe: palms at the centres of the box's y faces, normals into the box, the
// arm configuration equal to lwr4.hpp's q_hold(); and the torques it needs are well within the
// limits.
TEST(Lwr4Mjcf, HoldKeyframe)
{
    const ModelPtr model = load_model();
    ASSERT_TRUE(model);
    const mjModel* m = model.get();
    const DataPtr data(mj_makeData(m));
    mjData* d = data.get();
    const int key = mj_name2id(m, mjOBJ_KEY, "hold");
    ASSERT_GE(key, 0);
    mj_resetDataKeyframe(m, d, key);
    mj_forward(m, d);

    const Eigen::Matrix<double, 14, 1> q_hold = box_example::q_hold();
    for (int i = 0; i < 14; ++i) {
        EXPECT_EQ(d->qpos[i], q_hold[i]) << "qpos " << i;
    }
    const box_example::BoxSpec box = box_example::box_spec();
    const int box_site = mj_name2id(m, mjOBJ_SITE, "box_centre");
    const Eigen::Map<const Eigen::Vector3d> box_centre(d->site_xpos + 3 * box_site);
    EXPECT_LT((box_centre - box.hold_centre).norm(), 1e-15);

    for (Side side : {Side::left, Side::right}) {
        const double s = side == Side::left ? 1.0 : -1.0;
        const int site = mj_name2id(m, mjOBJ_SITE, (std::string(side_name(side)) + "_palm").c_str());
        const Eigen::Map<const Eigen::Vector3d> p(d->site_xpos + 3 * site);
        const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> r(d->site_xmat + 9 * site);
        const Eigen::Vector3d face_centre = box.hold_centre + Eigen::Vector3d(0.0, s * box.size.y() / 2, 0.0);
        const double distance = (p - face_centre).norm();
        const double normal_error = (r.col(2) - Eigen::Vector3d(0.0, -s, 0.0)).norm();
        std::cout << side_name(side) << " palm site to box face centre: " << distance
                  << " m, normal error " << normal_error << "\n";
        EXPECT_LT(distance, 1e-12);
        EXPECT_LT(normal_error, 1e-12);
        // lwr4.hpp's own kinematics agrees with MuJoCo's.
        const Eigen::Isometry3d palm = box_example::palm_pose(side, box_example::q_hold(side));
        EXPECT_LT((palm.translation() - p).norm(), 1e-12);
        EXPECT_LT((palm.linear() - Eigen::Matrix3d(r)).norm(), 1e-12);

        // Static torques: gravity (KDL) plus a 100 N squeeze and half the box's weight on the
        // palm; at most half the limits (they are about a third).
        const KdlResult kdl = kdl_dynamics(side, box_example::q_hold(side), Vector7::Zero());
        const Eigen::Vector3d force_on_palm(0.0, s * 100.0, -box.mass * 9.81 / 2.0);
        const Vector7 tau = kdl.gravity - kdl.jacobian.topRows(3).transpose() * force_on_palm;
        const Vector7 usage = tau.cwiseAbs().cwiseQuotient(box_example::torque_limits());
        std::cout << side_name(side) << " hold torque / limit: " << usage.transpose() << "\n";
        EXPECT_LT(usage.maxCoeff(), 0.5);
        // ... and the joints stay inside their position limits.
        EXPECT_TRUE((box_example::q_hold(side).cwiseAbs().array() <
                     0.8 * box_example::joint_position_limits().array())
                        .all());
    }
}

}  // namespace
