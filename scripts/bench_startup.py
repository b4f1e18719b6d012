"""Start-up time of the command line as a user meets it, written to docs/performance-startup.md.

    python scripts/bench_startup.py            # 15 runs of each command, warm file cache

Each command runs as a fresh process (what a shell loop pays every time): the minimum and
the median wall time of the runs, after two warm-up runs. Targets: ``wobble --help``
within 0.3 s and ``wobble chandler earth --json`` within 0.8 s; ``wobble modes earth mars`` within 1 s
after start-up: a fresh process imports what the command imports, then times the command's
own run in the same process; the whole process is timed too. The import profile of each command
(``python -X importtime``) names what is loaded, so a regression is easy to find.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))  # benchmarks/ is a folder of the checkout, not installed

# Without PYTHONDONTWRITEBYTECODE: the warm-up runs fill the bytecode cache as a user's runs do.
from benchmarks.timing import USER_ENV as ENV  # noqa: E402 - after sys.path.insert(0, ROOT)

COMMANDS = (
    ("python -c 'import wobble'", [sys.executable, "-c", "import wobble"], None),
    ("wobble --help", [sys.executable, "-m", "wobble", "--help"], 0.3),
    ("wobble chandler earth --json", [sys.executable, "-m", "wobble", "chandler", "earth", "--json"], 0.8),
    ("wobble chandler earth mars", [sys.executable, "-m", "wobble", "chandler", "earth", "mars"], None),
    ("wobble modes earth mars", [sys.executable, "-m", "wobble", "modes", "earth", "mars"], None),
    ("wobble precession earth mars", [sys.executable, "-m", "wobble", "precession", "earth", "mars"], None),
    (
        "wobble inertia --solid ellipsoid ...",
        [sys.executable, "-m", "wobble", "inertia", "--solid", "ellipsoid", "--mass", "2", "--axes", "3", "2", "1"],
        None,
    ),
    ("python -c 'import sys'", [sys.executable, "-c", "import sys"], None),
)


def wall_times(argv, runs: int) -> list[float]:
    times = []
    for i in range(runs + 2):
        t0 = time.perf_counter()
        subprocess.run(argv, check=True, capture_output=True, cwd=ROOT, env=ENV)
        if i >= 2:  # two warm-up runs fill the file cache (and Python's bytecode cache)
            times.append(time.perf_counter() - t0)
    return times


# The target: the normal modes within a second after start-up. The start-up (interpreter, NumPy,
# astropy, wobble's modules) is paid first; the command's own run is then timed in the process.
AFTER_STARTUP = (("wobble modes earth mars", ["modes", "earth", "mars"], ("wobble.cli", "wobble.api.modes"), 1.0),)
_AFTER_STARTUP_CODE = """
import contextlib, io, importlib, sys, time
for name in sys.argv[2:]:
    importlib.import_module(name)
import wobble.cli
args = sys.argv[1].split()
t0 = time.perf_counter()
with contextlib.redirect_stdout(io.StringIO()):
    status = wobble.cli.main(args)
print(time.perf_counter() - t0, status)
"""


def after_startup_times(args, modules, runs: int) -> list[float]:
    times = []
    for i in range(runs + 2):
        out = subprocess.run(
            [sys.executable, "-c", _AFTER_STARTUP_CODE, " ".join(args), *modules],
            check=True,
            capture_output=True,
            text=True,
            cwd=ROOT,
            env=ENV,
        ).stdout.split()
        if out[1] != "0":
            raise SystemExit(f"wobble {' '.join(args)} exited {out[1]}")
        if i >= 2:
            times.append(float(out[0]))
    return times


def heaviest_imports(argv, top: int = 3) -> str:
    out = subprocess.run(
        [argv[0], "-X", "importtime", *argv[1:]], capture_output=True, text=True, cwd=ROOT, env=ENV
    ).stderr
    rows = []
    for line in out.splitlines():
        parts = line.split("|")
        if (
            len(parts) == 3
            and parts[1].strip().isdigit()
            and parts[2].startswith(" ")
            and not parts[2].startswith("  ")
        ):
            rows.append((int(parts[1]), parts[2].strip()))
    rows.sort(reverse=True)
    return ", ".join(f"{name} {us / 1e3:.0f} ms" for us, name in rows[:top])


def report(runs: int) -> str:
    stamp = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    lines = [
        "# Start-up time",
        "",
        f"Measured by `python scripts/bench_startup.py` on {stamp}: {platform.processor() or platform.machine()}, "
        f"{os.cpu_count()} CPUs, Python {platform.python_version()}, load average "
        f"{os.getloadavg()[0]:.1f} at the start. Each command is a fresh process, {runs} runs after two warm-up runs "
        "(which fill the file cache and Python's bytecode cache, as a user's runs do).",
        "",
        "| command | min (s) | median (s) | target (s) | met | top-level imports (cumulative) |",
        "|---|---|---|---|---|---|",
    ]
    for label, argv, target in COMMANDS:
        t = wall_times(argv, runs)
        best, mid = min(t), statistics.median(t)
        met = "-" if target is None else ("yes" if mid <= target else "no")
        imports = heaviest_imports(argv) if label.startswith("wobble") or "import wobble" in label else ""
        lines.append(f"| `{label}` | {best:.3f} | {mid:.3f} | {target if target else '-'} | {met} | {imports} |")
    for label, args, modules, target in AFTER_STARTUP:
        t = after_startup_times(args, modules, runs)
        best, mid = min(t), statistics.median(t)
        met = "yes" if mid <= target else "no"
        lines.append(
            f"| `{label}`, after start-up | {best:.3f} | {mid:.3f} | {target} | {met} | "
            f"(imported first: {', '.join(modules)}) |"
        )
    lines += [
        "",
        "`python -c 'import sys'` is the interpreter's own start-up, the floor under every command.",
        "`import wobble` loads astropy's configuration only (to keep astropy offline) and resolves",
        "the public names on first use (lazy_loader, SPEC 1); a command imports what it uses, so the",
        "Chandler table needs astropy.units and NumPy but not xarray, pandas, dask, matplotlib or Numba",
        "(tests/test_architecture.py checks that; this page measures the time).",
        "A row *after start-up* times the command's own run in a process that has already imported",
        "the modules named (the target 'within a second after start-up' read as the physics, not the interpreter and",
        "astropy's import); the row without the suffix is the whole process.",
        "",
    ]
    return "\n".join(lines)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--runs", type=int, default=15)
    p.add_argument("-o", "--output", default=str(ROOT / "docs" / "performance-startup.md"))
    args = p.parse_args()
    text = report(args.runs)
    Path(args.output).write_text(text)
    print(text)


if __name__ == "__main__":
    main()
