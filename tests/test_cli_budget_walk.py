"""What a fresh-user walk through the budgets (``modes``, ``chandler``, ``precession``, ``invert``)
found, each as a test of the behaviour a user should meet."""

from __future__ import annotations

import json
import math
import re

import pytest

from cli_run import run_cli

# ---------------------------------------------------------------------------
# 1. `wobble modes --mode` chooses what is shown, never the physics.
# ---------------------------------------------------------------------------


def _modes(argv, capsys):
    code, out, err = run_cli(["modes", *argv], capsys)
    assert code == 0, err
    return out


def _rows(text: str, name: str) -> list[str]:
    return [line for line in text.splitlines() if line.startswith(f"  {name} ")]


def test_mode_cw_gives_the_numbers_of_the_full_run(capsys):
    # Was: --mode CW turned the core coupling off: 432.07 d and "FCN effect +0.00 d" against 431.99 and -0.08.
    full, cw = _modes(["earth", "--json"], capsys), _modes(["earth", "--mode", "CW", "--json"], capsys)
    full, cw = json.loads(full)[0], json.loads(cw)[0]
    assert [m["mode"] for m in cw["modes"]] == ["CW"]
    assert cw["modes"][0] == next(m for m in full["modes"] if m["mode"] == "CW")
    for key in ("fcn_effect_on_chandler_days", "chandler_coupling_off_days", "chandler_budget_days"):
        assert cw[key] == full[key]
    assert cw["fcn_effect_on_chandler_days"] == pytest.approx(-0.08, abs=0.01)
    assert set(cw) == set(full)  # the same keys: only the list of modes is shorter

    full_text, cw_text = _modes(["earth"], capsys), _modes(["earth", "--mode", "CW"], capsys)
    assert _rows(cw_text, "CW") == _rows(full_text, "CW") and len(_rows(cw_text, "CW")) == 1
    assert not _rows(cw_text, "FCN") and "core flattening" not in cw_text
    chandler_line = next(line for line in full_text.splitlines() if "FCN effect" in line)
    assert chandler_line in cw_text.splitlines() and "FCN effect -0.08 d" in chandler_line


@pytest.mark.parametrize("extra", [[], ["--profile", "prem"]])  # the second is the help's example
def test_mode_fcn_shows_no_cw_row(extra, capsys):
    # Was: the CW row was printed (and listed in --json) whatever --mode said.
    full_text = _modes(["earth"], capsys)
    text = _modes(["earth", "--mode", "FCN", *extra], capsys)
    assert not _rows(text, "CW") and "observed CW" not in text and "Chandler wobble" not in text
    assert _rows(text, "FCN") == _rows(full_text, "FCN") and len(_rows(text, "FCN")) == 2
    assert "the observed FCN requires e_f" in text
    data = json.loads(_modes(["earth", "--mode", "FCN", "--json", *extra], capsys))[0]
    full = json.loads(_modes(["earth", "--json"], capsys))[0]
    assert [(m["mode"], m["frame"]) for m in data["modes"]] == [("FCN", "terrestrial"), ("FCN", "celestial")]
    assert data["modes"] == full["modes"][1:]
    assert data["core_flattening_required"] == full["core_flattening_required"]


def test_mode_selection_in_python_keeps_the_physics():
    import wobble

    full, only_cw = wobble.normal_modes("mars"), wobble.normal_modes("mars", modes=("CW",))
    assert [m.label for m in only_cw.modes] == ["CW_terrestrial"]
    assert only_cw.mode("CW") == full.mode("CW")
    assert only_cw.fcn_effect_on_chandler == full.fcn_effect_on_chandler
    assert only_cw.core_flattening_hydrostatic == full.core_flattening_hydrostatic


def test_modes_help_says_what_mode_does(capsys):
    code, out, _ = run_cli(["modes", "--help"], capsys)
    assert code == 0
    help_text = " ".join(out.split())
    assert "show only this mode" in help_text and "the numbers do not change" in help_text
    assert "modes to compute" not in help_text


