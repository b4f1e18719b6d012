"""`wobble run`: scenes to CF netCDF from the command line; exit 2 and nothing written on bad input."""

from __future__ import annotations

import json

import pytest

import wobble
from wobble.cli import main
from wobble.io.scene_file import example_scene_path


def _run(capsys, *args):
    status = main(list(args))
    out, err = capsys.readouterr()
    return status, out, err


def test_run_an_example_by_name_with_json(tmp_path, capsys):
    out_file = tmp_path / "racket.nc"
    status, out, err = _run(capsys, "run", "tennis_racket", "-o", str(out_file), "--json")
    assert status == 0 and err == f"wrote {out_file}\n"  # stdout is the JSON; files written go to stderr
    summary = json.loads(out)
    assert summary["model"] == "free-elliptic" and summary["output"] == str(out_file)
    assert summary["error_estimate"] <= summary["accuracy_requested"]
    ds = wobble.load(out_file)
    assert ds.attrs["model"] == "free-elliptic" and "wobble run tennis_racket" in ds.attrs["history"]


def test_run_a_scene_file_with_a_table(tmp_path, capsys):
    with example_scene_path("top_cusps").open() as fh:
        text = fh.read()
    scene = tmp_path / "top.toml"
    scene.write_text(text)
    status, out, err = _run(capsys, "run", str(scene), "-o", str(tmp_path / "top.nc"))
    assert status == 0 and not err
    assert "model" in out and "error estimate" in out and "heavy-top" in out


def test_forcing_a_model_for_comparison(tmp_path, capsys):
    status, out, _ = _run(capsys, "run", "top_loops", "-o", str(tmp_path / "a.nc"), "--model", "dop853", "--json")
    assert status == 0 and json.loads(out)["model"] == "dop853"
    assert wobble.load(tmp_path / "a.nc").attrs["model_reason"].startswith("forced")


def test_list_examples(capsys):
    status, out, _ = _run(capsys, "run", "--list", "--json")
    listed = json.loads(out)
    assert status == 0 and {s["name"] for s in listed} == set(wobble.example_scenes()) and len(listed) >= 9
    assert all(s["title"] for s in listed)  # one line each on what the scene shows


BAD_SCENE = """schema = "wobble-scene/1"
[body]
moments = { value = [1, 2, 3], unit = "kg" }
[initial]
omega = { value = [1, 0.1, 1], unit = "rad/s" }
[time]
stop = "1 s"
samples = 3
"""


@pytest.mark.parametrize(
    "args, words",
    [
        (["run", "{bad}", "-o", "{out}"], ["bad.toml", "body.moments.unit"]),
        (["run", "{tight}", "-o", "{out}"], ["tight.toml", "accuracy", "at least"]),
        (["run", "{missing}", "-o", "{out}"], ["nope.toml", "no such file"]),
        (["run", "tennis_racket", "-o", "{out}", "--model", "heavy-top"], ["model"]),
        (["run", "tennis_racket", "-o", "{out}", "--model", "rk4"], ["model", "rk4"]),
        (["run", "no_such_example", "-o", "{out}"], ["SCENE", "tennis_racket"]),
        (["run", "tennis_racket"], ["-o/--output"]),
        # What is wrong with the scene or --model comes before a missing -o (both said "-o/--output: missing").
        (["run", "{bad}"], ["bad.toml", "body.moments.unit"]),
        (["run", "tennis_racket", "--model", "rk4"], ["--model: got rk4"]),
        # A shipped scene's accuracy is not the user's to edit: the message says how to ask for another one.
        (
            ["run", "tennis_racket", "--model", "splitting", "-o", "{out}"],
            ["accuracy", "after 1 run)", "wobble example tennis_racket my_tennis_racket.toml"],
        ),
        (["run", "tennis_racket", "-o", "{folder}/deep/x.nc"], ["existing folder"]),
    ],
)
def test_bad_input_exits_2_with_one_line_and_writes_nothing(tmp_path, capsys, args, words):
    (tmp_path / "bad.toml").write_text(BAD_SCENE)
    tight = BAD_SCENE.replace('unit = "kg" }', 'unit = "kg m2" }').replace("[body]", "accuracy = 1e-17\n[body]")
    (tmp_path / "tight.toml").write_text(tight)
    subs = {
        "bad": str(tmp_path / "bad.toml"),
        "tight": str(tmp_path / "tight.toml"),
        "missing": str(tmp_path / "nope.toml"),
        "out": str(tmp_path / "out.nc"),
        "folder": str(tmp_path),
    }
    status, out, err = _run(capsys, *[a.format(**subs) for a in args])
    assert status == 2 and not out
    assert err.count("\n") == 1 and err.startswith("wobble run: error:")
    for w in words:
        assert w in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml", "tight.toml"]


def test_existing_output_needs_overwrite(tmp_path, capsys):
    out_file = tmp_path / "x.nc"
    out_file.write_text("keep me")
    status, _, err = _run(capsys, "run", "tennis_racket", "-o", str(out_file))
    assert status == 2 and "--overwrite" in err and out_file.read_text() == "keep me"
    status, _, _ = _run(capsys, "run", "tennis_racket", "-o", str(out_file), "--overwrite")
    assert status == 0 and wobble.load(out_file).attrs["model"] == "free-elliptic"


def test_help_has_an_example(capsys):
    with pytest.raises(SystemExit):
        main(["run", "--help"])
    assert "wobble run tennis_racket" in capsys.readouterr().out
