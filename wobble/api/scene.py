"""Scenes with units, :func:`run` to an xarray Dataset, :func:`run_to_netcdf` streamed to a file.

A scene is a TOML file (docs/scenes.md), the same structure as a Python
mapping, or a :class:`Scene` built from Quantities. :func:`run` chooses the
cheapest model that meets the scene's accuracy (docs/engine.md) and records
the choice, the reason and the error estimate in the Dataset's attributes.

Example
-------
>>> import astropy.units as u
>>> import wobble
>>> scene = wobble.Scene(body=[1, 2, 3] * u.kg * u.m**2, omega0=[1e-3, 1, 1e-3] * u.rad / u.s,
...                      t_end=30 * u.s, samples=301)
>>> ds = wobble.run(scene)
>>> ds.attrs["model"]
'free-elliptic'
>>> float(ds["omega"].sel(axis="2").min()) < -0.9     # the racket flipped
True
"""

from __future__ import annotations

import json
import os
from typing import TYPE_CHECKING

import numpy as np
from astropy import units as u

from wobble.api.engine import Torque
from wobble.api.units import plain_array
from wobble.errors import InputError
from wobble.io import cf
from wobble.io import scene_file as _sf
from wobble.io.netcdf import StreamingWriter, simulation_time_units
from wobble.models import scene as _scene

if TYPE_CHECKING:
    import xarray as xr

__all__ = ["Scene", "run", "run_to_netcdf", "read_scene", "example_scenes"]

_MOI = u.kg * u.m**2


# The mapping's keys (those of a scene file) and the Python parameters they came from: an error names what the
# caller typed (t_end, not time.stop).
_PYTHON_NAMES = {
    "initial.omega": "omega0",
    "initial.attitude": "attitude0",
    "time.values": "t",
    "time.start": "t_start",
    "time.stop": "t_end",
    "time.samples": "samples",
    "time.epoch": "epoch",
}


def _in_python_names(exc: InputError) -> InputError:
    """``exc`` with the scene file's keys replaced by the Python parameters (``stop = start`` by t_end = t_start)."""

    def rename(text: str) -> str:
        for key, name in _PYTHON_NAMES.items():
            text = text.replace(key, name)
        return text.replace("stop = start", "t_end = t_start")

    return InputError(rename(exc.parameter), exc.value, rename(exc.allowed))


class Scene:
    """A simulation request built from Quantities (the same content as a scene file).

    Parameters
    ----------
    body : Quantity, dict or rigid body
        Principal moments along the body axes (``[1, 2, 3] * u.kg * u.m**2``,
        or (N, 3) for N bodies); or a mapping ``{"tensor": ...}``,
        ``{"planet": "earth"}``, ``{"moments": ..., "mass": ...}``; or an
        object with ``tensor`` (and optionally ``mass``) such as a
        :class:`wobble.RigidBody`. Its centre of mass is not read: a gravity
        torque takes ``center_of_mass`` itself.
    omega0 : Quantity
        Initial angular velocity, body frame, (3,) or (N, 3).
    attitude0 : array_like, optional
        Unit quaternion(s) (w, x, y, z) body -> inertial; default identity.
    torques : sequence of Torque
    t : Quantity, optional
        Output times; or ``t_end`` with ``samples`` (from ``t_start``, default 0 s).
    accuracy : float
        Relative accuracy wanted (each omega component against its largest
        value; attitude angle in rad).
    outputs : sequence of str
        From ``wobble.models.scene.OUTPUTS``.
    name, title : str
    epoch : str, datetime or astropy Time, optional
        The date-time of t = 0 for the CF time units: ISO 8601 text (UTC), a datetime, or a
        scalar astropy Time in any scale (converted to UTC); fractions of a second are kept.
    """

    def __init__(
        self,
        body,
        omega0,
        *,
        attitude0=None,
        torques=(),
        t=None,
        t_start=0 * u.s,
        t_end=None,
        samples=None,
        accuracy: float = 1e-9,
        outputs=("omega", "attitude"),
        name: str = "scene",
        title: str = "",
        epoch=None,
    ):
        # A single name is one output ("omega"), not its letters.
        outputs = [outputs] if isinstance(outputs, str) else list(outputs)
        mapping: dict = {"name": name, "title": title or name, "accuracy": accuracy, "outputs": outputs}
        mapping["body"] = _body_mapping(body)
        initial: dict = {"omega": omega0}
        if attitude0 is not None:
            initial["attitude"] = plain_array(attitude0, "attitude0", "unit quaternions (w, x, y, z), plain numbers")
        mapping["initial"] = initial
        torques = list(torques)  # read twice below: a generator would leave the record without its torques
        mapping["torques"] = [_torque_spec(tq, i) for i, tq in enumerate(torques)]
        if (t is None) == (t_end is None):
            raise InputError("t, t_end", (t, t_end), "either times t or t_end with samples")
        if t is not None:
            time = _uniform_grid(t) or {"values": t}
        else:
            if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)):
                raise InputError("samples", samples, "a whole number of output times with t_end")
            time = {"start": t_start, "stop": t_end, "samples": int(samples)}
        if epoch is not None:
            time["epoch"] = epoch
        mapping["time"] = time
        try:
            self._scene = _sf.scene_from_mapping(mapping)
        except InputError as exc:
            raise _in_python_names(exc) from None
        # The record of the scene (a run's ``scene`` attribute) holds each torque's table as given, so that the
        # scene runs again from it; the specs the model takes kept only the kind ({"kind": "gravity", "python":
        # "UniformGravity"}). A custom torque's function no file can hold: it stays named.
        plain = [tq.as_mapping() if isinstance(tq, Torque) else None for tq in torques]
        record = [_sf.to_plain(p) if p is not None else r for p, r in zip(plain, self._scene.mapping["torques"])]
        self._scene.mapping["torques"] = record

    @property
    def model(self) -> _scene.Scene:
        """The SI scene underneath."""
        return self._scene

    def __repr__(self) -> str:
        s = self._scene
        return f"Scene({s.name!r}, members={s.members}, times={s.times.size}, torques={[t.kind for t in s.torques]})"


