"""The physics, in SI float64 and frozen dataclasses.

Models never see units, xarray or files: the public API in :mod:`wobble.api`
converts Quantities to SI once on the way in and back once on the way out.
"""
