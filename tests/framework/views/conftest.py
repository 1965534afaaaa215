"""Small solved runs shared by the labelled-results, display and report tests."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

EXAMPLES = Path(__file__).resolve().parents[3] / "examples"


def _rig_data(pairs: int = 31, **sections) -> dict:
    """The fretting rig example (Nowell-Hills, bulk stress) without its stress and fatigue
    tables, at ``pairs`` pairs; ``sections`` replace or add tables."""
    data = tomllib.loads((EXAMPLES / "fretting_rig.toml").read_text())
    data.pop("stress", None)
    data.pop("fatigue", None)
    data["contact"]["pairs"] = pairs
    data.update(sections)
    return data


@pytest.fixture(scope="session")
def rig_run():
    """The rig (31 pairs, fixed mesh with its estimate) solved through the run pipeline."""
    from fretbem.pipeline import run_scene
    from fretbem.scenes.file import scene_from_data

    return run_scene(scene_from_data(_rig_data()))


@pytest.fixture(scope="session")
def rig_data():
    """``rig_data(pairs, **tables)``: the rig example's tables, to vary."""
    return _rig_data


@pytest.fixture(scope="session")
def demo_run():
    """The reference Cattaneo-Mindlin scene at 21 pairs (no bulk stress), with its estimate."""
    from fretbem.pipeline import run_scene
    from fretbem.scenes.file import load_scene

    return run_scene(load_scene(EXAMPLES / "cattaneo_mindlin.toml", pairs=21))
