"""The layer rule, enforced: import-linter contracts from pyproject.toml."""

from __future__ import annotations

import pytest

import ast
from pathlib import Path

from importlinter.cli import lint_imports

ROOT = Path(__file__).resolve().parents[1]


def test_import_contracts_hold(monkeypatch):
    """numerics <- models <- io <- api <- cli, and no units/xarray/I-O below the API."""
    monkeypatch.chdir(ROOT)
    status = lint_imports(config_filename=str(ROOT / "pyproject.toml"), no_cache=True, no_logo=True)
    assert status == 0, "import-linter contracts are broken; run `lint-imports` for details"


# Heavy packages a script that only computes a Chandler period never needs; loaded on first use.
HEAVY = ("numba", "xarray", "pandas", "astropy.utils.iers", "astropy.units", "scipy", "dask", "matplotlib", "netCDF4")


def _loaded_after(code: str) -> list[str]:
    import subprocess
    import sys

    # To the real stdout: the code may have redirected sys.stdout (a probe that printed into the
    # redirection saw nothing and passed whatever was loaded).
    probe = f"import sys; {code}; print(' '.join(m for m in {HEAVY!r} if m in sys.modules), file=sys.__stdout__)"
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True, cwd=ROOT)
    return out.stdout.split()


def _loaded_after_each(argvs) -> list[list[str]]:
    """The heavy packages loaded after each of ``wobble ARGV`` run in turn in one fresh interpreter
    (cumulative: the first command after which a package appears loaded it). One interpreter for all
    of them, as each start-up costs seconds of the suite."""
    import json
    import subprocess
    import sys

    probe = (
        "import contextlib, io, json, sys, wobble.cli as c\n"
        f"for argv in {argvs!r}:\n"
        "    with contextlib.redirect_stdout(io.StringIO()):\n"
        "        c.main(argv)\n"
        f"    print(json.dumps([m for m in {HEAVY!r} if m in sys.modules]), file=sys.__stdout__)\n"
    )
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True, cwd=ROOT)
    return [json.loads(line) for line in out.stdout.splitlines()]


def _first_to_load(argvs, forbidden):
    """(argv, packages) of the first command after which a forbidden package is loaded, else None."""
    for argv, loaded in zip(argvs, _loaded_after_each(argvs), strict=True):
        assert "astropy.units" in loaded  # the probe sees what was loaded
        if set(loaded) & forbidden:
            return argv, sorted(set(loaded) & forbidden)
    return None


def test_import_wobble_is_lazy():
    """`import wobble` (and the CLI's parser) load none of the heavy packages (issue 15: start-up)."""
    assert _loaded_after("import wobble, wobble.cli; wobble.cli.build_parser()") == []


def test_table_commands_skip_xarray():
    """`wobble chandler earth --json` (and the other planet tables) need astropy.units and NumPy,
    not xarray, pandas, dask or matplotlib (that is for -o and --plot)."""
    argvs = [[command, "earth", "--json"] for command in ("chandler", "modes", "precession")]
    assert _first_to_load(argvs, {"xarray", "pandas", "dask", "matplotlib", "numba", "astropy.utils.iers"}) is None


def test_polar_motion_reports_skip_xarray():
    """`wobble polar-motion`, `excitation` and `forecast` (JSON or text) read the record into plain
    arrays: no xarray, pandas or dask (through xarray's duck-array check), which only -o and --plot need."""
    argvs = [
        ["polar-motion", "--start", "1990", "--end", "2012", "--excitation-q", "none", "--json"],
        ["polar-motion", "--start", "1990", "--end", "2012", "--excitation-q", "none"],
        ["excitation", "--start", "2000-01-01", "--end", "2004-12-31", "--json"],
        ["excitation", "--start", "2000-01-01", "--end", "2004-12-31"],
        ["forecast", "--method", "ls_ar", "--issued", "2019-01-01", "--horizon", "30d", "--no-calibration", "--json"],
    ]
    assert _first_to_load(argvs, {"xarray", "pandas", "dask", "matplotlib", "netCDF4", "numba"}) is None


def test_public_names_resolve():
    """Every name in wobble.__all__ resolves (the lazy table has no typo)."""
    import wobble

    missing = [name for name in wobble.__all__ if getattr(wobble, name, None) is None]
    assert missing == []


# ---------------------------------------------------------------------------
# Public seams: a module uses another wobble module only through its public names.
# ---------------------------------------------------------------------------
PACKAGE = ROOT / "wobble"

# (importing module, private target) -> why it is allowed. Keep empty; an entry needs a reason.
PRIVATE_SEAMS_ALLOWED: dict[tuple[str, str], str] = {}