# ---------------------------------------------------------------------------
# 2. and 3. `wobble chandler --sources`: in the JSON too, and in units a geodesist reads.
# ---------------------------------------------------------------------------


def _chandler(argv, capsys):
    code, out, err = run_cli(["chandler", *argv], capsys)
    assert code == 0, err
    return out


def test_sources_are_in_the_json(capsys):
    # Was: `--sources --json` was byte-identical to `--json`.
    plain = json.loads(_chandler(["earth", "--json"], capsys))[0]
    with_sources = json.loads(_chandler(["earth", "--json", "--sources"], capsys))[0]
    assert "parameters" not in plain
    params = with_sources.pop("parameters")
    assert with_sources.pop("deprecated_keys") == {"parameters[].unit_astropy": "parameters[].unit"}
    assert plain.pop("deprecated_keys") == {}  # chandler lists its renames in every run: none without --sources
    assert with_sources == plain  # the existing keys are unchanged
    by_name = {p["name"]: p for p in params}
    keys = {"name", "value", "uncertainty", "unit", "unit_label", "unit_astropy", "source", "status"}
    assert all(set(p) == keys and p["unit_astropy"] == p["unit"] for p in params)
    assert by_name["love_number_k2"]["value"] == pytest.approx(0.29525)
    assert by_name["love_number_k2"]["uncertainty"] == pytest.approx(0.003)
    assert by_name["love_number_k2"]["unit"] == "" and by_name["love_number_k2"]["status"] == "secondary"
    assert by_name["observed_chandler_period"]["unit"] == "d"
    assert "Vicente & Wilson 1997" in by_name["observed_chandler_period"]["source"]
    rate = by_name["observed_precession_rate"]
    assert rate["unit_label"] == "arcsec / cy" and rate["value"] == pytest.approx(-5038.481507)
    from astropy import units as u

    # "unit" is what astropy reads: the label it held, "arcsec / cy", astropy reads as arcseconds per cycle.
    assert u.Unit(rate["unit"]) == u.arcsec / (100 * u.yr) != u.Unit("arcsec / cy")
    for p in params:  # every unit parses, to what the catalogue means
        assert p["unit"] == "" or u.Unit(p["unit"]).to_string() == p["unit"]
    flag = by_name["observed_precession_includes_geodesic"]
    assert flag["value"] is True and flag["uncertainty"] is None


@pytest.mark.parametrize(("body", "flag"), [("earth", "yes"), ("mars", "no")])
def test_sources_text_speaks_units_not_astropy(body, flag, capsys):
    # Was: "+/- 1e-09 1" (the unit of dimensionless numbers), "includes_geodesic: 1 +/- 0 1", "arcsec / hyr".
    text = _chandler([body, "--sources"], capsys)
    listing = text[text.index("  parameters (") :].splitlines()[1:]
    assert len(listing) > 15
    for line in listing:
        assert re.search(r" 1; ", line) is None, line
        assert "hyr" not in line and "sday" not in line and "m2 kg" not in line
    assert f"    observed_precession_includes_geodesic: {flag}; " in text
    dimensionless = next(line for line in listing if line.startswith("    love_number_k2: "))
    assert re.match(r"    love_number_k2: [\d.]+ \+/- [\d.]+; ", dimensionless)
    if body == "earth":
        assert "    observed_precession_rate: -5038.481507 +/- 0.0008 arcsec / cy; " in text
        assert "    observed_fcn_period: -431.18 +/- 0.1 sidereal days; " in text
        assert "    fluid_core_equatorial_moment: 9.066e+36 +/- 9e+34 kg m2; " in text
        # A conventional constant catalogued with uncertainty 0 was "+/- 0 s", which reads as a lost digit.
        assert "    love_number_k2_period: 200 s (taken as exact); " in text
    assert not any(re.search(r"\+/- 0(\.0*)?( |;)", line) for line in listing)


def test_sources_help_names_the_json_list(capsys):
    code, out, _ = run_cli(["chandler", "--help"], capsys)
    assert code == 0 and "'parameters'" in " ".join(out.split())


