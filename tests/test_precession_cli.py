"""`wobble precession`: table, JSON, netCDF round trip, CF, plot, and exit status 2 on bad input."""

from __future__ import annotations

import json
from pathlib import Path
import re

import numpy as np

import pytest
import xarray as xr

import wobble
from wobble.cli import main
from wobble.io.catalog import catalogue_names


def _run(capsys, *args):
    status = main(list(args))
    out, err = capsys.readouterr()
    return status, out, err


def test_table_shows_each_term_and_the_steps_to_iau_2006(capsys):
    status, out, err = _run(capsys, "precession", "earth", "mars")
    assert status == 0 and not err
    for word in (
        "sun_eccentricity",
        "moon_inclination",
        "moon_solar_perturbation",
        "geodesic",
        "psi_A",
        "p_A",
        "IAU 2000A",
        "Konopliv",
        "Circular",
    ):
        assert word in out


def test_json_keys_scripts_rely_on(capsys):
    status, out, _ = _run(capsys, "precession", "earth", "mars", "--json")
    data = json.loads(out)
    assert status == 0 and [d["body"] for d in data] == ["earth", "mars"]
    for d in data:
        for key in (
            "body",
            "rate_arcsec_per_century",
            "rate_uncertainty_arcsec_per_century",
            "terms",
            "observed_arcsec_per_century",
            "observed_uncertainty_arcsec_per_century",
            "source",
        ):
            assert key in d
        assert all({"name", "value_arcsec_per_century"} <= set(t) for t in d["terms"])
        # The unsuffixed names are listed as deprecated and still hold the same values (one release).
        for old, new in d["deprecated_keys"].items():
            if old.startswith("terms[]."):
                assert all(t[old[8:]] == t[new[8:]] for t in d["terms"])
            else:
                assert d[old] == d[new]
    assert abs(-data[0]["first_order_arcsec_per_century"] - 5040.70) < 0.05
    assert abs(data[1]["rate_mas_per_year"] + 7608.3) < 10


def test_the_principal_nutation_is_shown_beside_the_rigid_earth_series_and_iau_2000a(capsys):
    status, out, _ = _run(capsys, "precession", "earth")
    assert status == 0
    assert 'rigid Earth, REN-2000 (Souchay et al. 1999; H = 0.0032737548): -17.2806", +9.2279"' in out
    shown = re.search(r"model - REN-2000: ([+-][0-9.]+) %, ([+-][0-9.]+) %", out)
    assert shown and "model - IAU 2000A:" in out
    status, out, _ = _run(capsys, "precession", "earth", "--json")
    (nut,) = json.loads(out)[0]["nutation"]
    assert float(shown[1]) == pytest.approx(nut["difference_rigid_longitude_percent"], abs=5e-4)
    assert float(shown[2]) == pytest.approx(nut["difference_rigid_obliquity_percent"], abs=5e-4)
    assert nut["rigid_earth_series"] == "REN-2000"
    assert nut["rigid_earth_longitude_arcsec"] == -17.2805921 and nut["rigid_earth_obliquity_arcsec"] == 9.22791
    assert nut["rigid_earth_dynamical_flattening"] == 3.2737548e-3
    assert abs(nut["difference_rigid_longitude_percent"]) < 1 and abs(nut["difference_rigid_obliquity_percent"]) < 1
    assert nut["iau2000a_longitude_arcsec"] == -17.2064161
    assert "Souchay" in nut["rigid_earth_source"]


def test_netcdf_round_trip_and_cf(tmp_path, capsys, assert_cf_compliant):
    path = tmp_path / "precession.nc"
    status, out, _ = _run(capsys, "precession", "earth", "mars", "-o", str(path))
    assert status == 0 and f"wrote {path}" in out
    ds = wobble.load(path)
    assert dict(ds.sizes)["body"] == 2
    expected = wobble.precession_dataset([wobble.precession_rate("earth"), wobble.precession_rate("mars")])
    xr.testing.assert_identical(ds, expected.assign_attrs(ds.attrs))
    assert ds.wobble.quantity("precession_rate").unit == "rad / s"
    assert_cf_compliant(path)


def test_plot_is_written(tmp_path, capsys):
    path = tmp_path / "p.png"
    status, _, _ = _run(capsys, "precession", "mars", "--plot", str(path))
    assert status == 0 and path.stat().st_size > 1000


