"""Sweeps on dask: reproducible whatever the chunking and workers, streamed, validated early."""

from __future__ import annotations

import json
import math
from dataclasses import replace

import numpy as np
import pytest
import xarray as xr
from astropy import units as u

import wobble
from wobble.api.sweep import load_sweep, run_sweep, summarize_sweep, sweep
from wobble.cli import main
from wobble.errors import FileFormatError, InputError
from wobble.io.catalog import load_planet
from wobble.io.netcdf import open_wobble
from wobble.models.chandler import chandler_budget
from wobble.models.planet import Measured
from wobble.numerics import draws

MARS = {
    "schema": "wobble-sweep/1",
    "name": "mars_test",
    "target": "chandler",
    "body": "mars",
    "members": 5000,
    "seed": 7,
    "outputs": ["chandler_period", "step_period"],
    "vary": {
        "love_number_k2": {"distribution": "normal"},
        "polar_moment_factor": {"distribution": "normal"},
        "anelastic_exponent": {"distribution": "uniform", "low": 0.1, "high": 0.3},
    },
}


def test_draws_depend_only_on_seed_stream_and_member():
    whole = draws.standard_normal(3, 11, 0, 10000)
    pieces = np.concatenate([draws.standard_normal(3, 11, a, min(a + 777, 10000)) for a in range(0, 10000, 777)])
    np.testing.assert_array_equal(whole, pieces)
    assert abs(whole.mean()) < 0.05 and abs(whole.std() - 1) < 0.05
    assert not np.array_equal(whole, draws.standard_normal(3, 12, 0, 10000))  # streams differ
    u = draws.uniform(3, 11, 5, 9)
    assert ((u >= 0) & (u < 1)).all() and u.shape == (4,)


@pytest.mark.parametrize(
    ("chunk", "scheduler"),
    [(5000, "threads"), (1234, "threads"), (97, "threads"), (97, "synchronous"), (777, "processes")],
)
def test_same_seed_same_numbers_whatever_the_chunking_and_scheduler(chunk, scheduler):
    reference = run_sweep(MARS, chunk_size=5000, scheduler="synchronous")
    other = run_sweep(MARS, chunk_size=chunk, scheduler=scheduler)
    xr.testing.assert_identical(reference, other)


def test_distributed_cluster_matches_serial():
    from distributed import Client, LocalCluster

    reference = run_sweep(MARS, scheduler="synchronous")
    with LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1", dashboard_address=":0"
    ) as cluster:
        with Client(cluster) as client:
            on_cluster = run_sweep(MARS, chunk_size=600, scheduler=client)
            by_address = run_sweep(MARS, chunk_size=2000, scheduler=cluster.scheduler_address)
    xr.testing.assert_identical(reference, on_cluster)
    xr.testing.assert_identical(reference, by_address)


def test_a_model_dimension_comes_only_with_the_output_that_has_it(tmp_path):
    """Without step_period the Chandler budget's ``step`` dimension had no variable: xarray wrote its
    coordinate as a global 'coordinates' attribute, which CF does not define."""
    import netCDF4

    alone = {**MARS, "members": 50, "outputs": ["chandler_period"]}
    assert "step" not in run_sweep(alone).dims and "step" in run_sweep({**MARS, "members": 50}).dims
    path = tmp_path / "alone.nc"
    run_sweep(alone, path)
    with netCDF4.Dataset(path) as nc:
        assert "coordinates" not in nc.ncattrs() and "step" not in nc.dimensions


def test_streamed_file_equals_memory_and_is_cf(tmp_path, assert_cf_compliant):
    path = tmp_path / "mars.nc"
    in_memory = run_sweep(MARS, chunk_size=1000)
    from_file = run_sweep(MARS, path, chunk_size=1000, scheduler="processes")
    assert from_file.attrs["Conventions"] == "CF-1.10"
    xr.testing.assert_identical(from_file, in_memory.assign_attrs(from_file.attrs))
    assert_cf_compliant(path)
    with pytest.raises(wobble.OutputExistsError):
        run_sweep(MARS, path)


