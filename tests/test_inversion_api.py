"""wobble.invert, its InferenceData file, the setups, and ``wobble invert`` on the command line.

Short runs (a few hundred steps) keep these fast; they are meant to test the plumbing,
the file round trip, the diagnostics' warnings and the refusals, not the science
(scripts/calibrate_inversion.py and docs/inversion.md do that at full size).
"""

from __future__ import annotations

import copy
import json
import tomllib
from importlib import resources

import netCDF4
import numpy as np
import pytest

import wobble
from wobble.cli import main
from wobble.errors import FileFormatError, InputError, OutputExistsError

SHORT = dict(steps=200, burn=100, walkers=16)


@pytest.fixture(scope="module")
def mars():
    return wobble.invert("mars", seed=5, **SHORT)


def _setup(name="mars") -> dict:
    text = (resources.files("wobble._data") / "inversions" / f"{name}.toml").read_text()
    return tomllib.loads(text)


def test_shipped_setups_are_found_by_name():
    assert {"earth", "mars", "mars_chandler_only"} <= set(wobble.inversion_setups())


def _conjugate_setup(moves=None) -> dict:
    """Mars's k2 alone, a normal prior and a tidal k2 measured at the reference period (where the forward model
    is the identity): the posterior is the conjugate normal one."""
    setup = {
        "schema": "wobble-inversion/1",
        "name": "conjugate",
        "title": "k2 from a k2 measurement",
        "description": "a linear Gaussian case",
        "body": "mars",
        "model": "full",
        "sampler": {"walkers": 32, "steps": 1500, "burn": 300, "seed": 3},
        "parameters": {"love_number_k2": {"prior": "normal", "mean": 0.16, "sd": 0.01, "unit": ""}},
        "observables": {
            "tidal_k2": {
                "value": 0.169,
                "uncertainty": 0.006,
                "unit": "",
                "tidal_period": {"value": 44387.6, "unit": "s"},
            }
        },
    }
    if moves is not None:
        setup["sampler"]["moves"] = moves
    return setup


def test_a_well_fitted_independence_proposal_is_no_warning():
    """On a Gaussian posterior the independence move is accepted ~3/4 of the time: the ideal, and it was
    reported as 'the ensemble moves poorly' (> 0.7). The stretch move alone keeps the warning."""
    r = wobble.invert(_conjugate_setup())
    precision = 1 / 0.01**2 + 1 / 0.006**2
    mean, sd = (0.16 / 0.01**2 + 0.169 / 0.006**2) / precision, precision**-0.5
    x = r.samples[..., 0]
    assert abs(x.mean() - mean) < 4 * sd / np.sqrt(r.to_dict()["parameters"][0]["ess"])
    assert x.std() == pytest.approx(sd, rel=0.05)
    assert np.mean(r.acceptance) > 0.7
    assert r.warnings == []
    stretch = wobble.invert(_conjugate_setup(moves={"stretch": 1.0}), steps=300)  # an acceptance check: short
    assert np.mean(stretch.acceptance) > 0.7
    assert any("acceptance fraction" in w for w in stretch.warnings)


def test_result_speaks_the_vocabulary(mars):
    d = mars.to_dict()
    names = [p["name"] for p in d["parameters"]]
    assert names == [
        "fluid_core_radius",
        "fluid_core_density",
        "love_number_k2",
        "anelastic_exponent",
        "love_number_k2_imaginary",
        "polar_moment_factor",
        "core_compliance_beta",
        "core_compliance_gamma",
    ]
    for p in d["parameters"]:
        assert {"name", "unit", "median", "lower_68", "upper_68", "lower_95", "upper_95", "r_hat", "ess"} <= set(p)
        assert p["lower_95"] <= p["lower_68"] <= p["median"] <= p["upper_68"] <= p["upper_95"]
    assert d["parameters"][0]["unit"] == "km"
    assert d["sampler"] == "emcee" and d["settings"]["steps"] == 200 and d["settings"]["seed"] == 5
    obs = {o["name"]: o for o in d["observables"]}
    assert obs["chandler_period"]["observed"] == pytest.approx(206.9)
    assert obs["chandler_period"]["unit"] == "d"
    assert obs["tidal_k2"]["measured"] and not obs["chandler_quality_factor"]["measured"]
    # Every row has the same keys: a derived quantity's measurement and predictive keys are null, not missing.
    assert len({tuple(o) for o in d["observables"]}) == 1
    assert obs["chandler_quality_factor"]["observed"] is None and obs["chandler_quality_factor"]["source"] is None
    # FCN and precession from the catalogue (RISE; Konopliv et al. 2016), in the units people read.
    assert obs["fcn_period"]["observed"] == pytest.approx(-243.0) and obs["fcn_period"]["unit"] == "d"
    assert "Le Maistre et al. 2023" in obs["fcn_period"]["source"]
    assert obs["precession_rate"]["observed"] == pytest.approx(-7608.3) and obs["precession_rate"]["unit"] == "mas / yr"
    text = mars.summary()
    assert isinstance(text, str) and "fluid_core_radius" in text and "Staehler et al. 2021" in text