# ---------------------------------------------------------------------------
# 4. `wobble precession`: the rate in mas/yr to the digits its uncertainty supports.
# ---------------------------------------------------------------------------


def _decimals(number: str) -> int:
    return len(number.partition(".")[2])


def _check_mas_per_year(text: str) -> int:
    found = 0
    for line in text.splitlines():
        if "mas/yr" not in line or "=" not in line:
            continue
        m = re.search(
            r"([+-]?\d+(?:\.\d+)?) \+/- (\d+(?:\.\d+)?)\s+= ([+-]?\d+(?:\.\d+)?) \+/- (\d+(?:\.\d+)?) mas/yr", line
        )
        assert m, line
        arcsec, arcsec_sigma, mas, mas_sigma = m.groups()
        assert _decimals(mas) == _decimals(mas_sigma), line
        assert len(mas_sigma.replace(".", "").lstrip("0")) == 2, line  # two significant digits of the +/-
        assert float(mas) == pytest.approx(10 * float(arcsec), abs=float(mas_sigma))
        assert float(mas_sigma) == pytest.approx(10 * float(arcsec_sigma), rel=0.05)
        found += 1
    return found


def test_precession_of_a_planet_file_in_mas_per_year(capsys, tmp_path, monkeypatch):
    # Was: "-1464.0 +/- 4.9   = -14640.3 mas/yr": a tenth of a mas/yr under a 49 mas/yr uncertainty.
    monkeypatch.chdir(tmp_path)
    code, _, err = run_cli(["example", "my_planet.toml"], capsys)
    assert code == 0, err
    code, text, err = run_cli(["precession", "--body-file", "my_planet.toml"], capsys)
    assert code == 0, err
    assert _check_mas_per_year(text) == 1
    assert "-14640.3" not in text


def test_precession_of_the_catalogue_in_mas_per_year(capsys):
    code, text, err = run_cli(["precession", "earth", "mars"], capsys)
    assert code == 0, err
    assert _check_mas_per_year(text) == 4  # model and observed, each planet
    assert "= -7608.3 +/- 2.1 mas/yr" in text  # Konopliv et al. 2016, as the literature writes it


# ---------------------------------------------------------------------------
# 5. `wobble invert`: each row of the summary to one decimal place.
# ---------------------------------------------------------------------------

SHORT = ["--seed", "5", "--steps", "200", "--burn", "100", "--walkers", "16", "--quiet"]
NUMBER = r"[+-]?\d+(?:\.\d+)?(?:e[+-]\d+)?"


def _places(number: str) -> int:
    return _decimals(number.partition("e")[0])


def _expected_places(half_width: float) -> int:
    from wobble.io.text import decimals_for

    return decimals_for(half_width)


def test_invert_rows_share_their_decimal_places(capsys):
    # Was: "1799.3 [1756.9, 1840]", "0.001813 [0.0017304, 0.001898]" in one row.
    # The same seed gives the same numbers: the text and the JSON of two runs describe one posterior.
    code, text, err = run_cli(["invert", "mars", *SHORT], capsys)
    assert code == 0, err
    code, out, err = run_cli(["invert", "mars", *SHORT, "--json"], capsys)
    assert code == 0, err
    data = json.loads(out)
    lines = text.splitlines()
    for p in data["parameters"]:
        line = next(line for line in lines if line.startswith(f"  {p['name']} "))
        m = re.match(rf"  \w+\s+({NUMBER})\s+\[({NUMBER}), ({NUMBER})\]\s+\[({NUMBER}), ({NUMBER})\]", line)
        assert m, line
        places = {_places(x) for x in m.groups()}
        assert places == {_expected_places((p["upper_68"] - p["lower_68"]) / 2)}, line
        assert float(m.group(1)) == pytest.approx(p["median"], abs=10.0 ** -min(places))
    for row in data["observables"]:
        line = next(line for line in lines if line.startswith(f"  {row['name']} "))
        numbers = re.findall(NUMBER, line[len(row["name"]) + 2 :].rsplit("  ", 1)[0])
        assert len({_places(x) for x in numbers}) == 1, line
        if row["measured"]:
            assert len(numbers) == 6, line  # measured +/- sigma, predictive median [68 %], model median
            spread = min(row["observed_uncertainty"], (row["predictive_upper_68"] - row["predictive_lower_68"]) / 2)
        else:
            assert len(numbers) == 4, line
            spread = (row["upper_68"] - row["lower_68"]) / 2
        assert _places(numbers[0]) == _expected_places(spread), line


