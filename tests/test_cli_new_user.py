"""What a fresh-user review of the command line found (a clean install, every help example and
page followed as printed), each as a test of the behaviour a user should meet."""

from __future__ import annotations

import inspect
import json
import re
from importlib import resources
from pathlib import Path

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
    # Was: "got [-1.  2.  3.] m2 kg" (NumPy's print).
    code, out, err = _run(["free", "--inertia", "-1", "2", "3", "--omega", "1", "0.1", "1"], capsys)
    assert code == 2 and err.startswith("wobble free: error: --inertia: got (-1, 2, 3) m2 kg; allowed: positive values")


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
    for name in wobble.__all__:
        obj = getattr(wobble, name)
        texts[f"wobble.{name}"] = inspect.getdoc(obj) or ""
        for attr, member in vars(obj).items() if inspect.isclass(obj) else ():
            if not attr.startswith("_"):
                texts[f"wobble.{name}.{attr}"] = inspect.getdoc(member) or ""
    return texts


def test_user_facing_text_cites_no_internal_document():
    # Was: "Issue 8's top ... (notes section 5.7)" in the description of the top_cusps scene.
    texts = _shipped_texts()
    assert len(texts) > 100 and any(k.endswith(".toml") for k in texts)
    found = {k: m.group(0) for k, v in texts.items() if (m := _INTERNAL.search(v))}
    assert found == {}
