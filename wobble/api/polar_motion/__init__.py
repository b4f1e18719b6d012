"""Observed polar motion with units: the IERS record, the Chandler wobble, and the model beside it.

>>> import wobble
>>> data = wobble.load_polar_motion(start="2000-01-01", end="2004-12-31")
>>> data["x_p"].attrs["units"], data.sizes["time"]
('arcsec', 1827)
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

from wobble.api.polar_motion.analysis import PolarMotionAnalysis, QualityFactorEstimate, polar_motion_analysis
from wobble.api.polar_motion.estimate import ChandlerEstimate, chandler_wobble, published_chandler_period
from wobble.api.polar_motion.excitation import GeodeticExcitation, geodetic_excitation
from wobble.api.polar_motion.forecast import PolarMotionForecast, forecast_polar_motion
from wobble.api.polar_motion.hindcast import PolarMotionHindcast, hindcast_polar_motion
from wobble.api.polar_motion.record import MJD_UNITS, load_polar_motion

__all__ = [
    "MJD_UNITS",
    "published_chandler_period",
    "ChandlerEstimate",
    "QualityFactorEstimate",
    "PolarMotionAnalysis",
    "load_polar_motion",
    "chandler_wobble",
    "polar_motion_analysis",
    "GeodeticExcitation",
    "geodetic_excitation",
    "PolarMotionForecast",
    "forecast_polar_motion",
    "PolarMotionHindcast",
    "hindcast_polar_motion",
]
