"""Scene files (TOML): read, validate key by key, and turn into a CattaneoMindlinScene.

Unknown keys are errors (a typo must not be silently ignored), and every number must be
finite. The keys are documented in docs/scene-format.md.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import Any

import attrs

from .scenes import CattaneoMindlinScene

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


class SceneFileError(ValueError):
    """A scene file with an unknown key, a wrong type or a non-finite number."""


#: table -> key -> (scene field, expected type)
SCHEMA: dict[str, dict[str, tuple[str, type | tuple[type, ...]]]] = {
    "scene": {
        "basis": ("basis", str),
        "pairs": ("pairs", int),
        "zone": ("zone", (int, float)),
        "degree": ("degree", int),
        "increments": ("increments", int),
    },
    "geometry": {
        "radius": ("radius", (int, float)),
        "width": ("width", (int, float)),
        "height": ("height", (int, float)),
        "lower": ("lower", str),
    },
    "mesh": {
        "flank_elements": ("flank_elements", int),
        "side_elements": ("side_elements", int),
        "top_elements": ("top_elements", int),
    },
    "contact": {"friction": ("friction", (int, float))},
    "load": {
        "P": ("normal", (int, float)),
        "Q": ("tangential", list),
        "steps": ("names", list),
    },
}
MATERIAL_KEYS = {"E", "nu"}


def _check_number(where: str, value: Any) -> None:
    if isinstance(value, float) and not math.isfinite(value):
        raise SceneFileError(f"{where} must be a finite number, got {value!r}")


def _expect(where: str, value: Any, kind) -> None:
    if isinstance(value, bool) or not isinstance(value, kind):
        names = kind.__name__ if isinstance(kind, type) else " or ".join(k.__name__ for k in kind)
        raise SceneFileError(f"{where} must be {names}, got {value!r}")
    _check_number(where, value)


def _unknown(where: str, keys, known) -> None:
    extra = sorted(set(keys) - set(known))
    if extra:
        raise SceneFileError(
            f"unknown key{'s' if len(extra) > 1 else ''} {extra} in {where}; the keys there are "
            f"{sorted(known)} (see docs/scene-format.md)"
        )


def scene_from_dict(data: dict) -> CattaneoMindlinScene:
    """Validate a parsed scene file and build the scene it describes."""
    _unknown("the scene file", data, [*SCHEMA, "material"])
    fields: dict[str, Any] = {}
    for table, keys in SCHEMA.items():
        section = data.get(table, {})
        if not isinstance(section, dict):
            raise SceneFileError(f"[{table}] must be a table")
        _unknown(f"[{table}]", section, keys)
        for key, value in section.items():
            name, kind = keys[key]
            _expect(f"[{table}] {key}", value, kind)
            fields[name] = value
    for key in ("tangential", "names"):
        if key in fields:
            item = (int, float) if key == "tangential" else str
            for k, v in enumerate(fields[key]):
                _expect(f"[load] {'Q' if key == 'tangential' else 'steps'}[{k}]", v, item)
            fields[key] = tuple(fields[key])
    if "tangential" in fields and "names" not in fields:
        fields["names"] = tuple(f"step{k + 1}" for k in range(len(fields["tangential"])))
    if "names" in fields and len(fields["names"]) != len(fields.get("tangential", ())):
        raise SceneFileError(
            f"[load] steps has {len(fields['names'])} names but Q has "
            f"{len(fields.get('tangential', ()))} values; give one name per value of Q"
        )
    material = data.get("material", {})
    if not isinstance(material, dict):
        raise SceneFileError("[material] must be a table")
    _unknown("[material]", material, MATERIAL_KEYS | {"upper", "lower"})
    for side in ("upper", "lower"):
        override = material.get(side, {})
        if not isinstance(override, dict):
            raise SceneFileError(f"[material.{side}] must be a table (with E and nu)")
        _unknown(f"[material.{side}]", override, MATERIAL_KEYS)
        for key in ("E", "nu"):
            value = override.get(key, material.get(key))
            if value is not None:
                where = f"[material.{side}] {key}" if key in override else f"[material] {key}"
                _expect(where, value, (int, float))
                fields[f"{key}_{side}"] = float(value)
    try:
        return CattaneoMindlinScene(**fields)
    except (TypeError, ValueError) as err:
        raise SceneFileError(f"invalid scene: {err}") from err


def load_scene(path: str | Path, **overrides) -> CattaneoMindlinScene:
    """Read a TOML scene file; ``overrides`` (e.g. basis, pairs) replace its values."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text())
    except tomllib.TOMLDecodeError as err:
        raise SceneFileError(f"{path}: not valid TOML: {err}") from err
    except OSError as err:
        raise SceneFileError(f"cannot read scene file {path}: {err.strerror}") from err
    try:
        scene = scene_from_dict(data)
    except SceneFileError as err:
        raise SceneFileError(f"{path}: {err}") from None
    return attrs.evolve(scene, **{k: v for k, v in overrides.items() if v is not None})
