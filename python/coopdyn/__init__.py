"""coopdyn: dynamics and control of cooperative manipulation, from Python (docs/python.md).

The C++ library's functions and classes under their C++ names, on numpy arrays in the C++ API's
shapes: (6,) for a wrench or twist, (3, N) for grasp offsets, (6, 6N) for stacked inertias.
Erhart & Hirche 2016 (the model and its analysis) and Lin et al. (the projected inverse-dynamics
controller); the equation numbers in the docstrings are theirs (docs/conventions.md).
"""

from ._coopdyn import *  # noqa: F401,F403
from ._coopdyn import Error, InvalidArgument, InvalidModel  # noqa: F401
from . import _parameters, experiments  # noqa: F401

try:  # built where MuJoCo is found (docs/python.md, "The MuJoCo adapter")
    from ._mujoco import (InverseKinematicsOptions, InverseKinematicsResult,  # noqa: F401
                          InverseKinematicsStatus, MujocoArms, MujocoContactWrenches)
except ModuleNotFoundError as error:
    if error.name != __name__ + "._mujoco":
        raise

_parameters.install()

__version__ = "0.1.0"
