"""The CF Datasets of a polar-motion analysis: the record with its model, the windows, the spectrum, the estimates."""

from __future__ import annotations

import math

import numpy as np
from astropy import units as u

from wobble.api.polar_motion.record import (
    C04_REFERENCE,
    MJD_J2000,
    MJD_UNITS,
    RAD_PER_ARCSEC,
    SIGN_NOTE,
    attrs,
    mjd_values,
    series,
)
from wobble.io.cf import udunits
from wobble.io.dates import iso_date
from wobble.models import polar_motion as _pm

__all__ = ["analysis_dataset", "window_columns", "window_attrs", "windows_dataset", "spectrum_dataset"]

# The parts of the Chandler period's uncertainty (ChandlerEstimate.period_uncertainty_parts), in
# the order the file lists them, with their long_name.
_PERIOD_UNCERTAINTY_PARTS = {
    "formal": "white-noise (formal) uncertainty of the period, far too small",
    "autocorrelation": "period uncertainty from the residuals' autocorrelation",
    "subspans": "period uncertainty from the scatter over sub-spans",
    "excitation": "period uncertainty of a randomly excited wobble (Monte Carlo)",
    "model": "period uncertainty from the drift model",
}


def window_columns(wf: _pm.WindowedFits) -> dict[str, np.ndarray]:
    """The sliding-window fits in the units of their Dataset (MJD, mas, days, degrees), as plain arrays.

    The numbers of :func:`windows_dataset`, for the JSON and the text report, which need no xarray.
    """
    rad_mas = 1.0 / (RAD_PER_ARCSEC * 1e-3)
    day = 1.0 / _pm.DAY
    return {
        "window_time": MJD_J2000 + wf.centre / _pm.DAY,
        "window_time_bounds": np.stack([MJD_J2000 + wf.start / _pm.DAY, MJD_J2000 + wf.end / _pm.DAY], axis=1),
        "chandler_amplitude": wf.amplitude * rad_mas,
        "chandler_amplitude_uncertainty": wf.amplitude_sigma * rad_mas,
        "chandler_period": wf.period * day,
        "chandler_period_uncertainty": wf.period_sigma * day,
        "chandler_phase": np.degrees(wf.phase),
        "annual_prograde_amplitude": wf.annual_prograde_amplitude * rad_mas,
        "annual_prograde_amplitude_uncertainty": wf.annual_prograde_amplitude_sigma * rad_mas,
        "annual_retrograde_amplitude": wf.annual_retrograde_amplitude * rad_mas,
        "window_samples": wf.n_samples.astype(np.int32),
    }


def window_attrs(wf: _pm.WindowedFits) -> dict[str, float]:
    """``window_years`` and ``step_years`` of the windows (the attributes of :func:`windows_dataset`)."""
    return {"window_years": wf.window / _pm.JULIAN_YEAR, "step_years": wf.step / _pm.JULIAN_YEAR}


