// The MuJoCo adapter (coopdyn/adapters/mujoco.hpp, docs/adapters.md) against what it was not
// derived from, at seeded random states (joints within their ranges, nonzero velocities, the
// object and the other robot moved too) of three models: the dual-arm box (MJCF, K = 2, Q = 14),
// torso_arms.xml (a shared torso slide, a slide in an arm, an object's free joint and another
// robot's hinge first in qpos, an unchosen finger, armature and damping; K = 3) and
// two_link_arm.urdf (URDF, its contact a fixed link's body frame):
//
// - J against central differences of the contact poses (position, and log(R+ R-^T) for the
//   orientation), and against MuJoCo's own mj_jac;
// - Jdot qdot against central differences of MuJoCo's mj_jac along qdot, (J(q + e qdot) -
//   J(q - e qdot)) / 2e qdot;
// - M against mj_fullM's block and mj_mulM's products, symmetric; h against mj_rne with qacc = 0,
//   and by physics: its gravity part against the gradient of the bodies' potential energy, its
//   velocity part by qdot^T C qdot = 1/2 qdot^T Mdot qdot;
// - nothing of the object or the other robot leaks into M, h, J, Jdot qdot;
// - read() allocates nothing and leaves every byte of mjData as it was; neither do a push and the
//   palms' contact wrenches allocate;
// - the construction errors name the joint or site;
// - the contact points in the object's frame and the inverse kinematics (to 1e-9 on the box).
#include "../allocation_counter.hpp"

#include <coopdyn/adapters/mujoco.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <ostream>
#include <random>
#include <string>
#include <vector>

