"""Scene files (TOML): read a file into a :class:`~fretbem.scenes.spec.Scene`.

The keys, their units and defaults are the table of :mod:`fretbem.scenes.spec` (shown in
docs/scene-format.md); files in the round-1 format are translated on reading. Unknown keys
are errors (a typo must not be silently ignored), and every number must be finite.
"""

from __future__ import annotations

from pathlib import Path

import attrs

from .errors import SceneFileError
from .legacy import translate
from .spec import Scene, is_legacy, scene_from_dict
from .text import read_toml

__all__ = ["SceneFileError", "load_scene", "scene_from_data", "scene_from_dict"]


def scene_from_data(data) -> Scene:
    """A parsed scene file as a Scene; the round-1 format is translated here, and only here."""
    if isinstance(data, dict) and is_legacy(data):
        return attrs.evolve(scene_from_dict(translate(data)), legacy=True)
    return scene_from_dict(data)


def load_scene(path: str | Path, **contact_overrides) -> Scene:
    """Read a TOML scene file; ``contact_overrides`` (basis, pairs) replace [contact] keys."""
    path = Path(path)
    data = read_toml(path, "scene file", SceneFileError)
    try:
        scene = scene_from_data(data)
    except SceneFileError as err:
        raise SceneFileError(f"{path}: {err}") from None
    overrides = {k: v for k, v in contact_overrides.items() if v is not None}
    if overrides:
        scene = attrs.evolve(scene, contact=attrs.evolve(scene.contact, **overrides))
    return scene
