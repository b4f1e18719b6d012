"""The public Python API: Quantities in, Quantities and xarray Datasets out.

Everything here is re-exported from the top-level :mod:`wobble` package.
"""
