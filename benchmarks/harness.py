"""Run the work-precision benchmark and write its report.

``run(args)`` is ``wobble bench`` and ``main(argv)`` is ``scripts/work_precision.py``. Modes:

* the full run: every case, every setting; what docs/performance.md shows, about 20 min;
* ``--quick``: fewer settings and repeats, ensembles up to 10^4 members, 5-8 min. A
  target is judged only where the methods it compares ran at the full run's settings
  (the torqued cases keep them; elsewhere the target shows "not judged");
* ``--smoke``: a few seconds once the Numba kernels are cached on disk, one setting per method
  on two short cases: the harness's own test; no target is judged. The first run after
  installing also compiles the kernels (about 20 s), which no timing includes
  (:func:`benchmarks.timing.measure`).
"""

from __future__ import annotations

import argparse
import datetime
import gc
import os
import platform
import sys
import time
from pathlib import Path

import numpy as np

from benchmarks import top as topcases
from benchmarks import user_level
from benchmarks.ensemble import best_ratio, ensemble
from benchmarks.free import free_case
from benchmarks.report import USER_REPORT, is_docs_page
from benchmarks.timing import measure, measures_resident_memory, peak_memory, time_at
from benchmarks.torqued import torqued_case
from wobble.cli._output import finish
from wobble.cli.bench import CASE_KEYS, add_arguments
from wobble.errors import InputError
from wobble.numerics import compiled

TOP = {"top_cusps": 0, "top_undulating": 1, "top_loops": 2, "top_sleeping": 3}
# --smoke: two short cases (the torqued top's 5 s and 30 s of free-body ensembles, 100 members).
SMOKE_KEYS = ("torqued_asymmetric_top", "ensemble_free")


def _versions() -> dict:
    """Versions from the installed distributions' metadata (importing matplotlib or MuJoCo only
    to read a version would cost a second)."""
    from importlib.metadata import PackageNotFoundError, version

    def v(name):
        try:
            return version(name)
        except PackageNotFoundError:
            return None

    return {
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scipy": v("scipy"),
        "matplotlib": v("matplotlib"),
        "mujoco": v("mujoco"),
        "wobble": v("wobble"),
        "machine": platform.machine(),
        "processor": platform.processor() or "unknown CPU",
        "system": f"{platform.system()} {platform.release()}",
        "cpus": os.cpu_count(),
    }


def build_case(key: str, mode: str):
    quick = mode != "full"
    if key.startswith("free_"):
        return free_case(key, quick)
    if key in TOP:
        label, refname, kw = topcases.CASES[TOP[key]]
        dts = None
        if mode == "full":
            dts = {"RK4": [1e-2, 3e-3, 1e-3], "Euler": [1e-3, 1e-4]} if key == "top_cusps" else {"RK4": [1e-2, 3e-3]}
        elif mode == "quick":
            dts = {"RK4": [1e-2], "Euler": [1e-3]}
        return topcases.top_case(key, label, refname, kw, quick, dts)
    if key == "user_top":
        return user_level.user_top_case(quick)
    if key == "user_free":
        return user_level.user_free_case(quick)
    return torqued_case("satellite" if key == "torqued_satellite" else "asymmetric top", quick)


def _smoke_trim(case):
    """--smoke: one setting per method (the loosest); no Radau, no NumPy DOP853 and only the
    6th-order splitting (seconds matter here: it is the harness's own test)."""
    seen, keep = set(), []
    skip = ("scipy Radau", "wobble DOP853 (NumPy)", "wobble splitting-2", "wobble splitting-4")
    for r in case.runs:
        if r.method not in seen and r.method not in skip:
            seen.add(r.method)
            keep.append(r)
    case.runs = keep
    case.complete = False
    return case


def _load() -> list[float] | None:
    """The 1, 5 and 15 minute load averages (None where the platform has none)."""
    try:
        return [round(x, 2) for x in os.getloadavg()]
    except (AttributeError, OSError):
        return None


