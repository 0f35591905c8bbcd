// coopdyn._mujoco: the MuJoCo adapter's binding (arms.cpp, plant.cpp) and the C++ side of the
// controller-loop test (loop.cpp), built only where MuJoCo is found (python/CMakeLists.txt):
// _coopdyn and the library stay free of it. Its classes take and return _coopdyn's
// (ControllerInput, Pose, ContactPoint), which pybind11 shares between the two extensions;
// coopdyn/__init__.py imports _coopdyn first.
#include "arms.hpp"

PYBIND11_MODULE(_mujoco, module)
{
    module.doc() = "coopdyn's MuJoCo adapter; use coopdyn.MujocoArms (docs/python.md).";
    coopdyn::python::mujoco::bind_arms(module);
    coopdyn::python::mujoco::bind_plant(module);  // on bind_arms' MujocoArms
    coopdyn::python::mujoco::bind_loop(module);
}
