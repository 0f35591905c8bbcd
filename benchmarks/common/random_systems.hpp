// Seeded random inputs shared by the benchmarks: a small random-number helper and a random
// cooperative Model of impedance end-effectors. Built outside every timed loop.
#pragma once

#include <coopdyn/coopdyn.hpp>

#include <cstdint>
#include <random>
#include <vector>

namespace coopdyn_benchmark {

using coopdyn::Index;
using MatrixX = Eigen::MatrixXd;
using VectorX = Eigen::VectorXd;

class Random {
public:
    explicit Random(std::uint32_t seed) : engine_(seed) {}
    double uniform(double low, double high) { return std::uniform_real_distribution<double>(low, high)(engine_); }
    MatrixX matrix(Index rows, Index cols, double low = -1, double high = 1)
    {
        MatrixX result(rows, cols);
        for (Index j = 0; j < cols; ++j) {
            for (Index i = 0; i < rows; ++i) {
                result(i, j) = uniform(low, high);
            }
        }
        return result;
    }
    /// B B^T + size * shift I: SPD with a moderate condition number.
    MatrixX spd(Index size, double shift)
    {
        const MatrixX factor = matrix(size, size);
        return factor * factor.transpose() + shift * MatrixX::Identity(size, size);
    }
    Eigen::Quaterniond rotation()
    {
        Eigen::Vector4d coefficients(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
        return Eigen::Quaterniond(coefficients.normalized());
    }

private:
    std::mt19937 engine_;
};

/// A random cooperative Model of N impedance end-effectors (Arms = N or coopdyn::Dynamic), with a
/// non-symmetric grasp and non-identity grasp orientations, from a fixed seed.
template <int Arms>
coopdyn::Model<double, Arms, coopdyn::ImpedanceEndEffector> random_impedance_model(Index arms)
{
    Random random(4242u + static_cast<std::uint32_t>(arms));
    coopdyn::RigidObject<double> object;
    object.mass = random.uniform(1, 5);
    object.inertia_body = random.spd(3, 0.5);
    std::vector<coopdyn::Arm<coopdyn::ImpedanceEndEffector<double>>> arm_list(static_cast<std::size_t>(arms));
    for (auto& arm : arm_list) {
        arm.end_effector.mass = random.uniform(1, 5);
        arm.end_effector.rotational_inertia = random.spd(3, 0.5);
        arm.end_effector.translational_damping = random.uniform(10, 50);
        arm.end_effector.rotational_damping = random.uniform(1, 5);
        arm.end_effector.translational_stiffness = random.uniform(100, 500);
        arm.end_effector.rotational_stiffness = random.uniform(10, 50);
        arm.grasp_body.position = random.matrix(3, 1);
        arm.grasp_body.orientation = random.rotation();
    }
    return coopdyn::Model<double, Arms, coopdyn::ImpedanceEndEffector>(object, arm_list);
}

/// Model, Data and per-tick inputs for N arms (Arms = N or Dynamic), from a fixed seed.
template <int Arms> struct TickFixture {
    using ModelType = coopdyn::Model<double, Arms, coopdyn::ImpedanceEndEffector>;
    using DataType = coopdyn::Data<ModelType>;

    ModelType model;
    DataType data;
    coopdyn::RigidBodyState<double> state;
    coopdyn::Setpoints<double, Arms> setpoints;
    coopdyn::Disturbances<double, Arms> disturbances;

    explicit TickFixture(Index arms)
        : model(random_impedance_model<Arms>(arms)), data(model), setpoints(arms), disturbances(arms)
    {
        Random random(777u + static_cast<std::uint32_t>(arms));
        state.pose.position = random.matrix(3, 1);
        state.pose.orientation = random.rotation();
        state.twist = random.matrix(6, 1, -2, 2);
        for (Index i = 0; i < arms; ++i) {
            setpoints.positions.col(i) = random.matrix(3, 1);
            setpoints.orientations.col(i) = random.rotation().coeffs();
        }
        setpoints.twists = random.matrix(6 * arms, 1);
        setpoints.accelerations = random.matrix(6 * arms, 1);
        setpoints.wrenches = random.matrix(6 * arms, 1, -5, 5);
        disturbances.object = random.matrix(6, 1);
        disturbances.end_effectors = random.matrix(6 * arms, 1);
    }
};

}  // namespace coopdyn_benchmark
