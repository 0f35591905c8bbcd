// How the scenes' rigid plant (scene_rigid.hpp, RigidScenePlant) advances one step; its own header
// so that code naming it (examples/box/box_runs.hpp) need not parse the plant's.
#pragma once

namespace scenes {

/// How RigidScenePlant advances one step (docs/scenes.md, "The rigid plant").
enum class RigidIntegrator {
    /// Semi-implicit (symplectic) Euler, MuJoCo's own integrator: the velocities from the weld's
    /// accelerations at the step's start, then the positions from the new velocities. One
    /// evaluation of the arms' terms per step, the one the controller's input was read from.
    semi_implicit_euler,
    /// Classical Runge-Kutta of order 4: four evaluations per step; the reference the first is
    /// checked against (test_scenes, "RigidPlantIntegratorsConvergeToEachOther").
    rk4,
};

}  // namespace scenes