def windows_dataset(wf: _pm.WindowedFits):
    """The sliding-window fits as a Dataset on the ``window`` dimension."""
    from wobble.api.dataset import xarray

    xr = xarray()
    c = window_columns(wf)
    note = (
        "least-squares fit of drift, Chandler and annual terms in each window; uncertainty from the residuals' "
        "autocorrelation and the drift model"
    )
    return xr.Dataset(
        {
            "chandler_amplitude": (
                "window",
                c["chandler_amplitude"],
                attrs("milliarcsecond", "Chandler wobble amplitude in the window", comment=note),
            ),
            "chandler_amplitude_uncertainty": (
                "window",
                c["chandler_amplitude_uncertainty"],
                attrs("milliarcsecond", "one-sigma uncertainty of the windowed Chandler amplitude"),
            ),
            "chandler_period": (
                "window",
                c["chandler_period"],
                attrs("day", "Chandler wobble period in the window", comment=note),
            ),
            "chandler_period_uncertainty": (
                "window",
                c["chandler_period_uncertainty"],
                attrs("day", "one-sigma uncertainty of the windowed Chandler period"),
            ),
            "chandler_phase": (
                "window",
                c["chandler_phase"],
                attrs("degree", "argument of the Chandler term of x_p - i y_p at the window's centre"),
            ),
            "annual_prograde_amplitude": (
                "window",
                c["annual_prograde_amplitude"],
                attrs("milliarcsecond", "prograde annual wobble amplitude in the window"),
            ),
            "annual_prograde_amplitude_uncertainty": (
                "window",
                c["annual_prograde_amplitude_uncertainty"],
                attrs("milliarcsecond", "one-sigma uncertainty of the windowed prograde annual amplitude"),
            ),
            "annual_retrograde_amplitude": (
                "window",
                c["annual_retrograde_amplitude"],
                attrs("milliarcsecond", "retrograde annual wobble amplitude in the window"),
            ),
            "window_samples": (
                "window",
                c["window_samples"],
                attrs("1", "number of daily samples in the window"),
            ),
            # CF 7.1: a boundary variable is part of its coordinate's metadata and takes its units,
            # calendar and meaning from it; it has no long_name of its own (IOOS's checker flagged one that
            # differed from the coordinate's) and no fill value (the writer gives bounds none). A data
            # variable, not a coordinate: no variable has its (window, nv), so xarray wrote a coordinate
            # of it into a global 'coordinates' attribute, which CF does not define.
            "window_time_bounds": (("window", "nv"), c["window_time_bounds"]),
        },
        coords={
            # No standard_name "time": the record's time axis has it, and a second one made
            # cf_xarray's ds.cf["T"] ambiguous; the units ("days since ...") make this a time all the same.
            "window_time": (
                "window",
                c["window_time"],
                {
                    "units": MJD_UNITS,
                    "calendar": "standard",
                    "long_name": "centre of the window (UTC)",
                    "bounds": "window_time_bounds",
                },
            ),
        },
        attrs=window_attrs(wf),
    )


def spectrum_dataset(sp: _pm.Spectrum):
    """The two-sided amplitude spectrum as a Dataset on the ``frequency`` dimension."""
    from wobble.api.dataset import xarray

    xr = xarray()
    rad_mas = 1.0 / (RAD_PER_ARCSEC * 1e-3)
    # Cycles per Julian year, as the excitation's spectrum (one name, one unit in every file)
    freq = sp.rate / (2 * math.pi) * _pm.JULIAN_YEAR
    return xr.Dataset(
        {
            "amplitude_spectrum": (
                "frequency",
                sp.amplitude * rad_mas,
                attrs(
                    "milliarcsecond",
                    "two-sided amplitude spectrum of the detrended complex pole x_p - i y_p",
                    comment=f"radius of a circular term at each frequency; taper: {sp.taper}; drift polynomial "
                    f"degree {sp.drift_degree} removed",
                ),
            )
        },
        coords={
            "frequency": (
                "frequency",
                freq,
                attrs(
                    udunits("1/yr"), "frequency in cycles per Julian year (positive: prograde, negative: retrograde)"
                ),
            )
        },
    )


def _pole_in_mas(var):
    """A pole variable in mas (converted from its ``units``, which become ``milliarcsecond``)."""
    from wobble.api.dataset import quantity

    if var.attrs.get("units") == "milliarcsecond":
        return var
    return var.copy(data=quantity(var).to_value(u.mas)).assign_attrs(units="milliarcsecond")


def analysis_dataset(a):
    """The Dataset of ``PolarMotionAnalysis.to_dataset()``."""
    from wobble.api.dataset import xarray

    xr = xarray()
    ds = _record_and_fit(a)
    # The windowed estimates share names with the whole-span ones (on "method"):
    # in the file they carry a window_ prefix, so neither hides the other.
    windows = a.windows.rename({v: f"window_{v}" for v in a.windows.data_vars if not v.startswith("window_")})
    ds = xr.merge([ds, windows, a.spectrum], combine_attrs="drop_conflicts")
    ds = _estimates(ds, [a.least_squares, a.spectral], a.caveats)
    ds = _model_and_published(ds, a)
    if a.quality_factor_estimate is not None:
        ds = _quality_factor(ds, a.quality_factor_estimate)
    ds.attrs = _analysis_attrs(a)
    return ds


