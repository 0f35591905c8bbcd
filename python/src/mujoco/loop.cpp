// The C++ side of the controller-loop test (python/tests/test_mujoco_arms.py; docs/python.md, "The
// MuJoCo adapter"): `ticks` ticks of read, controller_tick and step on the MuJoCo model, the loop of
// docs/adapters.md written in C++, returning the torques. The test writes the same loop in Python
// with MujocoArms.read, coopdyn.controller_tick and MujocoArms.step and compares the torques
// bitwise: the bindings add nothing to the arithmetic. Test support, hence the underscore.
#include "arms.hpp"

#include <coopdyn/adapters/mujoco_model.hpp>
#include <coopdyn/control.hpp>

#include <pybind11/numpy.h>

namespace coopdyn::python::mujoco {
namespace {

using ModelX = ControllerModel<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::Dynamic>;
using DataX = ControllerData<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::Dynamic>;

/// Per tick: read the arms and the object's state (`object_body`), hold the desired pose and the
/// rest of `input` as given, tick, step. Returns the torques (ticks, Q).
py::array controller_loop(const OwnedArms& arms, const ModelX& controller, InputX input, const std::string& object_body,
                          long ticks)
{
    arms.check(input);
    const int body = detail::mujoco_body_id(arms.model(), object_body);
    py::array_t<double> torques({static_cast<py::ssize_t>(ticks), static_cast<py::ssize_t>(arms.arms().joints())});
    double* out = torques.mutable_data();
    {
        py::gil_scoped_release release;
        DataX data(controller);
        for (long tick = 0; tick < ticks; ++tick) {
            arms.arms().read(arms.model(), arms.data(), input);
            input.object = mujoco_object_state(arms.model(), arms.data(), body);
            const auto& tau = controller_tick(controller, data, input);
            std::copy(tau.data(), tau.data() + tau.size(), out + tick * tau.size());
            arms.step(tau);
        }
    }
    return std::move(torques);
}

}  // namespace

void bind_loop(py::module_& module)
{
    module.def("_controller_loop", &controller_loop, py::arg("arms"), py::arg("controller"), py::arg("input"),
               py::arg("object_body"), py::arg("ticks"),
               "Test support: `ticks` ticks of MujocoArms.read, object_state, controller_tick (a fresh "
               "ControllerData) and MujocoArms.step in C++; the torques (ticks, Q).");
}

}  // namespace coopdyn::python::mujoco