def test_same_decimals_shares_a_power_of_ten_for_tiny_numbers():
    from wobble.api.inversion import _same_decimals

    assert _same_decimals((1799.3, 1756.9, 1840.0), 41.5) == ["1799", "1757", "1840"]
    assert _same_decimals((0.001813, 0.0017304, 0.001898), 8.4e-5) == ["0.001813", "0.001730", "0.001898"]
    assert _same_decimals((4.2e-8, 3.1e-8, 5.3e-8), 1.1e-8) == ["4.2e-08", "3.1e-08", "5.3e-08"]
    assert _same_decimals((math.nan, 1.0), 0.1) == ["nan", "1.00"]


# ---------------------------------------------------------------------------
# 6. `wobble invert --help`: why the short examples warn, said once.
# ---------------------------------------------------------------------------


def test_invert_help_explains_the_short_examples_warnings(capsys):
    from wobble.cli._examples import example_commands

    code, out, _ = run_cli(["invert", "--help"], capsys)
    assert code == 0
    examples = [argv for argv in example_commands(out) if argv[:2] == ["wobble", "invert"]]
    short = [argv for argv in examples if "--steps" in argv]
    assert len(short) >= 4  # mars_chandler_only, -o/--plot, --prior-only, --seed 7, my_setup.toml
    flat = " ".join(out.split())
    assert flat.count("R-hat is above 1.01") == 1
    assert "The examples with --steps are cut short" in flat and "leave out --steps" in flat
    # No single example is singled out as the one that warns.
    example_lines = [line for line in out.splitlines() if line.strip().startswith("wobble invert")]
    assert not any("R-hat" in line for line in example_lines)


def test_the_modes_figure_draws_only_the_modes_shown():
    # Was: `wobble modes earth --mode CW --plot` still drew the FCN panel.
    import wobble

    drawn = [ax.axison for ax in wobble.plot.modes.modes_figure([wobble.normal_modes("earth", modes=("CW",))]).axes]
    assert drawn == [True, True]  # profile, CW: no empty column for the FCN (it left a blank third)
    everything = wobble.plot.modes.modes_figure([wobble.normal_modes("earth")]).axes
    assert [ax.axison for ax in everything] == [True, True, True]
    # Every line of the CW panel is in its legend (the hydrostatic e_f line was not), and the budget line is
    # called what the text calls it.
    cw = everything[2]
    assert {line.get_label() for line in cw.get_lines()} <= set(t.get_text() for t in cw.get_legend().get_texts())
    assert "Chandler budget (coupling off)" in [t.get_text() for t in cw.get_legend().get_texts()]


def test_the_modes_figure_of_a_body_without_a_profile_draws_its_chandler_period():
    """wobble modes --body-file my_planet.toml printed a Chandler period of 511.89 d; its figure drew only a
    'no density profile' panel."""
    from astropy import units as u

    import wobble

    from wobble.io.shipped import find_shipped

    r = wobble.normal_modes(wobble.load_planet(str(find_shipped("my_planet.toml").path())))
    assert r.figure is None
    profile, cw = wobble.plot.modes.modes_figure([r]).axes
    assert not profile.axison and "no density profile" in profile.texts[0].get_text()
    period = r.mode("CW").period.to_value(u.day)
    (model,) = [line for line in cw.get_lines() if line.get_label() == "CW (model)"]
    assert model.get_ydata()[0] == pytest.approx(period)


