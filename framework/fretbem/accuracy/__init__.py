"""Accuracy of a run: the error estimate, the accuracy modes and the adaptive mesh.

The names of :mod:`.modes` are re-exported here.
"""

from .modes import (
    MESHES,
    UNIFORM_RATE,
    Accuracy,
    AccuracyError,
    companion_pairs,
    estimate_blocker,
    mode_of,
    solve,
    solve_scene,
)

__all__ = [
    "MESHES",
    "UNIFORM_RATE",
    "Accuracy",
    "AccuracyError",
    "companion_pairs",
    "estimate_blocker",
    "mode_of",
    "solve",
    "solve_scene",
]
