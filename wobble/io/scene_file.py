"""Scene files (TOML, schema ``wobble-scene/1``) and the same structure as a Python mapping.

Every key is documented in docs/scenes.md. Physical numbers carry units, as a
string (``"1.5 kg m2"``), a table (``{ value = [1, 2, 3], unit = "kg m2" }``)
or, from Python, an :class:`astropy.units.Quantity`; a bare number where a
dimension is needed is an error. Errors name the file and the key
(``scene.toml, time.stop: ...``); a mapping without a file gives an
:class:`~wobble.errors.InputError` naming the key.

The result is a :class:`wobble.models.scene.Scene` in SI.
"""

from __future__ import annotations

import datetime as _dt
import json
import math
import os
import tomllib
from importlib import resources
from pathlib import Path

import numpy as np
from astropy import units as u

from wobble.errors import FileFormatError, InputError
from wobble.io.memory import available_memory, human_bytes
from wobble.io.quantity_values import NotReal, float64_value, quantity_from_text, real_float
from wobble.models import torques
from wobble.models.orbit import EphemerisTable, KeplerOrbit
from wobble.models.rigid_frame import BodyModel, InternalFrame
from wobble.models.scene import ALL_OUTPUTS, MODEL_NAMES, Scene
from wobble.models.torques import TorqueSpec
from wobble.numerics import quaternion as quat

__all__ = [
    "SCHEMA",
    "read_scene",
    "scene_from_mapping",
    "body_from_mapping",
    "torque_from_mapping",
    "example_scenes",
    "example_scene_path",
    "to_plain",
    "TORQUE_KINDS",
]

SCHEMA = "wobble-scene/1"
TOP_KEYS = (
    "schema",
    "name",
    "title",
    "description",
    "body",
    "initial",
    "torques",
    "time",
    "accuracy",
    "outputs",
    "model",
)
# The kinds a scene file names; "custom" (a Python function) comes only from Python.
TORQUE_KINDS = ("constant", "gravity", "gravity_gradient", "third_body", "magnetic", "damping")
_SOLID_LENGTHS = {
    "solid_sphere": ("radius",),
    "hollow_sphere": ("radius", "inner_radius"),
    "ellipsoid": ("semi_axes",),
    "box": ("edges",),
    "cylinder": ("radius", "height", "inner_radius"),
    "cone": ("radius", "height"),
    "thin_disc": ("radius",),
    "thin_rod": ("length",),
}
_MOI = u.kg * u.m**2


class _Reader:
    """Parsing helpers that know where they are (file and key) for their errors."""

    def __init__(self, source: str | None):
        self.source = source

    def error(self, where: str, value, allowed: str) -> Exception:
        shown = value if not isinstance(value, (dict, list)) or len(str(value)) < 60 else str(value)[:57] + "..."
        if self.source:
            return FileFormatError(self.source, where, f"got {shown!r}; allowed: {allowed}")
        return InputError(where, shown, allowed)

    def missing(self, where: str, what: str) -> Exception:
        if self.source:
            return FileFormatError(self.source, where, f"missing; {what}")
        return InputError.missing(where, what)

    def table(self, data, where: str, known) -> dict:
        if not isinstance(data, dict):
            raise self.error(where, data, "a table")
        unknown = sorted(set(data) - set(known))
        if unknown:
            key = f"{where}.{unknown[0]}" if where else unknown[0]
            raise self.error(key, unknown[0], "one of the keys " + ", ".join(known) + " (docs/scenes.md)")
        return data

    def quantity(self, raw, where: str, unit: u.UnitBase, *, ndim=None, width=None, positive=False, nonnegative=False):
        """SI float array from a Quantity, "1.5 kg m2", or {value, unit}."""
        kind = _kind(unit)
        if isinstance(raw, u.Quantity):
            q = raw
        elif isinstance(raw, str):
            try:
                q = quantity_from_text(raw)
            except (TypeError, ValueError):
                raise self.error(where, raw, f'a number with a unit of {kind} (e.g. "{_example(unit)}")') from None
        elif isinstance(raw, dict):
            self.table(raw, where, ("value", "unit"))
            if "value" not in raw or "unit" not in raw:
                raise self.error(where, raw, "a table with value and unit")
            try:
                un = u.Unit(str(raw["unit"]), parse_strict="raise")
            except ValueError:
                raise self.error(
                    f"{where}.unit",
                    raw["unit"],
                    f'a unit of {kind} astropy can parse (e.g. "{_example(unit).split(" ", 1)[1]}")',
                ) from None
            try:
                value = np.asarray(raw["value"], dtype=float)
            except (TypeError, ValueError):
                raise self.error(f"{where}.value", raw["value"], "numbers") from None
            q = value * un
        else:
            raise self.error(
                where, raw, f'a quantity with a unit of {kind}, e.g. "{_example(unit)}" (a bare number has no unit)'
            )
        try:
            si = float64_value(q, unit)  # float64, a copy of the caller's array, no equivalencies
        except NotReal as exc:
            raise self.error(where, str(q), str(exc)) from None
        except u.UnitConversionError:
            raise self.error(
                f"{where}" if not isinstance(raw, dict) else f"{where}.unit",
                str(q.unit),
                f'a unit of {kind} (e.g. "{_example(unit).split(" ", 1)[1]}")',
            ) from None
        self._check_array(si, raw, where, ndim, width, positive, nonnegative)
        return si

    def number(self, raw, where: str, *, ndim=None, width=None):
        if isinstance(raw, u.Quantity):  # the rule of every Quantity a user gives (quantity_values)
            try:
                raw = float64_value(raw, u.dimensionless_unscaled)
            except (u.UnitConversionError, NotReal):
                raise self.error(where, str(raw), "dimensionless numbers (real, unmasked)") from None
        if isinstance(raw, (str, dict, bool)):
            raise self.error(where, raw, "dimensionless numbers")
        try:
            arr = np.asarray(raw, dtype=float)
        except (TypeError, ValueError):
            raise self.error(where, raw, "dimensionless numbers") from None
        self._check_array(arr, raw, where, ndim, width, False, False)
        return arr

    def _check_array(self, arr, raw, where, ndim, width, positive, nonnegative):
        if not np.all(np.isfinite(arr)):
            raise self.error(where, raw, "finite numbers")
        if ndim is not None and arr.ndim not in ndim:
            want = " or ".join(
                {0: "a single number", 1: "a list", 2: "a list of lists", 3: "a list of 3x3 tensors"}[d] for d in ndim
            )
            raise self.error(where, raw, want)
        if width is not None and arr.ndim >= 1 and arr.shape[-1] != width:
            raise self.error(where, raw, f"{width} components per entry")
        if positive and np.any(arr <= 0):
            raise self.error(where, raw, "positive values")
        if nonnegative and np.any(arr < 0):
            raise self.error(where, raw, "non-negative values")

    def string(self, raw, where: str, choices=None) -> str:
        if not isinstance(raw, str):
            raise self.error(where, raw, "a string" + (f": one of {', '.join(choices)}" if choices else ""))
        if choices is not None and raw not in choices:
            raise self.error(where, raw, "one of " + ", ".join(choices))
        return raw


