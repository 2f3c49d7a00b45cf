"""Data shipped with tribobem: the demo scenario and four measured topographies.

The measured topographies (``example_ps.tiff``, ``di-3.di``, ``spot_1-1000nm.ibw``,
``plu-1.plu``; origin, grids and licence in ``topographies/README.md``) are package data under
``tribobem/data/topographies``: they are installed with the package, so examples, tests and
studies find them without any relative path.

One setting finds them: :func:`topography_path` looks in :func:`topography_dir`, which is the
shipped folder unless the environment variable ``TRIBOBEM_DATA_DIR`` names another folder (it
then replaces the shipped one entirely; nothing else is searched).  A scenario names a file of
that folder as ``path = "data:example_ps.tiff"`` (resolved by
:func:`tribobem.scenario.build.resolve_path` through :func:`topography_path`);
``tribobem info data:example_ps.tiff`` works the same way.
"""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import InputError

__all__ = ["DATA_ENV", "DATA_PREFIX", "TOPOGRAPHIES", "topography_dir", "topography_path"]

#: The environment variable that replaces the folder of measured topographies.
DATA_ENV = "TRIBOBEM_DATA_DIR"
#: Prefix of a scenario ``path`` (or a ``tribobem info`` argument) naming a file of that folder.
DATA_PREFIX = "data:"
#: The measured topographies shipped with the package (see ``topographies/README.md``).
TOPOGRAPHIES = ("example_ps.tiff", "di-3.di", "spot_1-1000nm.ibw", "plu-1.plu")

_SHIPPED = Path(__file__).resolve().parent / "topographies"


def topography_dir() -> Path:
    """The folder of measured topographies.

    Returns
    -------
    pathlib.Path
        ``$TRIBOBEM_DATA_DIR`` when set (and not empty; ``~`` and variables expanded), else the
        copy shipped inside the package (``tribobem/data/topographies``).
    """
    env = os.environ.get(DATA_ENV, "").strip()
    if env:
        return Path(os.path.expandvars(os.path.expanduser(env)))
    return _SHIPPED


def topography_path(name: str, *, must_exist: bool = True) -> Path:
    """The path of the measured topography ``name`` in :func:`topography_dir`.

    Parameters
    ----------
    name : str
        A file name of that folder, e.g. ``"example_ps.tiff"`` (a leading ``"data:"`` is
        accepted and removed).  The shipped files are :data:`TOPOGRAPHIES`.
    must_exist : bool
        Raise when the file is not there (default); False returns the path anyway.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    InputError
        For an empty name, a name that leaves the folder (``..``, an absolute path), or (with
        ``must_exist``) a file that is not in the folder; the message names the folder, whether
        ``TRIBOBEM_DATA_DIR`` chose it, and the shipped files.
    """
    text = str(name)
    if text.startswith(DATA_PREFIX):
        text = text[len(DATA_PREFIX):]
    rel = Path(text)
    if not text.strip() or rel.is_absolute() or ".." in rel.parts:
        raise InputError("path", f"{DATA_PREFIX}{text} must name a file of the data folder (e.g. "
                                 f"{DATA_PREFIX}example_ps.tiff), without '..' or an absolute path")
    folder = topography_dir()
    path = folder / rel
    if must_exist and not path.is_file():
        origin = (f"${DATA_ENV} = {os.environ.get(DATA_ENV)}" if os.environ.get(DATA_ENV, "").strip()
                  else "the copy shipped with tribobem")
        raise InputError("path", f"{DATA_PREFIX}{text}: no file {path} ({origin}); shipped files: "
                                 f"{', '.join(TOPOGRAPHIES)}")
    return path
