"""A Winkler-foundation body model and a Newton-then-Lemke solver: example fretbem plugins.

Registered in this package's ``pyproject.toml`` under the ``fretbem.bodies`` and
``fretbem.solvers`` entry-point groups, so a scene file can name ``model = "winkler"`` and
``solver = "newton-lemke"``.
"""

from __future__ import annotations

import attrs
import numpy as np

from fretbem.body import Body, ContactFace, ContactResponse
from fretbem.material import Material
from fretbem.scenes.models import BodyModel
from fretbem.solvers import LemkeSolver
from fretbem.solvers.newton import SemiSmoothNewton, Solver, SolverConvergenceError

__all__ = ["NewtonThenLemke", "WinklerFoundation", "WinklerModel"]

#: depth of the elastic layer the springs stand for (mm): k = E' / DEPTH
DEPTH = 1.0


@attrs.frozen(eq=False)
class WinklerFoundation(Body):
    """A bed of springs under a face on y = 0 (outward normal +y): u = t / k at every node."""

    x: np.ndarray = attrs.field(converter=lambda v: np.asarray(v, float))
    stiffness: float
    material: Material
    name: str = "foundation"
    tag: str = "contact"
    _cache: dict = attrs.field(init=False, factory=dict, repr=False)

    @property
    def loading_block(self):
        return None  # held by its springs

    @property
    def dofs(self) -> int:
        return 2 * len(self.x)

    def describe(self) -> dict:
        return {"model": "winkler", "stiffness": self.stiffness}

    def contact_face(self, tag: str) -> ContactFace:
        if tag != self.tag:
            raise KeyError(f"a Winkler foundation has only the face {self.tag!r}, not {tag!r}")
        n = len(self.x)
        return ContactFace(np.column_stack([self.x, np.zeros(n)]), np.tile([0.0, 1.0], (n, 1)))

    def contact_response(self, tag: str) -> ContactResponse:
        if tag not in self._cache:
            n = len(self.contact_face(tag).points)
            weights = np.zeros(n)  # trapezoidal: the face length each node carries
            weights[:-1] += np.diff(self.x) / 2
            weights[1:] += np.diff(self.x) / 2
            force = np.zeros((2, 2 * n))
            force[0, 0::2] = force[1, 1::2] = weights
            self._cache[tag] = ContactResponse(
                base=np.zeros((n, 2)),
                traction_map=np.eye(2 * n).reshape(n, 2, 2 * n) / self.stiffness,
                block_map=np.zeros((n, 2, 2)),
                load_map=np.zeros((n, 2, 0)),
                r_base=np.zeros(2),
                r_traction=np.zeros((2, 2 * n)),
                r_block=np.zeros((2, 2)),
                r_load=np.zeros((2, 0)),
                contact_force=force,
                has_block=False,
            )
        return self._cache[tag]

    def solution(self, tag, tractions, block, loads) -> dict:
        tractions = np.asarray(tractions, float)
        return {"tractions": tractions, "displacements": tractions / self.stiffness}


class WinklerModel(BodyModel):
    """The specimen as springs under its contact face, k = E' / 1 mm per unit area."""

    description = "bed of independent springs under the contact face (Winkler), k = E'/1 mm"

    def build(self, scene, role, boundary, material, conditions, family, refinement) -> Body:
        segments = [s for s in boundary.segments if s.tag == "contact"]
        if role != "specimen" or len(segments) != 1:
            raise ValueError("the winkler model is a specimen with one 'contact' segment")
        face = family.discretise(segments[0].curve, refinement["contact"])
        points = face.geometry(*face.collocation())[0]
        if np.ptp(points[:, 1]) > 1e-9 * np.ptp(points[:, 0]):
            raise ValueError("the winkler model needs a flat contact face (shape = 'flat')")
        order = np.argsort(points[:, 0])
        plane_modulus = material.E / (1.0 - material.nu**2)
        return WinklerFoundation(points[order, 0], plane_modulus / DEPTH, material, name=role)


@attrs.frozen
class NewtonThenLemke(Solver):
    """Semi-smooth Newton; Lemke's pivoting method where Newton does not converge."""

    first: Solver = attrs.field(factory=SemiSmoothNewton)
    second: Solver = attrs.field(factory=LemkeSolver)
    max_substeps: int = 0

    def solve_increment(self, problem, law, *, forces, loads, previous, start):
        try:
            return self.first.solve_increment(
                problem, law, forces=forces, loads=loads, previous=previous, start=start
            )
        except SolverConvergenceError:
            return self.second.solve_increment(
                problem, law, forces=forces, loads=loads, previous=previous, start=start
            )
