"""`wobble chandler`: table, JSON, netCDF, and exit status 2 on bad input."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
import xarray as xr

from wobble.cli import main
from wobble.io.netcdf import open_wobble


def _run(capsys, *args):
    status = main(list(args))
    out, err = capsys.readouterr()
    return status, out, err


def test_table_for_earth_and_mars(capsys):
    status, out, err = _run(capsys, "chandler", "earth", "mars")
    assert status == 0 and not err
    assert "Earth: Chandler wobble budget" in out and "Mars: Chandler wobble budget" in out
    for word in ("rigid", "elastic", "fluid_core", "ocean_pole_tide", "anelastic", "observed", "residual", "86400 s"):
        assert word in out


def test_json_schema_scripts_rely_on(capsys):
    status, out, _ = _run(capsys, "chandler", "earth", "mars", "--json")
    assert status == 0
    data = json.loads(out)
    assert [d["body"] for d in data] == ["earth", "mars"]
    for d in data:
        for key in ("body", "model", "period_days", "period_uncertainty_days", "observed_days", "steps"):
            assert key in d
        assert d["steps"][0]["name"] == "rigid"
        assert all({"name", "period_days"} <= set(s) for s in d["steps"])
        assert "86400 s" in d["day"]
    assert abs(data[0]["period_days"] - 433.1) / 433.1 < 0.01
    assert abs(data[1]["period_days"] - 206.9) / 206.9 < 0.02


def test_json_observed_is_null_when_unknown(tmp_path, capsys):
    f = tmp_path / "blob.toml"
    f.write_text(
        'schema = "wobble/1"\nkind = "planet"\nname = "blob"\n'
        '[parameters.rotation_rate]\nvalue = 1e-4\nuncertainty = 0\nunit = "rad s-1"\nsource = "test"\nstatus = '
        '"assumed"\n'
        '[parameters.dynamical_flattening]\nvalue = -0.01\nuncertainty = 0\nunit = ""\nsource = "test"\nstatus = '
        '"assumed"\n'
    )
    status, out, _ = _run(capsys, "chandler", "--body-file", str(f), "--json")
    d = json.loads(out)[0]
    assert status == 0 and d["observed_days"] is None and d["sense"] == "retrograde"


def test_netcdf_output_round_trip_and_cf(tmp_path, capsys, assert_cf_compliant):
    path = tmp_path / "chandler.nc"
    status, _, _ = _run(capsys, "chandler", "earth", "mars", "-o", str(path))
    assert status == 0
    ds = open_wobble(path)
    assert dict(ds.sizes) == {"body": 2, "step": 5}
    assert ds["period"].attrs["units"] == "day" and "references" in ds["period"].attrs
    for key in ("Conventions", "history", "source"):
        assert key in ds.attrs
    assert "chandler" in ds.attrs["history"]
    assert np.isnan(ds["period"].sel(body="mars", step="ocean_pole_tide"))
    assert int(ds["applied"].sel(body="mars", step="ocean_pole_tide")) == 0
    # Reading back gives the same numbers as the API.
    import wobble

    expected = wobble.chandler_dataset([wobble.chandler_budget("earth"), wobble.chandler_budget("mars")])
    xr.testing.assert_identical(ds, expected.assign_attrs(ds.attrs))
    assert_cf_compliant(path)
    # The Monte Carlo sigma (the text's +/-) and the linear one, each under its own name: the file held the
    # Monte Carlo value under a "(linear propagation)" label.
    budget = wobble.chandler_budget("earth")
    mc, linear = (
        ds["model_period_uncertainty"].sel(body="earth"),
        ds["model_period_uncertainty_linear"].sel(body="earth"),
    )
    assert float(mc) == budget.period_uncertainty.to_value("d") and "Monte Carlo" in mc.attrs["long_name"]
    assert float(linear) == budget.period_uncertainty_linear.to_value("d") and "linear" in linear.attrs["long_name"]
    assert float(linear) != float(mc)


def test_existing_output_is_not_destroyed(tmp_path, capsys):
    path = tmp_path / "chandler.nc"
    path.write_bytes(b"keep me")
    status, out, err = _run(capsys, "chandler", "earth", "-o", str(path))
    assert status == 2 and "--overwrite" in err and err.count("\n") == 1
    assert path.read_bytes() == b"keep me"
    status, _, err = _run(capsys, "chandler", "earth", "--model", "bogus", "-o", str(path), "--overwrite")
    assert status == 2 and path.read_bytes() == b"keep me"


@pytest.mark.parametrize(
    ("args", "fragment"),
    [
        (["chandler", "pluto"], "BODY: got pluto; allowed: one of earth, mars"),
        # Printed twice and written as two "earth" rows, which wobble.load turned into a duplicate index.
        (["chandler", "earth", "Earth"], "BODY: got Earth (given twice); allowed: each body once"),
        (["chandler", "earth", "--model", "bogus"], "model: got bogus"),
        (["chandler", "mars", "--model", "ocean"], "mars supports"),
        (["chandler", "--body-file", "/nonexistent.toml"], "--body-file: got /nonexistent.toml"),
        # Was "(it is a folder)": Path("") is the current folder.
        (["chandler", "--body-file", ""], "--body-file: got ''; allowed: an existing file (an empty path was given)"),
    ],
)
def test_bad_input_exit_2_one_line(capsys, args, fragment):
    status, out, err = _run(capsys, *args)
    assert status == 2
    assert fragment in err and err.count("\n") == 1 and "Traceback" not in err


def test_console_script_runs_without_traceback():
    proc = subprocess.run(
        [sys.executable, "-m", "wobble", "chandler", "venus"], capture_output=True, text=True, check=False
    )
    assert proc.returncode == 2 and "Traceback" not in proc.stderr
    assert proc.stderr.strip().startswith("wobble chandler: error: BODY: got venus")


def test_help_has_an_example(capsys):
    with pytest.raises(SystemExit) as info:
        main(["chandler", "--help"])
    assert info.value.code == 0
    assert "examples:" in capsys.readouterr().out


def test_plot_option_draws_the_budget(tmp_path, capsys):
    path = tmp_path / "budget.png"
    assert main(["chandler", "earth", "mars", "--plot", str(path)]) == 0
    assert path.stat().st_size > 10_000


def test_readme_and_docs_show_what_the_command_prints(capsys):
    """The README's 'What the first line prints' and docs/chandler.md show the real output."""
    import re
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    assert main(["chandler", "earth", "mars"]) == 0
    printed = capsys.readouterr().out.rstrip("\n")
    for page, heading in (
        (root / "README.md", "## What the first line prints"),
        (root / "docs" / "chandler.md", "Output of `wobble chandler earth mars`:"),
    ):
        text = page.read_text()
        block = re.search(r"```text\n(.*?)\n```", text[text.index(heading) :], flags=re.S).group(1)
        assert block == printed, f"{page.name} shows an old output of 'wobble chandler earth mars'"


