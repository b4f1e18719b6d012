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
MODES: dict[str, Spec] = {
    "period": Spec(("body", "mode"), "day", "signed period of the free mode (negative: retrograde)"),
    "period_uncertainty": Spec(("body", "mode"), "day", "one-sigma uncertainty of the period (linear propagation)"),
    "rate": Spec(("body", "mode"), "rad s-1", "signed frequency of the free mode (positive: prograde)"),
    "observed_period": Spec(("body", "mode"), "day", "observed signed period of the mode"),
    "observed_period_uncertainty": Spec(("body", "mode"), "day", "one-sigma uncertainty of the observed period"),
    "love_number_k2": Spec(("body", "mode"), "1", "degree-2 Love number k2 at the mode's frequency in the planet's frame"),
    "sense": Spec(("body", "mode"), "1", "sense of the mode relative to the spin"),
    "core_flattening_hydrostatic": Spec(("body",), "1", "hydrostatic dynamical ellipticity of the liquid core (C_f - A_f)/A_f"),
    "core_flattening_required": Spec(("body",), "1", "dynamical ellipticity of the liquid core that the observed FCN period requires"),
    "core_flattening_required_uncertainty": Spec(("body",), "1", "one-sigma uncertainty of the required core dynamical ellipticity"),
    "core_flattening_excess": Spec(("body",), "percent", "required over hydrostatic core dynamical ellipticity, minus one"),
    "fcn_period_required": Spec(("body",), "day", "FCN period in space with the required core ellipticity put back"),
    "chandler_budget_period": Spec(("body",), "day", "Chandler period of the first-order budget"),
    "chandler_period_coupling_off": Spec(("body",), "day", "Chandler period with the core-mantle coupling off"),
    "surface_flattening_hydrostatic": Spec(("body",), "1", "hydrostatic surface flattening from Clairaut's equation"),
    "dynamical_flattening_hydrostatic": Spec(("body",), "1", "hydrostatic dynamical flattening H = (C - A)/C"),
    # The hydrostatic figure of one body (HydrostaticFigure.to_dataset).
    "radius": Spec(("radius",), "km", "radius of the level surface (its mean radius)"),
    "level_surface_flattening": Spec(("radius",), "1", "flattening of the hydrostatic level surface (Clairaut's equation)"),
    "radau_parameter": Spec(("radius",), "1", "Radau's eta = r d(ln flattening)/dr"),
    "density": Spec(("radius",), "kg m-3", "density of the profile (the layer above at an interface)"),
}

# Forced precession and nutation (wobble precession).
PRECESSION: dict[str, Spec] = {}

# Geodetic excitation of polar motion (wobble excitation).
EXCITATION: dict[str, Spec] = {}

# Polar-motion forecasts and hindcasts (wobble forecast).
FORECAST: dict[str, Spec] = {}

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
