"""NURBS basis: the geometry's own functions, Greville collocation, h- and p-refinement."""

from __future__ import annotations

import weakref

import numpy as np

from fretbem.basis import Basis, ElementMap, Refinement
from fretbem.geometry import knots as kv
from fretbem.geometry.nurbs import NurbsCurve, bspline_from_window, rational_columns


def _merge_breakpoints(existing: np.ndarray, requested: np.ndarray) -> np.ndarray:
    """Requested element boundaries plus the curve's own interior knots, each kept once.

    A requested breakpoint closer than a third of its spacing to an existing knot snaps onto
    it, so no sliver elements appear where the curve already has a knot.
    """
    merged = requested.copy()
    spacing = np.diff(requested).min() if requested.size > 1 else 1.0
    for knot in existing[1:-1]:
        nearest = int(np.argmin(np.abs(merged - knot)))
        if abs(merged[nearest] - knot) < spacing / 3 and 0 < nearest < merged.size - 1:
            merged[nearest] = knot
        else:
            merged = np.sort(np.append(merged, knot))
    return np.unique(merged)


def _among(values: np.ndarray, sorted_set: np.ndarray) -> np.ndarray:
    """Whether each of ``values`` equals an entry of the sorted ``sorted_set``."""
    at = np.minimum(np.searchsorted(sorted_set, values), sorted_set.size - 1)
    return sorted_set[at] == values


class NurbsBasis(Basis):
    """Isogeometric (IGABEM) family: exact geometry, collocation at Greville abscissae."""

    name = "nurbs"
    description = "NURBS of the CAD geometry itself (IGABEM), Greville collocation, h/p refinement"
    interpolatory = False
    #: straight lines (degree 1) are elevated so every segment carries quadratic unknowns
    default_degree = 2

    @classmethod
    def discretise(cls, curve: NurbsCurve, refinement: Refinement) -> NurbsBasis:
        default = max(curve.degree, cls.default_degree)
        degree = default if refinement.degree is None else int(refinement.degree)
        if degree < curve.degree:
            raise ValueError(
                f"the nurbs family cannot lower a segment's degree ({curve.degree}) to {degree}: "
                f"the exact geometry needs degree >= {curve.degree}; ask for degree >= "
                f"{curve.degree}"
            )
        knots = curve.knots  # elevation and insertion in one refinement (one solve)
        for _ in range(degree - curve.degree):
            knots = kv.elevate(knots)
        existing = kv.breakpoints(knots)
        if refinement.at is None:
            wanted = _merge_breakpoints(existing, refinement.breakpoints())
        else:  # explicit breakpoints are kept where they are (the curve's own knots added)
            wanted = np.union1d(existing, refinement.breakpoints())
        new = wanted[~_among(wanted, existing)]  # np.setdiff1d of sorted distinct values
        if refinement.c0_at:  # C0 there: the knot repeated to multiplicity = degree
            new = np.sort(np.concatenate([new, np.repeat(refinement.c0_at, degree - 1)]))
        if new.size:
            knots = kv.insert(knots, new)
        if degree > curve.degree or new.size:
            curve, _ = curve.refine(knots, degree)
        bounds = kv.breakpoints(curve.knots)
        element_bounds = np.column_stack([bounds[:-1], bounds[1:]])
        spans = np.searchsorted(curve.knots, element_bounds[:, 0], side="right") - 1
        connectivity = spans[:, None] - degree + np.arange(degree + 1)
        return cls(
            curve=curve,
            degree=degree,
            element_bounds=element_bounds,
            connectivity=connectivity,
            geometry_coefficients=curve.control_points,
            natural_collocation=kv.greville(curve.knots, degree),
        )

    def shape_functions(self, elements, local):
        values, derivatives, scale, _ = _columns(self, elements, local)
        return _stacked(values), _stacked([d * scale for d in derivatives])

    def map(self, elements, local) -> ElementMap:
        """``Basis.map``'s numbers (the same arithmetic, bit for bit) from one gather of the
        elements' data (:func:`_point_table`) and columns over the points throughout: no
        (points, functions) array is read column by column."""
        values, derivatives, scale, (x, y) = _columns(self, elements, local)
        derivatives = [d * scale for d in derivatives]
        coordinates = []
        for coefficient in (x, y):
            point = values[0] * coefficient[0]
            tangent = derivatives[0] * coefficient[0]
            for a in range(1, len(values)):
                point += values[a] * coefficient[a]
                tangent += derivatives[a] * coefficient[a]
            coordinates.append((point, tangent))
        (px, tx), (py, ty) = coordinates
        jacobians = np.sqrt(tx * tx + ty * ty)
        return ElementMap(
            _stacked(values),
            _stacked((px, py)),
            _stacked((tx, ty)),
            jacobians,
            _stacked((ty / jacobians, -tx / jacobians)),
        )

    def abscissae(self, elements, local):
        """:meth:`map`'s x and dx/d(local) with the values (the same arithmetic, bit for
        bit), from the coefficients :func:`_columns` gathers: no y, Jacobian or normal, no
        second gather of the coefficients, no stacked derivatives."""
        values, derivatives, scale, (x, _) = _columns(self, elements, local)
        point = values[0] * x[0]
        tangent = (derivatives[0] * scale) * x[0]
        for a in range(1, len(values)):
            point += values[a] * x[a]
            tangent += (derivatives[a] * scale) * x[a]
        return point, tangent, _stacked(values)


