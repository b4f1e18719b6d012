"""Keep astropy offline.

wobble never needs the network: the Earth orientation data it reads ship with
the ``astropy-iers-data`` package. astropy would otherwise try to download fresh
IERS tables the first time a time-scale conversion needs them, so importing
wobble switches that off.

The switches are written into astropy's configuration sections, which its
``ConfigItem`` objects read at the moment they are used; the IERS module itself
(about 0.4 s to import) is not loaded here, so ``import wobble`` stays cheap.
"""

from __future__ import annotations

__all__ = ["configure_astropy_offline"]


def configure_astropy_offline(*, forbid_all_downloads: bool = False) -> None:
    """Stop astropy from downloading IERS tables (and optionally anything).

    Parameters
    ----------
    forbid_all_downloads : bool
        Also set ``astropy.utils.data.conf.allow_internet = False``. The command
        line does this (the process is ours); the library leaves other astropy
        downloads of the user's own program alone.
    """
    import sys

    from astropy.config.configuration import get_config

    iers = get_config("astropy.utils.iers.iers")
    iers["auto_download"] = False
    # With auto_download off astropy uses the bundled IERS-B table; an old
    # table is expected here, not a reason to warn or to fetch.
    iers["auto_max_age"] = None
    loaded = sys.modules.get("astropy.utils.iers.iers")
    if loaded is not None:
        # A module imported before wobble may have cached values: set them directly too.
        loaded.conf.auto_download = False
        loaded.conf.auto_max_age = None
    if forbid_all_downloads:
        get_config("astropy.utils.data")["allow_internet"] = False
