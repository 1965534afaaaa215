"""An elastic body: boundary, material, discretisation, boundary conditions, linear solve.

The body assembles H and G once (lazily) and factorises its collocation system once per set
of contact segments, so repeated solves and load steps only do triangular solves.
"""

from __future__ import annotations

import time
from collections.abc import Mapping

import attrs
import numpy as np
import scipy.linalg as sla

from . import bases
from .basis import Basis, Refinement
from .conditions import Condition, Displacement, LoadingBlock, Traction, evaluate
from .geometry.boundary import Boundary
from .integration import Assembler, Collocation, IntegrationSettings, offsets
from .kernels import KelvinKernel
from .material import Material

#: kinds of each (function, component) coefficient pair
TRACTION, DISPLACEMENT, BLOCK, CONTACT = 0, 1, 2, 3


class RigidMotionError(ValueError):
    """The boundary conditions leave a rigid-body motion of a body undetermined."""


def _component_names(index: int) -> str:
    return "xy"[index]


@attrs.frozen(eq=False)
class Body:
    """A homogeneous elastic body described by its boundary.

    Attributes
    ----------
    boundary : Boundary
    material : Material
    conditions : tuple of Displacement, Traction or LoadingBlock
        Segments and components no condition names are traction free.
    basis : str or Basis subclass
        Name of an installed family (see ``fretbem bases``) or a class.
    refinement : mapping of tag to Refinement
        Per-tag discretisation; tags not listed get ``Refinement()``.
    name : str
    integration : IntegrationSettings
    """

    boundary: Boundary = attrs.field(validator=attrs.validators.instance_of(Boundary))
    material: Material = attrs.field(validator=attrs.validators.instance_of(Material))
    conditions: tuple[Condition, ...] = attrs.field(default=(), converter=tuple)
    basis: str | type[Basis] = "nurbs"
    refinement: Mapping[str, Refinement] = attrs.field(factory=dict, converter=dict)
    name: str = "body"
    integration: IntegrationSettings = attrs.field(factory=IntegrationSettings)
    _cache: dict = attrs.field(init=False, factory=dict, repr=False)

    def __attrs_post_init__(self) -> None:
        bases.get(self.basis)  # an unknown family is an error now, listing the installed ones
        for condition in self.conditions:
            if not isinstance(condition, (Displacement, Traction, LoadingBlock)):
                raise TypeError(f"body {self.name!r}: unknown boundary condition {condition!r}")
            self._indices(condition.tag, f"a {type(condition).__name__} condition")
        for tag in self.refinement:
            self._indices(tag, "a refinement")
        blocks = [c for c in self.conditions if isinstance(c, LoadingBlock)]
        if len(blocks) > 1:
            raise ValueError(f"body {self.name!r} has {len(blocks)} loading blocks; at most one")
        self._prescriptions()  # raises on conflicting conditions

    def _indices(self, tag: str, used_by: str) -> list[int]:
        try:
            return self.boundary.indices(tag)
        except KeyError as err:
            raise KeyError(
                f"body {self.name!r}: {used_by} refers to tag {tag!r}, but {err.args[0]}"
            ) from None

    # -- discretisation and matrices ------------------------------------------------------
    @property
    def family(self) -> type[Basis]:
        """The basis family class (resolved through the registry)."""
        return bases.get(self.basis)

    @property
    def segments(self) -> tuple[Basis, ...]:
        """The discretised segments, one Basis per boundary segment (computed once)."""
        if "segments" not in self._cache:
            family = self.family
            self._cache["segments"] = tuple(
                family.discretise(s.curve, self.refinement.get(s.tag, Refinement()))
                for s in self.boundary.segments
            )
        return self._cache["segments"]

    @property
    def offsets(self) -> np.ndarray:
        """First global function index of each segment, and the total at the end."""
        return offsets(self.segments)

    @property
    def n_functions(self) -> int:
        """Number of basis functions over the whole boundary."""
        return int(self.offsets[-1])

    @property
    def dofs(self) -> int:
        """Boundary unknowns of the discretised body: 2 coefficients per function."""
        return 2 * self.n_functions

    @property
    def collocation(self) -> Collocation:
        """Collocation points of every segment (computed once)."""
        if "collocation" not in self._cache:
            self._cache["collocation"] = Collocation.of(self.segments)
        return self._cache["collocation"]

    @property
    def timings(self) -> dict[str, float]:
        """Wall times (s) of the work done so far: assembly, factorisation."""
        return self._cache.setdefault("timings", {})

    def matrices(self) -> tuple[np.ndarray, np.ndarray]:
        """H and G (2N x 2N), assembled on first request and cached."""
        if "matrices" not in self._cache:
            start = time.perf_counter()
            assembler = Assembler(self.segments, KelvinKernel.of(self.material), self.integration)
            self._cache["matrices"] = assembler.assemble()
            self.timings["assembly"] = time.perf_counter() - start
        return self._cache["matrices"]

    def function_slice(self, segment: int) -> slice:
        """Global function indices of one segment."""
        return slice(int(self.offsets[segment]), int(self.offsets[segment + 1]))

    def resultant_weights(self) -> np.ndarray:
        """int phi_a dGamma for every function: tractions coefficients to resultant force."""
        if "resultant" not in self._cache:
            from .quadrature import QuadratureRule

            rule = QuadratureRule.gauss_legendre(8)
            out = np.zeros(self.n_functions)
            for k, basis in enumerate(self.segments):
                elements = np.repeat(np.arange(basis.n_elements), rule.points.size)
                local = np.tile(rule.points, basis.n_elements)
                _, _, jac, _ = basis.geometry(elements, local)
                values, _ = basis.shape_functions(elements, local)
                weights = jac * np.tile(rule.weights, basis.n_elements)
                np.add.at(
                    out, self.offsets[k] + basis.connectivity[elements], values * weights[:, None]
                )
            self._cache["resultant"] = out
        return self._cache["resultant"]

    # -- boundary conditions --------------------------------------------------------------
    def _prescriptions(self) -> dict[tuple[int, int], tuple[int, object]]:
        """(segment, component) -> (kind, value) for every prescribed component."""
        table: dict[tuple[int, int], tuple[int, object]] = {}
        for condition in self.conditions:
            for segment in self.boundary.indices(condition.tag):
                for comp in range(2):
                    if isinstance(condition, LoadingBlock):
                        entry = (BLOCK, condition.force[comp])
                    else:
                        value = (condition.x, condition.y)[comp]
                        if value is None:
                            continue
                        kind = DISPLACEMENT if isinstance(condition, Displacement) else TRACTION
                        entry = (kind, value)
                    if (segment, comp) in table:
                        raise ValueError(
                            f"body {self.name!r}: segment {segment} ({condition.tag!r}) has two "
                            f"conditions on its {_component_names(comp)} component; keep one"
                        )
                    table[(segment, comp)] = entry
        return table

    def layout(self, contact_tags: tuple[str, ...] = ()) -> tuple[np.ndarray, np.ndarray]:
        """Kind (TRACTION, DISPLACEMENT, BLOCK, CONTACT) and known coefficient of every dof.

        Computed once per set of contact tags (the rigid-motion check and the factorised
        system both need it); the arrays are read-only.
        """
        key = ("layout", tuple(sorted(contact_tags)))
        if key not in self._cache:
            kinds, known = self._layout(contact_tags)
            kinds.setflags(write=False)
            known.setflags(write=False)
            self._cache[key] = (kinds, known)
        return self._cache[key]

    def _layout(self, contact_tags: tuple[str, ...]) -> tuple[np.ndarray, np.ndarray]:
        kinds = np.full((self.n_functions, 2), TRACTION)
        known = np.zeros((self.n_functions, 2))
        contact_segments = {k for tag in contact_tags for k in self._indices(tag, "a contact")}
        table = self._prescriptions()
        for k, basis in enumerate(self.segments):
            sl = self.function_slice(k)
            if k in contact_segments:
                if any((k, c) in table for c in range(2)):
                    raise ValueError(
                        f"body {self.name!r}: segment {k} ({self.boundary.segments[k].tag!r}) "
                        "is a contact segment and also has a boundary condition; remove one"
                    )
                kinds[sl] = CONTACT
                continue
            points = None
            for comp in range(2):
                kind, value = table.get((k, comp), (TRACTION, 0.0))
                kinds[sl, comp] = kind
                if kind == BLOCK:
                    continue
                if callable(value):
                    if points is None:
                        elements, local = basis.collocation()
                        points = basis.geometry(elements, local)[0]
                    values = evaluate(value, points)
                    known[sl, comp] = np.linalg.solve(basis.collocation_matrix(), values)
                else:
                    known[sl, comp] = float(value)  # partition of unity: constant coefficients
        return kinds, known

    @property
    def loading_block(self) -> LoadingBlock | None:
        """The body's loading block condition, if any."""
        return next((c for c in self.conditions if isinstance(c, LoadingBlock)), None)

    def free_rigid_motions(
        self, contact_tags: tuple[str, ...] = (), *, block_translates: bool = True
    ) -> list[str]:
        """Rigid motions (x/y translation, rotation) the prescribed displacements leave free.

        A loading block stops rotation; its translation is free under force control
        (``block_translates``), which contact or the prescribed force must then determine.
        """
        kinds, _ = self.layout(contact_tags)
        x, y = self.collocation.points.T
        rows = []
        for comp in range(2):
            fixed = kinds[:, comp] == DISPLACEMENT
            unit = np.zeros((fixed.sum(), 3))
            unit[:, comp] = 1.0
            unit[:, 2] = -y[fixed] if comp == 0 else x[fixed]
            rows.append(unit)
            block = kinds[:, comp] == BLOCK
            if block.any():
                arm = -(y[block] - y[block].mean()) if comp == 0 else x[block] - x[block].mean()
                rows.append(np.column_stack([np.zeros((block.sum(), 2)), arm]))
                if not block_translates:
                    rows.append(np.eye(3)[comp][None])
        matrix = np.concatenate(rows)
        scale = max(np.ptp(self.collocation.points, axis=0).max(), 1e-300)
        matrix[:, 2] /= scale
        _, singular, vt = np.linalg.svd(matrix, full_matrices=True)
        rank = int(np.sum(singular > 1e-8 * max(singular.max(initial=0.0), 1.0)))
        free = []
        for vector in vt[rank:]:
            names = ["x translation", "y translation", "rotation"]
            free.append(names[int(np.argmax(np.abs(vector)))])
        return sorted(set(free))

    def check_supported(self, contact_tags: tuple[str, ...] = (), *, in_contact=False) -> None:
        """Raise RigidMotionError naming the free motions and how to remove them."""
        free = self.free_rigid_motions(contact_tags, block_translates=not in_contact)
        if free:
            raise RigidMotionError(
                f"body {self.name!r}: its boundary conditions leave rigid motion free "
                f"({', '.join(free)}), so the problem has no unique solution; prescribe a "
                "displacement on some segment (e.g. Displacement('bottom')) or, for a body "
                "pressed into contact, load it through a LoadingBlock"
            )

    def system(self, contact_tags: tuple[str, ...] = ()) -> BodySystem:
        """The factorised collocation system, with the given segments left to contact."""
        key = ("system", tuple(sorted(contact_tags)))
        if key not in self._cache:
            self._cache[key] = BodySystem(self, tuple(contact_tags))
        return self._cache[key]

    def solve(self) -> BodySolution:
        """Solve the body on its own (no contact): a linear elastostatic problem."""
        self.check_supported()
        system = self.system()
        delta = np.zeros(2)
        if system.block_dofs.size:
            r0, stiffness = system.resultant_map()
            delta = np.linalg.solve(stiffness, np.asarray(self.loading_block.force) - r0)
        return system.solution(delta, np.zeros(0))


