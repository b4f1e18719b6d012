"""``wobble chandler``: Chandler wobble budgets as a table, JSON or netCDF."""

from __future__ import annotations

import argparse
import json
import math

from wobble.errors import InputError

EPILOG = """\
examples:
  wobble chandler earth mars
  wobble chandler mars --model rigid --json
  wobble chandler earth mars -o chandler.nc --overwrite
  wobble chandler earth mars --plot budget.png
  wobble chandler --body-file my_planet.toml

models (each includes the steps before it; 'full' runs every step the body's
parameters support): rigid, elastic, fluid_core (core), ocean_pole_tide (ocean),
anelastic, full. Periods are in days of 86400 s. The observed period is never an
input to the model; it is shown for comparison.
"""


def register(sub) -> None:
    p = sub.add_parser(
        "chandler",
        help="Chandler wobble period budgets (rigid Euler period -> observed)",
        description="Chandler wobble periods from physical parameters, step by step: rigid body, "
        "elastic yielding, liquid core, ocean pole tide, mantle anelasticity.",
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("bodies", nargs="*", metavar="BODY", help="catalogued planets (default: all of them)")
    p.add_argument("--body-file", action="append", default=[], metavar="FILE", help="a planet file in the wobble/1 schema (repeatable)")
    p.add_argument("--model", default="full", help="last step to include (default: full)")
    p.add_argument("--json", action="store_true", help="print a JSON list, one object per body")
    p.add_argument("--sources", action="store_true", help="also list every parameter with its value, uncertainty and source")
    p.add_argument("-o", "--output", metavar="FILE.nc", help="write a CF-1.10 netCDF file")
    p.add_argument("--overwrite", action="store_true", help="replace an existing output file")
    p.add_argument("--plot", metavar="FILE.png", help="draw the budget, step by step, against the observed period")
    p.set_defaults(func=run)


def run(args) -> int:
    from wobble.api.chandler import chandler_budget, chandler_dataset, known_planets

    bodies = list(args.bodies) + list(args.body_file)
    if not bodies:
        bodies = known_planets()
    for name in args.bodies:
        if name.lower() not in known_planets():
            raise InputError("BODY", name, f"one of {', '.join(known_planets())} (files go with --body-file)")
    budgets = [chandler_budget(b, args.model) for b in bodies]
    if args.output:
        from wobble.io.netcdf import write_netcdf

        write_netcdf(chandler_dataset(budgets), args.output, overwrite=args.overwrite, command=args.command_line)
    if args.plot:
        from wobble.plot.chandler import budget_figure

        budget_figure(budgets, args.plot)
    if args.json:
        print(json.dumps([b.to_dict() for b in budgets], indent=2))
    else:
        print("\n\n".join(_table(b, sources=args.sources) for b in budgets))
        if args.output:
            print(f"\nwrote {args.output}")
    return 0


def _fmt(q, digits=2, sign=False) -> str:
    from astropy import units as u

    if q is None:
        return "-"
    x = q.to_value(u.day)
    if not math.isfinite(x):
        return "inf"
    return f"{x:+.{digits}f}" if sign else f"{x:.{digits}f}"


def _table(b, sources: bool = False) -> str:
    from wobble.models.chandler import STEP_LABELS

    lines = [f"{b.planet.title}: Chandler wobble budget (model '{b.model}'; days of 86400 s)"]
    lines.append(f"  {'step':<16}{'period [d]':>11}{'change [d]':>12}{'k2':>8}   physics (references)")
    for s in b.steps:
        label, refs = STEP_LABELS[s.name]
        k2 = f"{s.love_number:.4f}" if s.love_number else "-"
        lines.append(f"  {s.name:<16}{_fmt(s.period):>11}{_fmt(s.change, sign=True):>12}{k2:>8}   {label} ({refs})")
    lines.append(f"  {'model':<16}{_fmt(b.period):>11} +/- {_fmt(b.period_uncertainty)} ({b.sense} wobble)")
    if b.observed is not None:
        lines.append(f"  {'observed':<16}{_fmt(b.observed):>11} +/- {_fmt(b.observed_uncertainty)}")
        pct = 100 * b.relative_residual
        lines.append(f"  {'residual':<16}{_fmt(b.residual, sign=True):>11} ({pct:+.2f} %)")
    else:
        lines.append(f"  {'observed':<16}{'unknown':>11}")
    if b.secular_love_number is not None:
        lines.append(f"  secular Love number k_s = {b.secular_love_number:.4f}")
    if b.quality_factor is not None:
        lines.append(f"  Q implied by the out-of-phase part of k2: {b.quality_factor:.0f}")
    if sources:
        lines.append("  parameters (value +/- one sigma, unit; source [status if not read]):")
        for key, p in b.planet.file.parameters.items():
            unit = p.value.unit.to_string() or "1"
            value = f"{p.value.value:.10g} +/- {p.uncertainty.value:.3g} {unit}"
            lines.append(f"    {key}: {value}; {b.planet.source(key)}")
    else:
        lines.append(f"  (sources of every number: wobble chandler {b.body} --sources)")
    return "\n".join(lines)