def run_benchmark(mode: str = "full", keys=None, repeats: int | None = None, progress=None) -> dict:
    """Run the cases and return the JSON-ready results (see ``wobble bench --json``)."""
    if not keys:
        keys = SMOKE_KEYS if mode == "smoke" else CASE_KEYS
    keys = list(keys)
    repeats = repeats or {"full": 3, "quick": 2, "smoke": 1}[mode]
    say = progress or (lambda s: None)
    started = time.perf_counter()
    # One full collection, then the heap as it is now is left out of every later collection
    # (gc.freeze): the collections before each timed run scan only what the runs made. A full
    # collection of the ~10^6 objects of SciPy, astropy and xarray takes ~0.1 s each time.
    gc.collect()
    gc.freeze()
    try:
        # A status line when Numba starts compiling outside a warm-up (a case's references); measure()
        # says which method's kernels it compiles in a warm-up.
        with compiled.compilation_notice(
            lambda: say("  compiling Numba kernels (first run after installing only: they are then cached on disk) ...")
        ):
            return _run_cases(mode, keys, repeats, say, started)
    finally:
        gc.unfreeze()


def _run_cases(mode, keys, repeats, say, started) -> dict:
    out = {
        "meta": {
            "mode": mode,
            "repeats": repeats,
            "date": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds"),
            "versions": _versions(),
            "load_start": _load(),
            "timing": "one warm-up run (its output is the one checked), then min and median of the repeats, "
            "every run once per round (interleaved); runs whose warm-up took over 2 s are timed once "
            "(their warm-up); runs under 50 ms get three times the repeats; Numba-compiled kernels "
            "are loaded from their disk cache (or compiled) in the warm-up, which is not timed: a run whose "
            "warm-up imported Numba, loaded or compiled kernels is run once more, and that run's time stands "
            "for the warm-up's, and a timed run during which Numba did any of that is discarded and run "
            "again; a garbage "
            "collection before each timed run scans only what the runs made (what existed after the warm-ups "
            "is frozen out of it: a full collection evicts the CPU caches a millisecond run then starts from)",
            "memory": (
                "peak resident memory that one run of each method at its loosest setting adds to the "
                "process, at the case's full output size (Linux VmHWM - VmRSS in a forked child after "
                "returning free heap to the system; everything the run makes resident counts, C "
                "libraries included; '-' where it could not be measured)"
                if measures_resident_memory()
                else "tracemalloc peak (Python and NumPy allocations) of one run of each method at its "
                "loosest setting, at the case's full output size"
            ),
        },
        "cases": [],
        "ensembles": [],
    }
    for key in keys:
        if key.startswith("ensemble_"):
            which = key.split("_", 1)[1]
            sizes = {"full": [100, 1000, 10_000, 100_000, 1_000_000], "quick": [100, 1000, 10_000], "smoke": [100]}[
                mode
            ]
            say(f"{key}")
            res = ensemble(
                which,
                sizes,
                repeats,
                cap_s=60.0 if mode == "full" else 10.0,
                progress=say,
                scipy_rtols=(1e-7,) if mode == "smoke" else (1e-7, 1e-9, 1e-11),
            )
            out["ensembles"].append(res)
            continue
        case = build_case(key, mode)
        if mode == "smoke":
            _smoke_trim(case)
        say(f"{key}: {len(case.runs)} runs")
        rows = measure(case.runs, repeats, progress=say)
        memory = {}
        for r in case.runs:
            if r.method not in memory:  # its loosest setting (the first), at the full output size
                memory[r.method] = (r.setting, peak_memory(r.fn))
        for row in rows:
            m = memory.get(row["method"])
            row["peak_memory_bytes"] = m[1] if m and m[0] == row["setting"] else None
        extra = {}
        if key == "free_earth":
            xs = case.context["t"] * 2.4e-7
            extra["np_sin_same_size_s"] = min(_t(lambda: np.sin(xs)) for _ in range(20))
        out["cases"].append(
            {
                "key": key,
                "title": case.title,
                "description": case.description,
                "error_measure": case.error_measure,
                "reference": case.reference,
                "outputs": case.outputs,
                "notes": case.notes,
                "rows": rows,
                "complete": case.complete,
                **extra,
            }
        )
        if "stages" in case.context:
            out["cases"][-1]["stages"] = case.context["stages"]
    out["meta"]["seconds"] = time.perf_counter() - started
    out["meta"]["load_end"] = _load()
    out["targets"] = targets(out)
    return out


def _t(fn):
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


# ---------------------------------------------------------------------------
# Targets
# ---------------------------------------------------------------------------
def _row(case, method, setting=None):
    for r in case["rows"]:
        if r["method"] == method and (setting is None or r["setting"].startswith(setting)):
            return r
    return None