def test_short_runs_warn_about_convergence_in_text_and_json(mars):
    """200 steps cannot converge: the warnings must say so, never stay silent."""
    assert any("R-hat above 1.01" in w for w in mars.warnings)
    assert mars.to_dict()["warnings"] == mars.warnings
    assert "WARNING: R-hat above 1.01" in mars.summary()


def test_inference_data_round_trip_with_arviz_and_xarray(mars, tmp_path):
    from wobble.api.dataset import xarray
    from wobble.api.inversion import arviz

    az, xr = arviz(), xarray()
    idata = mars.to_inference_data()
    for group in (
        "posterior",
        "prior",
        "posterior_predictive",
        "prior_predictive",
        "log_likelihood",
        "observed_data",
        "constant_data",
        "sample_stats",
    ):
        assert hasattr(idata, group), group
    path = mars.write(tmp_path / "mars.nc")
    back = az.from_netcdf(path)
    xr.testing.assert_identical(back.posterior, idata.posterior)
    xr.testing.assert_identical(back.observed_data, idata.observed_data)
    post = xr.open_dataset(path, group="posterior")
    assert post["fluid_core_radius"].attrs["units"] == "km"
    np.testing.assert_array_equal(post["fluid_core_radius"].values, mars.samples[..., 0] / 1e3)
    post.close()
    summary = az.summary(back, var_names=["fluid_core_radius"], kind="diagnostics")
    assert summary.loc["fluid_core_radius", "r_hat"] == pytest.approx(
        mars.to_dict()["parameters"][0]["r_hat"], abs=0.011
    )
    assert back.observed_data["chandler_period"].values.tolist() == pytest.approx([206.9])
    assert back.posterior_predictive["chandler_period"].dims == ("chain", "draw", "chandler_period_dim_0")
    # The root group, which ArviZ leaves empty, carries every wobble file's global attributes; wobble.load,
    # which reads the root group, says how to open the groups instead of returning an empty Dataset.
    with netCDF4.Dataset(path) as nc:
        root = {k: nc.getncattr(k) for k in nc.ncattrs()}
    assert root["Conventions"] == "CF-1.10" and root["source"].startswith("wobble")
    assert root["title"] == f"wobble inversion: {mars.setup.title}" and "wobble" in root["history"]
    assert "emcee" in root["references"] and "Vehtari" in root["references"]  # the groups' references, at the root too
    # Every numeric variable has units and a long_name (docs/netcdf.md), ArviZ's index coordinates too.
    for group in idata.groups():
        for name, var in getattr(idata, group).variables.items():
            if var.dtype.kind in "fiu":
                assert var.attrs.get("units") and var.attrs.get("long_name"), (group, name)
    assert root["inference_data_groups"].split() == list(idata.groups())
    with pytest.raises(FileFormatError, match=r"an inference-data file of wobble invert .* arviz\.from_netcdf"):
        wobble.load(path)


def test_write_refuses_to_replace_and_leaves_no_temporary(mars, tmp_path):
    target = tmp_path / "out.nc"
    target.write_text("keep me")
    with pytest.raises(OutputExistsError):
        mars.write(target)
    assert target.read_text() == "keep me"
    mars.write(target, overwrite=True)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.nc"]


def test_corner_plot_is_written(mars, tmp_path):
    path = mars.plot(tmp_path / "corner.png")
    assert path.stat().st_size > 10_000


