"""Free memory and byte counts, for the checks that refuse a request before it is allocated.

Here, below the API, so that a file reader (a scene's time grid) can refuse as the API does.
"""

from __future__ import annotations

import os

__all__ = ["available_memory", "human_bytes"]


def available_memory() -> int:
    """Free physical memory in bytes (8 GiB where the platform cannot say)."""
    try:
        return int(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):  # pragma: no cover - non-POSIX
        return 2**33


def human_bytes(nbytes: float) -> str:
    """``1.5e9`` -> ``'1.5 GB'`` (decimal prefixes)."""
    for unit in ("B", "kB", "MB", "GB", "TB", "PB"):
        if nbytes < 1000:
            return f"{nbytes:.3g} {unit}"
        nbytes /= 1000
    return f"{nbytes:.3g} EB"
