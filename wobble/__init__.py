"""wobble: planetary wobble and rigid-body rotation, with units.

The public API is re-exported here; everything takes and returns
:class:`astropy.units.Quantity` for dimensional values. See the README and
``docs/`` for the physics and examples.

Names are loaded on first use (SPEC 1, ``lazy_loader``): ``import wobble`` costs
a few milliseconds, and a script that only computes Chandler periods never
loads xarray, pandas, dask, matplotlib or Numba.
"""

from __future__ import annotations

import lazy_loader as _lazy

from wobble._offline import configure_when_astropy_loads as _configure_when_astropy_loads

# Public name -> the module that defines it (imported when the name is first used).
_PUBLIC = {
    "errors": ["WobbleError", "InputError", "FileFormatError", "OutputExistsError"],
    "io.netcdf": ["write_netcdf"],
    "api.dataset": ["load", "quantity"],
    "api.chandler": [
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
    ],
    "api.modes": [
        "HydrostaticFigure",
        "FreeMode",
        "NormalModes",
        "hydrostatic_figure",
        "normal_modes",
        "modes_dataset",
    ],
    "api.free": ["FreeRotation"],
    "api.bodies": ["RigidBody", "PrincipalAxes"],
    "api.sweep": ["sweep", "run_sweep", "load_sweep", "summarize_sweep"],
    "api.polar_motion": [
        "load_polar_motion",
        "chandler_wobble",
        "polar_motion_analysis",
        "ChandlerEstimate",
        "PolarMotionAnalysis",
        "QualityFactorEstimate",
        "geodetic_excitation",
        "GeodeticExcitation",
        "forecast_polar_motion",
        "PolarMotionForecast",
        "hindcast_polar_motion",
        "PolarMotionHindcast",
    ],
    "api.precession": [
        "PrecessionBudget",
        "PrincipalNutation",
        "precession_rate",
        "principal_nutation",
        "precession_dataset",
    ],
    "api.precession_measure": ["PrecessionMeasurement", "measure_precession"],
    "api.top": ["HeavyTop"],
    "api.engine": ["Torque"],
    "api.scene": ["Scene", "run", "run_to_netcdf", "example_scenes"],
    "api.examples": ["example_files", "example_path", "copy_example"],
    "api.inversion": [
        "invert",
        "Inversion",
        "injection_recovery",
        "Calibration",
        "inversion_setups",
        "load_inversion_setup",
    ],
}

_lazy_getattr, _lazy_dir, _names = _lazy.attach(__name__, submodules=["plot"], submod_attrs=_PUBLIC)
__all__ = ["__version__", *_names]


def __getattr__(name: str):
    if name == "__version__":  # importlib.metadata costs ~60 ms: read on first use
        global __version__
        from importlib.metadata import PackageNotFoundError, version

        try:
            __version__ = version("wobble")
        except PackageNotFoundError:  # a source tree that was never installed
            __version__ = "0.0.0+unknown"
        return __version__
    return _lazy_getattr(name)


def __dir__():
    return [*_lazy_dir(), "__version__"]


# No network at run time: astropy must never try to download IERS tables. Set in
# astropy's configuration now if astropy is loaded, else the moment it is imported;
# neither imports astropy's IERS machinery (~0.4 s).
_configure_when_astropy_loads()
