/// \file
/// \brief The projected inverse-dynamics controller of the second paper (Lin et al.) and its
/// kernels: projected dynamics, contact-wrench bias, friction rows, the QP solver, the controller
/// Model/Data and its tick (docs/control.md). Independent of the first paper's Model/Data.
#pragma once

#include "coopdyn/control/contact_wrenches.hpp"
#include "coopdyn/control/controller.hpp"
#include "coopdyn/control/controller_model.hpp"
#include "coopdyn/control/controller_status.hpp"
#include "coopdyn/control/friction.hpp"
#include "coopdyn/control/projected_dynamics.hpp"
#include "coopdyn/model/grasp_jacobians.hpp"
#include "coopdyn/model/internal_wrench_basis.hpp"
#include "coopdyn/numerics/qp_solver.hpp"
