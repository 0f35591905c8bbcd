// coopdyn.MujocoArms (docs/python.md, "The MuJoCo adapter"): the C++ adapter
// coopdyn::MujocoArms<Dynamic, Dynamic> (include/coopdyn/adapters/mujoco.hpp, docs/adapters.md) on
// a MuJoCo model of its own, loaded from an MJCF or URDF file with mj_loadXML (no MuJoCo Python
// package is needed): it owns the mjModel and the mjData, set_state / step move the state, read
// fills a coopdyn.ControllerInput. Shared by the extension's translation units (arms.cpp binds it,
// plant.cpp its forces and inverse kinematics, loop.cpp runs the C++ side of the controller-loop
// test).
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
          arms_(model_.get(), joint_names, contact_sites, frames),
          touched_(static_cast<std::size_t>(model_->nbody), Touched{-1, MujocoContactWrenches<>(arms_.arms())})
    {
        forward();
    }
    /// mj_forward on the current state, then record_contacts (its constraint solve's forces).
    void forward() const noexcept
    {
        mj_forward(model_.get(), data_.get());
        record_contacts();
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
        record_contacts();
        mj_step1(model_.get(), data_.get());
    }

    /// The hands' contact wrenches on `body` (any body of its weld) in the last constraint solve
    /// (the last step's, or the last forward()'s), or null when no hand touched it.
    const MujocoContactWrenches<>* contact_wrenches(int body) const noexcept
    {
        const int weld = model_->body_weldid[body];
        for (std::size_t k = 0; k < touched_count_; ++k) {
            if (touched_[k].weld == weld) {
                return &touched_[k].wrenches;
            }
        }
        return nullptr;
    }

private:
    /// The hands' contact wrenches on one weld (a body and the bodies fixed to it).
    struct Touched {
        int weld;
        MujocoContactWrenches<> wrenches;
    };

    /// MujocoArms::read_contact_wrenches on every weld a hand touches, while `data` holds the
    /// contacts and the forces of one constraint solve: after mj_step2 (the next mj_step1 finds new
    /// contacts, which mj_contactForce would read with these forces) or mj_forward. Sized for every
    /// body at construction: allocation-free.
    void record_contacts() const noexcept
    {
        const mjModel* model = model_.get();
        const mjData* data = data_.get();
        touched_count_ = 0;
        for (int c = 0; c < data->ncon; ++c) {
            const int first = model->body_weldid[model->geom_bodyid[data->contact[c].geom1]];
            const int second = model->body_weldid[model->geom_bodyid[data->contact[c].geom2]];
            for (Index i = 0; i < arms_.arms(); ++i) {
                const int hand = model->body_weldid[arms_.contact(i).body];
                if (first == hand) {
                    note_touched(second);
                }
                if (second == hand) {
                    note_touched(first);
                }
            }
        }
        for (std::size_t k = 0; k < touched_count_; ++k) {
            arms_.read_contact_wrenches(model, data, touched_[k].weld, touched_[k].wrenches);
        }
    }
    void note_touched(int weld) const noexcept
    {
        for (std::size_t k = 0; k < touched_count_; ++k) {
            if (touched_[k].weld == weld) {
                return;
            }
        }
        touched_[touched_count_++].weld = weld;  // at most nbody welds
    }

    std::unique_ptr<mjModel, ModelDeleter> model_;
    std::unique_ptr<mjData, DataDeleter> data_;
    Arms arms_;
    mutable std::vector<Touched> touched_;  ///< [0, touched_count_): the welds the hands touched
    mutable std::size_t touched_count_ = 0;
};

void bind_arms(py::module_& module);
void bind_loop(py::module_& module);
/// The applied wrenches, the contact wrenches and place_hands on bind_arms' MujocoArms (plant.cpp).
void bind_plant(py::module_& module);

}  // namespace coopdyn::python::mujoco
