"""NURBS basis: the geometry's own functions, Greville collocation, h- and p-refinement."""

from __future__ import annotations

import weakref

import numpy as np

from fretbem.basis import Basis, Refinement
from fretbem.geometry import knots as kv
from fretbem.geometry.nurbs import NurbsCurve, rational_basis


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
        elements = np.asarray(elements, dtype=np.intp)
        lo, width, bound, spans = _element_table(self)
        width = width[elements]
        xi = lo[elements] + (np.asarray(local, float) + 1.0) * 0.5 * width
        xi = np.minimum(xi, bound[elements])
        values, derivatives, _ = rational_basis(
            self.curve.knots, self.degree, self.curve.weights, xi, spans[elements]
        )
        return values, derivatives * (0.5 * width)[:, None]


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
