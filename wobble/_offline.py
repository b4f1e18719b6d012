"""Keep astropy offline.

wobble never needs the network: the Earth orientation data it reads ship with
the ``astropy-iers-data`` package. astropy would otherwise try to download fresh
IERS tables the first time a time-scale conversion needs them, so importing
wobble switches that off: at once when astropy is already loaded, else the moment
astropy is first imported (by wobble or by anyone), through a one-shot import hook,
so that ``import wobble`` and ``wobble --help`` do not pay astropy's import (~0.2 s).

The switches are written into astropy's configuration sections, which its
``ConfigItem`` objects read at the moment they are used; the IERS module itself
(about 0.4 s to import) is not loaded here, so ``import wobble`` stays cheap.
"""

from __future__ import annotations

import importlib.util
import sys

__all__ = ["configure_astropy_offline", "configure_when_astropy_loads"]


class _AstropyImportHook:
    """A meta path finder (importlib.abc.MetaPathFinder's protocol; the ABC costs 20 ms to import):
    finds astropy as the other finders do, then configures it right after its ``__init__`` runs."""

    def find_spec(self, name, path=None, target=None):
        if name != "astropy":
            return None
        _remove_hook()  # one shot; also lets importlib.util.find_spec below reach the real finders
        spec = importlib.util.find_spec(name)
        loader = getattr(spec, "loader", None)
        if loader is None or not hasattr(loader, "exec_module"):
            return spec
        exec_module = loader.exec_module

        def exec_then_configure(module):
            exec_module(module)
            configure_astropy_offline()

        loader.exec_module = exec_then_configure  # this loader instance loads astropy alone
        return spec


def _remove_hook() -> None:
    sys.meta_path[:] = [f for f in sys.meta_path if not isinstance(f, _AstropyImportHook)]


def configure_when_astropy_loads() -> None:
    """:func:`configure_astropy_offline` now if astropy is loaded, else as soon as it is imported."""
    if "astropy" in sys.modules:
        configure_astropy_offline()
    elif not any(isinstance(f, _AstropyImportHook) for f in sys.meta_path):
        sys.meta_path.insert(0, _AstropyImportHook())


def configure_astropy_offline(*, forbid_all_downloads: bool = False) -> None:
    """Stop astropy from downloading IERS tables (and optionally anything).

    Parameters
    ----------
    forbid_all_downloads : bool
        Also set ``astropy.utils.data.conf.allow_internet = False``. The command
        line does this (the process is ours); the library leaves other astropy
        downloads of the user's own program alone.
    """
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
