"""The half-plane as a body model a scene can choose (``models = {"lower": "half-plane"}``).

The scene describes each body as for the BEM model (boundary, conditions, refinement); the
half-plane keeps only the contact face (its profile, discretisation and the loading block)
and replaces the rest of the body by the half-plane under that face.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from fretbem.basis import Basis, Refinement
from fretbem.conditions import Condition, LoadingBlock
from fretbem.geometry.boundary import Boundary, OpenFace
from fretbem.material import Material

from .body import HalfPlaneBody
from .influence import HalfPlaneFaceError

#: the name scenes use for this model
MODEL = "half-plane"


def half_plane_model(
    label: str,
    *,
    scene: Any,
    boundary: Boundary | OpenFace,
    material: Material,
    conditions: Sequence[Condition],
    family: type[Basis],
    refinement: Mapping[str, Refinement],
    tag: str = "contact",
    name: str | None = None,
) -> HalfPlaneBody:
    """The ``label`` body ("upper": a pad above its surface; "lower": a specimen below it),
    named ``name`` (``label`` if None).

    Keeps the segments tagged ``tag`` (the face: one segment, or several end to end such as
    a rounded flat's fillet, flat and fillet) with their refinement and a loading block if
    the body has one; supports and other segments describe the finite body only.
    """
    segments = [segment for segment in boundary.segments if segment.tag == tag]
    if not segments:
        key = "[pad] model" if label == "upper" else "[specimen] model"
        raise HalfPlaneFaceError(
            f'{key} = "half-plane": the half-plane model of the {label} body needs a segment '
            f"tagged {tag!r} as its face, but the boundary has none; tag the contact segment(s) "
            f"{tag!r}"
        )
    block = next((c for c in conditions if isinstance(c, LoadingBlock)), None)
    return HalfPlaneBody(
        tuple(segment.curve for segment in segments),
        material,
        side="upper" if label == "upper" else "lower",
        basis=family,
        # the default made only when the face's tag has no refinement (not for every build)
        refinement=refinement[tag] if tag in refinement else Refinement(),
        loading_block=block,
        tag=tag,
        name=label if name is None else name,
    )
