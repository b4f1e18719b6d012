"""The work-precision harness (benchmarks/) measures the right error; wobble bench runs.

No timing assertions: only that errors are computed against the right reference, that
the runs are interleaved as documented, and that the command line behaves.
"""

from __future__ import annotations

import gc
import json
import sys
import types
from pathlib import Path

import numpy as np
import pytest

from wobble.cli import bench as cli_bench
from wobble.cli import main
from wobble.models.free import free_rotation

cli_bench.harness()  # puts this checkout's benchmarks/ on the path, as `wobble bench` does

from benchmarks import cases as C  # noqa: E402 - after cli_bench.harness() puts benchmarks/ on sys.path
from benchmarks import free as F  # noqa: E402 - after cli_bench.harness() puts benchmarks/ on sys.path
from benchmarks.timing import Run, measure, measures_resident_memory, peak_memory, time_at, traced_peak  # noqa: E402 - after cli_bench.harness() puts benchmarks/ on sys.path


def test_rel_and_phase_error_known_values():
    want = np.array([[3.0, 4.0, 0.0], [0.0, 1.0, 0.0]])
    got = want.copy()
    got[0, 0] += 5e-7  # |d| / |want| = 5e-7 / 5 on the first row
    assert C.rel_error(got, want) == pytest.approx(1e-7, rel=1e-9)
    assert C.rel_error(got[:1], want) == np.inf  # a run that returned the wrong number of outputs
    # a wobble vector rotated by 1e-9 rad about the figure axis: phase error 1e-9
    ang = np.linspace(0.0, 6.0, 7)
    w = np.stack([np.cos(ang), np.sin(ang), 10 * np.ones_like(ang)], axis=1) * 1e-6
    wr = np.stack([np.cos(ang + 1e-9), np.sin(ang + 1e-9), 10 * np.ones_like(ang)], axis=1) * 1e-6
    assert C.phase_error(wr, w) == pytest.approx(1e-9, rel=1e-5)
    # wrapping: a phase of pi - 1e-3 against -pi + 1e-3 differs by 2e-3, not 2 pi - 2e-3
    a = np.array([[np.cos(np.pi - 1e-3), np.sin(np.pi - 1e-3), 0.0]])
    b = np.array([[np.cos(-np.pi + 1e-3), np.sin(-np.pi + 1e-3), 0.0]])
    assert C.phase_error(a, b) == pytest.approx(2e-3, rel=1e-6)


def test_injected_perturbation_is_reported():
    """Feed a method's check a copy of the exact solution perturbed by a known amount."""
    case = F.free_case("free_generic", quick=True)
    ctx = case.context
    w = ctx["w_exact"].copy()
    delta = 3e-9
    k = w.shape[0] // 3
    w[k] *= 1 + delta  # one output off by a relative 3e-9
    wob = next(r for r in case.runs if r.method == "wobble DOP853")
    res = wob.check(types.SimpleNamespace(omega=w[:, None, :]))
    assert res["error_vs_exact"] == pytest.approx(delta, rel=1e-6)
    sc = next(r for r in case.runs if r.method == "scipy DOP853")
    res = sc.check(types.SimpleNamespace(success=True, y=w.T))
    assert res["error"] == pytest.approx(delta, rel=1e-6)
    # the exact method's check reads the mpmath reference times: perturb one of them
    ex = next(r for r in case.runs if r.method == "wobble exact")
    w2 = ctx["w_exact"].copy()
    assert ex.check(w2)["error"] < 1e-14
    w2[ctx["iw"][5]] *= 1 + delta
    assert ex.check(w2)["error"] == pytest.approx(delta, rel=1e-3)
    # a failed SciPy run is an infinite error, not a crash
    assert sc.check(types.SimpleNamespace(success=False, y=w.T[:, :5]))["error"] == np.inf


def test_error_of_a_small_case_matches_an_independent_computation():
    """Symmetric body I = (1, 1, 2), omega0 = (0.1, 0, 1): omega_perp turns at 1 rad/s exactly."""
    I = np.array([1.0, 1.0, 2.0])
    w0 = np.array([0.1, 0.0, 1.0])
    t = np.linspace(0.0, 20.0, 41)
    sol = F.solve(F.free_euler_rhs(I), t, w0, "RK45", 1e-5, 1e-8)
    got = F.sol_omega(sol, t.size)
    harness = C.rel_error(got, free_rotation(I, w0).omega(t))
    by_hand = max(
        float(
            np.sqrt((got[i, 0] - 0.1 * np.cos(ti)) ** 2 + (got[i, 1] - 0.1 * np.sin(ti)) ** 2 + (got[i, 2] - 1.0) ** 2)
        )
        / float(np.sqrt(0.01 + 1.0))
        for i, ti in enumerate(t)
    )
    assert 1e-9 < harness < 1e-2
    assert harness == pytest.approx(by_hand, rel=1e-6)


