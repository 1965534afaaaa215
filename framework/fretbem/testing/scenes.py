"""Variants of a scene file's data for tests: one key changed or removed at a time."""

from __future__ import annotations

import copy
from collections.abc import Mapping
from typing import Any

__all__ = ["SMALL_SCENE", "scene_data_with"]

#: a 21-pair cylinder-on-arc scene of the reference cycle, small enough for sweeps and
#: repeated runs in tests (equilibrium to 1e-3 P); read it, never change it in place
SMALL_SCENE: dict[str, Any] = {
    "scene": {"basis": "nurbs", "pairs": 21, "zone": 1.5},
    "geometry": {"radius": 70.0, "width": 6.5, "height": 16.25, "lower": "arc"},
    "mesh": {"flank_elements": 8, "side_elements": 8, "top_elements": 6},
    "material": {"E": 73400.0, "nu": 0.33},
    "contact": {"friction": 0.3},
    "load": {"P": 100.0, "Q": [0.0, 18.0, 0.0, -18.0, 0.0], "steps": ["A", "B", "C", "D", "E"]},
}


def scene_data_with(data: Mapping[str, Any], changes: Mapping[str, Any]) -> dict[str, Any]:
    """A deep copy of ``data`` (a parsed scene file) with ``changes`` applied: each key is
    ``"table__key"``, its value the new one, or None to remove the key (a missing table is
    made)."""
    changed = copy.deepcopy(dict(data))
    for where, value in changes.items():
        table, key = where.split("__")
        if value is None:
            changed.get(table, {}).pop(key, None)
        else:
            changed.setdefault(table, {})[key] = value
    return changed
