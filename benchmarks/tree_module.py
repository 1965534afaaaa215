"""One module of another source tree, loaded under a name of its own beside this tree's
fretbem (the benchmarks that time two trees' versions of one function in one process)."""

from __future__ import annotations

import importlib.util
from pathlib import Path
from types import ModuleType


def tree_module(tree: str | Path, dotted: str, name: str) -> ModuleType:
    """``dotted`` (e.g. ``"fretbem.bem.mirror_split"``) from ``tree``'s framework folder, as
    the module ``name``; its imports of fretbem resolve to the fretbem already imported."""
    path = Path(tree) / "framework" / Path(*dotted.split(".")).with_suffix(".py")
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