def _kind(unit):
    if unit.is_equivalent(u.rad / u.s, equivalencies=None):
        return "angular speed"
    if unit.is_equivalent(_MOI, equivalencies=None):
        return "moment of inertia"
    if unit.is_equivalent(u.m**3 / u.s**2, equivalencies=None):
        return "gravitational parameter"
    if unit.is_equivalent(u.N * u.m * u.s, equivalencies=None):
        return "angular momentum (damping coefficient, N m s)"
    return str(unit.physical_type)


def _example(unit):
    examples = {
        "time": "10 s",
        "angular speed": "1 rad/s",
        "moment of inertia": "1 kg m2",
        "mass": "1 kg",
        "length": "0.1 m",
        "angle": "30 deg",
        "acceleration": "9.81 m/s2",
        "gravitational parameter": "3.986004418e14 m3/s2",
    }
    return examples.get(_kind(unit), f"1 {unit.to_string()}")


# --------------------------------------------------------------------------
# Sections
# --------------------------------------------------------------------------
def _body(r: _Reader, data) -> tuple[BodyModel, np.ndarray | None]:
    """(BodyModel, centre of mass from the reference point or None)."""
    if data is None:
        raise r.missing("body", "give moments, tensor, planet or solid (docs/scenes.md)")
    if not isinstance(data, dict):
        raise r.error("body", data, "a table with one of moments, tensor, planet, solid")
    given = [k for k in ("moments", "tensor", "planet", "solid") if k in data]
    if len(given) != 1:
        raise r.error("body", sorted(data), "exactly one of moments, tensor, planet, solid")
    kind = given[0]
    if kind == "solid":
        return _solid(r, data)
    r.table(data, "body", (kind, "mass", "symmetric") if kind == "planet" else (kind, "mass"))
    mass = None
    if "mass" in data:
        mass = float(r.quantity(data["mass"], "body.mass", u.kg, ndim=(0,), positive=True))
    try:
        if kind == "moments":
            m = r.quantity(data["moments"], "body.moments", _MOI, ndim=(0, 1, 2), width=3, positive=True)
            if m.ndim == 0:  # one moment: a sphere (or any body with I1 = I2 = I3)
                m = np.full(3, float(m))
            return BodyModel.from_moments(m, mass), None
        if kind == "tensor":
            t = r.quantity(data["tensor"], "body.tensor", _MOI, ndim=(2, 3), width=3)
            if t.shape[-2:] != (3, 3):
                raise r.error("body.tensor", data["tensor"], "a 3x3 tensor (or a list of them)")
            return BodyModel.from_tensor(t, mass), None
    except InputError as exc:
        raise r.error(f"body.{kind}", exc.value, exc.allowed) from None
    symmetric = data.get("symmetric", False)
    if not isinstance(symmetric, bool):
        raise r.error("body.symmetric", symmetric, "true or false")
    return _planet_body(r, data["planet"], mass, symmetric), None


def _planet(r: _Reader, name, where):
    from wobble.io.catalog import load_planet

    if not isinstance(name, str):
        raise r.error(where, name, 'the name of a catalogued planet (data/bodies), e.g. "earth"')
    try:
        params, _ = load_planet(name)
    except InputError as exc:
        raise r.error(where, name, exc.allowed) from None
    return params


