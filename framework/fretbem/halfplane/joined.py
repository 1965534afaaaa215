"""A contact face of several discretised segments read as one face (a rounded flat's three).

The half-plane's influence coefficients need only the face's element maps, its shape
functions and its collocation points; :class:`JoinedFace` numbers the elements, functions
and nodes of its parts one after the other so the surface operator treats them as one face.
Each part keeps its own functions (the traction may jump at a junction, as on a BEM body).
"""

from __future__ import annotations

import attrs
import numpy as np

from fretbem.basis import Basis, ElementMap

from .influence import HalfPlaneFaceError


def _parts(value) -> tuple[Basis, ...]:
    parts = tuple(value)
    if not parts or not all(isinstance(p, Basis) for p in parts):
        raise HalfPlaneFaceError("a joined half-plane face needs one or more discretised segments")
    if len({p.n_local for p in parts}) != 1:
        raise HalfPlaneFaceError(
            "the segments of a half-plane face must be discretised by one family at one degree "
            f"(functions per element: {[p.n_local for p in parts]})"
        )
    return parts


@attrs.frozen(eq=False)
class JoinedFace:
    """Discretised segments (one family, one degree) numbered as one face.

    Attributes
    ----------
    parts : tuple of Basis
        The segments in boundary order.
    """

    parts: tuple[Basis, ...] = attrs.field(converter=_parts)
    _cache: dict = attrs.field(init=False, factory=dict, repr=False)

    def __attrs_post_init__(self) -> None:
        ends = np.array(
            [p.map(np.array([0, p.n_elements - 1]), np.array([-1.0, 1.0])).points[:, 0]
             for p in self.parts]
        )  # fmt: skip
        steps = np.diff(ends.ravel())
        span = max(float(np.ptp(ends)), 1e-300)
        if not (np.all(steps > -1e-9 * span) or np.all(steps < 1e-9 * span)):
            raise HalfPlaneFaceError(
                "the segments of a half-plane face must follow one another along x, each "
                f"starting where the previous one ends (their x ranges: {ends.tolist()}); "
                "give the contact segments end to end in boundary order"
            )

    @property
    def degree(self) -> int:
        """The parts' degree."""
        return self.parts[0].degree

    @property
    def n_elements(self) -> int:
        """Elements of all parts."""
        return int(self.element_offsets[-1])

    @property
    def n_functions(self) -> int:
        """Functions of all parts."""
        return int(self.function_offsets[-1])

    @property
    def n_local(self) -> int:
        """Functions non-zero on one element."""
        return self.parts[0].n_local

    @property
    def element_offsets(self) -> np.ndarray:
        """First global element of each part, and the total (len(parts) + 1)."""
        return np.concatenate([[0], np.cumsum([p.n_elements for p in self.parts])])

    @property
    def function_offsets(self) -> np.ndarray:
        """First global function (node) of each part, and the total (len(parts) + 1)."""
        return np.concatenate([[0], np.cumsum([p.n_functions for p in self.parts])])

    @property
    def connectivity(self) -> np.ndarray:
        """Global function index of each element's local functions."""
        if "connectivity" not in self._cache:
            offsets = self.function_offsets
            self._cache["connectivity"] = np.concatenate(
                [p.connectivity + offsets[k] for k, p in enumerate(self.parts)]
            )
        return self._cache["connectivity"]

    def _split(self, elements):
        elements = np.asarray(elements, dtype=np.intp)
        part = np.searchsorted(self.element_offsets, elements, side="right") - 1
        return part, elements - self.element_offsets[part]

    def map(self, elements: np.ndarray, local: np.ndarray) -> ElementMap:
        """Shape functions and geometry at global (element, local coordinate) points."""
        part, own = self._split(elements)
        local = np.asarray(local, dtype=float)
        m = len(own)
        values = np.zeros((m, self.n_local))
        points, tangents, normals = np.zeros((m, 2)), np.zeros((m, 2)), np.zeros((m, 2))
        jacobians = np.zeros(m)
        for k, basis in enumerate(self.parts):
            rows = np.flatnonzero(part == k)
            if rows.size:
                e = basis.map(own[rows], local[rows])
                values[rows], points[rows], tangents[rows] = e.values, e.points, e.tangents
                jacobians[rows], normals[rows] = e.jacobians, e.normals
        return ElementMap(values, points, tangents, jacobians, normals)

    def shape_functions(self, elements: np.ndarray, local: np.ndarray):
        """Values and d/d(local) of the local functions at global (element, local) points."""
        part, own = self._split(elements)
        local = np.asarray(local, dtype=float)
        values = np.zeros((len(own), self.n_local))
        derivatives = np.zeros_like(values)
        for k, basis in enumerate(self.parts):
            rows = np.flatnonzero(part == k)
            if rows.size:
                values[rows], derivatives[rows] = basis.shape_functions(own[rows], local[rows])
        return values, derivatives

    def collocation(self) -> tuple[np.ndarray, np.ndarray]:
        """Global element and local coordinate of every node, part after part."""
        pieces = [p.collocation() for p in self.parts]
        offsets = self.element_offsets
        elements = np.concatenate([e + offsets[k] for k, (e, _) in enumerate(pieces)])
        return elements, np.concatenate([local for _, local in pieces])

    def collocation_matrix(self) -> np.ndarray:
        """E of the face: the parts' E matrices on the diagonal (coefficients to node values)."""
        n = self.n_functions
        out = np.zeros((n, n))
        offsets = self.function_offsets
        for k, basis in enumerate(self.parts):
            block = slice(offsets[k], offsets[k + 1])
            out[block, block] = basis.collocation_matrix()
        return out
