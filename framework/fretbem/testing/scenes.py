"""Variants of a scene file's data for tests: one key changed or removed at a time."""

from __future__ import annotations

import copy
from collections.abc import Mapping
from typing import Any

__all__ = ["scene_data_with"]


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
