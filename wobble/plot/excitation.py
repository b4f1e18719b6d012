"""Figures of the geodetic excitation: spectra of the pole and of its excitation, the Chandler band against time.

The pole's spectrum has a sharp Chandler peak; the excitation's is broadband
there (the resonance, not the excitation, makes the peak). The band amplitudes
against time show the post-2015 decline of the wobble beside its excitation.
"""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from wobble.plot.polar_motion import log_floor, mark_collapse
from wobble.plot._style import decimal_year
from wobble.plot.save import WIDE_DPI, save_figure

__all__ = ["excitation_figure", "save_excitation_figure"]


def excitation_figure(ex) -> Figure:
    """Two panels: two-sided amplitude spectra (pole and excitation), and Chandler-band amplitudes against time."""
    fig = Figure(figsize=(10, 8), layout="constrained")
    ax_s, ax_t = fig.subplots(2, 1)
    f, ac, ap = ex.spectra()
    ax_s.plot(f, ap, lw=0.8, color="C0", label="pole x_p - i y_p")
    ax_s.plot(f, ac, lw=0.8, color="C3", label="excitation chi_1 + i chi_2")
    pc = 1 / ex.chandler_period.to_value("yr")
    ax_s.axvspan(pc - 0.1, pc + 0.1, color="0.8", alpha=0.5, label="Chandler band")
    ax_s.set_yscale("log")
    ax_s.set_xlim(-3, 3)
    view = np.abs(f) <= 3
    log_floor(ax_s, np.concatenate([f[view], f[view]]), np.concatenate([ap[view], ac[view]]))
    ax_s.set_xlabel("frequency [cycles per year] (negative: retrograde)")
    ax_s.set_ylabel("amplitude [mas]")
    # The title states what is drawn, not a finding: on a short span the pole's peak may not stand out.
    q = "inf" if ex.quality_factor is None or not np.isfinite(ex.quality_factor) else f"{ex.quality_factor:.0f}"
    ax_s.set_title(
        f"two-sided spectra of the pole and of its excitation (T_c = {ex.chandler_period.value:.1f} d, Q = {q})",
        fontsize="medium",
    )
    ax_s.legend(fontsize="small")
    if ex.band_chi is not None:
        years = decimal_year(ex.time_mjd)
        known = np.isfinite(ex.band_pole)  # NaN within the band-pass kernel's reach of the ends
        ax_t.plot(years, ex.band_pole, color="C0", label="pole, Chandler band")
        ax_t.plot(years[1:], ex.band_chi, color="C3", label="excitation, Chandler band")
        mark_collapse(ax_t, years[known], "2015-01-01, where the before/after comparison splits")
        ax_t.set_xlim(years[0], years[-1])
        ax_t.set_yscale("log")
        ax_t.set_xlabel("year")
        ax_t.set_ylabel("band amplitude [mas]")
        ax_t.legend(fontsize="small")
        reach = ex.band_reach.to_value("yr")
        ax_t.set_title(
            "amplitude within +/- 0.1 cycle per year of the Chandler frequency; "
            f"none within {reach:.0f} yr of the ends",
            fontsize="medium",
        )
    else:  # the band-pass needs eleven years (GeodeticExcitation.band_chi): say so, not a bare 0-1 axis
        ax_t.set_axis_off()
        ax_t.text(
            0.5,
            0.5,
            "no Chandler-band amplitudes: the band-pass needs daily samples without gaps over "
            f"{2 * ex.band_reach.to_value('yr') + 1:.1f} years\n"
            f"(its kernel reaches {ex.band_reach.to_value('yr'):.1f} years either side, and a year of amplitudes "
            "is the least)",
            ha="center",
            va="center",
            transform=ax_t.transAxes,
            fontsize="small",
        )
    return fig


def save_excitation_figure(ex, path, *, overwrite: bool = False):
    """Write :func:`excitation_figure` to ``path`` (png, pdf or svg)."""
    return save_figure(excitation_figure(ex), path, overwrite=overwrite, dpi=WIDE_DPI)