def _planet_body(r: _Reader, name, mass, symmetric=False) -> BodyModel:
    """Principal moments A <= B <= C of a catalogued planet from its figure (H, J2 or C/Ma2, C22, S22).

    ``symmetric``: both equatorial moments set to their mean (A + B)/2, the A of H = (C - A)/C,
    so H and C are kept and the triaxiality (C22, S22) is dropped.
    """
    from dataclasses import replace

    from wobble.models.chandler import principal_moments

    p = _planet(r, name, "body.planet")
    figure = principal_moments(p)
    if figure is None:
        raise r.error(
            "body.planet", name, "a planet whose file gives gm, equatorial_radius and C/(M a^2) (or j2 with H)"
        )
    moments, planet_mass = figure
    moments = np.array(moments)
    if symmetric:
        moments[:2] = 0.5 * (moments[0] + moments[1])
    radius = None if p.equatorial_radius is None else float(p.equatorial_radius.value)
    body = BodyModel.from_moments(moments, mass if mass is not None else planet_mass)
    return replace(body, radius=radius)


def _solid(r: _Reader, data):
    """A named solid from the rigid-bodies library (closed-form tensors, Goldstein et al. 2002, sec. 5.1)."""
    from wobble.models import solids

    name = r.string(data["solid"], "body.solid", tuple(_SOLID_LENGTHS))
    lengths = _SOLID_LENGTHS[name]
    r.table(data, "body", ("solid", "mass", "about") + lengths)
    if "mass" not in data:
        raise r.missing("body.mass", "a named solid needs its mass")
    mass = float(r.quantity(data["mass"], "body.mass", u.kg, ndim=(0,), positive=True))
    kwargs = {}
    for key in lengths:
        if key in data:
            val = r.quantity(data[key], f"body.{key}", u.m, nonnegative=True)
            kwargs[key] = float(val) if val.ndim == 0 else val
    solid = getattr(solids, name)(mass, **kwargs)
    if "about" in data:
        solid = solid.shifted_to(r.quantity(data["about"], "body.about", u.m, ndim=(1,), width=3))
    body = BodyModel.from_tensor(np.asarray(solid.tensor), mass)
    return body, np.asarray(solid.center_of_mass) - np.asarray(solid.reference_point)


def _euler_quaternion(angles):
    """z-x-z Euler angles (phi, theta, psi) -> quaternion of R = Rz(phi) Rx(theta) Rz(psi) (body -> inertial)."""
    phi, theta, psi = angles[..., 0], angles[..., 1], angles[..., 2]
    z = np.array([0.0, 0.0, 1.0])
    x = np.array([1.0, 0.0, 0.0])
    return quat.multiply(
        quat.from_axis_angle(z, phi), quat.multiply(quat.from_axis_angle(x, theta), quat.from_axis_angle(z, psi))
    )


def _euler_omega(angles, rates):
    """Body-frame omega from z-x-z Euler angles and their rates (Goldstein eq. 4.125)."""
    _, theta, psi = angles[..., 0], angles[..., 1], angles[..., 2]
    dphi, dtheta, dpsi = rates[..., 0], rates[..., 1], rates[..., 2]
    return np.stack(
        [
            dphi * np.sin(theta) * np.sin(psi) + dtheta * np.cos(psi),
            dphi * np.sin(theta) * np.cos(psi) - dtheta * np.sin(psi),
            dphi * np.cos(theta) + dpsi,
        ],
        axis=-1,
    )


