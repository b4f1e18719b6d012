"""The CF registry: every variable wobble writes, with its dimensions and metadata.

Dataset builders never spell ``units``/``long_name`` by hand: they name a
variable of a table here and pass the data,

>>> import numpy as np
>>> dims, data, attrs = variable("chandler", "model_period", np.array([431.5]))
>>> dims, attrs["units"], attrs["long_name"]
(('body',), 'day', 'modelled Chandler period')

so one name means one thing (dimensions, UDUNITS units, long name, CF
standard name where the CF table has one) in every file wobble writes, and a
reader's documentation (docs/netcdf.md) can be generated from one place.

A table is one kind of file (``chandler``, ``modes``, ...); :data:`COMMON`
holds the variables shared by several kinds (time, spin rate). A builder may
add ``comment``, ``references`` or flag attributes per call; it cannot change
the units, dimensions or names, which belong to the registry.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from wobble.errors import InputError

__all__ = [
    "Spec",
    "COMMON",
    "TABLES",
    "SIMULATION_TIME_UNITS",
    "MJD_UNITS",
    "spec",
    "attrs",
    "variable",
    "time_coordinate",
    "flag_attrs",
]

# CF time units for elapsed simulation time (the epoch is nominal: J2000.0).
SIMULATION_TIME_UNITS = "seconds since 2000-01-01 12:00:00"
# Modified Julian Date, the IERS's time axis.
MJD_UNITS = "days since 1858-11-17 00:00:00"


@dataclass(frozen=True)
class Spec:
    """How one variable is written.

    Attributes
    ----------
    dims : tuple of str
        Dimension names, in order.
    units : str
        UDUNITS-2 units (``day``, ``rad s-1``, ``1`` for dimensionless).
    long_name : str
        What the variable is, in words.
    standard_name : str or None
        The CF standard name, where the CF table has one.
    """

    dims: tuple[str, ...]
    units: str
    long_name: str
    standard_name: str | None = None

    def attrs(self, **extra) -> dict:
        """The variable's attributes, with ``extra`` (comment, references, flags) added."""
        out = {"units": self.units, "long_name": self.long_name}
        if self.standard_name:
            out["standard_name"] = self.standard_name
        fixed = set(out) & set(extra)
        if fixed:
            raise InputError("attributes", sorted(fixed), "extra attributes other than units, long_name, standard_name")
        out.update({k: v for k, v in extra.items() if v is not None})
        return out


# ---------------------------------------------------------------------------
# Shared by several kinds of file.
# ---------------------------------------------------------------------------
COMMON: dict[str, Spec] = {
    "spin_rate": Spec(("body",), "rad s-1", "sidereal spin rate"),
}

# ---------------------------------------------------------------------------
# One table per kind of file. Add a kind as a new table below and in TABLES.
# ---------------------------------------------------------------------------
CHANDLER: dict[str, Spec] = {
    "period": Spec(("body", "step"), "day", "Chandler wobble period after each model step"),
    "wobble_rate": Spec(("body", "step"), "rad s-1", "signed free wobble frequency (positive: prograde)"),
    "love_number_k2_effective": Spec(("body", "step"), "1", "effective degree-2 Love number k2 used by the step"),
    "applied": Spec(("body", "step"), "1", "whether the body's parameters support the step"),
    "model_period": Spec(("body",), "day", "modelled Chandler period"),
    "model_period_uncertainty": Spec(("body",), "day", "one-sigma uncertainty of the modelled period (linear propagation)"),
    "observed_period": Spec(("body",), "day", "observed Chandler period"),
    "observed_period_uncertainty": Spec(("body",), "day", "one-sigma uncertainty of the observed period"),
    "residual": Spec(("body",), "day", "modelled minus observed Chandler period"),
    "quality_factor": Spec(("body",), "1", "wobble quality factor implied by the out-of-phase Love number"),
    "secular_love_number": Spec(("body",), "1", "secular Love number k_s = 3G(C-A)/(a^5 Omega^2)"),
}

