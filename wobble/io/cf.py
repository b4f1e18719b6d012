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

import re
from collections.abc import Mapping
from dataclasses import dataclass

from wobble.errors import InputError
from wobble.models.vocabulary import BODY_AXES, INERTIAL_AXES, QUATERNION_COMPONENTS

__all__ = [
    "Spec",
    "COMMON",
    "LABELS",
    "TABLES",
    "SIMULATION_TIME_UNITS",
    "MJD_UNITS",
    "spec",
    "attrs",
    "variable",
    "time_coordinate",
    "CF_DECODABLE_SECONDS",
    "label_coordinate",
    "with_member",
    "flag_attrs",
    "udunits",
    "INT64_MAX",
    "INT64_ALLOWED",
]

# The largest integer a file holds in an attribute or a coordinate (netCDF's int64): seeds are
# recorded as attributes and member indices as a coordinate, so neither may exceed it.
INT64_MAX = 2**63 - 1
INT64_ALLOWED = "up to 2**63 - 1 (the file records it as a 64-bit integer)"

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

#: String-labelled dimensions: (labels, long name). Stored as label variables in files.
LABELS: dict[str, tuple[tuple[str, ...], str]] = {
    "axis": (BODY_AXES, "body axis (the body frame the moments were given in)"),
    "inertial_axis": (INERTIAL_AXES, "inertial axis"),
    "component": (QUATERNION_COMPONENTS, "quaternion component, scalar first"),
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
    "model_period_uncertainty": Spec(
        ("body",),
        "day",
        "one-sigma uncertainty of the modelled period (standard deviation over Monte Carlo draws of the inputs)",
    ),
    "model_period_uncertainty_linear": Spec(
        ("body",), "day", "one-sigma uncertainty of the modelled period (first-order, linear propagation)"
    ),
    "observed_period": Spec(("body",), "day", "observed Chandler period"),
    "observed_period_uncertainty": Spec(("body",), "day", "one-sigma uncertainty of the observed period"),
    "residual": Spec(("body",), "day", "modelled minus observed Chandler period"),
    "quality_factor": Spec(("body",), "1", "wobble quality factor implied by the out-of-phase Love number"),
    "secular_love_number": Spec(("body",), "1", "secular Love number k_s = 3G(C-A)/(a^5 Omega^2)"),
}

# Torque-free rotation, exact (wobble free, FreeRotation.to_dataset).
FREE: dict[str, Spec] = {
    "omega": Spec(("time", "axis"), "rad s-1", "angular velocity in the body (principal-axis) frame"),
    "angular_momentum": Spec(
        ("inertial_axis",), "kg m2 s-1", "angular momentum in the inertial frame (the body frame at t = 0), constant"
    ),
    "attitude": Spec(
        ("time", "component"), "1", "unit quaternion (w, x, y, z) rotating body vectors into the inertial frame"
    ),
    "kinetic_energy": Spec(("time",), "J", "kinetic energy from omega(t)"),
    "kinetic_energy_drift": Spec(("time",), "J", "kinetic energy minus its initial value"),
    "angular_momentum_magnitude": Spec(("time",), "kg m2 s-1", "magnitude of the angular momentum from omega(t)"),
    "angular_momentum_magnitude_drift": Spec(
        ("time",), "kg m2 s-1", "magnitude of the angular momentum minus its initial value"
    ),
    "moment_of_inertia": Spec(("axis",), "kg m2", "principal moment of inertia"),
}