def _initial(r: _Reader, data, body_data):
    if data is None:
        raise r.missing("initial", "give omega (or euler_rates, or spin_rate)")
    keys = (
        "omega",
        "euler_rates",
        "spin_rate",
        "wobble_angle",
        "wobble_phase",
        "attitude",
        "euler_angles",
        "obliquity",
    )
    r.table(data, "initial", keys)
    rate_keys = [k for k in ("omega", "euler_rates", "spin_rate") if k in data]
    if len(rate_keys) != 1:
        raise r.error("initial", sorted(data), "exactly one of omega, euler_rates, spin_rate")
    given = [k for k in ("attitude", "euler_angles", "obliquity") if k in data]
    if len(given) > 1:
        raise r.error(
            f"initial.{given[1]}", f"both {given[0]} and {given[1]}", "one of attitude, euler_angles, obliquity"
        )
    angles = None
    if "obliquity" in data:
        # Body axis 3 at (0, sin eps, cos eps): tilted towards +y, so that the inertial x axis
        # is the vernal equinox (the ascending node of the x-y plane on the body's equator).
        eps = r.quantity(data["obliquity"], "initial.obliquity", u.rad, ndim=(0, 1))
        if np.any(eps < 0) or np.any(eps > np.pi):
            shown = np.degrees(eps).round(6).tolist()
            raise r.error("initial.obliquity", f"{shown} deg", "an angle in [0, 180] deg")
        angles = np.stack(np.broadcast_arrays(np.pi, eps, 0.0), axis=-1)
        q0 = _euler_quaternion(angles)
    elif "euler_angles" in data:
        angles = r.quantity(data["euler_angles"], "initial.euler_angles", u.rad, ndim=(1, 2), width=3)
        q0 = _euler_quaternion(angles)
    elif "attitude" in data:
        q0 = r.number(data["attitude"], "initial.attitude", ndim=(1, 2), width=4)
        norm = np.linalg.norm(q0, axis=-1)
        if np.any(np.abs(norm - 1.0) > 1e-6):
            raise r.error("initial.attitude", data["attitude"], "unit quaternions (w, x, y, z), |q| = 1 within 1e-6")
        q0 = q0 / norm[..., None]
    else:
        q0 = np.array([1.0, 0.0, 0.0, 0.0])
    kind = rate_keys[0]
    if kind != "spin_rate" and ("wobble_angle" in data or "wobble_phase" in data):
        raise r.error("initial.wobble_angle", "with " + kind, "wobble_angle and wobble_phase only with spin_rate")
    if kind == "omega":
        w0 = r.quantity(data["omega"], "initial.omega", u.rad / u.s, ndim=(1, 2), width=3)
    elif kind == "euler_rates":
        if angles is None:
            raise r.missing("initial.euler_angles", "euler_rates need euler_angles (z-x-z: phi, theta, psi)")
        rates = r.quantity(data["euler_rates"], "initial.euler_rates", u.rad / u.s, ndim=(1, 2), width=3)
        w0 = _euler_omega(angles, rates)
    else:
        raw = data["spin_rate"]
        if raw == "catalogue":
            if not isinstance(body_data, dict) or "planet" not in body_data:
                raise r.error("initial.spin_rate", raw, '"catalogue" only with body.planet; else an angular speed')
            spin = np.asarray(_planet(r, body_data["planet"], "body.planet").rotation_rate.value)
        else:
            spin = r.quantity(raw, "initial.spin_rate", u.rad / u.s, ndim=(0, 1))
        wob = r.quantity(data.get("wobble_angle", "0 rad"), "initial.wobble_angle", u.rad, ndim=(0, 1))
        phase = r.quantity(data.get("wobble_phase", "0 rad"), "initial.wobble_phase", u.rad, ndim=(0, 1))
        spin, wob, phase = np.broadcast_arrays(spin, wob, phase)
        w0 = np.stack([spin * np.sin(wob) * np.cos(phase), spin * np.sin(wob) * np.sin(phase), spin * np.cos(wob)], -1)
    return w0, q0


def _torque(r: _Reader, i: int, data, body, com):
    if isinstance(data, TorqueSpec):
        return data
    return _torque_spec(r, f"torques[{i}]", data, body, com)


def torque_from_mapping(data) -> TorqueSpec:
    """A torque from its scene-file table, with Quantities or unit strings as values.

    The one place where a torque's parameters are checked and converted to SI: scene
    files (``[[torques]]``) and the API's :class:`wobble.Torque` constructors both come here,
    so a parameter means the same, in the same unit, everywhere. Errors name the key.
    """
    return _torque_spec(_Reader(None), "", data, None, None)


def _key(where: str, name: str) -> str:
    return f"{where}.{name}" if where else name


def _torque_spec(r: _Reader, where: str, data, body, com) -> TorqueSpec:
    if not isinstance(data, dict):
        raise r.error(where or "torque", data, "a table with a kind")
    if "kind" not in data:
        raise r.missing(_key(where, "kind"), "one of " + ", ".join(TORQUE_KINDS))
    kind = r.string(data["kind"], _key(where, "kind"), TORQUE_KINDS)
    return _TORQUE_READERS[kind](r, where, data, body, com)


def _constant(r: _Reader, where, data, body, com) -> TorqueSpec:
    r.table(data, where, ("kind", "torque", "frame"))
    if "torque" not in data:
        raise r.missing(_key(where, "torque"), 'the torque vector, e.g. { value = [0, 0, 1], unit = "N m" }')
    tau = r.quantity(data["torque"], _key(where, "torque"), u.N * u.m, ndim=(1, 2), width=3)
    frame = r.string(data.get("frame", "body"), _key(where, "frame"), ("body", "inertial"))
    return torques.ConstantTorque(tau, frame)


def _gravity(r: _Reader, where, data, body, com) -> TorqueSpec:
    r.table(data, where, ("kind", "g", "gravity", "mass", "center_of_mass"))
    if "g" in data and "gravity" in data:
        raise r.error(_key(where, "gravity"), "both g and gravity", "one of them")
    if "gravity" in data:
        grav = r.quantity(data["gravity"], _key(where, "gravity"), u.m / u.s**2, ndim=(1,), width=3)
    else:
        g = float(
            r.quantity(
                data.get("g", f"{torques.STANDARD_GRAVITY} m/s2"),
                _key(where, "g"),
                u.m / u.s**2,
                ndim=(0,),
                positive=True,
            )
        )
        grav = np.array([0.0, 0.0, -g])
    if "mass" in data:
        mass = r.quantity(data["mass"], _key(where, "mass"), u.kg, ndim=(0, 1), positive=True)
    elif body is not None and body.mass is not None:
        mass = np.asarray(body.mass)
    else:
        raise r.missing(_key(where, "mass"), "the mass (or body.mass)")
    if "center_of_mass" in data:
        r_cm = r.quantity(data["center_of_mass"], _key(where, "center_of_mass"), u.m, ndim=(1, 2), width=3)
    elif com is not None:
        r_cm = com
    else:
        raise r.missing(_key(where, "center_of_mass"), "the centre of mass from the pivot, body frame (m)")
    return torques.UniformGravity(mass, r_cm, grav)