def test_the_chandler_figure_marks_the_rigid_period_and_prints_the_text_s_digits():
    """The rigid step was a bar from the axis' left edge (0.85 x the rigid period), a length that meant
    nothing; the legend gave Mars' observed period as 206.9 +/- 0.5 where the text prints 206.90 +/- 0.50."""
    from astropy import units as u

    import wobble

    earth, mars = wobble.chandler_budget("earth"), wobble.chandler_budget("mars")
    axes = wobble.plot.chandler.budget_figure([earth, mars]).axes
    for ax, b in zip(axes, (earth, mars)):
        rigid = b.steps[0].period.to_value(u.day)
        assert all(bar.get_x() != ax.get_xlim()[0] for bar in ax.patches if bar.get_height() == 0.6)
        (mark,) = [line for line in ax.get_lines() if line.get_marker() == "D"]
        assert mark.get_xdata()[0] == pytest.approx(rigid) and f"{rigid:.1f} d" in [t.get_text() for t in ax.texts]
        assert ax.get_xlabel() == "period [d]"
    labels = [t.get_text() for t in axes[1].get_legend().get_texts()]
    assert "observed 206.90 ± 0.50 d" in labels


def test_the_chandler_figure_s_legend_covers_no_bar_nor_change():
    """my_planet.toml has two steps, rigid and elastic: the legend in the lower left, the corner Earth's
    waterfall leaves empty, covered its one bar. It now stands beside the axes for every planet."""
    import wobble
    from wobble.api.examples import example_path

    budgets = [wobble.chandler_budget(example_path("my_planet.toml")), wobble.chandler_budget("earth")]
    fig = wobble.plot.chandler.budget_figure(budgets)
    fig.canvas.draw()
    for ax in fig.axes:
        legend = ax.get_legend().get_window_extent()
        assert legend.x0 >= ax.get_window_extent().x1
        assert len(ax.patches) >= 1 and not any(legend.overlaps(p.get_window_extent()) for p in ax.patches)


def test_the_modes_chandler_panel_draws_the_model_s_uncertainty_beside_the_observed():
    """Mars' model, 205.6 +/- 2.7 d, against 206.9 +/- 0.5 d observed: with only the observed band drawn the
    model line looked 2.6 sigma off, where the text says -0.5 sigma."""
    import numpy as np

    import wobble

    r = wobble.normal_modes("mars")
    cw = r.mode("CW")
    panel = [ax for ax in wobble.plot.modes.modes_figure([r]).axes if ax.get_title() == "Chandler wobble (prograde)"]
    (ax,) = panel
    bands = [c for c in ax.collections if c.get_label() == "model ±1σ"]
    assert len(bands) == 1
    top, bottom = bands[0].get_paths()[0].vertices[:, 1].max(), bands[0].get_paths()[0].vertices[:, 1].min()
    model = ax.get_lines()[0].get_ydata()
    sigma = cw.period_uncertainty.to_value("d")
    assert top == pytest.approx(np.max(model) + sigma, rel=1e-9) and bottom == pytest.approx(
        np.min(model) - sigma, rel=1e-9
    )


def test_the_budget_s_summary_is_the_command_s_table(capsys):
    """ChandlerBudget had no text form in Python (print(budget) gave its repr), while the modes, the
    precession and the polar motion all had summary(). It is the command's table, but for its last line."""
    import wobble
    from wobble.cli import main
    from wobble.io.text import with_uncertainty

    budget = wobble.chandler_budget("mars")
    assert main(["chandler", "mars"]) == 0
    printed = capsys.readouterr().out.rstrip("\n").splitlines()
    text = budget.summary().splitlines()
    assert text[:-1] == printed[:-1] and printed[-1] == "  (sources of every number: wobble chandler mars --sources)"
    assert text[-1] == "  (sources of every number: summary(sources=True))"
    model = with_uncertainty(budget.period.to_value("d"), budget.period_uncertainty.to_value("d"))
    assert any(line.split()[:4] == ["model", *model.split()] for line in text)
    assert "love_number_k2: 0.169 +/- 0.006" in budget.summary(sources=True)