def test_lazy_dataset_computes_the_same():
    lazy = sweep(MARS, chunk_size=1000)
    assert lazy["chandler_period"].chunks is not None
    xr.testing.assert_identical(lazy.compute(), run_sweep(MARS, chunk_size=1000))


def test_monte_carlo_spread_matches_linear_propagation():
    # One parameter with a small uncertainty: the period is linear in it, so the Monte
    # Carlo standard deviation must equal |dT/dk2| sigma (sampling error ~ 1/sqrt(2N)).
    spec = {**MARS, "members": 40000, "vary": {"love_number_k2": {"distribution": "normal"}}}
    summary = summarize_sweep(run_sweep(spec))
    mars = load_planet("mars")[0]
    only_k2 = replace(
        mars, **{k: Measured(v.value, 0.0) for k, v in mars.measured_fields().items() if k != "love_number_k2"}
    )
    linear = chandler_budget(only_k2)
    assert summary.std == pytest.approx(linear.period_sigma / 86400, rel=0.02)
    assert summary.mean == pytest.approx(linear.period / 86400, abs=3 * summary.std / np.sqrt(40000) + 1e-3)


def test_grid_sweep_equals_the_scalar_model_point_by_point():
    spec = {
        "schema": "wobble-sweep/1",
        "name": "grid",
        "target": "chandler",
        "body": "mars",
        "outputs": ["chandler_period"],
        "vary": {
            "love_number_k2": {"distribution": "grid", "values": [0.15, 0.169, 0.19]},
            "fluid_core_radius": {"distribution": "grid", "start": 1700, "stop": 1900, "num": 5, "unit": "km"},
        },
    }
    ds = run_sweep(spec, chunk_size=4)
    assert ds["chandler_period"].dims == ("love_number_k2", "fluid_core_radius")
    # The grid is written as the file gave it (km), the model run in SI.
    assert ds.fluid_core_radius.attrs["units"] == "km" and ds.love_number_k2.attrs["units"] == "1"
    assert ds.fluid_core_radius.values.tolist() == [1700.0, 1750.0, 1800.0, 1850.0, 1900.0]
    mars = load_planet("mars")[0]
    for k2 in ds.love_number_k2.values:
        for rc in ds.fluid_core_radius.values:
            p = replace(mars, love_number_k2=Measured(k2), fluid_core_radius=Measured(rc * 1e3))
            got = float(ds["chandler_period"].sel(love_number_k2=k2, fluid_core_radius=rc))
            assert got == pytest.approx(chandler_budget(p).period / 86400, rel=1e-13)


def test_unphysical_members_are_marked_and_the_sweep_goes_on():
    spec = {**MARS, "members": 2000, "vary": {"love_number_k2": {"distribution": "normal", "mean": 0.5, "sd": 0.6}}}
    ds = run_sweep(spec)
    codes = ds["invalid_reason"].values
    assert (codes == 5).any() and (codes == 3).any() and (codes == 0).any()  # k2 < 0 and k2 > k_s
    assert np.isnan(ds["chandler_period"].values[codes != 0]).all()
    assert np.isfinite(ds["chandler_period"].values[codes == 0]).all()
    assert "softer_than_fluid" in ds["invalid_reason"].attrs["flag_meanings"]