def test_measure_interleaves_and_checks_the_warm_up_output():
    calls = []

    def maker(name):
        def fn():
            calls.append(name)
            return name

        return fn

    runs = [
        Run("a", "1", maker("a"), lambda o: {"error": 1.0 if o == "a" else 0.0}),
        Run("b", "1", maker("b"), lambda o: {"error": 2.0}),
    ]
    rows = measure(runs, repeats=2, slow_s=10.0)
    # warm-ups first, then rounds in which every run goes once (fast runs: 3 x repeats)
    assert calls[:2] == ["a", "b"]
    assert calls[2:] == ["a", "b"] * 6
    assert [r["error"] for r in rows] == [1.0, 2.0]
    assert all(r["timed_runs"] == 6 and r["t_min"] <= r["t_median"] for r in rows)


def test_measure_never_times_numba_compilation(monkeypatch):
    """A run whose warm-up compiled is run once more for its time, and a timed run that compiled is run
    again: the clock (a fake one, advanced 100 "s" by a call that compiles and 1 by one that does not)
    shows only runs that did not compile. Before, a warm-up over ``slow_s`` was the run's only timing."""
    nb = pytest.importorskip("numba")
    from benchmarks import timing

    now = [0.0]
    monkeypatch.setattr(timing, "clock", lambda: now[0])

    @nb.njit
    def kernel(x):
        return x + 1

    calls = {"a": [], "b": []}

    def maker(name, arg):
        def fn():
            before = len(kernel.signatures)
            kernel(arg(len(calls[name])))
            compiled = len(kernel.signatures) > before
            calls[name].append(compiled)
            now[0] += 100.0 if compiled else 1.0
            return name

        return fn

    said = []
    runs = [
        # a compiles kernel(float) in its warm-up; b compiles kernel(int) in its second timed run
        Run("a", "1", maker("a", lambda k: 1.0), lambda o: {"error": 0.0}),
        Run("b", "1", maker("b", lambda k: 1 if k == 2 else 1.0), lambda o: {"error": 0.0}),
    ]
    try:
        rows = measure(runs, repeats=2, slow_s=10.0, progress=said.append)
    finally:
        gc.unfreeze()
    assert calls["a"] == [True, False, False, False]  # warm-up (compiles), its re-run, two timed runs
    assert calls["b"] == [False, False, True, False]  # warm-up, timed, timed (compiles: discarded), again
    for row in rows:
        assert row["t_min"] == row["t_median"] == 1.0 and row["timed_runs"] == 2 and not row["timed_once"]
    assert [r["warm_up_jit"] for r in rows] == ["compiled", None]
    assert any(line.strip().startswith("compiling the Numba kernels of a") for line in said)

    def compiles_every_time():
        nb.njit(lambda: 1.0)()  # a new dispatcher: compiled at every call

    try:
        with pytest.raises(RuntimeError, match="Numba loaded or compiled"):
            measure([Run("c", "1", compiles_every_time, lambda o: {"error": 0.0})], repeats=1)
    finally:
        gc.unfreeze()


def _numba_signatures() -> int:
    """Signatures compiled (or loaded from the disk cache) by the Numba dispatchers of wobble's modules."""
    if "numba" not in sys.modules:
        return 0
    from numba.core.dispatcher import Dispatcher

    return sum(
        len(v.signatures)
        for name, module in list(sys.modules.items())
        if name.startswith("wobble.") and module is not None
        for v in list(vars(module).values())
        if isinstance(v, Dispatcher)
    )


def test_time_at_and_peak_memory():
    pts = [(1e-4, 1.0), (1e-8, 100.0)]
    assert time_at(pts, 1e-6) == pytest.approx(10.0)
    assert time_at(pts, 1e-10) is None  # never reached
    assert time_at(pts, 1e-2) == 1.0  # reached by its cheapest point
    # 10^7 float64 = 80 MB, whatever earlier runs freed (the child measures fresh pages)
    junk = [np.ones(10**6) for _ in range(30)]
    del junk
    for measure_peak in (peak_memory, traced_peak):
        assert 8.0e7 <= measure_peak(lambda: np.ones(10**7)) <= 8.4e7, measure_peak
        assert measure_peak(lambda: None) < 2**20
    if measures_resident_memory():
        assert peak_memory(lambda: 1 / 0) is None  # a failing run reports nothing


