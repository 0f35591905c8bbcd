/// \file
/// \brief Everything in coopdyn: the per-tick core (coopdyn/core.hpp), the analysis
/// (coopdyn/analysis.hpp) and the second paper's controller (coopdyn/control.hpp). A controller that only needs the per-tick parts compiles much faster
/// with coopdyn/core.hpp alone (README, "Headers").
#pragma once

#include "coopdyn/core.hpp"
#include "coopdyn/analysis.hpp"
#include "coopdyn/control.hpp"
