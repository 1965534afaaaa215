"""The README and the docs stand alone: no path outside the repository, the paper cited."""

from __future__ import annotations

import os
import re
from fnmatch import fnmatch
from pathlib import Path

ROOT = Path(__file__).parents[3]
OUTSIDE = re.compile(r"\.\./shared|(?<![\w.-])shared/(reference|fretting|style)|/work/shared")
SOURCES = ("*.md", "*.rst", "*.py", "*.txt", "*.toml")
GENERATED = {"_build", "auto_tutorials", "auto_verification", "api"}


def _product_files() -> list[Path]:
    """os.walk, which skips a folder that vanishes while it walks (the docs build, run beside
    the tests, writes and renames output folders under docs/tutorials)."""
    files = [ROOT / "README.md"]
    for folder in ("docs", "examples", "framework", "plugins"):
        for top, folders, names in os.walk(ROOT / folder):
            folders[:] = [f for f in folders if f not in GENERATED]
            files += [Path(top, n) for n in names if any(fnmatch(n, s) for s in SOURCES)]
    return files


def test_no_reference_outside_the_repository():
    """Reproducer: the README pointed new users at ../shared/reference-scene.md."""
    offenders = [
        f"{p.relative_to(ROOT)}:{n}"
        for p in _product_files()
        for n, line in enumerate(p.read_text(errors="replace").splitlines(), 1)
        if OUTSIDE.search(line)
    ]
    assert not offenders, f"paths outside the repository in: {offenders}"


def test_readme_describes_the_reference_scene_and_sources():
    """The scene's numbers, the paper's title and the CalculiX figures are in the README."""
    readme = " ".join((ROOT / "README.md").read_text().split())
    for fact in ("R = 70 mm", "E = 73 400 MPa", "f = 0.3", "P = 100 N/mm", "0.3289 mm",
                 "193.5 MPa", "2D contact simulation of fretting specimens using IGABEM",
                 "4.104 %", "CalculiX", "27 s", "720 s", "units.json", "--overwrite"):  # fmt: skip
        assert fact in readme, fact
