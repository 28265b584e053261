"""planar: planar mechanism kinematics with one generic constraint solver.

Describe a mechanism as bodies joined by revolute, prismatic, slot, gear, rack-and-pinion and
rolling joints; drive it; sweep the inputs. Positions come from a batched Newton solver,
velocities and accelerations from linear solves with the same Jacobian.
"""

from importlib.metadata import PackageNotFoundError, version as _dist_version

from planar.errors import (AssemblyError, ConnectivityError, FileFormatError, IndeterminateWarning, InputError,
                           MobilityError, ModelError, PlanarError, RedundancyError, SynthesisError, WriteError)
from planar.designs import DesignSweep, Vary, sweep_designs
from planar.dimensions import Dyad
from planar.mass import bar, disc, plate
from planar.model import Body, Mechanism, Model
from planar.results import Status, Sweep


def _version():
    # the installed distribution's version; a source tree that is not installed has none
    try:
        return _dist_version("planar-kinematics")
    except PackageNotFoundError:
        return "0+unknown"


__version__: str = _version()

__all__ = [
    "Mechanism", "Model", "Body", "Dyad", "Sweep", "Status", "sweep_designs", "DesignSweep", "Vary", "bar", "disc",
    "plate",
    "PlanarError", "ModelError", "ConnectivityError", "MobilityError", "RedundancyError",
    "AssemblyError", "InputError", "FileFormatError", "SynthesisError", "WriteError", "IndeterminateWarning",
]
