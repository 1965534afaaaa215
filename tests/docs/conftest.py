"""Fixtures of the documentation tests: the example plugin package, installed with pip."""

from __future__ import annotations

import importlib
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

from fretbem import registry as bases

REPO = Path(__file__).resolve().parents[2]
PLUGIN = REPO / "examples" / "custom_basis"
DISTRIBUTION = "fretbem-cubic"
FAMILY = "lagrange3"


def pip(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "pip", *args],
        capture_output=True,
        text=True,
        check=False,
        timeout=600,
    )


def discovered() -> bool:
    """Whether the registry finds the example family (rediscovering installed packages)."""
    importlib.invalidate_caches()
    bases.refresh()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # a stale install fails to import
        return FAMILY in bases.available()


def _unpacked(target: Path) -> None:
    """The package and the ``.dist-info`` with the entry points of its pyproject.toml, as pip
    writes them, in ``target`` (where no wheel can be built offline)."""
    import shutil

    import tomllib

    project = tomllib.loads((PLUGIN / "pyproject.toml").read_text())["project"]
    shutil.copytree(PLUGIN / "fretbem_cubic", target / "fretbem_cubic")
    info = target / f"fretbem_cubic-{project['version']}.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(
        f"Metadata-Version: 2.1\nName: {project['name']}\nVersion: {project['version']}\n"
    )
    groups = project["entry-points"]
    (info / "entry_points.txt").write_text(
        "".join(
            f"[{group}]\n" + "".join(f"{k} = {v}\n" for k, v in entries.items())
            for group, entries in groups.items()
        )
    )


@pytest.fixture(scope="session")
def cubic_plugin(tmp_path_factory):
    """examples/custom_basis built by pip as a user installs it, into a temporary target.

    Nothing is installed into the user's environment: the package and its ``.dist-info``
    (with the entry points) go to a temporary directory put on ``sys.path`` for the session
    and removed after, so a killed test run leaves no plugin installed either.
    """
    if discovered():
        yield bases.get(FAMILY)
        return
    if pip("--version").returncode != 0:
        pytest.skip(
            "pip is not available in this Python, so the example plugin cannot be installed"
        )
    target = tmp_path_factory.mktemp("plugin-target")
    # offline (needs setuptools and wheel here); else the files pip would write by hand
    common = ("install", "--no-deps", "--target", str(target), "--no-warn-script-location")
    done = pip(*common, "--no-build-isolation", str(PLUGIN))
    if done.returncode != 0:
        _unpacked(target)
    sys.path.insert(0, str(target))
    try:
        assert discovered(), f"{DISTRIBUTION} built but {FAMILY!r} is not discovered"
        yield bases.get(FAMILY)
    finally:
        sys.path.remove(str(target))
        for name in [m for m in sys.modules if m.split(".")[0] == "fretbem_cubic"]:
            del sys.modules[name]
        importlib.invalidate_caches()
        bases.refresh()
