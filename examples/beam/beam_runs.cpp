// The instances beam_runs.hpp declares: the beam's experiments, compiled once for two_arm_beam and
// the Python module (library beam_example_runs).
#include "beam_runs.hpp"

namespace beam_example {

template ExperimentResult run_experiment<coopdyn::ImpedanceModel<2>>(const Scenario&, const coopdyn::ImpedanceModel<2>&,
                                                                    const ExperimentSpec&, const RunOptions&,
                                                                    Progress&, unsigned long long);
template ExperimentResult run_experiment<coopdyn::ImpedanceModel<3>>(const Scenario&, const coopdyn::ImpedanceModel<3>&,
                                                                    const ExperimentSpec&, const RunOptions&,
                                                                    Progress&, unsigned long long);
template ExperimentResult run_experiment<coopdyn::ImpedanceModelX>(const Scenario&, const coopdyn::ImpedanceModelX&,
                                                                  const ExperimentSpec&, const RunOptions&, Progress&,
                                                                  unsigned long long);

}  // namespace beam_example
