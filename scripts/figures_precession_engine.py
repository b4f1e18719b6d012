"""Draw the figures of docs/precession.md section 7 from a real 20-year run of the scene earth_precession.

Usage: python scripts/figures_precession_engine.py

* docs/figures/precession_engine_path.png: the simulated spin axis (angular momentum) in space,
  20 years: its track on the sky and, with the secular precession removed, the nutation in
  longitude and obliquity against time, beside the 18.6-year term of the first-order model;
* docs/figures/precession_engine_nutation.png: the nutation ellipse of the 18.6-year term: the
  simulated pole with the secular motion removed, the fitted 18.6-year term, the first-order
  rigid model and IAU 2000A (non-rigid Earth).
"""

from __future__ import annotations

import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import wobble
from wobble.models.precession_measure import axis_angles

OUT = Path(__file__).resolve().parents[1] / "docs" / "figures"
ARCSEC = math.pi / 180 / 3600
YEAR = 365.25 * 86400.0
IAU = (-17.2064161, 9.2052331)  # IAU 2000A principal term (Mathews, Herring & Buffett 2002)


def _node(ds):
    """The Moon's node from the moving equinox, rad, at the run's times (from the scene's elements)."""
    import json

    from wobble.io.scene_file import scene_from_mapping

    moon = next(t for t in scene_from_mapping(json.loads(ds.attrs["scene"])).torques if t.name == "moon").orbit
    return moon.longitude_of_node, moon.node_rate


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    ds = wobble.run("earth_precession")
    m = wobble.measure_precession(ds)
    print(m.summary())
    t = ds["time"].values
    years = t / YEAR
    big_l = ds["angular_momentum"].values
    psi, eps = axis_angles(big_l / np.linalg.norm(big_l, axis=1)[:, None])
    rate = m.rate.to_value("rad/s")
    node0, node_rate = _node(ds)
    omega = node0 + (node_rate - rate) * t  # the node from the moving equinox (psi0 = pi: x is the equinox)
    lon, obl = m.nutation_longitude.value, m.nutation_obliquity.value
    # the secular line: the fit's rate, through psi with its 18.6-year term taken out (1.07 cycles in
    # 20 years do not average to zero); then the nutation in the IAU convention, Delta psi = -(psi - line)
    psi_sec = np.mean(psi - rate * t + lon * ARCSEC * np.sin(omega)) + rate * t
    dpsi = -(psi - psi_sec) / ARCSEC
    deps = (eps - m.obliquity.to_value("rad")) / ARCSEC
    alon, aobl = m.analytic_nutation_longitude.value, m.analytic_nutation_obliquity.value
    sin_eps = math.sin(float(np.mean(eps)))

    fig, axes = plt.subplots(2, 1, figsize=(7.2, 6.4))
    ax = axes[0]
    along = (psi - psi[0]) * sin_eps / ARCSEC
    ax.plot(along, (eps - eps[0]) / ARCSEC, lw=0.6, color="C0")
    ax.set_xlabel("along the precession: (psi - psi0) sin(eps) [arcsec]")
    # The nutation (~10") beside 20 years of precession (~1000"): unequal scales, and the label says by how much.
    fig.canvas.draw()
    box = ax.get_window_extent()
    dx, dy = np.ptp(ax.get_xlim()), np.ptp(ax.get_ylim())
    ax.set_ylabel(f"eps - eps0 [arcsec]\n(vertical exaggeration {(dx / box.width) / (dy / box.height):.0f}:1)")
    ax.set_title(
        f"Earth's spin axis in space, 20 years by brute force (wobble run earth_precession): {m.rate.value:+.2f}\"/cy",
        fontsize=9,
    )
    ax.invert_xaxis()
    ax = axes[1]
    ax.plot(years, dpsi, lw=0.5, color="C0", label="Delta psi, simulated (secular part removed)")
    ax.plot(years, deps, lw=0.5, color="C3", label="Delta eps, simulated")
    ax.plot(years, alon * np.sin(omega), lw=1.2, ls="--", color="k", label="18.6-year term, first-order model")
    ax.plot(years, aobl * np.cos(omega), lw=1.2, ls="--", color="k")
    ax.set_xlabel("years from J2000.0")
    ax.set_ylabel("nutation [arcsec]")
    ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    path = OUT / "precession_engine_path.png"
    fig.savefig(path, dpi=150)
    plt.close(fig)
    print(f"wrote {path}")

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(8.4, 5.0), gridspec_kw={"width_ratios": [1, 1.25]})
    ax.plot(dpsi * sin_eps, deps, lw=0.3, color="0.6", label="simulated pole, secular motion removed (20 yr)")
    full = np.linspace(0, 2 * math.pi, 361)
    ellipses = (
        (lon, obl, dict(lw=1.6, color="C0"), f'fitted 18.6-yr term: {lon:+.4f}", {obl:+.4f}"'),
        (alon, aobl, dict(lw=1.0, ls="--", color="k"), f'first-order rigid model: {alon:+.4f}", {aobl:+.4f}"'),
        (
            IAU[0],
            IAU[1],
            dict(lw=1.0, ls=":", color="C3"),
            f'IAU 2000A (non-rigid Earth): {IAU[0]:+.4f}", {IAU[1]:+.4f}"',
        ),
    )
    for a, b, style, label in ellipses:
        ax.plot(a * sin_eps * np.sin(full), b * np.cos(full), label=label, **style)
        # the same ellipse minus IAU 2000A's, in milliarcseconds: the rigid Earth's excess
        bx.plot(1e3 * (a - IAU[0]) * sin_eps * np.sin(full), 1e3 * (b - IAU[1]) * np.cos(full), **style)
    ax.set_aspect("equal")
    ax.set_xlabel("Delta psi sin(eps) [arcsec]")
    ax.set_ylabel("Delta eps [arcsec]")
    ax.set_title("The 18.6-year nutation ellipse", fontsize=9)
    bx.set_aspect("equal")
    bx.set_xlabel("minus IAU 2000A: Delta psi sin(eps) [mas]")
    bx.set_ylabel("minus IAU 2000A: Delta eps [mas]")
    bx.set_title("The rigid Earth's excess over IAU 2000A", fontsize=9)
    fig.legend(fontsize=7, loc="lower center", ncol=2)
    fig.tight_layout(rect=(0, 0.12, 1, 0.96))
    path = OUT / "precession_engine_nutation.png"
    fig.savefig(path, dpi=150)
    plt.close(fig)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
