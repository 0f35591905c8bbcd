/// \file
/// \brief Everything in coopdyn: the per-tick core (coopdyn/core.hpp) and the analysis
/// (coopdyn/analysis.hpp). A controller that only needs the per-tick parts compiles much faster
/// with coopdyn/core.hpp alone (README, "Headers").
#pragma once

#include "coopdyn/core.hpp"
#include "coopdyn/analysis.hpp"