def _module_name(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _is_module(dotted: str) -> bool:
    """True when ``dotted`` (``wobble.x.y``) names a module or package of the source tree."""
    path = ROOT.joinpath(*dotted.split("."))
    return path.with_suffix(".py").is_file() or (path / "__init__.py").is_file()


def _is_private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def _private_use(importer: str, target: str) -> str | None:
    """Why ``importer`` may not reach ``target`` (a dotted wobble name), or None when it may.

    The first private component of ``target`` decides: a private *module* may be used anywhere
    inside the package that holds it; a private *name* of a module only by that module.
    """
    parts = target.split(".")
    for k, part in enumerate(parts):
        if not _is_private(part):
            continue
        owner, reached = ".".join(parts[:k]), ".".join(parts[: k + 1])
        if _is_module(reached):
            if importer == owner or importer.startswith(owner + "."):
                return None
            return f"private module {reached} used outside {owner}"
        if importer == owner:
            return None
        return f"private name {reached}"
    return None


def _absolute(importer: str, is_package: bool, node) -> str:
    """The absolute module a ``from ... import`` statement reads from."""
    if not node.level:
        return node.module
    base = importer.split(".")
    base = base if is_package else base[:-1]
    base = base[: len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def _attribute_chain(node) -> list[str] | None:
    """``a.b.c`` as ["a", "b", "c"]; None when the chain does not start at a plain name."""
    names = []
    while isinstance(node, ast.Attribute):
        names.append(node.attr)
        node = node.value
    if not isinstance(node, ast.Name):
        return None
    return [node.id, *reversed(names)]


def _private_seams(path: Path, source: str | None = None) -> list[str]:
    """Every place where the module at ``path`` reaches a private name of another wobble module."""
    importer = _module_name(path)
    is_package = path.name == "__init__.py"
    source = path.read_text(encoding="utf-8") if source is None else source
    tree = ast.parse(source, filename=str(path))
    found: list[tuple[int, str]] = []
    aliases: dict[str, str] = {}  # local name -> the wobble module it is bound to

    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            origin = _absolute(importer, is_package, node)
            if origin.split(".")[0] != "wobble":
                continue
            found.append((node.lineno, origin))
            for alias in node.names:
                target = f"{origin}.{alias.name}"
                found.append((node.lineno, target))
                if _is_module(target):
                    aliases[alias.asname or alias.name] = target
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] != "wobble":
                    continue
                found.append((node.lineno, alias.name))
                aliases[alias.asname or "wobble"] = alias.name if alias.asname else "wobble"

    for node in ast.walk(tree):
        chain = _attribute_chain(node) if isinstance(node, ast.Attribute) else None
        if chain and chain[0] in aliases:
            found.append((node.lineno, ".".join([aliases[chain[0]], *chain[1:]])))

    problems = {}
    for lineno, target in sorted(set(found)):
        why = _private_use(importer, target)
        if why and (importer, target) not in PRIVATE_SEAMS_ALLOWED:
            problems.setdefault(f"{path.relative_to(ROOT)}:{lineno}: {why}", None)
    return list(problems)


def test_no_private_names_across_modules():
    """No module imports a private name (``_x``) of another wobble module (issue 16: public seams).

    Checked: ``from wobble.x import _name``, ``from . import _name``, ``import wobble.x._y``, and
    ``alias._name`` where ``alias`` is an imported wobble module. A private module (``_output``)
    may be used anywhere inside its own package; dunder names are public.
    """
    problems = [p for path in sorted(PACKAGE.rglob("*.py")) for p in _private_seams(path)]
    assert problems == [], "private names used across modules:\n" + "\n".join(problems)


def test_private_seam_check_finds_each_form():
    """The check itself: each form of reaching a private name is found, the allowed ones are not."""
    source = "\n".join(
        [
            "from wobble.models.chandler import _evaluate",  # 1: private name of another module
            "from . import _output",  # 2: private module of its own package (allowed)
            "from wobble.api import _sampling",  # 3: private module of another package
            "from wobble.models import chandler as cm",  # 4
            "cm._evaluate(cm.__name__)",  # 5: alias._name (the dunder is allowed)
            "import wobble.numerics._dop853_tableau",  # 6: private module of another package
            "wobble.models.hydrostatic._JUMP_TOLERANCE",  # 7: attribute chain from the package
            "from ._output import print_json",  # 8: allowed
        ]
    )
    found = _private_seams(PACKAGE / "cli" / "planted.py", source)
    assert [int(p.split(":")[1]) for p in found] == [1, 3, 5, 6, 7], found


@pytest.mark.parametrize(
    "code",
    [
        "import wobble; from astropy.time import Time",  # astropy imported after wobble (the import hook)
        "import astropy; import wobble",  # astropy loaded first (configured at once)
        "import wobble; from astropy.utils import iers",
    ],
)
def test_astropy_is_offline_whatever_the_import_order(code):
    import subprocess
    import sys

    probe = f"{code}; from astropy.utils import iers; print(iers.conf.auto_download, iers.conf.auto_max_age)"
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True, cwd=ROOT)
    assert out.stdout.split() == ["False", "None"]
