"""The boundary element body: NURBS boundary, any basis family, conditions, linear solve.

The body assembles H and G once (lazily) and factorises its collocation system once per set
of contact segments, so repeated solves and load steps only do triangular solves; its
contact response is that system condensed onto the contact face's node tractions.
"""

from __future__ import annotations

import time
import weakref
from collections.abc import Mapping, Sequence

import attrs
import numpy as np

from fretbem import registry as bases
from fretbem.basis import Basis, Refinement
from fretbem.body import Body, ContactFace, ContactResponse, RigidMotionError
from fretbem.conditions import Condition, LoadingBlock
from fretbem.geometry.boundary import Boundary
from fretbem.geometry.nurbs import NurbsCurve
from fretbem.material import Material
from fretbem.numerics.quadrature import QuadratureRule
from fretbem.numerics.scatter import added_at

from . import assembly, image_matrices, images
from . import layout as bem_layout
from .integration import Assembler, Collocation, IntegrationSettings, offsets
from .kernels import KelvinKernel
from .layout import BLOCK, DISPLACEMENT, Layout
from .stresses import StressSettings, somigliana_operator
from .system import BodySolution, BodySystem, contact_response, face_rows, face_values_matrix

# BodySolution and BodySystem (fretbem.bem.system) are importable from here too
__all__ = ["BemBody", "discretised"]


def discretised(family: type[Basis], segment, refinement: Refinement) -> Basis:
    """``segment.discretised(family, refinement)`` (the segment keeps its discretisations;
    a point image of a segment discretised before takes that one reflected:
    :func:`fretbem.bem.images.discretise`)."""
    return segment.discretised(family, refinement, images.discretise)


#: the refinement of a segment no tag names (one instance: equal to every ``Refinement()``)
_DEFAULT_REFINEMENT = Refinement()