def targets(res: dict) -> list[dict]:
    """Each target: what was measured, and whether it is met (None: not measured in
    this run, or not judged because the methods it compares did not run at the full run's settings)."""
    cases = {c["key"]: c for c in res["cases"]}
    smoke = res["meta"]["mode"] == "smoke"
    out = []

    # ``case``: the target compares settings a reduced run may leave out (judged only when the
    # case ran them all); the separatrix and Earth targets need only wobble's exact solution.
    def add(name, target, measured, met, ratio=None, case=None):
        judged = not (smoke or (case is not None and not case.get("complete", True)))
        if met is not None and not judged:
            measured += f" (--{res['meta']['mode']} runs fewer settings than the full run)"
            met = None
        status = {True: "met", False: "missed"}.get(met, "not judged" if not judged else "not measured")
        out.append({"case": name, "target": target, "measured": measured, "met": met, "ratio": ratio, "status": status})

    c = cases.get("free_generic")
    if c:
        ex, dop = _row(c, "wobble exact"), _row(c, "scipy DOP853", "rtol 1e-12")
        if dop:
            ratio = dop["t_min"] / ex["t_min"]
            add(
                "generic free body",
                "exact error <= 1e-13 in >= 100x less time than SciPy DOP853 at rtol 1e-12",
                f"exact {ex['error']:.1e} in {ex['t_min']:.3g} s; DOP853 rtol 1e-12 {dop['error']:.1e} in "
                f"{dop['t_min']:.3g} s; {ratio:.0f}x",
                ex["error"] <= 1e-13 and ratio >= 100,
                ratio,
                c,
            )
        else:
            add(
                "generic free body",
                "exact error <= 1e-13, >= 100x faster than DOP853 at rtol 1e-12",
                "DOP853 at rtol 1e-12 not run in this mode",
                None,
            )
    c = cases.get("free_separatrix")
    if c:
        ex = _row(c, "wobble exact")
        sc = [r["error"] for r in c["rows"] if r["method"].startswith("scipy")]
        add(
            "near the separatrix",
            "exact error <= 1e-10 and flip times within 1e-9 s",
            f"exact {ex['error']:.1e}, flip times {ex['flip_time_error_s']:.1e} s; best SciPy "
            f"{min(sc) if sc else float('nan'):.1e}",
            ex["error"] <= 1e-10 and ex["flip_time_error_s"] <= 1e-9,
        )
    c = cases.get("free_earth")
    if c:
        ex = _row(c, "wobble exact")
        ev = _row(c, "wobble exact (evaluation only)") or ex
        add(
            "Earth, 100 years daily",
            "exact phase error <= 1e-12 rad in under 1 ms for 36,526 outputs",
            f"phase error {ev['error']:.1e} rad; evaluation {ev['t_min'] * 1e3:.2f} ms ({ev['t_min'] / 1e-3:.2f} x the "
            f"1 ms goal), {ex['t_min'] * 1e3:.2f} ms including the construction of the solution",
            ev["error"] <= 1e-12 and ev["t_min"] < 1e-3,
            ev["t_min"] / 1e-3,
        )
    for key in ("top_undulating", "top_cusps", "top_loops", "top_sleeping"):
        c = cases.get(key)
        if not c:
            continue
        ex, dop = _row(c, "wobble exact"), _row(c, "scipy DOP853", "rtol 1e-12")
        if not dop:
            add(
                c["title"],
                ">= 1000x faster than DOP853 at rtol 1e-12, equal or better error",
                "DOP853 at rtol 1e-12 not run in this mode",
                None,
            )
            continue
        ratio = dop["t_min"] / ex["t_min"]
        better = ex["error"] <= dop["error"] and ex.get("turning_error", 0) <= dop.get("turning_error", float("inf"))
        add(
            c["title"],
            ">= 1000x faster than DOP853 at rtol 1e-12, equal or better error",
            f"{ratio:.0f}x (exact {ex['t_min'] * 1e3:.2f} ms incl. construction, DOP853 {dop['t_min']:.3g} s); "
            "attitude "
            f"{ex['error']:.1e} vs {dop['error']:.1e} rad, turning points {ex.get('turning_error', 0):.1e} vs "
            f"{dop.get('turning_error', float('nan')):.1e}",
            ratio >= 1000 and better,
            ratio,
            c,
        )
    for key in ("torqued_satellite", "torqued_asymmetric_top"):
        c = cases.get(key)
        if not c:
            continue
        parts, ok = [], []
        for target in (1e-6, 1e-8, 1e-10):
            pts = {}
            for r in c["rows"]:
                pts.setdefault(r["method"], []).append((r["error"], r["t_min"]))
            ref = time_at(pts.get("scipy DOP853", []), target)
            wob = {m: time_at(p, target) for m, p in pts.items() if m.startswith("wobble")}
            wob = {m: v for m, v in wob.items() if v is not None}
            if ref is None or not wob:
                parts.append(f"{target:g}: not reached")
                continue
            best = min(wob, key=wob.get)
            parts.append(f"{target:g}: {ref / wob[best]:.2f}x ({best})")
            ok.append(ref / wob[best])
        add(
            c["title"],
            "one trajectory: best wobble integrator >= 5x faster than DOP853 at equal error",
            "; ".join(parts),
            bool(ok) and min(ok) >= 5,
            min(ok) if ok else None,
            c,
        )
    for e in res["ensembles"]:
        if e["key"] != "ensemble_satellite":
            continue
        r = best_ratio(e, 10_000)
        add(
            "ensemble of 10^4 satellites",
            ">= 100x faster per member than SciPy DOP853 at equal error",
            "10^4 members not run in this mode" if r is None else f"best {r:.0f}x per member",
            None if r is None else r >= 100,
            r,
        )
    c = cases.get("user_top")
    if c:
        parts, ratios, better = [], [], True
        for api in (r for r in c["rows"] if r["method"] == user_level.API_TOP):
            plain = next(
                r for r in c["rows"] if r["method"] == user_level.PLAIN and r["setting"].startswith(api["setting"])
            )
            ratios.append(plain["t_min"] / api["t_min"])
            better = better and api["error"] <= plain["error"]
            parts.append(
                f"{api['setting']} {ratios[-1]:.0f}x ({api['t_min'] * 1e3:.2f} ms vs {plain['t_min']:.3g} s; "
                f"{api['error']:.1e} vs {plain['error']:.1e} rad)"
            )
        add(
            "Heavy top through the public API",
            "HeavyTop(...).motion(t) >= 1000x faster than plain SciPy DOP853 (rtol 1e-12, no events), "
            "equal or better error",
            "; ".join(parts),
            min(ratios) >= 1000 and better,
            min(ratios),
            c,
        )
    add(
        "energy over 10^6 splitting steps",
        "bounded energy error (no secular drift) for orders 2, 4, 6",
        "not re-measured here (a 10-minute run): see performance-engine.md, produced by scripts/bench_engine.py",
        None,
    )
    return out


