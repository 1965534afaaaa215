"""Worked examples of the extension points, shown in the how-to pages and run by the tests.

- :class:`WinklerFoundation`, a body model (a bed of independent springs);
- :class:`FallbackSolver`, a solver (one solver, then another if it fails);
- :class:`TrescaFriction`, a contact law (a shear bound independent of the pressure).
"""

from __future__ import annotations

import attrs
import numpy as np

from fretbem.body import Body, ContactFace, ContactResponse
from fretbem.contact.law import ContactLaw, LawEvaluation, PairState
from fretbem.material import Material
from fretbem.solvers.newton import Solver, SolverConvergenceError


@attrs.frozen(eq=False)
class WinklerFoundation(Body):
    """A bed of springs under a flat face: u = t / k at every node, independently.

    Attributes
    ----------
    x : ndarray
        Node abscissae of the face (on y = 0, outward normal +y), increasing.
    stiffness : float
        Spring stiffness k per unit area (MPa/mm), normal and tangential alike.
    material : Material
        Reported only (a Winkler bed has no elastic continuum).
    name : str
    """

    x: np.ndarray = attrs.field(converter=lambda v: np.asarray(v, float))
    stiffness: float
    material: Material = attrs.field(factory=lambda: Material(70000.0, 0.3))
    name: str = "foundation"
    _cache: dict = attrs.field(init=False, factory=dict, repr=False)

    @property
    def loading_block(self):
        return None  # held by its springs

    @property
    def dofs(self) -> int:
        return 2 * len(self.x)

    def contact_face(self, tag: str) -> ContactFace:
        if tag != "contact":
            raise KeyError(f"a Winkler foundation has only the face 'contact', not {tag!r}")
        n = len(self.x)
        points = np.column_stack([self.x, np.zeros(n)])
        return ContactFace(points, np.tile([0.0, 1.0], (n, 1)))

    def contact_response(self, tag: str) -> ContactResponse:
        if tag not in self._cache:
            n = len(self.contact_face(tag).points)
            # trapezoidal node weights: the face length each node carries
            weights = np.zeros(n)
            spacing = np.diff(self.x)
            weights[:-1] += spacing / 2
            weights[1:] += spacing / 2
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


@attrs.frozen
class FallbackSolver(Solver):
    """Try ``first``; if it does not converge, solve the same increment with ``second``."""

    first: Solver
    second: Solver
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


@attrs.frozen
class TrescaFriction(ContactLaw):
    """Unilateral contact with a shear bound g independent of the pressure (Tresca).

    F_n = p - max(0, p - r_n gap); on contact pairs F_t = q - proj[-g, g](q + r_t s).
    """

    bound: float

    def evaluate(self, p, q, gap, slip, r_n, r_t) -> LawEvaluation:
        contact = p - r_n * gap > 0
        trial = q + r_t * slip
        stick = contact & (np.abs(trial) < self.bound)
        sliding = contact & ~stick
        direction = np.sign(trial)
        f_n = np.where(contact, r_n * gap, p)
        f_t = np.where(stick, -r_t * slip, np.where(sliding, q - self.bound * direction, q))
        states = np.full(len(p), PairState.SEPARATED, dtype=int)
        states[stick], states[sliding] = PairState.STICK, PairState.SLIP
        return LawEvaluation(f_n, f_t, states, direction)

    def jacobian_rows(self, evaluation, normal_map, tangential_map, r_n, r_t):
        n, n_x = normal_map.shape
        rows = np.arange(n)
        states = evaluation.states
        separated, stick = states == PairState.SEPARATED, states == PairState.STICK
        jac = np.zeros((2 * n, n_x))
        jac[rows[separated], rows[separated]] = 1.0
        jac[rows[~separated]] = r_n * normal_map[~separated]
        jac[n + rows[stick]] = -r_t * tangential_map[stick]
        free = ~stick  # separated and slipping pairs: dF_t/dq = 1, nothing else
        jac[n + rows[free], n + rows[free]] = 1.0
        return jac