def test_wobble_bench_smoke_json(capsys, tmp_path, monkeypatch):
    from benchmarks import harness

    # Every call of every run, with the Numba signatures it added: only a warm-up may add any.
    added = {}
    measure = harness.measure

    def watched(runs, *args, **kwargs):
        for r in runs:
            log = added.setdefault((r.method, r.setting), [])

            def fn(fn=r.fn, log=log):
                before = _numba_signatures()
                out = fn()
                log.append(_numba_signatures() - before)
                return out

            r.fn = fn
        return measure(runs, *args, **kwargs)

    monkeypatch.setattr(harness, "measure", watched)
    report = tmp_path / "perf.md"
    code = main(
        [
            "bench",
            "--smoke",
            "--case",
            "torqued_asymmetric_top",
            "--json",
            "--plot",
            str(tmp_path / "figs"),
            "-o",
            str(report),
        ]
    )
    assert code == 0
    out, err = capsys.readouterr()
    data = json.loads(out)
    assert out.startswith('{\n  "meta"')  # indented by 2, as every command's --json
    # every file written is named on stderr (stdout is the JSON document)
    figure = tmp_path / "figs" / "work_precision_torqued_asymmetric_top.png"
    assert err.splitlines()[-2:] == [f"wrote {figure}", f"wrote {report}"]
    assert set(data) >= {"meta", "cases", "ensembles", "targets"}
    assert data["meta"]["mode"] == "smoke" and data["meta"]["versions"]["numpy"] == np.__version__
    (case,) = data["cases"]
    assert case["key"] == "torqued_asymmetric_top"
    methods = {r["method"] for r in case["rows"]}
    assert {"scipy DOP853", "wobble DOP853", "wobble splitting-6"} <= methods
    for r in case["rows"]:
        assert {"method", "setting", "error", "t_min", "t_median", "timed_runs", "peak_memory_bytes"} <= set(r)
        assert 0 < r["error"] < 1e-3
    # a smoke run judges no target: it runs fewer settings than the full run
    (target,) = [t for t in data["targets"] if t["case"] == "Torqued: asymmetric top"]
    assert target["met"] is None and target["status"] == "not judged"
    assert (tmp_path / "figs" / "work_precision_torqued_asymmetric_top.png").stat().st_size > 1000
    text = report.read_text()
    assert "## Targets" in text and "figs/work_precision_torqued_asymmetric_top.png" in text
    # no timed run compiled or loaded a Numba kernel: every run's calls after its warm-up added no signature
    assert len(added) == len(case["rows"]) and all(len(calls) >= 2 for calls in added.values())
    assert all(calls[1:] == [0] * (len(calls) - 1) for calls in added.values()), added


def test_wobble_bench_names_the_files_it_writes(capsys, tmp_path, monkeypatch):
    """Without --json, the table on stdout, then a "wrote PATH" line per file (as every command)."""
    monkeypatch.chdir(tmp_path)
    argv = ["bench", "--smoke", "--case", "torqued_asymmetric_top", "-o", "r.md", "--plot", "figs"]
    assert main(argv) == 0
    out = capsys.readouterr().out.splitlines()
    assert "Targets:" in out
    assert out[-2:] == [f"wrote {Path('figs', 'work_precision_torqued_asymmetric_top.png')}", "wrote r.md"]
    assert (tmp_path / "r.md").is_file() and (tmp_path / "figs" / "work_precision_torqued_asymmetric_top.png").is_file()


@pytest.mark.parametrize(
    "argv",
    [
        ["bench", "--repeats", "0"],
        ["bench", "--case", "no_such_case"],
        ["bench", "--smoke", "-o", "/no/such/folder/report.md"],
        ["bench", "--quick", "--smoke"],
        ["bench", "--bogus"],
    ],
)
def test_wobble_bench_bad_input_exits_2_with_one_line(argv, capsys):
    try:
        code = main(argv)
    except SystemExit as exc:
        code = exc.code
    err = capsys.readouterr().err
    assert code == 2
    # an unknown option is refused by the top-level parser ("wobble: error: ..."), as for every command
    assert err.count("\n") == 1 and err.startswith(("wobble bench: error:", "wobble: error:"))


