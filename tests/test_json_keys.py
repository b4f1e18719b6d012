"""One rule for renamed JSON keys (wobble.io.json_keys), and the commands that follow it: each alias holds its
new key's value, and a command's keys do not depend on its options."""

from __future__ import annotations

import json

import pytest

from json_listings import listings as _listings
from wobble.cli import main
from wobble.io.json_keys import deprecate, values_at


def test_deprecate_aliases_keys_in_nested_objects_lists_and_maps():
    doc = {
        "a_days": 1.0,
        "rows": [{"new": 1}, {"new": 2}, {"other": 3}],
        "methods": {"k": {"rms_mas": 4}, "l": {"rms_mas": 5}},
        "details": {"x": 0},
    }
    renames = {
        "a": "a_days",
        "rows[].old": "rows[].new",
        "methods.*.rms": "methods.*.rms_mas",
        "details.q": "a_days",  # across parents: one value each
    }
    out = deprecate(doc, renames)
    assert out is doc and out["a"] == 1.0 and out["details"]["q"] == 1.0
    assert [r.get("old") for r in out["rows"]] == [1, 2, None]  # no alias where the new key is absent
    assert values_at(out, "methods.*.rms") == [4, 5] == values_at(out, "methods.*.rms_mas")
    assert out["deprecated_keys"] == renames
    # A second call adds to the listing.
    deprecate(out, {"b": "a_days"})
    assert out["deprecated_keys"] == {**renames, "b": "a_days"} and out["b"] == 1.0
    with pytest.raises(ValueError, match="single values"):
        deprecate({"rows": []}, {"rows[].x": "y"})


def _json(capsys, *args):
    assert main([*args, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def _check_aliases(doc):
    """Every old path of ``deprecated_keys`` holds exactly what its new path holds (and there is one)."""
    assert doc["deprecated_keys"]
    for old, new in doc["deprecated_keys"].items():
        assert values_at(doc, old) == values_at(doc, new) != [], (old, new)


def test_free_and_top_print_the_same_keys_whatever_the_options(capsys, tmp_path):
    """free and top printed t_end_s, samples and t_end_chosen_by only with --t-end, -o or --plot, and free its
    flip times only for a body that flips; output and plot only when written. Now null (or []) otherwise."""
    free = ["free", "--inertia", "1", "2", "3", "--omega", "0.1", "0", "1"]
    plain = _json(capsys, *free)
    spanned = _json(capsys, *free, "--t-end", "10", "-o", str(tmp_path / "f.nc"))
    assert set(plain) == set(spanned)
    assert plain["t_end_s"] is None and plain["flip_times_s"] == [] and plain["flips_in_span"] == 0
    assert plain["output"] is None and plain["plot"] is None and spanned["output"] == str(tmp_path / "f.nc")
    flipping = _json(capsys, "free", "--inertia", "1", "2", "3", "--omega", "0.01", "1", "0.01", "--t-end", "1e5")
    assert set(flipping) == set(plain) and flipping["flips_in_span"] > 1000 == len(flipping["flip_times_s"])
    # Over 1e13 s (1.9e11 flips) the count is made without the list, which ran out of memory.
    far = _json(capsys, "free", "--inertia", "1", "2", "3", "--omega", "1e-6", "1", "1e-6", "--t-end", "1e13")
    assert far["flips_in_span"] > 1e11 and len(far["flip_times_s"]) == 1000
    # The error estimate in run's flat form; the object it was is an alias for one release.
    assert plain["error_estimate"]["omega_relative"] == plain["error_estimate_omega_relative"]
    _check_aliases(plain)
    assert main(free) == 0 and "None" not in capsys.readouterr().out  # the text has no span row without one

    top = ["top", "--I1", "1", "--I3", "0.5", "--mgl", "1", "--theta0", "30", "--omega3", "10"]
    plain = _json(capsys, *top)
    spanned = _json(capsys, *top, "--t-end", "5")
    assert set(plain) == set(spanned) and plain["samples"] is None and spanned["t_end_s"] == 5
    assert plain["nutation_class"] == plain["nutation"] and plain["error_estimate_attitude_rad"] >= 0
    _check_aliases(plain)
    assert main(top) == 0 and "None" not in capsys.readouterr().out


def test_inertia_names_its_output_whether_or_not_it_wrote_one(capsys, tmp_path):
    plain = _json(capsys, "inertia", "--solid", "box", "--mass", "2", "--edges", "1", "2", "3")
    written = _json(
        capsys, "inertia", "--solid", "box", "--mass", "2", "--edges", "1", "2", "3", "-o", str(tmp_path / "i.nc")
    )
    assert set(plain) == set(written) and plain["output"] is None and written["output"] == str(tmp_path / "i.nc")


def test_renamed_keys_alias_their_new_names(capsys):
    """modes' q (Omega^2 a^3/GM) is centrifugal_ratio, as forecast's q is the Chandler Q; chandler --sources'
    unit is what astropy reads."""
    (earth,) = _json(capsys, "modes", "earth")
    figure = earth["hydrostatic_figure"]
    assert figure["centrifugal_ratio"] == figure["q"] == pytest.approx(0.00345, rel=0.01)
    _check_aliases(figure)
    (budget,) = _json(capsys, "chandler", "mars", "--sources")
    _check_aliases(budget)
    assert budget["deprecated_keys"] == {"parameters[].unit_astropy": "parameters[].unit"}
    from astropy import units as u

    for p in budget["parameters"]:  # every unit is one astropy reads, to itself
        assert p["unit"] == "" or u.Unit(p["unit"]).to_string() == p["unit"]


def test_every_object_that_holds_an_alias_lists_it(capsys):
    """polar-motion's estimates and precession's terms had their aliases added by hand (one by a helper of their
    own, which listed nothing in the estimates): now every command goes through ``deprecate``, and each object
    holding an old name lists it, and its listing holds."""
    pm = _json(capsys, "polar-motion", "--start", "2000-01-01", "--end", "2012-12-31")
    estimates = list(pm["estimates"].values())
    assert len(list(_listings(pm))) == 1 + len(estimates) == 3
    for estimate in estimates:
        assert estimate["deprecated_keys"] == {
            "annual_amplitude_mas": "annual_prograde_amplitude_mas",
            "annual_amplitude_uncertainty_mas": "annual_prograde_amplitude_uncertainty_mas",
        }
    (prec,) = _json(capsys, "precession", "earth")
    assert prec["terms"] and all(t["value"] == t["value_arcsec_per_century"] for t in prec["terms"])
    for doc in (pm, prec):
        for listing in _listings(doc):
            _check_aliases(listing)


@pytest.mark.parametrize("command", ["chandler", "modes", "precession"])
def test_the_planet_commands_name_their_files_in_every_body_s_object(capsys, tmp_path, command):
    """chandler, modes and precession print a list, one object per body, and named no file they wrote (a
    single object got output and plot; a list was passed over). Each body's object now names the files,
    which hold every body, and null when none was asked for."""
    plain = _json(capsys, command, "earth", "mars")
    assert [(d["output"], d["plot"]) for d in plain] == [(None, None)] * 2
    nc, png = tmp_path / "b.nc", tmp_path / "b.png"
    written = _json(capsys, command, "earth", "mars", "-o", str(nc), "--plot", str(png))
    assert [(d["output"], d["plot"]) for d in written] == [(str(nc), str(png))] * 2
    assert nc.stat().st_size > 0 and png.stat().st_size > 0
    assert [set(d) for d in written] == [set(d) for d in plain]
