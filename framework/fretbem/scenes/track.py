"""The specimen's track for finite sliding (``[contact] sliding = true``).

A pad that slides several contact widths needs the specimen's contact segment (the face it
is paired on) to cover the whole slide: the track is a straight contact segment of
half-width ``[contact] track_width`` (default: the candidate zone plus the largest
displacement ``delta`` of the history), meshed twice as finely as the pad's zone.
"""

from __future__ import annotations

import math

import attrs

from fretbem.geometry.boundary import Segment
from fretbem.geometry.nurbs import NurbsCurve

from .spec import Scene, SceneFileError

__all__ = ["TRACK_DENSITY", "sliding_scene", "track_face", "track_half_width"]

#: the track's elements per length over the pad zone's: at equal density the pressure's
#: error depends on where the pad's nodes fall on the track's elements (0.15 to 0.8 % of
#: p0 measured on examples/gross_sliding.toml), at twice 0.08 to 0.10 %
TRACK_DENSITY = 2.0


def track_half_width(scene: Scene, zone: float) -> float:
    """Half-width (mm) of the specimen's contact segment the pad slides along."""
    if scene.contact.track_width is not None:
        return float(scene.contact.track_width)
    deltas = [abs(d) for d in (scene.load.delta or ()) if d is not None and math.isfinite(d)]
    return zone + max(deltas, default=0.0)


def track_face(track: float) -> list[Segment]:
    """The straight face the flat specimen is built from: one contact segment, -track to
    track at y = 0 (the specimen's flanks run from its ends to it)."""
    return [Segment("contact", NurbsCurve.line([-track, 0.0], [track, 0.0]))]


def sliding_scene(scene: Scene, zone: float, track: float, pad_elements: int) -> Scene:
    """``scene`` ready for sliding on a track of half-width ``track``: a flat specimen long
    enough, its contact face meshed ``TRACK_DENSITY`` times as finely as the pad's zone
    (``pad_elements`` elements over 2 ``zone``) unless ``[specimen]`` sets its own pairs or
    elements."""
    if scene.contact.pairing != "node-to-segment":
        raise SceneFileError(
            "[contact] sliding = true re-pairs the faces by projection as the pad slides, "
            f"but [contact] pairing = {scene.contact.pairing!r}; set [contact] pairing = "
            "'node-to-segment'"
        )
    shape = scene.specimen.shape
    if getattr(shape, "kind", None) != "flat":
        raise SceneFileError(
            "[contact] sliding = true slides the pad along a straight track (the pairs share "
            "one frame and the pad's block translates without turning, so the pad cannot "
            "follow an arc), but [specimen] "
            f"shape = {getattr(shape, 'kind', type(shape).__name__)!r}; use [specimen] "
            "shape = 'flat'"
        )
    if not zone <= track < shape.length / 2:
        raise SceneFileError(
            f"[contact] sliding: the track (half-width {track:.4g} mm, [contact] track_width or "
            f"the zone {zone:.4g} mm plus the largest [load] delta) must lie between the zone "
            f"and the specimen's ends (half-length {shape.length / 2:.4g} mm); lengthen "
            "[specimen] length, or set [contact] track_width within those bounds"
        )
    specimen = scene.specimen
    if specimen.pairs is not None or specimen.elements is not None:
        return scene
    elements = max(1, math.ceil(TRACK_DENSITY * pad_elements * track / zone))
    return attrs.evolve(scene, specimen=attrs.evolve(specimen, elements=elements))
