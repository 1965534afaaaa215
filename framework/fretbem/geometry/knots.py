"""Knot-vector utilities: check, generate, refine (pure functions on arrays)."""

from __future__ import annotations

import numpy as np

from fretbem.errors import InputError


class KnotVectorError(InputError):
    """A knot vector that cannot define an open (clamped) spline curve."""


def check(knots: np.ndarray, degree: int, n_control_points: int) -> None:
    """Raise KnotVectorError unless ``knots`` is an open knot vector for this degree and size.

    Open (clamped) vectors make the curve interpolate its end control points, which the
    boundary's closedness check and the segment-wise discretisation rely on.
    """
    knots = np.asarray(knots, dtype=float)
    if int(degree) != degree or degree < 1:
        raise KnotVectorError(f"degree must be an integer >= 1, got {degree!r}")
    # (the ufunc reductions called directly: np.all, np.any and np.diff's own frames cost more
    # than the work on a knot vector, and a scene build checks a dozen)
    if knots.ndim != 1 or not np.logical_and.reduce(np.isfinite(knots), axis=None):
        raise KnotVectorError(f"knot vector must be a 1-D array of finite numbers, got {knots!r}")
    expected = n_control_points + degree + 1
    if knots.size != expected:
        raise KnotVectorError(
            f"knot vector has {knots.size} entries but degree {degree} with {n_control_points} "
            f"control points needs n + p + 1 = {expected}; add or remove knots or control points"
        )
    steps = knots[1:] - knots[:-1]
    if np.logical_or.reduce(steps < 0):
        where = int(np.argmax(steps < 0))
        raise KnotVectorError(
            f"knot vector must be non-decreasing, but knot {where + 1} ({knots[where + 1]}) < "
            f"knot {where} ({knots[where]}); sort the knots"
        )
    if knots[-1] <= knots[0]:
        raise KnotVectorError("knot vector spans an empty parameter interval; knots must increase")
    # non-decreasing: the first p + 1 knots are equal when the (p + 1)-th is the first
    if knots[degree] != knots[0] or knots[-degree - 1] != knots[-1]:
        raise KnotVectorError(
            f"knot vector must be open (first and last knots repeated degree + 1 = {degree + 1} "
            f"times) so the curve starts and ends at its end control points; got {knots!r}"
        )
    # sorted now: a knot repeated more than p times equals the knot p places on
    interior = knots[degree + 1 : -degree - 1]
    repeated = interior[degree:] == interior[:-degree]
    if np.logical_or.reduce(repeated):
        bad = interior[degree:][repeated][0]
        raise KnotVectorError(
            f"interior knot {bad} is repeated more than degree = {degree} times, which makes the "
            "curve discontinuous; split it into two segments instead"
        )


def open_uniform(degree: int, n_elements: int, domain: tuple[float, float] = (0.0, 1.0)):
    """Open knot vector with ``n_elements`` equal knot spans on ``domain``."""
    breaks = np.linspace(domain[0], domain[1], n_elements + 1)
    return from_breakpoints(breaks, degree)


def from_breakpoints(breakpoints: np.ndarray, degree: int) -> np.ndarray:
    """Open knot vector with the given distinct breakpoints, interior ones simple (C^{p-1})."""
    breakpoints = np.asarray(breakpoints, dtype=float)
    return np.concatenate(
        [np.repeat(breakpoints[0], degree), breakpoints, np.repeat(breakpoints[-1], degree)]
    )


def breakpoints(knots: np.ndarray) -> np.ndarray:
    """Distinct knot values: the element boundaries (np.unique's values, 5x faster on the
    few dozen knots of a segment: a scene build asks for them some 50 times)."""
    knots = np.sort(np.asarray(knots, dtype=float).ravel())
    keep = np.empty(knots.size, dtype=bool)
    keep[:1] = True
    np.not_equal(knots[1:], knots[:-1], out=keep[1:])
    return knots[keep]


def greville(knots: np.ndarray, degree: int) -> np.ndarray:
    """Greville abscissae: averages of ``degree`` consecutive interior knots (one per function)."""
    knots = np.asarray(knots, dtype=float)
    n = knots.size - degree - 1
    total = knots[1 : n + 1].copy()  # the windows' sums in order, as a mean adds them
    for j in range(2, degree + 1):
        total += knots[j : n + j]
    # an average of equal end knots can land one ulp outside the domain
    return np.minimum(np.maximum(total / degree, knots[0]), knots[-1])


def insert(knots: np.ndarray, new_knots: np.ndarray) -> np.ndarray:
    """Knot vector with ``new_knots`` merged in (the refined spline space contains the old one)."""
    return np.sort(np.concatenate([np.asarray(knots, float), np.asarray(new_knots, float)]))


def elevate(knots: np.ndarray) -> np.ndarray:
    """Knot vector of the once degree-elevated space: every distinct knot gains one multiplicity."""
    return np.sort(np.concatenate([np.asarray(knots, float), breakpoints(knots)]))