def test_quick_judges_targets_only_with_the_full_runs_methods():
    """--quick keeps every setting of the methods a torqued target compares (SciPy's DOP853 and
    every wobble integrator), so it judges that target as the full run does; a case built with
    fewer settings (the free body's DOP853 stops at rtol 1e-8) is not judged."""
    from benchmarks import harness
    from benchmarks.torqued import torqued_case

    full, quick = torqued_case("asymmetric top", False), torqued_case("asymmetric top", True)

    def kept(case):
        return {(r.method, r.setting) for r in case.runs if r.method == "scipy DOP853" or r.method.startswith("wobble")}

    assert kept(quick) == kept(full) and quick.complete
    assert len(quick.runs) < len(full.runs)
    row = {"method": "wobble exact", "setting": "omega", "error": 1e-16, "t_min": 1e-3}
    res = {
        "meta": {"mode": "quick"},
        "ensembles": [],
        "cases": [
            {
                "key": "free_generic",
                "complete": False,
                "rows": [row, {"method": "scipy DOP853", "setting": "rtol 1e-12", "error": 1e-9, "t_min": 1.0}],
            }
        ],
    }
    (t,) = [t for t in harness.targets(res) if t["case"] == "generic free body"]
    assert t["met"] is None and t["status"] == "not judged" and "fewer settings" in t["measured"]
    res["cases"][0]["complete"] = True
    (t,) = [t for t in harness.targets(res) if t["case"] == "generic free body"]
    assert t["met"] is True


def test_user_level_rows_measure_what_the_api_returns():
    """The user-level top case checks the Dataset's attitude against mpmath (perturbing one
    reference sample shows up as that error) and times the plain DOP853 without events."""
    from benchmarks import user_level as U

    case = U.user_top_case(quick=True)
    api = next(r for r in case.runs if r.method == U.API_TOP)
    ds = api.fn()
    assert set(ds.data_vars) >= {"theta", "omega", "attitude", "energy_drift"}
    assert api.check(ds)["error"] < 1e-13
    q = ds["attitude"].values.copy()
    q[-1] = [0.0, 1.0, 0.0, 0.0]  # the last output (a reference time: 1000.25 periods) turned by pi
    assert api.check({"attitude": types.SimpleNamespace(values=q)})["error"] > 1.0
    plain = next(r for r in case.runs if r.method == U.PLAIN)
    assert "no events" in plain.method and "rtol 1e-12" in plain.setting


def test_wobble_bench_from_an_installed_copy_is_one_line(monkeypatch, tmp_path, capsys):
    """Installed without the source tree, `wobble bench` refuses in one line (exit 2)."""
    import wobble

    fake = tmp_path / "site-packages" / "wobble"
    fake.mkdir(parents=True)
    monkeypatch.setattr(wobble, "__file__", str(fake / "__init__.py"))
    code = main(["bench", "--smoke"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "source checkout" in err


def test_the_text_report_reads_as_text():
    """The text began with a blank line, showed the docs' reST markup (``|omega - omega_ref|``), and its
    ensemble rows had no header (a blank members column, an unlabelled ratio)."""
    from benchmarks.harness import text_table

    res = {
        "cases": [{"title": "T", "key": "k", "outputs": 3, "error_measure": "max of ``|w - w_ref|``", "rows": []}],
        "ensembles": [
            {
                "title": "Ensemble: E",
                "scipy": [
                    {"method": "scipy DOP853 (loop)", "setting": "rtol 1e-07", "error": 1e-7, "per_member_s": 4e-3}
                ],
                "rows": [
                    {
                        "method": "wobble exact flow",
                        "setting": "free_flow",
                        "members": 100,
                        "error": 1e-14,
                        "per_member_s": 4e-5,
                        "ratio_vs_scipy": 100.0,
                    }
                ],
            }
        ],
        "targets": [],
    }
    text = text_table(res)
    assert text.startswith("T (k), 3 outputs; error: max of |w - w_ref|") and "``" not in text
    lines = text.splitlines()
    header = lines[lines.index("Ensemble: E") + 1]
    assert header.split() == ["method", "setting", "members", "error", "time", "per", "member", "vs", "scipy"]


def test_the_work_precision_label_is_plain_wrapped_text_and_names_the_floor_only_when_used():
    """The torqued cases' label held the docs' reST (``omega``), ran past both edges of the figure, and said
    "(zero drawn at 1e-17)" where no error was zero."""
    from wobble.plot.bench import ERROR_FLOOR, work_precision_figure

    what = "max over the outputs of ``|omega - omega_ref| / |omega_ref|`` and of the attitude angle (rad)"
    rows = [{"method": "a", "error": 1e-9, "t_min": 1e-3}, {"method": "a", "error": 1e-12, "t_min": 2e-3}]
    ax = work_precision_figure("case", rows, xlabel=what).axes[0]
    label = ax.get_xlabel()
    assert "``" not in label and "zero drawn" not in label and max(map(len, label.splitlines())) <= 95
    rows.append({"method": "a", "error": 0.0, "t_min": 3e-3})
    floored = work_precision_figure("case", rows, xlabel=what).axes[0].get_xlabel()
    assert f"(zero drawn at {ERROR_FLOOR:g})" in " ".join(floored.split())
