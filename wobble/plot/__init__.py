"""Matplotlib figures (interface layer). Import submodules directly, e.g. ``wobble.plot.free``."""