def _gravity_gradient(r: _Reader, where, data, body, com) -> TorqueSpec:
    r.table(data, where, ("kind", "gm", "primary", "distance", "direction", "orbit_normal", "phase", "mean_motion"))
    if ("gm" in data) == ("primary" in data):
        raise r.error(_key(where, "gm"), sorted(data), "exactly one of gm and primary (a catalogued planet)")
    if "gm" in data:
        gm = float(r.quantity(data["gm"], _key(where, "gm"), u.m**3 / u.s**2, ndim=(0,), positive=True))
    else:
        p = _planet(r, data["primary"], _key(where, "primary"))
        if p.gm is None:
            raise r.error(_key(where, "primary"), data["primary"], "a planet whose file gives gm")
        gm = p.gm.value
    if "distance" not in data:
        raise r.missing(_key(where, "distance"), "the distance to the attracting mass")
    dist = float(r.quantity(data["distance"], _key(where, "distance"), u.m, ndim=(0,), positive=True))
    if ("direction" in data) == ("orbit_normal" in data):
        raise r.error(
            _key(where, "direction"), sorted(data), "exactly one of direction (fixed) and orbit_normal (circular orbit)"
        )
    direction = normal = None
    if "direction" in data:
        direction = _nonzero(r, data["direction"], _key(where, "direction"))
    else:
        normal = _nonzero(r, data["orbit_normal"], _key(where, "orbit_normal"))
    phase = float(r.quantity(data.get("phase", "0 rad"), _key(where, "phase"), u.rad, ndim=(0,)))
    n = None
    if "mean_motion" in data:
        n = float(r.quantity(data["mean_motion"], _key(where, "mean_motion"), u.rad / u.s, ndim=(0,)))
    return torques.GravityGradient(gm, dist, direction, normal, phase, n)


def _nonzero(r: _Reader, raw, where: str) -> np.ndarray:
    vec = r.number(raw, where, ndim=(1,), width=3)
    if not np.linalg.norm(vec) > 0:
        raise r.error(where, raw, "a non-zero vector")
    return vec


_ORBIT_ANGLES = ("inclination", "longitude_of_node", "argument_of_periapsis", "mean_anomaly")
_ORBIT_RATES = ("mean_motion", "node_rate", "periapsis_rate")
_THIRD_BODY_KEYS = (
    "kind",
    "name",
    "gm",
    "semi_major_axis",
    "eccentricity",
    *_ORBIT_ANGLES,
    *_ORBIT_RATES,
    "ephemeris",
    "position",
)


def _third_body(r: _Reader, where, data, body, com) -> TorqueSpec:
    """A third body on a Keplerian orbit, an ephemeris table, or (Python) a position callable."""
    r.table(data, where, _THIRD_BODY_KEYS)
    name = data.get("name", "third_body")
    if not isinstance(name, str) or not name:
        raise r.error(_key(where, "name"), name, "a non-empty string (the perturber's name)")
    if "gm" not in data:
        raise r.missing(_key(where, "gm"), 'the perturber\'s G M, e.g. "4.9028e12 m3/s2" (the Moon)')
    gm_si = r.quantity(data["gm"], _key(where, "gm"), u.m**3 / u.s**2, ndim=(0,))
    if not gm_si > 0:
        raise r.error(_key(where, "gm"), data["gm"], "a positive G M (a negative mass is unphysical)")
    sources = [k for k in ("semi_major_axis", "ephemeris", "position") if k in data]
    if len(sources) != 1:
        raise r.error(
            _key(where, "semi_major_axis"),
            sorted(data),
            "exactly one of semi_major_axis (with the other orbital elements), ephemeris (a table) "
            "and position (a Python callable)",
        )
    orbit_keys = ("eccentricity", *_ORBIT_ANGLES, *_ORBIT_RATES)
    if sources[0] != "semi_major_axis" and any(k in data for k in orbit_keys):
        extra = next(k for k in orbit_keys if k in data)
        raise r.error(
            _key(where, extra), data[extra], f"orbital elements only with semi_major_axis (not with {sources[0]})"
        )
    if sources[0] == "semi_major_axis":
        a = float(r.quantity(data["semi_major_axis"], _key(where, "semi_major_axis"), u.m, ndim=(0,)))
        e = float(r.number(data.get("eccentricity", 0.0), _key(where, "eccentricity"), ndim=(0,)))
        angles = {k: float(r.quantity(data.get(k, "0 deg"), _key(where, k), u.rad, ndim=(0,))) for k in _ORBIT_ANGLES}
        rates = {
            k: float(r.quantity(data[k], _key(where, k), u.rad / u.s, ndim=(0,))) for k in _ORBIT_RATES if k in data
        }
        if "mean_motion" not in rates and a > 0:
            rates["mean_motion"] = float(np.sqrt(float(gm_si) / a**3))  # the perturber as the heavy partner
        return _checked(
            r, where, lambda: torques.ThirdBody(float(gm_si), orbit=KeplerOrbit(a, e, **angles, **rates), name=name)
        )
    if sources[0] == "ephemeris":
        table = r.table(data["ephemeris"], _key(where, "ephemeris"), ("times", "positions"))
        for key in ("times", "positions"):
            if key not in table:
                raise r.missing(
                    _key(where, f"ephemeris.{key}"),
                    'times (e.g. { value = [0, 1, 2, 3], unit = "d" }) and positions (m, one triple per time)',
                )
        t = r.quantity(table["times"], _key(where, "ephemeris.times"), u.s, ndim=(1,))
        pos = r.quantity(table["positions"], _key(where, "ephemeris.positions"), u.m, ndim=(2,), width=3)
        return _checked(r, where, lambda: torques.ThirdBody(float(gm_si), ephemeris=EphemerisTable(t, pos), name=name))
    if not callable(data["position"]):
        raise r.error(
            _key(where, "position"),
            data["position"],
            "a Python callable f(t) -> positions (n, 3) in m (scene files use semi_major_axis or ephemeris)",
        )
    return _checked(r, where, lambda: torques.ThirdBody(float(gm_si), position=data["position"], name=name))


