/// \file
/// \brief Spatial inertias: SpatialInertia (a rigid body's, or any diag(m I3, J) seen from
/// another point) and ArticulatedInertia (a general symmetric positive definite 6x6, such as an
/// arm's task-space inertia Lambda_i of (21)), with the operations the cooperative model is built
/// from: the shift G_i M_i G_i^T of (31), sums, rotation into {w} (9), and a structured solve.
///
/// Both act on motions [v; w] and give forces [f; t] (docs/conventions.md), torques about the
/// reference point. Fixed-size, Scalar-generic, allocation-free.
#pragma once

#include "coopdyn/spatial/articulated_inertia.hpp"
#include "coopdyn/spatial/rigid_body_inertia.hpp"