def test_the_figure_says_what_the_text_says():
    """The model and observed bars looked alike (Earth's -8.3 sigma residual unseen); Mars' model bar left out
    the geodesic term its waterfall added; numbers had three decimals where the text gives the uncertainty's
    two significant digits ("+/- 0.001" for 0.00080)."""
    from astropy import units as u

    import wobble
    from wobble.plot.precession import budget_figure

    earth, mars = wobble.precession_rate("earth"), wobble.precession_rate("mars")
    ax_e, ax_m = budget_figure([earth, mars]).axes
    cy = u.arcsec / (100 * u.yr)
    residual = (earth.rate - earth.observed).to_value(cy)
    sigma = residual / np.hypot(earth.rate_uncertainty.to_value(cy), earth.observed_uncertainty.to_value(cy))
    assert f"model - observed {residual:+.3f} ({sigma:+.1f} σ)" in ax_e.get_title()
    # The figure's numbers are the ones the text prints (IAU 2006: -5038.481507"/cy, sigma 0.0008).
    texts = [t.get_text() for t in ax_e.texts]
    summary = earth.summary()
    for text in ("-5038.48151 ± 0.00080", f"{earth.rate.to_value(cy):.3f} ± {earth.rate_uncertainty.to_value(cy):.3f}"):
        assert text in texts and text.replace("±", "+/-") in summary
    labels = [t.get_text() for t in ax_m.get_yticklabels()]
    assert not mars.includes_geodesic and "geodesic (not in the model)" in labels and "model (tidal)" in labels
    # The planets' seven terms are one bar, as in the text; the tidal terms' bars end where the model bar does.
    assert labels.count("planets") == 1 and not {"jupiter", "venus"} & set(labels)
    bars = len(mars.terms) - len(mars.planet_terms) + 1
    tidal = sum(t.rate.to_value(u.arcsec / (100 * u.yr)) for t in mars.terms if t.name != "geodesic")
    ends = [p.get_x() + p.get_width() for p in ax_m.patches[:bars] if p.get_facecolor()[3] > 0]
    assert min(ends) == pytest.approx(tidal) == pytest.approx(mars.rate.to_value(u.arcsec / (100 * u.yr)))


def test_chandler_still_lists_only_planets(capsys):
    assert catalogue_names() == ["earth", "mars"]
    status, out, _ = _run(capsys, "chandler", "--json")
    assert status == 0 and [d["body"] for d in json.loads(out)] == ["earth", "mars"]


_PLANET = """schema = "wobble/1"
kind = "planet"
name = "blob"
[parameters.rotation_rate]
value = 7e-5
uncertainty = 0
unit = "rad s-1"
source = "test"
status = "assumed"
[parameters.dynamical_flattening]
value = 0.003
uncertainty = 0
unit = ""
source = "test"
status = "assumed"
[parameters.equatorial_radius]
value = 6.4e6
uncertainty = 0
unit = "m"
source = "test"
status = "assumed"
[parameters.obliquity]
value = {obliquity}
uncertainty = 0
unit = "deg"
source = "test"
status = "assumed"
[parameters.orbit_semi_major_axis]
value = 1.0
uncertainty = 0
unit = "AU"
source = "test"
status = "assumed"
[parameters.orbit_eccentricity]
value = {eccentricity}
uncertainty = 0
unit = ""
source = "test"
status = "assumed"
"""

_MOON = """schema = "wobble/1"
kind = "perturber"
name = "pebble"
primary = "blob"
[parameters.gm]
value = {gm}
uncertainty = 0
unit = "m3 s-2"
source = "test"
status = "assumed"
[parameters.semi_major_axis]
value = {a}
uncertainty = 0
unit = "km"
source = "test"
status = "assumed"
[parameters.eccentricity]
value = {e}
uncertainty = 0
unit = ""
source = "test"
status = "assumed"
"""


def test_a_body_file_with_a_satellite_runs(tmp_path, capsys):
    body = tmp_path / "blob.toml"
    body.write_text(_PLANET.format(obliquity=20.0, eccentricity=0.01))
    moon = tmp_path / "pebble.toml"
    moon.write_text(_MOON.format(gm=5e12, a=4e5, e=0.05))
    status, out, _ = _run(capsys, "precession", "--body-file", str(body), "--perturber", str(moon), "--json")
    d = json.loads(out)[0]
    assert status == 0 and d["observed_arcsec_per_century"] is None
    assert [t["name"] for t in d["terms"]][:4] == ["sun", "sun_eccentricity", "pebble", "pebble_eccentricity"]