class BodySystem:
    """H u = G t with prescribed data moved right, factorised once.

    Unknowns z: u where traction is known (and on contact segments), t where displacement is
    known (and on the loading block). The loading-block displacement delta and the contact
    traction coefficients stay as parameters: z = z0 + Z_delta delta + Z_contact t_contact.
    """

    def __init__(self, body: Body, contact_tags: tuple[str, ...]):
        self.body = body
        h, g = body.matrices()
        start = time.perf_counter()
        kinds, known = body.layout(contact_tags)
        self.kinds, self.known = kinds.ravel(), known.ravel()
        solves_u = (self.kinds == TRACTION) | (self.kinds == CONTACT)
        self.solves_u = solves_u
        matrix = np.where(solves_u[None, :], h, -g)
        rhs = -h[:, self.kinds == DISPLACEMENT] @ self.known[self.kinds == DISPLACEMENT]
        rhs += g[:, self.kinds == TRACTION] @ self.known[self.kinds == TRACTION]
        self.block_dofs = np.flatnonzero(self.kinds == BLOCK)
        block_columns = np.zeros((len(self.kinds), 2))
        block_columns[self.block_dofs, self.block_dofs % 2] = 1.0
        self.contact_dofs = np.flatnonzero(self.kinds == CONTACT)
        parameters = np.column_stack([rhs, -h @ block_columns, g[:, self.contact_dofs]])
        self.factor = sla.lu_factor(matrix, check_finite=False)
        response = sla.lu_solve(self.factor, parameters, check_finite=False)
        if not np.all(np.isfinite(response)):
            raise RigidMotionError(
                f"body {body.name!r}: the collocation system is singular; check that the "
                "boundary conditions fix the rigid motions"
            )
        self.base = response[:, 0]
        self.block_response = response[:, 1:3]
        self.contact_response = response[:, 3:]
        body.timings["factorisation"] = time.perf_counter() - start

    def unknowns(self, delta: np.ndarray, contact_tractions: np.ndarray) -> np.ndarray:
        """z = z0 + Z_delta delta + Z_contact t_contact."""
        return self.base + self.block_response @ delta + self.contact_response @ contact_tractions

    def block_resultant(self, z: np.ndarray) -> np.ndarray:
        """Resultant force (2, ...) of the loading block's tractions in unknown vector(s) z."""
        weights = np.repeat(self.body.resultant_weights(), 2)[self.block_dofs]
        select = np.zeros((2, len(self.block_dofs)))
        select[self.block_dofs % 2, np.arange(len(self.block_dofs))] = weights
        return select @ z[self.block_dofs]

    def resultant_map(self) -> tuple[np.ndarray, np.ndarray]:
        """Block resultant force as r0 + K delta (with zero contact traction)."""
        return self.block_resultant(self.base), self.block_resultant(self.block_response)

    def solution(self, delta: np.ndarray, contact_tractions: np.ndarray) -> BodySolution:
        """Full displacement and traction coefficients for given block and contact data."""
        z = self.unknowns(delta, contact_tractions)
        u = np.where(self.solves_u, z, self.known)
        t = np.where(self.solves_u, self.known, z)
        u[self.block_dofs] = delta[self.block_dofs % 2]
        t[self.contact_dofs] = contact_tractions
        return BodySolution(self.body, u.reshape(-1, 2), t.reshape(-1, 2), np.asarray(delta))


@attrs.frozen(eq=False)
class BodySolution:
    """Displacement and traction coefficients of a solved body.

    Attributes
    ----------
    body : Body
    displacement_coefficients, traction_coefficients : ndarray, shape (N, 2)
    block_displacement : ndarray, shape (2,)
    """

    body: Body
    displacement_coefficients: np.ndarray
    traction_coefficients: np.ndarray
    block_displacement: np.ndarray

    def _field(self, coefficients, segment: int, params) -> np.ndarray:
        basis = self.body.segments[segment]
        return basis.evaluation_matrix(params) @ coefficients[self.body.function_slice(segment)]

    def displacement(self, segment: int, params) -> np.ndarray:
        """Displacement (m, 2) at curve parameters of one segment."""
        return self._field(self.displacement_coefficients, segment, params)

    def traction(self, segment: int, params) -> np.ndarray:
        """Traction (m, 2) at curve parameters of one segment."""
        return self._field(self.traction_coefficients, segment, params)

    def points(self, segment: int, params) -> np.ndarray:
        """Positions (m, 2) of the discretised geometry at curve parameters."""
        basis = self.body.segments[segment]
        return basis.geometry(*basis.to_local(params))[0]
