"""The specimen's track for finite sliding (``[contact] sliding = true``).

A pad that slides several contact widths needs the specimen's contact segment (the face it
is paired on) to cover the whole slide: the track is a contact segment of half-width
``[contact] track_width`` (default: the candidate zone plus the largest displacement
``delta`` of the history), meshed twice as finely as the pad's zone (or at the density
``[specimen]`` pairs or elements give in the zone); straight on a flat
specimen, a circular arc on a cylinder specimen (convex) or a groove (concave); the pad turns
with the arc as it slides.
"""

from __future__ import annotations

import math

import attrs

from fretbem.geometry.boundary import Segment
from fretbem.geometry.nurbs import NurbsCurve
from fretbem.geometry.shapes import CylinderSpecimen

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


def track_face(track: float, specimen=None) -> list[Segment]:
    """The face the specimen's track is built from: one contact segment over |x| <= track,
    straight at y = 0 for a flat specimen (its flanks run from its ends to it), for a
    cylinder specimen the arc its boundary mirrors (as it mirrors a cylinder pad's face);
    a groove reads only its ends' x and draws its own concave arc between them."""
    if isinstance(specimen, CylinderSpecimen):
        r = specimen.radius
        half, down = math.asin(track / r), -math.pi / 2
        return [Segment("contact", NurbsCurve.arc([0.0, r], r, down - half, down + half))]
    return [Segment("contact", NurbsCurve.line([-track, 0.0], [track, 0.0]))]


def sliding_scene(
    scene: Scene, zone: float, track: float, pad_elements: int, specimen_elements: int | None = None
) -> Scene:
    """``scene`` ready for sliding on a track of half-width ``track``: a flat specimen long
    enough, its contact face meshed ``TRACK_DENSITY`` times as finely as the pad's zone
    (``pad_elements`` elements over 2 ``zone``), or as finely as ``[specimen]`` pairs or
    elements ask in the zone (``specimen_elements`` over 2 ``zone``): those keys count the
    zone, as on every scene, and the track carries their density along the whole slide."""
    if scene.contact.pairing != "node-to-segment":
        raise SceneFileError(
            "[contact] sliding = true re-pairs the faces by projection as the pad slides, "
            f"but [contact] pairing = {scene.contact.pairing!r}; set [contact] pairing = "
            "'node-to-segment'"
        )
    shape = scene.specimen.shape
    kind = getattr(shape, "kind", type(shape).__name__)
    if kind not in ("flat", "cylinder", "groove"):
        raise SceneFileError(
            "[contact] sliding = true slides the pad along a track the scene builds on a flat "
            "specimen (straight), a cylinder specimen or a groove (a convex or concave circular "
            f"arc the pad turns along), but [specimen] shape = {kind!r}; use [specimen] shape = "
            "'flat', 'cylinder' or 'groove' (a hand-made circular face slides from Python: "
            "fretbem.sliding.run_sliding)"
        )
    if kind != "flat":
        for role in ("pad", "specimen"):
            if getattr(scene, role).model == "half-plane":
                raise SceneFileError(
                    f"[contact] sliding = true on a {kind} specimen slides the pad along an "
                    f"arc, turning it with the arc, but [{role}] model = 'half-plane': a "
                    "half-plane's elasticity is that of a straight surface fixed in its axes, "
                    "which cannot turn along an arc; set [pad] model = 'bem' and [specimen] "
                    "model = 'bem', or slide on a flat specimen ([specimen] shape = 'flat')"
                )
        stress = scene.extras.get("stress", {})
        if isinstance(stress, dict) and stress.get("body") == "upper":
            raise SceneFileError(
                f"[stress] body = 'upper': the pad slides along the {kind} specimen's arc and "
                "turns with it, so its fields are in its own turned axes, not the global frame "
                "the stresses are given in; evaluate the specimen ([stress] body = 'lower'), "
                "or slide on a flat specimen ([specimen] shape = 'flat')"
            )
    ends, size = (shape.length, "length") if kind == "flat" else (shape.width, "width")
    if not zone <= track < ends / 2:
        raise SceneFileError(
            f"[contact] sliding: the track (half-width {track:.4g} mm, [contact] track_width or "
            f"the zone {zone:.4g} mm plus the largest [load] delta) must lie between the zone "
            f"and the specimen's ends (half-{size} {ends / 2:.4g} mm); lengthen [specimen] "
            f"{size}, or set [contact] track_width within those bounds"
        )
    if specimen_elements is None:
        elements = max(1, math.ceil(TRACK_DENSITY * pad_elements * track / zone))
    else:
        elements = max(1, math.ceil(specimen_elements * track / zone))
    specimen = attrs.evolve(scene.specimen, pairs=None, elements=elements)
    return attrs.evolve(scene, specimen=specimen)