#: int phi_a dGamma per discretised segment (weak keys: shared by bodies that share it)
_WEIGHTS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
#: each discretised segment's functions sampled on 8-point Gauss rules per element (weak
#: keys): the resultant and the moment weights integrate them, and the adaptive mode's levels
#: keep every segment but the contact face, so a level samples only its new face
_SAMPLES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _segment_samples(basis: Basis) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Function indices (points, p+1), points (points, 2), values (points, p+1) and
    quadrature weights with the Jacobian (points,) of one segment's 8-point Gauss rules
    (a point image's: its points negated, :func:`fretbem.bem.images.source`)."""
    image = images.source(basis) if basis not in _SAMPLES else None
    if image in _SAMPLES:
        functions, points, values, weights = _SAMPLES[image]
        points = -points + 0.0  # its zeros +0, as the image's own evaluation
        points.flags.writeable = False
        _SAMPLES[basis] = (functions, points, values, weights)
    if basis not in _SAMPLES:
        rule = QuadratureRule.gauss_legendre(8)
        elements = np.repeat(np.arange(basis.n_elements), rule.points.size)
        local = np.tile(rule.points, basis.n_elements)
        m = basis.map(elements, local)  # one basis evaluation for geometry and values
        weights = m.jacobians * np.tile(rule.weights, basis.n_elements)
        samples = (basis.connectivity[elements], m.points, m.values, weights)
        for array in samples:
            array.flags.writeable = False
        _SAMPLES[basis] = samples
    return _SAMPLES[basis]


def _segment_weights(basis: Basis) -> np.ndarray:
    """int phi_a dGamma for the functions of one discretised segment (8-point Gauss)."""
    if basis not in _WEIGHTS:
        functions, _, values, weights = _segment_samples(basis)
        out = added_at(basis.n_functions, functions, values * weights[:, None])
        out.flags.writeable = False
        _WEIGHTS[basis] = out
    return _WEIGHTS[basis]


@attrs.frozen(eq=False)
class BemBody(Body):
    """A homogeneous elastic body described by its boundary: the boundary element model.

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
        bem_layout.check_conditions(self)

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
                discretised(family, s, self.refinement.get(s.tag, _DEFAULT_REFINEMENT))
                for s in self.boundary.segments
            )
        return self._cache["segments"]

    @property
    def offsets(self) -> np.ndarray:
        """First global function index of each segment, and the total at the end (computed
        once: the contact response asks for it per segment, 22 times per call)."""
        if "offsets" not in self._cache:
            first = offsets(self.segments)
            first.flags.writeable = False
            self._cache["offsets"] = first
        return self._cache["offsets"]

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
            self._cache["matrices"] = self._assembled()
        return self._cache["matrices"]

    def system_matrices(self, g_free: tuple[int, ...] = ()) -> tuple[np.ndarray, np.ndarray]:
        """H and G for a solve that never reads G's columns of the segments ``g_free``
        (:func:`fretbem.bem.system.g_free_segments`): the cached :meth:`matrices` if
        assembled, else H and G with those columns left at 0 by the numpy loops, cached
        apart until :meth:`release_matrices` (:meth:`matrices` never returns them)."""
        key = ("system matrices", tuple(g_free))
        if "matrices" in self._cache or not g_free:
            return self.matrices()
        if key not in self._cache:
            self._cache[key] = self._assembled(key[1])
        return self._cache[key]

    def permuted_source(self, g_free: tuple[int, ...] = ()):
        """(kept matrices, column map, row map) when this body's H and G, not in memory yet,
        would be the last assembled body's permuted, without forming them; else None
        (:func:`~fretbem.bem.image_matrices.permutation`)."""
        if "matrices" in self._cache or ("system matrices", tuple(g_free)) in self._cache:
            return None
        return image_matrices.permutation(*self._image_key(g_free))

    def _image_key(self, g_free: tuple[int, ...]) -> tuple:
        """What tells whether this body's H and G are a kept body's permuted: segments,
        first dofs and rows, the kernel's constants, the settings, ``g_free``."""
        kernel = KelvinKernel.of(self.material)
        key = (kernel.shear_modulus, kernel.effective_nu)
        first_dofs = 2 * self.offsets
        counts = np.bincount(self.collocation.segment, minlength=len(self.segments))
        first_rows = 2 * np.concatenate([[0], np.cumsum(counts)])
        return (self.segments, first_dofs, first_rows, key, self.integration, g_free)

    def _assembled(self, g_free: tuple[int, ...] = ()) -> tuple[np.ndarray, np.ndarray]:
        """H and G: the last body's permuted if this body is its exact point image
        (:mod:`fretbem.bem.image_matrices`), else assembled (and kept for a point image)."""
        start = time.perf_counter()
        where = self._image_key(g_free)
        matrices = image_matrices.derived(*where)
        if matrices is None:
            kernel = KelvinKernel.of(self.material)
            matrices = Assembler(self.segments, kernel, self.integration).assemble(g_free)
            image_matrices.keep(*where, *matrices)
        else:
            self.note_permuted()
        self.timings["assembly"] = time.perf_counter() - start
        return matrices

    def note_permuted(self) -> None:
        """Record, as an assembly would, that this body's H and G are the last body's
        permuted (the last body's blocks lent for this one are not needed any longer)."""
        if self.n_functions <= assembly.LEND_MAX_FUNCTIONS:
            assembly.BLOCKS.assembled(
                self.segments, lent=self.n_functions > assembly.REUSE_MAX_FUNCTIONS
            )

    def function_slice(self, segment: int) -> slice:
        """Global function indices of one segment."""
        return slice(int(self.offsets[segment]), int(self.offsets[segment + 1]))

    def resultant_weights(self, segments: Sequence[int] | None = None) -> np.ndarray:
        """int phi_a dGamma for every function: tractions coefficients to resultant force.

        ``segments``: integrate those segments' functions only (0 on the others), for a
        caller that reads no other (the contact response: the face and the block)."""
        if segments is not None:
            out = np.zeros(self.n_functions)
            for k in segments:
                out[self.function_slice(k)] = _segment_weights(self.segments[k])
            return out
        if "resultant" not in self._cache:
            self._cache["resultant"] = np.concatenate(
                [_segment_weights(basis) for basis in self.segments]
            )
        return self._cache["resultant"]

    def moment_weights(self, centre, segments: Sequence[int] | None = None) -> np.ndarray:
        """int phi_a (x - cx) dGamma and int phi_a (y - cy) dGamma for every function (N, 2):
        traction coefficients to their moment about ``centre`` (``segments``: those
        segments' functions only, 0 on the others)."""
        centre = np.asarray(centre, float)
        out = np.zeros((self.n_functions, 2))
        for k, basis in enumerate(self.segments):
            if segments is not None and k not in segments:
                continue
            functions, points, values, weights = _segment_samples(basis)
            for j in range(2):
                np.add.at(
                    out[:, j],
                    self.offsets[k] + functions,
                    values * ((points[:, j] - centre[j]) * weights)[:, None],
                )
        return out

    def rotation_coefficients(self, centre) -> np.ndarray:
        """Displacement coefficients (N, 2) of a unit rigid rotation about ``centre``, each
        segment's interpolating the field at its collocation points."""
        centre = np.asarray(centre, float)
        colloc = self.collocation
        out = np.zeros((self.n_functions, 2))
        for k, basis in enumerate(self.segments):
            arm = colloc.points[colloc.segment == k] - centre
            values = np.column_stack([-arm[:, 1], arm[:, 0]])
            out[self.function_slice(k)] = np.linalg.solve(basis.collocation_matrix(), values)
        return out

    # -- boundary conditions --------------------------------------------------------------
    def layout(self, contact_tags: tuple[str, ...] = ()) -> Layout:
        """Kinds and known coefficients of every dof, computed once per set of contact tags.

        The rigid-motion check and the factorised system both need it; arrays are read-only.
        """
        key = ("layout", tuple(sorted(contact_tags)))
        if key not in self._cache:
            self._cache[key] = bem_layout.layout(self, contact_tags)
        return self._cache[key]

    @property
    def load_names(self) -> tuple[str, ...]:
        """Named history loads scaling the body's tractions (``Traction(..., load=name)``)."""
        return bem_layout.load_names(self)

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
        kinds = self.layout(contact_tags).kinds
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
        return list(_free_motions(matrix))

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
            if contact_tags:
                # the contact path needs neither H nor G again (every later solve is a
                # product with the response): 2 N^2 floats, 512 MB at 1921 pairs; a later
                # system for other contact faces re-assembles them
                self.release_matrices()
        return self._cache[key]

    def release_matrices(self) -> None:
        """Forget H and G (assembled again if asked for): they are the body's largest arrays."""
        self._cache.pop("matrices", None)
        for key in [k for k in self._cache if isinstance(k, tuple) and k[0] == "system matrices"]:
            del self._cache[key]

    def solve(self, loads: Mapping[str, float] | None = None) -> BodySolution:
        """Solve the body on its own (no contact): a linear elastostatic problem.

        ``loads`` gives the amplitude of each named load (``load_names``; missing ones 0).
        """
        self.check_supported()
        system = self.system()
        beta = self._amplitudes(loads or {})
        delta = np.zeros(2)
        if system.block_dofs.size:
            r0, stiffness = system.resultant_map()
            r0 = r0 + system.block_resultant(system.load_response) @ beta
            delta = np.linalg.solve(stiffness, np.asarray(self.loading_block.force) - r0)
        return system.solution(delta, np.zeros(0), beta)

    def _amplitudes(self, loads: Mapping[str, float]) -> np.ndarray:
        return np.array([float(loads.get(name, 0.0)) for name in self.load_names])

    # -- the Body contract ------------------------------------------------------------------
    @property
    def segment_tags(self) -> tuple[str, ...]:
        """The tag of each boundary segment."""
        return self.boundary.tags

    def face_curve(self, tag: str) -> NurbsCurve:
        """The exact curve of the one segment tagged ``tag``, before refinement."""
        index, _ = self.face_segment(tag)
        return self.boundary.segments[index].curve

    def face_refinement(self, tag: str) -> Refinement:
        """The refinement of the segment ``tag`` (the default one if none is given)."""
        return self.refinement.get(tag, _DEFAULT_REFINEMENT)

    def with_face_refinement(self, tag: str, refinement: Refinement) -> BemBody:
        """A new body with the segment ``tag`` at ``refinement`` (other segments shared)."""
        return attrs.evolve(self, refinement={**self.refinement, tag: refinement})

    def stress_operator(self, points: np.ndarray, settings: StressSettings | None = None):
        """Somigliana's identity at interior ``points``, as a matrix over the boundary data."""
        material = self.material
        return somigliana_operator(
            self.segments,
            points,
            shear_modulus=material.shear_modulus,
            nu=material.nu,
            plane_stress=material.plane_stress,
            settings=settings,
        )

    def describe(self) -> dict:
        """Model, basis family and the contact-face degree for the run summary."""
        return {"model": "bem", "basis": self.family.name, "degree": self.segments[0].degree}

    def contact_face(self, tag: str) -> ContactFace:
        """Collocation points and normals of the segments tagged ``tag``, in boundary order."""
        rows, _ = face_rows(self, tag)
        colloc = self.collocation
        return ContactFace(colloc.points[rows], colloc.normals[rows])

    def contact_response(self, tag: str) -> ContactResponse:
        """Displacement at the face's collocation points per unit node traction (cached).

        Raises RigidMotionError if the body is not held with the face in contact.
        """
        key = ("response", tag)
        if key not in self._cache:
            self.check_supported((tag,), in_contact=True)
            self._cache[key] = contact_response(self, tag)
        return self._cache[key]

    def solution(
        self,
        tag: str,
        tractions: np.ndarray,
        block: np.ndarray,
        loads: Mapping[str, float],
        rotation: float = 0.0,
    ) -> BodySolution:
        """Every boundary coefficient for node tractions (n, 2) on the face ``tag``, block
        delta, loads and the block's rotation (rad, about the response's rotation centre:
        a rigid rotation of the whole body, which leaves the tractions unchanged)."""
        inverse_values = np.linalg.solve(face_values_matrix(self, tag), np.asarray(tractions))
        solution = self.system((tag,)).solution(
            np.asarray(block, float), inverse_values.ravel(), self._amplitudes(loads)
        )
        if not rotation:
            return solution
        centre = self.contact_response(tag).rotation.centre
        moved = solution.displacement_coefficients + rotation * self.rotation_coefficients(centre)
        return attrs.evolve(solution, displacement_coefficients=moved)


#: the free motions of the last few constraint matrices (:meth:`BemBody.free_rigid_motions`):
#: bodies re-meshed on a contact face (the adaptive levels) keep the rows of their held
#: segments, so each level asks again about the same matrix
_FREE_MOTIONS: dict = {}


def _free_motions(matrix: np.ndarray) -> tuple[str, ...]:
    """The rigid motions (sorted names) in the null space of the scaled constraint rows."""
    key = (matrix.shape, matrix.tobytes())
    if key not in _FREE_MOTIONS:
        _, singular, vt = np.linalg.svd(matrix, full_matrices=True)
        rank = int(np.sum(singular > 1e-8 * max(singular.max(initial=0.0), 1.0)))
        free = []
        for vector in vt[rank:]:
            names = ["x translation", "y translation", "rotation"]
            free.append(names[int(np.argmax(np.abs(vector)))])
        if len(_FREE_MOTIONS) >= 16:
            _FREE_MOTIONS.pop(next(iter(_FREE_MOTIONS)))
        _FREE_MOTIONS[key] = tuple(sorted(set(free)))
    return _FREE_MOTIONS[key]
