/// \file
/// \brief Deprecated (kept for one release): the QP solver moved to
/// `coopdyn/numerics/qp_solver.hpp` (coopdyn::solve_qp, QpSolver, QpStatus, unchanged);
/// docs/qp_solver.md. This header only includes it.
#pragma once

#include "coopdyn/numerics/qp_solver.hpp"
