/// \file
/// \brief The fixed-step integration schemes (Simulator's, docs/dynamics.md "Simulator"), in a
/// header of their own so that code naming one need not parse a simulator.
#pragma once

namespace coopdyn {

/// Integration scheme of a fixed-step simulation: Simulator, and the examples' scene rigid plant
/// (examples/scenes/scene_rigid.hpp).
enum class Integrator {
    /// Classical 4th-order Runge-Kutta on (p, q, v, w), quaternion renormalised after each step.
    /// Four evaluations of the dynamics per step.
    runge_kutta_4,
    /// Semi-implicit (symplectic) Euler: v += dt a, then p += dt v and q = exp(dt w) (x) q with the
    /// new velocity. One evaluation per step; first order, but with bounded energy error for
    /// the undamped springs.
    semi_implicit_euler,
};

}  // namespace coopdyn
