"""wobble: planetary wobble and rigid-body rotation, with units.

The public API is re-exported here; everything takes and returns
:class:`astropy.units.Quantity` for dimensional values. See the README and
``docs/`` for the physics and examples.
"""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError as _PackageNotFoundError
from importlib.metadata import version as _version

from wobble._offline import configure_astropy_offline as _configure_astropy_offline

try:
    __version__ = _version("wobble")
except _PackageNotFoundError:  # a source tree that was never installed
    __version__ = "0.0.0+unknown"

# No network at run time: astropy must never try to download IERS tables.
_configure_astropy_offline()

from wobble.errors import FileFormatError, InputError, OutputExistsError, WobbleError  # noqa: E402
from wobble.io.netcdf import write_netcdf  # noqa: E402
from wobble.api.dataset import load, quantity  # noqa: E402  (registers the ds.wobble accessor)
from wobble.api.chandler import (  # noqa: E402
    BudgetStep,
    ChandlerBudget,
    FreeWobble,
    Planet,
    chandler_budget,
    chandler_dataset,
    euler_period,
    free_precession_rate,
    known_planets,
    load_planet,
    rigid_wobble,
)
from wobble.api.free import FreeRotation  # noqa: E402
from wobble.api.bodies import PrincipalAxes, RigidBody  # noqa: E402
from wobble.api.sweep import load_sweep, run_sweep, summarize_sweep, sweep  # noqa: E402
from wobble.api.polar_motion import (  # noqa: E402
    ChandlerEstimate,
    PolarMotionAnalysis,
    QualityFactorEstimate,
    chandler_wobble,
    load_polar_motion,
    polar_motion_analysis,
)
from wobble.api.top import HeavyTop  # noqa: E402
from wobble.api.engine import Torque  # noqa: E402
from wobble.api.scene import Scene, example_scenes, run, run_to_netcdf  # noqa: E402

__all__ = [
    "__version__",
    "WobbleError",
    "InputError",
    "FileFormatError",
    "OutputExistsError",
    "load",
    "quantity",
    "write_netcdf",
    "Planet",
    "BudgetStep",
    "ChandlerBudget",
    "FreeWobble",
    "known_planets",
    "load_planet",
    "chandler_budget",
    "chandler_dataset",
    "rigid_wobble",
    "free_precession_rate",
    "euler_period",
    "FreeRotation",
    "RigidBody",
    "PrincipalAxes",
    "sweep",
    "run_sweep",
    "load_sweep",
    "summarize_sweep",
    "load_polar_motion",
    "chandler_wobble",
    "polar_motion_analysis",
    "ChandlerEstimate",
    "PolarMotionAnalysis",
    "QualityFactorEstimate",
    "HeavyTop",
    "Torque",
    "Scene",
    "run",
    "run_to_netcdf",
    "example_scenes",
]
