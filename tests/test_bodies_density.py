"""Inertia from density grids: quadrature order, invariances, streaming, units, bad grids.

The reference is a smooth density with moments computed by mpmath (1-D integrals of
x^n e^{kx} at 30 digits), independent of the grid code.
"""

from __future__ import annotations

import tracemalloc

import mpmath as mp
import numpy as np
import pytest
import xarray as xr
from astropy import units as u
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from wobble import InputError, RigidBody
from wobble.io.density_grid import open_density
from wobble.numerics.grid_quadrature import RULE_ORDER

KGM2 = u.kg * u.m**2

# rho = A exp(al x + be y + ga z) + B exp(-ga x + al y - be z) on an off-centre box (kg/m3, m)
A, B = 1000.0, 500.0
AL, BE, GA = 0.8, -0.5, 0.3
BOX = [(0.2, 1.2), (-0.5, 0.3), (1.0, 1.6)]


def _rho(x, y, z):
    return A * np.exp(AL * x + BE * y + GA * z) + B * np.exp(-GA * x + AL * y - BE * z)


def _reference():
    """Mass, centre of mass and central tensor of the smooth density, from mpmath at 30 digits."""
    with mp.workdps(30):

        def j(n, k, lo, hi):
            return mp.quad(lambda x: x**n * mp.e ** (k * x), [lo, hi])

        def moment(a, b, c):
            (x0, x1), (y0, y1), (z0, z1) = BOX
            return A * j(a, AL, x0, x1) * j(b, BE, y0, y1) * j(c, GA, z0, z1) + B * j(a, -GA, x0, x1) * j(
                b, AL, y0, y1
            ) * j(c, -BE, z0, z1)

        mass = moment(0, 0, 0)
        e = np.eye(3, dtype=int)
        com = [moment(*e[k]) / mass for k in range(3)]
        s = [[moment(*(e[j] + e[k])) - mass * com[j] * com[k] for k in range(3)] for j in range(3)]
        tensor = [
            [
                float(s[(j + 1) % 3][(j + 1) % 3] + s[(j + 2) % 3][(j + 2) % 3]) if j == k else float(-s[j][k])
                for k in range(3)
            ]
            for j in range(3)
        ]
        return float(mass), np.array([float(c) for c in com]), np.array(tensor)


REFERENCE = _reference()


def _grid(n, rule, length_unit=u.m, density_unit=u.kg / u.m**3):
    coords = []
    for lo, hi in BOX:
        if rule == "voxel":  # cell centres of n cells filling the box
            h = (hi - lo) / n
            coords.append(lo + (np.arange(n) + 0.5) * h)
        else:  # nodes on the box edges
            coords.append(np.linspace(lo, hi, n))
    x, y, z = np.meshgrid(*coords, indexing="ij")
    rho = (_rho(x, y, z) * u.kg / u.m**3).to_value(density_unit)
    return xr.DataArray(
        rho,
        dims=("x", "y", "z"),
        coords={d: (d, (c * u.m).to_value(length_unit), {"units": str(length_unit)}) for d, c in zip("xyz", coords)},
        attrs={"units": density_unit.to_string()},
    )


@pytest.mark.parametrize(
    ("rule", "sizes"),
    [("trapezoid", [17, 33, 65, 129]), ("simpson", [17, 33, 65, 129]), ("voxel", [16, 32, 64, 128])],
)
def test_grid_converges_at_the_documented_order(rule, sizes):
    mass, com, tensor = REFERENCE
    errors = []
    for n in sizes:
        body = RigidBody.from_density(_grid(n, rule), rule=rule)
        errors.append(np.max(np.abs(body.tensor.to_value(KGM2) - tensor)) / np.max(np.abs(tensor)))
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    # Measured: trapezoid 2.000, simpson 4.000, voxel 2.000 (h -> h/2).
    np.testing.assert_allclose(orders, RULE_ORDER[rule], atol=0.05)
    assert errors[-1] < {"trapezoid": 2e-4, "simpson": 2e-9, "voxel": 5e-6}[rule]
    assert body.mass.to_value(u.kg) == pytest.approx(mass, rel=errors[-1] * 10)
    np.testing.assert_allclose(body.center_of_mass.to_value(u.m), com, rtol=errors[-1] * 10)