def _checked(r: _Reader, where: str, build):
    """Build a model object, naming its key (and the file) in the error of a parameter it refuses."""
    try:
        return build()
    except InputError as exc:
        raise r.error(_key(where, exc.parameter), exc.value, exc.allowed) from None


def _magnetic(r: _Reader, where, data, body, com) -> TorqueSpec:
    r.table(data, where, ("kind", "dipole", "field"))
    for key, what in (
        ("dipole", 'the body\'s magnetic dipole moment, body frame, e.g. { value = [0, 0, 1], unit = "A m2" }'),
        ("field", 'the uniform magnetic field, inertial frame, e.g. { value = [0, 0, -50], unit = "uT" }'),
    ):
        if key not in data:
            raise r.missing(_key(where, key), what)
    mu = r.quantity(data["dipole"], _key(where, "dipole"), u.A * u.m**2, ndim=(1, 2), width=3)
    field = r.quantity(data["field"], _key(where, "field"), u.T, ndim=(1, 2), width=3)
    return torques.MagneticDipole(mu, field)


def _damping(r: _Reader, where, data, body, com) -> TorqueSpec:
    r.table(data, where, ("kind", "coefficient"))
    if "coefficient" not in data:
        raise r.missing(_key(where, "coefficient"), "the damping coefficient c in tau = -c omega (N m s)")
    c = r.quantity(data["coefficient"], _key(where, "coefficient"), u.N * u.m * u.s, ndim=(0, 1), nonnegative=True)
    return torques.LinearDamping(c)


_TORQUE_READERS = {
    "constant": _constant,
    "gravity": _gravity,
    "gravity_gradient": _gravity_gradient,
    "third_body": _third_body,
    "magnetic": _magnetic,
    "damping": _damping,
}


def _check_grid_memory(r, key: str, value, n: float) -> None:
    """Refuse a time grid of ``n`` samples whose 8-byte times alone would take more than half the free memory
    (samples = 1e30 raised NumPy's 'Maximum allowed size exceeded' with a traceback)."""
    have = available_memory() // 2
    if not n * 8 <= have:
        raise r.error(
            key,
            value,
            f"at most {have // 8} times here: {n:.3g} times need {human_bytes(8 * n)} of memory for the time grid "
            f"alone and {human_bytes(have)} is usable",
        )


def _times(r: _Reader, data):
    if data is None:
        raise r.missing("time", "give stop with samples or step, or values")
    r.table(data, "time", ("start", "stop", "samples", "step", "values", "epoch"))
    epoch = None
    if "epoch" in data:
        epoch = _epoch(r, data["epoch"])
    if "values" in data:
        if any(k in data for k in ("stop", "samples", "step")):
            raise r.error("time.values", sorted(data), "values alone, or stop with samples or step")
        # One time may be given bare (5 s, as FreeRotation.omega takes it): a grid of one output.
        t = np.atleast_1d(r.quantity(data["values"], "time.values", u.s, ndim=(0, 1)))
        if t.size == 0:
            raise r.error("time.values", data["values"], "at least one output time (none were given)")
        if np.any(np.diff(t) <= 0):
            raise r.error(
                "time.values", data["values"], "times increasing strictly (the time grid may not go backwards)"
            )
        return t, epoch
    start = float(r.quantity(data.get("start", "0 s"), "time.start", u.s, ndim=(0,)))
    if "stop" not in data:
        raise r.missing("time.stop", 'the end of the run (e.g. "100 s")')
    stop = float(r.quantity(data["stop"], "time.stop", u.s, ndim=(0,)))
    if stop < start:
        raise r.error("time.stop", data["stop"], f"a time after time.start ({start} s): the grid may not go backwards")
    if ("samples" in data) == ("step" in data):
        raise r.error("time", sorted(data), "exactly one of samples and step with start/stop")
    if "samples" in data:
        n = data["samples"]
        # stop = start with several samples repeated one time, which CF refuses (time must increase strictly).
        if isinstance(n, bool) or not isinstance(n, int) or n < 1 or (n == 1) != (stop == start):
            raise r.error("time.samples", n, "a whole number >= 2 (1 when stop = start)")
        _check_grid_memory(r, "time.samples", n, n)
        return np.linspace(start, stop, n), epoch
    step = float(r.quantity(data["step"], "time.step", u.s, ndim=(0,)))
    if not step > 0:
        raise r.error("time.step", data["step"], "a positive step (the time grid may not go backwards)")
    ratio = (stop - start) / step * (1 + 1e-12)
    _check_grid_memory(r, "time.step", data["step"], ratio + 1 if math.isfinite(ratio) else math.inf)
    return step_grid(start, stop, step), epoch