def _record_and_fit(a):
    """The record's pole on the fitted days, with the least-squares model, its residuals and the mean pole (mas)."""
    mjd, t, z = series(a.data)
    fit = a.least_squares.raw
    model = fit.model(t)
    mean = fit.mean_pole(t)
    mas = 1.0 / (RAD_PER_ARCSEC * 1e-3)

    def xy(p):
        x, y = _pm.pole_xy(p)
        return x * mas, y * mas

    mx, my = xy(model)
    rx, ry = xy(z - model)
    px, py = xy(mean)
    observed = a.data.isel(time=np.nonzero(np.isin(mjd_values(a.data["time"]), mjd))[0])[
        ["x_p", "y_p", "x_p_error", "y_p_error"]
    ]
    # The pole in mas, as every wobble file writes it, whatever unit a Dataset of the caller's own gave.
    observed = observed.assign({name: _pole_in_mas(observed[name]) for name in observed.data_vars})
    ls_note = "nonlinear least-squares fit of drift, Chandler and annual terms (wobble.models.polar_motion)"
    ds = observed.assign(
        x_p_model=("time", mx, attrs("milliarcsecond", "fitted model of x_p", comment=ls_note)),
        y_p_model=("time", my, attrs("milliarcsecond", "fitted model of y_p", comment=ls_note)),
        x_p_residual=("time", rx, attrs("milliarcsecond", "x_p minus its fitted model")),
        y_p_residual=("time", ry, attrs("milliarcsecond", "y_p minus its fitted model")),
        x_p_mean_pole=("time", px, attrs("milliarcsecond", "x_p of the fitted mean-pole drift")),
        y_p_mean_pole=("time", py, attrs("milliarcsecond", "y_p of the fitted mean-pole drift")),
    )
    return ds


def _estimates(ds, methods, caveats):
    """The Chandler and annual estimates of each method (least squares, spectrum) on ``method``."""

    def per_method(fn):
        return np.array([fn(e) for e in methods], dtype=float)

    est = {
        "chandler_period": ("day", "Chandler wobble period", lambda e: e.period.to_value(u.day)),
        "chandler_period_uncertainty": (
            "day",
            "adopted one-sigma uncertainty of the Chandler period",
            lambda e: e.period_uncertainty.to_value(u.day),
        ),
        **{
            f"chandler_period_uncertainty_{part}": (
                "day",
                long_name,
                lambda e, part=part: e.period_uncertainty_parts[part].to_value(u.day),
            )
            for part, long_name in _PERIOD_UNCERTAINTY_PARTS.items()
        },
        "chandler_amplitude": (
            "milliarcsecond",
            "Chandler wobble amplitude over the span",
            lambda e: e.amplitude.to_value(u.mas),
        ),
        "chandler_amplitude_uncertainty": (
            "milliarcsecond",
            "one-sigma uncertainty of the Chandler amplitude",
            lambda e: e.amplitude_uncertainty.to_value(u.mas),
        ),
        "chandler_phase": (
            "degree",
            "argument of the Chandler term of x_p - i y_p at the epoch",
            lambda e: e.phase.to_value(u.deg),
        ),
        "annual_prograde_amplitude": (
            "milliarcsecond",
            "prograde annual wobble amplitude",
            lambda e: e.annual_prograde_amplitude.to_value(u.mas),
        ),
        "annual_prograde_amplitude_uncertainty": (
            "milliarcsecond",
            "one-sigma uncertainty of the prograde annual amplitude",
            lambda e: e.annual_prograde_amplitude_uncertainty.to_value(u.mas),
        ),
        "annual_retrograde_amplitude": (
            "milliarcsecond",
            "retrograde annual wobble amplitude",
            lambda e: e.annual_retrograde_amplitude.to_value(u.mas),
        ),
        "annual_retrograde_amplitude_uncertainty": (
            "milliarcsecond",
            "one-sigma uncertainty of the retrograde annual amplitude",
            lambda e: e.annual_retrograde_amplitude_uncertainty.to_value(u.mas),
        ),
    }
    for name, (unit, long_name, fn) in est.items():
        ds[name] = ("method", per_method(fn), attrs(unit, long_name))
    # Whether each method resolves a Chandler term (the period at the search band's edge, or a least-squares term
    # that cannot be told from the annual ones, is the search's, not the wobble's; the caveats say which).
    ds["chandler_resolved"] = (
        "method",
        np.array([e.resolved for e in methods], dtype=np.int8),
        {
            "units": "1",  # as every numeric variable, and the sweeps' invalid_reason flags
            "long_name": "whether the span resolves a Chandler term",
            "flag_values": np.array([0, 1], dtype=np.int8),
            "flag_meanings": "not_resolved resolved",
            # The caveats, when there are any (an empty comment is a compliance checker's complaint).
            **({"comment": "; ".join(caveats)} if caveats else {}),
        },
    )
    ds = ds.assign_coords(method=("method", [e.method for e in methods], {"long_name": "estimation method"}))
    ds["epoch"] = (
        (),
        float(methods[0].epoch.mjd),  # the least squares' mid-span
        {"units": MJD_UNITS, "calendar": "standard", "long_name": "epoch of the phases (mid-span)"},
    )
    return ds