def test_many_unphysical_draws_are_a_warning(tmp_path, capsys):
    """A core density of 6000 +/- 30000 kg m-3 (a unit slip) dropped 44 % of the draws with only a note."""
    import re

    from wobble.io.catalog import catalogue_file

    text = catalogue_file("mars").read_text()
    wide = re.sub(r"(\[parameters\.fluid_core_density\]\nvalue = [^\n]*\nuncertainty = )[^\n]*", r"\g<1>30000.0", text)
    (tmp_path / "wide.toml").write_text(wide)
    assert main(["chandler", "--body-file", str(tmp_path / "wide.toml")]) == 0
    out = capsys.readouterr().out
    assert "WARNING: " in out and "of the draws were unphysical" in out
    assert main(["chandler", "mars"]) == 0
    assert "WARNING" not in capsys.readouterr().out  # 2.3 % dropped: a note, no warning


def test_json_names_the_steps_a_planet_file_cannot_run(capsys):
    """The text printed "steps not run (parameters missing)"; the JSON left the step out silently. Mars'
    catalogue has no ocean pole tide Love number (it has no ocean)."""
    status = main(["chandler", "earth", "mars", "--json"])
    earth, mars = json.loads(capsys.readouterr().out)
    assert status == 0 and earth["not_run"] == {}
    assert mars["not_run"] == {"ocean_pole_tide": ["ocean_pole_tide_love_number"]}


def test_sources_give_values_as_the_file_does(capsys):
    """Ten significant digits cut Mars' rotation rate 350.891985307 deg/d to 350.8919853."""
    import tomllib

    from wobble.io.catalog import catalogue_file

    status = main(["chandler", "mars", "--sources"])
    out = capsys.readouterr().out
    catalogued = tomllib.loads(catalogue_file("mars").read_text())["parameters"]["rotation_rate"]["value"]
    line = next(x for x in out.splitlines() if x.strip().startswith("rotation_rate:"))
    assert status == 0 and float(line.split()[1]) == catalogued and line.split()[1] == "350.891985307"
    assert "love_number_k2_period: 200 s" in main_text(["chandler", "earth", "--sources"], capsys)


def main_text(argv, capsys) -> str:
    assert main(argv) == 0
    return capsys.readouterr().out


def test_exact_inputs_print_the_period_to_seven_digits(tmp_path, capsys):
    """A body given by an exact H and spin: the budget's sigma is 0, and the period printed to two fixed places
    read 0.02 d for a fast body. Now seven significant digits, against Euler's 2 pi (1 - H)/(H Omega)
    (Goldstein, Poole & Safko 2002 sec. 5.6), in `chandler` and `modes` alike."""
    import math

    entry = 'value = {}\nuncertainty = 0\nunit = "{}"\nsource = "test"\nstatus = "assumed"\n'
    path = tmp_path / "fast.toml"
    path.write_text(
        'schema = "wobble/1"\nkind = "planet"\nname = "fast"\ntitle = "Fast"\n\n'
        "[parameters.dynamical_flattening]\n" + entry.format(0.003, "") + "\n"
        "[parameters.rotation_rate]\n" + entry.format(1, "rad/s")
    )
    want = f"{2 * math.pi * (1 - 0.003) / 0.003 / 86400:.7g}"
    assert want == "0.02416796"
    status, out, err = _run(capsys, "chandler", "--body-file", str(path))
    assert status == 0 and f"model            {want} +/- 0 (prograde wobble)" in out, out
    status, out, err = _run(capsys, "modes", "--body-file", str(path))
    assert status == 0 and f"{want} +/- 0  prograde" in out and "Chandler wobble 0.02417 d" in out, out
