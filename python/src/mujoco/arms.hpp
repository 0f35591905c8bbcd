// coopdyn.MujocoArms (docs/python.md, "The MuJoCo adapter"): the C++ adapter
// coopdyn::MujocoArms<Dynamic, Dynamic> (include/coopdyn/adapters/mujoco.hpp, docs/adapters.md) on
// a MuJoCo model of its own, loaded from an MJCF or URDF file with mj_loadXML (no MuJoCo Python
// package is needed): it owns the mjModel and the mjData, set_state / step move the state, read
// fills a coopdyn.ControllerInput. Shared by the extension's two translation units (arms.cpp binds
// it, loop.cpp runs the C++ side of the controller-loop test).
#pragma once

#include <coopdyn/adapters/mujoco.hpp>
#include <coopdyn/control/controller_model.hpp>

#include <pybind11/pybind11.h>

#include <memory>
#include <string>
#include <vector>

namespace coopdyn::python::mujoco {

namespace py = pybind11;
using Arms = MujocoArms<Eigen::Dynamic, Eigen::Dynamic>;
using InputX = ControllerInput<double, Eigen::Dynamic, Eigen::Dynamic>;

struct ModelDeleter {
    void operator()(mjModel* model) const noexcept { mj_deleteModel(model); }
};
struct DataDeleter {
    void operator()(mjData* data) const noexcept { mj_deleteData(data); }
};

/// The model file's mjModel; throws InvalidModel (parameter model_path) with MuJoCo's message.
inline mjModel* load_model(const std::string& path)
{
    char error[1000] = "";
    mjModel* model = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
    if (model == nullptr) {
        throw InvalidModel("MuJoCo arms", "model_path", no_arm, "cannot load '" + path + "': " + error);
    }
    return model;
}

class OwnedArms {
public:
    OwnedArms(const std::string& path, const std::vector<std::string>& joint_names,
              const std::vector<std::string>& contact_sites,
              MujocoContactFrames frames = MujocoContactFrames::sites_or_bodies)
        : model_(load_model(path)), data_(mj_makeData(model_.get())),
          arms_(model_.get(), joint_names, contact_sites, frames)
    {
        mj_forward(model_.get(), data_.get());
    }
    const mjModel* model() const noexcept { return model_.get(); }
    mjData* data() const noexcept { return data_.get(); }
    const Arms& arms() const noexcept { return arms_; }

    /// Throws InvalidArgument unless `input` holds K contacts and Q joints (read would write out of
    /// bounds: the adapter checks sizes only with debug assertions).
    void check(const InputX& input) const
    {
        if (input.inertia.rows() != arms_.joints() || input.jacobian.rows() != 6 * arms_.arms() ||
            input.contact_positions.cols() != arms_.arms()) {
            throw InvalidArgument("MujocoArms.read", "input", no_arm,
                                  "is sized for " + std::to_string(input.contact_positions.cols()) + " contacts and " +
                                      std::to_string(input.inertia.rows()) + " joints, the arms have " +
                                      std::to_string(arms_.arms()) + " and " + std::to_string(arms_.joints()));
        }
    }
    /// tau on the chosen joints (qfrc_applied), then the rest of this step and the position and
    /// velocity stages of the next (mj_step2, mj_step1): read() then sees the new state, as in the
    /// split step of docs/adapters.md's loop.
    template <typename Torque> void step(const Torque& tau) const noexcept
    {
        for (Index j = 0; j < arms_.joints(); ++j) {
            data_->qfrc_applied[arms_.dof_address(j)] = tau(j);
        }
        mj_step2(model_.get(), data_.get());
        mj_step1(model_.get(), data_.get());
    }

private:
    std::unique_ptr<mjModel, ModelDeleter> model_;
    std::unique_ptr<mjData, DataDeleter> data_;
    Arms arms_;
};

void bind_arms(py::module_& module);
void bind_loop(py::module_& module);

}  // namespace coopdyn::python::mujoco