@pytest.mark.parametrize(
    ("edit", "where", "fragment"),
    [
        ({"bogus": 1}, "bogus", "unknown key"),
        ({"vary": {"love_number": {"distribution": "normal"}}}, "vary.love_number", "unknown parameter"),
        (
            {"vary": {"love_number_k2": {"distribution": "poisson"}}},
            "vary.love_number_k2.distribution",
            "allowed: normal",
        ),
        ({"vary": {"love_number_k2": {"distribution": "uniform", "low": 1}}}, "vary.love_number_k2", "low and high"),
        ({"members": 0}, "members", "positive"),
        ({"outputs": ["nope"]}, "outputs", "allowed: chandler_period"),
        ({"target": "weather"}, "target", "allowed: chandler"),
        ({"body": "pluto"}, "body", "pluto"),
        (
            {"vary": {"love_number_k2": {"distribution": "grid", "values": [0.1]}, "j2": {"distribution": "normal"}}},
            "vary",
            "mixing",
        ),
        (
            {"vary": {"love_number_k2": {"distribution": "normal", "unit": "m"}}},
            "vary.love_number_k2.unit",
            'allowed: a pure number (unit = "" or left out)',  # it said "a unit of dimensionless"
        ),
    ],
)
def test_bad_sweeps_fail_before_any_work_naming_the_key(edit, where, fragment):
    with pytest.raises(FileFormatError) as info:
        sweep({**MARS, **edit})
    assert info.value.where == where and fragment in str(info.value)


def test_shipped_sweeps_load_and_run_small():
    from importlib import resources

    for name in ("mars_chandler", "earth_chandler"):
        path = resources.files("wobble._data") / "sweeps" / f"{name}.toml"
        spec = replace(load_sweep(str(path)), members=500)
        summary = summarize_sweep(run_sweep(spec))
        assert summary.valid >= 470  # Mars's anelastic exponent, 0.2 +- 0.1, is negative in 2.3 % of draws
        assert abs(summary.mean - summary.observed) / summary.observed < 0.02


@pytest.mark.parametrize("body", ["earth", "mars"])
def test_sweep_spread_is_the_budgets_uncertainty(body):
    """One answer (issue 15): the shipped sweep varies every parameter the budget's +/- propagates,
    so the sweep's standard deviation and the budget's agree within their sampling errors."""
    from importlib import resources

    import wobble

    path = resources.files("wobble._data") / "sweeps" / f"{body}_chandler.toml"
    members = 40_000
    summary = summarize_sweep(run_sweep(replace(load_sweep(str(path)), members=members)))
    budget = wobble.chandler_budget(body)
    sigma = budget.period_uncertainty.to_value("day")
    # Standard errors of a standard deviation: sd / sqrt(2 (n - 1)) for each estimate.
    se = np.hypot(summary.std / np.sqrt(2 * (summary.valid - 1)), sigma / np.sqrt(2 * (100_000 - 1)))
    assert abs(summary.std - sigma) < 4 * se, (summary.std, sigma, se)
    # The linear propagation is the first-order term of the same thing, and nearly equal to it.
    linear = budget.period_uncertainty_linear.to_value("day")
    assert abs(linear / sigma - 1) < 0.1


def test_cli_summary_json_plot_and_errors(tmp_path, capsys):
    out = tmp_path / "m.nc"
    status = main(
        ["sweep", "mars_chandler", "--members", "300", "-o", str(out), "--json", "--plot", str(tmp_path / "h.png")]
    )
    captured = capsys.readouterr()
    # No progress bar when stderr is not a terminal; under --json the files written are announced there.
    assert status == 0 and captured.err.splitlines() == [f"wrote {out}", f"wrote {tmp_path / 'h.png'}"]
    data = json.loads(captured.out)
    assert data["members"] == 300 and data["unit"] == "d" and data["observed"] == pytest.approx(206.9)
    assert data["units"] == "day"  # the old key, as it was, for one release
    assert open_wobble(out)["chandler_period"].shape == (300,)
    assert (tmp_path / "h.png").stat().st_size > 1000
    status = main(["sweep", "mars_chandler", "--members", "300", "-o", str(out)])
    err = capsys.readouterr().err
    assert status == 2 and "--overwrite" in err and err.count("\n") == 1
    status = main(["sweep", "no_such_sweep"])
    err = capsys.readouterr().err
    assert status == 2 and "SWEEP: got no_such_sweep; allowed: an existing file" in err and "mars_chandler.toml" in err


