"""The abstract basis family, the refinement request, and the shared geometry layer.

A family (a plugin) discretises one boundary segment: it splits the segment's parameter
range into elements, supplies reference shape functions on each element (local coordinate
in [-1, 1]), the global numbering of the segment's coefficients, the geometry coefficients
(control points or nodes) and its natural collocation parameters. Everything else
(points, normals, Jacobians, the E matrix, corner handling) is done once here.
"""

from __future__ import annotations

import functools
from abc import ABC, abstractmethod
from typing import ClassVar

import attrs
import numpy as np

from fretbem.geometry.nurbs import NurbsCurve
from fretbem.numerics.scatter import added_at

from .validators import count_field, float_array, number_field, shape, whole_number


@attrs.frozen(eq=False)
class ElementMap:
    """Shape-function values and geometry at a set of (element, local coordinate) points.

    Attributes
    ----------
    values : ndarray, shape (m, n_local)
    points, tangents, normals : ndarray, shape (m, 2)
    jacobians : ndarray, shape (m,)
    """

    values: np.ndarray
    points: np.ndarray
    tangents: np.ndarray
    jacobians: np.ndarray
    normals: np.ndarray


#: collocation parameters at a segment end are moved this fraction of the end element inward
END_SHIFT = 1.0 / 6.0


def _as_intervals(value) -> tuple[tuple[float, float], ...] | None:
    """A point s, or a sequence whose items are points s or intervals (s0, s1)."""
    if value is None:
        return None
    if np.isscalar(value):
        return ((float(value), float(value)),)
    out = []
    for item in value:
        lo, hi = (item, item) if np.isscalar(item) else item
        out.append((float(lo), float(hi)))
    return tuple(out)


def _as_floats(value) -> tuple[float, ...]:
    """The numbers of ``value`` (a number or a sequence, flattened) as a tuple of floats;
    the usual empty tuple as it is (np.ravel's call costs more than the rest)."""
    if type(value) is tuple and not value:
        return value
    return tuple(float(x) for x in np.ravel(value))


def _check_toward(instance, attribute, value) -> None:
    for lo, hi in value or ():
        if not (0.0 <= lo <= hi <= 1.0):
            raise ValueError(
                f"Refinement.toward needs points or intervals 0 <= s0 <= s1 <= 1, got {value!r}"
            )


def _as_breakpoints(value) -> tuple[float, ...] | None:
    """Explicit element boundaries: strictly increasing, from 0 to 1."""
    if value is None:
        return None
    at = np.asarray(value, dtype=float).ravel()
    if (
        at.size < 2
        or not np.all(np.isfinite(at))
        or at[0] != 0.0
        or at[-1] != 1.0
        or np.any(np.diff(at) <= 0.0)
    ):
        raise ValueError(
            "Refinement.at needs strictly increasing breakpoints from 0.0 to 1.0 (the "
            f"normalised parameter, both ends included), got {value!r}"
        )
    return tuple(float(v) for v in at)


def _degree(value) -> int | None:
    """A requested degree: None (the family's default) or a whole number >= 1."""
    if value is None:
        return None
    fix = "give the basis degree, or None for the family's default"
    return whole_number("Refinement.degree", value, low=1, fix=fix)


