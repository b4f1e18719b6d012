"""Float64 numerical kernels in SI: no units, no data structures, no I/O.

Only NumPy and SciPy are imported here (enforced by the import-linter
contracts in pyproject.toml).
"""
