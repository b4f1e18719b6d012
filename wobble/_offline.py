"""Keep astropy offline.

wobble never needs the network: the Earth orientation data it reads ship with
the ``astropy-iers-data`` package. astropy would otherwise try to download fresh
IERS tables the first time a time-scale conversion needs them, so importing
wobble switches that off.
"""

from __future__ import annotations


def configure_astropy_offline(*, forbid_all_downloads: bool = False) -> None:
    """Stop astropy from downloading IERS tables (and optionally anything).

    Parameters
    ----------
    forbid_all_downloads : bool
        Also set ``astropy.utils.data.conf.allow_internet = False``. The command
        line does this (the process is ours); the library leaves other astropy
        downloads of the user's own program alone.
    """
    from astropy.utils import iers

    iers.conf.auto_download = False
    # With auto_download off astropy uses the bundled IERS-B table; an old
    # table is expected here, not a reason to warn or to fetch.
    iers.conf.auto_max_age = None
    if forbid_all_downloads:
        from astropy.utils.data import conf as data_conf

        data_conf.allow_internet = False