@attrs.frozen(cache_hash=True)
class Refinement:
    """How finely one segment is discretised.

    The hash is kept: a segment's discretisations are looked up by refinement, an explicit
    one of a few dozen breakpoints at every body a level builds.

    Attributes
    ----------
    elements : int
        Number of elements (knot spans) on the segment.
    degree : int or None
        Requested degree (p-refinement); None keeps the family's default.
    toward : tuple of (float, float) or None
        Normalised parameter intervals (a point if both ends are equal) where elements are
        smallest; given as a point s or a sequence of points s and intervals (s0, s1), e.g.
        ``(0.0, 1.0)`` for both ends, ``[(0.4, 0.6)]`` for an interval. None for uniform.
    ratio : float
        Size of the largest element over the smallest (>= 1) when graded.
    at : tuple of float or None
        Explicit element boundaries in the normalised parameter (0 and 1 included); when
        given they replace the uniform or graded ones (see :meth:`explicit`).
    c0_at : tuple of float
        Breakpoints of ``at`` where the basis is only C0 (families whose functions are
        smoother across elements repeat the knot there); empty for full continuity.
    """

    elements: int = attrs.field(
        default=4, converter=count_field("give the number of elements on the segment")
    )
    degree: int | None = attrs.field(default=None, converter=_degree)
    toward: tuple[tuple[float, float], ...] | None = attrs.field(
        default=None, converter=_as_intervals, validator=_check_toward
    )
    ratio: float = attrs.field(
        default=1.0,
        converter=number_field(
            "largest over smallest element", "give a ratio >= 1 (1: uniform)", low=1.0
        ),
    )
    at: tuple[float, ...] | None = attrs.field(default=None, converter=_as_breakpoints)
    c0_at: tuple[float, ...] = attrs.field(default=(), converter=_as_floats)

    def __attrs_post_init__(self) -> None:
        if self.at is not None and self.elements != len(self.at) - 1:
            raise ValueError(
                f"Refinement.at lists {len(self.at)} breakpoints, i.e. {len(self.at) - 1} "
                f"elements, but elements = {self.elements}; build it with "
                "Refinement.explicit(breakpoints), which sets elements from the list"
            )
        if self.c0_at and (self.at is None or not set(self.c0_at) <= set(self.at[1:-1])):
            raise ValueError(
                f"Refinement.c0_at {self.c0_at!r} must be interior breakpoints listed in "
                "Refinement.at; give both through Refinement.explicit(breakpoints, c0_at=...)"
            )

    @classmethod
    def explicit(cls, breakpoints, degree: int | None = None, c0_at=()) -> Refinement:
        """Elements between the given breakpoints (normalised parameter, 0 and 1 included).

        For callers that place element boundaries themselves, e.g. adaptive refinement that
        puts a breakpoint on a contact edge. ``c0_at``: breakpoints where a smoother family
        lowers its continuity to C0 (NURBS repeat the knot), so the traction may kink there
        and a collocation point (Greville abscissa) sits on it.
        """
        at = _as_breakpoints(breakpoints)
        return cls(elements=len(at) - 1, degree=degree, at=at, c0_at=c0_at)

    @classmethod
    def uniform(cls, elements: int, degree: int | None = None) -> Refinement:
        """Equal elements in the parameter."""
        return cls(elements=elements, degree=degree)

    @classmethod
    def graded(cls, elements: int, toward, ratio: float, degree: int | None = None) -> Refinement:
        """Elements smallest at ``toward`` (points s or intervals (s0, s1) in [0, 1])."""
        return cls(elements=elements, degree=degree, toward=toward, ratio=ratio)

    def breakpoints(self) -> np.ndarray:
        """Element boundaries in the normalised parameter [0, 1].

        Element density falls linearly with distance from ``toward``, from 1 to 1 / ratio,
        and the breakpoints equidistribute it; ``at``, when given, is returned as it is.
        """
        if self.at is not None:
            return np.array(self.at)
        if self.toward is None or self.ratio == 1.0:
            return np.linspace(0.0, 1.0, self.elements + 1)
        return _graded(self.elements, self.toward, self.ratio).copy()


@functools.lru_cache(maxsize=256)
def _graded(elements: int, toward: tuple, ratio: float) -> np.ndarray:
    """Graded breakpoints (see :meth:`Refinement.breakpoints`), computed once per grading:
    a scene's corner grading serves four segments of each body."""
    s = np.linspace(0.0, 1.0, 4001)
    dist = np.min([np.maximum(np.maximum(lo - s, s - hi), 0.0) for lo, hi in toward], axis=0)
    far = max(dist.max(), 1e-300)
    density = 1.0 / (1.0 + (ratio - 1.0) * dist / far)
    cumulative = np.concatenate([[0.0], np.cumsum(0.5 * (density[1:] + density[:-1]))])
    levels = np.linspace(0.0, cumulative[-1], elements + 1)
    out = np.interp(levels, cumulative, s)
    out[0], out[-1] = 0.0, 1.0
    out.setflags(write=False)
    return out


