// The beam's experiments, compiled once (beam_runs.cpp, the library beam_example_runs) for the
// program two_arm_beam and the Python module's coopdyn.experiments.beam (python/src/experiments/):
// explicit instantiation declarations of run_experiment on the Models of 2, 3 and any number of
// arms, so that the files that include this header call those instances instead of compiling
// them again (docs/performance.md, "Compile time and CI"; docs/python.md, "Compile time"). A file
// that includes this header links beam_example_runs.
#pragma once

#include "beam_experiment.hpp"

namespace beam_example {

extern template ExperimentResult run_experiment<coopdyn::ImpedanceModel<2>>(
    const Scenario&, const coopdyn::ImpedanceModel<2>&, const ExperimentSpec&, const RunOptions&, Progress&,
    unsigned long long);
extern template ExperimentResult run_experiment<coopdyn::ImpedanceModel<3>>(
    const Scenario&, const coopdyn::ImpedanceModel<3>&, const ExperimentSpec&, const RunOptions&, Progress&,
    unsigned long long);
extern template ExperimentResult run_experiment<coopdyn::ImpedanceModelX>(
    const Scenario&, const coopdyn::ImpedanceModelX&, const ExperimentSpec&, const RunOptions&, Progress&,
    unsigned long long);

/// two_arm_beam's run on the Model of the scenario's arm count (ImpedanceModel<2>, <3>, or
/// ImpedanceModelX), without a progress line: for callers that build no Model themselves (the
/// Python module), compiled in beam_runs.cpp.
ExperimentResult run_beam_experiment(const Scenario& scenario, const ExperimentSpec& spec, const RunOptions& options,
                                     unsigned long long seed_offset);

}  // namespace beam_example
