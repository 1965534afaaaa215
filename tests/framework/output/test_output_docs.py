"""The README and the docs stand alone: no path outside the repository, the paper cited."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).parents[3]
OUTSIDE = re.compile(r"\.\./shared|(?<![\w.-])shared/(reference|fretting|style)|/work/shared")
SOURCES = ("*.md", "*.rst", "*.py", "*.txt", "*.toml")


def _product_files() -> list[Path]:
    files = [ROOT / "README.md"]
    for folder in ("docs", "examples", "framework", "plugins"):
        for pattern in SOURCES:
            files += [
                p for p in (ROOT / folder).rglob(pattern)
                if not {"_build", "auto_tutorials", "auto_verification", "api"} & set(p.parts)
            ]  # fmt: skip
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