# Rotational normal modes of a layered planet (wobble modes).
MODES: dict[str, Spec] = {}

# Forced precession and nutation (wobble precession).
PRECESSION: dict[str, Spec] = {}

# Geodetic excitation of polar motion (wobble excitation).
EXCITATION: dict[str, Spec] = {
    "x_p": Spec(("time",), "milliarcsecond", "pole coordinate x_p (toward the Greenwich meridian)"),
    "y_p": Spec(("time",), "milliarcsecond", "pole coordinate y_p (toward 90 deg W longitude)"),
    "chi_1": Spec(("time",), "milliarcsecond", "geodetic excitation chi_1 (real part of chi, from the pole by the Liouville equation)"),
    "chi_2": Spec(("time",), "milliarcsecond", "geodetic excitation chi_2 (imaginary part of chi; chi = chi_1 + i chi_2)"),
    "x_p_round_trip": Spec(("time",), "milliarcsecond", "x_p rebuilt from the excitation (forward Liouville equation)"),
    "y_p_round_trip": Spec(("time",), "milliarcsecond", "y_p rebuilt from the excitation (forward Liouville equation)"),
    "chandler_band_chi": Spec(("time",), "milliarcsecond", "amplitude of the excitation in the prograde Chandler band"),
    "chandler_band_pole": Spec(("time",), "milliarcsecond", "amplitude of the pole in the prograde Chandler band"),
    "excitation_spectrum": Spec(("frequency",), "milliarcsecond", "two-sided amplitude spectrum of the excitation chi_1 + i chi_2"),
    "pole_spectrum": Spec(("frequency",), "milliarcsecond", "two-sided amplitude spectrum of the pole x_p - i y_p"),
    "frequency": Spec(("frequency",), "year-1", "frequency in cycles per Julian year (positive: prograde)"),
    "chandler_period": Spec((), "day", "Chandler period T_c of the complex frequency sigma_c"),
    "quality_factor": Spec((), "1", "quality factor Q of the Chandler wobble"),
    "round_trip_rms": Spec((), "milliarcsecond", "RMS distance between the record and the pole rebuilt from its excitation"),
}

