"""The corner plot of an inversion: every pair of parameters, the priors and the published values.

Drawn with ``corner`` (Foreman-Mackey 2016, JOSS 1, 24). The diagonal shows each
parameter's posterior (a step histogram) over its prior (dashed), with the published values
of the setup (``[[compare.<name>]]``) as lines and bands, named in one legend in the empty
upper-right triangle; the off-diagonal panels show the 2-D posteriors (filled contours at
0.5, 1, 1.5 and 2 sigma of a 2-D Gaussian). A parameter of a large or small magnitude is
drawn in a power of ten of its unit, named in its label (``[$10^{36}$ kg m$^{2}$]``): Matplotlib's
offset text ("1e36") overlapped the panel above.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from wobble.plot._style import power_label, power_of_ten, unit_label
from wobble.plot.save import WIDE_DPI

__all__ = ["corner_figure", "corner_plot"]


def corner_figure(result):
    """The corner plot of ``result`` (a :class:`wobble.api.inversion.Inversion`) as a Figure."""
    import corner
    import matplotlib.pyplot as plt

    params = result.posterior.parameters
    ndim = len(params)
    samples = np.stack([result.samples[..., i].ravel() / p.scale for i, p in enumerate(params)], axis=-1)
    power = [_power_of_ten(samples[:, i]) for i in range(ndim)]
    shown = np.array([10.0**k for k in power])
    samples = samples / shown
    prior = np.stack([result.prior_samples[:, i] / p.scale for i, p in enumerate(params)], axis=-1) / shown
    labels = [_label(p, k) for p, k in zip(params, power)]
    fig = plt.figure(figsize=(2.1 * ndim + 1.0, 2.1 * ndim + 1.0))
    corner.corner(
        samples,
        fig=fig,
        labels=labels,
        quantiles=[0.16, 0.5, 0.84],
        show_titles=False,
        label_kwargs={"fontsize": 8},
        hist_kwargs={"density": True, "color": "C0"},
        color="C0",
        bins=40,
        smooth=1.0,
        plot_datapoints=False,
        fill_contours=True,
        levels=tuple(1.0 - np.exp(-0.5 * np.array([0.5, 1.0, 1.5, 2.0]) ** 2)),
    )
    axes = np.array(fig.axes).reshape(ndim, ndim)
    # One colour per reference across the figure (counted per parameter, two references shared orange);
    # C0 is the posterior's.
    # C1-C9, then tab20's light shades but blue's: 18 colours, none the posterior's C0.
    palette = [f"C{k}" for k in range(1, 10)] + [plt.get_cmap("tab20").colors[k] for k in range(3, 20, 2)]
    colours = {id(c): palette[j % len(palette)] for j, c in enumerate(result.setup.comparisons)}
    named = {}  # one legend for the figure: in the diagonal panels the entries covered the histograms
    for i, p in enumerate(params):
        ax = axes[i, i]
        unit = p.scale * shown[i]
        lo, hi = ax.get_xlim()
        inside = prior[:, i][(prior[:, i] >= lo) & (prior[:, i] <= hi)]
        if inside.size:
            weights = np.full(inside.size, 1.0 / prior.shape[0])
            ax.hist(
                inside,
                bins=40,
                range=(lo, hi),
                weights=weights / ((hi - lo) / 40),
                histtype="step",
                color="0.45",
                ls="--",
                label="prior",
            )
        for c in (x for x in result.setup.comparisons if x.name == p.name):
            colour = colours[id(c)]
            if c.value is not None:
                ax.axvline(c.value / unit, color=colour, lw=1.2, label=f"{p.name}: {_source(c)}")
                if c.uncertainty is not None:
                    ax.axvspan(
                        (c.value - c.uncertainty) / unit, (c.value + c.uncertainty) / unit, color=colour, alpha=0.15
                    )
            else:
                ax.axvspan(c.low / unit, c.high / unit, color=colour, alpha=0.15, label=f"{p.name}: {_source(c)}")
        ax.set_xlim(lo, hi)
        for handle, label in zip(*ax.get_legend_handles_labels()):
            named.setdefault(label, handle)
    if named:
        fig.legend(named.values(), named.keys(), loc="upper right", bbox_to_anchor=(0.98, 0.93), fontsize=7)
    kind = "prior only" if result.prior_only else "posterior"
    fig.suptitle(f"{result.setup.title} ({kind})", fontsize=10)
    return fig


def _power_of_ten(values) -> int:
    """The power of ten a parameter is drawn in: :func:`power_of_ten` of its median magnitude."""
    finite = np.abs(values[np.isfinite(values)])
    return power_of_ten(float(np.median(finite))) if finite.size else 0


def _label(p, power: int) -> str:
    unit = power_label(power, unit_label(p.unit))  # "$10^{36}$ kg m$^{2}$", as every figure spells units
    return f"{p.name}\n[{unit}]" if unit else p.name


def _source(comparison) -> str:
    """A published value's source up to its first parenthesis: the authors and year."""
    return comparison.source.split("(")[0].strip()


def corner_plot(result, path, *, overwrite: bool = False, dpi: int = WIDE_DPI) -> Path:
    """Write :func:`corner_figure` to ``path`` (PNG, PDF or SVG by its suffix), atomically.

    The path is checked before anything is drawn; the figure is saved under a temporary name in the
    target folder and renamed (:func:`wobble.plot.save.save_figure`); an existing file is replaced
    only with ``overwrite=True``.
    """
    from wobble.plot.save import check_plot_path, save_figure

    check_plot_path(path, overwrite, "path")
    return save_figure(corner_figure(result), path, overwrite=overwrite, dpi=dpi)
