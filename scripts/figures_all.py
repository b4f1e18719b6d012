"""Regenerate every figure of the documentation (docs/gallery.md) from real runs.

Usage: python scripts/figures_all.py [--list] [NAME ...]

Runs, one after the other and each in its own process (so a failure is
reported, not hidden, and the others still run):

* every ``scripts/figures_*.py`` (a new figures script is picked up without
  editing this file),
* ``scripts/example_top_loops.py`` (the getting-started figure),
* ``scripts/hindcast_polar_motion.py`` (the forecast page's figures, its example forecast and the
  excitation figure, with the 2016-2020 hindcast's numbers they are drawn from),
* ``wobble sweep mars_chandler --plot docs/figures/sweep_mars_chandler.png``
  (the sweep histogram; 100,000 members), unless a ``figures_sweep*.py``
  script draws it (``scripts/figures_sweeps.py`` does).

NAME restricts the run to the jobs whose name contains it (e.g. ``top``).
No network is used. The exit status is the number of jobs that failed.
About two minutes on two cores (102 s on 2026-11-29; the forecast hindcast takes about 60 s
of it, the Bayesian inversion 25 s).
"""

from __future__ import annotations

import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCRIPTS = ROOT / "scripts"
FIGURES = ROOT / "docs" / "figures"


def jobs() -> list[tuple[str, list[str]]]:
    """(name, command) for every figure generator, in a stable order."""
    scripts = sorted(p for p in SCRIPTS.glob("figures_*.py") if p.name != Path(__file__).name)
    found = [(p.stem, [sys.executable, str(p)]) for p in scripts]
    found.append(("example_top_loops", [sys.executable, str(SCRIPTS / "example_top_loops.py")]))
    found.append(("hindcast_polar_motion", [sys.executable, str(SCRIPTS / "hindcast_polar_motion.py")]))
    if not any(p.stem.startswith("figures_sweep") for p in scripts):
        found.append(
            (
                "sweep_mars_chandler",
                [
                    sys.executable,
                    "-m",
                    "wobble",
                    "sweep",
                    "mars_chandler",
                    "--quiet",
                    "--plot",
                    str(FIGURES / "sweep_mars_chandler.png"),
                ],
            )
        )
    return found


def main(argv: list[str]) -> int:
    todo = jobs()
    if "--list" in argv:
        for name, command in todo:
            print(f"{name}: {' '.join(command[1:])}")
        return 0
    if argv:
        todo = [(name, command) for name, command in todo if any(word in name for word in argv)]
    failed = []
    for name, command in todo:
        start = time.perf_counter()
        proc = subprocess.run(command, cwd=ROOT, capture_output=True, text=True, check=False)
        status = "ok" if proc.returncode == 0 else f"FAILED (exit {proc.returncode})"
        print(f"{name:24s} {time.perf_counter() - start:6.1f} s  {status}", flush=True)
        if proc.returncode:
            failed.append(name)
            print(proc.stderr[-2000:], file=sys.stderr)
    print(f"{len(todo) - len(failed)} of {len(todo)} figure jobs ran; figures in {FIGURES.relative_to(ROOT)}/")
    return len(failed)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