namespace {

using coopdyn::Index;
using Arms = coopdyn::MujocoArms<Eigen::Dynamic, Eigen::Dynamic>;

using ModelPointer = coopdyn::MujocoModelPointer;
using DataPointer = coopdyn::MujocoDataPointer;

ModelPointer load(const std::string& path)
{
    char error[1000] = {0};
    ModelPointer model(mj_loadXML(path.c_str(), nullptr, error, sizeof error));
    if (!model) {
        ADD_FAILURE() << path << ": " << error;
    }
    return model;
}

struct Case {
    const char* name;
    std::string path;
    std::vector<std::string> joints;
    std::vector<std::string> contacts;
};

/// GoogleTest prints a parameter in the test's listing (ctest -N); without this it dumps the
/// struct's bytes, pointers included, so the listing would change from run to run.
void PrintTo(const Case& c, std::ostream* out) { *out << c.name; }

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

Case box_case() { return {"box", COOPDYN_BOX_MJCF, box_joints(), {"left_palm", "right_palm"}}; }
Case torso_case()
{
    // q's order differs from the model's dof order on purpose.
    return {"torso",
            COOPDYN_ADAPTER_DIR "/torso_arms.xml",
            {"right_shoulder", "torso_lift", "left_shoulder", "left_elbow", "left_extend", "left_wrist", "right_elbow",
             "right_wrist"},
            {"left_tip", "right_tip", "torso_site"}};
}
Case urdf_case() { return {"urdf", COOPDYN_ADAPTER_DIR "/two_link_arm.urdf", {"shoulder", "elbow", "wrist_slide"}, {"palm"}}; }

/// A random state: chosen joints within their ranges (or +-pi, +-0.2 m), velocities in +-1.5, and
/// every other joint moved too (a free joint to a random pose and twist). Then mj_forward.
void randomise(const mjModel* model, mjData* data, std::mt19937& random)
{
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (int joint = 0; joint < model->njnt; ++joint) {
        const int q = model->jnt_qposadr[joint];
        const int v = model->jnt_dofadr[joint];
        const int type = model->jnt_type[joint];
        if (type == mjJNT_FREE) {
            for (int k = 0; k < 3; ++k) {
                data->qpos[q + k] += 0.3 * unit(random);
            }
            Eigen::Quaterniond orientation(Eigen::Vector4d(unit(random), unit(random), unit(random), unit(random)));
            orientation.normalize();
            data->qpos[q + 3] = orientation.w();
            data->qpos[q + 4] = orientation.x();
            data->qpos[q + 5] = orientation.y();
            data->qpos[q + 6] = orientation.z();
            for (int k = 0; k < 6; ++k) {
                data->qvel[v + k] = unit(random);
            }
            continue;
        }
        const double low = model->jnt_limited[joint] ? model->jnt_range[2 * joint] : (type == mjJNT_SLIDE ? -0.2 : -M_PI);
        const double high = model->jnt_limited[joint] ? model->jnt_range[2 * joint + 1] : (type == mjJNT_SLIDE ? 0.2 : M_PI);
        data->qpos[q] = low + (high - low) * 0.5 * (1.0 + unit(random));
        data->qvel[v] = 1.5 * unit(random);
    }
    mj_forward(model, data);
}

/// The chosen joints' qpos set to q on a copy of data, and the position stages run.
void set_q(const mjModel* model, mjData* copy, const Arms& arms, const Eigen::VectorXd& q)
{
    for (Index j = 0; j < arms.joints(); ++j) {
        copy->qpos[arms.qpos_address(j)] = q(j);
    }
    mj_kinematics(model, copy);
    mj_comPos(model, copy);
}

/// MuJoCo's own Jacobian of the contact points (mj_jac at the contact point, its body), chosen
/// columns, rows [v; w].
Eigen::MatrixXd mujoco_jacobian(const mjModel* model, const mjData* data, const Arms& arms)
{
    Eigen::MatrixXd jacobian(6 * arms.arms(), arms.joints());
    std::vector<mjtNum> linear(static_cast<std::size_t>(3 * model->nv)), angular(linear.size());
    for (Index i = 0; i < arms.arms(); ++i) {
        mj_jac(model, data, linear.data(), angular.data(), arms.contact(i).position(data), arms.contact(i).body);
        for (int axis = 0; axis < 3; ++axis) {
            for (Index j = 0; j < arms.joints(); ++j) {
                const std::size_t at = static_cast<std::size_t>(axis * model->nv + arms.dof_address(j));
                jacobian(6 * i + axis, j) = linear[at];
                jacobian(6 * i + 3 + axis, j) = angular[at];
            }
        }
    }
    return jacobian;
}

struct Reading {
    Eigen::MatrixXd inertia;
    Eigen::VectorXd bias;
    Eigen::MatrixXd jacobian;
    Eigen::VectorXd rate;
    Eigen::VectorXd q, qdot;
};

Reading read_all(const mjModel* model, const mjData* data, const Arms& arms)
{
    coopdyn::ControllerInput<double> input(arms.arms(), arms.joints());
    arms.read(model, data, input);
    return {input.inertia, input.bias, input.jacobian, input.jacobian_rate_qdot, input.positions, input.velocities};
}

class Conformance : public ::testing::TestWithParam<Case> {
protected:
    void SetUp() override
    {
        model_ = load(GetParam().path);
        ASSERT_TRUE(model_);
        data_.reset(mj_makeData(model_.get()));
        copy_.reset(mj_makeData(model_.get()));
        arms_ = std::make_unique<Arms>(model_.get(), GetParam().joints, GetParam().contacts);
    }
    ModelPointer model_;
    DataPointer data_, copy_;
    std::unique_ptr<Arms> arms_;
};

constexpr int states = 20;

TEST_P(Conformance, JacobianMatchesCentralDifferencesOfTheContactPosesAndMujocosJac)
{
    std::mt19937 random(11);
    const double step = 1e-6;
    double worst_difference = 0.0, worst_mujoco = 0.0;
    for (int trial = 0; trial < states; ++trial) {
        randomise(model_.get(), data_.get(), random);
        const Reading reading = read_all(model_.get(), data_.get(), *arms_);
        Eigen::MatrixXd differences(reading.jacobian.rows(), reading.jacobian.cols());
        for (Index j = 0; j < arms_->joints(); ++j) {
            std::vector<coopdyn::Pose<double>> plus, minus;
            for (const double sign : {1.0, -1.0}) {
                mj_copyData(copy_.get(), model_.get(), data_.get());
                Eigen::VectorXd q = reading.q;
                q(j) += sign * step;
                set_q(model_.get(), copy_.get(), *arms_, q);
                for (Index i = 0; i < arms_->arms(); ++i) {
                    (sign > 0 ? plus : minus).push_back(arms_->contact_pose(copy_.get(), i));
                }
            }
            for (Index i = 0; i < arms_->arms(); ++i) {
                const auto& p = plus[static_cast<std::size_t>(i)];
                const auto& m = minus[static_cast<std::size_t>(i)];
                differences.block<3, 1>(6 * i, j) = (p.position - m.position) / (2 * step);
                differences.block<3, 1>(6 * i + 3, j) =
                    coopdyn::quaternion_log(Eigen::Quaterniond(p.orientation * m.orientation.conjugate())) / (2 * step);
            }
        }
        worst_difference = std::max(worst_difference, (reading.jacobian - differences).cwiseAbs().maxCoeff());
        worst_mujoco = std::max(worst_mujoco,
                                (reading.jacobian - mujoco_jacobian(model_.get(), data_.get(), *arms_)).cwiseAbs().maxCoeff());
    }
    std::printf("[%s] J: max |J - central differences| = %.3g, max |J - mj_jac| = %.3g\n", GetParam().name,
                worst_difference, worst_mujoco);
    EXPECT_LT(worst_difference, 2e-9);
    EXPECT_LT(worst_mujoco, 1e-14);
}

TEST_P(Conformance, JacobianRateTimesVelocityMatchesCentralDifferencesOfMujocosJacAlongQdot)
{
    std::mt19937 random(12);
    const double step = 1e-6;
    double worst = 0.0;
    for (int trial = 0; trial < states; ++trial) {
        randomise(model_.get(), data_.get(), random);
        const Reading reading = read_all(model_.get(), data_.get(), *arms_);
        Eigen::MatrixXd jacobians[2];
        for (int k = 0; k < 2; ++k) {
            mj_copyData(copy_.get(), model_.get(), data_.get());
            set_q(model_.get(), copy_.get(), *arms_, reading.q + (k == 0 ? step : -step) * reading.qdot);
            jacobians[k] = mujoco_jacobian(model_.get(), copy_.get(), *arms_);
        }
        const Eigen::VectorXd expected = (jacobians[0] - jacobians[1]) / (2 * step) * reading.qdot;
        worst = std::max(worst, (reading.rate - expected).cwiseAbs().maxCoeff());
    }
    std::printf("[%s] Jdot qdot: max |read - central differences| = %.3g\n", GetParam().name, worst);
    EXPECT_LT(worst, 5e-9);
}

TEST_P(Conformance, InertiaIsMujocosBlockAndItsProductsBiasIsRne)
{
    std::mt19937 random(13);
    std::normal_distribution<double> normal;
    const int nv = model_->nv;
    std::vector<mjtNum> full(static_cast<std::size_t>(nv * nv)), vector(static_cast<std::size_t>(nv)),
        product(static_cast<std::size_t>(nv)), rne(static_cast<std::size_t>(nv));
    double worst_block = 0.0, worst_product = 0.0, worst_bias = 0.0;
    for (int trial = 0; trial < states; ++trial) {
        randomise(model_.get(), data_.get(), random);
        const Reading reading = read_all(model_.get(), data_.get(), *arms_);
        EXPECT_EQ((reading.inertia - reading.inertia.transpose()).norm(), 0.0);
        EXPECT_EQ(reading.inertia.llt().info(), Eigen::Success);
        mj_fullM(model_.get(), full.data(), data_->qM);
        Eigen::VectorXd x(arms_->joints());
        std::fill(vector.begin(), vector.end(), 0.0);
        for (Index a = 0; a < arms_->joints(); ++a) {
            x(a) = normal(random);
            vector[static_cast<std::size_t>(arms_->dof_address(a))] = x(a);
            for (Index b = 0; b < arms_->joints(); ++b) {
                const double entry = full[static_cast<std::size_t>(arms_->dof_address(a) * nv + arms_->dof_address(b))];
                worst_block = std::max(worst_block, std::abs(reading.inertia(a, b) - entry));
            }
        }
        mj_mulM(model_.get(), data_.get(), product.data(), vector.data());
        const Eigen::VectorXd mx = reading.inertia * x;
        mj_copyData(copy_.get(), model_.get(), data_.get());
        mju_zero(copy_->qacc, nv);
        mj_rne(model_.get(), copy_.get(), 1, rne.data());
        for (Index a = 0; a < arms_->joints(); ++a) {
            const std::size_t dof = static_cast<std::size_t>(arms_->dof_address(a));
            worst_product = std::max(worst_product, std::abs(mx(a) - product[dof]));
            worst_bias = std::max(worst_bias, std::abs(reading.bias(a) - rne[dof]));
        }
    }
    std::printf("[%s] M: max |M - mj_fullM block| = %.3g, max |M x - mj_mulM x| = %.3g; h: max |h - mj_rne| = %.3g\n",
                GetParam().name, worst_block, worst_product, worst_bias);
    EXPECT_EQ(worst_block, 0.0);
    EXPECT_LT(worst_product, 2e-14);
    EXPECT_EQ(worst_bias, 0.0);  // the same RNE, run with qacc = 0: bit for bit
}

/// Gravity's potential energy of every body, U = -sum m_b g . x_b (x_b: centre of mass).
double potential_energy(const mjModel* model, const mjData* data)
{
    double energy = 0.0;
    for (int body = 1; body < model->nbody; ++body) {
        energy -= model->body_mass[body] * mju_dot3(model->opt.gravity, data->xipos + 3 * body);
    }
    return energy;
}

// h checked by physics rather than by MuJoCo's RNE again: its gravity part g = dU/dq (central
// differences of the bodies' potential energy), and its velocity part by the energy identity
// qdot^T (h - g) = qdot^T C qdot = 1/2 qdot^T Mdot qdot (Mdot - 2C is skew-symmetric along qdot),
// with Mdot from central differences of the read M along qdot. The joints outside the chosen
// ones are at rest here, so the chosen arms are a closed system of their own.
TEST_P(Conformance, BiasIsTheGradientOfGravitysEnergyPlusVelocityTermsThatDoNoWork)
{
    std::mt19937 random(16);
    const double step = 1e-6;
    double worst_gravity = 0.0, worst_power = 0.0;
    for (int trial = 0; trial < states; ++trial) {
        randomise(model_.get(), data_.get(), random);
        std::vector<char> chosen(static_cast<std::size_t>(model_->nv), 0);
        for (Index j = 0; j < arms_->joints(); ++j) {
            chosen[static_cast<std::size_t>(arms_->dof_address(j))] = 1;
        }
        for (int dof = 0; dof < model_->nv; ++dof) {
            data_->qvel[dof] = chosen[static_cast<std::size_t>(dof)] != 0 ? data_->qvel[dof] : 0.0;
        }
        mj_forward(model_.get(), data_.get());
        const Reading reading = read_all(model_.get(), data_.get(), *arms_);
        mj_copyData(copy_.get(), model_.get(), data_.get());
        mju_zero(copy_->qvel, model_->nv);
        mj_forward(model_.get(), copy_.get());
        const Reading at_rest = read_all(model_.get(), copy_.get(), *arms_);
        // Fourth-order central differences with a larger step: U is hundreds of J, so the
        // second-order ones at 1e-6 would lose 1e-7 to rounding alone.
        const double energy_step = 1e-3;
        Eigen::VectorXd gradient(arms_->joints());
        for (Index j = 0; j < arms_->joints(); ++j) {
            double energies[4];
            const double offsets[4] = {2.0, 1.0, -1.0, -2.0};
            for (int k = 0; k < 4; ++k) {
                Eigen::VectorXd q = reading.q;
                q(j) += offsets[k] * energy_step;
                set_q(model_.get(), copy_.get(), *arms_, q);
                energies[k] = potential_energy(model_.get(), copy_.get());
            }
            gradient(j) = (-energies[0] + 8 * energies[1] - 8 * energies[2] + energies[3]) / (12 * energy_step);
        }
        worst_gravity = std::max(worst_gravity, (at_rest.bias - gradient).cwiseAbs().maxCoeff());
        Eigen::MatrixXd inertias[2];
        for (int k = 0; k < 2; ++k) {
            mj_copyData(copy_.get(), model_.get(), data_.get());
            for (Index j = 0; j < arms_->joints(); ++j) {
                copy_->qpos[arms_->qpos_address(j)] += (k == 0 ? step : -step) * reading.qdot(j);
            }
            mj_forward(model_.get(), copy_.get());
            inertias[k] = read_all(model_.get(), copy_.get(), *arms_).inertia;
        }
        const Eigen::MatrixXd inertia_rate = (inertias[0] - inertias[1]) / (2 * step);
        const double power = reading.qdot.dot(reading.bias - at_rest.bias);
        worst_power = std::max(worst_power, std::abs(power - 0.5 * reading.qdot.dot(inertia_rate * reading.qdot)));
    }
    std::printf("[%s] h: max |g - dU/dq| = %.3g, max |qdot^T (h - g) - qdot^T Mdot qdot / 2| = %.3g\n", GetParam().name,
                worst_gravity, worst_power);
    EXPECT_LT(worst_gravity, 5e-10);
    EXPECT_LT(worst_power, 1e-8);
}

TEST_P(Conformance, NothingOfTheObjectOrOtherRobotsLeaksIn)
{
    std::mt19937 random(14);
    for (int trial = 0; trial < 5; ++trial) {
        randomise(model_.get(), data_.get(), random);
        const Reading before = read_all(model_.get(), data_.get(), *arms_);
        // Move every joint of another tree (the object's free joint, the other robot) and nothing else.
        std::vector<char> chosen_tree(static_cast<std::size_t>(model_->nbody), 0);
        for (Index j = 0; j < arms_->joints(); ++j) {
            chosen_tree[static_cast<std::size_t>(model_->body_rootid[model_->jnt_bodyid[arms_->joint_id(j)]])] = 1;
        }
        for (int joint = 0; joint < model_->njnt; ++joint) {
            if (chosen_tree[static_cast<std::size_t>(model_->body_rootid[model_->jnt_bodyid[joint]])] != 0) {
                continue;
            }
            const int count = model_->jnt_type[joint] == mjJNT_FREE ? 3 : 1;  // a free joint's position only
            for (int k = 0; k < count; ++k) {
                data_->qpos[model_->jnt_qposadr[joint] + k] += 0.37;
            }
            for (int k = 0; k < (model_->jnt_type[joint] == mjJNT_FREE ? 6 : 1); ++k) {
                data_->qvel[model_->jnt_dofadr[joint] + k] -= 2.1;
            }
        }
        mj_forward(model_.get(), data_.get());
        const Reading after = read_all(model_.get(), data_.get(), *arms_);
        EXPECT_EQ((after.inertia - before.inertia).norm(), 0.0);
        EXPECT_EQ((after.bias - before.bias).norm(), 0.0);
        EXPECT_EQ((after.jacobian - before.jacobian).norm(), 0.0);
        EXPECT_EQ((after.rate - before.rate).norm(), 0.0);
    }
}

TEST_P(Conformance, ReadFillsTheContactPosesFromTheSites)
{
    std::mt19937 random(17);
    randomise(model_.get(), data_.get(), random);
    coopdyn::ControllerInput<double> input(arms_->arms(), arms_->joints());
    arms_->read(model_.get(), data_.get(), input);
    EXPECT_TRUE(input.contact_poses_filled);
    for (Index i = 0; i < arms_->arms(); ++i) {
        // MuJoCo's own frame of the contact (a site's or a body's): its position, and its rotation
        // matrix (row-major) whose columns the quaternion must turn the unit axes onto.
        const auto& contact = arms_->contact(i);
        const mjtNum* xpos = (contact.is_site ? data_->site_xpos : data_->xpos) + 3 * contact.id;
        const mjtNum* xmat = (contact.is_site ? data_->site_xmat : data_->xmat) + 9 * contact.id;
        EXPECT_EQ(Eigen::Vector3d(input.contact_positions.col(i)), Eigen::Vector3d(xpos[0], xpos[1], xpos[2])) << i;
        const Eigen::Quaterniond q(Eigen::Vector4d(input.contact_orientations.col(i)));
        for (int c = 0; c < 3; ++c) {
            const Eigen::Vector3d column(xmat[c], xmat[3 + c], xmat[6 + c]);
            EXPECT_LT((q * Eigen::Vector3d::Unit(c) - column).norm(), 1e-12) << i << ", axis " << c;
        }
    }
}

TEST_P(Conformance, ReadAllocatesNothingAndLeavesDataAsItWas)
{
    std::mt19937 random(15);
    randomise(model_.get(), data_.get(), random);
    coopdyn::ControllerInput<double> input(arms_->arms(), arms_->joints());
    const std::vector<char> before(static_cast<const char*>(data_->buffer),
                                   static_cast<const char*>(data_->buffer) + data_->nbuffer);
    const std::vector<char> stack_before(reinterpret_cast<const char*>(data_->stack),
                                         reinterpret_cast<const char*>(data_->stack + data_->nstack));
    const mjModel* model = model_.get();
    const mjData* data = data_.get();
    const Arms& arms = *arms_;
    const auto allocations = allocation_counter::count_allocations([&] { arms.read(model, data, input); });
    EXPECT_EQ(allocations.operator_new, 0);
    EXPECT_EQ(allocations.eigen, 0);
    EXPECT_EQ(std::memcmp(before.data(), data_->buffer, before.size()), 0);
    EXPECT_EQ(std::memcmp(stack_before.data(), data_->stack, stack_before.size()), 0);
}

// The forces' per-tick functions (coopdyn/adapters/mujoco_forces.hpp): a push at a point and the
// palms' contact wrenches on the dual-arm box, its palms pressed 0.5 mm into it (four contacts
// each), allocate nothing; the values are checked in test_mujoco_helpers.cpp.
TEST(MujocoForces, PushingAndReadingContactWrenchesAllocateNothing)
{
    const ModelPointer model = load(COOPDYN_BOX_MJCF);
    ASSERT_TRUE(model);
    const DataPointer data(mj_makeData(model.get()));
    const int geom = mj_name2id(model.get(), mjOBJ_GEOM, "box_geom");
    model->geom_size[3 * geom + 1] += 0.0005;
    mj_resetDataKeyframe(model.get(), data.get(), mj_name2id(model.get(), mjOBJ_KEY, "hold"));
    mj_forward(model.get(), data.get());
    const Arms arms(model.get(), box_joints(), {"left_palm", "right_palm"});
    coopdyn::MujocoContactWrenches<> wrenches(2);
    const int box = mj_name2id(model.get(), mjOBJ_BODY, "box");
    const coopdyn::Vector6<double> push = (coopdyn::Vector6<double>() << 0, 0, -20, 0, 0, 0).finished();
    const Eigen::Vector3d point(0.4, 0.0, 1.5);
    const mjModel* constant = model.get();
    const auto allocations = allocation_counter::count_allocations([&] {
        coopdyn::mujoco_set_applied_wrench(constant, data.get(), box, push, point);
        arms.read_contact_wrenches(constant, data.get(), box, wrenches);
    });
    EXPECT_EQ(allocations.operator_new, 0);
    EXPECT_EQ(allocations.eigen, 0);
    EXPECT_EQ(wrenches.points.sum(), 8);
}

INSTANTIATE_TEST_SUITE_P(Models, Conformance, ::testing::Values(box_case(), torso_case(), urdf_case()),
                         [](const ::testing::TestParamInfo<Case>& model) { return std::string(model.param.name); });

}  // namespace