@pytest.mark.parametrize(
    ("planet", "moon", "fragment"),
    [
        ({"obliquity": 200.0, "eccentricity": 0.01}, None, "parameters.obliquity"),
        ({"obliquity": -1.0, "eccentricity": 0.01}, None, "parameters.obliquity"),
        ({"obliquity": 20.0, "eccentricity": 1.5}, None, "orbit_eccentricity"),
        ({"obliquity": 20.0, "eccentricity": 0.01}, {"gm": -5e12, "a": 4e5, "e": 0.05}, "parameters.gm"),
        ({"obliquity": 20.0, "eccentricity": 0.01}, {"gm": 5e12, "a": 4e5, "e": 1.2}, "parameters.eccentricity"),
        ({"obliquity": 20.0, "eccentricity": 0.01}, {"gm": 5e12, "a": 6000.0, "e": 0.1}, "semi_major_axis"),
    ],
)
def test_bad_input_exit_2_one_line_nothing_written(tmp_path, capsys, planet, moon, fragment):
    body = tmp_path / "blob.toml"
    body.write_text(_PLANET.format(**planet))
    args = ["precession", "--body-file", str(body), "-o", str(tmp_path / "out.nc"), "--plot", str(tmp_path / "out.png")]
    if moon is not None:
        path = tmp_path / "pebble.toml"
        path.write_text(_MOON.format(**moon))
        args += ["--perturber", str(path)]
    status, out, err = _run(capsys, *args)
    assert status == 2 and fragment in err and err.count("\n") == 1 and "Traceback" not in err
    assert not (tmp_path / "out.nc").exists() and not (tmp_path / "out.png").exists()


def test_an_uncertainty_past_its_value_names_the_perturber_file(tmp_path, capsys):
    """The Moon's distance given in AU with its uncertainty left at 0.1 (it was km): the +-1 sigma propagation
    evaluated the model at a negative distance, and the refusal named the body's catalogue file and that
    negative distance, which nobody typed (a review finding)."""
    from wobble.io.perturbers import load_perturber

    text = Path(load_perturber("moon").path).read_text()
    old = 'value = 384399.0\nuncertainty = 0.1\nunit = "km"'
    assert old in text
    path = tmp_path / "moonau.toml"
    path.write_text(
        text.replace(old, 'value = 0.0025695553\nuncertainty = 0.1\nunit = "AU"').replace('"moon"', '"moonau"')
    )
    status, out, err = _run(capsys, "precession", "earth", "--perturber", str(path))
    assert status == 2 and err.count("\n") == 1, err
    assert "moonau.toml, parameters.semi_major_axis: 3.844e+08 +/- 1.49598e+10 (SI)" in err, err
    assert "keeps value - sigma and value + sigma physical" in err and "earth.toml" not in err


@pytest.mark.parametrize(("typed", "why"), [("./missing.toml", "there is no such file"), (".", "it is a folder")])
def test_a_perturber_path_that_is_not_a_file_says_why(tmp_path, monkeypatch, capsys, typed, why):
    # Was "--perturber: got ./missing.toml; allowed: one of moon, sun, or the path of a perturber file", for a
    # missing file and a folder alike.
    monkeypatch.chdir(tmp_path)
    status, out, err = _run(capsys, "precession", "earth", "--perturber", typed, "-o", "out.nc")
    assert status == 2 and out == "" and err.count("\n") == 1
    assert err == (
        f"wobble precession: error: --perturber: got {typed}; allowed: one of deimos, earth, jupiter, mars, mercury, "
        f"moon, neptune, phobos, saturn, sun, uranus, venus, or the path of a perturber file ({why})\n"
    )
    assert not (tmp_path / "out.nc").exists()


def test_unknown_body_is_refused(capsys):
    status, _, err = _run(capsys, "precession", "pluto")
    assert status == 2 and "BODY: got pluto" in err


def test_perturbers_given_say_which_catalogued_satellites_they_leave_out(capsys):
    """--perturber sun alone (the Sun only) printed Earth's rate without the Moon, and a residual of 3.7 million
    sigma, without a word that the Moon had been left out."""
    status, out, _ = _run(capsys, "precession", "--perturber", "sun", "earth", "--json")
    (earth,) = json.loads(out)
    assert status == 0 and [t["name"] for t in earth["terms"] if t["name"].startswith("moon")] == []
    assert (
        "left out: moon, mercury, venus, mars, jupiter, saturn, uranus, neptune (the catalogue's perturbers of Earth; "
        "the perturbers given replace them)"
    ) in earth["notes"]
    everything = ["moon", "mercury", "venus", "mars", "jupiter", "saturn", "uranus", "neptune"]
    status, out, _ = _run(capsys, "precession", *(f"--perturber={p}" for p in everything), "earth", "--json")
    assert not any(n.startswith("left out") for n in json.loads(out)[0]["notes"])
    status, out, _ = _run(capsys, "precession", "earth", "--json")  # the default: nothing left out
    assert not any(n.startswith("left out") for n in json.loads(out)[0]["notes"])


def test_one_perturber_by_name_is_that_perturber_not_its_letters():
    """perturbers="moon" is ["moon"]: it was iterated into "m", "o", ... and refused as the perturber "m"."""
    one = wobble.precession_rate("earth", perturbers="moon")
    listed = wobble.precession_rate("earth", perturbers=["moon"])
    assert one.rate == listed.rate and one.to_dict()["notes"] == listed.to_dict()["notes"]
