"""``wobble chandler``: Chandler wobble budgets as a table, JSON or netCDF."""

from __future__ import annotations

import argparse

from wobble.cli._planets import add_bodies, add_outputs, bodies_from_args, report

EPILOG = """\
examples:
  wobble chandler earth mars
  wobble chandler mars --model rigid --json
  wobble chandler earth mars -o chandler.nc --overwrite
  wobble chandler earth mars --plot budget.png
  wobble example my_planet.toml                 a planet file to edit, copied here
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
    add_bodies(p)
    p.add_argument("--model", default="full", help="last step to include (default: full)")
    p.add_argument(
        "--sources",
        action="store_true",
        help="also list every parameter with its value, uncertainty, unit and source (with --json: a 'parameters' "
        "list of {name, value, uncertainty, unit (as astropy reads it), unit_label, source, status} per body)",
    )
    add_outputs(p, "draw the budget, step by step, against the observed period")
    p.set_defaults(func=run)


def run(args) -> int:
    from wobble.api.chandler import chandler_budget, chandler_dataset

    bodies = bodies_from_args(args)
    # A planet file is named in the table's title as the user typed it.
    given = [None] * len(args.bodies) + list(args.body_file)
    typed = given if given else [None] * len(bodies)
    budgets = [chandler_budget(b, args.model) for b in bodies]
    names = {id(b): t for b, t in zip(budgets, typed)}
    return report(
        args,
        budgets,
        chandler_dataset,
        "wobble.plot.chandler:budget_figure",
        text=lambda b: _table(b, sources=args.sources, typed=names[id(b)]),
        document=lambda b: _document(b, args.sources),
    )


def _document(b, sources: bool) -> dict:
    """The budget's JSON, with its catalogued parameters under ``--sources``. Its ``deprecated_keys`` lists the
    renamed keys it holds: the parameters' (``--sources``), else none (``{}``), so that every run has the key."""
    from wobble.api.chandler import PARAMETER_RENAMES
    from wobble.io.json_keys import deprecate

    if not sources:
        return deprecate(b.to_dict(), {})
    return deprecate({**b.to_dict(), "parameters": b.planet.parameter_list()}, PARAMETER_RENAMES)


def _table(b, sources: bool = False, typed: str | None = None) -> str:
    """The budget's text (:meth:`wobble.ChandlerBudget.summary`), its last line naming this command."""
    from wobble.api.chandler_text import budget_text

    where = f"--body-file {typed}" if typed else b.body
    return budget_text(b, sources, hint=f"sources of every number: wobble chandler {where} --sources")