def step_grid(start: float, stop: float, step: float) -> np.ndarray:
    """The times of ``time = {start, stop, step}`` (s): start + k step up to stop, and stop itself when the
    last step falls short of it by more than rounding."""
    n = int(math.floor((stop - start) / step * (1 + 1e-12))) + 1
    t = start + step * np.arange(n)
    if t[-1] < stop * (1 - 1e-15) - 1e-300 and not math.isclose(t[-1], stop):
        t = np.append(t, stop)
    return t


def _epoch(r: _Reader, raw) -> str:
    """The epoch as CF's reference time in UTC, ``YYYY-MM-DD hh:mm:ss[.ffffff]``: the fraction of a second
    is kept (it was cut, so the times decoded from a file came out up to a second early) and the year is
    four digits (year 1 was written "1-01-01")."""
    dt = _dt

    if _is_astropy_time(raw):
        if raw.ndim != 0:
            raise r.error("time.epoch", raw, "one date-time (a scalar astropy Time), not an array of them")
        raw = raw.utc.to_datetime()
    if isinstance(raw, (dt.datetime, dt.date)):
        value = raw if isinstance(raw, dt.datetime) else dt.datetime(raw.year, raw.month, raw.day)
    elif isinstance(raw, str):
        try:
            value = dt.datetime.fromisoformat(raw.strip().replace("Z", "+00:00"))
        except ValueError:
            raise r.error("time.epoch", raw, 'an ISO 8601 date-time in UTC, e.g. "2000-01-01 12:00:00"') from None
    else:
        raise r.error("time.epoch", raw, 'an ISO 8601 date-time in UTC, e.g. "2000-01-01 12:00:00"')
    if value.tzinfo is not None:
        value = value.astimezone(dt.timezone.utc).replace(tzinfo=None)
    text = f"{value.year:04d}-{value.month:02d}-{value.day:02d} {value.hour:02d}:{value.minute:02d}:{value.second:02d}"
    return text + (f".{value.microsecond:06d}".rstrip("0") if value.microsecond else "")


def _is_astropy_time(value) -> bool:
    """An astropy Time, tested without importing astropy.time for the common string epoch."""
    return type(value).__module__.startswith("astropy.time") and hasattr(value, "utc")


def _members(r, named: dict) -> int:
    """The ensemble size N from the leading axes of per-member arrays (1 if none)."""
    n = 1
    for where, arr, base in named.values():
        if arr.ndim > base:
            if arr.shape[0] == 0:  # an empty ensemble was built, then crashed in wobble.run
                raise r.error(where, "0 members", "at least one member (one row per member)")
            if n != 1 and arr.shape[0] != n:
                raise r.error(where, f"{arr.shape[0]} members", f"the same number of members as elsewhere ({n})")
            n = arr.shape[0]
    return n