def test_a_shipped_sweep_loads_by_name_in_python_as_on_the_command_line(tmp_path, monkeypatch):
    # Was: wobble.run_sweep("mars_chandler") raised "no such file" while `wobble sweep mars_chandler` ran.
    from wobble.io.shipped import find_shipped

    by_name = load_sweep("mars_chandler")
    assert by_name == load_sweep(find_shipped("mars_chandler", "sweeps", (".toml",)).path())
    # A file of the user's with that name wins, as on the command line.
    monkeypatch.chdir(tmp_path)
    (tmp_path / "mars_chandler").write_text("not a sweep")
    with pytest.raises(FileFormatError):
        load_sweep("mars_chandler")


def test_members_without_a_finite_output_are_counted_apart_from_the_invalid(capsys):
    """The top phase diagram: upright tops (theta0 = 0) spun below the sleeping threshold have no nutation
    period (inf) but nothing invalid; the summary said 45850 valid of 45955 with no reason for the 105."""
    ds = run_sweep("top_phase_diagram")
    s = summarize_sweep(ds)
    period = ds["nutation_period"]
    missing = (ds["invalid_reason"] == 0) & ~np.isfinite(period)
    assert s.not_finite == int(missing.sum()) > 0 and s.valid + s.not_finite == s.members - sum(
        s.invalid_reasons.values()
    )
    assert bool((ds["theta0"].broadcast_like(period).where(missing) == 0).sum() == missing.sum())
    assert not bool(ds["sleeping_stable"].where(missing, False).astype(bool).any())  # below the threshold
    assert s.not_finite_classes == {"sleeping": s.not_finite}
    assert main(["sweep", "top_phase_diagram"]) == 0
    assert f"no finite nutation_period: {s.not_finite} (sleeping {s.not_finite})" in capsys.readouterr().out


def test_sweep_parameter_units_are_written_as_the_other_files_write_them():
    """UDUNITS-style products of powers (``m3 kg-1 s-2``, as every other wobble file), not astropy's
    ``m3 / (kg s2)``; each reads back as the same unit."""
    from astropy import units as u

    from wobble.api.sweep_targets import _unit_text
    from wobble.io.catalog import PLANET_UNITS

    for key, unit in PLANET_UNITS.items():
        text = _unit_text(key)
        assert "/" not in text and "(" not in text, (key, text)
        assert u.Unit(text if text != "1" else "") == unit, key


def test_members_whose_scales_leave_the_float_range_are_invalid_not_warned(tmp_path, capsys):
    """A sweep bypassed the planet file's scale check (a review): spins of 1e-300 and 1e300 rad/s printed NumPy's
    overflow warnings, an infinite spread and a valid member with a period of 2e298 d. They are invalid members
    now, as a planet file with those values is refused; Earth's own spin is the one valid member, at the period
    wobble chandler earth gives."""
    spec = tmp_path / "spin_grid.toml"
    spec.write_text(
        'schema = "wobble-sweep/1"\nname = "spin_grid"\ntarget = "chandler"\nbody = "earth"\nmodel = "full"\n'
        'seed = 1\noutputs = ["chandler_period"]\n\n[vary.rotation_rate]\ndistribution = "grid"\n'
        'values = [7.292115e-5, 1e-160, 1e160, 1e-300, 1e300]\nunit = "rad/s"\n'
    )
    assert main(["sweep", str(spec), "--json", "--quiet"]) == 0
    captured = capsys.readouterr()
    assert captured.err == ""
    data = json.loads(captured.out)
    assert (data["members"], data["valid"]) == (5, 1)
    # Against nature: the observed Chandler period the catalogue cites (a published value), within the model's
    # and the observation's sigma together (a model 10 % too soft, 460 d, fails); and the same member as the budget.
    budget = wobble.chandler_budget("earth")
    observed, sigma = (
        budget.observed.to_value(u.day),
        math.hypot(budget.period_uncertainty.to_value(u.day), budget.observed_uncertainty.to_value(u.day)),
    )
    assert abs(data["percentiles"]["50"] - observed) < 2 * sigma
    assert data["percentiles"]["50"] == pytest.approx(budget.period.to_value(u.day), rel=1e-6)


