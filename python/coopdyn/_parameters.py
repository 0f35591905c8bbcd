"""__repr__, __eq__ and pickling for coopdyn's parameter objects (plain data with settable fields).

Each class lists its fields; the state of an object is the dict of those fields, so an object
prints as ClassName(field=value, ...), compares field by field (arrays with numpy.array_equal)
and pickles by rebuilding it from the default constructor and setting the fields.
"""

import numpy as np

from . import _coopdyn as _c

FIELDS = {
    _c.Pose: ("position", "orientation"),
    _c.RigidBodyState: ("pose", "twist"),
    _c.ContactFriction: ("friction_coefficient", "torsional_coefficient", "patch_half_length_x",
                         "patch_half_length_y", "minimum_normal_force", "pyramid_edges"),
    _c.ContactPoint: ("frame", "friction"),
    _c.SqueezeObjective: ("internal_weight", "moment_weight", "torque_weight", "squeeze_weight"),
    _c.ContactQpOptions: ("warm_start", "iteration_limit", "fallback_weight"),
    _c.FaultOptions: ("tick_period", "prediction_limit", "slip_distance_threshold", "slip_angle_threshold",
                      "slip_squeeze_factor"),
    _c.RigidObject: ("mass", "inertia_body"),
    _c.ImpedanceEndEffector: ("mass", "rotational_inertia", "translational_damping", "rotational_damping",
                              "translational_stiffness", "rotational_stiffness"),
    _c.Arm: ("end_effector", "grasp_body"),
    _c.ResolvedAccelerationEndEffector: ("apparent_inertia", "derivative_gain", "proportional_gain"),
    _c.ResolvedAccelerationArm: ("end_effector", "grasp_body"),
    _c.ControllerParameters: ("joints", "contacts", "stiffness", "damping", "posture_stiffness",
                              "posture_damping", "objective", "qp", "torque_limits", "torque_rate_limits", "faults",
                              "check_contact_normals", "joint_names"),
}


def _state(obj):
    return {name: getattr(obj, name) for name in FIELDS[type(obj)]}


def _equal(a, b):
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return np.shape(a) == np.shape(b) and bool(np.array_equal(a, b))
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        return len(a) == len(b) and all(_equal(x, y) for x, y in zip(a, b))
    return a == b


def _eq(self, other):
    if type(self) is not type(other):
        return NotImplemented
    mine, theirs = _state(self), _state(other)
    return all(_equal(mine[name], theirs[name]) for name in mine)


def _repr_value(value):
    if isinstance(value, np.ndarray):
        return "array(" + np.array2string(value, separator=", ", threshold=64) + ")"
    if isinstance(value, list):
        return "[" + ", ".join(_repr_value(v) for v in value) + "]"
    return repr(value)


def _repr(self):
    fields = ", ".join(f"{name}={_repr_value(value)}" for name, value in _state(self).items())
    return f"{type(self).__name__}({fields})"


def _rebuild(cls, state):
    obj = cls()
    for name, value in state.items():
        setattr(obj, name, value)
    return obj


def _reduce(self):
    return (_rebuild, (type(self), _state(self)))


def install():
    for cls in FIELDS:
        cls.__eq__ = _eq
        cls.__ne__ = lambda self, other: not (_eq(self, other) is True)
        cls.__hash__ = None
        cls.__repr__ = _repr
        cls.__reduce__ = _reduce