def _stacked(columns) -> np.ndarray:
    """``np.stack(columns, axis=1)`` (C order) without its dispatch."""
    out = np.empty((columns[0].size, len(columns)))
    for a, column in enumerate(columns):
        out[:, a] = column
    return out


def _columns(basis: NurbsBasis, elements, local) -> tuple[list, list, np.ndarray, tuple]:
    """R, dR/dxi (lists of columns over the points), d xi / d(local) and the p + 1
    geometry coefficients of each point's functions per coordinate, as columns."""
    p = basis.degree
    rows = np.take(_point_table(basis), np.asarray(elements, dtype=np.intp), axis=1)
    xi = rows[0] + (np.asarray(local, float) + 1.0) * 0.5 * rows[1]
    xi = np.minimum(xi, rows[2])
    knots = basis.curve.knots
    xi = np.minimum(np.maximum(xi, knots[0]), knots[-1])  # as _bspline_columns clips
    window, weights = rows[4 : 4 + 2 * p], rows[4 + 2 * p : 5 + 3 * p]
    values, derivatives = rational_columns(*bspline_from_window(window, p, xi), list(weights))
    coefficients = rows[5 + 3 * p :]
    return values, derivatives, rows[3], (coefficients[: p + 1], coefficients[p + 1 :])


def _point_table(basis: NurbsBasis) -> np.ndarray:
    """Per element, one column of everything a point evaluation gathers (computed once per
    discretised segment): its start, width and largest parameter (:func:`_element_table`),
    half width, the 2 p knots about its span, the weights and the geometry coefficients
    (x, then y) of its p + 1 functions."""
    table = _POINT_TABLES.get(basis)
    if table is None:
        lo, width, bound, spans = _element_table(basis)
        p = basis.degree
        knots, weights = basis.curve.knots, basis.curve.weights
        window = knots[np.arange(1 - p, p + 1)[:, None] + spans]
        first = spans - p
        local_weights = weights[first + np.arange(p + 1)[:, None]]
        coefficients = basis.geometry_coefficients[basis.connectivity.T]  # (p + 1, el, 2)
        table = np.vstack(
            [lo, width, bound, 0.5 * width, window, local_weights,
             coefficients[..., 0], coefficients[..., 1]]
        )  # fmt: skip
        _POINT_TABLES[basis] = table
    return table


#: ``_point_table`` per discretised segment (weak keys: it goes with the segment)
_POINT_TABLES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _element_table(basis: NurbsBasis) -> tuple[np.ndarray, ...]:
    """Per element: its start, its width, the largest parameter evaluated in it, its knot
    span (computed once per discretised segment).

    Each point takes its element's knot span (no search); it is evaluated at most at the
    largest float below hi - 1e-13 (hi - lo) (the last element: up to its end), where the
    span search of the curve's own evaluation would still find this element.
    """
    table = _TABLES.get(basis)
    if table is None:
        knots = basis.curve.knots
        lo, hi = basis.element_bounds.T
        width = hi - lo
        bound = np.where(
            hi < knots[-1], np.minimum(hi - 1e-13 * width, np.nextafter(hi, -np.inf)), np.inf
        )
        spans = np.searchsorted(knots, lo, side="right") - 1
        table = _TABLES[basis] = (lo.copy(), width, bound, spans)
    return table


#: ``_element_table`` per discretised segment (weak keys: it goes with the segment)
_TABLES: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()