@pytest.mark.parametrize("chunk_size", [0, -5, 10.5, True])
def test_a_chunk_size_that_is_not_a_positive_integer_is_refused(chunk_size):
    """chunk_size=0 was read as 'not given' and ran with the default, while 10.5 was refused."""
    with pytest.raises(InputError, match=r"^chunk_size: got .*; allowed: a positive integer"):
        wobble.sweep("mars_chandler", chunk_size=chunk_size)


def test_numbers_for_a_parameter_with_a_dimension_need_their_unit():
    """A core radius of 5000 without a unit was read in SI, a 5 m core, without a word (the planet file gives
    it in km); a pure number (k2, the anelastic exponent) needs none, and the catalogue's own values none."""
    core = {**MARS, "members": 50, "vary": {"fluid_core_radius": {"distribution": "normal", "mean": 1800, "sd": 50}}}
    with pytest.raises(
        FileFormatError,
        match=r"vary\.fluid_core_radius\.unit: missing; allowed: the unit of the "
        r"numbers given \(a unit of length",
    ):
        run_sweep(core)
    core["vary"]["fluid_core_radius"]["unit"] = "kg"  # said "allowed: a unit of m"
    with pytest.raises(FileFormatError, match=r"unit: got 'kg'; allowed: a unit of length \(e\.g\. m\)$"):
        run_sweep(core)
    core["vary"]["fluid_core_radius"]["unit"] = "km"
    drawn = run_sweep(core)["fluid_core_radius"]
    assert drawn.attrs["units"] == "km" and "normal(mean=1800, sd=50) in km" in drawn.attrs["comment"]
    assert abs(drawn.values.mean() - 1800) < 4 * 50 / math.sqrt(50)
    catalogued = {**MARS, "members": 50, "vary": {"love_number_k2": {"distribution": "normal"}}}
    assert run_sweep(catalogued).sizes["member"] == 50
    top = {
        "schema": "wobble-sweep/1",
        "name": "t",
        "target": "heavy_top",
        "base": {k: {"value": 1.0, "unit": un, "uncertainty": 0} for k, un in (("I1", "kg m2"), ("mgl", "J"))}
        | {"I3": {"value": 0.5, "unit": "kg m2", "uncertainty": 0}},
        "vary": {
            "theta0": {"distribution": "grid", "values": [30, 60]},
            "omega3": {"distribution": "grid", "values": [10.0], "unit": "rad/s"},
            "phidot0": {"distribution": "grid", "values": [0.0], "unit": "rad/s"},
        },
    }
    with pytest.raises(FileFormatError, match=r"vary\.theta0\.unit: missing"):
        run_sweep(top)


def test_a_grid_sweep_is_summarised_by_its_range():
    """A grid's members are chosen points: its summary gives their range (min, max of the grid's values) and
    the text no 'sd from the mean' (it printed the observed period '-0.01 sd' from a grid's mean)."""
    grid = {**MARS, "vary": {"love_number_k2": {"distribution": "grid", "values": [0.15, 0.17, 0.19]}}}
    grid.pop("members")
    ds = run_sweep(grid)
    s = summarize_sweep(ds)
    periods = ds["chandler_period"].values
    assert s.grid and (s.minimum, s.maximum) == (periods.min(), periods.max()) and s.members == 3
    assert "over the grid" in s.summary() and "sd from the mean" not in s.summary()
    assert not summarize_sweep(run_sweep({**MARS, "members": 50})).grid
