"""What a fresh-user review of the command line found (a clean install, every help example and
page followed as printed), each as a test of the behaviour a user should meet."""

from __future__ import annotations

import importlib
import inspect
import json
import math
import re
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

import wobble

from cli_run import run_cli as _run


TOP = ["top", "--I1", "1", "--I3", "0.5", "--mgl", "1", "--theta0", "60", "--omega3", "10"]


@pytest.mark.parametrize(
    "argv",
    [
        ["chandler", "earth", "-o", "x.txt"],
        [*TOP, "-o", "x.png"],
        ["free", "--inertia", "1", "2", "3", "--omega", "1", "0.1", "1", "-o", "x"],
        ["run", "tennis_racket", "-o", "x.zarr"],  # only sweeps write Zarr stores
    ],
)
def test_an_output_named_for_another_format_is_refused(argv, capsys, tmp_path, monkeypatch):
    # Was: `wobble chandler earth -o x.txt` wrote a netCDF file named x.txt (--plot x.nc was refused).
    monkeypatch.chdir(tmp_path)
    code, out, err = _run(argv, capsys)
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and "-o/--output: got " in err and "a file name ending in .nc" in err
    assert list(tmp_path.iterdir()) == []


def test_netcdf_names_are_accepted(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    for name in ("a.nc", "b.NC", "c.nc4"):
        code, out, err = _run(["chandler", "earth", "-o", name], capsys)
        assert code == 0, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.nc", "b.NC", "c.nc4"]


def test_a_sweep_may_write_a_zarr_store_and_says_so_when_refused(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, out, err = _run(["sweep", "mars_chandler", "--members", "10", "-o", "x.csv"], capsys)
    assert code == 2 and "a file name ending in .nc (netCDF) or a Zarr store ending in .zarr" in err


def test_top_checks_a_t_end_it_does_not_use(capsys):
    # Was: exit 0 with a mass for a time unless -o or --plot was given too.
    code, out, err = _run([*TOP, "--t-end", "5 kg"], capsys)
    assert code == 2 and out == ""
    assert err == (
        "wobble top: error: --t-end: got 5 kg; allowed: a Quantity with units of time (e.g. 1 d, 86164.1 s)\n"
    )


def test_run_says_where_a_model_choice_came_from(capsys, tmp_path, monkeypatch):
    # Was: "forced (--model dop853)" for a model set by the scene file's own model key.
    monkeypatch.chdir(tmp_path)
    code, out, err = _run(["run", "earth_precession", "-o", "a.nc", "--json"], capsys)
    assert code == 0, err
    assert json.loads(out)["model_reason"].startswith('forced (the scene\'s model = "dop853"): ')
    code, out, err = _run(["run", "earth_precession", "-o", "b.nc", "--model", "dop853", "--json"], capsys)
    assert code == 0, err
    assert json.loads(out)["model_reason"].startswith("forced (--model dop853): ")


def test_an_existing_output_names_the_option_of_each_interface(capsys, tmp_path, monkeypatch):
    # Was: "--overwrite (overwrite=True)" on both, mixing the command line and Python.
    monkeypatch.chdir(tmp_path)
    (tmp_path / "a.nc").write_bytes(b"previous")
    code, out, err = _run(["chandler", "earth", "-o", "a.nc"], capsys)
    assert code == 2
    assert err == "wobble chandler: error: a.nc: file exists; allowed: a new path, or --overwrite to replace it\n"
    import wobble

    with pytest.raises(wobble.OutputExistsError, match=r"a new path, or overwrite=True to replace it$"):
        wobble.write_netcdf(wobble.chandler_budget("earth").to_dataset(), "a.nc")
    assert (tmp_path / "a.nc").read_bytes() == b"previous"


def test_an_array_quantity_is_shown_as_typed(capsys):
    # Was: "got [-1.  2.  3.] m2 kg" (NumPy's print). The command line shows the values as typed.
    from astropy import units as u

    with pytest.raises(wobble.InputError, match=r"^moments: got \(-1, 2, 3\) m2 kg; allowed: positive values"):
        wobble.FreeRotation([-1, 2, 3] * u.kg * u.m**2, [1, 0.1, 1] * u.rad / u.s)
    code, out, err = _run(["free", "--inertia", "-1", "2", "3", "--omega", "1", "0.1", "1"], capsys)
    assert code == 2 and err.startswith("wobble free: error: --inertia: got -1 2 3; allowed: positive values")
    # One value in an array is bracketed as a list: "(1.1) m2 kg" read as a number in parentheses.
    with pytest.raises(wobble.InputError, match=r"^moments: got \[1.1\] m2 kg; allowed: shape \(3,\)"):
        wobble.FreeRotation([1.1] * u.kg * u.m**2, [1, 0.1, 1] * u.rad / u.s)


# What a user reads (help texts, public docstrings, the descriptions of shipped files that
# `wobble run --list` prints and netCDF summaries carry) cites books and papers, never the
# project's internal documents: the course notes and the issue tracker are not shipped.
_INTERNAL = re.compile(r"\bnotes?'? ?(sec|p\.|pp\.|section|page)|course notes|\bissue ?#?\d", re.IGNORECASE)


def _shipped_texts():
    from wobble.cli import build_parser
    from wobble.cli._examples import help_texts

    data = Path(str(resources.files("wobble._data")))  # data/ in a checkout, wobble/_data installed
    texts = {f"wobble {name} --help": text for name, text in help_texts(build_parser()).items()}
    texts.update({str(p.relative_to(data)): p.read_text() for p in sorted(data.rglob("*.toml"))})
    public = [(f"wobble.{name}", getattr(wobble, name)) for name in wobble.__all__]
    for module in wobble.plot.__all__:
        plots = importlib.import_module(f"wobble.plot.{module}")
        public += [(f"wobble.plot.{module}", plots)] + [
            (f"wobble.plot.{module}.{n}", getattr(plots, n)) for n in plots.__all__
        ]
    for name, obj in public:
        texts[name] = inspect.getdoc(obj) or ""
        for attr, member in vars(obj).items() if inspect.isclass(obj) else ():
            if not attr.startswith("_"):
                texts[f"{name}.{attr}"] = inspect.getdoc(member) or ""
    return texts


def test_user_facing_text_cites_no_internal_document():
    # Was: "Issue 8's top ... (notes section 5.7)" in the description of the top_cusps scene.
    texts = _shipped_texts()
    assert len(texts) > 100 and any(k.endswith(".toml") for k in texts)
    found = {k: m.group(0) for k, v in texts.items() if (m := _INTERNAL.search(v))}
    assert found == {}


def test_an_api_error_names_the_option_the_user_typed(capsys, tmp_path, monkeypatch):
    # Was: "members: got 0" for --members (the Python parameter's name, which the user never typed).
    monkeypatch.chdir(tmp_path)
    code, out, err = _run(["sweep", "mars_chandler", "--members", "0"], capsys)
    assert code == 2 and err.startswith("wobble sweep: error: --members: got 0; allowed: a positive integer")
    from wobble.cli import _as_typed, build_parser
    from wobble.errors import InputError

    parser = build_parser()
    shown = _as_typed(InputError("output", "x.nc", "a path"), parser, "chandler")
    assert str(shown) == "-o/--output: got x.nc; allowed: a path"
    missing = _as_typed(InputError.missing("t_end", "a time"), parser, "free")
    assert str(missing) == "--t-end: missing; allowed: a time"
    other = InputError("moments", 1, "a Quantity")  # not an option of the command: left alone
    assert _as_typed(other, parser, "free") is other
    both = _as_typed(InputError("omega3, psidot0", (1.0, 2.0), "exactly one"), parser, "top")
    assert str(both) == "--omega3, --psidot0: got (1.0, 2.0); allowed: exactly one"


@pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs a /proc file system that refuses new files")
def test_a_folder_that_refuses_the_file_is_named_not_the_temporary(capsys, tmp_path, monkeypatch):
    # Was: "No such file or directory (/proc/.x.nc.14478.z_miwvgn.tmp)", a name the user never typed.
    monkeypatch.chdir(tmp_path)
    for argv in (
        ["chandler", "earth", "-o", "/proc/x.nc"],
        ["sweep", "mars_chandler", "--members", "5", "-o", "/proc/x.zarr"],
    ):
        code, out, err = _run(argv, capsys)
        assert code == 2 and err.count("\n") == 1 and ".tmp" not in err and f"({argv[-1]})" in err


def test_an_unknown_scene_is_named_before_a_missing_output(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, out, err = _run(["run", "no_such_scene"], capsys)
    assert code == 2 and err.startswith("wobble run: error: SCENE: got no_such_scene; allowed: an existing file")


def test_a_unit_on_the_first_of_three_values_applies_to_all(capsys):
    # Was: "1 g cm2" 2 3 read 2 and 3 as kg m2 and refused (1e-07, 2, 3) as unordered nonsense.
    from astropy import units as u

    from wobble.api.units import parse_quantities

    assert u.allclose(parse_quantities(["1 g cm2", "2", "3"], "--inertia", u.kg * u.m**2), [1, 2, 3] * u.g * u.cm**2)
    q = parse_quantities(["1 g cm2", "2 g cm2", "3e-7 kg m2"], "--inertia", u.kg * u.m**2)
    assert u.allclose(q, [1, 2, 3] * u.g * u.cm**2)
    assert parse_quantities(["1", "2", "3"], "--inertia", u.kg * u.m**2).unit == u.kg * u.m**2
    mixed = parse_quantities(["7.292115e-11", "0", "360 deg/d"], "--omega", u.rad / u.s)  # bare values are SI
    assert u.allclose(mixed, [7.292115e-11, 0, 2 * np.pi / 86400] * u.rad / u.s, rtol=1e-15, atol=0 * u.rad / u.s)
    code, out, err = _run(["free", "--inertia", "1 g cm2", "2", "3", "--omega", "1", "0.1", "1", "--json"], capsys)
    assert code == 0 and json.loads(out)["period_s"] > 0
    code, out, err = _run(["free", "--inertia", "-1 g cm2", "2", "3", "--omega", "1", "0.1", "1"], capsys)
    assert code == 2 and "got -1 g cm2 2 3;" in err  # the user's numbers, no binary noise


def test_inertia_text_shows_rounding_as_zero(capsys):
    # Was: centre of mass (-3.854941e-19, 0, 0) m and an axis (-8.747885e-14, 0.7071068, -0.7071068).
    code, out, err = _run(["inertia", "--points", "dumbbell.csv", "--length-unit", "cm"], capsys)
    assert code == 0 and "centre of mass      (0, 0, 0) m" in out and "axis e2 = (0, 0.7071068, -0.7071068)" in out
    code, out, err = _run(["inertia", "--points", "dumbbell.csv", "--length-unit", "cm", "--json"], capsys)
    assert json.loads(out)["center_of_mass_m"][0] != 0.0  # JSON keeps the computed floats


def test_an_empty_span_is_refused(capsys, tmp_path, monkeypatch):
    # Was: 1001 samples all at t = 0 (a time coordinate that is not monotonic).
    from astropy import units as u

    from wobble.errors import InputError

    monkeypatch.chdir(tmp_path)
    for argv in (["free", "--inertia", "1", "2", "3", "--omega", "1", "0.1", "1"], TOP):
        for extra in (["-o", "x.nc"], []):  # without -o it printed "span 0 to 0 s, 1001 samples"
            code, out, err = _run([*argv, "--t-end", "0", *extra], capsys)
            assert code == 2 and err.count("\n") == 1 and "--t-end: got 0; allowed: a positive, finite time" in err
        code, out, err = _run([*argv, "--samples", "1", "-o", "x.nc"], capsys)  # "0 to 20.8 s, 1 samples": t = 0
        assert code == 2 and "--samples: got 1; allowed: a whole number >= 2" in err
    assert list(tmp_path.iterdir()) == []
    body = wobble.FreeRotation([1, 2, 3] * u.kg * u.m**2, [1, 0.1, 1] * u.rad / u.s)
    with pytest.raises(InputError, match="t_end"):
        body.to_dataset(t_end=0 * u.s, samples=11)
    assert body.to_dataset(t_end=0 * u.s, samples=1).sizes["time"] == 1


def test_top_says_how_its_span_was_chosen(capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, out, err = _run([*TOP, "--plot", "a.png"], capsys)
    assert code == 0 and "(10 nutation periods, the default; --t-end to change)" in out
    code, out, err = _run([*TOP, "--plot", "b.png", "--t-end", "20"], capsys)
    assert code == 0 and "0 to 20 s, 1001 samples (--t-end)" in out


def test_shipped_names_are_listed_as_typed(capsys):
    # Was: the unknown-name error listed earth.toml and mars.toml twice (bodies/ and inversions/).
    code, out, err = _run(["example", "no_such_file"], capsys)
    assert code == 2
    names = err.split("a shipped file: ")[1].split(" (wobble example --list)")[0].split(", ")
    assert len(names) == len(set(names)) and "bodies/earth.toml" in names and "inversions/earth.toml" in names
    code, out, err = _run(["example", "--list"], capsys)
    assert all(f"  {name} " in out for name in names)


def test_bare_example_lists_what_list_lists(capsys):
    # Was: 'wobble example' alone was an error (NAME: missing), the first thing a newcomer types.
    bare = _run(["example"], capsys)
    listed = _run(["example", "--list"], capsys)
    assert bare == listed and bare[0] == 0 and "bodies/earth.toml" in bare[1]
    code, out, err = _run(["example", ""], capsys)
    assert code == 2 and "NAME: got ''" in err


def test_a_scene_unit_example_reads_as_people_write_it(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert _run(["example", "tennis_racket", "s.toml"], capsys)[0] == 0
    text = (tmp_path / "s.toml").read_text()
    (tmp_path / "s.toml").write_text(text.replace('unit = "kg m2"', 'unit = "kg"', 1))
    code, out, err = _run(["run", "s.toml", "-o", "x.nc"], capsys)
    assert code == 2 and err.endswith('allowed: a unit of moment of inertia (e.g. "kg m2")\n')


def test_plot_functions_check_their_inputs_as_the_api_does():
    # Was: AttributeError: 'int' object has no attribute 'to_value' (and 'str' has no 'steps').
    from astropy import units as u

    from wobble.errors import InputError

    body = wobble.FreeRotation([1, 2, 3] * u.kg * u.m**2, [1, 0.1, 1] * u.rad / u.s)
    top = wobble.HeavyTop(
        I1=1 * u.kg * u.m**2, I3=0.5 * u.kg * u.m**2, mgl=1 * u.J, theta0=60 * u.deg, omega3=10 * u.rad / u.s
    )
    calls = {
        "t_end": [
            lambda: wobble.plot.free.motion_figure(body, 20),
            lambda: wobble.plot.top.axis_locus_figure(top, 20),
            lambda: wobble.plot.free.flip_figure([1, 2, 3] * u.kg * u.m**2, [1e-6, 1, 1e-6] * u.rad / u.s, 20),
        ],
        "budgets": [lambda: wobble.plot.chandler.budget_figure(["earth"])],
        "moments": [lambda: wobble.plot.free.polhode_figure([1, 2, 3], [[1, 0, 1]])],
        "body": [lambda: wobble.plot.free.motion_figure(top, 20 * u.s)],
        "top": [lambda: wobble.plot.top.axis_locus_figure(body, 20 * u.s)],
        "source": [lambda: wobble.plot.scene.scene_figure(3)],
    }
    for parameter, fns in calls.items():
        for fn in fns:
            with pytest.raises(InputError) as info:
                fn()
            assert info.value.parameter == parameter


def test_a_sweep_prints_spans_as_people_read_them():
    # Was: "precession_period: mean 504982.186 s, sd 311200.363" and percentiles to the hundredth of a second.
    from wobble.api.sweep import SweepSummary

    day = 86400.0
    pct = {"2.5": 1.09 * day, "16": 2.33 * day, "50": 5.24 * day, "84": 9.24 * day, "97.5": 14.56 * day}
    common = dict(members=100, valid=100, invalid_reasons={})
    summary = SweepSummary(
        "precession_period", "s", mean=5.84 * day, std=3.6 * day, percentiles=pct, observed=math.nan, **common
    )
    assert summary.summary().splitlines()[1:] == [
        "  precession_period: mean 5.8 d, sd 3.6 d",
        "    2.5/16/50/84/97.5 %: 1.1 / 2.3 / 5.2 / 9.2 / 14.6 d",
    ]

    def chandler(**kwargs):
        return SweepSummary("chandler_period", "day", observed=206.9, **common, **kwargs)

    summary = chandler(mean=205.857, std=2.739, percentiles={k: 205.84 for k in pct})
    assert summary.summary().splitlines()[1::2] == [
        "  chandler_period: mean 205.9 d, sd 2.7 d",
        "  observed: 206.9 d (+0.38 sd from the mean)",
    ]
    # A grid's points are chosen, not drawn: its range, and where the observed value falls in it.
    grid = chandler(
        mean=206.9, std=3.6, percentiles={k: 207.17 for k in pct}, grid=True, minimum=200.43, maximum=213.06
    )
    assert grid.summary().splitlines()[1:] == [
        "  chandler_period over the grid: 200.4 to 213.1 d (median 207.2 d)",
        "  observed: 206.9 d (inside the grid's range)",
    ]


def test_a_negative_value_with_a_unit_is_read_as_a_value(capsys):
    # Was: "argument --horizon: expected one argument" (argparse took -5d for an option).
    code, out, err = _run(["forecast", "--horizon", "-5d"], capsys)
    assert code == 2 and err.startswith("wobble forecast: error: --horizon: got -5 d; allowed:")
    code, out, err = _run(["free", "--inertia", "1", "2", "3", "--omega", "-1 rad/s", "-.1", "1", "--json"], capsys)
    assert code == 0, err


def test_precession_takes_only_the_body_s_own_satellites_once(capsys):
    # Was: the Moon about Mars (-5780"/cy, residual -2905 sigma), the Moon counted twice, and
    # "the published higher-order terms below account for it" under a residual of 3445"/cy.
    for argv, allowed in (
        (["mars", "--perturber", "moon"], "a satellite of mars, or a planet (this one orbits earth)"),
        (["earth", "--perturber", "moon", "--perturber", "moon"], "each perturber once (it is already included)"),
    ):
        code, out, err = _run(["precession", *argv], capsys)
        assert code == 2 and err == f"wobble precession: error: --perturber: got moon; allowed: {allowed}\n"
    code, out, err = _run(["precession", "earth", "--perturber", "sun"], capsys)
    residual = next(line for line in out.splitlines() if line.strip().startswith("residual"))
    assert code == 0 and "account for it" not in residual
    # Nor is it counted in sigma ("+3678486.5 sigma"), nor are there steps to IAU 2006 from a "Sun and Moon
    # (model)" that is the Sun's alone (a review finding).
    assert "sigma" not in residual and "not a test of the model: the observed rate holds the torque of moon" in residual
    assert "  steps to IAU 2006 (" not in out and "Sun and Moon (model)" not in out
    assert "note: no steps to IAU 2006: its rates hold the torque of moon, left out here" in out
    code, out, err = _run(["precession", "earth"], capsys)
    residual = next(line for line in out.splitlines() if line.strip().startswith("residual"))
    assert "the published higher-order terms below account for it" in residual


def test_a_value_out_of_range_in_a_planet_file_is_named_with_its_file_and_key(capsys, tmp_path, monkeypatch):
    # Was: "parameters: got my_planet; allowed: a parameter is outside its physical range", naming
    # neither the file, nor the parameter, nor its value.
    monkeypatch.chdir(tmp_path)
    assert _run(["example", "my_planet.toml", "p.toml"], capsys)[0] == 0
    text = (tmp_path / "p.toml").read_text()
    head, tail = text.split("[parameters.love_number_k2]\n", 1)
    (tmp_path / "p.toml").write_text(
        head + "[parameters.love_number_k2]\n" + tail.replace("value = 0.3", "value = -0.3", 1)
    )
    code, out, err = _run(["chandler", "--body-file", "p.toml"], capsys)
    assert code == 2 and err == (
        "wobble chandler: error: p.toml, parameters.love_number_k2.value: got -0.3; "
        "allowed: a non-negative Love number\n"
    )


def test_free_shows_the_moments_as_typed_in_its_errors(capsys):
    # Was: "got (1.0000000000000001e-07, 2.0, 3.0000000000000004)", the SI floats of "1 g cm2" "2 kg m2" 3.
    code, out, err = _run(["free", "--inertia", "1 g cm2", "2 kg m2", "3", "--omega", "1", "0.1", "1"], capsys)
    assert code == 2 and err.startswith("wobble free: error: --inertia: got 1 g cm2 2 kg m2 3; allowed: principal")


def test_arguments_are_named_as_typed(capsys, tmp_path, monkeypatch):
    # Was: "setup: got nope", "output: got sub/dir" and "wobble: error: unrecognized arguments: --quiet".
    monkeypatch.chdir(tmp_path)
    cases = {
        ("invert", "nope"): "wobble invert: error: SETUP: got nope; allowed: ",
        ("example", "tennis_racket", "sub/dir/"): "wobble example: error: DEST: got sub/dir/; allowed: a path in",
        ("forecast", "--quiet"): "wobble forecast: error: unrecognized arguments: --quiet",
        ("chandler", "earth", "--bogus", "3"): "wobble chandler: error: unrecognized arguments: --bogus 3",
    }
    for argv, start in cases.items():
        code, out, err = _run(list(argv), capsys)
        assert code == 2 and err.startswith(start) and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []


def test_sweep_files_cite_their_own_model_and_one_member_has_no_spread(capsys, tmp_path, monkeypatch):
    # Was: every sweep file cited the Monte Carlo of catalogue uncertainties (JCGM 101), the top's
    # phase-diagram grid too; a one-member sweep printed "sd nan" and "+nan sd from the mean".
    import xarray as xr

    monkeypatch.chdir(tmp_path)
    code, out, err = _run(["sweep", "mars_chandler", "--members", "1"], capsys)
    assert code == 0 and "(no spread: 1 valid member(s))" in out and "nan" not in out
    refs = {}
    for name, extra in (("mars_chandler", ["--members", "10"]), ("top_phase_diagram", [])):
        assert _run(["sweep", name, "-o", f"{name}.nc", *extra], capsys)[0] == 0
        with xr.open_dataset(f"{name}.nc") as ds:
            refs[name] = ds.attrs["references"]
    assert "JCGM 101" in refs["mars_chandler"] and "JCGM" not in refs["top_phase_diagram"]
    assert "Goldstein, Poole & Safko 2002" in refs["top_phase_diagram"]


def test_text_output_reads_as_people_write(capsys, tmp_path, monkeypatch):
    # Was: "16.66667 min (1000 s)" for --t-end 1000, "1 point masses", 5161.381 kg m2 of rounding
    # beside 8.3e37 in the planet grid's tensor, and windows thinned without saying so.
    monkeypatch.chdir(tmp_path)
    code, out, err = _run(["free", "--inertia", "1", "2", "3", "--omega", "1", "0.1", "1", "--t-end", "1000"], capsys)
    assert "0 to 1000 s, 1001 samples (--t-end)" in out
    code, out, err = _run([*TOP, "--t-end", "2 min", "--plot", "t.png"], capsys)
    assert "0 to 2 min (120 s), 1001 samples (--t-end)" in out
    (tmp_path / "one.csv").write_text("m,x,y,z\n1,0,0,1\n")
    code, out, err = _run(["inertia", "--points", "one.csv"], capsys)
    assert out.startswith("wobble inertia: 1 point mass from one.csv\n")
    code, out, err = _run(["inertia", "--density", "planet.nc"], capsys)
    rows = out.split("input axes x, y, z)\n")[1].splitlines()[:3]
    assert [row.split()[1:] for row in rows[:1]] == [["0", "0"]] and rows[1].split()[0] == "0"


def test_a_converted_value_is_shown_as_typed(capsys):
    # Was: "--theta0: got 200.0 deg", "--I1: got -1.0", "--tolerance: got -1.0" for 200, -1 and -1.
    cases = {
        ("top", "--I1", "1", "--I3", "0.5", "--mgl", "1", "--theta0", "200", "--omega3", "10"): "--theta0: got 200;",
        ("top", "--I1=-1", "--I3", "0.5", "--mgl", "1", "--theta0", "20", "--omega3", "10"): "--I1: got -1;",
        ("inertia", "--solid", "sphere", "--mass", "1", "--radius", "1", "--tolerance", "-1"): "--tolerance: got -1;",
    }
    for argv, needle in cases.items():
        code, out, err = _run(list(argv), capsys)
        assert code == 2 and needle in err and err.count("\n") == 1