# The outputs of a scene run (wobble run, wobble.run): a "member" dimension follows
# "time" for ensembles (with_member).
SCENE: dict[str, Spec] = {
    "omega": Spec(("time", "axis"), "rad s-1", "angular velocity in the body frame"),
    "attitude": Spec(
        ("time", "component"), "1", "unit quaternion (w, x, y, z) rotating body vectors into the inertial frame"
    ),
    "angular_momentum": Spec(("time", "inertial_axis"), "kg m2 s-1", "angular momentum in the inertial frame"),
    "angular_momentum_magnitude": Spec(("time",), "kg m2 s-1", "magnitude of the angular momentum"),
    "kinetic_energy": Spec(("time",), "J", "rotational kinetic energy"),
    "potential_energy": Spec(("time",), "J", "potential energy of the torques (gravity, gravity gradient, magnetic)"),
    "total_energy": Spec(("time",), "J", "kinetic plus potential energy"),
    "axis_direction": Spec(("time", "inertial_axis"), "1", "direction of body axis 3 in the inertial frame"),
    "tilt": Spec(("time",), "rad", "angle between body axis 3 and the inertial z axis"),
    "wobble_angle": Spec(("time",), "rad", "angle between the angular velocity and body axis 3"),
    "mean_precession_rate": Spec(
        ("time",),
        "rad s-1",
        "mean precession rate of the node of the body's equator on the "
        "inertial x-y plane over the run (negative: retrograde), first-order averaged model",
    ),
}

# The heavy symmetric top, exact (wobble top -o, HeavyTop.to_dataset).
TOP: dict[str, Spec] = {
    "theta": Spec(("time",), "rad", "nutation angle theta: tilt of the symmetry axis from the upward vertical"),
    "phi": Spec(("time",), "rad", "precession angle phi (wrapped to [-pi, pi])"),
    "psi": Spec(("time",), "rad", "spin angle psi (wrapped to [-pi, pi])"),
    "thetadot": Spec(("time",), "rad s-1", "nutation rate dtheta/dt"),
    "phidot": Spec(("time",), "rad s-1", "precession rate dphi/dt"),
    "psidot": Spec(
        ("time",), "rad s-1", "spin-angle rate dpsi/dt (the axial spin is omega3 = dpsi/dt + dphi/dt cos theta)"
    ),
    "omega": Spec(("time", "axis"), "rad s-1", "angular velocity in the body frame (axis 3 = symmetry axis)"),
    "attitude": Spec(
        ("time", "component"), "1", "unit quaternion (w, x, y, z) rotating body vectors into the inertial frame"
    ),
    "symmetry_axis": Spec(
        ("time", "inertial_axis"),
        "1",
        "unit vector of the symmetry axis in the inertial frame (Z up): its trace on the unit sphere",
    ),
    "energy": Spec(("time",), "J", "total energy recomputed from the motion"),
    "energy_drift": Spec(("time",), "J", "total energy minus its initial value"),
    "p_phi": Spec(("time",), "kg m2 s-1", "vertical angular momentum p_phi recomputed from the motion"),
    "p_phi_drift": Spec(("time",), "kg m2 s-1", "p_phi minus its initial value"),
    "p_psi": Spec(("time",), "kg m2 s-1", "axial angular momentum p_psi recomputed from the motion"),
    "p_psi_drift": Spec(("time",), "kg m2 s-1", "p_psi minus its initial value"),
}

# A rigid body's inertia (wobble inertia -o, RigidBody.to_dataset).
BODIES: dict[str, Spec] = {
    "tensor": Spec(("row", "column"), "kg m2", "inertia tensor about the reference point, input-frame axes"),
    "principal_moments": Spec(
        ("principal",), "kg m2", "principal moments of inertia about the reference point, ascending"
    ),
    "principal_axes": Spec(
        ("principal", "component"), "1", "principal axis unit vectors (one per row) in input-frame components"
    ),
    "principal_moment_differences": Spec(("pair",), "kg m2", "differences of principal moments I2-I1, I3-I2, I3-I1"),
    "center_of_mass": Spec(("component",), "m", "centre of mass, input frame"),
    "reference_point": Spec(("component",), "m", "point the inertia tensor is taken about, input frame"),
    "mass": Spec((), "kg", "total mass"),
}

