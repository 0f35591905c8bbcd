"""The example programs' experiments as functions (docs/python.md, "The experiments").

``box`` runs the second paper's dual-arm box experiment (Lin et al. section IV; docs/dual-arm-box.md)
and ``beam`` the first paper's two-arm beam (Erhart & Hirche 2016 Section V; docs/two-arm-beam.md),
with the C++ code of the programs ``dual_arm_box`` and ``two_arm_beam`` (the GIL released while they
run). Each returns ``(log, summary)``: ``log`` a dict of numpy columns named as the programs' CSV
files (float64; the status columns as str), ``summary`` a dict (the box: the program's table row;
the beam: the identification table's columns and a few numbers). Every array owns its memory.

Needs the extension ``coopdyn._experiments``, built where MuJoCo and nlohmann-json are found.
"""

import importlib
import os
from typing import NamedTuple

try:
    _experiments = importlib.import_module(__package__ + "._experiments")
except ModuleNotFoundError as error:  # built without MuJoCo or nlohmann-json
    if error.name != __package__ + "._experiments":
        raise
    _experiments = None
    _import_error = error

SHIPPED_BOX_SCENARIOS = ("hold", "push", "add_mass", "circle")


class ExperimentResult(NamedTuple):
    log: dict
    summary: dict


def _extension():
    if _experiments is None:
        raise ImportError("coopdyn was built without its experiments (coopdyn._experiments needs MuJoCo and "
                          f"nlohmann-json at build time): {_import_error}")
    return _experiments


def _scenario_file(scenario, folder, scene=None):
    """A scenario's file: an existing path as given, else a shipped name in `folder` (or its `scene`)."""
    scenario = os.fspath(scenario)
    if os.path.isfile(scenario) or scenario.endswith(".json"):
        return scenario
    if scene is not None:
        folder = os.path.join(folder, scene)
    return os.path.join(folder, scenario + ".json")


def box(scenario, plant="mujoco", duration=None, seed=1, *, friction=None, scene=None, scenario_dir=None,
        minimum_squeeze=False, log_every=1):
    """Runs one dual-arm box scenario on one plant, as ``dual_arm_box --plant <plant>`` does.

    scenario: a shipped name ("hold", "push", "add_mass", "circle"; "ur5e_panda/hold" or
      scene="ur5e_panda" for a scene's), or the path of a scenario JSON file.
    plant: "mujoco" (friction contact) or "rigid" (welded palms).
    duration: simulated seconds (default: the scenario's); seed: the person's trembling hand.
    friction: the controller's friction coefficient (default: the scenario's), as --friction.
    scene: the shipped scene whose scenarios a name picks ("ur5e_panda", "three_arms").
    scenario_dir: the folder of shipped names (default: examples/box/scenarios of the source tree
      the module was built from).
    minimum_squeeze: also measure the least squeeze that holds the box (MuJoCo plant, LWR 4 pair
      only; about 1 s of wall time), summary["minimum_squeeze"]; else None.
    log_every: keep every n-th tick in the log (as --log-every); the summary uses every tick.

    Returns ExperimentResult(log, summary): log columns as in docs/dual-arm-box.md ("The CSV
    columns"), summary the program's table row (docs/dual-arm-box.md, "Output").
    """
    extension = _extension()
    folder = scenario_dir if scenario_dir is not None else os.path.join(extension.box_dir, "scenarios")
    file = _scenario_file(scenario, os.fspath(folder), scene)
    if duration is not None and not duration > 0:
        raise ValueError(f"duration: must be positive, got {duration}")
    if int(log_every) < 1:
        raise ValueError(f"log_every: must be at least 1, got {log_every}")
    log, summary = extension.box_run(file, plant, None if duration is None else float(duration), int(seed),
                                     None if friction is None else float(friction), bool(minimum_squeeze),
                                     int(log_every))
    return ExperimentResult(log, summary)


def beam(experiment="x", scenario="beam", duration=20.0, seed=1, *, excitation="multisine", force=0.0,
         torque=0.0, runs=4, noise=False, scenario_dir=None):
    """Runs one two-arm beam experiment, as ``two_arm_beam --experiment <experiment>`` does.

    experiment: "x" (translation along x, (56)-(57)), "rot_z" ((59)-(60)) or "se3" ((61)-(62)).
    scenario: a shipped name ("beam", "asymmetric_two_arms", "plate_three_arms") or a JSON file.
    duration: simulated seconds per run (at least 100 time steps); seed: excitation and noise.
    excitation: "multisine" or "push"; force, torque: amplitudes (0: the scenario's).
    runs: 4, 2 or 1 excitation runs combined for the identification (as --runs); noise: the
      sensor model (as --noise).
    scenario_dir: the folder of shipped names (default: examples/beam/scenarios of the source tree).

    Returns ExperimentResult(log, summary): log columns as in docs/two-arm-beam.md (the +u run),
    summary the identification table's columns (<scenario>_identification.csv) and
    simulated_seconds, warmup_seconds, cross_axis_motion, nominal_coupling.
    """
    extension = _extension()
    folder = scenario_dir if scenario_dir is not None else extension.beam_scenario_dir
    file = _scenario_file(scenario, os.fspath(folder))
    log, summary = extension.beam_run(file, experiment, float(duration), excitation, float(force), float(torque),
                                      int(seed), int(runs), bool(noise))
    return ExperimentResult(log, summary)
