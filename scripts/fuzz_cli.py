"""Fuzz the ``wobble`` command line at a large budget: every subcommand, every input format.

The strategies and checks are those of the test suite (tests/fuzz_strategies.py); this script
runs many more inputs (>= 10,000 by default) in a pool of processes, each input in-process through
``wobble.cli.main`` in its own empty folder with a time limit, and reports what ran per command
and every distinct failure with a minimal reproduction (arguments dropped while it persists).

    python scripts/fuzz_cli.py                         # 10,000 inputs, seed 0, two processes
    python scripts/fuzz_cli.py --count 500 --only free top --jobs 1
    python scripts/fuzz_cli.py --count 20000 --seed 7 --report fuzz.json

Each chunk's interpreter has its address space limited (``--memory``, 6 GiB by default), so an
input that asks for more memory than that fails with a MemoryError the report names, instead of
taking the machine: the time bound (SIGALRM) cannot interrupt one long call into compiled code,
which once drew 2.3 million lines into a figure and took 21 GB before it was stopped by hand.

Exit status 0 when nothing failed, 1 otherwise.
"""

from __future__ import annotations

import argparse
import collections
import concurrent.futures
import json
import os
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
os.environ.setdefault("MPLBACKEND", "Agg")
os.environ.setdefault("OMP_NUM_THREADS", "1")

#: Relative share of the inputs per command (the slow ones get fewer; every one gets some).
WEIGHTS = {
    "chandler": 4,
    "modes": 2,
    "precession": 8,
    "polar-motion": 3,
    "excitation": 3,
    "forecast": 4,
    "inertia": 16,
    "free": 18,
    "top": 18,
    "run": 8,
    "sweep": 4,
    "invert": 1,
    "example": 8,
    "bench": 1,
}
CHUNK = 100
#: Address space allowed to each chunk's interpreter, GiB (a wobble command takes well under 1 GiB).
MEMORY_GIB = 6.0


def limit_memory(gib: float) -> None:
    """Cap this process's address space at ``gib`` GiB (0: no cap): past it, allocations raise MemoryError."""
    import resource

    if gib > 0:
        limit = int(gib * 2**30)
        _soft, hard = resource.getrlimit(resource.RLIMIT_AS)
        resource.setrlimit(resource.RLIMIT_AS, (limit if hard == resource.RLIM_INFINITY else min(limit, hard), hard))


def plan(count: int, only, seed: int) -> list[tuple[str, int, int]]:
    """(command, inputs, seed) chunks that add up to ``count``."""
    weights = {c: w for c, w in WEIGHTS.items() if not only or c in only}
    total = sum(weights.values())
    share = {c: max(1, round(count * w / total)) for c, w in weights.items()}
    share[max(share, key=share.get)] += count - sum(share.values())
    chunks = []
    for command, n in share.items():
        k = 0
        while n > 0:
            size = min(CHUNK, n)
            chunks.append((command, size, seed * 100_003 + hash_command(command) * 1009 + k))
            n -= size
            k += 1
    chunks.sort(key=lambda c: c[2] % 7919)  # interleave the commands, deterministically
    return chunks


def hash_command(command: str) -> int:
    return sum(ord(c) * (i + 1) for i, c in enumerate(command))


def run_chunk(job, out_path: str) -> None:
    """Generate and run ``n`` inputs for ``command`` (hypothesis seeded by ``seed``); pickle the results.

    Runs in its own interpreter (``--chunk``): a command that starts processes of its own
    (``--scheduler processes``) works as from a shell, and a crash of the interpreter itself is
    caught by the parent, which then reports the input being run (kept in ``out_path.current``).
    """
    import pickle
    import warnings

    import fuzz_strategies as fz
    from hypothesis import HealthCheck, Phase, given, settings
    from hypothesis import seed as hseed

    command, n, seed = job
    warnings.simplefilter("ignore")  # the harness records the run's own warnings itself
    base = tempfile.mkdtemp(prefix="wobble-fuzz-")
    results = []

    @hseed(seed)
    @settings(
        max_examples=n,
        database=None,
        deadline=None,
        phases=[Phase.generate],
        derandomize=False,
        suppress_health_check=list(HealthCheck),
    )
    @given(fz.case_strategy(command))
    def go(case):
        with open(out_path + ".current", "wb") as fh:
            pickle.dump(case, fh)
        outcome = fz.run_case(case, base)
        results.append((case, outcome.status, outcome.seconds, outcome.problems, outcome.warnings))

    try:
        go()
    finally:
        import shutil

        shutil.rmtree(base, ignore_errors=True)
    failures = []
    for case, _status, _seconds, problems, noise in results:
        for problem in problems:
            failures.append({"signature": fz.signature(problem), "problem": problem, "case": case})
        for warning in noise:
            failures.append({"signature": fz.signature(warning), "problem": warning, "case": case, "warning": True})
    statuses = collections.Counter(r[1] for r in results)
    seconds = sum(r[2] for r in results)
    with open(out_path, "wb") as fh:
        pickle.dump((command, len(results), dict(statuses), seconds, failures), fh)


