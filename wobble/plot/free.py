"""Figures of torque-free rotation: the polhode on the energy ellipsoid, a tennis-racket flip."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from astropy import units as u

from wobble.api.free import FreeRotation

__all__ = ["polhode_figure", "flip_figure"]


def polhode_figure(moments, omegas, *, samples: int = 2000):
    """Polhodes (paths of L in the body frame) on the energy ellipsoid.

    Parameters
    ----------
    moments : astropy.units.Quantity
        Three principal moments (same for all curves).
    omegas : list of astropy.units.Quantity
        Initial angular velocities; each is rescaled to the energy of the first
        so all polhodes lie on one ellipsoid ``sum L_j^2 / I_j = 2 T``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    I = moments.to_value(u.kg * u.m**2)  # noqa: E741
    fig = plt.figure(figsize=(6.4, 6.0))
    ax = fig.add_subplot(projection="3d")
    w_first = omegas[0].to_value(u.rad / u.s)
    two_t = float(np.sum(I * w_first**2))
    uu, vv = np.meshgrid(np.linspace(0, 2 * np.pi, 60), np.linspace(0, np.pi, 30))
    radii = np.sqrt(two_t * I)
    ax.plot_surface(
        radii[0] * np.cos(uu) * np.sin(vv), radii[1] * np.sin(uu) * np.sin(vv), radii[2] * np.cos(vv),
        color="0.85", alpha=0.25, linewidth=0,
    )
    for w in omegas:
        w = w.to_value(u.rad / u.s)
        w = w * np.sqrt(two_t / np.sum(I * w**2))
        body = FreeRotation(moments, w * u.rad / u.s)
        period = body.period.to_value(u.s)
        span = period if np.isfinite(period) else 60.0 / max(body.model.precession_rate, 1e-300)
        t = np.linspace(0, span, samples)
        L = body.model.omega(t) * I
        color = "C3" if body.regime == "separatrix" else ("C0" if body.regime == "major-axis" else "C2")
        ax.plot(L[:, 0], L[:, 1], L[:, 2], color=color, lw=1.2)
    ax.set_xlabel("$L_1$ (kg m$^2$ s$^{-1}$)")
    ax.set_ylabel("$L_2$")
    ax.set_zlabel("$L_3$")
    ax.set_box_aspect(radii)
    ax.set_title("Polhodes on the energy ellipsoid (blue: about $I_3$, green: about $I_1$)")
    return fig


def flip_figure(moments, omega0, t_end):
    """Components of omega through tennis-racket (Dzhanibekov) flips, flip times marked."""
    body = FreeRotation(moments, omega0)
    t_end_s = t_end.to_value(u.s)
    ds = body.evaluate(t_end=t_end, samples=4001)
    fig, ax = plt.subplots(figsize=(7.0, 3.8))
    for k, label in enumerate(("$\\omega_1$", "$\\omega_2$", "$\\omega_3$")):
        ax.plot(ds.time, ds.omega[:, k], label=label)
    for tf in body.flip_times(t_end).to_value(u.s):
        ax.axvline(tf, color="0.6", lw=0.8, ls=":")
    ax.set_xlim(0, t_end_s)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("body-frame angular velocity (rad s$^{-1}$)")
    ax.set_title(f"Tennis-racket flips: 1 - m = {body.complementary_parameter:.2g}, "
                 f"flip every {body.time_between_flips.to_value(u.s):.6f} s")
    ax.legend(loc="upper right")
    fig.tight_layout()
    return fig
