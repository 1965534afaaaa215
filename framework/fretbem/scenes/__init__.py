"""Scenes: the scene-file record, its reader and legacy translation, the builder,
the reference scene.

The names of :mod:`.reference` are re-exported here.
"""


from .reference import (
    FACE_TAGS,
    REFERENCE_STEPS,
    CattaneoMindlinScene,
    body_model,
    cattaneo_mindlin,
    lower_boundary,
    upper_boundary,
)

__all__ = [
    "FACE_TAGS",
    "REFERENCE_STEPS",
    "CattaneoMindlinScene",
    "body_model",
    "cattaneo_mindlin",
    "lower_boundary",
    "upper_boundary",
]