def _body_mapping(body):
    if isinstance(body, u.Quantity):
        return {"moments": body}
    if isinstance(body, dict):
        return dict(body)
    tensor = getattr(body, "tensor", None)
    if isinstance(tensor, u.Quantity):
        out = {"tensor": tensor}
        if getattr(body, "mass", None) is not None:
            out["mass"] = body.mass
        return out
    raise InputError("body", body, "moments (a Quantity in kg m2), a mapping, or a rigid body with a tensor")


def _torque_spec(tq, i):
    if isinstance(tq, Torque):
        return tq.spec
    if isinstance(tq, dict):
        return tq
    raise InputError(f"torques[{i}]", tq, "a wobble.Torque (Torque.gravity(...), ...) or a torque mapping")


def read_scene(path) -> _scene.Scene:
    """Read a scene file (TOML) into an SI scene; errors name the file and key."""
    return _sf.read_scene(path)


def example_scenes() -> list[str]:
    """Names of the example scenes in data/scenes (``wobble.run("tennis_racket")`` runs one)."""
    return _sf.example_scenes()


def _as_scene(scene) -> _scene.Scene:
    if isinstance(scene, Scene):
        return scene.model
    if isinstance(scene, _scene.Scene):
        return scene
    if isinstance(scene, dict):
        return _sf.scene_from_mapping(scene)
    if isinstance(scene, (str, os.PathLike)):
        # As `wobble run` reads it: a file of that name first, else the shipped scene ("tennis_racket"
        # or "tennis_racket.toml"), else one line naming the shipped ones.
        from wobble.io.shipped import resolve

        return _sf.read_scene(resolve(scene, "scenes", "scene"))
    raise InputError("scene", scene, "a wobble.Scene, a mapping, a scene file path or an example name")


# --------------------------------------------------------------------------
# Datasets
# --------------------------------------------------------------------------
def _block_dataset(scene: _scene.Scene, t, outputs: dict) -> xr.Dataset:
    data_vars = {}
    for name, arr in outputs.items():
        dims, values, attrs = cf.variable("scene", name, arr if scene.ensemble else arr[:, 0])
        data_vars[name] = (cf.with_member(dims) if scene.ensemble else dims, values, attrs)
    coords = {"time": cf.time_coordinate(np.asarray(t, dtype=float), simulation_time_units(scene.epoch))}
    if _scene.SUMMARY_OUTPUTS & set(outputs):
        # One value for the whole run: a time mean over the cell [start, stop] (CF 1.10 sec. 7.1, 7.3).
        for name in _scene.SUMMARY_OUTPUTS & set(outputs):
            data_vars[name][2]["cell_methods"] = "time: mean"
        data_vars["time_bounds"] = (("time", "bounds"), np.array([[scene.times[0], scene.times[-1]]], dtype=float), {})
    used = {d for v in data_vars.values() for d in v[0]}
    for dim in cf.LABELS:
        if dim in used:
            coords[dim] = cf.label_coordinate(dim)
    if "time_bounds" in data_vars:
        coords["time"][2]["bounds"] = "time_bounds"
    if scene.ensemble:
        coords["member"] = (
            "member",
            np.arange(scene.members, dtype=np.int64),
            {"long_name": "ensemble member", "units": "1"},
        )
    from wobble.api.dataset import xarray

    # Through wobble.api.dataset: every Dataset wobble returns carries the ds.wobble accessor.
    return xarray().Dataset(data_vars, coords=coords)


