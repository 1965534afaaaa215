"""Scenes: the scene record, its file reader and round-1 translation, the one builder, the
body models a scene names, and the reference scene.

The names of :mod:`.reference` are re-exported here.
"""

from .reference import REFERENCE_STEPS, CattaneoMindlinScene, cattaneo_mindlin

__all__ = ["REFERENCE_STEPS", "CattaneoMindlinScene", "cattaneo_mindlin"]
