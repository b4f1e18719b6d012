"""Matplotlib figures (interface layer), one module per kind of figure.

The modules load on first use (SPEC 1, ``lazy_loader``), so ``import wobble`` and
``wobble.plot`` cost nothing until a figure is drawn, and ``wobble.plot.free`` works
after a plain ``import wobble`` as the README shows.
"""

import lazy_loader as _lazy

__getattr__, __dir__, __all__ = _lazy.attach(
    __name__,
    submodules=[
        "bench",
        "chandler",
        "excitation",
        "forecast",
        "free",
        "inversion",
        "modes",
        "polar_motion",
        "precession",
        "save",
        "scene",
        "sweep",
        "top",
    ],
)