def test_corner_plot_draws_large_numbers_in_a_named_power_of_ten_and_one_legend(mars):
    """The fluid core's moment (~1e36 kg m2 for Earth) was drawn with Matplotlib's offset text "1e36" over the
    panel above; each diagonal panel had a legend over its histogram."""
    import matplotlib.pyplot as plt

    from wobble.plot.inversion import corner_figure

    earth = wobble.invert("earth", seed=5, **SHORT)
    fig = corner_figure(earth)
    try:
        names = [p.name for p in earth.posterior.parameters]
        k = names.index("fluid_core_equatorial_moment")
        ndim = len(names)
        bottom = fig.axes[(ndim - 1) * ndim + k]
        assert "[$10^{36}$ kg m$^{2}$]" in bottom.get_xlabel()
        fig.canvas.draw()
        assert bottom.xaxis.get_offset_text().get_text() == ""
        median = np.median(earth.samples[..., k]) / earth.posterior.parameters[k].scale / 1e36
        lo, hi = fig.axes[k * ndim + k].get_xlim()
        assert lo < median < hi  # the panel is in the unit its label names
        assert all(ax.get_legend() is None for ax in fig.axes) and len(fig.legends) == 1
        assert any(t.get_text().startswith("core_flattening_excess: ") for t in fig.legends[0].get_texts())
        # Every reference its own colour (counted per parameter, two references shared orange).
        legend = fig.legends[0]
        references = [
            h.get_facecolor() if hasattr(h, "get_facecolor") and not hasattr(h, "get_xdata") else h.get_color()
            for h, t in zip(legend.legend_handles, legend.get_texts())
            if t.get_text() != "prior"
        ]
        from matplotlib.colors import to_hex

        keys = [to_hex(c, keep_alpha=False) for c in references]
        assert len(keys) >= 2 and len(set(keys)) == len(keys)
    finally:
        plt.close(fig)


def test_same_seed_same_numbers_and_dask_gives_the_same_ensembles():
    a = wobble.invert("earth", seed=3, ensembles=2, **SHORT)
    b = wobble.invert("earth", seed=3, ensembles=2, scheduler="threads", **SHORT)
    np.testing.assert_array_equal(a.samples, b.samples)
    assert a.samples.shape[0] == 2 * SHORT["walkers"]
    assert a.to_dict()["parameters"] == b.to_dict()["parameters"]


def test_prior_only_run_is_wider_than_the_posterior(mars):
    prior = wobble.invert("mars", seed=5, prior_only=True, **SHORT)
    p68 = {r["name"]: r["upper_68"] - r["lower_68"] for r in prior.to_dict()["parameters"]}
    q68 = {r["name"]: r["upper_68"] - r["lower_68"] for r in mars.to_dict()["parameters"]}
    # The k2 measurement and the period cut k2 and the core radius well below their flat priors.
    assert q68["love_number_k2"] < 0.3 * p68["love_number_k2"]
    assert q68["fluid_core_radius"] < 0.5 * p68["fluid_core_radius"]
    assert "PRIOR ONLY" in prior.summary()
    # Its predictive column is the prior's (it was headed "posterior predictive").
    assert "prior predictive (68 %)" in prior.summary() and "posterior predictive" not in prior.summary()
    assert "posterior predictive (68 %)" in mars.summary()


def test_the_posterior_file_s_units_are_udunits(mars):
    """Every units attribute of the InferenceData parses in UDUNITS (cf_units): "mas / yr", astropy's
    string, did not (now milliarcsecond julian_year-1, the Julian year astropy's yr is; lower case, which pint
    reads too)."""
    cf_units = pytest.importorskip("cf_units")
    idata = mars.to_inference_data()
    written = {}
    for group in idata.groups():
        for name, var in getattr(idata, group).data_vars.items():
            if "units" in var.attrs:
                written[name] = var.attrs["units"]
                cf_units.Unit(var.attrs["units"])
    assert written["precession_rate"] == "milliarcsecond julian_year-1"


def test_injection_recovery_runs_on_a_real_setup():
    cal = wobble.injection_recovery("mars", draws=2, seed=1, steps=100, burn=50, walkers=16)
    d = cal.to_dict()
    assert d["draws"] == 2 and set(d["coverage"]) == set(cal.names)
    assert "coverage" in cal.summary()


