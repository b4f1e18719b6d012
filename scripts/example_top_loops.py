"""A heavy top with loops: run it, save it to netCDF, load it back and plot it.

The third script of docs/getting-started.md, as a file. It runs the example
scene ``top_loops`` (data/scenes/top_loops.toml: the exact heavy symmetric top,
started precessing backwards so that its axis traces loops), writes the result
as CF-1.10 netCDF, reads the file back and draws the axis trace seen from above
and the tilt against time.

Usage: python scripts/example_top_loops.py [OUTPUT_FOLDER]

Without a folder it writes a temporary netCDF file and the figure
docs/figures/getting_started_top_loops.png (the one in the docs).
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
from astropy import units as u

import wobble

FIGURES = Path(__file__).resolve().parents[1] / "docs" / "figures"


def main(folder: Path | None = None) -> tuple[Path, Path]:
    """Run the scene; return the netCDF file and the figure written."""
    nc_folder = folder or Path(tempfile.mkdtemp())
    png = (folder or FIGURES) / "getting_started_top_loops.png"

    ds = wobble.run("top_loops")  # exact heavy top, 10 s
    path = wobble.write_netcdf(ds, nc_folder / "top_loops.nc", overwrite=True)
    back = wobble.load(path)  # xarray, with units
    axis = back["axis_direction"]  # symmetry axis in space
    tilt = back.wobble.quantity("tilt").to(u.deg)
    t = back.wobble.quantity("time").to(u.s)

    fig, (top_view, side) = plt.subplots(1, 2, figsize=(9, 4), layout="constrained")
    top_view.plot(axis.sel(inertial_axis="X"), axis.sel(inertial_axis="Y"), lw=1)
    top_view.plot(0, 0, "k+")
    top_view.set_aspect("equal")
    top_view.set(xlabel="X", ylabel="Y", title="symmetry axis seen from above")
    side.plot(t.value, tilt.value, lw=1)
    side.set(xlabel="time [s]", ylabel="tilt from the vertical [deg]", title="nutation")
    fig.suptitle(f"{back.attrs['title']} (model: {back.attrs['model']})")
    png.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(png, dpi=110)
    plt.close(fig)
    print(f"tilt between {np.min(tilt):.1f} and {np.max(tilt):.1f}; wrote {path} and {png}")
    return Path(path), png


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else None)