def _uniform_grid(t) -> dict | None:
    """``t`` as start, stop and samples when ``np.linspace`` gives exactly its seconds, or as start, stop and
    step when the scene file's step grid does (``np.arange``'s), else None: the scene is kept in every file's
    ``scene`` attribute, where 200,001 explicit times took 2 MB. Anything else (a plain float, uneven times)
    stays as given, and is read and refused or taken as before."""
    # A plain Quantity of real numbers only: a Masked one (or complex times) goes to the reader, which refuses
    # it, where to_value would strip the mask.
    if type(t) is not u.Quantity or t.dtype.kind not in "fi" or t.ndim != 1 or t.size < 3:
        return None
    if not t.unit.is_equivalent(u.s):
        return None
    seconds = t.to_value(u.s)
    if not np.all(np.isfinite(seconds)):
        return None
    start, stop = float(seconds[0]), float(seconds[-1])
    if np.array_equal(np.linspace(start, stop, seconds.size), seconds):
        return {"start": start * u.s, "stop": stop * u.s, "samples": int(seconds.size)}
    # The step that made start + k step is not always seconds[1] - seconds[0] (rounded by the sum): try the
    # doubles next to the mean step too. Only an exact reproduction is kept.
    candidates = [float(seconds[1] - seconds[0])]
    up = down = (stop - start) / (seconds.size - 1)
    candidates.append(up)
    for _ in range(4):
        up, down = float(np.nextafter(up, np.inf)), float(np.nextafter(down, -np.inf))
        candidates += [up, down]
    for step in candidates:
        if step > 0 and np.array_equal(_sf.step_grid(start, stop, step), seconds):
            return {"start": start * u.s, "stop": stop * u.s, "step": step * u.s}
    return None


def _attributes(scene: _scene.Scene, record: _scene.RunRecord) -> dict:
    est = record.error_estimate
    worst = max(est["omega_relative"], est["attitude_rad"])
    # The splitting's rounding floor (the part a shorter step cannot lower), where it was measured:
    # a netCDF attribute cannot be None, so a run without the measurement has no such attribute.
    rounding = {"error_estimate_rounding": est["rounding"]} if "rounding" in est else {}
    return {
        "title": scene.title or scene.name,
        "summary": scene.description or f"wobble scene {scene.name}",
        "references": "Goldstein, Poole & Safko 2002, Classical Mechanics, sections 5.5-5.7; Landau & Lifshitz, "
        "Mechanics, section 37; Touma & Wisdom 1994, AJ 107, 1189; Hairer, Norsett & Wanner, Solving ODEs I (DOP853)",
        "scene_name": scene.name,
        "scene": json.dumps(scene.mapping, sort_keys=True),
        "model": record.model,
        "model_reason": record.reason,
        "model_settings": json.dumps(record.settings, sort_keys=True),
        "error_estimate": worst,
        "error_estimate_omega_relative": est["omega_relative"],
        "error_estimate_attitude_rad": est["attitude_rad"],
        "error_estimate_method": est["method"],
        **rounding,
        "accuracy_requested": scene.accuracy,
        "attempts": record.attempts,
    }


class _Collector:
    def __init__(self, scene):
        self.scene = scene
        self.begin()

    def begin(self):
        self.parts = []

    def discard(self):
        self.parts = []

    def write(self, t, outputs):
        self.parts.append((np.asarray(t), outputs))

    def dataset(self):
        t = np.concatenate([p[0] for p in self.parts])
        names = self.parts[0][1].keys()
        joined = {k: np.concatenate([p[1][k] for p in self.parts]) for k in names}
        return _block_dataset(self.scene, t, joined)


class _Streamer:
    def __init__(self, scene, writer: StreamingWriter):
        self.scene = scene
        self.writer = writer
        self.times = 0  # the times written: the scene's, or one for a summary output (a time mean)

    def begin(self):
        self.writer.begin()
        self.times = 0  # a run retried at a tighter tolerance writes its times again

    def discard(self):
        self.writer.discard()
        self.times = 0

    def write(self, t, outputs):
        self.writer.append(_block_dataset(self.scene, t, outputs))
        self.times += int(np.size(t))


