"""The ``half-plane`` body model (``[pad] model`` / ``[specimen] model``): an elastic
half-plane under the contact face, in a module of its own so that a scene of BEM bodies
never loads the half-plane package (the registry imports a plugin only when named)."""

from __future__ import annotations

from fretbem.body import Body
from fretbem.halfplane.scene import half_plane_model

from .models import BodyModel

__all__ = ["HalfPlaneModel"]


class HalfPlaneModel(BodyModel):
    """An elastic half-plane under the contact face (closed-form surface response)."""

    description = "elastic half-plane below the contact face (Flamant influence functions)"
    face_only = True

    def build(self, scene, role, boundary, material, conditions, family, refinement) -> Body:
        return half_plane_model(
            "upper" if role == "pad" else "lower",
            scene=scene,
            boundary=boundary,
            material=material,
            conditions=conditions,
            family=family,
            refinement=refinement,
            name=role,  # named at construction: evolve would discretise the face again
        )
