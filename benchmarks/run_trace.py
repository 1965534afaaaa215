"""Which fretbem modules one ``fretbem run`` enters (the house issue's "passes through").

Counts, with ``sys.setprofile``, every call into a fretbem module from another module while
``fretbem run SCENE --no-figures --no-vtk`` runs in this process; imports are not counted.

    python benchmarks/run_trace.py examples/cattaneo_mindlin.toml [--all]

(``--all`` lists every module entered, not the ten most entered.)
"""

from __future__ import annotations

import collections
import pkgutil
import sys
import tempfile

import fretbem

try:
    from fretbem.app import cli
except ImportError:  # the flat layout before the house regrouping
    from fretbem import cli


def main(scene: str) -> None:
    entered: collections.Counter = collections.Counter()

    def profile(frame, event, arg):
        if event != "call":
            return
        module = frame.f_globals.get("__name__", "")
        caller = frame.f_back.f_globals.get("__name__", "") if frame.f_back else ""
        if module.startswith("fretbem") and caller != module:
            entered[module] += 1

    with tempfile.TemporaryDirectory() as out:
        sys.setprofile(profile)
        try:
            cli.main(["run", scene, "--out", f"{out}/o", "--no-figures", "--no-vtk"])
        finally:
            sys.setprofile(None)
    total = [m.name for m in pkgutil.walk_packages(fretbem.__path__, "fretbem.")]
    print(f"modules entered: {len(entered)} of {len(total)}")
    for module, count in entered.most_common(10 if len(sys.argv) < 3 else None):
        print(f"  {count:6d}  {module}")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "examples/cattaneo_mindlin.toml")
