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


@pytest.fixture(scope="session")
def cubic_plugin():
    """examples/custom_basis installed into this environment, as a user installs it.

    Left as found: an install this fixture made is uninstalled afterwards.
    """
    if discovered():
        yield bases.get(FAMILY)
        return
    if pip("--version").returncode != 0:
        pytest.skip(
            "pip is not available in this Python, so the example plugin cannot be installed"
        )
    # offline first (needs setuptools and wheel here), then with an isolated build
    done = pip("install", "--no-deps", "--no-build-isolation", str(PLUGIN))
    if done.returncode != 0:
        done = pip("install", "--no-deps", str(PLUGIN))
    assert done.returncode == 0, f"pip install {PLUGIN} failed:\n{done.stdout}\n{done.stderr}"
    try:
        assert discovered(), f"{DISTRIBUTION} installed but {FAMILY!r} is not discovered"
        yield bases.get(FAMILY)
    finally:
        pip("uninstall", "--yes", DISTRIBUTION)
        for name in [m for m in sys.modules if m.split(".")[0] == "fretbem_cubic"]:
            del sys.modules[name]
        importlib.invalidate_caches()
        bases.refresh()