# --------------------------------------------------------------------------
# Entry points
# --------------------------------------------------------------------------
def scene_from_mapping(data, source: str | None = None) -> Scene:
    """Build a :class:`~wobble.models.scene.Scene` from a mapping (the TOML structure).

    Parameters
    ----------
    data : dict
        The scene; see docs/scenes.md.
    source : str, optional
        The file it came from (named in errors).

    Raises
    ------
    wobble.errors.FileFormatError
        With a source: the file and the key at fault.
    wobble.errors.InputError
        Without one: the key at fault.
    """
    r = _Reader(source)
    r.table(data, "", TOP_KEYS)
    if "schema" in data and data["schema"] != SCHEMA:
        raise r.error("schema", data["schema"], repr(SCHEMA))
    name = data.get("name", Path(source).stem if source else "scene")
    if not isinstance(name, str) or not name:
        raise r.error("name", name, "a non-empty string")
    title = data.get("title", name)
    description = data.get("description", "")
    for key, value in (("title", title), ("description", description)):
        if not isinstance(value, str):
            raise r.error(key, value, "a string")
    body, com = _body(r, data.get("body"))
    w0, q0 = _initial(r, data.get("initial"), data.get("body"))
    raw_torques = data.get("torques", [])
    if not isinstance(raw_torques, (list, tuple)):
        raise r.error("torques", raw_torques, "a list of torque tables ([[torques]])")
    torques = tuple(_torque(r, i, t, body, com) for i, t in enumerate(raw_torques))
    times, epoch = _times(r, data.get("time"))
    accuracy = data.get("accuracy", 1e-9)
    # Any real number (NumPy's float32, a Fraction: np.float32(1e-9) was refused); not text or a bool.
    try:
        accuracy = real_float(accuracy)
    except (TypeError, ValueError):
        accuracy = math.nan
    if not 0 < accuracy < 1:
        raise r.error("accuracy", data.get("accuracy"), "a relative accuracy in (0, 1), e.g. 1e-9")
    outputs = data.get("outputs", ["omega", "attitude"])
    if isinstance(outputs, str) or not isinstance(outputs, (list, tuple)) or not outputs:
        raise r.error("outputs", outputs, "a non-empty list of " + ", ".join(ALL_OUTPUTS))
    for i, o in enumerate(outputs):
        r.string(o, f"outputs[{i}]", ALL_OUTPUTS)
    model = data.get("model", "auto")
    r.string(model, "model", ("auto",) + MODEL_NAMES)
    moments = np.asarray(body.moments)
    n = _members(r, {"m": ("body", moments, 1), "w": ("initial.omega", w0, 1), "q": ("initial.attitude", q0, 1)})
    ensemble = n > 1 or w0.ndim == 2 or q0.ndim == 2 or moments.ndim == 2
    try:
        w0 = np.broadcast_to(w0, (n, 3)).copy()
        q0 = np.broadcast_to(q0, (n, 4)).copy()
        # Validate the torques against the body now, so that errors name their keys.
        for i, t in enumerate(torques):
            try:
                t.bind(InternalFrame.of(body, n), n)
                check = getattr(t, "check_scene", None)
                if check is not None:  # a perturber inside the body, an ephemeris short of the run
                    check(moments, body.mass, body.radius, float(times[0]), float(times[-1]))
            except InputError as exc:
                raise r.error(f"torques[{i}].{exc.parameter}", exc.value, exc.allowed) from None
    except ValueError as exc:
        if isinstance(exc, (InputError, FileFormatError)):
            raise
        raise r.error("initial", str(exc), "per-member arrays of matching length") from None
    return Scene(
        body=body,
        omega0=w0,
        attitude0=q0,
        torques=torques,
        times=times,
        accuracy=float(accuracy),
        outputs=tuple(dict.fromkeys(outputs)),
        ensemble=bool(ensemble),
        name=name,
        title=title,
        description=description,
        epoch=epoch,
        source=source,
        mapping=to_plain(data),
    )


def body_from_mapping(data) -> BodyModel:
    """The body of a scene's ``body`` table, built as :func:`scene_from_mapping` builds it.

    For readers of a run's record (the ``scene`` attribute of the files ``wobble run`` writes) that
    need only the body: the whole scene may not rebuild from the record (a torque given as a Python
    object is recorded by its name only).

    Raises
    ------
    wobble.errors.InputError
        The key at fault.
    """
    return _body(_Reader(None), data)[0]


def read_scene(path: str | os.PathLike) -> Scene:
    """Read a scene file (TOML).

    Raises
    ------
    wobble.errors.FileFormatError
        Unreadable TOML, or a missing/wrong key (naming the file and the key).
    """
    path = Path(path)
    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except FileNotFoundError:
        raise FileFormatError(path, None, "no such file") from None
    except IsADirectoryError:
        raise FileFormatError(path, None, "a folder, not a scene file") from None
    except tomllib.TOMLDecodeError as exc:
        raise FileFormatError(path, None, f"not valid TOML ({exc})") from None
    return scene_from_mapping(data, str(path))


def _scenes_dir():
    return resources.files("wobble._data") / "scenes"


def example_scenes() -> list[str]:
    """Names of the example scenes shipped in data/scenes."""
    return sorted(p.name[:-5] for p in _scenes_dir().iterdir() if p.name.endswith(".toml"))


def example_scene_path(name: str):
    """Path of the example scene ``name`` (a Traversable inside the package)."""
    if name not in example_scenes():
        raise InputError("scene", name, "one of " + ", ".join(example_scenes()) + ", or a path to a scene file")
    return _scenes_dir() / f"{name}.toml"


def to_plain(data):
    """A JSON-serialisable copy of a scene mapping (Quantities as {value, unit})."""
    if isinstance(data, dict):
        return {str(k): to_plain(v) for k, v in data.items()}
    if isinstance(data, (list, tuple)):
        return [to_plain(v) for v in data]
    if isinstance(data, u.Quantity):
        return {"value": np.asarray(data.value).tolist(), "unit": data.unit.to_string()}
    if isinstance(data, np.ndarray):
        return data.tolist()
    if isinstance(data, (np.floating, np.integer)):
        return data.item()
    if isinstance(data, (str, int, float, bool)) or data is None:
        return data
    if isinstance(data, (_dt.date, _dt.time)):
        return data.isoformat()
    if hasattr(data, "kind"):
        return {"kind": data.kind, "python": getattr(data, "name", type(data).__name__)}
    try:
        json.dumps(data)
        return data
    except TypeError:
        return str(data)