def _model_and_published(ds, a):
    """The Chandler budget's period after each model step beside the observed and published periods."""
    rows = a.comparison()
    model_rows = [r for r in rows if r["kind"] == "model"]
    ds = ds.assign_coords(
        model_step=(
            "model_step",
            [r["name"].removeprefix("model: ") for r in model_rows],
            {"long_name": "step of the Chandler model of wobble.chandler_budget('earth')"},
        )
    )
    ds["model_period"] = (
        "model_step",
        np.array([r["period"].to_value(u.day) for r in model_rows]),
        attrs("day", "modelled Chandler period after each model step"),
    )
    ds["model_minus_observed"] = (
        "model_step",
        # NaN where the least squares resolve no Chandler term (nothing observed to compare with).
        np.array([np.nan if r["residual"] is None else r["residual"].to_value(u.day) for r in model_rows]),
        attrs("day", "modelled minus observed (least-squares) Chandler period"),
    )
    ds["model_period_uncertainty"] = (
        (),
        a.budget.period_uncertainty.to_value(u.day),
        attrs("day", "one-sigma uncertainty of the full model's period"),
    )
    pub = a.published
    ds["published_period"] = (
        (),
        pub["period"].to_value(u.day),
        attrs("day", "published Chandler period", references=pub["reference"]),
    )
    ds["published_period_uncertainty"] = (
        (),
        pub["uncertainty"].to_value(u.day),
        attrs("day", "one-sigma uncertainty of the published Chandler period"),
    )
    return ds


def _quality_factor(ds, q):
    """The maximum-likelihood Q of the Chandler line and its intervals."""
    ds["quality_factor"] = (
        (),
        q.value,
        attrs("1", "maximum-likelihood Q of the Chandler line (inf: unresolved)", comment="; ".join(q.caveats)),
    )
    ds["quality_factor_low"] = ((), q.low, attrs("1", "lower end of the 68 % interval of Q"))
    ds["quality_factor_high"] = ((), q.high, attrs("1", "upper end of the 68 % interval of Q (inf: unbounded)"))
    ds["quality_factor_lower_bound_95"] = ((), q.lower_bound_95, attrs("1", "one-sided 95 % lower bound of Q"))
    return ds


def _analysis_attrs(a) -> dict:
    """The file's global attributes: title, summary of the estimates, references, source and sign convention."""
    e = a.least_squares
    return {
        "title": "Observed polar motion and the Chandler wobble",
        "summary": (
            f"Chandler period {e.period.value:.1f} +/- {e.period_uncertainty.value:.1f} d and amplitude "
            f"{e.amplitude.value:.0f} +/- {e.amplitude_uncertainty.value:.0f} mas (least squares"
            f"{'' if e.resolved else '; not resolved: ' + e.unresolved_because}), "
            f"{a.spectral.period.value:.1f} +/- {a.spectral.period_uncertainty.value:.1f} d (spectrum"
            f"{'' if a.spectral.resolved else '; not resolved: ' + a.spectral.unresolved_because}), "
            f"{iso_date(e.start)} to {iso_date(e.end)}"
        ),
        "references": "; ".join([a.data.attrs.get("references", C04_REFERENCE), a.published["reference"]]),
        "source_file": a.source_file or "",
        "comment": SIGN_NOTE
        + ". Days are days of 86400 s. Windows: "
        + f"{a.windows.attrs['window_years']:g} yr every {a.windows.attrs['step_years']:g} yr.",
    }