@attrs.frozen(eq=False)
class Basis(ABC):
    """One boundary segment discretised by a basis family.

    A family subclasses this, sets ``name``, ``description`` and ``interpolatory``, and
    implements :meth:`discretise` and :meth:`shape_functions`.

    Attributes
    ----------
    curve : NurbsCurve
        The segment's exact geometry (parameter in [0, 1]).
    degree : int
    element_bounds : ndarray, shape (n_elements, 2)
        Parameter interval of each element on ``curve``.
    connectivity : ndarray of int, shape (n_elements, n_local)
        Segment-level index of each element's local functions.
    geometry_coefficients : ndarray, shape (n_functions, 2)
        Control points (isogeometric) or nodes (isoparametric): x = sum phi_a X_a.
    natural_collocation : ndarray, shape (n_functions,)
        The family's collocation parameters (Greville abscissae, nodes), before the
        segment ends are moved inward.
    """

    name: ClassVar[str] = ""
    description: ClassVar[str] = ""
    interpolatory: ClassVar[bool] = False
    #: :meth:`discretise` and :meth:`map` are odd in the geometry: a curve reflected through
    #: the origin (its control points negated) is discretised into the same elements,
    #: functions and collocation with the geometry coefficients negated, and ``map`` changes
    #: the sign of points, tangents and normals exactly, its values and Jacobians the same
    #: (true of sums of products with the coefficients, as the shared :meth:`map`); a family
    #: for which this is not so sets False (:mod:`fretbem.bem.images` then takes nothing
    #: from a point image for it)
    odd_in_geometry: ClassVar[bool] = True

    curve: NurbsCurve
    degree: int
    element_bounds: np.ndarray = attrs.field(converter=float_array, validator=shape(None, 2))
    connectivity: np.ndarray = attrs.field(converter=lambda a: np.asarray(a, dtype=np.intp))
    geometry_coefficients: np.ndarray = attrs.field(converter=float_array, validator=shape(None, 2))
    natural_collocation: np.ndarray = attrs.field(converter=float_array, validator=shape(None))

    # -- what a family provides -------------------------------------------------------------
    @classmethod
    @abstractmethod
    def discretise(cls, curve: NurbsCurve, refinement: Refinement) -> Basis:
        """Discretise ``curve`` (parameter [0, 1]) at ``refinement``."""

    @abstractmethod
    def shape_functions(
        self, elements: np.ndarray, local: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Values and d/d(local) of each element's local functions, shape (m, n_local) each.

        ``elements`` and ``local`` are equal-length 1-D arrays; local coordinates in [-1, 1].
        """

    # -- shared layer ---------------------------------------------------------------------
    @property
    def n_elements(self) -> int:
        """Number of elements on the segment."""
        return len(self.element_bounds)

    @property
    def n_functions(self) -> int:
        """Number of basis functions (coefficients) on the segment."""
        return len(self.geometry_coefficients)

    @property
    def n_local(self) -> int:
        """Functions non-zero on one element."""
        return self.connectivity.shape[1]

    def to_local(self, params: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Element index and local coordinate of curve parameters."""
        params = np.asarray(params, float)
        elements = np.searchsorted(self.element_bounds[:, 0], params, side="right") - 1
        # np.clip's numbers as the two ufuncs it applies (its own frames cost more here)
        elements = np.minimum(np.maximum(elements, 0), self.n_elements - 1)
        lo, hi = self.element_bounds[elements].T
        return elements, np.minimum(np.maximum(2.0 * (params - lo) / (hi - lo) - 1.0, -1.0), 1.0)

    def to_parameter(self, elements: np.ndarray, local: np.ndarray) -> np.ndarray:
        """Curve parameters of (element, local coordinate) points."""
        lo, hi = self.element_bounds[elements].T
        return lo + (np.asarray(local) + 1.0) * 0.5 * (hi - lo)

    def map(self, elements: np.ndarray, local: np.ndarray) -> ElementMap:
        """Shape functions and geometry at once (one basis evaluation), for quadrature."""
        values, derivatives = self.shape_functions(elements, local)
        functions = self.connectivity[elements]
        # sum over the local functions in their order, coordinate by coordinate: the
        # arithmetic of an einsum over them, every operation along the points
        points, tangents = np.empty((len(functions), 2)), np.empty((len(functions), 2))
        for k in range(2):
            coordinate = self.geometry_coefficients[:, k]
            column = coordinate[functions]
            np.multiply(values[:, 0], column[:, 0], out=points[:, k])
            np.multiply(derivatives[:, 0], column[:, 0], out=tangents[:, k])
            for a in range(1, functions.shape[1]):
                points[:, k] += values[:, a] * column[:, a]
                tangents[:, k] += derivatives[:, a] * column[:, a]
        tx, ty = tangents[:, 0], tangents[:, 1]
        jacobians = np.sqrt(tx * tx + ty * ty)
        normals = np.empty_like(tangents)
        np.divide(ty, jacobians, out=normals[:, 0])
        np.divide(-tx, jacobians, out=normals[:, 1])
        return ElementMap(values, points, tangents, jacobians, normals)

    def abscissae(self, elements: np.ndarray, local: np.ndarray):
        """(x, dx/d(local), shape values (m, n_local)) at the points: :meth:`map`'s first
        coordinates, summed as it sums them (the same numbers), without y, the Jacobians and
        the normals (the half-plane's influence integrals read x alone)."""
        values, derivatives = self.shape_functions(elements, local)
        column = self.geometry_coefficients[:, 0][self.connectivity[elements]]
        x = values[:, 0] * column[:, 0]
        dx = derivatives[:, 0] * column[:, 0]
        for a in range(1, column.shape[1]):
            x += values[:, a] * column[:, a]
            dx += derivatives[:, a] * column[:, a]
        return x, dx, values

    def geometry(self, elements: np.ndarray, local: np.ndarray):
        """Points, tangents d x / d(local), Jacobians and unit outward normals, from the basis."""
        m = self.map(elements, local)
        return m.points, m.tangents, m.jacobians, m.normals

    @property
    def collocation_parameters(self) -> np.ndarray:
        """Natural collocation parameters with the segment's end points moved into the segment.

        Moving the end points off the corner gives every collocation point a smooth boundary
        (c = I/2) and lets the traction jump between segments (docs/theory.md, corners).
        """
        params = np.array(self.natural_collocation, dtype=float)
        first = self.element_bounds[0]
        last = self.element_bounds[-1]
        tol = 1e-12
        params[params <= first[0] + tol] = first[0] + END_SHIFT * (first[1] - first[0])
        params[params >= last[1] - tol] = last[1] - END_SHIFT * (last[1] - last[0])
        return params

    def collocation(self) -> tuple[np.ndarray, np.ndarray]:
        """Element and local coordinate of every collocation point."""
        return self.to_local(self.collocation_parameters)

    def evaluation_matrix(self, params: np.ndarray) -> np.ndarray:
        """Matrix mapping this segment's coefficients to values at curve ``params``."""
        elements, local = self.to_local(params)
        values, _ = self.shape_functions(elements, local)
        rows = np.arange(len(elements))[:, None]
        return added_at((len(elements), self.n_functions), (rows, self.connectivity[elements]),
                        values)  # fmt: skip

    def collocation_matrix(self) -> np.ndarray:
        """The E matrix of the paper (eq. 5-6): coefficients to values at collocation points."""
        return self.evaluation_matrix(self.collocation_parameters)


@functools.lru_cache(maxsize=512)
def face_points(family: type[Basis], elements: int, degree: int | None = None) -> int:
    """Collocation points (pairs) a family puts on a face of ``elements`` elements (cached)."""
    line = NurbsCurve.line([0, 0], [1, 0], degree=1)
    return family.discretise(line, Refinement(elements=elements, degree=degree)).n_functions


def points_per_element(family: type[Basis], degree: int | None = None) -> tuple[float, float]:
    """Collocation points per element of a family's face, and the extra ones of the face."""
    a, b = face_points(family, 4, degree), face_points(family, 8, degree)
    per = (b - a) / 4
    return per, a - 4 * per