# ---------------------------------------------------------------------------
# Output
# ---------------------------------------------------------------------------
def _plain(text: str) -> str:
    """reST literal markup (``...``), written for the docs, as plain text for a terminal."""
    return text.replace("``", "")


def text_table(res: dict) -> str:
    lines = []
    for c in res["cases"]:
        lines.append(f"{c['title']} ({c['key']}), {c['outputs']} outputs; error: {_plain(c['error_measure'])}")
        lines.append(
            f"  {'method':<26} {'setting':<44} {'error':>9} {'min (s)':>10} {'median (s)':>10} {'peak MiB':>9}"
        )
        for r in c["rows"]:
            mem = "-" if r.get("peak_memory_bytes") is None else f"{r['peak_memory_bytes'] / 2**20:.2f}"
            lines.append(
                f"  {r['method']:<26} {r['setting'][:44]:<44} {r['error']:>9.2e} {r['t_min']:>10.4g} "
                f"{r['t_median']:>10.4g} {mem:>9}"
            )
        lines.append("")
    for e in res["ensembles"]:
        lines.append(e["title"])
        # Headed like the cases' tables: the SciPy baseline has no member count (it loops over them).
        lines.append(f"  {'method':<26} {'setting':<14} {'members':>9} {'error':>9} {'time per member':>18}  vs scipy")
        for r in e["scipy"]:
            lines.append(
                f"  {r['method']:<26} {r['setting']:<14} {'':>9} {r['error']:>9.2e} "
                f"{r['per_member_s'] * 1e6:>10.1f} us/member"
            )
        for r in e["rows"]:
            ratio = "-" if r["ratio_vs_scipy"] is None else f"{r['ratio_vs_scipy']:.1f}x"
            lines.append(
                f"  {r['method']:<26} {r['setting']:<14} {r['members']:>9} {r['error']:>9.2e} "
                f"{r['per_member_s'] * 1e6:>10.2f} us/member  {ratio}"
            )
        lines.append("")
    lines.append("Targets:")
    for t in res["targets"]:
        status = t["status"].upper() if t["status"] == "missed" else t["status"]
        lines.append(f"  [{status}] {t['case']}: {t['target']} -- {t['measured']}")
    return "\n".join(lines)


