// The MuJoCo adapter's per-tick read (coopdyn/adapters/mujoco.hpp, docs/adapters.md "Cost") on the
// dual-arm box (K = 2, Q = 14) at its keyframe "hold" with the arms moving: read() alone (MuJoCo's
// stages already run, as after mj_step1); the same from MuJoCo's own functions, as the box example
// read before the adapter; and, for scale, the MuJoCo stages read() needs (mj_kinematics,
// mj_comPos, mj_crb, mj_comVel, mj_rne: what mj_step1 spends on the arms).
#include <benchmark/benchmark.h>
#include <coopdyn/adapters/mujoco.hpp>

#include <stdexcept>
#include <string>
#include <vector>

namespace {

struct Box {
    mjModel* model = nullptr;
    mjData* data = nullptr;
    Box()
    {
        char error[1000] = {0};
        model = mj_loadXML(COOPDYN_BOX_MJCF, nullptr, error, sizeof error);
        if (model == nullptr) {
            throw std::runtime_error(error);
        }
        data = mj_makeData(model);
        mj_resetDataKeyframe(model, data, mj_name2id(model, mjOBJ_KEY, "hold"));
        for (int j = 0; j < 14; ++j) {
            data->qvel[j] = 0.1 * (j - 6);  // moving: Jdot qdot and h's Coriolis part are not zero
        }
        mj_forward(model, data);
    }
    ~Box()
    {
        mj_deleteData(data);
        mj_deleteModel(model);
    }
    Box(const Box&) = delete;
    Box& operator=(const Box&) = delete;
};

std::vector<std::string> joint_names()
{
    std::vector<std::string> names;
    for (const char* side : {"left", "right"}) {
        for (int j = 1; j <= 7; ++j) {
            names.push_back(std::string(side) + "_joint" + std::to_string(j));
        }
    }
    return names;
}

template <int K, int Q> void BM_MujocoArmsRead(benchmark::State& state)
{
    const Box box;
    const coopdyn::MujocoArms<K, Q> arms(box.model, joint_names(), {"left_palm", "right_palm"});
    coopdyn::ControllerInput<double, K, Q> input(2, 14);
    for (auto _ : state) {
        arms.read(box.model, box.data, input);
        benchmark::DoNotOptimize(input.jacobian_rate_qdot.data());
        benchmark::ClobberMemory();
    }
}
BENCHMARK_TEMPLATE(BM_MujocoArmsRead, 2, 14)->Name("BM_MujocoArmsRead<2, 14>");
BENCHMARK_TEMPLATE(BM_MujocoArmsRead, Eigen::Dynamic, Eigen::Dynamic)->Name("BM_MujocoArmsRead<Dynamic, Dynamic>");

/// Baseline: what the box example read with before the adapter (MuJoCo's own functions: the full
/// nv x nv inertia, mj_jacSite, and Jdot qdot by mj_rnePostConstraint with qacc zeroed and
/// mj_objectAcceleration, which writes to data), into the same input.
void BM_MujocoFunctionsBaseline(benchmark::State& state)
{
    const Box box;
    const coopdyn::MujocoArms<2, 14> arms(box.model, joint_names(), {"left_palm", "right_palm"});
    coopdyn::ControllerInput<double, 2, 14> input(2, 14);
    const int nv = box.model->nv;
    std::vector<mjtNum> full(static_cast<std::size_t>(nv * nv)), jacobian(static_cast<std::size_t>(6 * nv));
    for (auto _ : state) {
        mj_fullM(box.model, full.data(), box.data->qM);
        for (int row = 0; row < 14; ++row) {
            for (int col = 0; col < 14; ++col) {
                input.inertia(row, col) = full[static_cast<std::size_t>(row * nv + col)];
            }
            input.bias(row) = box.data->qfrc_bias[row];
        }
        mju_zero(box.data->qacc, nv);
        mj_rnePostConstraint(box.model, box.data);
        for (int palm = 0; palm < 2; ++palm) {
            const int site = arms.contact(palm).id;
            mj_jacSite(box.model, box.data, jacobian.data(), jacobian.data() + 3 * nv, site);
            for (int axis = 0; axis < 6; ++axis) {
                for (int col = 0; col < 14; ++col) {
                    input.jacobian(6 * palm + axis, col) = jacobian[static_cast<std::size_t>(axis * nv + col)];
                }
            }
            mjtNum acceleration[6];
            mj_objectAcceleration(box.model, box.data, mjOBJ_SITE, site, acceleration, 0);
            for (int axis = 0; axis < 3; ++axis) {
                input.jacobian_rate_qdot(6 * palm + axis) = acceleration[3 + axis] + box.model->opt.gravity[axis];
                input.jacobian_rate_qdot(6 * palm + 3 + axis) = acceleration[axis];
            }
        }
        benchmark::DoNotOptimize(input.jacobian_rate_qdot.data());
        benchmark::ClobberMemory();
    }
}
BENCHMARK(BM_MujocoFunctionsBaseline);

void BM_MujocoStagesReadNeeds(benchmark::State& state)
{
    const Box box;
    for (auto _ : state) {
        mj_kinematics(box.model, box.data);
        mj_comPos(box.model, box.data);
        mj_crb(box.model, box.data);
        mj_comVel(box.model, box.data);
        mj_rne(box.model, box.data, 0, box.data->qfrc_bias);
        benchmark::ClobberMemory();
    }
}
BENCHMARK(BM_MujocoStagesReadNeeds);

}  // namespace
