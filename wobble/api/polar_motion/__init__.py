"""Observed polar motion with units: the IERS record, the Chandler wobble, and the model beside it.

>>> import wobble
>>> data = wobble.load_polar_motion(start="2000-01-01", end="2004-12-31")
>>> data["x_p"].attrs["units"], data.sizes["time"]
('milliarcsecond', 1827)
>>> data["time"].attrs["units"]
'days since 1858-11-17 00:00:00'

The pole is the complex number p = x_p - i y_p; with that sign the Chandler
wobble is a *prograde* circle (counter-clockwise seen from above the north
pole), at a positive frequency of the two-sided spectrum. The estimation is
:mod:`wobble.models.polar_motion`; the method and the numbers are in
``docs/polar-motion.md``. One module per idea:

* :mod:`.record`: the IERS record as a Dataset (:func:`load_polar_motion`);
* :mod:`.estimate`: one estimate with units (:func:`chandler_wobble`);
* :mod:`.analysis`: the whole analysis (:func:`polar_motion_analysis`);
* :mod:`.dataset`: its CF Datasets;
* :mod:`.excitation`: the geodetic excitation (:func:`geodetic_excitation`);
* :mod:`.forecast` and :mod:`.hindcast`: forecasts and their scores.
"""

from __future__ import annotations

import importlib

# Public name -> the submodule that defines it, imported on first use: `wobble polar-motion`
# never loads the forecasts' modules (SciPy's signal and linear-algebra solvers).
_WHERE = {
    "MJD_UNITS": "record",
    "load_polar_motion": "record",
    "published_chandler_period": "estimate",
    "ChandlerEstimate": "estimate",
    "chandler_wobble": "estimate",
    "QualityFactorEstimate": "analysis",
    "PolarMotionAnalysis": "analysis",
    "polar_motion_analysis": "analysis",
    "GeodeticExcitation": "excitation",
    "geodetic_excitation": "excitation",
    "PolarMotionForecast": "forecast",
    "forecast_polar_motion": "forecast",
    "PolarMotionHindcast": "hindcast",
    "hindcast_polar_motion": "hindcast",
}
__all__ = list(_WHERE)


def __getattr__(name: str):
    module = _WHERE.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(f"{__name__}.{module}"), name)


def __dir__():
    return sorted(set(globals()) | set(_WHERE))