def test_units_of_the_grid_are_honoured():
    """The same grid in cm and g/cm3 gives the same body as in m and kg/m3."""
    si = RigidBody.from_density(_grid(17, "simpson"), rule="simpson")
    cgs = RigidBody.from_density(_grid(17, "simpson", u.cm, u.g / u.cm**3), rule="simpson")
    np.testing.assert_allclose(cgs.tensor.to_value(KGM2), si.tensor.to_value(KGM2), rtol=1e-13, atol=1e-13 * 250)
    np.testing.assert_allclose(cgs.center_of_mass.to_value(u.m), si.center_of_mass.to_value(u.m), rtol=1e-14)


def test_solid_ellipsoid_voxels_approach_the_closed_form():
    """A density that jumps at the surface: first order only, but it gets there."""
    a, b, c = 0.3, 0.2, 0.1
    n = 96
    cs = [(np.arange(n) + 0.5) * 2 * s / n - s for s in (a, b, c)]
    x, y, z = np.meshgrid(*cs, indexing="ij")
    inside = (x / a) ** 2 + (y / b) ** 2 + (z / c) ** 2 <= 1
    da = xr.DataArray(
        np.where(inside, 7800.0, 0.0),
        dims=("x", "y", "z"),
        coords={d: (d, v, {"units": "m"}) for d, v in zip("xyz", cs)},
        attrs={"units": "kg m-3"},
    )
    grid = RigidBody.from_density(da, rule="voxel")
    exact = RigidBody.ellipsoid(grid.mass, [a, b, c] * u.m)
    np.testing.assert_allclose(grid.principal_moments.to_value(KGM2), exact.principal_moments.to_value(KGM2), rtol=5e-3)
    assert grid.mass.to_value(u.kg) == pytest.approx(7800 * 4 / 3 * np.pi * a * b * c, rel=5e-3)


small_grids = st.tuples(st.integers(2, 5), st.integers(2, 5), st.integers(2, 5)).flatmap(
    lambda shape: arrays(float, shape, elements=st.floats(0.0, 10.0)).filter(lambda a: a.sum() > 0.5)
)


@given(
    small_grids,
    st.permutations([0, 1, 2]),
    st.lists(st.booleans(), min_size=3, max_size=3),
    arrays(float, 3, elements=st.floats(-100.0, 100.0)),
)
@settings(max_examples=60)
def test_grid_invariance_under_axis_rotations_and_translation(rho, perm, flips, offset):
    """Relabelling and reversing axes (rotations by 90 degrees, reflections) and moving the grid.

    Array axis k becomes spatial axis ``perm[k]``, with its coordinate negated when
    flipped, and the whole grid shifted by ``offset``: the central tensor becomes
    P I P^T with P the signed permutation; the centre of mass moves with the grid.
    """
    spacing = (0.5, 0.3, 0.2)
    coords = [np.arange(n) * h for n, h in zip(rho.shape, spacing)]
    base = xr.DataArray(
        rho,
        dims=("x", "y", "z"),
        coords={d: (d, c, {"units": "m"}) for d, c in zip("xyz", coords)},
        attrs={"units": "kg m-3"},
    )
    names = "xyz"
    p = np.zeros((3, 3))
    new_coords = {}
    for k in range(3):
        sign = -1.0 if flips[k] else 1.0
        p[perm[k], k] = sign
        new_coords[names[perm[k]]] = (names[perm[k]], sign * coords[k] + offset[perm[k]], {"units": "m"})
    moved = xr.DataArray(
        rho, dims=tuple(names[perm[k]] for k in range(3)), coords=new_coords, attrs={"units": "kg m-3"}
    )
    one = RigidBody.from_density(base)
    two = RigidBody.from_density(moved)
    t1 = one.tensor.to_value(KGM2)
    # Second moments are taken about the grid centre, then the centre of mass is
    # subtracted: rounding ~ eps M L^2 for a grid of extent L, whatever the offset.
    extent = max(n * h for n, h in zip(rho.shape, spacing))
    floor = 1e-13 * one.mass.to_value(u.kg) * extent**2
    scale = np.max(np.abs(t1))
    assert np.max(np.abs(two.tensor.to_value(KGM2) - p @ t1 @ p.T)) <= 1e-12 * scale + floor
    np.testing.assert_allclose(
        two.center_of_mass.to_value(u.m),
        p @ one.center_of_mass.to_value(u.m) + offset,
        rtol=0,
        atol=1e-11 * (1 + np.abs(offset).max()),
    )
    np.testing.assert_allclose(
        two.principal_moments.to_value(KGM2), one.principal_moments.to_value(KGM2), rtol=0, atol=1e-12 * scale + floor
    )