# ---------------------------------------------------------------------------
# Bad input: one line naming the problem, nothing written
# ---------------------------------------------------------------------------


def _broken(path_to_key, value, delete=False):
    data = copy.deepcopy(_setup())
    node = data
    for key in path_to_key[:-1]:
        node = node[key]
    if delete:
        del node[path_to_key[-1]]
    else:
        node[path_to_key[-1]] = value
    return data


@pytest.mark.parametrize(
    "edit, message",
    [
        ((["parameters", "fluid_core_radius", "low"], 2500), "low < high"),
        (
            (["parameters", "fluid_core_density"], {"prior": "normal", "mean": 6000, "sd": -300}),
            "positive standard deviation",
        ),
        ((["parameters", "anelastic_exponent"], {"prior": "uniform", "low": 0.5, "high": 1.5}), "physical range"),
        ((["parameters", "core_radius"], {}), "parameters.core_radius: unknown parameter"),
        (
            (["observables", "lod_variation"], {"value": 1.0, "uncertainty": 0.1}),
            "observables.lod_variation: unknown observable",
        ),
        ((["observables", "fcn_period", "value"], -243.0), "observables.fcn_period.uncertainty: missing"),
        (
            (["parameters", "core_flattening_exces"], {"prior": "uniform", "low": 0, "high": 0.1}),
            "parameters.core_flattening_exces: unknown parameter",
        ),
        ((["parameters", "core_flattening_excess"], {"prior": "uniform", "low": 0.1, "high": -0.1}), "low < high"),
        ((["parameters", "core_flattening_excess"], {"prior": "uniform", "low": -1.5, "high": 0.3}), "physical range"),
        (
            (["parameters", "core_flattening_excess"], {"prior": "normal", "mean": 0.05, "sd": 0.0}),
            "positive standard deviation",
        ),
        ((["parameters", "core_flattening_excess"], {}), "does not catalogue an uncertainty"),
        ((["parameters", "observed_fcn_period"], {}), "parameters.observed_fcn_period: unknown parameter"),
        ((["profile"], "prem"), "profile"),
        ((["observables", "tidal_k2", "uncertainty"], None, True), "observables.tidal_k2.uncertainty: missing"),
        ((["observables", "tidal_k2", "uncertainty"], 0.0), "positive one-sigma uncertainty"),
        (
            (["parameters", "fluid_core_radius"], {"prior": "uniform", "low": 3000, "high": 3300, "unit": "km"}),
            "hydrostatic figure exists",
        ),
        ((["parameters", "fluid_core_radius"], {"prior": "uniform", "low": 1900, "high": 2300, "unit": "km"}), None),
        ((["parameters", "gm"], {}), None),  # catalogued with an uncertainty: allowed
        ((["parameters", "equatorial_radius"], {}), "does not catalogue an uncertainty"),
        ((["sampler", "walkers"], 7), "walkers"),
        ((["sampler", "moves"], {"hop": 1.0}), "sampler.moves.hop: unknown move"),
        ((["sampler", "moves"], {"de": -1.0}), "positive weight"),
        ((["sampler", "moves"], {"stretch": 0.5, "de": 0.5}), None),  # a mixture of one's own: allowed
    ],
)
def test_bad_setups_are_refused_naming_the_key(edit, message):
    data = _broken(*edit)
    if message is None:
        wobble.load_inversion_setup(data)
        return
    with pytest.raises(FileFormatError) as err:
        wobble.load_inversion_setup(data)
    assert message in str(err.value)


def test_unknown_setup_name_is_an_input_error():
    with pytest.raises(InputError, match="setup: got venus"):
        wobble.invert("venus")


