// Includes all of coopdyn for the example programs.
//
// GCC 12 reports a false -Warray-bounds inside coopdyn/analysis/identification.hpp (the
// Levenberg-Marquardt update `candidate.head(n) += step` on a fixed 5-vector, once inlined into a
// large translation unit at -O2/-O3). The warning is silenced for the library's headers only, and
// only for GCC 12; the example's own code keeps every warning.
#pragma once

#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ == 12
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Warray-bounds"
#endif
#include <coopdyn/coopdyn.hpp>
#include <coopdyn/analysis/identification.hpp>
#if defined(__GNUC__) && !defined(__clang__) && __GNUC__ == 12
#pragma GCC diagnostic pop
#endif
