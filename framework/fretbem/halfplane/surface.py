"""A discretised half-plane surface: nodes, and displacement as an affine map of node tractions.

The face is any curve running monotonically in x (a flat line, or the profile of a pad):
its points give the contact geometry (and so the initial gap), while the elasticity is that
of the half-plane below (or above) the straight surface the profile is drawn over, the usual
half-plane idealisation of a non-conformal contact (Johnson 1985, sec. 4.1).
"""

from __future__ import annotations

import weakref

import attrs
import numpy as np
import scipy.linalg as sla

from fretbem.basis import Basis
from fretbem.bem import images
from fretbem.body import interleaved_map
from fretbem.material import Material
from fretbem.numerics.scatter import added_at
from fretbem.validators import positive

from .influence import (
    DEFAULT_DATUM,
    FlamantCompliance,
    check_face,
    gauss_samples,
    rule_map,
    rule_map_with,
    side_sign,
    surface_integrals,
)
from .joined import JoinedFace
from .shared import node_integrals
from .symmetry import mirrored, mirrored_rows


@attrs.frozen(eq=False)
class HalfPlaneSurface:
    """The surface operator of one half-plane on its discretised contact face.

    Attributes
    ----------
    face : Basis or JoinedFace
        The discretised face (one segment, or several joined); its collocation points are
        the nodes where traction and displacement are given. Traction is interpolated by the
        shape functions.
    material : Material
    side : str
        "lower" for a body occupying y < surface (its outward normal +y), "upper" for y >
        surface (outward normal -y).
    datum : float
        Distance d0 (> 0, mm) from a line load at which its ln r displacement is zero (10 mm by
        default). Only a rigid translation of each body depends on it, never the contact
        tractions.
    bulk_origin : float
        x at which the bulk-stress displacement u_x = eps (x - bulk_origin) is zero.
    shared_as : tuple or None
        (family name, curves, refinement) the face was discretised from: a face of another
        surface with the same projection then shares its influence integrals
        (:mod:`fretbem.halfplane.shared`); None computes them alone.
    """

    face: Basis | JoinedFace = attrs.field(
        validator=attrs.validators.instance_of((Basis, JoinedFace))
    )
    material: Material = attrs.field(validator=attrs.validators.instance_of(Material))
    side: str = attrs.field(default="lower")
    datum: float = attrs.field(default=DEFAULT_DATUM, converter=float, validator=positive)
    bulk_origin: float = attrs.field(default=0.0, converter=float)
    shared_as: tuple | None = attrs.field(default=None, kw_only=True)
    _cache: dict = attrs.field(init=False, factory=dict, repr=False)

    def __attrs_post_init__(self) -> None:
        side_sign(self.side)
        if self.shared_as is None:
            check_face(self.face, self.gauss_samples)
        else:  # joined now: a twin made later finds this face (and that it passed the check)
            self._cache["shared"] = node_integrals(
                *self.shared_as, self.side, self.datum, self.points[:, 0],
                check=lambda: check_face(self.face, self.gauss_samples),
            )  # fmt: skip

    @property
    def compliance(self) -> FlamantCompliance:
        """The line-load constants A, B of the material (formed once)."""
        if "compliance" not in self._cache:
            self._cache["compliance"] = FlamantCompliance.of(self.material)
        return self._cache["compliance"]

    @property
    def points(self) -> np.ndarray:
        """Node positions (n, 2): the face's collocation points."""
        if "points" not in self._cache:
            nodes = _image_nodes(self.face)
            if nodes is None:
                elements, local = self._collocation
                if "rule_map" not in self._cache and self._needs_rules:
                    # the rule map is wanted anyway: the nodes mapped in the same call
                    rules, mapped = rule_map_with(self.face, elements, local)
                    self._cache["rule_map"] = rules
                else:
                    mapped = self.face.map(elements, local)
                nodes = (mapped.points, elements, mapped.values)
                if isinstance(self.face, Basis):
                    _NODES[self.face] = nodes
            points, elements, values = nodes
            points.setflags(write=False)
            self._cache["points"] = points
            if _plain_collocation(self.face):  # E is these shape values, scattered
                self._cache["node_values"] = (elements, values)
        return self._cache["points"]

    @property
    def _collocation(self) -> tuple[np.ndarray, np.ndarray]:
        """The face's ``collocation()`` (element, local coordinate of each node), found once:
        the nodes' map and the node integrals both read it."""
        if "collocation" not in self._cache:
            self._cache["collocation"] = self.face.collocation()
        return self._cache["collocation"]

    @property
    def normals(self) -> np.ndarray:
        """Outward unit normals (n, 2) of the half-plane: (0, 1) below, (0, -1) above
        (formed once, read-only: the contact pair asks for the face several times)."""
        if "normals" not in self._cache:
            normals = np.zeros((len(self.points), 2))
            normals[:, 1] = side_sign(self.side)
            normals.setflags(write=False)
            self._cache["normals"] = normals
        return self._cache["normals"]

    @property
    def collocation_matrix(self) -> np.ndarray:
        """E: traction coefficients to node values (computed once)."""
        if "collocation_matrix" not in self._cache:
            self.points  # noqa: B018 - maps the nodes, whose shape values E holds
            if "node_values" in self._cache:
                # Basis.collocation_matrix's numbers: the shape functions at the same nodes
                # (evaluated once, for the points), scattered into their columns
                elements, values = self._cache.pop("node_values")
                rows = np.arange(len(elements))[:, None]
                matrix = added_at((len(elements), self.face.n_functions),
                                  (rows, self.face.connectivity[elements]), values)  # fmt: skip
            else:
                matrix = self.face.collocation_matrix()
            matrix.setflags(write=False)
            self._cache["collocation_matrix"] = matrix
        return self._cache["collocation_matrix"]

    @property
    def gauss_samples(self):
        """The face at every element's Gauss points (:func:`~.influence.gauss_samples`),
        computed once: the face check, the force and the moment integrals share them."""
        if "gauss_samples" not in self._cache:
            self._cache["gauss_samples"] = gauss_samples(self.face, self._rule_map)
        return self._cache["gauss_samples"]

    @property
    def _rule_map(self):
        """The face mapped once at the points of both its own integrals and the influence
        integrals (:func:`~.influence.rule_map`), kept: the Gauss samples are its rows, and
        the node integrals map no point again (a surface computing them needs the samples
        too: the face check, the force and moment weights)."""
        if "rule_map" not in self._cache:
            if "points" not in self._cache and self._needs_rules:
                self.points  # noqa: B018 - maps the nodes and the rule points in one call
            if "rule_map" not in self._cache:  # the nodes were known (a point image's)
                self._cache["rule_map"] = rule_map(self.face)
        return self._cache["rule_map"]

    @property
    def _needs_rules(self) -> bool:
        """Whether this surface will map its rule points whatever happens: a face that
        checks itself alone (no sharing), or an upper one (a pad, whose block's moment
        integrals read the Gauss samples). A lower twin of a face already checked may never
        need them: its nodes are then mapped alone."""
        return self.shared_as is None or self.side == "upper"

    def per_node_value(self, per_coefficient: np.ndarray) -> np.ndarray:
        """Rows of ``per_coefficient`` (m, N) taken through E^-1: per unit node value (E's
        band form found once)."""
        if "bands" not in self._cache:
            self._cache["bands"] = _bands(self.collocation_matrix)
        return _solve_transposed(self.collocation_matrix, self._cache["bands"], per_coefficient)

    def coefficient_map(self, x) -> np.ndarray:
        """Displacement (m, 2, 2N) at surface abscissae ``x`` per traction coefficient.

        Column 2 b + j: unit coefficient of traction component j on shape function b.
        """
        integrals = surface_integrals(self.face, x, self.datum, mapped=self._cache.get("rule_map"))
        return self._displacement_map(integrals.log, integrals.sign)

    def _blocks(self, log: np.ndarray, sign: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(A, B) (m, N) of the map ``[[A, B], [-B, A]]`` from the ln and sign integrals."""
        c, sigma = self.compliance, side_sign(self.side)
        return -c.log * log, sigma * c.jump * sign

    def _displacement_map(self, log: np.ndarray, sign: np.ndarray) -> np.ndarray:
        """(m, 2, 2N) from the ln and sign integrals (m, N) of N functions or node values."""
        return interleaved_map(*self._blocks(log, sign))

    @property
    def traction_blocks(self) -> tuple[np.ndarray, np.ndarray]:
        """(A, B) (n, n): ``traction_map`` is ``[[A, B], [-B, A]]`` per node pair."""
        if "traction_blocks" not in self._cache:
            x = self.points[:, 0]

            def compute() -> np.ndarray:  # at the nodes' own (element, local coordinate)
                at = self._collocation
                half = mirrored_rows(self.face, x, self._rule_map)
                if half is None:
                    return self._node_integrals(x, at)
                # a symmetric face: its first half's rows, the rest mirrored
                first = self._node_integrals(x[:half], (at[0][:half], at[1][:half]))
                return mirrored(first, x.size)

            both = compute() if self.shared_as is None else self._cache["shared"].get(compute)
            blocks = self._blocks(both[: x.size], both[x.size :])
            for block in blocks:
                block.setflags(write=False)
            self._cache["traction_blocks"] = blocks
        return self._cache["traction_blocks"]

    @property
    def traction_map(self) -> np.ndarray:
        """Displacement (n, 2, 2n) at the nodes per unit node traction (column 2 a + j)."""
        if "traction_map" not in self._cache:
            self._cache["traction_map"] = interleaved_map(*self.traction_blocks)
            self._cache["traction_map"].setflags(write=False)
        return self._cache["traction_map"]

    def node_map(self, x) -> np.ndarray:
        """Displacement (m, 2, 2n) at surface abscissae ``x`` per unit node traction."""
        both = self._node_integrals(x)
        m = both.shape[0] // 2
        return self._displacement_map(both[:m], both[m:])

    def _node_integrals(self, x, at=None) -> np.ndarray:
        """The ln integrals over the rows of the sign integrals (2 m, n) at abscissae ``x``,
        per unit node value (``at``: the points' (element, local coordinate) on the face,
        if they are its own)."""
        # the face's own nodes (``at``): mapped with the Gauss samples (once for both)
        mapped = self._rule_map if at is not None else self._cache.get("rule_map")
        integrals = surface_integrals(self.face, x, self.datum, at, mapped)
        # per node value = per coefficient @ E^-1 (coefficients = E^-1 values): the four
        # blocks of the map are the ln and sign integrals times constants, so two solves
        return self.per_node_value(np.concatenate([integrals.log, integrals.sign]))

    def _force_weights(self) -> np.ndarray:
        """int phi_a |dx| per unit node value (a twin's, reversed, where shared)."""

        def compute() -> np.ndarray:
            # int phi_b |dx| per coefficient, then per node value through E^-1
            integrals = _shape_integrals(self.face, self.gauss_samples)
            return self.per_node_value(integrals[None])[0]

        if "shared" not in self._cache:
            return compute()
        return self._cache["shared"].force_weights(compute)

    def bulk_displacement(self, x) -> np.ndarray:
        """Surface displacement (m, 2) per unit far-field stress sigma_xx (the "bulk" load).

        A uniform sigma_xx leaves the straight surface traction free; Hooke's law gives
        u_x = eps (x - bulk_origin) with eps = (1 - nu^2) / E (plane strain) or 1 / E (plane
        stress), and u_y = 0 on the surface.
        """
        x = np.asarray(x, dtype=float)
        out = np.zeros((*x.shape, 2))
        out[..., 0] = self.compliance.bulk_strain(self.material) * (x - self.bulk_origin)
        return out

    def contact_force(self) -> np.ndarray:
        """Resultant force (2, 2n) of the face tractions per unit node traction."""
        weights = self._force_weights()
        n = len(weights)
        out = np.zeros((2, n, 2))
        out[0, :, 0] = weights
        out[1, :, 1] = weights
        return out.reshape(2, 2 * n)


#: each single-segment face's nodes as mapped (points, elements, shape values), while the
#: face lives: the face discretised as its point image (:func:`fretbem.bem.images.discretise`)
#: takes them with the points negated
_NODES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _image_nodes(face) -> tuple | None:
    """(points, elements, shape values) at the nodes of ``face`` when it was discretised as
    the point image of a face whose nodes are known: the points negated, the rest the same
    (the family's map is odd in the geometry: ``Basis.odd_in_geometry``); else None."""
    source = images.source(face) if isinstance(face, Basis) else None
    nodes = None if source is None else _NODES.get(source)
    if nodes is None:
        return None
    points, elements, values = nodes
    return -points + 0.0, elements, values  # + 0.0: a coordinate 0 stays 0, not -0


def _plain_collocation(face) -> bool:
    """Whether ``face`` is one segment whose E is :class:`~fretbem.basis.Basis`'s own (the
    shape values at :meth:`~fretbem.basis.Basis.collocation`, scattered): a family that
    overrides how E or its nodes are formed keeps its own."""
    kind = type(face)
    return isinstance(face, Basis) and all(
        getattr(kind, name) is getattr(Basis, name)
        for name in ("collocation_matrix", "evaluation_matrix", "collocation",
                     "collocation_parameters", "to_local")
    )  # fmt: skip


def transposed_solve(matrix: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """``rows @ matrix^-1`` (rows (m, N), matrix (N, N)), through a banded LU when it is banded.

    E of a spline or Lagrange face is banded (each node sees the few functions of its
    element): a banded LU then costs O(N) per row where a dense one costs O(N^2).
    """
    return _solve_transposed(matrix, _bands(matrix), rows)


def _bands(matrix: np.ndarray):
    """((upper, lower), bands of the transpose in LAPACK's layout), or None when the matrix
    is too wide-banded for a banded LU to pay."""
    nonzero_rows, nonzero_cols = np.nonzero(matrix)
    lower = int(np.max(nonzero_rows - nonzero_cols, initial=0))
    upper = int(np.max(nonzero_cols - nonzero_rows, initial=0))
    n = matrix.shape[0]
    if lower + upper + 1 > n // 4:
        return None
    # the transpose has the bands swapped: its lower band is the matrix's upper one
    bands = np.zeros((lower + upper + 1, n))
    transposed = matrix.T
    for k in range(-upper, lower + 1):  # diagonal k of the transpose (k > 0 above)
        diagonal = np.diagonal(transposed, k)
        if k >= 0:
            bands[lower - k, k:] = diagonal
        else:
            bands[lower - k, : n + k] = diagonal
    return (upper, lower), bands


def _solve_transposed(matrix: np.ndarray, banded, rows: np.ndarray) -> np.ndarray:
    """``rows @ matrix^-1`` through :func:`_bands`' form (dense when None)."""
    if banded is None:
        return np.linalg.solve(matrix.T, rows.T).T
    return _banded(*banded, rows.T).T


def _banded(sizes: tuple[int, int], bands: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """``scipy.linalg.solve_banded(sizes, bands, rhs)`` for finite float64 input, through the
    LAPACK routine it calls (gtsv for one band each side, else gbsv): the same numbers without
    its checks and batching (~60 % of the call at 61 nodes, four calls per body build)."""
    lower, upper = sizes
    if bands.shape[1] == 1 or rhs.size == 0:
        return sla.solve_banded(sizes, bands, rhs)
    if lower == upper == 1:
        *_, x, info = sla.lapack.dgtsv(bands[2, :-1], bands[1, :], bands[0, 1:], rhs,
                                       False, False, False, False)  # fmt: skip
    else:
        factors = np.zeros((2 * lower + upper + 1, bands.shape[1]))
        factors[lower:] = bands
        *_, x, info = sla.lapack.dgbsv(lower, upper, factors, rhs, overwrite_ab=True)
    if info > 0:
        raise np.linalg.LinAlgError("singular matrix")
    if info < 0:  # pragma: no cover - LAPACK argument error
        raise ValueError(f"illegal value in argument {-info} of the banded solve")
    return x


def _shape_integrals(face: Basis, samples=None) -> np.ndarray:
    """int phi_b dx over the projected face, for each shape function b (``samples``: the
    face's :func:`~.influence.gauss_samples`, if already computed)."""
    elements, rule_weights, m = gauss_samples(face) if samples is None else samples
    weights = np.abs(m.tangents[:, 0]) * rule_weights
    return added_at(face.n_functions, face.connectivity[elements], m.values * weights[:, None])
