"""The tumbling-asteroid ensemble against the single-member exact solution and the symmetric closed forms."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from astropy import units as u

import wobble
from wobble.api.sweep import run_sweep
from wobble.errors import FileFormatError
from wobble.models.free import free_rotation
from wobble.models.free_ensemble import free_ensemble

SPEC = {
    "schema": "wobble-sweep/1",
    "name": "ast_test",
    "target": "free_rotation",
    "members": 3000,
    "seed": 11,
    "base": {"moment_a": {"value": 1e17, "unit": "kg m2"}, "final_time": {"value": 10.0, "unit": "d"}},
    "vary": {
        "moment_ratio_ba": {"distribution": "uniform", "low": 1.0, "high": 3.0},
        "moment_ratio_cb": {"distribution": "uniform", "low": 1.0, "high": 1.5},
        "spin_period": {"distribution": "uniform", "low": 24.0, "high": 240.0, "unit": "h"},
        "spin_cos_colatitude": {"distribution": "uniform", "low": -1.0, "high": 1.0},
        "spin_longitude": {"distribution": "uniform", "low": 0.0, "high": 360.0, "unit": "deg"},
    },
}


@pytest.fixture(scope="module")
def ens():
    return run_sweep(SPEC, chunk_size=700)


def _si(var, unit):
    """A drawn value in ``unit``: the sweep writes draws in the unit the file gave (h, deg)."""
    return float(wobble.quantity(var).to_value(unit))


def _member(ds, j):
    m = ds.isel(member=j)
    ia = 1e17
    ib = ia * float(m.moment_ratio_ba)
    ic = ib * float(m.moment_ratio_cb)
    cz, lon = float(m.spin_cos_colatitude), _si(m.spin_longitude, u.rad)
    sz = np.sqrt(1 - cz * cz)
    w = 2 * np.pi / _si(m.spin_period, u.s) * np.array([sz * np.cos(lon), sz * np.sin(lon), cz])
    return (ia, ib, ic), w


def test_members_agree_with_the_single_member_exact_solution(ens):
    codes = {"major-axis": 1, "minor-axis": 2}
    checked = 0
    for j in range(0, ens.sizes["member"], 97):
        moments, w = _member(ens, j)
        m = ens.isel(member=j)
        if int(m.invalid_reason):
            assert moments[0] + moments[1] < moments[2] and int(m.regime) == -1
            with pytest.raises(wobble.InputError):
                free_rotation(moments, w)
            continue
        model = free_rotation(moments, w)
        assert int(m.regime) == codes[model.regime]
        np.testing.assert_allclose(float(m.nutation_period), model.period, rtol=1e-13)
        np.testing.assert_allclose(
            m.omega_final.values, model.omega(10 * 86400.0), rtol=0, atol=1e-13 * np.linalg.norm(w)
        )
        # The wobble angle (circulation axis against L) over one period, sampled densely.
        t = np.linspace(0, model.period, 4001)
        om = model.omega(t)
        ll = np.asarray(moments) * om
        ax = 2 if int(m.regime) == 1 else 0
        ang = np.arccos(np.abs(ll[:, ax]) / np.linalg.norm(ll, axis=1))
        assert ang.min() >= float(m.wobble_angle_min) - 1e-9 and ang.max() <= float(m.wobble_angle_max) + 1e-9
        np.testing.assert_allclose(
            [ang.min(), ang.max()], [float(m.wobble_angle_min), float(m.wobble_angle_max)], atol=2e-6
        )
        # Mean precession rate: the mean of Landau & Lifshitz's phidot (eq. 37.14) over a period.
        a, b = [k for k in range(3) if k != ax]
        ia, ib = moments[a], moments[b]
        phidot = (
            np.linalg.norm(ll[0])
            * (ia * om[:, a] ** 2 + ib * om[:, b] ** 2)
            / (ia**2 * om[:, a] ** 2 + ib**2 * om[:, b] ** 2)
        )
        np.testing.assert_allclose(2 * np.pi / float(m.precession_period), phidot[:-1].mean(), rtol=1e-9)
        checked += 1
    assert checked > 20


def test_symmetric_members_match_the_notes_closed_forms():
    # Oblate I1 = I2 < I3: Omega = (I3 - I1) omega3 / I1, free precession L / I1, constant cone angle.
    moments = np.array([[2.0, 2.0, 3.0], [1.0, 3.0, 3.0]])
    omega = np.array([[0.1, 0.2, 0.5], [0.3, 0.1, 0.2]])
    res = free_ensemble(moments, omega, 5.0)
    big_l = np.linalg.norm(moments * omega, axis=1)
    np.testing.assert_allclose(res["nutation_period"][0], 2 * np.pi / ((3.0 - 2.0) * 0.5 / 2.0), rtol=1e-14)
    np.testing.assert_allclose(res["precession_rate"], [big_l[0] / 2.0, big_l[1] / 3.0], rtol=1e-13)
    np.testing.assert_allclose(res["wobble_angle_min"][0], np.arccos(3.0 * 0.5 / big_l[0]), rtol=1e-13)
    np.testing.assert_allclose(res["wobble_angle_max"][0], res["wobble_angle_min"][0], rtol=1e-13)
    assert res["regime"].tolist() == [1, 2]  # oblate: short-axis mode; prolate: long-axis mode
    np.testing.assert_allclose(res["omega_final"][0], free_rotation(moments[0], omega[0]).omega(5.0), atol=1e-15)


def test_triangle_violations_are_flagged_and_others_unaffected(ens):
    ds = ens
    ratio_ba, ratio_cb = ds.moment_ratio_ba.values, ds.moment_ratio_cb.values
    violates = 1 + ratio_ba < ratio_ba * ratio_cb
    assert violates.any()
    np.testing.assert_array_equal(ds.invalid_reason.values == 1, violates)
    assert np.isnan(ds.precession_period.values[violates]).all()
    assert np.isfinite(ds.precession_period.values[~violates]).all()
    summary = wobble.summarize_sweep(ds)
    assert summary.variable == "precession_period" and summary.valid == int((~violates).sum())
    assert set(summary.classes) == {"steady", "major-axis", "minor-axis", "separatrix"}


def test_reproducible_whatever_the_chunking_and_scheduler(ens):
    xr.testing.assert_identical(ens, run_sweep(SPEC, chunk_size=3000, scheduler="synchronous"))
    xr.testing.assert_identical(ens, run_sweep(SPEC, chunk_size=1111, scheduler="processes"))


def test_shipped_ensemble_streams_in_bounded_memory(tmp_path, assert_cf_compliant):
    import tracemalloc
    from dataclasses import replace

    spec = wobble.load_sweep("data/sweeps/tumbling_asteroids.toml")
    assert spec.members == 100_000
    small = replace(spec, members=40_000)
    tracemalloc.start()
    ds = run_sweep(small, tmp_path / "ast.nc", chunk_size=5000)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    # 40000 members x ~15 doubles = 5 MB of results; chunks of 5000 keep the peak far below
    # what holding every intermediate of every member would take.
    assert peak < 60e6
    assert ds.sizes["member"] == 40_000 and ds.omega_final.dims == ("member", "body_axis")
    assert_cf_compliant(tmp_path / "ast.nc")


def test_bad_parameter_names_fail_before_any_work():
    bad = {**SPEC, "vary": {**SPEC["vary"], "spin_axis": {"distribution": "uniform", "low": 0.0, "high": 1.0}}}
    with pytest.raises(FileFormatError, match="vary.spin_axis.*allowed: moment_a"):
        wobble.sweep(bad)
    missing = {**SPEC, "vary": {k: v for k, v in SPEC["vary"].items() if k != "spin_period"}}
    with pytest.raises(FileFormatError, match="missing spin_period"):
        wobble.sweep(missing)


def test_the_ensemble_figure_of_an_ensemble_without_a_valid_member(tmp_path):
    """A file whose spin directions are all out of range (fuzz seed 311: cos colatitude from -1e100) gave no
    valid member: the figure warned "Mean of empty slice" and called every invalid member a triangle
    violation. It now says there is none to draw, and counts each reason."""
    from wobble.plot.sweep import ensemble

    cos = {"distribution": "uniform", "low": 2.0, "high": 3.0}
    bad = {**SPEC, "members": 40, "vary": {**SPEC["vary"], "spin_cos_colatitude": cos}}
    ds = run_sweep(bad)
    fig = ensemble(ds, tmp_path / "none.png")
    texts = [t.get_text() for ax in fig.axes for t in ax.texts]
    assert "no member with a finite precession period" in texts
    title = fig.axes[0].get_legend().get_title().get_text()
    counts = {code: int(np.sum(ds["invalid_reason"].values == code)) for code in (1, 2)}
    assert title.startswith("invalid: ") and f"{counts[2]:,} (bad moments or spin)" in title
    assert (tmp_path / "none.png").stat().st_size > 0
    good = ensemble(run_sweep({**SPEC, "members": 40}))
    assert "no member" not in [t.get_text() for ax in good.axes for t in ax.texts]


def test_the_ensemble_scatter_names_its_colours_where_no_member_can_be():
    """The right panel had no legend; it sits below the diagonal, where wobble angle max < min is impossible."""
    from wobble.plot.sweep import ensemble

    ax = ensemble(run_sweep({**SPEC, "members": 200})).axes[1]
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any(label.startswith("major-axis") for label in labels) and ax.get_legend()._loc == 4  # lower right
    # 200 members are all drawn: the title said "4000 members each" whatever the ensemble held.
    assert ax.get_title() == "angle between circulation axis and L (every member)"
