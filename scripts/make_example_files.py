"""Regenerate the binary example input data/examples/planet.nc (a density grid).

The file is committed (32^3-sized grids are small) so that ``wobble inertia --density
planet.nc`` runs on a fresh install; this script says exactly how it was made:

    python scripts/make_example_files.py

A two-layer oblate planet: a uniform core (11 000 kg/m3, equatorial radius 3 480 km)
inside a uniform mantle (4 400 kg/m3, equatorial radius 6 378 km), both flattened by
1/300 (round numbers near Earth's: an example, not a model of Earth). The step in density
is resolved only to the grid spacing (406 km), so the moments are good to about a per cent.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

ROOT = Path(__file__).resolve().parents[1]
N = 33  # odd: Simpson's rule needs an odd number of nodes
HALF_WIDTH = 6.5e6  # m, just outside the planet
LAYERS = ((6.378e6, 4400.0), (3.48e6, 11000.0))  # (equatorial radius m, density kg/m3), outside in
FLATTENING = 1.0 / 300.0


def density_grid() -> xr.Dataset:
    x = np.linspace(-HALF_WIDTH, HALF_WIDTH, N)
    X, Y, Z = np.meshgrid(x, x, x, indexing="ij")
    rho = np.zeros_like(X)
    for a, density in LAYERS:  # outside in: each layer overwrites the one outside it
        c = a * (1.0 - FLATTENING)
        inside = (X**2 + Y**2) / a**2 + Z**2 / c**2 <= 1.0
        rho[inside] = density
    coord = {"units": "m"}
    return xr.Dataset(
        {"rho": (("x", "y", "z"), rho, {"units": "kg m-3", "long_name": "mass density"})},
        coords={
            "x": ("x", x, {**coord, "long_name": "x"}),
            "y": ("y", x, {**coord, "long_name": "y"}),
            "z": ("z", x, {**coord, "long_name": "z (spin axis)"}),
        },
        attrs={
            "title": "Example density grid: a two-layer oblate planet (wobble example planet.nc)",
            "Conventions": "CF-1.10",
            "comment": __doc__.split("\n\n")[2].replace("\n", " "),
        },
    )


def main() -> None:
    path = ROOT / "data" / "examples" / "planet.nc"
    encoding = {"rho": {"zlib": True, "complevel": 9, "shuffle": True}}
    density_grid().to_netcdf(path, format="NETCDF4", engine="netcdf4", encoding=encoding)
    print(f"wrote {path} ({path.stat().st_size} bytes)")


if __name__ == "__main__":
    main()
