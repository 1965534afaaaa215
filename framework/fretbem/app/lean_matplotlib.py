"""matplotlib without its property tables in the console script's process.

matplotlib (3.11) writes, while it is imported, a table of every settable property into the
docstring of each Artist class's ``set`` method (:func:`matplotlib.artist.kwdoc`: ~120
tables, ~0.1 s CPU, a quarter of its import and a quarter of the demo's import floor). The
console script's process reads no docstring, so there the table is one line that says where
it went; the classes, their ``set`` signatures and every figure drawn are the same. A
Python session (no console script) and a process that imported matplotlib before keep
matplotlib's tables.
"""

from __future__ import annotations

import importlib.abc
import importlib.machinery
import sys

__all__ = ["NOTE", "install"]

#: what a ``set`` docstring lists instead of the properties in the console script's process
NOTE = "(not listed in the fretbem command's process: see matplotlib.artist.kwdoc)"

#: the module whose ``kwdoc`` builds the tables (every Artist subclass calls it when made)
ARTIST = "matplotlib.artist"


def _note(artist) -> str:
    """:func:`matplotlib.artist.kwdoc`'s place: the note, for any artist or class."""
    return NOTE


class _Finder(importlib.abc.MetaPathFinder):
    """Finds ``matplotlib.artist`` as the path finder does, once, and has its loader replace
    the module's ``kwdoc`` right after running it (before any Artist subclass is made)."""

    def find_spec(self, name, path, target=None):
        if name != ARTIST:
            return None
        _remove()
        spec = importlib.machinery.PathFinder.find_spec(name, path, target)
        run = getattr(spec, "loader", None) and getattr(spec.loader, "exec_module", None)
        if run is None:  # not found, or a loader of another kind: matplotlib as it is
            return spec

        def exec_module(module) -> None:
            run(module)
            if callable(getattr(module, "kwdoc", None)):
                module.kwdoc = _note

        spec.loader.exec_module = exec_module  # this module's loader only
        return spec


_FINDER = _Finder()


def _remove() -> None:
    if _FINDER in sys.meta_path:
        sys.meta_path.remove(_FINDER)


def install() -> None:
    """Replace matplotlib's property tables by :data:`NOTE` when matplotlib is imported in
    this process from now on (nothing if it is imported already)."""
    if ARTIST not in sys.modules and _FINDER not in sys.meta_path:
        sys.meta_path.insert(0, _FINDER)
