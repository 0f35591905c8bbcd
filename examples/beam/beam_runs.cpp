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

ExperimentResult run_beam_experiment(const Scenario& scenario, const ExperimentSpec& spec, const RunOptions& options,
                                     unsigned long long seed_offset)
{
    Progress progress(false);
    switch (scenario.arm_count()) {
    case 2: {
        const coopdyn::ImpedanceModel<2> model(scenario.object, scenario.arms, scenario.gravity);
        return run_experiment(scenario, model, spec, options, progress, seed_offset);
    }
    case 3: {
        const coopdyn::ImpedanceModel<3> model(scenario.object, scenario.arms, scenario.gravity);
        return run_experiment(scenario, model, spec, options, progress, seed_offset);
    }
    default: {
        const coopdyn::ImpedanceModelX model(scenario.object, scenario.arms, scenario.gravity);
        return run_experiment(scenario, model, spec, options, progress, seed_offset);
    }
    }
}

}  // namespace beam_example