# Polar-motion forecasts and hindcasts (wobble forecast).
FORECAST: dict[str, Spec] = {
    "lead_time": Spec(("lead",), "day", "lead time from the issue time", "forecast_period"),
    "issue_time": Spec(("issue",), "days since 1858-11-17 00:00:00", "issue time of the forecast (UTC)", "forecast_reference_time"),
    "x_p": Spec(("lead",), "milliarcsecond", "forecast of the pole coordinate x_p"),
    "y_p": Spec(("lead",), "milliarcsecond", "forecast of the pole coordinate y_p"),
    "x_p_bounds_68": Spec(("lead", "bounds"), "milliarcsecond", "68 % interval of the x_p forecast"),
    "y_p_bounds_68": Spec(("lead", "bounds"), "milliarcsecond", "68 % interval of the y_p forecast"),
    "x_p_bounds_95": Spec(("lead", "bounds"), "milliarcsecond", "95 % interval of the x_p forecast"),
    "y_p_bounds_95": Spec(("lead", "bounds"), "milliarcsecond", "95 % interval of the y_p forecast"),
    "x_p_forecast": Spec(("method", "issue", "lead"), "milliarcsecond", "hindcast of x_p"),
    "y_p_forecast": Spec(("method", "issue", "lead"), "milliarcsecond", "hindcast of y_p"),
    "x_p_sigma": Spec(("method", "issue", "lead"), "milliarcsecond", "stated one-sigma error of the x_p hindcast"),
    "y_p_sigma": Spec(("method", "issue", "lead"), "milliarcsecond", "stated one-sigma error of the y_p hindcast"),
    "x_p_observed": Spec(("issue", "lead"), "milliarcsecond", "x_p of the record at the forecast time"),
    "y_p_observed": Spec(("issue", "lead"), "milliarcsecond", "y_p of the record at the forecast time"),
    "mae_x": Spec(("method", "lead"), "milliarcsecond", "mean absolute error of x_p"),
    "mae_y": Spec(("method", "lead"), "milliarcsecond", "mean absolute error of y_p"),
    "rms_x": Spec(("method", "lead"), "milliarcsecond", "RMS error of x_p"),
    "rms_y": Spec(("method", "lead"), "milliarcsecond", "RMS error of y_p"),
    "mae_2d": Spec(("method", "lead"), "milliarcsecond", "mean absolute error of the 2-D pole |p - p_forecast|"),
    "rms_2d": Spec(("method", "lead"), "milliarcsecond", "RMS error of the 2-D pole"),
    "coverage_68": Spec(("method", "lead"), "1", "fraction of x_p and y_p outcomes inside the 68 % interval"),
    "coverage_95": Spec(("method", "lead"), "1", "fraction of x_p and y_p outcomes inside the 95 % interval"),
    "rms_2d_persistence": Spec(("lead",), "milliarcsecond", "RMS error of the 2-D pole of persistence (the last value used)"),
    "rms_2d_ls": Spec(("lead",), "milliarcsecond", "RMS error of the 2-D pole of the least-squares extrapolation alone"),
    "skill_persistence": Spec(("method", "lead"), "1", "skill against persistence, 1 - RMS_2d / RMS_2d(persistence)"),
    "skill_ls": Spec(("method", "lead"), "1", "skill against the least-squares extrapolation, 1 - RMS_2d / RMS_2d(LS)"),
    "latency": Spec((), "day", "publication delay assumed: the data used end this long before the issue time"),
}

TABLES: dict[str, Mapping[str, Spec]] = {
    "chandler": CHANDLER,
    "modes": MODES,
    "precession": PRECESSION,
    "excitation": EXCITATION,
    "forecast": FORECAST,
}


def spec(table: str, name: str) -> Spec:
    """The registered :class:`Spec` of variable ``name`` in ``table`` (or :data:`COMMON`)."""
    try:
        entries = TABLES[table]
    except KeyError:
        raise InputError("table", table, f"one of {', '.join(TABLES)}") from None
    found = entries.get(name) or COMMON.get(name)
    if found is None:
        raise InputError("variable", f"{table}.{name}", "a variable registered in wobble.io.cf")
    return found


def attrs(table: str, name: str, **extra) -> dict:
    """The CF attributes of ``name`` in ``table``, with ``extra`` added."""
    return spec(table, name).attrs(**extra)


def variable(table: str, name: str, data, **extra) -> tuple:
    """``(dims, data, attrs)`` for the :class:`xarray.Dataset` constructor."""
    s = spec(table, name)
    return s.dims, data, s.attrs(**extra)


def time_coordinate(values, units: str = SIMULATION_TIME_UNITS, *, long_name: str = "time", **extra) -> tuple:
    """``(dims, values, attrs)`` of a CF time coordinate (float64 numbers since an epoch).

    Times stay numbers so that round trips are exact; ``units`` is
    ``"<unit> since <epoch>"`` (:data:`SIMULATION_TIME_UNITS`, :data:`MJD_UNITS`).
    """
    out = {"units": units, "standard_name": "time", "long_name": long_name, "axis": "T", "calendar": "standard"}
    out.update({k: v for k, v in extra.items() if v is not None})
    return ("time",), values, out


def flag_attrs(meanings: Mapping[int, str]) -> dict:
    """``flag_values``/``flag_meanings`` of an integer code variable (CF sec. 3.5)."""
    import numpy as np

    codes = sorted(meanings)
    words = [meanings[c].strip().replace(" ", "_") for c in codes]
    return {"flag_values": np.array(codes, dtype=np.int8), "flag_meanings": " ".join(words)}