def test_cli_bad_setup_exits_2_with_one_line_and_writes_nothing(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    bad = tmp_path / "bad.toml"
    text = (resources.files("wobble._data") / "inversions" / "mars.toml").read_text()
    bad.write_text(text.replace("uncertainty = 0.006\n", ""))
    status = main(["invert", str(bad), "-o", "out.nc", "--plot", "c.png", "--quiet"])
    out, err = capsys.readouterr()
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and "observables.tidal_k2.uncertainty" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml"]


def test_cli_json_and_files(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    status = main(
        [
            "invert",
            "earth",
            "--steps",
            "150",
            "--burn",
            "50",
            "--walkers",
            "16",
            "--seed",
            "2",
            "--json",
            "-o",
            "e.nc",
            "--plot",
            "e.png",
            "--quiet",
        ]
    )
    out, err = capsys.readouterr()
    assert status == 0
    d = json.loads(out)
    assert d["setup"] == "earth" and d["settings"]["seed"] == 2 and d["output"] == "e.nc"
    assert [p["name"] for p in d["parameters"]][0] == "anelastic_exponent"
    assert "core_flattening_excess" in [p["name"] for p in d["parameters"]]
    assert {o["name"] for o in d["observables"]} >= {"chandler_period", "fcn_period", "core_ellipticity"}
    assert d["warnings"]
    assert err.splitlines() == ["wrote e.nc", "wrote e.png"]
    # The same command again refuses to replace the files, before sampling.
    assert main(["invert", "earth", "--steps", "150", "--burn", "50", "--walkers", "16", "-o", "e.nc", "--quiet"]) == 2


@pytest.mark.parametrize(
    "edit, message",
    [
        ('[parameters.core_flattening_excess]\nprior = "uniform"\nlow = 0.3\nhigh = -0.2', "low < high"),
        ('[parameters.core_flatening_excess]\nprior = "uniform"\nlow = -0.2\nhigh = 0.3', "unknown parameter"),
    ],
)
def test_cli_bad_new_parameter_exits_2_with_one_line_and_writes_nothing(edit, message, tmp_path, capsys, monkeypatch):
    """The FCN's core-flattening excess: an improper prior or a misspelt name is one line, exit 2, no file."""
    monkeypatch.chdir(tmp_path)
    text = (resources.files("wobble._data") / "inversions" / "earth.toml").read_text()
    start = text.index("[parameters.core_flattening_excess]")
    end = text.index("[parameters.core_compliance_beta]")
    (tmp_path / "bad.toml").write_text(text[:start] + edit + "\n\n" + text[end:])
    status = main(["invert", "bad.toml", "-o", "out.nc", "--plot", "c.png", "--quiet"])
    out, err = capsys.readouterr()
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and message in err and "core_fla" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml"]


def test_mars_same_seed_same_numbers_with_fcn_and_precession():
    """Seeded reproducibility on the full Mars setup (FCN, precession, tabulated core)."""
    a = wobble.invert("mars", seed=9, steps=60, burn=20, walkers=16)
    b = wobble.invert("mars", seed=9, steps=60, burn=20, walkers=16)
    c = wobble.invert("mars", seed=10, steps=60, burn=20, walkers=16)
    np.testing.assert_array_equal(a.samples, b.samples)
    assert not np.array_equal(a.samples, c.samples)


def test_a_planet_file_in_place_of_the_setups_body(tmp_path, capsys, mars):
    """wobble invert mars --body-file my_mars.toml (a copy of Mars' file, its satellites found by its name): the
    same numbers as the shipped body; a path that is neither a file nor a catalogued planet names --body-file."""
    from wobble.cli import main
    from wobble.io.catalog import catalogue_file

    path = tmp_path / "my_mars.toml"
    path.write_text(catalogue_file("mars").read_text())
    shipped = mars.to_dict()  # wobble.invert("mars", seed=5, **SHORT), the module's
    own = wobble.invert("mars", body=path, seed=5, **SHORT).to_dict()
    assert own["body"] == shipped["body"] == "mars"
    # Renamed, the file is another body: its name is the output's, and Mars' satellites (found by the name
    # "mars") are not its own, so the Sun and the planets precess it; Mars' planet file lies on its orbit
    # and is left out (equation (7) needs two orbits apart).
    from wobble.io.inversion_file import resolve_setup
    from wobble.io.parameter_file import read_toml

    ares = tmp_path / "ares.toml"
    ares.write_text(catalogue_file("mars").read_text().replace('name = "mars"', 'name = "ares"', 1))
    setup = wobble.load_inversion_setup({**read_toml(resolve_setup("mars")), "body": str(ares)})
    planets = ["mercury", "venus", "earth", "jupiter", "saturn", "uranus", "neptune"]
    assert setup.planet.name == "ares" and [o.name for o in setup.context.perturbers] == ["sun", *planets]
    # ...and says so, as the precession budget does (the JSON's "notes", the text's "note:" lines, netCDF attrs).
    assert setup.notes == (f"precession: {wobble.precession_rate(ares).notes[-1]}",)
    assert setup.notes[0].startswith("precession: left out: mars (a planet whose orbit comes within 10%")
    assert own["notes"] == shipped["notes"] == []
    for mine, theirs in zip(own["parameters"], shipped["parameters"]):
        assert mine["name"] == theirs["name"] and mine["median"] == theirs["median"]
    code = main(["invert", "mars", "--body-file", str(tmp_path / "missing.toml"), "--steps", "10"])
    assert code == 2
    # Said to be missing, as wobble chandler --body-file says it (it was "a planet file, or a catalogued planet").
    err = capsys.readouterr().err
    assert "--body-file: got " in err and "allowed: an existing file (there is no such file), or a shipped one" in err
    assert main(["invert", "mars", "--body-file", str(tmp_path), "--steps", "10"]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err.count("\n") == 1 and "(it is a folder)" in captured.err
    # An empty path is said to be one (it was called a folder: Path("") is the current folder).
    assert main(["invert", "mars", "--body-file", "", "--steps", "10"]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err.count("\n") == 1
    assert "--body-file: got ''; allowed: an existing file (an empty path was given)" in captured.err
    # A shipped planet file by name, from any folder, as chandler reads it: Mars' setup needs a core density that
    # the example planet does not catalogue, and the refusal names the example's own name.
    assert main(["invert", "mars", "--body-file", "my_planet.toml", "--steps", "10"]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err.count("\n") == 1
    assert "my_planet does not catalogue an uncertainty for fluid_core_density" in captured.err


def test_a_broken_planet_file_is_named_as_typed(tmp_path, monkeypatch, capsys):
    """wobble invert mars --body-file ./sub/bad.toml named /abs/path/sub/bad.toml (made absolute so that the
    setup's folder does not change a relative path's meaning): named as typed, as wobble chandler names it."""
    from wobble.cli import main

    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "bad.toml").write_text("garbage = [\n")
    monkeypatch.chdir(tmp_path)
    assert main(["invert", "mars", "--body-file", "./sub/bad.toml", "--steps", "10", "-o", "out.nc"]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err.count("\n") == 1
    assert captured.err.startswith("wobble invert: error: ./sub/bad.toml: not valid TOML"), captured.err
    assert str(tmp_path) not in captured.err and not (tmp_path / "out.nc").exists()


def test_diagnostics_report_the_measured_worst_r_hat_beside_the_thresholds(mars):
    """The JSON's diagnostics held r_hat_max = 1.01 and ess_min = 400, the warnings' thresholds, beside
    the measured min_ess; the measured worst R-hat was nowhere. Now max_r_hat is measured (the largest of
    the parameters' R-hat) and the thresholds are r_hat_threshold and ess_threshold (old names kept
    for a release, listed under deprecated_keys)."""
    d = mars.to_dict()
    diag = d["diagnostics"]
    assert diag["max_r_hat"] == max(p["r_hat"] for p in d["parameters"])
    assert diag["min_ess"] == min(min(p["ess"], p["ess_tail"]) for p in d["parameters"])
    assert (diag["r_hat_threshold"], diag["ess_threshold"]) == (wobble.api.inversion.RHAT_MAX, 400)
    for old, new in diag["deprecated_keys"].items():
        assert diag[old] == diag[new]


def test_a_run_too_large_for_memory_is_refused_before_any_work(capsys):
    """--walkers 1e10 asked numpy for 298 GiB and ended in a traceback; --ensembles 1e20 ran without end."""
    from cli_run import run_cli

    for option in (["--walkers", "1e10"], ["--ensembles", "1e20"]):
        code, out, err = run_cli(["invert", "mars", *option], capsys)
        assert (code, out) == (2, "") and err.count("\n") == 1
        # The options that set the product are named, with their values (the message named the product alone).
        assert err.startswith("wobble invert: error: --walkers x (--burn + --steps) x --ensembles: got ")
        assert option[1].replace("1e10", "10000000000").replace("1e20", "1" + "0" * 20) in err
        assert "of memory and" in err and "usable" in err
