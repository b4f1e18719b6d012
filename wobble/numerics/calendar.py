"""The day and the years wobble counts time in, in SI seconds.

One definition for every layer: the models and the interfaces had each written ``365.25 * 86400``
(or their own ``_YEAR``) for the Julian year, and the polar-motion record its tropical year.
"""

from __future__ import annotations

__all__ = ["DAY", "JULIAN_YEAR", "TROPICAL_YEAR", "MJD_J2000"]

#: The day of 86400 SI seconds (the IERS day, astropy's ``u.day``).
DAY = 86400.0

#: The Julian year, 365.25 days (astropy's ``u.yr``; the year of Julian centuries and of "per year" rates).
JULIAN_YEAR = 365.25 * DAY

#: The mean tropical year, 365.24219 days: the period of the seasons, so of the seasonal forcing of the
#: annual wobble.
TROPICAL_YEAR = 365.24219 * DAY

#: The Modified Julian Date of J2000.0 (2000-01-01 12:00 TT), where decimal years count from 2000.0.
MJD_J2000 = 51544.5
