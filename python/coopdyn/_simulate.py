"""Simulator.run: steps a Simulator and returns its log as a dict of numpy arrays (docs/python.md,
"A first example")."""

import numpy as np

from . import _coopdyn as _c


def run(self, steps, inputs=None):
    """run(steps, inputs=None) -> dict of numpy arrays, one row per step taken.

    Calls step(inputs) `steps` times (stopping early when a step fails: check .status). Row k holds
    the step's start: "time" (steps,), the object's "position" (steps, 3), "orientation"
    (steps, 4) as [x, y, z, w], "twist" (steps, 6), and the evaluation there (Simulator.data):
    "object_acceleration" (steps, 6) and "wrenches" (steps, 6(N+1)) = [h_o; h_1; ...; h_N] of
    (18). The arrays are new and writable.
    """
    arms = self.data.arms
    log = {
        "time": np.empty(steps),
        "position": np.empty((steps, 3)),
        "orientation": np.empty((steps, 4)),
        "twist": np.empty((steps, 6)),
        "object_acceleration": np.empty((steps, 6)),
        "wrenches": np.empty((steps, 6 * (arms + 1))),
    }
    taken = 0
    for k in range(steps):
        start_time, state = self.time, self.state
        if not self.step(inputs).ok:
            break
        data = self.data
        log["time"][k] = start_time
        log["position"][k] = state.pose.position
        log["orientation"][k] = state.pose.orientation
        log["twist"][k] = state.twist
        log["object_acceleration"][k] = data.object_acceleration()
        log["wrenches"][k] = data.wrenches
        taken = k + 1
    return {name: column[:taken].copy() for name, column in log.items()}


def install():
    _c.Simulator.run = run