def spawn_chunk(job, folder: str, memory_gib: float = MEMORY_GIB):
    """Run one chunk in a fresh interpreter (address space capped at ``memory_gib``); its results, or a
    failure naming the input that killed it."""
    import pickle
    import subprocess

    command, n, seed = job
    out = os.path.join(folder, f"{command}-{seed}.pickle")
    proc = subprocess.run(
        [sys.executable, __file__, "--chunk", command, str(n), str(seed), out, str(memory_gib)],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    if proc.returncode == 0 and os.path.exists(out):
        with open(out, "rb") as fh:
            return pickle.load(fh)
    case = None
    if os.path.exists(out + ".current"):
        with open(out + ".current", "rb") as fh:
            case = pickle.load(fh)
    import fuzz_strategies as fz

    case = case or fz.Case(command, [command])
    problem = (
        f"interpreter died: exit status {proc.returncode}: "
        f"{proc.stderr.strip().splitlines()[-1][:200] if proc.stderr.strip() else ''}"
    )
    return command, 0, {}, 0.0, [{"signature": f"interpreter died ({command})", "problem": problem, "case": case}]


def write_cases(report: Path, failures: dict, prefix: str = "") -> str:
    """Each failure's (minimal) input in full beside the report, ``<report>-cases/<prefix><n>/``: its files
    as they were (the report shows only their first 600 bytes) and ``command.txt``, to run there."""
    import shlex

    import fuzz_strategies as fz

    folder = report.with_name(report.stem + "-cases")
    for k, f in enumerate(failures.values(), start=1):
        case = f.get("minimal", f["case"])
        target = folder / f"{prefix}{k}"
        target.mkdir(parents=True, exist_ok=True)
        fz.lay_out(case, target)
        (target / "command.txt").write_text(shlex.join(["wobble", *case.argv]) + "\n")
        f["case_folder"] = str(target)
    return str(folder)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--count", type=int, default=10_000, help="inputs to generate and run (default 10000)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the generation (default 0)")
    parser.add_argument("--jobs", type=int, default=2, help="worker processes (default 2)")
    parser.add_argument("--only", nargs="+", metavar="COMMAND", help="fuzz only these subcommands")
    parser.add_argument("--report", metavar="FILE.json", help="write the summary and the failures as JSON")
    parser.add_argument("--no-minimize", action="store_true", help="report failures as generated")
    parser.add_argument(
        "--memory",
        type=float,
        default=MEMORY_GIB,
        metavar="GIB",
        help=f"address space of each chunk's interpreter, GiB (default {MEMORY_GIB:g}; 0: no limit)",
    )
    args = parser.parse_args(argv)
    sys.path.insert(0, str(ROOT / "tests"))
    import fuzz_strategies as fz

    for c in args.only or []:
        if c not in fz.COMMANDS:
            parser.error(f"--only: {c!r} is not one of {', '.join(fz.COMMANDS)}")
    chunks = plan(args.count, args.only, args.seed)
    print(
        f"fuzzing wobble: {args.count} inputs in {len(chunks)} chunks, seed {args.seed}, {args.jobs} processes",
        flush=True,
    )
    started = time.perf_counter()
    per = collections.defaultdict(lambda: {"inputs": 0, "status": collections.Counter(), "seconds": 0.0})
    failures: dict[str, dict] = {}
    done = 0
    # Each chunk runs in a fresh interpreter (threads here only wait for them).
    folder = tempfile.mkdtemp(prefix="wobble-fuzz-results-")
    pool = concurrent.futures.ThreadPoolExecutor(args.jobs)
    futures = [pool.submit(spawn_chunk, chunk, folder, args.memory) for chunk in chunks]
    interrupted = False
    try:
        for future in concurrent.futures.as_completed(futures):
            command, n, statuses, seconds, found = future.result()
            done += n
            row = per[command]
            row["inputs"] += n
            row["status"].update(statuses)
            row["seconds"] += seconds
            for f in found:
                if f["signature"] not in failures and not f.get("warning"):
                    print(f"  new failure: {f['problem']}\n    {f['case'].show().splitlines()[0]}", flush=True)
                entry = failures.setdefault(f["signature"], {"count": 0, **f, "command": command})
                entry["count"] += 1
            elapsed = time.perf_counter() - started
            broken = sum(not f.get("warning") for f in failures.values())
            print(
                f"[{elapsed:7.1f} s] {done}/{args.count} inputs; {broken} distinct failures "
                f"(last chunk: {command}, {n} inputs)",
                flush=True,
            )
    except KeyboardInterrupt:  # Ctrl-C: summarise the chunks that finished (their subprocesses got it too)
        interrupted = True
        print("interrupted: the summary covers the chunks that finished", flush=True)
    pool.shutdown(wait=not interrupted, cancel_futures=True)
    wall = time.perf_counter() - started
    warned = {s: f for s, f in failures.items() if f.get("warning")}
    failures = {s: f for s, f in failures.items() if not f.get("warning")}
    import shutil

    shutil.rmtree(folder, ignore_errors=True)

    print(f"\n{done} inputs in {wall:.0f} s wall time")
    print(f"{'command':<14}{'inputs':>8}{'exit 0':>8}{'exit 2':>8}{'other':>8}{'mean s':>8}")
    for command in fz.COMMANDS:
        if command not in per:
            continue
        row = per[command]
        s = row["status"]
        other = row["inputs"] - s.get(0, 0) - s.get(2, 0)
        print(
            f"{command:<14}{row['inputs']:>8}{s.get(0, 0):>8}{s.get(2, 0):>8}{other:>8}"
            f"{row['seconds'] / max(1, row['inputs']):>8.2f}"
        )
    if warned:
        print(f"\n{len(warned)} distinct Python warnings printed on stderr (noise, not counted as failures):")
        for _sig, f in sorted(warned.items()):
            print(f"- {f['problem']}  ({f['count']} inputs)\n  " + f["case"].show().splitlines()[0])
    if failures:
        print(f"\n{len(failures)} distinct failures:")
        with tempfile.TemporaryDirectory() as tmp:
            for sig, f in sorted(failures.items()):
                case = f["case"] if args.no_minimize else fz.minimize(f["case"], sig, tmp)
                f["minimal"] = case
                f["reproduction"] = case.show()
                print(f"\n- {sig}  ({f['count']} inputs)\n  {f['problem']}\n  " + case.show().replace("\n", "\n  "))
    else:
        print(
            "\nno failures: every input exited 0 or 2 in time, without a traceback, and left no partial, "
            "temporary or changed file"
        )
    if args.report:
        cases = write_cases(Path(args.report), failures) if failures else None
        if warned:  # a warning's input in full too (seed 311's sweep file was cut at 600 bytes in the report)
            cases = write_cases(Path(args.report), warned, prefix="warning-")
        summary = {
            "count": done,
            "seed": args.seed,
            "jobs": args.jobs,
            "wall_seconds": round(wall, 1),
            "per_command": {
                c: {
                    "inputs": r["inputs"],
                    "status": dict(r["status"]),
                    "mean_seconds": round(r["seconds"] / max(1, r["inputs"]), 3),
                }
                for c, r in per.items()
            },
            "failures": [
                {
                    "signature": s,
                    "count": f["count"],
                    "problem": f["problem"],
                    "reproduction": f.get("reproduction", f["case"].show()),
                    "case_folder": f.get("case_folder"),
                }
                for s, f in failures.items()
            ],
            "warnings": [
                {
                    "warning": f["problem"],
                    "count": f["count"],
                    "example": f["case"].show().splitlines()[0],
                    "reproduction": f["case"].show(),  # the command and the files it reads
                    "case_folder": f.get("case_folder"),
                }
                for f in warned.values()
            ],
        }
        summary["cases_folder"] = cases
        Path(args.report).write_text(json.dumps(summary, indent=2) + "\n")
    return 1 if failures else 0


if __name__ == "__main__":
    if len(sys.argv) == 7 and sys.argv[1] == "--chunk":
        limit_memory(float(sys.argv[6]))
        run_chunk((sys.argv[2], int(sys.argv[3]), int(sys.argv[4])), sys.argv[5])
        sys.exit(0)
    sys.exit(main())
