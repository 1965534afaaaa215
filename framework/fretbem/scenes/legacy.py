"""The round-1 scene file format ([scene], [geometry], [material.upper/lower]) translated.

Round-1 files described one family: a cylindrical pad on a similar cylinder or on a flat,
both w wide and h high, the lower body clamped at its bottom, constant P. They keep running:
:func:`translate` rewrites them into the current tables, and the reader marks the scene as
``legacy`` so the command line can say the file is in the old form.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from .errors import SceneFileError

__all__ = ["LEGACY_TABLES", "translate"]

#: old table -> old key -> (new table, new key)
LEGACY_TABLES: dict[str, dict[str, tuple[str, str]]] = {
    "scene": {
        "basis": ("contact", "basis"),
        "pairs": ("contact", "pairs"),
        "zone": ("contact", "zone"),
        "degree": ("contact", "degree"),
        "increments": ("load", "increments"),
    },
    "geometry": {"radius": ("", "radius"), "width": ("", "width"), "height": ("", "height")},
    "mesh": {k: ("mesh", k) for k in ("flank_elements", "side_elements", "top_elements")},
    "contact": {"friction": ("contact", "friction")},
    "load": {"P": ("load", "P"), "Q": ("load", "Q"), "steps": ("load", "steps")},
}


def _fail(message: str):
    raise SceneFileError(f"{message} (the file is in the round-1 format)")


def _check_finite(where: str, value: Any) -> None:
    if isinstance(value, float) and not math.isfinite(value):
        _fail(f"{where} must be a finite number, got {value!r}")
    if isinstance(value, list):
        for k, item in enumerate(value):
            _check_finite(f"{where}[{k}]", item)
    if isinstance(value, dict):
        for key, item in value.items():
            _check_finite(f"[{where.strip('[]')}.{key}]" if isinstance(item, dict) else
                          f"{where} {key}", item)  # fmt: skip


def _refuse_unknown(where: str, keys, known, noun: str = "keys") -> None:
    unknown = sorted(set(keys) - set(known))
    if unknown:
        _fail(
            f"unknown key{'s' if len(unknown) > 1 else ''} {unknown} in {where}; the {noun} "
            f"there are {sorted(known)}"
        )


def translate(data: Mapping[str, Any]) -> dict[str, Any]:
    """The same scene in the current format (unknown old keys are errors naming them)."""
    for table, section in data.items():
        _check_finite(f"[{table}]", section)
    _refuse_unknown("the scene file", data, {*LEGACY_TABLES, "material"}, "tables")
    out: dict[str, dict[str, Any]] = {
        "pad": {},
        "specimen": {},
        "contact": {},
        "mesh": {},
        "load": {},
    }
    geometry = data.get("geometry", {})
    if not isinstance(geometry, dict):
        _fail("[geometry] must be a table")
    lower = geometry.get("lower", "arc")
    if lower not in ("arc", "flat"):
        _fail(f"[geometry] lower must be 'arc' or 'flat', got {lower!r}")
    for table, keys in LEGACY_TABLES.items():
        section = data.get(table, {})
        if not isinstance(section, dict):
            _fail(f"[{table}] must be a table")
        _refuse_unknown(
            f"[{table}]", section, set(keys) | ({"lower"} if table == "geometry" else set())
        )
        for key, value in section.items():
            if key == "lower":
                continue
            new_table, new_key = keys[key]
            if new_table:
                out[new_table][new_key] = value
            else:  # geometry: both bodies
                out["pad"][new_key] = value
                if lower == "arc":
                    out["specimen"][new_key] = value
                elif new_key == "width":
                    out["specimen"]["length"] = value
                elif new_key == "height":
                    out["specimen"]["thickness"] = value
    out["pad"]["shape"] = "cylinder"
    out["specimen"]["shape"] = "cylinder" if lower == "arc" else "flat"
    out["specimen"]["support"] = "clamped-bottom"
    load = out["load"]
    if "Q" in load and "steps" not in load and isinstance(load["Q"], list):
        load["steps"] = [f"step{k + 1}" for k in range(len(load["Q"]))]
    material = data.get("material", {})
    if not isinstance(material, dict):
        _fail("[material] must be a table")
    _refuse_unknown("[material]", material, {"E", "nu", "upper", "lower"})
    out["material"] = {k: v for k, v in material.items() if k in ("E", "nu")}
    for old, new in (("upper", "pad"), ("lower", "specimen")):
        own = material.get(old, {})
        if not isinstance(own, dict):
            _fail(f"[material.{old}] must be a table (with E and nu)")
        _refuse_unknown(f"[material.{old}]", own, {"E", "nu"})
        if own:
            out[new]["material"] = dict(own)
    return {k: v for k, v in out.items() if v or k in ("pad", "specimen")}