def test_streaming_in_slabs_gives_the_same_answer():
    da = _grid(33, "trapezoid")
    whole = RigidBody.from_density(da, chunk_bytes=2**30)
    slabs = RigidBody.from_density(da, chunk_bytes=1)  # one plane at a time
    t = whole.tensor.to_value(KGM2)
    np.testing.assert_allclose(slabs.tensor.to_value(KGM2), t, rtol=0, atol=1e-14 * np.abs(t).max())
    about = RigidBody.from_density(da, about="origin")
    np.testing.assert_allclose(
        about.tensor.to_value(KGM2), whole.shifted_to("origin").tensor.to_value(KGM2), rtol=1e-14
    )


def test_lazy_file_is_read_slab_by_slab(tmp_path):
    """A 128^3 grid on disk read 4 planes at a time: peak memory stays a few slabs, not the 16 MiB array."""
    n = 128
    c = np.linspace(-1.0, 1.0, n)
    x, y, z = np.meshgrid(c, c, c, indexing="ij", sparse=True)
    rho = np.where(x * x + 4 * y * y + 9 * z * z <= 1, 5500.0, 0.0)
    ds = xr.Dataset(
        {"rho": (("z", "y", "x"), rho, {"units": "kg m-3"})},
        coords={d: (d, c, {"units": "m"}) for d in "xyz"},
    )
    path = tmp_path / "grid.nc"
    ds.to_netcdf(path, encoding={"rho": {"chunksizes": (4, n, n), "zlib": False}})
    in_memory = RigidBody.from_density(ds["rho"])
    del ds, rho
    with open_density(path) as lazy:
        tracemalloc.start()
        slab = 4 * n * n * 8
        body = RigidBody.from_density(lazy, chunk_bytes=slab)
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
    assert peak < 6 * slab < (n**3 * 8) / 5, f"peak {peak / 2**20:.1f} MiB"
    t = in_memory.tensor.to_value(KGM2)
    np.testing.assert_allclose(body.tensor.to_value(KGM2), t, rtol=0, atol=1e-14 * np.abs(t).max())


BAD_GRIDS = [
    (lambda da: da.assign_coords(x=("x", [0.2, 0.4, 0.7, 0.9, 1.2], {"units": "m"})), "density.x", "uniformly spaced"),
    (lambda da: da.assign_coords(y=("y", da.y.values)), "density.y", "length units"),
    (lambda da: da.assign_coords(z=("z", da.z.values, {"units": "kg"})), "density.z", "length units"),
    (lambda da: da.assign_coords(z=("z", da.z.values, {"units": "parsecs!"})), "density.z", "astropy can parse"),
    (lambda da: da.assign_attrs(units=""), "density", "mass/volume units"),
    (lambda da: da.assign_attrs(units="kg"), "density", "mass/volume units"),
    (lambda da: da.where(da.x < 1.0), "density", "finite"),
    (lambda da: -da, "density", "non-negative"),
    (lambda da: da * 0, "density", "positive total mass"),
    (lambda da: da.rename(z="r"), "density", "dimensions x, y and z"),
    (lambda da: da.isel(z=0), "density", "dimensions x, y and z"),
    (lambda da: da.drop_vars("x"), "density.x", "coordinate"),
    (lambda da: da.isel(x=[0]), "density.x", "at least 2 points"),
    (lambda da: da.values, "density", "DataArray"),
]


@pytest.mark.parametrize(("edit", "parameter", "allowed"), BAD_GRIDS)
def test_bad_grids_name_the_parameter(edit, parameter, allowed):
    da = edit(_grid(5, "trapezoid").assign_attrs(units="kg m-3"))
    with pytest.raises(InputError) as info:
        RigidBody.from_density(da)
    assert info.value.parameter == parameter
    assert allowed in str(info.value)


def test_simpson_needs_odd_point_counts_and_rules_are_checked():
    with pytest.raises(InputError, match=r"density\.x: got 6 points; allowed: an odd number"):
        RigidBody.from_density(_grid(6, "trapezoid"), rule="simpson")
    with pytest.raises(InputError, match=r"rule: got gauss; allowed: trapezoid, simpson, voxel"):
        RigidBody.from_density(_grid(5, "trapezoid"), rule="gauss")


def test_bad_values_report_where_they_are():
    da = _grid(5, "trapezoid")
    da[2, 3, 1] = np.nan
    with pytest.raises(InputError, match=r"density: got nan at index \[x=2, y=3, z=1\]"):
        RigidBody.from_density(da)
