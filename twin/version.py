"""The installed package's version (``importlib.metadata``), written into every result's
attributes and printed by ``twin --version``; a module of its own so the command line can show it
without importing the result schema (xarray)."""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, version


def package_version() -> str:
    """``thermal-twin``'s installed version, or ``0+unknown`` when run from a source tree that
    was never installed."""
    try:
        return version("thermal-twin")
    except PackageNotFoundError:
        return "0+unknown"
