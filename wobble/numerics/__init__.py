"""Float64 numerical kernels in SI: no units, no data structures, no I/O.

Only NumPy and SciPy are imported here, and Numba by the two compiled kernels
(rigid_dop853, nome_grid), which are imported only where they run (enforced by
the import-linter contracts in pyproject.toml and tests/test_architecture.py).
"""
