"""The precession and the principal nutation measured from an engine run, beside the averaged model.

:func:`measure_precession` takes the Dataset (or netCDF file) of a scene whose torques are
third bodies (``wobble.run("earth_precession")``), reads the spin-axis direction in space
(the angular momentum's, or the figure axis ``axis_direction``), and fits the node longitude
psi of the equator and the obliquity eps with a secular rate and the perturbers' periodic
terms (:func:`wobble.models.precession_measure.fit_precession_nutation`). The perturbers'
orbits, and so the arguments of every term, come from the scene recorded in the file.
The result stands beside the first-order averaged model of the same scene
(:mod:`wobble.models.precession_averaged`: Goldstein, Poole & Safko 2002, sec. 5.8;
Woolard 1953; Kinoshita 1977).

>>> import wobble
>>> ds = wobble.run("earth_precession")                       # doctest: +SKIP
>>> m = wobble.measure_precession(ds)                          # doctest: +SKIP
>>> print(m.summary())                                         # doctest: +SKIP

Arguments of the fitted terms
-----------------------------
For a perturber on a Keplerian orbit with node Omega, argument of periapsis w and mean
anomaly M, the mean longitude is L = Omega + w + M. Angles that involve longitudes are
counted from the moving equinox, the descending node of the equator on the x-y plane,
psi(t) + pi: for each perturber the terms 2L, M, 2L + M, 2L - M and, for an inclined orbit
with a regressing node, Omega, 2 Omega, 2L - Omega and 2L - 2 Omega (the first-order
expansion of the tidal potential in the eccentricity and the inclination). A term that
cannot be told apart from one already in the fit over the span (frequencies closer than
one cycle per span) is left out. The principal nutation is the node term of the inclined
perturber whose nutation is largest (the Moon's 18.6-year term).
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from astropy import units as u

from wobble.api.precession import ARCSEC_PER_CENTURY
from wobble.api.units import to_si
from wobble.errors import InputError
from wobble.models.precession_averaged import averaged_precession, averaging_applies
from wobble.models.precession_measure import PrecessionFit, axis_angles, check_times, fit_precession_nutation
from wobble.models.torques import ThirdBody
from wobble.numerics import quaternion as quat

from wobble.numerics.calendar import JULIAN_YEAR

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["PrecessionMeasurement", "measure_precession"]

_RATE = u.rad / u.s


@dataclass(frozen=True)
class PrecessionMeasurement:
    """The mean precession and the principal nutation of a simulated axis, beside the averaged model.

    Attributes
    ----------
    rate, rate_sigma : Quantity
        Secular rate of the node longitude of the equator (arcsec per Julian century;
        negative: retrograde) and its standard error from the fit's residuals.
    obliquity : Quantity
        Mean obliquity at t = 0 (deg).
    nutation_longitude, nutation_obliquity : Quantity or None
        Principal nutation in the IAU convention: Delta psi = A sin(Omega),
        Delta eps = B cos(Omega) (arcsec), Omega the node of ``perturber`` from the equinox.
    nutation_longitude_sigma, nutation_obliquity_sigma : Quantity or None
    nutation_period : Quantity or None
        Period of that node relative to the moving equinox (Julian years).
    perturber : str or None
    axis : str
        The vector measured: ``angular_momentum`` or ``axis_direction`` (the figure axis).
    analytic_rate : Quantity or None
        The first-order averaged rate of the same scene (None where averaging does not apply).
    analytic_nutation_longitude, analytic_nutation_obliquity : Quantity or None
        The first-order rigid-body amplitudes of the same scene (Woolard 1953; Kinoshita 1977).
    residual_rms_longitude, residual_rms_obliquity : Quantity
        RMS of the fit's residuals in psi and eps (arcsec).
    samples : int
    span : Quantity
        Length of the series (Julian years).
    terms : dict
        Every other fitted term: name -> (psi sin, psi cos, eps sin, eps cos) in arcsec (IAU sign for psi).
    caveats : list of str
        What the span could not do: separate the principal term from the secular rate (a span shorter
        than its period, where the rate and the amplitudes may be off by more than their formal errors:
        a 15-year Earth run's rate by 6 "/cy), or fit a term it cannot tell from another (left out).
    """

    rate: u.Quantity
    rate_sigma: u.Quantity
    obliquity: u.Quantity
    nutation_longitude: u.Quantity | None
    nutation_obliquity: u.Quantity | None
    nutation_longitude_sigma: u.Quantity | None
    nutation_obliquity_sigma: u.Quantity | None
    nutation_period: u.Quantity | None
    perturber: str | None
    axis: str
    analytic_rate: u.Quantity | None
    analytic_nutation_longitude: u.Quantity | None
    analytic_nutation_obliquity: u.Quantity | None
    residual_rms_longitude: u.Quantity
    residual_rms_obliquity: u.Quantity
    samples: int
    span: u.Quantity
    terms: dict = field(default_factory=dict)
    caveats: list = field(default_factory=list)

    @property
    def rate_difference(self) -> float | None:
        """Measured / analytic rate - 1 (None without the analytic model)."""
        return None if self.analytic_rate is None else float(self.rate / self.analytic_rate - 1)

    @property
    def nutation_differences(self) -> tuple[float, float] | None:
        """Measured / analytic amplitude - 1, in longitude and in obliquity."""
        if self.analytic_nutation_longitude is None or self.nutation_longitude is None:
            return None
        return (
            float(self.nutation_longitude / self.analytic_nutation_longitude - 1),
            float(self.nutation_obliquity / self.analytic_nutation_obliquity - 1),
        )

    def to_dict(self) -> dict:
        """JSON-ready numbers (arcsec, arcsec per Julian century, years)."""

        def arcsec(q):
            return None if q is None else float(q.to_value(u.arcsec))

        def rate(q):
            return None if q is None else float(q.to_value(ARCSEC_PER_CENTURY))

        diffs = self.nutation_differences
        return {
            "axis": self.axis,
            "samples": self.samples,
            "span_years": float(self.span.to_value(u.yr)),
            "rate_arcsec_per_century": rate(self.rate),
            "rate_sigma_arcsec_per_century": rate(self.rate_sigma),
            "analytic_rate_arcsec_per_century": rate(self.analytic_rate),
            "rate_difference": self.rate_difference,
            "obliquity_deg": float(self.obliquity.to_value(u.deg)),
            "perturber": self.perturber,
            "nutation_period_years": None
            if self.nutation_period is None
            else float(self.nutation_period.to_value(u.yr)),
            "nutation_longitude_arcsec": arcsec(self.nutation_longitude),
            "nutation_longitude_sigma_arcsec": arcsec(self.nutation_longitude_sigma),
            "nutation_obliquity_arcsec": arcsec(self.nutation_obliquity),
            "nutation_obliquity_sigma_arcsec": arcsec(self.nutation_obliquity_sigma),
            "analytic_nutation_longitude_arcsec": arcsec(self.analytic_nutation_longitude),
            "analytic_nutation_obliquity_arcsec": arcsec(self.analytic_nutation_obliquity),
            "nutation_longitude_difference": None if diffs is None else diffs[0],
            "nutation_obliquity_difference": None if diffs is None else diffs[1],
            "residual_rms_longitude_arcsec": arcsec(self.residual_rms_longitude),
            "residual_rms_obliquity_arcsec": arcsec(self.residual_rms_obliquity),
            "terms_arcsec": {k: list(v) for k, v in self.terms.items()},
            "caveats": list(self.caveats),
        }

    def summary(self) -> str:
        """The measurement as text for a person."""
        d = self.to_dict()
        lines = [
            f"precession and nutation measured from the simulated {self.axis.replace('_', ' ')} "
            f"({self.samples} samples over {d['span_years']:.2f} yr)"
        ]
        line = f'  mean rate      {d["rate_arcsec_per_century"]:+.4f} +/- {d["rate_sigma_arcsec_per_century"]:.4f} "/cy'
        if self.analytic_rate is not None:
            line += (
                f'   averaged model {d["analytic_rate_arcsec_per_century"]:+.4f} "/cy '
                f"(difference {100 * self.rate_difference:+.4f} %)"
            )
        lines.append(line)
        lines.append(f"  mean obliquity {d['obliquity_deg']:.6f} deg")
        if self.nutation_longitude is not None:
            whose = f"{self.perturber}'s node" if self.perturber else "the node_rate given"
            lines.append(f"  principal nutation ({whose}, {d['nutation_period_years']:.2f} yr), IAU convention:")
            for name, key in (("Delta psi", "longitude"), ("Delta eps", "obliquity")):
                text = (
                    f'    {name} = {d[f"nutation_{key}_arcsec"]:+.5f} +/- {d[f"nutation_{key}_sigma_arcsec"]:.5f}" '
                    f"{'sin' if key == 'longitude' else 'cos'}(Omega)"
                )
                if d[f"analytic_nutation_{key}_arcsec"] is not None:
                    text += (
                        f'   first-order rigid model {d[f"analytic_nutation_{key}_arcsec"]:+.5f}" '
                        f"(difference {100 * d[f'nutation_{key}_difference']:+.3f} %)"
                    )
                lines.append(text)
        lines.append(
            f'  fit residuals (rms): {d["residual_rms_longitude_arcsec"]:.2g}" in psi, '
            f'{d["residual_rms_obliquity_arcsec"]:.2g}" in eps ({len(self.terms)} other periodic terms fitted)'
        )
        lines += [f"  caveat: {c}" for c in self.caveats]
        return "\n".join(lines)

    def to_dataset(self) -> xr.Dataset:
        """The measured and analytic values as a CF Dataset (rad and rad/s), one scalar each."""
        from wobble.api.dataset import xarray

        xr = xarray()

        def var(q, unit, long_name, **attrs):
            value = np.nan if q is None else float(q.to_value(unit))
            return xr.Variable(
                (), value, {"units": "rad s-1" if unit == _RATE else "rad", "long_name": long_name, **attrs}
            )

        return xr.Dataset(
            {
                "precession_rate": var(
                    self.rate, _RATE, "measured mean precession rate of the equator's node (negative: retrograde)"
                ),
                "precession_rate_sigma": var(self.rate_sigma, _RATE, "standard error of the measured rate"),
                "analytic_precession_rate": var(self.analytic_rate, _RATE, "first-order averaged precession rate"),
                "obliquity": var(self.obliquity, u.rad, "mean obliquity at t = 0"),
                "nutation_longitude": var(
                    self.nutation_longitude, u.rad, "principal nutation in longitude, coefficient of sin(node)"
                ),
                "nutation_obliquity": var(
                    self.nutation_obliquity, u.rad, "principal nutation in obliquity, coefficient of cos(node)"
                ),
                "analytic_nutation_longitude": var(
                    self.analytic_nutation_longitude, u.rad, "first-order rigid-body nutation in longitude"
                ),
                "analytic_nutation_obliquity": var(
                    self.analytic_nutation_obliquity, u.rad, "first-order rigid-body nutation in obliquity"
                ),
            },
            attrs={
                "title": "Precession and nutation measured from a simulated spin axis",
                "comment": f"axis: {self.axis}; principal term: {self.perturber}'s node; IAU convention for the "
                "nutation",
                "references": "Woolard 1953; Kinoshita 1977; Goldstein, Poole & Safko 2002, sec. 5.8",
            },
        )

    def __repr__(self) -> str:
        return (
            f"PrecessionMeasurement(rate={self.rate:.4f}, nutation=({self.nutation_longitude}, "
            f"{self.nutation_obliquity}))"
        )


# ---------------------------------------------------------------------------
# The measurement
# ---------------------------------------------------------------------------
def _dataset(ds):
    if isinstance(ds, (str, os.PathLike)):
        from wobble.api.dataset import load

        return load(ds)
    return ds


def _seconds(ds) -> np.ndarray:
    t = ds["time"].values
    if np.issubdtype(t.dtype, np.datetime64):
        return (t - t[0]).astype("timedelta64[ns]").astype(float) * 1e-9
    units = str(ds["time"].attrs.get("units", "seconds since"))
    if not (units.startswith("second") or units.strip() == "s"):  # "s": elapsed time past CF's calendar range
        raise InputError("ds.time", units, "times in seconds (a wobble run's output)")
    return np.asarray(t, dtype=float)


def _member(ds, member) -> int:
    """The member index, checked against the run's members (a run without a member dimension has one).

    ``member=5`` of a one-member run had been accepted, and measured member 0.
    """
    count = int(ds.sizes.get("member", 1))
    if member is None:
        return 0
    if isinstance(member, bool) or not isinstance(member, (int, np.integer)) or not 0 <= member < count:
        allowed = "0 (the run has one member)" if count == 1 else f"a whole number from 0 to {count - 1}"
        raise InputError("member", member, allowed)
    return int(member)


def _vectors(ds, axis, member):
    member = _member(ds, member)
    names = ("angular_momentum", "axis_direction") if axis is None else (axis,)
    for name in names:
        if name in ds:
            v = ds[name]
            if "member" in v.dims:
                v = v.isel(member=member)
            vec = np.asarray(v.values, dtype=float)
            return name, vec / np.linalg.norm(vec, axis=-1, keepdims=True)
    if "attitude" in ds and axis in (None, "axis_direction"):
        q = ds["attitude"]
        if "member" in q.dims:
            q = q.isel(member=member)
        return "axis_direction", quat.rotate(np.asarray(q.values, dtype=float), np.array([0.0, 0.0, 1.0]))
    raise InputError(
        "axis",
        axis or "angular_momentum, axis_direction",
        "a run with the output angular_momentum or axis_direction (or attitude)",
    )


def _scene(ds):
    from wobble.io.scene_file import scene_from_mapping

    text = ds.attrs.get("scene")
    if text is None:
        return None
    try:
        return scene_from_mapping(json.loads(text))
    except (ValueError, TypeError):
        return None


def _arguments(
    perturbers, psi0, psi_rate, span, principal=None, left_out=None, given_node=None, given=None, nyquist=math.inf
):
    """The fitted terms' (rate, phase at t = 0) in rad/s and rad, counted from the moving equinox.

    ``given_node`` (rate, phase) is the user's principal argument, in place of ``principal``'s node;
    ``given`` ({name: (rate, phase)}) the user's own terms. Both are fitted whatever their rates
    (:func:`_check_given` refuses those the span cannot separate) and come first, so that a
    perturber's term the span cannot tell from one of them is left out, as from the principal node.

    Returns (node argument or None, {name: (rate, phase)}); the names of the terms the span cannot
    separate, and of those at or past the samples' ``nyquist`` rate (which the samples see as slower
    aliases), are appended to ``left_out``.
    """
    node = None
    extra: dict = dict(given or {})
    taken: list[float] = [0.0]

    def add(name, rate, phase):
        # Leave out a term the span cannot separate from one already fitted (and the secular term).
        if name in extra:  # the user's term of that name is fitted instead, and the caveats say so
            if left_out is not None:
                left_out.append(f"{name}{_REPLACED}")
            return
        if not abs(rate) < nyquist:  # an alias of a slower term: fitting it would fit that term twice
            if left_out is not None:
                left_out.append(f"{name}{_ALIASED}")
            return
        if all(_separable(rate, r, span) for r in taken):
            extra[name] = (rate, phase)
            taken.append(rate)
        elif left_out is not None:
            left_out.append(name)

    eq0 = psi0 + math.pi  # the equinox: the descending node of the equator
    if given_node is not None:
        node = given_node
        principal = None  # its node is then a term like any other, fitted if the span separates it
    elif principal is not None:  # first, so that a term the span cannot tell from it is left out
        o = principal.orbit
        node = (o.node_rate - psi_rate, o.longitude_of_node - eq0)
    if node is not None:
        taken.append(node[0])
    _check_given(node, "node_rate" if given_node is not None else "the principal node", extra, span)
    taken.extend(r for r, _ in extra.values())
    for spec in perturbers:
        o = spec.orbit
        lam_rate = o.mean_motion + o.periapsis_rate + o.node_rate - psi_rate
        lam0 = o.longitude_of_node + o.argument_of_periapsis + o.mean_anomaly - eq0
        om_rate = o.node_rate - psi_rate
        om0 = o.longitude_of_node - eq0
        m_rate, m0 = o.mean_motion, o.mean_anomaly
        k = spec.name
        inclined = o.inclination != 0 and o.node_rate != 0
        if inclined and spec is not principal:
            add(f"Omega_{k}", om_rate, om0)
        if inclined:
            add(f"2Omega_{k}", 2 * om_rate, 2 * om0)
        add(f"2L_{k}", 2 * lam_rate, 2 * lam0)
        add(f"l_{k}", m_rate, m0)
        add(f"2L+l_{k}", 2 * lam_rate + m_rate, 2 * lam0 + m0)
        add(f"2L-l_{k}", 2 * lam_rate - m_rate, 2 * lam0 - m0)
        if inclined:
            add(f"2L-Omega_{k}", 2 * lam_rate - om_rate, 2 * lam0 - om0)
            add(f"2L-2Omega_{k}", 2 * lam_rate - 2 * om_rate, 2 * lam0 - 2 * om0)
    return node, extra


def _principal(perturbers):
    """The inclined perturber with a regressing node whose nutation is largest: GM/a^3 sin 2i / |nu|."""
    best, size = None, 0.0
    for spec in perturbers:
        o = spec.orbit
        if o.inclination != 0 and o.node_rate != 0:
            s = spec.gm / o.semi_major_axis**3 * abs(math.sin(2 * o.inclination)) / abs(o.node_rate)
            if s > size:
                best, size = spec, s
    return best


def measure_precession(
    ds, *, axis: str | None = None, member: int | None = None, node_rate=None, node_phase=None, extra=None
) -> PrecessionMeasurement:
    """Measure the mean precession rate and the principal nutation from a simulated spin axis.

    Parameters
    ----------
    ds : xarray.Dataset or path
        A run of a scene (``wobble.run``, ``wobble.run_to_netcdf``) with ``angular_momentum``
        or ``axis_direction`` (or ``attitude``), in an inertial frame whose x-y plane is the
        reference plane (the ecliptic) and x its origin of longitudes.
    axis : {"angular_momentum", "axis_direction"}, optional
        The vector to measure; default the angular momentum when present (its direction
        moves only under the torque; the figure axis adds the free and forced diurnal
        motion about it, well below an arcsecond), else the figure axis.
    member : int, optional
        The ensemble member (default the first).
    node_rate, node_phase : Quantity, optional
        The principal term's argument (rate relative to the moving equinox, phase at
        t = 0), for a run whose scene has no Keplerian perturber with a regressing node.
    extra : dict, optional
        More terms to fit: name -> (rate, phase) as Quantities. They are fitted first: a
        perturber's term the span cannot tell from one of them (rates less than one cycle over
        the span apart) is left out and named in ``caveats``, as is a perturber's term whose name one
        of them takes. A term that close to the secular rate, to the node (``node_rate`` or the
        principal perturber's) or to another of ``extra`` is refused (InputError naming ``extra``).
        Without a node, the first term carries the fit's principal argument; it is reported in
        ``terms`` with the others.

    Returns
    -------
    PrecessionMeasurement
    """
    ds = _dataset(ds)
    t = check_times(_seconds(ds))
    name, vec = _vectors(ds, axis, member)
    scene = _scene(ds)
    perturbers = [
        s for s in (scene.torques if scene is not None else ()) if isinstance(s, ThirdBody) and s.orbit is not None
    ]
    analytic = None
    if scene is not None and averaging_applies(scene.body, scene.omega0, scene.attitude0, scene.torques) is None:
        analytic = averaged_precession(scene.body, scene.omega0, scene.attitude0, scene.torques)
    psi, _ = axis_angles(vec)
    span = float(t[-1] - t[0])
    # First guess of the secular rate: the averaged model, or a straight line through psi.
    psi_rate = float(analytic.rate[0]) if analytic is not None else float(np.polyfit(t, psi, 1)[0])
    psi0 = float(psi[0])
    principal = _principal(perturbers)
    user_extra = _user_terms(extra)
    fit: PrecessionFit | None = None
    node = None
    given_node = _given_node(node_rate, node_phase)
    _check_sampling(t, given_node, user_extra)
    for _ in range(2):  # the arguments depend on the equinox's motion, which the first fit measures
        left_out: list[str] = []
        node, terms = _arguments(
            perturbers, psi0, psi_rate, span, principal, left_out, given_node, user_extra, _nyquist(t)
        )
        use_node, stand_in = node, None
        if use_node is None:
            if not terms:
                raise InputError(
                    "node_rate", None, "the argument of a periodic term (the scene has no Keplerian perturber)"
                )
            # No node: the first term carries the fit's principal argument, and is reported with the others.
            stand_in = next(iter(terms))
            use_node = terms.pop(stand_in)
        fit = fit_precession_nutation(t, vec, use_node[0], use_node[1], extra=terms)
        psi_rate = fit.rate
        psi0 = _intercept(t, psi, fit)
    arcsec = u.rad.to(u.arcsec)
    have_node = node is not None
    caveats = _caveats(t, use_node[0], left_out)
    nut = None
    if analytic is not None and principal is not None and given_node is None:  # a user's node is not the model's
        nut = dict(analytic.nutation).get(principal.name)
    return PrecessionMeasurement(
        rate=_arcsec_cy(fit.rate),
        rate_sigma=_arcsec_cy(fit.rate_sigma),
        obliquity=(fit.obliquity * u.rad).to(u.deg),
        nutation_longitude=fit.nutation_longitude * arcsec * u.arcsec if have_node else None,
        nutation_obliquity=fit.nutation_obliquity * arcsec * u.arcsec if have_node else None,
        nutation_longitude_sigma=fit.nutation_longitude_sigma * arcsec * u.arcsec if have_node else None,
        nutation_obliquity_sigma=fit.nutation_obliquity_sigma * arcsec * u.arcsec if have_node else None,
        nutation_period=(2 * math.pi / abs(node[0]) * u.s).to(u.yr) if have_node else None,
        perturber=None if principal is None or node_rate is not None else principal.name,
        axis=name,
        analytic_rate=None if analytic is None else _arcsec_cy(float(analytic.rate[0])),
        analytic_nutation_longitude=None if nut is None else nut.longitude * arcsec * u.arcsec,
        analytic_nutation_obliquity=None if nut is None else nut.obliquity * arcsec * u.arcsec,
        residual_rms_longitude=fit.residual_rms_longitude * arcsec * u.arcsec,
        residual_rms_obliquity=fit.residual_rms_obliquity * arcsec * u.arcsec,
        samples=int(t.size),
        span=(span * u.s).to(u.yr),
        terms={k: tuple(x * arcsec for x in v) for k, v in _fitted_terms(fit, stand_in).items()},
        caveats=caveats,
    )


def _given_node(node_rate, node_phase) -> tuple[float, float] | None:
    """The user's principal argument, (rate rad/s, phase rad), or None; a phase needs its rate."""
    if node_rate is None and node_phase is not None:
        raise InputError("node_phase", node_phase, "a phase only with node_rate, the argument it is the phase of")
    if node_rate is None:
        return None
    phase = node_phase if node_phase is not None else 0 * u.rad
    return to_si(node_rate, "node_rate", _RATE, shape=()), to_si(phase, "node_phase", u.rad, shape=())


def _caveats(t, principal_rate: float, left_out: list[str]) -> list[str]:
    """What limits the measurement: a span shorter than the principal term's period, and the perturbers' terms
    left out (faster than the samples' Nyquist limit, inseparable over the span, or named by a term of yours)."""
    span = float(t[-1] - t[0])
    caveats = []
    if abs(principal_rate) * span < 2 * math.pi:
        period = 2 * math.pi / abs(principal_rate) / JULIAN_YEAR
        caveats.append(
            f"the span ({span / JULIAN_YEAR:.1f} yr) is shorter than the principal term's period ({period:.1f} yr): "
            "the secular rate and that term are not separated, and both may be off by more than their formal errors"
        )
    replaced = [n.removesuffix(_REPLACED) for n in left_out if n.endswith(_REPLACED)]
    aliased = [n.removesuffix(_ALIASED) for n in left_out if n.endswith(_ALIASED)]
    apart = [n for n in left_out if not n.endswith((_REPLACED, _ALIASED))]
    if aliased:
        caveats.append(
            f"left out, faster than the samples' Nyquist limit ({_nyquist(t):.3g} rad/s): {', '.join(aliased)}"
        )
    if apart:
        caveats.append(f"left out, the span cannot separate them from the terms fitted: {', '.join(apart)}")
    if replaced:
        caveats.append(f"left out, a term of yours has their names: {', '.join(replaced)}")
    return caveats


#: How a perturber's term left out for a user's term of the same name is listed in ``left_out``.
_REPLACED = " (a term of yours has its name)"
#: Likewise, a perturber's term at or past the samples' Nyquist rate.
_ALIASED = " (past the Nyquist rate)"


def _nyquist(t) -> float:
    """pi over the largest gap between the samples (rad/s): faster motion is seen as a slower alias."""
    return math.pi / float(np.max(np.diff(t)))


def _separable(rate: float, other: float, span: float) -> bool:
    """Whether the span tells two terms apart: their rates differ by a cycle over it (|Delta rate| span >= 2 pi).

    Closer terms are nearly the same column of the least-squares design (a term and its opposite rate the
    same column up to sign): their amplitudes would come out as large, opposite and meaningless numbers with
    formal errors to match.
    """
    return abs(abs(rate) - abs(other)) * span >= 2 * math.pi


def _check_given(node, node_name: str, extra: dict, span: float) -> None:
    """Refuse a user's term the span cannot tell from the secular rate, the node (``node_name``: the user's
    ``node_rate`` or the principal perturber's) or another of theirs."""
    taken = [("the secular rate", 0.0)] + ([(node_name, node[0])] if node is not None else [])
    for name, (rate, _) in extra.items():
        for other, r in taken:
            if not _separable(rate, r, span):
                raise InputError(
                    "extra",
                    f"{name!r} at {rate:.6g} rad/s",
                    f"terms whose rates differ from {other} ({r:.6g} rad/s) and from each other by at least "
                    f"one cycle over the span, 2 pi / {span:.6g} s = {2 * math.pi / span:.3g} rad/s",
                )
        taken.append((repr(name), rate))


def _user_terms(extra) -> dict[str, tuple[float, float]]:
    """``extra``'s terms as {name: (rate rad/s, phase rad)}, each a pair of finite Quantities."""
    allowed = "a mapping name -> (rate, phase): an angular frequency and an angle as Quantities, both finite"
    if extra is None:
        return {}
    if not hasattr(extra, "items"):
        raise InputError("extra", extra, allowed)
    terms = {}
    for name, pair in extra.items():
        if not isinstance(name, str):
            raise InputError("extra", f"a term named {name!r}", "terms named by strings")
        if not (isinstance(pair, (tuple, list)) and len(pair) == 2):
            raise InputError(f"extra[{name!r}]", pair, allowed)
        rate, phase = pair
        terms[name] = (
            to_si(rate, f"extra[{name!r}] rate", _RATE, shape=()),
            to_si(phase, f"extra[{name!r}] phase", u.rad, shape=()),
        )
    return terms


def _check_sampling(t, node, extra: dict) -> None:
    """Refuse a user's rate at or past the sampling's Nyquist limit, pi over the largest gap: the samples see
    it as a slower alias, which the fit would take for another term (a node at pi/day over daily samples
    gave a nutation of -1.1e9 +/- 1.7e9 arcsec)."""
    limit = _nyquist(t)
    given = ([("node_rate", node[0])] if node is not None else []) + [
        (f"extra[{name!r}] rate", rate) for name, (rate, _) in extra.items()
    ]
    for name, rate in given:
        if not abs(rate) < limit:
            raise InputError(
                name,
                f"{rate:.6g} rad/s",
                f"rates below the samples' Nyquist limit, pi / {np.max(np.diff(t)):.6g} s = {limit:.6g} rad/s",
            )


def _fitted_terms(fit: PrecessionFit, stand_in: str | None) -> dict:
    """The fit's terms, with the one that stood in for the principal argument (when there was no node) among
    them, in the same (psi sin, psi cos, eps sin, eps cos) form: it was missing from the result."""
    if stand_in is None:
        return dict(fit.terms)
    principal = (
        fit.nutation_longitude,
        fit.nutation_longitude_out_of_phase,
        fit.nutation_obliquity_out_of_phase,
        fit.nutation_obliquity,
    )
    return {stand_in: principal, **fit.terms}


def _intercept(t, psi, fit: PrecessionFit) -> float:
    """psi at t = 0 without the periodic terms (the fit's secular line)."""
    return float(np.mean(psi - fit.rate * t))


def _arcsec_cy(rate_si: float) -> u.Quantity:
    return (rate_si << _RATE).to(ARCSEC_PER_CENTURY)