# Rotational normal modes of a layered planet (wobble modes).
MODES: dict[str, Spec] = {
    "period": Spec(("body", "mode"), "day", "signed period of the free mode (negative: retrograde)"),
    "period_uncertainty": Spec(("body", "mode"), "day", "one-sigma uncertainty of the period (linear propagation)"),
    "rate": Spec(("body", "mode"), "rad s-1", "signed frequency of the free mode (positive: prograde)"),
    "observed_period": Spec(("body", "mode"), "day", "observed signed period of the mode"),
    "observed_period_uncertainty": Spec(("body", "mode"), "day", "one-sigma uncertainty of the observed period"),
    "love_number_k2": Spec(
        ("body", "mode"), "1", "degree-2 Love number k2 at the mode's frequency in the planet's frame"
    ),
    "sense": Spec(("body", "mode"), "1", "sense of the mode relative to the spin"),
    "core_flattening_hydrostatic": Spec(
        ("body",), "1", "hydrostatic dynamical ellipticity of the liquid core (C_f - A_f)/A_f"
    ),
    "core_flattening_hydrostatic_uncertainty": Spec(
        ("body",), "1", "one-sigma uncertainty of the hydrostatic core dynamical ellipticity (0 for a fixed profile)"
    ),
    "core_flattening_required": Spec(
        ("body",), "1", "dynamical ellipticity of the liquid core that the observed FCN period requires"
    ),
    "core_flattening_required_uncertainty": Spec(
        ("body",), "1", "one-sigma uncertainty of the required core dynamical ellipticity"
    ),
    "core_flattening_excess": Spec(
        ("body",), "percent", "required over hydrostatic core dynamical ellipticity, minus one"
    ),
    "core_flattening_excess_uncertainty": Spec(
        ("body",), "percent", "one-sigma uncertainty of the core ellipticity excess (both ellipticities propagated)"
    ),
    "fcn_period_required": Spec(("body",), "day", "FCN period in space with the required core ellipticity put back"),
    "chandler_budget_period": Spec(("body",), "day", "Chandler period of the first-order budget"),
    "chandler_period_coupling_off": Spec(("body",), "day", "Chandler period with the core-mantle coupling off"),
    "surface_flattening_hydrostatic": Spec(("body",), "1", "hydrostatic surface flattening from Clairaut's equation"),
    "dynamical_flattening_hydrostatic": Spec(("body",), "1", "hydrostatic dynamical flattening H = (C - A)/C"),
    # The hydrostatic figure of one body (HydrostaticFigure.to_dataset).
    "radius": Spec(("radius",), "km", "radius of the level surface (its mean radius)"),
    "level_surface_flattening": Spec(
        ("radius",), "1", "flattening of the hydrostatic level surface (Clairaut's equation)"
    ),
    "radau_parameter": Spec(("radius",), "1", "Radau's eta = r d(ln flattening)/dr"),
    "density": Spec(("radius",), "kg m-3", "density of the profile (the layer above at an interface)"),
}

# Forced precession and nutation (wobble precession). Rates are of the node
# longitude of the equator on the orbit plane, eastward (negative: retrograde).
PRECESSION: dict[str, Spec] = {
    "term_rate": Spec(("body", "term"), "rad s-1", "contribution of each term to the precession rate"),
    "first_order_rate": Spec(("body",), "rad s-1", "first-order tidal precession rate of the spin axis"),
    "planetary_rate": Spec(("body",), "rad s-1", "the planets' share of the first-order rate (their direct torque)"),
    "precession_rate": Spec(("body",), "rad s-1", "modelled precession rate, defined as the observed one"),
    "precession_rate_uncertainty": Spec(
        ("body",), "rad s-1", "one-sigma uncertainty of the modelled precession rate (linear propagation)"
    ),
    "observed_precession_rate": Spec(("body",), "rad s-1", "observed precession rate"),
    "observed_precession_rate_uncertainty": Spec(
        ("body",), "rad s-1", "one-sigma uncertainty of the observed precession rate"
    ),
    "nutation_longitude": Spec(
        ("body",), "rad", "amplitude of the principal nutation in longitude (coefficient of sin Omega, IAU sign)"
    ),
    "nutation_obliquity": Spec(
        ("body",), "rad", "amplitude of the principal nutation in obliquity (coefficient of cos Omega)"
    ),
}

