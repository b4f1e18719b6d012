"""Parameter sweeps and ensembles on dask, in bounded memory.

A sweep (``data/sweeps/*.toml``, schema in :mod:`wobble.io.sweep_file`)
names a target, a base body, the parameters that vary (random draws or
grids) and the outputs to keep. Members are evaluated chunk by chunk with the
vectorised models (no Python loop over members):

* :func:`sweep` returns a lazy, dask-backed :class:`xarray.Dataset`; compute it
  with any dask scheduler;
* :func:`run_sweep` streams the chunks to a CF netCDF file as they finish
  (threads, processes or a ``dask.distributed`` cluster), writing under a
  temporary name and renaming at the end, with a progress bar when asked.

Random draws depend only on (seed, parameter, member index)
(:mod:`wobble.numerics.draws`): the same seed gives the same numbers whatever
the chunking and the number of workers.

>>> import wobble
>>> ds = wobble.sweep({"schema": "wobble-sweep/1", "name": "demo", "target": "chandler",
...                    "body": "mars", "members": 1000, "seed": 1,
...                    "vary": {"love_number_k2": {"distribution": "normal"}}}).compute()
>>> bool(200 < float(ds.chandler_period.mean()) < 210)
True
"""

from __future__ import annotations

import contextlib
import math
import os
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import dask
import dask.array as da
import numpy as np
import xarray as xr

from wobble.api.sweep_targets import TARGETS, ChandlerTarget, target_for
from wobble.api._scheduler import LOCAL, check_scheduler, connected, process_pool
from wobble.errors import InputError
from wobble.io.cf import INT64_ALLOWED, INT64_MAX
from wobble.io.netcdf import write_netcdf_blocks
from wobble.io.sweep_file import (
    SweepSpec,
    read_sweep_file,
    sweep_spec_from_dict,
)
from wobble.io.zarr_store import is_zarr_path, open_wobble_zarr, write_zarr_blocks
from wobble.models import chandler as chandler_model

__all__ = ["load_sweep", "sweep", "run_sweep", "SweepSummary", "summarize_sweep"]

DEFAULT_CHUNK = 20_000


def load_sweep(sweep) -> SweepSpec:
    """A sweep from a path, the name of a shipped sweep (``"mars_chandler"``), a dict with the TOML
    structure, or a SweepSpec. A file of the user's wins over a shipped sweep of the same name, as on
    the command line."""
    if isinstance(sweep, SweepSpec):
        return sweep
    if isinstance(sweep, dict):
        return sweep_spec_from_dict(sweep)
    if not Path(os.fspath(sweep)).is_file():
        from wobble.io.shipped import find_shipped

        found = find_shipped(str(sweep), "sweeps", (".toml",))
        if found is not None:
            return read_sweep_file(found.path())
    return read_sweep_file(sweep)


# ---------------------------------------------------------------------------
# Members, chunks and the lazy dataset
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class _Plan:
    spec: SweepSpec
    target: object
    dims: tuple[str, ...]
    shape: tuple[int, ...]
    chunk_rows: int  # along the first dimension

    @property
    def size(self) -> int:
        return int(np.prod(self.shape))

    def row_chunks(self):
        for start in range(0, self.shape[0], self.chunk_rows):
            yield start, min(self.shape[0], start + self.chunk_rows)

    def overrides(self, r0: int, r1: int) -> dict[str, np.ndarray]:
        """Parameter values for rows r0..r1 of the first dimension (all members in them)."""
        if self.spec.is_grid:
            grids = [np.asarray(v.values) for v in self.target.variations]
            grids[0] = grids[0][r0:r1]
            mesh = np.meshgrid(*grids, indexing="ij")
            return {v.name: m for v, m in zip(self.target.variations, mesh)}
        return {v.name: v.member_values(self.spec.seed, r0, r1) for v in self.target.variations}


