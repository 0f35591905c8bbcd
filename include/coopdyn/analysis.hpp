/// \file
/// \brief The offline analysis of coopdyn: internal/external wrenches, apparent impedance,
/// stability, synthesis, identification and the numerics they use (matrix exponential,
/// discretisation, NNLS, Levenberg-Marquardt). Includes the core (coopdyn/core.hpp).
#pragma once

#include "coopdyn/core.hpp"
#include "coopdyn/analysis/apparent_impedance.hpp"
#include "coopdyn/analysis/equation_error.hpp"
#include "coopdyn/analysis/identification.hpp"
#include "coopdyn/analysis/impedance_discretization.hpp"
#include "coopdyn/analysis/impedance_synthesis.hpp"
#include "coopdyn/analysis/internal_wrenches.hpp"
#include "coopdyn/analysis/stability.hpp"
#include "coopdyn/numerics/levenberg_marquardt.hpp"
#include "coopdyn/numerics/linear_discretization.hpp"
#include "coopdyn/numerics/matrix_exponential.hpp"
#include "coopdyn/numerics/non_negative_least_squares.hpp"