# Geodetic excitation of polar motion (wobble excitation).
EXCITATION: dict[str, Spec] = {
    "x_p": Spec(("time",), "milliarcsecond", "pole coordinate x_p (toward the Greenwich meridian)"),
    "y_p": Spec(("time",), "milliarcsecond", "pole coordinate y_p (toward 90 deg W longitude)"),
    "chi_1": Spec(
        ("time",),
        "milliarcsecond",
        "geodetic excitation chi_1 (real part of chi, from the pole by the Liouville equation)",
    ),
    "chi_2": Spec(
        ("time",), "milliarcsecond", "geodetic excitation chi_2 (imaginary part of chi; chi = chi_1 + i chi_2)"
    ),
    "x_p_round_trip": Spec(("time",), "milliarcsecond", "x_p rebuilt from the excitation (forward Liouville equation)"),
    "y_p_round_trip": Spec(("time",), "milliarcsecond", "y_p rebuilt from the excitation (forward Liouville equation)"),
    "chandler_band_chi": Spec(("time",), "milliarcsecond", "amplitude of the excitation in the prograde Chandler band"),
    "chandler_band_pole": Spec(("time",), "milliarcsecond", "amplitude of the pole in the prograde Chandler band"),
    "excitation_spectrum": Spec(
        ("frequency",), "milliarcsecond", "two-sided amplitude spectrum of the excitation chi_1 + i chi_2"
    ),
    "pole_spectrum": Spec(("frequency",), "milliarcsecond", "two-sided amplitude spectrum of the pole x_p - i y_p"),
    # UDUNITS' "year" is the tropical year (365.242198781 d): cycles per Julian year are "julian_year-1".
    "frequency": Spec(("frequency",), "julian_year-1", "frequency in cycles per Julian year (positive: prograde)"),
    "chandler_period": Spec((), "day", "Chandler period T_c of the complex frequency sigma_c"),
    "quality_factor": Spec((), "1", "quality factor Q of the Chandler wobble"),
    "round_trip_rms": Spec(
        (), "milliarcsecond", "RMS distance between the record and the pole rebuilt from its excitation"
    ),
}

# Polar-motion forecasts and hindcasts (wobble forecast).
FORECAST: dict[str, Spec] = {
    "lead_time": Spec(("lead",), "day", "lead time from the issue time", "forecast_period"),
    "issue_time": Spec(
        ("issue",), "days since 1858-11-17 00:00:00", "issue time of the forecast (UTC)", "forecast_reference_time"
    ),
    "x_p": Spec(("lead",), "milliarcsecond", "forecast of the pole coordinate x_p"),
    "y_p": Spec(("lead",), "milliarcsecond", "forecast of the pole coordinate y_p"),
    "x_p_bounds_68": Spec(("lead", "bounds"), "milliarcsecond", "68 % interval of the x_p forecast"),
    "y_p_bounds_68": Spec(("lead", "bounds"), "milliarcsecond", "68 % interval of the y_p forecast"),
    "x_p_bounds_95": Spec(("lead", "bounds"), "milliarcsecond", "95 % interval of the x_p forecast"),
    "y_p_bounds_95": Spec(("lead", "bounds"), "milliarcsecond", "95 % interval of the y_p forecast"),
    "x_p_forecast": Spec(("method", "issue", "lead"), "milliarcsecond", "hindcast of x_p"),
    "y_p_forecast": Spec(("method", "issue", "lead"), "milliarcsecond", "hindcast of y_p"),
    "x_p_sigma": Spec(
        ("method", "issue", "lead"), "milliarcsecond", "the model's own one-sigma error of the x_p hindcast"
    ),
    "y_p_sigma": Spec(
        ("method", "issue", "lead"), "milliarcsecond", "the model's own one-sigma error of the y_p hindcast"
    ),
    "x_p_half_width_68": Spec(
        ("method", "issue", "lead"), "milliarcsecond", "half-width of the 68 % interval of the x_p hindcast"
    ),
    "y_p_half_width_68": Spec(
        ("method", "issue", "lead"), "milliarcsecond", "half-width of the 68 % interval of the y_p hindcast"
    ),
    "x_p_half_width_95": Spec(
        ("method", "issue", "lead"), "milliarcsecond", "half-width of the 95 % interval of the x_p hindcast"
    ),
    "y_p_half_width_95": Spec(
        ("method", "issue", "lead"), "milliarcsecond", "half-width of the 95 % interval of the y_p hindcast"
    ),
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
    "rms_2d_persistence": Spec(
        ("lead",), "milliarcsecond", "RMS error of the 2-D pole of persistence (the last value used)"
    ),
    "rms_2d_ls": Spec(
        ("lead",), "milliarcsecond", "RMS error of the 2-D pole of the least-squares extrapolation alone"
    ),
    "skill_persistence": Spec(("method", "lead"), "1", "skill against persistence, 1 - RMS_2d / RMS_2d(persistence)"),
    "skill_ls": Spec(("method", "lead"), "1", "skill against the least-squares extrapolation, 1 - RMS_2d / RMS_2d(LS)"),
    "latency": Spec((), "day", "publication delay assumed: the data used end this long before the issue time"),
}

