"""A body's contact face as a field: locate points on its exact geometry, interpolate node values.

A pairing by projection needs, of each face, two things the node values alone do not give:
where a point of the other face lands on this face's exact NURBS geometry (projection along
the pair normal), and the value there of a field known by its node values (traction or
displacement at the collocation points), through the face's own basis functions. Both are
here, for any body whose :attr:`~fretbem.body.Body.segments` hold its face (BEM, half-plane).
"""

from __future__ import annotations

import attrs
import numpy as np

from fretbem.basis import Basis
from fretbem.body import Body

__all__ = ["FaceField", "FaceProjectionError", "nearest_nodes"]


class FaceProjectionError(ValueError):
    """The face cannot be located along the pair tangent (it folds back, or has no segments)."""


#: samples per element of the bracket search before Newton's iterations on the exact curve
SAMPLES_PER_ELEMENT = 8
#: Newton iterations of the projection (quadratic convergence from the bracket's estimate)
NEWTON_ITERATIONS = 6
#: passes of the closest-point projection (each shrinks the error by distance / radius of
#: curvature, below 1e-3 within a contact zone: round-off in a few passes)
CLOSEST_PASSES = 12


@attrs.frozen(eq=False)
class FaceField:
    """The segments of one contact face, their node offsets and their node-value inverses.

    Attributes
    ----------
    segments : tuple of Basis
        The discretised segments of the face, in the order of the face's nodes.
    offsets : ndarray of int, shape (len(segments) + 1,)
        Face node range of each segment (node values of segment i are rows offsets[i]:offsets[i+1]).
    inverses : tuple of ndarray
        E^-1 of each segment: node values to coefficients.
    """

    segments: tuple[Basis, ...]
    offsets: np.ndarray
    inverses: tuple[np.ndarray, ...]

    @classmethod
    def of(cls, body: Body, tag: str) -> FaceField:
        """The face ``tag`` of ``body`` (its segments in boundary order, as its face nodes)."""
        segments = tuple(
            b for b, t in zip(body.segments, body.segment_tags, strict=True) if t == tag
        )
        if not segments:
            raise FaceProjectionError(
                f"body {body.name!r} exposes no discretised segment tagged {tag!r}, so its face "
                "cannot be located by projection; use pairing = 'node-to-node'"
            )
        sizes = [b.n_functions for b in segments]
        n_nodes = body.contact_face(tag).n_nodes
        if sum(sizes) != n_nodes:
            raise FaceProjectionError(
                f"body {body.name!r}: the segments tagged {tag!r} have {sum(sizes)} functions but "
                f"the face {n_nodes} nodes; a projection pairing needs one node per function"
            )
        inverses = tuple(np.linalg.inv(b.collocation_matrix()) for b in segments)
        return cls(segments, np.concatenate([[0], np.cumsum(sizes)]), inverses)

    def turned(self, angle: float, pivot: np.ndarray) -> FaceField:
        """The same face turned rigidly by ``angle`` (rad) about ``pivot``: its curves and
        geometry coefficients turned (a NURBS curve turns with its control points), its
        bases and node values unchanged."""
        c, s = np.cos(angle), np.sin(angle)
        turn = np.array([[c, -s], [s, c]])

        def moved(points):
            return pivot + (np.asarray(points) - pivot) @ turn.T

        segments = tuple(
            attrs.evolve(
                b,
                curve=attrs.evolve(b.curve, control_points=moved(b.curve.control_points)),
                geometry_coefficients=moved(b.geometry_coefficients),
            )
            for b in self.segments
        )
        return attrs.evolve(self, segments=segments)

    @property
    def n_nodes(self) -> int:
        """Number of face nodes."""
        return int(self.offsets[-1])

    def locate(self, along: np.ndarray, tangent: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Segment and curve parameter where the face reaches ``along`` = X . tangent.

        Returns (segment index, parameter); the index is -1 where the face does not reach.
        The projection runs on each segment's exact curve (Newton from a sampled bracket).
        """
        along = np.asarray(along, float)
        segment = np.full(along.shape, -1, dtype=np.intp)
        params = np.zeros(along.shape)
        for index, basis in enumerate(self.segments):
            curve = basis.curve
            grid = _grid(basis)
            xi = curve.points(grid) @ tangent
            steps = np.diff(xi)
            if not (np.all(steps > 0) or np.all(steps < 0)):
                raise FaceProjectionError(
                    "a contact segment turns back along the pair tangent (near "
                    f"{curve.points(grid[np.argmin(np.abs(steps))]).round(6)}), so a point of the "
                    "other face can face it twice; contact faces must run monotonically along "
                    "the surface"
                )
            order = np.argsort(xi)
            lo, hi = xi[order[0]], xi[order[-1]]
            span = hi - lo
            inside = (segment < 0) & (along >= lo - 1e-12 * span) & (along <= hi + 1e-12 * span)
            if not inside.any():
                continue
            target = along[inside]
            s = np.interp(target, xi[order], grid[order])
            for _ in range(NEWTON_ITERATIONS):
                point, derivative = curve.points_and_derivatives(s)
                f = point @ tangent - target
                df = derivative @ tangent
                s = np.clip(s - f / df, 0.0, 1.0)
            segment[inside] = index
            params[inside] = s
        return segment, params

    def locate_each(
        self, points: np.ndarray, tangents: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Segment and curve parameter where the face crosses the line through each point
        normal to its own tangent: X . t_k = P_k . t_k (:meth:`locate` with a tangent per
        point). Returns (segment index, parameter); the index is -1 where the face does not
        reach."""
        points, tangents = np.asarray(points, float), np.asarray(tangents, float)
        along = np.einsum("kd,kd->k", points, tangents)
        segment = np.full(along.shape, -1, dtype=np.intp)
        params = np.zeros(along.shape)
        for index, basis in enumerate(self.segments):
            curve = basis.curve
            grid = _grid(basis)
            xi = curve.points(grid) @ tangents.T  # (samples, points)
            steps = np.diff(xi, axis=0)
            if not (np.all(steps > 0, axis=0) | np.all(steps < 0, axis=0)).all():
                raise FaceProjectionError(
                    "a contact segment turns back along a pair tangent, so a point of the other "
                    "face can face it twice; contact faces must run monotonically along the "
                    "surface"
                )
            lo, hi = xi.min(axis=0), xi.max(axis=0)
            span = hi - lo
            inside = (segment < 0) & (along >= lo - 1e-12 * span) & (along <= hi + 1e-12 * span)
            if not inside.any():
                continue
            rows = np.flatnonzero(inside)
            s = np.empty(rows.size)
            for j, k in enumerate(rows):
                order = np.argsort(xi[:, k])
                s[j] = np.interp(along[k], xi[order, k], grid[order])
            target, tangent = along[rows], tangents[rows]
            for _ in range(NEWTON_ITERATIONS):
                point, derivative = curve.points_and_derivatives(s)
                f = np.einsum("kd,kd->k", point, tangent) - target
                df = np.einsum("kd,kd->k", derivative, tangent)
                s = np.clip(s - f / df, 0.0, 1.0)
            segment[rows] = index
            params[rows] = s
        return segment, params

    def project(self, points: np.ndarray, tangent: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The closest point of the face to each point (segment, parameter; -1 off the face):
        the face's point whose normal passes through it, found by locating along the face's
        tangent where it was last found, from ``tangent`` (the error shrinks by the distance
        over the radius of curvature at each pass)."""
        points = np.asarray(points, float)
        tangents = np.tile(np.asarray(tangent, float), (len(points), 1))
        segment, params = self.locate_each(points, tangents)
        for _ in range(CLOSEST_PASSES):
            found = segment >= 0
            if not found.any():
                break
            normals = self.normals(segment[found], params[found])
            tangents[found] = np.stack([normals[:, 1], -normals[:, 0]], axis=1)
            before = self.points(segment, params)
            segment, params = self.locate_each(points, tangents)
            moved = np.linalg.norm(self.points(segment, params) - before, axis=1)
            if np.all(segment[found] >= 0) and not np.nanmax(moved[found], initial=0.0) > 1e-15:
                break
        return segment, params

    def closest(self, points: np.ndarray, tangent: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`project` for many points at once (a transfer's quadrature points): located
        along ``tangent``, then Gauss-Newton on (X(s) - P) . X'(s) = 0, each step shrinking
        the error by the distance over the radius of curvature, a point stopped at a
        segment's end carried on to the next. (segment, parameter); -1 where the closest
        point would lie past the face's ends."""
        points = np.asarray(points, float)
        segment, params = self.locate(points @ np.asarray(tangent, float), tangent)
        last = len(self.segments) - 1
        for _ in range(2):  # a second round for the points carried over a segment's end
            moved = np.zeros(segment.shape, dtype=bool)
            for index, basis in enumerate(self.segments):
                here = np.flatnonzero(segment == index)
                if not here.size:
                    continue
                s, target = params[here], points[here]
                for _ in range(CLOSEST_PASSES):
                    point, derivative = basis.curve.points_and_derivatives(s)
                    step = np.einsum("kd,kd->k", point - target, derivative)
                    s = np.clip(s - step / np.einsum("kd,kd->k", derivative, derivative), 0, 1)
                point, derivative = basis.curve.points_and_derivatives(s)
                along = np.einsum("kd,kd->k", point - target, derivative)
                along /= np.linalg.norm(derivative, axis=1)
                past = np.abs(along) > 1e-12 * (1.0 + np.linalg.norm(point - target, axis=1))
                ahead = past & (s == 1.0) & (index < last)
                behind = past & (s == 0.0) & (index > 0)
                params[here] = np.where(ahead, 0.0, np.where(behind, 1.0, s))
                segment[here] = np.where(ahead, index + 1, np.where(behind, index - 1, index))
                moved[here] = ahead | behind
                off = past & ~ahead & ~behind & ((s == 0.0) | (s == 1.0))
                segment[here[off]] = -1
            if not moved.any():
                break
        return segment, params

    def points(self, segment: np.ndarray, params: np.ndarray) -> np.ndarray:
        """Positions (m, 2) on the exact face geometry at located (segment, parameter)."""
        return self._on_curves("points", segment, params)

    def normals(self, segment: np.ndarray, params: np.ndarray) -> np.ndarray:
        """Unit outward normals (m, 2) of the exact face geometry at (segment, parameter)."""
        return self._on_curves("normals", segment, params)

    def _on_curves(self, what: str, segment: np.ndarray, params: np.ndarray) -> np.ndarray:
        out = np.full((len(params), 2), np.nan)
        for index, basis in enumerate(self.segments):
            here = segment == index
            if here.any():
                out[here] = getattr(basis.curve, what)(params[here])
        return out

    def local(self, segment: np.ndarray, params: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The basis functions non-zero at each point: face coefficient indices and values.

        Returns (columns, values), both (m, k) with k the most local functions of a segment
        (padding: value 0); a point off the face (segment -1) has only zero values.
        """
        k = max(b.n_local for b in self.segments)
        columns = np.zeros((len(params), k), dtype=np.intp)
        values = np.zeros((len(params), k))
        for index, basis in enumerate(self.segments):
            here = np.flatnonzero(segment == index)
            if here.size:
                elements, local = basis.to_local(params[here])
                shape, _ = basis.shape_functions(elements, local)
                columns[here, : basis.n_local] = self.offsets[index] + basis.connectivity[elements]
                values[here, : basis.n_local] = shape
        return columns, values

    def values_matrix(self) -> np.ndarray:
        """E of the face: coefficients to node values (block diagonal over its segments)."""
        out = np.zeros((self.n_nodes, self.n_nodes))
        for index, basis in enumerate(self.segments):
            block = slice(self.offsets[index], self.offsets[index + 1])
            out[block, block] = basis.collocation_matrix()
        return out

    def inverse_values_matrix(self) -> np.ndarray:
        """E^-1 of the face: node values to coefficients (block diagonal)."""
        out = np.zeros((self.n_nodes, self.n_nodes))
        for index, inverse in enumerate(self.inverses):
            block = slice(self.offsets[index], self.offsets[index + 1])
            out[block, block] = inverse
        return out

    def interpolation(self, segment: np.ndarray, params: np.ndarray) -> np.ndarray:
        """Matrix (m, n_nodes): face node values -> field values at (segment, parameter).

        Row k is N(s_k) E^-1 of the segment holding point k (the face's own basis); a row
        whose point is off the face (segment -1) is zero.
        """
        out = np.zeros((len(params), self.n_nodes))
        for index, (basis, inverse) in enumerate(zip(self.segments, self.inverses, strict=True)):
            here = np.flatnonzero(segment == index)
            if here.size:
                columns = slice(self.offsets[index], self.offsets[index + 1])
                out[here, columns] = basis.evaluation_matrix(params[here]) @ inverse
        return out


def _grid(basis: Basis) -> np.ndarray:
    """The parameters sampled on a segment to bracket a projection."""
    return np.unique(
        np.concatenate(
            [np.linspace(lo, hi, SAMPLES_PER_ELEMENT + 1) for lo, hi in basis.element_bounds]
        )
    )


def nearest_nodes(matrix: np.ndarray) -> np.ndarray:
    """The node with the largest weight in each row of an interpolation matrix (for reports)."""
    return np.argmax(np.abs(matrix), axis=1)