_MEMORY_LIMIT = 2 * 2**30


def _estimated_bytes(scene) -> int:
    width = sum(int(np.prod([len(cf.LABELS[d][0]) for d in cf.spec("scene", o).dims[1:]])) for o in scene.outputs)
    return int(scene.times.size) * scene.members * max(width, 1) * 8


def run(scene, *, model: str | None = None) -> xr.Dataset:
    """Run a scene and return its outputs as an xarray Dataset (in memory).

    Parameters
    ----------
    scene : Scene, dict, path or example name
        What to simulate (``"tennis_racket"`` runs ``data/scenes/tennis_racket.toml``).
    model : str, optional
        Force a model (``free-symmetric``, ``free-elliptic``, ``heavy-top``,
        ``splitting``, ``dop853``) instead of the automatic choice.

    Returns
    -------
    xarray.Dataset
        ``time`` (CF seconds since the scene's epoch), the outputs asked for
        (``omega(time[, member], axis)``, ``attitude(..., component)``, ...),
        and global attributes ``model``, ``model_reason``,
        ``error_estimate`` (with its parts and method), ``scene`` (JSON),
        ``accuracy_requested``.

    Raises
    ------
    wobble.errors.InputError, wobble.errors.FileFormatError
        Bad scene (naming the key, and the file if any), a model that does not
        apply, an accuracy no model can reach, or an output too large for
        memory (then use :func:`run_to_netcdf`, which streams).

    Examples
    --------
    >>> import wobble
    >>> ds = wobble.run("top_loops")  # data/scenes/top_loops.toml
    >>> ds.attrs["model"], ds.attrs["error_estimate"] < ds.attrs["accuracy_requested"]
    ('heavy-top', True)
    >>> print(f"{ds.wobble.quantity('tilt').max().to('deg'):.1f}")
    74.8 deg
    """
    sc = _as_scene(scene)
    need = _estimated_bytes(sc)
    if need > _MEMORY_LIMIT:
        raise InputError(
            "scene",
            sc.name,
            f"an output that fits in memory ({need / 1e9:.3g} GB asked): use "
            "wobble.run_to_netcdf or `wobble run -o FILE`, which write as they go",
        )
    sink = _Collector(sc)
    record = _scene.execute(sc, sink, model=model)
    ds = sink.dataset()
    ds.attrs.update(_attributes(sc, record))
    return ds


def run_to_netcdf(
    scene,
    path,
    *,
    model: str | None = None,
    overwrite: bool = False,
    command: str | None = None,
    block_bytes: int = 64 * 2**20,
) -> dict:
    """Run a scene and stream its outputs to a CF netCDF file as they are computed.

    The file is written under a temporary name in the target folder and
    renamed when the run has finished and met its accuracy, so a failed or
    interrupted run leaves nothing behind and never replaces an existing file;
    an existing file is replaced only with ``overwrite=True``. Memory stays
    bounded by ``block_bytes`` whatever the output size.

    Returns
    -------
    dict
        The run summary: ``model``, ``model_reason``, ``error_estimate`` (and
        parts; ``error_estimate_rounding`` is the splitting's rounding floor, included in the
        estimate, or None where not measured), ``output``, ``members``, ``times`` (written: one for
        a scene whose only output is a time mean, ``mean_precession_rate``).
    """
    if isinstance(block_bytes, bool) or not isinstance(block_bytes, (int, np.integer)) or block_bytes < 1:
        raise InputError("block_bytes", block_bytes, "a positive whole number of bytes")
    sc = _as_scene(scene)
    writer = StreamingWriter(path, overwrite=overwrite, command=command)
    sink = _Streamer(sc, writer)
    try:
        record = _scene.execute(sc, sink, model=model, block_bytes=block_bytes)
        attrs = _attributes(sc, record)
        out = writer.close(attrs)
    except BaseException:
        writer.discard()
        raise
    summary = {
        k: attrs[k]
        for k in (
            "model",
            "model_reason",
            "error_estimate",
            "error_estimate_omega_relative",
            "error_estimate_attitude_rad",
            "accuracy_requested",
            "attempts",
        )
    }
    summary.update(
        {
            "error_estimate_rounding": attrs.get("error_estimate_rounding"),
            "scene": sc.name,
            "output": str(out),
            "members": sc.members,
            "times": sink.times,
            "settings": record.settings,
            "stats": record.stats,
        }
    )
    return summary