TABLES: dict[str, Mapping[str, Spec]] = {
    "chandler": CHANDLER,
    "free": FREE,
    "scene": SCENE,
    "top": TOP,
    "bodies": BODIES,
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


#: How far from its epoch a CF calendar time can be decoded: cftime (and xarray through it) counts
#: the offset in 64-bit microseconds, 2**63 us = 9.22e12 s, about 292,000 years.
CF_DECODABLE_SECONDS = 9.2e12
_SINCE = re.compile(r"\s*(\S+)\s+since\s+(.+?)\s*")
_SECONDS_PER = {"seconds": 1.0, "second": 1.0, "s": 1.0, "days": 86400.0, "day": 86400.0, "d": 86400.0}
_BARE_UNIT = {"seconds": "s", "second": "s", "days": "d", "day": "d"}
_EPOCH_DATE = re.compile(r"(-?\d+)-(\d+)-(\d+)")


def time_coordinate(values, units: str = SIMULATION_TIME_UNITS, *, long_name: str = "time", **extra) -> tuple:
    """``(dims, values, attrs)`` of a CF time coordinate (float64 numbers since an epoch).

    Times stay numbers so that round trips are exact; ``units`` is
    ``"<unit> since <epoch>"`` (:data:`SIMULATION_TIME_UNITS`, :data:`MJD_UNITS`).
    A span reaching past :data:`CF_DECODABLE_SECONDS` from the epoch (a run of a million
    years) would make a file that xarray and cftime refuse to open, decoding its times; its
    coordinate is elapsed time instead: ``units`` the bare unit (``s``), no calendar, standard
    name or axis (to CF, a time axis is a calendar time), the epoch in ``time_origin``.
    """
    import numpy as np  # here, not at the top: the command line imports this registry before NumPy

    match = _SINCE.fullmatch(units)
    out = {"units": units, "standard_name": "time", "long_name": long_name, "axis": "T", "calendar": _calendar(match)}
    data = np.asarray(values, dtype=float)
    if match and match.group(1) in _SECONDS_PER and data.size and np.any(np.isfinite(data)):
        reach = float(np.nanmax(np.abs(data))) * _SECONDS_PER[match.group(1)]
        if reach > CF_DECODABLE_SECONDS:
            unit, epoch = match.groups()
            out = {
                "units": _BARE_UNIT.get(unit, unit),
                "long_name": f"{long_name} since {epoch}",
                "time_origin": epoch,
                "comment": (
                    "elapsed time, not a calendar time: the span reaches past 292,000 years from the epoch, "
                    "beyond which cftime and xarray cannot decode CF calendar times (64-bit microseconds)"
                ),
            }
    out.update({k: v for k, v in extra.items() if v is not None})
    return ("time",), values, out


def _calendar(match) -> str:
    """CF's "standard" calendar, or "proleptic_gregorian" for an epoch before 1582-10-15.

    wobble's dates are proleptic Gregorian (Python's datetime, astropy's ISO times); CF's "standard"
    calendar is the Julian one before the Gregorian reform, where a reader would have decoded an epoch
    of 0001-01-01 two days away from the date meant.
    """
    date = _EPOCH_DATE.match(match.group(2)) if match else None
    if date is not None and tuple(int(v) for v in date.groups()) < (1582, 10, 15):
        return "proleptic_gregorian"
    return "standard"


def label_coordinate(dim: str) -> tuple:
    """``(dim, labels, attrs)`` of a string-labelled dimension from :data:`LABELS`."""
    labels, long_name = LABELS[dim]
    return dim, list(labels), {"long_name": long_name}


def with_member(dims: tuple[str, ...]) -> tuple[str, ...]:
    """``dims`` with the ensemble dimension ``member`` after ``time`` (or first)."""
    at = 1 if dims[:1] == ("time",) else 0
    return dims[:at] + ("member",) + dims[at:]


def flag_attrs(meanings: Mapping[int, str]) -> dict:
    """``flag_values``/``flag_meanings`` of an integer code variable (CF sec. 3.5)."""
    import numpy as np

    codes = sorted(meanings)
    words = [meanings[c].strip().replace(" ", "_") for c in codes]
    return {"flag_values": np.array(codes, dtype=np.int8), "flag_meanings": " ".join(words)}


# UDUNITS names for the astropy symbols UDUNITS lacks or reads otherwise: "mas" and "deg" are not UDUNITS
# units and "yr" is the tropical year there (2.1e-5 shorter than astropy's Julian year). The Julian year is
# spelled in lower case, which UDUNITS (cf-units) and pint (cf_xarray's registry) both read as 365.25 d;
# pint has no "Julian_year", which files before 2026-11-30 carry (read back below).
_UDUNITS_NAMES = {
    "mas": "milliarcsecond",
    "arcsec": "arcsecond",
    "deg": "degree",
    "yr": "julian_year",
    "a": "julian_year",
}


def udunits(unit) -> str:
    """A unit (astropy Unit or its text) as a UDUNITS string for a netCDF ``units`` attribute:
    ``kg m-3``, ``milliarcsecond Julian_year-1`` for astropy's ``mas / yr``, ``1`` for a pure number."""
    from astropy import units as u

    unit = u.Unit(unit or u.dimensionless_unscaled)
    if unit == u.dimensionless_unscaled:
        return "1"
    try:
        text = unit.to_string("fits")
    except ValueError:  # a scale FITS cannot write (arcsec / cy): astropy's own string, as given
        return unit.to_string()
    # FITS orders by power (m2 kg); a moment of inertia is written kg m2 everywhere else.
    words = text.split()
    words.sort(key=lambda w: not (w.rstrip("0123456789") == "kg"))
    return _renamed(" ".join(words), _UDUNITS_NAMES)


def _renamed(text: str, names: dict) -> str:
    """``text``'s unit words renamed by ``names``, each keeping its exponent (``yr-1`` -> ``Julian_year-1``)."""
    words = []
    for word in text.split():
        base = word.rstrip("-0123456789")
        words.append(names.get(base, base) + word[len(base) :])
    return " ".join(words)


#: The UDUNITS names :func:`udunits` writes, back to astropy's (which has no "Julian_year").
_ASTROPY_NAMES = {udunits_name: name for name, udunits_name in _UDUNITS_NAMES.items() if name != "a"}
_ASTROPY_NAMES["Julian_year"] = "yr"  # the spelling of older files


def astropy_unit_text(text: str) -> str:
    """A ``units`` attribute as text astropy parses: :func:`udunits`'s names mapped back
    (``milliarcsecond Julian_year-1`` is ``mas yr-1``); other words unchanged."""
    return _renamed(text, _ASTROPY_NAMES)
