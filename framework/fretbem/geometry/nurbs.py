"""Exact NURBS curves: evaluation, normals, knot insertion and degree elevation."""

from __future__ import annotations

import math
import threading

import attrs
import numpy as np

from fretbem.numerics.scatter import added_at
from fretbem.validators import finite, float_array, shape

from . import knots as kv


def bspline_basis(
    knots: np.ndarray, degree: int, xi: np.ndarray, span: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The p + 1 non-zero B-spline functions at each ``xi`` and their first derivatives.

    Returns ``(values, derivatives, first)``: arrays of shape (m, p + 1) holding the functions
    ``first[k] .. first[k] + p`` at ``xi[k]``; right-continuous at knots. ``span`` (the knot
    span of each point, e.g. its element's) skips the search. The NURBS Book's A2.2 (values)
    and eq. 2.9 (derivatives from degree p - 1), vectorised over points one function at a
    time (1-D arrays; the 2 p knots about each span gathered at once): 3-9x faster than
    scipy's ``BSpline.design_matrix`` (whose sparse output must be unpacked to element-local
    blocks), measured in benchmarks/bspline_basis.py, and is tested against it.
    """
    values, derivatives, first = _bspline_columns(knots, degree, xi, span)
    return np.stack(values, axis=1), np.stack(derivatives, axis=1), first


def _bspline_columns(
    knots: np.ndarray, degree: int, xi: np.ndarray, span: np.ndarray | None = None
) -> tuple[list[np.ndarray], list[np.ndarray], np.ndarray]:
    """``bspline_basis`` as lists of p + 1 columns (1-D arrays over the points): every
    operation runs along the points, none along the short function axis."""
    knots = np.asarray(knots, dtype=float)
    xi = np.atleast_1d(np.asarray(xi, dtype=float))
    xi = np.minimum(np.maximum(xi, knots[0]), knots[-1])  # np.clip's result, 3x faster
    n = knots.size - degree - 1
    if span is None:
        span = np.minimum(np.maximum(np.searchsorted(knots, xi, side="right") - 1, degree), n - 1)
    # knots span + 1 - p .. span + p, one row each: the recursion's and the derivatives'
    window = knots[np.arange(1 - degree, degree + 1)[:, None] + span]
    values, derivatives = bspline_from_window(window, degree, xi)
    return values, derivatives, span - degree


def bspline_from_window(window, degree: int, xi: np.ndarray) -> tuple[list, list]:
    """The recursion of ``_bspline_columns`` from each point's 2 p knots about its span
    (``window[i]``: knot span + 1 - p + i at every point) and its clipped ``xi``: the p + 1
    values and derivatives, as lists of columns (a caller that gathers the knots with other
    per-element data, :class:`fretbem_nurbs.basis.NurbsBasis`, saves their own gather)."""
    left = [None] + [xi - window[degree - j] for j in range(1, degree + 1)]
    right = [None] + [window[degree - 1 + j] - xi for j in range(1, degree + 1)]
    values = [np.ones(xi.size)]
    lower = values
    for j in range(1, degree + 1):
        if j == degree:
            lower = values  # the degree p - 1 functions, for derivatives
        saved = 0.0
        new = []
        for r in range(j):
            temp = values[r] / (right[r + 1] + left[j - r])
            new.append(saved + right[r + 1] * temp)
            saved = left[j - r] * temp
        new.append(saved)
        values = new
    # d N_r = p N_{r-1, p-1} / (k[s + r] - k[s + r - p]) - p N_{r, p-1} / (k[s + r + 1] - ...)
    derivatives = []
    derivative = 0.0
    for r in range(degree + 1):
        term = degree * lower[r] / (window[degree + r] - window[r]) if r < degree else 0.0
        derivatives.append(derivative - term)  # an array: degree >= 1
        derivative = term
    return values, derivatives


def rational_basis(
    knots: np.ndarray,
    degree: int,
    weights: np.ndarray,
    xi: np.ndarray,
    span: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Local NURBS functions R (paper eq. 4) and dR/dxi, as ``bspline_basis`` returns them.

    Column by column (``_bspline_columns``): the weight sums are added in function order,
    the arithmetic of a sum along the function axis, without its short inner loops.
    """
    values, derivatives, first = _bspline_columns(knots, degree, xi, span)
    rational, drational = rational_columns(
        values, derivatives, [weights[first + r] for r in range(degree + 1)]
    )
    return np.stack(rational, axis=1), np.stack(drational, axis=1), first


def rational_columns(values: list, derivatives: list, weights: list) -> tuple[list, list]:
    """R and dR/dxi as lists of columns from the B-spline columns and each point's weights
    of its p + 1 functions (``rational_basis``'s arithmetic, without its stacking)."""
    weighted = [v * w for v, w in zip(values, weights, strict=True)]
    dweighted = [d * w for d, w in zip(derivatives, weights, strict=True)]
    total, dtotal = weighted[0].copy(), dweighted[0].copy()
    for r in range(1, len(weighted)):
        total += weighted[r]
        dtotal += dweighted[r]
    squared = total**2
    pairs = zip(weighted, dweighted, strict=True)
    return [w / total for w in weighted], [(dw * total - w * dtotal) / squared for w, dw in pairs]


#: control points up to which refinement solves densely: below it LAPACK on the full matrix
#: beats building a sparse one (0.1 ms against 1 ms at 60 points), above it the banded
#: sparse LU keeps refinement linear in the control points (80 000 DOFs in 0.4 s)
DENSE_REFINE_MAX = 400


def _collocation_matrix(basis: tuple, sites: int, n_functions: int, *, dense=False):
    """Matrix of all B-spline functions at the first ``sites`` points of ``basis`` (the
    ``bspline_basis`` triple) for refinement: CSC or dense.

    Each row has degree + 1 non-zeros, so refining to n control points costs O(n p^2)
    memory and time instead of the O(n^2) / O(n^3) of a dense interpolation solve.
    """
    values, first = basis[0][:sites], basis[2][:sites]
    local = values.shape[1]
    rows = np.repeat(np.arange(sites), local)
    cols = (first[:, None] + np.arange(local)).ravel()
    shape = (sites, n_functions)
    if dense:
        return added_at(shape, (rows, cols), values.ravel())
    from scipy import sparse

    return sparse.csc_array((values.ravel(), (rows, cols)), shape=shape)


def _curve_points(basis: tuple, homogeneous: np.ndarray) -> np.ndarray:
    """Curve points at the points of ``basis`` (the ``bspline_basis`` triple) from the
    homogeneous control points (w x, w y, w)."""
    values, _, first = basis
    hom = np.einsum("ma,mak->mk", values, homogeneous[first[:, None] + np.arange(values.shape[1])])
    return hom[:, :2] / hom[:, 2:]


def sample_points(curves, xi: np.ndarray) -> list[np.ndarray]:
    """Points of each curve at the same parameters ``xi``, shape (m, 2) each: curves on the
    same knot vector (a shape's arcs, its lines) share one basis evaluation."""
    xi = np.asarray(xi, dtype=float)
    bases: dict = {}
    out = []
    for curve in curves:
        key = (curve.degree, curve.knots.tobytes())
        if key not in bases:
            bases[key] = bspline_basis(curve.knots, curve.degree, xi)
        out.append(_curve_points(bases[key], curve._homogeneous()))
    return out


def _refinement_operator(
    knots: np.ndarray, degree: int, new_knots: np.ndarray, new_degree: int
) -> tuple[np.ndarray, tuple, tuple]:
    """T (Pw_new = T @ Pw_old) from one spline space to a finer one, and the basis triples of
    both at the probes of the refinement's check (the Greville sites first); see
    :meth:`NurbsCurve.refine`. Knot insertion into a space holding the old one is
    :func:`_insertion_operator`'s, exact by construction (the triples None: no check).

    T depends on the knot vectors and degrees only, not on the curve: the segments of a
    scene refined alike (a body's sides, the faces' contact arcs) share one solve. Kept in
    :data:`_OPERATORS` up to ``DENSE_REFINE_MAX`` sites.
    """
    key = (degree, knots.tobytes(), new_degree, new_knots.shape, new_knots.tobytes())
    operator = _OPERATORS.get(key)
    if operator is not None:
        return operator
    kv.check(new_knots, new_degree, new_knots.size - new_degree - 1)
    if new_degree == degree and _contains(new_knots, knots):
        operator = (_insertion_operator(knots, degree, new_knots), None, None)
        operator[0].setflags(write=False)
        if operator[0].shape[0] <= DENSE_REFINE_MAX:
            with _OPERATORS_LOCK:
                if len(_OPERATORS) >= 256:
                    _OPERATORS.pop(next(iter(_OPERATORS)))
                _OPERATORS[key] = operator
        return operator
    if new_degree < degree or new_knots[0] != knots[0] or new_knots[-1] != knots[-1]:
        raise ValueError(
            f"refinement must keep the domain {(float(knots[0]), float(knots[-1]))} and may "
            f"not lower the degree ({degree} -> {new_degree})"
        )
    sites = kv.greville(new_knots, new_degree)
    # check away from the interpolation sites too: midpoints of every span of both vectors
    breaks = kv.breakpoints(np.concatenate([new_knots, knots]))
    probes = np.concatenate([sites, 0.5 * (breaks[1:] + breaks[:-1])])
    # one basis evaluation per knot vector serves the solve (its first rows, the sites)
    # and the check (all rows); the functions at a point do not depend on the others
    new_basis = bspline_basis(new_knots, new_degree, probes)
    old_basis = bspline_basis(knots, degree, probes)
    dense = sites.size <= DENSE_REFINE_MAX
    new_matrix = _collocation_matrix(new_basis, sites.size, sites.size, dense=dense)
    old_matrix = _collocation_matrix(old_basis, sites.size, knots.size - degree - 1, dense=True)
    try:  # banded (Schoenberg-Whitney): a sparse LU is linear in the control points
        if dense:
            transform = np.linalg.solve(new_matrix, old_matrix)
        else:
            from scipy.sparse.linalg import splu

            transform = splu(new_matrix).solve(old_matrix)
    except (RuntimeError, np.linalg.LinAlgError):  # "Factor is exactly singular"
        transform = np.full(old_matrix.shape, np.nan)
    if not np.all(np.isfinite(transform)):
        raise ValueError(
            "knots closer than round-off make the refined space degenerate; merge them"
        )
    transform[np.abs(transform) < 1e-14] = 0.0
    operator = (transform, new_basis, old_basis)
    for array in (transform, *new_basis, *old_basis):
        array.setflags(write=False)
    if dense:
        with _OPERATORS_LOCK:  # sweeps may build scenes in threads
            if len(_OPERATORS) >= 256:  # the oldest goes first
                _OPERATORS.pop(next(iter(_OPERATORS)))
            _OPERATORS[key] = operator
    return operator


def _contains(new_knots: np.ndarray, knots: np.ndarray) -> bool:
    """Whether the sorted ``new_knots`` hold every knot of the sorted ``knots`` at least as
    often on the same domain (the spline space of one degree on them then holds the old)."""
    if new_knots[0] != knots[0] or new_knots[-1] != knots[-1]:
        return False
    have = np.searchsorted(new_knots, knots, side="right") - np.searchsorted(new_knots, knots)
    need = np.searchsorted(knots, knots, side="right") - np.searchsorted(knots, knots)
    return bool(np.logical_and.reduce(have >= need))


def _insertion_operator(knots: np.ndarray, degree: int, new_knots: np.ndarray) -> np.ndarray:
    """T (Pw_new = T @ Pw_old) of knot insertion, ``new_knots`` holding ``knots``: each new
    control point is the blossom of the old curve's piece about its Greville abscissa at its
    p interior knots (de Boor's recursion, one argument per level: the Oslo algorithm of
    Cohen, Lyche and Riesenfeld 1980), vectorised over the new control points. The exact
    refinement: the rows are convex weights, the refined curve the old one to round-off."""
    p = degree
    n_old = knots.size - p - 1
    n_new = new_knots.size - p - 1
    greville = kv.greville(new_knots, p)
    span = np.minimum(np.maximum(np.searchsorted(knots, greville, side="right") - 1, p), n_old - 1)
    window = knots[np.arange(1 - p, p + 1)[:, None] + span]  # row r: knot span + 1 - p + r
    # weights[r, a]: the weight of P_{span - p + a} in de Boor's point r (unit at the start)
    weights = np.repeat(np.eye(p + 1)[:, :, None], n_new, axis=2)
    for level in range(1, p + 1):
        # points level .. p mix their predecessors at tau_{i + level} over the old knots
        # span - p + r .. span + 1 + r - level
        low, high = window[level - 1 : p], window[p : 2 * p + 1 - level]
        alpha = ((new_knots[level : level + n_new] - low) / (high - low))[:, None, :]
        weights[level:] = (1.0 - alpha) * weights[level - 1 : p] + alpha * weights[level:]
    transform = np.zeros((n_new, n_old))
    transform[np.arange(n_new)[:, None], span[:, None] - p + np.arange(p + 1)] = weights[p].T
    transform[np.abs(transform) < 1e-14] = 0.0
    return transform


#: refinement operators by (degree, knots, new degree, new knots): see _refinement_operator
_OPERATORS: dict = {}
_OPERATORS_LOCK = threading.Lock()


@attrs.frozen(eq=False)
class NurbsCurve:
    """A planar NURBS curve on an open knot vector.

    Attributes
    ----------
    degree : int
        Polynomial degree p >= 1.
    knots : ndarray, shape (n + p + 1,)
        Open (clamped) non-decreasing knot vector.
    control_points : ndarray, shape (n, 2)
    weights : ndarray, shape (n,)
        Strictly positive weights (all ones for a B-spline).
    """

    degree: int = attrs.field(converter=lambda d: int(d) if float(d).is_integer() else d)
    knots: np.ndarray = attrs.field(converter=float_array, validator=finite)
    control_points: np.ndarray = attrs.field(
        converter=float_array, validator=[shape(None, 2), finite]
    )
    weights: np.ndarray = attrs.field(converter=float_array, validator=[shape(None), finite])

    def __attrs_post_init__(self) -> None:
        kv.check(self.knots, self.degree, len(self.control_points))
        if self.weights.shape != (len(self.control_points),):
            raise ValueError(
                f"NurbsCurve needs one weight per control point: {len(self.control_points)} "
                f"control points but {self.weights.size} weights"
            )
        if np.any(self.weights <= 0):
            i = int(np.argmax(self.weights <= 0))
            raise ValueError(
                f"NURBS weight {i} is {self.weights[i]}; weights must be > 0 (a zero or negative "
                "weight puts the curve through infinity); use positive weights"
            )

    # -- constructors -----------------------------------------------------------------------
    @classmethod
    def exact_image(cls, source: NurbsCurve, knots, control_points, weights) -> NurbsCurve:
        """A curve of ``source``'s degree whose arrays an exact transformation of the valid
        ``source`` gave (reversed, reflected, averaged with its mirror: as many control
        points and weights, finite, positive weights, an open knot vector): the fields as the
        converters make them (read-only float copies) without the checks, which such arrays
        pass by construction (a quarter of the checked construction's cost; a scene build
        makes half a dozen)."""
        if len(control_points) != len(source.control_points):  # pragma: no cover - misuse
            raise ValueError("an exact image has as many control points as its source")
        curve = object.__new__(cls)  # as _valid makes it
        object.__setattr__(curve, "degree", source.degree)
        for name, value in (("knots", knots), ("control_points", control_points),
                            ("weights", weights)):  # fmt: skip
            own = getattr(source, name)
            # an array of the source itself (read-only, its own copy) is shared, not copied
            object.__setattr__(curve, name, own if value is own else float_array(value))
        return curve

    @classmethod
    def _valid(cls, degree: int, knots, control_points, weights) -> NurbsCurve:
        """A curve from arrays valid by construction: the fields as the converters make them
        (read-only float copies), without the checks."""
        curve = object.__new__(cls)
        object.__setattr__(curve, "degree", degree)
        object.__setattr__(curve, "knots", float_array(knots))
        object.__setattr__(curve, "control_points", float_array(control_points))
        object.__setattr__(curve, "weights", float_array(weights))
        return curve

    @classmethod
    def line(cls, start, end, *, degree: int = 1) -> NurbsCurve:
        """Straight segment from ``start`` to ``end`` (equally spaced control points)."""
        start, end = np.asarray(start, float), np.asarray(end, float)
        s = np.linspace(0.0, 1.0, degree + 1)[:, None]
        knots = [0.0] * (degree + 1) + [1.0] * (degree + 1)  # kv.open_uniform(degree, 1)
        points = start + s * (end - start)
        if (
            type(degree) is int
            and degree >= 1
            and points.shape == (degree + 1, 2)
            and np.logical_and.reduce(np.isfinite(points), axis=None)
        ):  # an open knot vector, unit weights, finite points: valid by construction
            return cls._valid(degree, knots, points, [1.0] * (degree + 1))
        return cls(degree, knots, points, [1.0] * (degree + 1))  # the checks name the field

    @classmethod
    def arc(cls, center, radius: float, start_angle: float, end_angle: float) -> NurbsCurve:
        """Exact circular arc as a rational quadratic, split into pieces of at most 90 degrees.

        Angles in radians; the arc runs counter-clockwise if ``end_angle > start_angle``.
        """
        if not (radius > 0 and math.isfinite(radius)):
            raise ValueError(f"arc radius must be finite and > 0, got {radius!r}")
        sweep = end_angle - start_angle
        if sweep == 0 or abs(sweep) > 2 * math.pi:
            raise ValueError(f"arc sweep must be in (0, 2 pi] in magnitude, got {sweep!r}")
        pieces = max(1, math.ceil(abs(sweep) / (math.pi / 2) - 1e-12))
        half = sweep / pieces / 2
        cx, cy = (float(c) for c in np.asarray(center, float))
        points, weights = [], []  # in Python floats: the same IEEE operations as on arrays

        def at(scale, angle):
            return (cx + scale * math.cos(angle), cy + scale * math.sin(angle))

        for i in range(pieces):
            a0 = start_angle + 2 * i * half
            mid = a0 + half
            if i == 0:
                points.append(at(radius, a0))
                weights.append(1.0)
            points.append(at(radius / math.cos(half), mid))
            weights.append(math.cos(half))
            a1 = a0 + 2 * half
            points.append(at(radius, a1))
            weights.append(1.0)
        inner = [k / pieces for k in range(1, pieces) for _ in range(2)]
        knots = [0.0, 0.0, 0.0, *inner, 1.0, 1.0, 1.0]
        if not all(math.isfinite(c) for point in points for c in point):
            return cls(2, knots, points, weights)  # the checks name the field
        # open knots, 2 pieces + 1 points, weights 1 and cos(half) >= cos(pi / 4) > 0: valid
        # by construction, so without the checks (36 us of the 46 an arc took; a scene
        # build draws half a dozen)
        return cls._valid(2, knots, points, weights)

    # -- evaluation -------------------------------------------------------------------------
    @property
    def domain(self) -> tuple[float, float]:
        """Parameter interval of the curve."""
        return float(self.knots[0]), float(self.knots[-1])

    @property
    def n_control_points(self) -> int:
        """Number of control points."""
        return len(self.control_points)

    def _homogeneous(self) -> np.ndarray:
        """Control points in homogeneous form (w x, w y, w), shape (n, 3)."""
        out = np.empty((len(self.weights), 3))
        np.multiply(self.control_points, self.weights[:, None], out=out[:, :2])
        out[:, 2] = self.weights
        return out

    def _homogeneous_at(self, xi):
        """Homogeneous point (w x, w y, w) and its derivative at ``xi``, each (m, 3)."""
        values, derivatives, first = bspline_basis(self.knots, self.degree, np.ravel(xi))
        hom = self._homogeneous()[first[:, None] + np.arange(self.degree + 1)]
        return np.einsum("ma,mak->mk", values, hom), np.einsum("ma,mak->mk", derivatives, hom)

    def points(self, xi) -> np.ndarray:
        """Curve points C(xi), shape xi.shape + (2,)."""
        # the homogeneous point as _homogeneous_at sums it (the same numbers), without the
        # derivative it also forms
        values, _, first = _bspline_columns(self.knots, self.degree, np.ravel(xi))
        hom = self._homogeneous()[first[:, None] + np.arange(self.degree + 1)]
        hom = np.einsum("ma,mak->mk", np.stack(values, axis=1), hom)
        return (hom[:, :2] / hom[:, 2:]).reshape(*np.shape(xi), 2)

    def derivatives(self, xi) -> np.ndarray:
        """First derivatives dC/dxi (quotient rule on homogeneous coordinates)."""
        hom, dhom = self._homogeneous_at(xi)
        point = hom[:, :2] / hom[:, 2:]
        return ((dhom[:, :2] - dhom[:, 2:] * point) / hom[:, 2:]).reshape(*np.shape(xi), 2)

    def points_and_derivatives(self, xi) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`points` and :meth:`derivatives` at once, from one basis evaluation (the
        same values, bit for bit: a Newton step on the curve needs both)."""
        hom, dhom = self._homogeneous_at(xi)
        point = hom[:, :2] / hom[:, 2:]
        derivative = (dhom[:, :2] - dhom[:, 2:] * point) / hom[:, 2:]
        return point.reshape(*np.shape(xi), 2), derivative.reshape(*np.shape(xi), 2)

    def jacobians(self, xi) -> np.ndarray:
        """|dC/dxi|: arc length per unit parameter."""
        return np.linalg.norm(self.derivatives(xi), axis=-1)

    def normals(self, xi) -> np.ndarray:
        """Unit normals to the right of the direction of travel (outward on a CCW boundary)."""
        d = self.derivatives(xi)
        return np.stack([d[..., 1], -d[..., 0]], axis=-1) / np.linalg.norm(d, axis=-1)[..., None]

    def basis_functions(self, xi) -> tuple[np.ndarray, np.ndarray]:
        """Rational basis R_i(xi) and dR_i/dxi as dense (m, n) arrays (paper eq. 4)."""
        values, derivatives, first = rational_basis(self.knots, self.degree, self.weights, xi)
        rows = np.arange(len(first))[:, None]
        cols = first[:, None] + np.arange(self.degree + 1)
        dense = np.zeros((2, len(first), self.n_control_points))
        dense[0][rows, cols] = values
        dense[1][rows, cols] = derivatives
        return dense[0], dense[1]

    # -- refinement -------------------------------------------------------------------------
    def refine(self, new_knots: np.ndarray, new_degree: int | None = None):
        """The same curve in a finer spline space, and the matrix T with Pw_new = T @ Pw_old.

        The new space (``new_knots``, ``new_degree``) must contain the old one. Knot
        insertion (same degree, every old knot kept) takes the Oslo algorithm; a degree
        elevation interpolates the homogeneous control points at the new Greville abscissae
        and checks the curve is kept (both exact up to round-off).
        """
        degree = self.degree if new_degree is None else int(new_degree)
        new_knots = np.asarray(new_knots, float)
        transform, new_basis, old_basis = _refinement_operator(
            self.knots, self.degree, new_knots, degree
        )
        transform = transform.copy()
        old_hom = self._homogeneous()
        hom = transform @ old_hom
        if new_basis is None:  # knot insertion: exact; convex rows keep the weights > 0
            # valid by construction: the knots passed kv.check when the operator was made,
            # the points and weights are convex combinations of this valid curve's
            refined = NurbsCurve._valid(degree, new_knots, hom[:, :2] / hom[:, 2:], hom[:, 2])
            return refined, transform
        refined = NurbsCurve(degree, new_knots, hom[:, :2] / hom[:, 2:], hom[:, 2])
        # the check is the curve's own: a space that lacks the old one may still hold a curve
        new_points = _curve_points(new_basis, refined._homogeneous())
        mismatch = np.max(np.abs(new_points - _curve_points(old_basis, old_hom)))
        size = np.ptp(self.control_points, axis=0).max()
        if mismatch > 1e-9 * max(size, 1.0):
            raise ValueError(
                "the requested knots/degree do not contain the curve's spline space (knots may "
                "only be added and multiplicities only raised); refinement would change the curve"
            )
        return refined, transform

    def insert_knots(self, values) -> tuple[NurbsCurve, np.ndarray]:
        """h-refinement: insert knot ``values`` (curve unchanged); returns (curve, T)."""
        values = np.atleast_1d(np.asarray(values, float))
        lo, hi = self.domain
        if np.any((values <= lo) | (values >= hi)):
            raise ValueError(f"inserted knots must lie strictly inside the domain ({lo}, {hi})")
        return self.refine(kv.insert(self.knots, values))

    def elevate_degree(self, times: int = 1) -> tuple[NurbsCurve, np.ndarray]:
        """p-refinement: raise the degree ``times`` times (curve unchanged); returns (curve, T)."""
        if int(times) != times or times < 0:
            raise ValueError(f"elevate_degree needs a whole number of times >= 0, got {times!r}")
        knots = self.knots
        for _ in range(times):
            knots = kv.elevate(knots)
        return self.refine(knots, self.degree + times)

    def reparametrised(self, domain: tuple[float, float] = (0.0, 1.0)) -> NurbsCurve:
        """The same curve with its knots mapped linearly onto ``domain``."""
        lo, hi = self.domain
        if (lo, hi) == (domain[0], domain[1]):  # the map is the identity: the curve itself
            return self
        knots = domain[0] + (self.knots - lo) * (domain[1] - domain[0]) / (hi - lo)
        return attrs.evolve(self, knots=knots)

    def flattened(self, y: float = 0.0) -> NurbsCurve:
        """A straight curve at height ``y`` with this curve's x(xi).

        Same knots and weights, control points (x_i, y): the face of a flat that a curved
        face can be paired with node to node (equal refinement gives facing points).
        """
        points = np.column_stack(
            [self.control_points[:, 0], np.full(self.n_control_points, float(y))]
        )
        return attrs.evolve(self, control_points=points)

    def reversed(self) -> NurbsCurve:
        """The same curve traversed the other way (normals flip)."""
        lo, hi = self.domain
        return NurbsCurve.exact_image(
            self, (lo + hi) - self.knots[::-1], self.control_points[::-1], self.weights[::-1]
        )
