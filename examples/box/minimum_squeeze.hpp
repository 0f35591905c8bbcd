// The measured minimum squeeze that still holds the box (docs/dual-arm-box.md, "The minimum
// squeeze"): what the MuJoCo plant really needs, next to the Coulomb estimate W / (2 mu_true), so
// that a user sees the safety margin the controller's conservative friction model and f_min keep.
//
// A probe is a short hold on the MuJoCo plant under the scenario's heaviest static load
// (static_load: the box with all its added mass and, if a person pushes, the push ramped in and
// held) with the controller's f_min set to the squeeze under test and its friction model opened
// up (mu, the torsion coefficient and the patch's half-size all probe_opening), and its objective
// the smallest squeeze |B z| instead of the smallest squeeze torque |J^T B z| (L(20)): none of
// the QP's friction rows binds, it asks for f_min and nothing more, and the palms press with that
// normal force. (With L(20) the QP prefers about 10 N at 0.7 kg: some squeeze lowers the torque
// the arms need to carry the box.) The box holds when it slips less than held_slip along
// the palms during the probe. Too little squeeze lets it slide away at once (a deficit of 0.1 N
// slides it centimetres within the probe), so the bisection's threshold is sharp; MuJoCo's
// creep (docs/dual-arm-box.md, "Creep") stays far below held_slip.
#pragma once

#include "box_experiment.hpp"
#include "mujoco_plant.hpp"

#include <algorithm>
#include <optional>

namespace box_example {

/// The controller's friction coefficient, torsion coefficient (m) and patch half-size (m) in a
/// probe: large enough that no friction row of the QP asks for more than f_min.
constexpr double probe_opening = 10.0;
/// Slip along the palms (m) below which a probe counts as held (the end-to-end tests' criterion).
constexpr double held_slip = 1e-3;
/// The bisection stops when the bracket is narrower than this (N).
constexpr double squeeze_resolution = 0.1;

/// The probe of `scenario` at `squeeze` newtons per palm (see the file comment): 2 s of hold, or
/// the push's ramp plus 3 s when a person pushes (the box moves down to its new equilibrium).
inline BoxScenario squeeze_probe(const BoxScenario& scenario, double squeeze)
{
    BoxScenario probe;
    probe.source = scenario.source;
    probe.name = scenario.name + "_minimum_squeeze";
    probe.experiment = Experiment::hold;
    probe.duration = 2.0;
    probe.box_mass = heaviest_box_mass(scenario);
    probe.plant_friction = scenario.plant_friction;
    probe.controller = scenario.controller;
    probe.controller.friction = probe_opening;
    probe.controller.torsional_friction = probe_opening;
    probe.controller.patch_half_size = probe_opening;
    probe.controller.objective.internal_weight = 0.0;
    probe.controller.objective.torque_weight = 0.0;
    probe.controller.objective.squeeze_weight = 1.0;
    probe.controller.minimum_normal_force = squeeze;
    if (scenario.push) {
        Push held = *scenario.push;
        held.start = 0.0;
        held.repeats = 1;
        probe.duration = held.ramp + 3.0;
        held.hold = probe.duration;
        held.period = 2.0 * probe.duration;
        probe.push = held;
    }
    return probe;
}

/// Whether the MuJoCo plant holds the box in the probe of `scenario` at `squeeze`.
inline bool squeeze_holds(const DualArmBoxModel& world, const Grasp& grasp, const BoxScenario& scenario, double squeeze)
{
    const BoxScenario probe = squeeze_probe(scenario, squeeze);
    MujocoPlant plant(world, probe.plant_friction);
    plant.set_box_mass(probe.box_mass);
    const ExperimentRun run = run_experiment(plant, probe, grasp);
    if (run.dropped) {
        return false;
    }
    double slip = 0.0;
    for (const TickLog& row : run.log) {
        slip = std::max({slip, row.slip[0], row.slip[1]});
    }
    return slip < held_slip;
}

struct MinimumSqueeze {
    double squeeze = 0.0;   ///< N per palm: the smallest squeeze found to hold (bracket's top)
    double coulomb = 0.0;   ///< static_load / (2 mu_true)
    int probes = 0;
};

/// Bisection on the squeeze between 0 (the box slides away) and a squeeze that holds (from
/// 2 x the Coulomb estimate + 10 N, doubled until it holds, at most four times). Empty when
/// even the largest squeeze tried does not hold.
inline std::optional<MinimumSqueeze> measure_minimum_squeeze(const DualArmBoxModel& world, const Grasp& grasp,
                                                             const BoxScenario& scenario)
{
    MinimumSqueeze result;
    result.coulomb = static_load(scenario) / (2.0 * scenario.plant_friction.sliding);
    double holding = 2.0 * result.coulomb + 10.0;
    for (int doubling = 0;; ++doubling) {
        ++result.probes;
        if (squeeze_holds(world, grasp, scenario, holding)) {
            break;
        }
        if (doubling == 4) {
            return std::nullopt;
        }
        holding *= 2.0;
    }
    double sliding = 0.0;
    while (holding - sliding > squeeze_resolution) {
        const double middle = 0.5 * (holding + sliding);
        ++result.probes;
        (squeeze_holds(world, grasp, scenario, middle) ? holding : sliding) = middle;
    }
    result.squeeze = holding;
    return result;
}

}  // namespace box_example
