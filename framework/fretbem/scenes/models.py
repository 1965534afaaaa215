"""Body models a scene names (``[pad] model``, ``[specimen] model``): how each builds a Body.

A body model is a plugin of the ``fretbem.bodies`` entry-point group: a :class:`BodyModel`
subclass whose :meth:`~BodyModel.build` makes the pad or the specimen of a scene from the
boundary, material, conditions and face discretisation the scene builder prepared. The
built-in ones are ``bem`` (:class:`~fretbem.bem.body.BemBody`, here) and ``half-plane``
(:class:`~fretbem.halfplane.body.HalfPlaneBody`, in :mod:`fretbem.scenes.half_plane_model`,
a module of its own so that the lazy registry loads the half-plane package only for a
scene that names it).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Mapping, Sequence
from typing import ClassVar

from fretbem.basis import Basis, Refinement
from fretbem.bem.body import BemBody
from fretbem.body import Body
from fretbem.conditions import Condition
from fretbem.geometry.boundary import Boundary, OpenFace
from fretbem.material import Material

__all__ = ["BemModel", "BodyModel"]


class BodyModel(ABC):
    """Builds a scene's pad (``role`` "pad") or specimen ("specimen") as a :class:`Body`."""

    #: one line for ``fretbem plugins``
    description: ClassVar[str] = ""
    #: True if :meth:`build` reads only the face segments of ``boundary`` (its ``segments``
    #: tagged flank or contact): the scene builder then passes a library shape's face as an
    #: :class:`~fretbem.geometry.boundary.OpenFace` and skips building and checking the closed
    #: boundary (a drawn ``nurbs`` shape's boundary is always built and checked)
    face_only: ClassVar[bool] = False

    @abstractmethod
    def build(
        self,
        scene,
        role: str,
        boundary: Boundary | OpenFace,
        material: Material,
        conditions: Sequence[Condition],
        family: type[Basis],
        refinement: Mapping[str, Refinement],
    ) -> Body:
        """The body; ``refinement`` maps boundary tags to their discretisation."""


class BemModel(BodyModel):
    """A finite elastic body discretised by boundary elements on its whole boundary."""

    description = "finite elastic body, boundary elements on its whole NURBS boundary"

    def build(self, scene, role, boundary, material, conditions, family, refinement) -> Body:
        return BemBody(boundary, material, conditions, basis=family, refinement=refinement,
                       name=role)  # fmt: skip