def write_figures(res: dict, folder: Path) -> dict:
    from wobble.io.atomic import atomic_target
    from wobble.plot.bench import work_precision_figure

    folder.mkdir(exist_ok=True)
    written = {}
    for c in res["cases"]:
        if c["key"].startswith("user_"):
            continue  # a table per top, not a sweep of settings: no diagram
        fig = work_precision_figure(
            f"{c['title']}: {c['outputs']} outputs", c["rows"], xlabel=c["error_measure"].split(",")[0]
        )
        written[c["key"]] = _save(fig, folder / f"work_precision_{c['key']}.png", atomic_target)
    for e in res["ensembles"]:
        rows = [{**r, "method": f"{r['method']} ({r['members']})"} for r in e["rows"]]
        rows += [{**r, "method": "scipy DOP853 (loop of members)"} for r in e["scipy"]]
        fig = work_precision_figure(e["title"], rows, xlabel="error", per_member=True)
        written[e["key"]] = _save(fig, folder / f"work_precision_{e['key']}.png", atomic_target)
    return written


def _save(fig, path: Path, atomic_target):
    with atomic_target(path, overwrite=True) as tmp:
        fig.savefig(tmp, format="png", dpi=110)
    return path


class _Parser(argparse.ArgumentParser):
    """Usage errors as one line on stderr, exit status 2 (as every wobble command)."""

    def error(self, message: str):  # overrides argparse.ArgumentParser.error
        self.exit(2, f"{self.prog}: error: {message}\n")


def parser(prog: str = "wobble bench") -> argparse.ArgumentParser:
    """The options of ``wobble bench`` (:func:`wobble.cli.bench.add_arguments`), for the scripts."""
    p = _Parser(prog=prog, description="Work-precision benchmark of every solver.")
    add_arguments(p)
    return p


def run(args, command: str) -> int:
    from benchmarks.report import markdown
    from wobble.io.atomic import atomic_target

    if args.repeats is not None and args.repeats < 1:
        raise InputError("--repeats", args.repeats, "a whole number >= 1")
    for k in args.case or []:
        if k not in CASE_KEYS:
            raise InputError("--case", k, ", ".join(CASE_KEYS))
    plot = Path(args.plot) if args.plot else None
    if plot is not None and (plot.exists() and not plot.is_dir() or not plot.parent.is_dir()):
        raise InputError("--plot", args.plot, "a folder, or a new folder in an existing one")
    report = Path(args.output) if args.output else None
    if report is not None:
        if report.is_dir() or not report.parent.is_dir():
            raise InputError("-o/--output", args.output, "a file path in an existing folder")
        if report.exists() and not args.overwrite:
            raise InputError("-o/--output", args.output, "a new file (or add --overwrite)")
    mode = "smoke" if args.smoke else "quick" if args.quick else "full"
    res = run_benchmark(mode, args.case, args.repeats, progress=lambda s: print(s, file=sys.stderr, flush=True))
    res["meta"]["command"] = command
    figures = write_figures(res, plot) if plot else {}
    written = list(figures.values())
    if report is not None:
        text = markdown(res, report, figures)
        with atomic_target(report, overwrite=args.overwrite) as tmp:
            Path(tmp).write_text(text)
        written.append(report)
        if is_docs_page(report) and any(c["key"].startswith("user_") for c in res["cases"]):
            written.append(write_user_report(res, report.parent / USER_REPORT))
    # As every wobble command: the results (one JSON document under --json), then "wrote PATH" per file.
    return finish(args, res, lambda: print(text_table(res)), written)


def write_user_report(res: dict, path: Path) -> Path:
    """docs/performance-user.md from a run that included the user-level cases (replaced)."""
    from benchmarks.report import user_report
    from wobble.io.atomic import atomic_target

    with atomic_target(path, overwrite=True) as tmp:
        Path(tmp).write_text(user_report(res))
    return path


def main(argv=None, prog: str = "wobble bench", shown=None) -> int:
    """Parse ``argv`` and run; bad input: one line on stderr, exit status 2.

    ``shown``: the arguments to record as the command in the report (default ``argv``).
    """
    from wobble.errors import WobbleError

    p = parser(prog)
    argv = sys.argv[1:] if argv is None else list(argv)
    args = p.parse_args(argv)
    try:
        return run(args, f"{prog} {' '.join(argv if shown is None else shown)}".strip())
    except (WobbleError, OSError) as exc:
        print(f"{prog}: error: {' '.join(str(exc).split())}", file=sys.stderr)
        return 2