def _plan(spec: SweepSpec, chunk_size: int | None) -> _Plan:
    target = target_for(spec)
    # "is None", not "or": chunk_size=0 was taken as "not given" and ran with the default.
    chunk = chunk_size if chunk_size is not None else (spec.chunk_size or DEFAULT_CHUNK)
    if not isinstance(chunk, int) or isinstance(chunk, bool) or chunk <= 0:
        raise InputError("chunk_size", chunk, "a positive integer")
    if spec.is_grid:
        dims = tuple(v.name for v in target.variations)
        shape = tuple(len(v.values) for v in target.variations)
        per_row = int(np.prod(shape[1:])) if len(shape) > 1 else 1
        rows = max(1, chunk // per_row)
    else:
        if spec.members > INT64_MAX:  # a member's index is a coordinate of the file
            raise InputError("members", spec.members, f"a positive integer {INT64_ALLOWED}")
        dims, shape, rows = ("member",), (spec.members,), chunk
    return _Plan(spec, target, dims, shape, rows)


def _chunk(plan: _Plan, r0: int, r1: int) -> dict[str, np.ndarray]:
    over = plan.overrides(r0, r1)
    out = plan.target.evaluate(over)
    if not plan.spec.is_grid:  # keep each member's drawn values, in the unit the file gave them in
        out.update({v.name: v.shown_draws(over[v.name]) for v in plan.target.variations})
    return out


def _var_attrs(plan: _Plan, name: str) -> dict:
    target = plan.target
    if name == "invalid_reason":
        return target.invalid_attrs()
    if name in target.outputs:
        return target.output_attrs(name)
    var = next(v for v in target.variations if v.name == name)
    k = 1.0 / var.scale
    how = (
        f"normal(mean={var.mean * k:.10g}, sd={var.sd * k:.6g})"
        if var.distribution == "normal"
        else f"uniform({var.low * k:.10g}, {var.high * k:.10g})"
    )
    unit = "" if var.shown_units == "1" else f" in {var.shown_units}"
    return {"units": var.shown_units, "long_name": f"sampled {name}", "comment": f"drawn from {how}{unit}"}


def _layout(plan: _Plan):
    """Names, dims, shapes and dtypes of the output variables (from a 1-row probe)."""
    probe = _chunk(plan, 0, min(plan.shape[0], 1))
    layout = {}
    for name, arr in probe.items():
        extra = plan.target.extra_dims(name)
        dims = plan.dims + tuple(d for d, _ in extra)
        shape = plan.shape + tuple(len(c) for _, c in extra)
        layout[name] = (dims, shape, arr.dtype)
    return layout


def _coords(plan: _Plan, layout: dict) -> dict:
    """The sweep's coordinates, and the model's own dimensions (a Chandler budget's ``step``) of the outputs
    in ``layout`` only: a dimension no variable had was a dangling coordinate, which xarray wrote as a
    global ``coordinates`` attribute, a name CF gives no meaning."""
    coords = {}
    if plan.spec.is_grid:
        for v in plan.target.variations:
            coords[v.name] = (v.name, v.shown_grid(), {"units": v.shown_units, "long_name": f"grid of {v.name}"})
    else:
        coords["member"] = ("member", np.arange(plan.shape[0]), {"long_name": "member index", "units": "1"})
    for name in layout:
        for dim, values in plan.target.extra_dims(name):
            attrs = getattr(plan.target, "coord_attrs", {}).get(dim, {"long_name": f"{dim} of the model"})
            coords[dim] = (dim, values, attrs)
    return coords


def _references(plan: _Plan) -> str:
    """The model's references, and for random draws of a body's catalogued uncertainties the Monte Carlo's."""
    refs = [plan.target.references]
    if plan.target.name == "chandler" and not plan.spec.is_grid:
        refs.append("Monte Carlo propagation of the catalogue's uncertainties (JCGM 101:2008, GUM Supplement 1)")
    return "; ".join(refs)


def _attrs(plan: _Plan) -> dict:
    spec = plan.spec
    return {
        "title": spec.title,
        "references": _references(plan),
        "sweep_name": spec.name,
        "sweep_target": spec.target,
        "sweep_seed": spec.seed,
        "sweep_file": spec.path or "",
        "comment": "Periods in days of 86400 s. Random draws depend only on (seed, parameter, member).",
        **plan.target.attrs(),
    }


def sweep(spec, *, chunk_size: int | None = None) -> xr.Dataset:
    """A sweep as a lazy (dask-backed) Dataset; nothing is computed yet.

    Parameters
    ----------
    spec : path, dict or SweepSpec
        The sweep (see :mod:`wobble.io.sweep_file`).
    chunk_size : int, optional
        Members per chunk (default: the file's ``chunk_size`` or 20000).

    Returns
    -------
    xarray.Dataset
        Dimension ``member`` (random sweeps) or one per grid parameter; the
        outputs, each member's drawn values and ``invalid_reason``.
    """
    plan = _plan(load_sweep(spec), chunk_size)
    layout = _layout(plan)
    parts = {name: [] for name in layout}
    for r0, r1 in plan.row_chunks():
        result = dask.delayed(_chunk, pure=True)(plan, r0, r1)
        for name, (_dims, shape, dtype) in layout.items():
            block_shape = (r1 - r0, *shape[1:])
            parts[name].append(da.from_delayed(result[name], shape=block_shape, dtype=dtype))
    data = {
        name: (dims, da.concatenate(parts[name], axis=0), _var_attrs(plan, name))
        for name, (dims, shape, dtype) in layout.items()
    }
    return xr.Dataset(data, coords=_coords(plan, layout), attrs=_attrs(plan))


# ---------------------------------------------------------------------------
# Running to a file, on any scheduler
# ---------------------------------------------------------------------------


class _Progress:
    """A one-line progress bar on stderr (only when asked: the CLI asks on a terminal)."""

    def __init__(self, total: int, enabled: bool):
        self.total, self.enabled, self.done, self.t0 = total, enabled, 0, time.perf_counter()

    def advance(self, n: int):
        self.done += n
        if self.enabled:
            frac = self.done / self.total
            bar = "#" * int(30 * frac)
            rate = self.done / max(time.perf_counter() - self.t0, 1e-9)
            sys.stderr.write(f"\r[{bar:<30}] {100 * frac:5.1f}% {self.done}/{self.total} members, {rate:,.0f}/s")
            sys.stderr.flush()

    def close(self):
        if self.enabled:
            sys.stderr.write("\n")


@contextlib.contextmanager
def _pool(scheduler, n_chunks: int):
    """One process pool for a whole run (dask would start a new one per compute call)."""
    if scheduler != "processes" or n_chunks <= 1:
        yield None
        return
    import multiprocessing

    workers = min(os.cpu_count() or 1, n_chunks)
    with process_pool(workers, multiprocessing.get_context("spawn")) as pool:
        yield pool


def _local_get(scheduler):
    """dask's get function of a local scheduler's name. Given the name, dask looks for dask.distributed
    first (importing it: 0.3-1.1 s of a sweep that computes in 0.3 s); given the function, it does not."""
    if scheduler == "synchronous":
        from dask.local import get_sync

        return get_sync
    if scheduler == "processes":
        from dask.multiprocessing import get

        return get
    from dask.threaded import get

    return get


def _compute_chunks(plan: _Plan, scheduler, batch: int):
    """Yield (r0, r1, outputs) chunk by chunk, computed in parallel batches on dask."""
    chunks = list(plan.row_chunks())
    if scheduler is None or scheduler in LOCAL:
        with _pool(scheduler, len(chunks)) as pool:
            extra = {"pool": pool} if pool is not None else {}
            for i in range(0, len(chunks), batch):
                todo = chunks[i : i + batch]
                delayed = [dask.delayed(_chunk, pure=True)(plan, a, b) for a, b in todo]
                results = dask.compute(*delayed, scheduler=_local_get(scheduler), **extra)
                for (a, b), res in zip(todo, results):
                    yield a, b, res
        return
    from distributed import as_completed

    with connected(scheduler) as client:
        pending = iter(chunks)
        futures = {}
        for a, b in [next(pending) for _ in range(min(batch, len(chunks)))]:
            futures[client.submit(_chunk, plan, a, b, pure=True)] = (a, b)
        queue = as_completed(list(futures))
        for fut in queue:
            a, b = futures.pop(fut)
            yield a, b, fut.result()
            nxt = next(pending, None)
            if nxt is not None:
                new = client.submit(_chunk, plan, *nxt, pure=True)
                futures[new] = nxt
                queue.add(new)


def run_sweep(
    spec,
    output: str | os.PathLike | None = None,
    *,
    overwrite: bool = False,
    chunk_size: int | None = None,
    scheduler=None,
    progress: bool = False,
    command: str | None = None,
) -> xr.Dataset:
    """Run a sweep; stream it to ``output`` (CF netCDF) if given, else compute it in memory.

    Parameters
    ----------
    spec : path, dict or SweepSpec
        The sweep.
    output : path-like, optional
        netCDF file, or a Zarr store when the name ends in ``.zarr`` (needs the
        optional ``zarr`` package), written chunk by chunk under a temporary name
        and renamed at the end (memory stays bounded whatever the member count).
    overwrite : bool
        Replace an existing output file.
    chunk_size : int, optional
        Members per chunk.
    scheduler : str or distributed.Client, optional
        ``"threads"`` (default), ``"processes"``, ``"synchronous"``, a
        ``dask.distributed`` scheduler address (``"tcp://..."``) or a Client.
    progress : bool
        Show a progress bar on stderr.
    command : str, optional
        Recorded in the file's history.

    Returns
    -------
    xarray.Dataset
        The results (read back from the file when ``output`` is given).
    """
    from wobble.io.netcdf import open_wobble

    plan = _plan(load_sweep(spec), chunk_size)
    check_scheduler(scheduler)
    template = sweep(plan.spec, chunk_size=chunk_size)
    batch = 2 * (os.cpu_count() or 2)
    bar = _Progress(plan.size, progress)

    def blocks():
        per_row = plan.size // plan.shape[0]
        for r0, r1, res in _compute_chunks(plan, scheduler, batch):
            for name, values in res.items():
                index = (slice(r0, r1),) + (slice(None),) * (values.ndim - 1)
                yield name, index, values
            bar.advance((r1 - r0) * per_row)

    try:
        if output is None:
            arrays = {name: np.empty(template[name].shape, dtype=template[name].dtype) for name in template.data_vars}
            for name, index, values in blocks():
                arrays[name][index] = values
            data = {n: (template[n].dims, a, template[n].attrs) for n, a in arrays.items()}
            return xr.Dataset(data, coords=template.coords, attrs=template.attrs)
        if is_zarr_path(output):
            write_zarr_blocks(template, output, blocks(), overwrite=overwrite, command=command)
        else:
            write_netcdf_blocks(template, output, blocks(), overwrite=overwrite, command=command)
    finally:
        bar.close()
    return open_wobble_zarr(output) if is_zarr_path(output) else open_wobble(output)


# ---------------------------------------------------------------------------
# Summaries
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class SweepSummary:
    """Distribution of a sweep's main output over its valid members."""

    variable: str
    units: str
    members: int
    valid: int
    mean: float
    std: float
    percentiles: dict
    observed: float
    invalid_reasons: dict
    classes: dict = None
    #: Members without an invalid reason whose ``variable`` is not finite (a sleeping top has no
    #: nutation period), left out of ``valid`` and the statistics; by class where the target has one.
    not_finite: int = 0
    not_finite_classes: dict = None
    #: A grid sweep: its members are grid points, not draws, so their range (``minimum``, ``maximum``) is
    #: what the text reports; the mean, sd and percentiles are of the grid's points, not of a distribution.
    grid: bool = False
    minimum: float = math.nan
    maximum: float = math.nan

    def summary(self, title: str = "") -> str:
        """The text ``wobble sweep`` prints: members, invalid ones by reason, classes, and the output's
        distribution (a random sweep) or its range over the grid (a grid sweep) beside the observed value."""
        lines = [title] if title else []
        lines.append(f"  members: {self.members} ({self.valid} valid)")
        lines += [f"    invalid: {n} ({reason})" for reason, n in self.invalid_reasons.items()]
        if self.not_finite:
            # Not invalid: these members have no finite value of the output (a sleeping top has no nutation period).
            by_class = ", ".join(f"{name} {n}" for name, n in (self.not_finite_classes or {}).items())
            lines.append(f"    no finite {self.variable}: {self.not_finite}" + (f" ({by_class})" if by_class else ""))
        if self.classes:
            lines.append("  " + ", ".join(f"{name}: {n}" for name, n in self.classes.items()))
        return "\n".join(lines + self._distribution())

    def __str__(self) -> str:
        return self.summary()

    def _distribution(self) -> list[str]:
        """Mean, sd, percentiles (and the observed value) to the sd's two significant digits, a span in the unit
        a person would use (a precession period of 5.8 d, not 504982.186 s); a grid's range instead."""
        from wobble.io.text import decimals_for, span_unit

        size, units = span_unit(self.percentiles["50"]) if self.units == "s" else (1.0, self.units)
        units = {"day": "d", "days": "d"}.get(units, units)  # as every other command writes days
        if not self.std > 0:  # one valid member (or all equal): no spread to round the digits to
            return [f"  {self.variable}: {self.mean / size:.7g} {units} (no spread: {self.valid} valid member(s))"]
        d = decimals_for(self.std / size)
        if self.grid:
            # Grid points are chosen, not drawn: a mean, an sd and "+0.01 sd from the mean" would describe the
            # grid's spacing, not an uncertainty.
            lo, hi, mid = self.minimum / size, self.maximum / size, self.percentiles["50"] / size
            out = [f"  {self.variable} over the grid: {lo:.{d}f} to {hi:.{d}f} {units} (median {mid:.{d}f} {units})"]
            if not math.isnan(self.observed):
                obs = self.observed / size
                where = "inside" if lo <= obs <= hi else "below" if obs < lo else "above"
                out.append(f"  observed: {obs:.{d}f} {units} ({where} the grid's range)")
            return out
        p = [self.percentiles[k] / size for k in ("2.5", "16", "50", "84", "97.5")]
        out = [
            f"  {self.variable}: mean {self.mean / size:.{d}f} {units}, sd {self.std / size:.{d}f} {units}",
            "    2.5/16/50/84/97.5 %: " + " / ".join(f"{x:.{d}f}" for x in p) + f" {units}",
        ]
        if not math.isnan(self.observed):
            z = (self.observed - self.mean) / self.std
            out.append(f"  observed: {self.observed / size:.{d}f} {units} ({z:+.2f} sd from the mean)")
        return out

    def to_dict(self) -> dict:
        """JSON-ready: what ``wobble sweep --json`` prints after the sweep's name and files.

        ``unit`` is the variable's unit as astropy writes it (``d``, ``s``; ``""`` for a pure number), the key
        other commands' rows use. ``units``, the file's CF spelling (``day``), stays one release as it was: not
        an alias under ``deprecated_keys``, whose old keys hold their new key's value, since a script may compare
        it with ``"day"`` (README, "Commands").
        """
        from astropy import units as u

        d = self.__dict__.copy()
        d["observed"] = None if math.isnan(self.observed) else self.observed
        out = {}
        for key, value in d.items():
            if key == "units":
                out["unit"] = u.Unit(value).to_string()
            out[key] = value
        return out


def summarize_sweep(ds: xr.Dataset, variable: str | None = None) -> SweepSummary:
    """Mean, spread and percentiles of ``variable`` over valid finite members, invalid counts by reason.

    ``variable`` defaults to the target's main output (``chandler_period``,
    ``nutation_period`` or ``precession_period``); for targets with a class
    output (``nutation_class``, ``regime``) ``classes`` counts the valid
    members in each class.
    """
    variable = variable or ds.attrs.get("sweep_main_output", "chandler_period")
    if variable not in ds:
        raise InputError("variable", variable, f"one of {', '.join(map(str, ds.data_vars))}")
    values = np.asarray(ds[variable].values, dtype=float).ravel()
    codes = np.asarray(ds["invalid_reason"].values).ravel()
    ok = (codes == 0) & np.isfinite(values)
    good = values[ok]
    pct = {str(p): float(np.percentile(good, p)) if good.size else math.nan for p in (2.5, 16, 50, 84, 97.5)}
    target = TARGETS.get(ds.attrs.get("sweep_target", "chandler"), ChandlerTarget)
    texts = chandler_model.INVALID_REASONS if target is ChandlerTarget else target.invalid_reasons
    reasons = {texts[int(c)]: int(n) for c, n in zip(*np.unique(codes[codes != 0], return_counts=True))}
    classes = not_finite_classes = None
    class_output = ds.attrs.get("sweep_class_output", "")
    if class_output and class_output in ds:
        flag = ds[class_output]
        meanings = str(flag.attrs["flag_meanings"]).split()
        flag_values = np.asarray(flag.attrs["flag_values"]).tolist()
        cls = np.asarray(flag.values).ravel()[codes == 0]
        classes = {meaning: int((cls == v).sum()) for v, meaning in zip(flag_values, meanings) if v >= 0}
        gone = np.asarray(flag.values).ravel()[(codes == 0) & ~np.isfinite(values)]
        not_finite_classes = {m: int((gone == v).sum()) for v, m in zip(flag_values, meanings) if (gone == v).any()}
    return SweepSummary(
        variable=variable,
        units=str(ds[variable].attrs.get("units", "")),
        members=int(values.size),
        valid=int(ok.sum()),
        mean=float(good.mean()) if good.size else math.nan,
        std=float(good.std(ddof=1)) if good.size > 1 else math.nan,
        percentiles=pct,
        observed=float(ds.attrs.get("observed_chandler_period_days", math.nan)),
        invalid_reasons=reasons,
        classes=classes,
        not_finite=int(((codes == 0) & ~np.isfinite(values)).sum()),
        not_finite_classes=not_finite_classes,
        grid="member" not in ds[variable].dims,
        minimum=float(good.min()) if good.size else math.nan,
        maximum=float(good.max()) if good.size else math.nan,
    )
