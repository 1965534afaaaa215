"""Conformance checks for the extension points: basis families, body models and solvers.

:func:`check_basis` checks a basis family, :func:`check_body` a body model (a
:class:`~fretbem.body.Body` implementation) and :func:`check_solver` a contact solver.

A third-party family runs the same suite as the built-in ones::

    from fretbem.testing import check_basis
    from my_package import MyBasis

    def test_conformance():
        check_basis(MyBasis)

Only the public :class:`~fretbem.basis.Basis` API is used, so the checks hold for any
subclass. A failure raises ``AssertionError`` naming the family, the curve, the refinement
and the property that does not hold.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np

from fretbem.basis import Basis, Refinement
from fretbem.geometry.nurbs import NurbsCurve

from .contact import check_body, check_solver

__all__ = [
    "FD_TOL",
    "check_basis",
    "check_body",
    "check_solver",
    "default_curves",
    "default_refinements",
]

#: relative tolerance of the derivative check (fourth-order central differences, step 1e-4)
FD_TOL = 1e-8
_FD_STEP = 1e-4
#: local coordinates sampled on every element (the ends included)
_LOCAL = np.array([-1.0, -0.77, -0.31, 0.0, 0.42, 0.9, 1.0])
#: parameters where refined and coarse geometry are compared
_SAMPLES = np.linspace(0.0, 1.0, 50)


def _arc_120() -> NurbsCurve:
    """Exact 120-degree arc (radius 1.5, centre (0.5, -0.25)) as ONE rational quadratic span.

    Middle weight cos(60 deg) = 1/2; unlike :meth:`NurbsCurve.arc` it is not split at 90 deg.
    """
    center, radius, half = np.array([0.5, -0.25]), 1.5, math.pi / 3
    start, mid, end = 0.2, 0.2 + half, 0.2 + 2 * half
    points = [
        center + radius * np.array([math.cos(start), math.sin(start)]),
        center + radius / math.cos(half) * np.array([math.cos(mid), math.sin(mid)]),
        center + radius * np.array([math.cos(end), math.sin(end)]),
    ]
    return NurbsCurve(2, [0, 0, 0, 1, 1, 1], points, [1.0, math.cos(half), 1.0])


def default_curves() -> dict[str, NurbsCurve]:
    """Name -> curve on [0, 1]: a line, a one-span 120-degree arc, a quarter circle, a cubic."""
    cubic_points = [[0.0, 0.0], [1.0, 0.6], [2.1, -0.3], [3.0, 0.8], [3.6, 0.1], [4.5, 0.5]]
    return {
        "line": NurbsCurve.line([-0.5, 0.25], [1.5, 1.0]),
        "arc 120 deg": _arc_120(),
        "quarter circle": NurbsCurve.arc([0.0, 0.0], 2.0, 0.0, math.pi / 2),
        "cubic B-spline": NurbsCurve(
            3, [0, 0, 0, 0, 0.3, 0.55, 1, 1, 1, 1], cubic_points, np.ones(len(cubic_points))
        ),
    }


def default_refinements() -> tuple[Refinement, ...]:
    """Uniform 1, 3 and 7 elements, and two graded meshes (toward a point, toward an end)."""
    return (
        Refinement.uniform(1),
        Refinement.uniform(3),
        Refinement.uniform(7),
        Refinement.graded(6, 0.3, ratio=5.0),
        Refinement.graded(5, 1.0, ratio=3.0),
    )


class _Case:
    """One (family, curve, refinement) discretisation and its failure messages."""

    def __init__(self, cls: type[Basis], name: str, curve: NurbsCurve, refinement: Refinement):
        self.cls, self.name, self.curve, self.refinement = cls, name, curve, refinement
        self.basis = cls.discretise(curve, refinement)
        self.size = float(np.ptp(curve.points(np.linspace(0.0, 1.0, 65)), axis=0).max())

    def require(self, ok: bool, prop: str, detail: str) -> None:
        """Raise AssertionError naming the property unless ``ok``."""
        if not ok:
            raise AssertionError(
                f"{self.cls.__name__} (family {self.cls.name!r}) on the {self.name} with "
                f"{self.refinement!r}: {prop} fails: {detail}"
            )


def _element_samples(basis: Basis, local: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every element crossed with ``local``, as equal-length (elements, local) arrays."""
    elements = np.repeat(np.arange(basis.n_elements), local.size)
    return elements, np.tile(local, basis.n_elements)


def _check_structure(case: _Case) -> None:
    """discretise returns the class, elements tile [0, 1], connectivity covers every function."""
    b = case.basis
    case.require(isinstance(b, case.cls), "discretise", f"returned a {type(b).__name__}")
    bounds = b.element_bounds
    case.require(
        bounds[0, 0] == 0.0 and bounds[-1, 1] == 1.0,
        "element bounds cover [0, 1]",
        f"first {bounds[0, 0]}, last {bounds[-1, 1]}",
    )
    case.require(
        np.all(bounds[:, 1] > bounds[:, 0]) and np.array_equal(bounds[1:, 0], bounds[:-1, 1]),
        "elements are contiguous with positive length",
        f"bounds {bounds.tolist()}",
    )
    case.require(
        b.n_elements >= case.refinement.elements,
        "element count",
        f"{b.n_elements} elements for {case.refinement.elements} requested",
    )
    conn = b.connectivity
    case.require(
        conn.shape == (b.n_elements, b.n_local),
        "connectivity shape",
        f"{conn.shape}, expected ({b.n_elements}, n_local)",
    )
    used = np.unique(conn)
    case.require(
        np.array_equal(used, np.arange(b.n_functions)),
        "connectivity indices cover 0 .. n_functions - 1",
        f"n_functions = {b.n_functions}, indices used {used.tolist()}",
    )
    case.require(
        np.all([len(set(row)) == len(row) for row in conn.tolist()]),
        "connectivity rows are distinct",
        f"{conn.tolist()}",
    )


def _check_partition_of_unity(case: _Case, tol: float) -> None:
    """Values sum to 1 and derivatives to 0 at every sample."""
    b = case.basis
    values, derivatives = b.shape_functions(*_element_samples(b, _LOCAL))
    m = b.n_elements * _LOCAL.size
    case.require(
        values.shape == (m, b.n_local) and derivatives.shape == (m, b.n_local),
        "shape_functions output shape",
        f"values {values.shape}, derivatives {derivatives.shape}, expected ({m}, {b.n_local})",
    )
    error = np.abs(values.sum(axis=1) - 1.0).max()
    case.require(error <= tol, "partition of unity (sum phi = 1)", f"max |sum - 1| = {error:.3e}")
    scale = max(1.0, np.abs(derivatives).max())
    error = np.abs(derivatives.sum(axis=1)).max() / scale
    case.require(
        error <= tol, "partition of unity (sum dphi = 0)", f"max |sum dphi| = {error:.3e} relative"
    )


def _check_derivatives(case: _Case) -> None:
    """d/d(local) matches fourth-order central differences of the values."""
    b = case.basis
    interior = _LOCAL[np.abs(_LOCAL) < 1.0 - 3 * _FD_STEP]
    elements, local = _element_samples(b, interior)
    h = _FD_STEP

    def at(shift: float) -> np.ndarray:
        return b.shape_functions(elements, local + shift)[0]

    fd = (at(-2 * h) - 8 * at(-h) + 8 * at(h) - at(2 * h)) / (12 * h)
    _, derivatives = b.shape_functions(elements, local)
    scale = max(1.0, np.abs(derivatives).max())
    error = np.abs(fd - derivatives).max() / scale
    case.require(
        error <= FD_TOL,
        "derivatives match finite differences",
        f"max relative difference {error:.3e} > {FD_TOL:.0e}",
    )


def _check_geometry(case: _Case, tol: float) -> None:
    """Element ends on the exact curve, evaluation_matrix consistent, normals agree."""
    b, curve = case.basis, case.curve
    ends = np.array([-1.0, 1.0])
    elements, local = _element_samples(b, ends)
    points = b.geometry(elements, local)[0]
    exact = curve.points(b.element_bounds.ravel())
    error = np.abs(points - exact).max() / case.size
    case.require(
        error <= tol,
        "element ends lie on the exact curve",
        f"max distance {error:.3e} relative to the curve size",
    )
    params = np.linspace(0.0, 1.0, 37)
    via_matrix = b.evaluation_matrix(params) @ b.geometry_coefficients
    via_geometry = b.geometry(*b.to_local(params))[0]
    error = np.abs(via_matrix - via_geometry).max() / case.size
    case.require(
        error <= tol,
        "evaluation_matrix @ geometry_coefficients equals geometry()",
        f"max difference {error:.3e} relative",
    )
    elements, local = b.to_local(params)
    error = np.abs(b.to_parameter(elements, local) - params).max()
    case.require(error <= tol, "to_parameter inverts to_local", f"max difference {error:.3e}")
    _, _, _, normals = b.geometry(elements, local)
    agree = np.sum(normals * curve.normals(params), axis=1)
    case.require(
        np.all(agree > 0.5),
        "normals point to the same side as the curve's",
        f"min cos(angle) = {agree.min():.3f}",
    )


def _check_collocation(case: _Case, tol: float) -> None:
    """Collocation inside the segment; E square, nonsingular, rows sum to 1; nodality.

    For an interpolatory family E is the identity only on rows whose point was not moved:
    the shared layer moves collocation at the segment ends inward (``END_SHIFT``), where
    several functions are nonzero. Nodality is checked at ``natural_collocation`` instead.
    """
    b = case.basis
    params = b.collocation_parameters
    inside = (params > b.element_bounds[0, 0] + tol) & (params < b.element_bounds[-1, 1] - tol)
    case.require(
        bool(np.all(inside)),
        "collocation points lie strictly inside the segment",
        f"parameters {params[~inside].tolist()} are at or beyond the segment ends",
    )
    elements, local = b.collocation()
    error = np.abs(b.to_parameter(elements, local) - params).max()
    case.require(error <= tol, "collocation() matches collocation_parameters", f"max {error:.3e}")
    matrix = b.collocation_matrix()
    n = b.n_functions
    case.require(
        matrix.shape == (n, n),
        "collocation matrix E is square",
        f"shape {matrix.shape}, n_functions {n}",
    )
    condition = np.linalg.cond(matrix)
    case.require(
        condition * tol < 1.0,
        "collocation matrix E is nonsingular",
        f"condition number {condition:.3e}",
    )
    error = np.abs(matrix.sum(axis=1) - 1.0).max()
    case.require(error <= tol, "rows of E sum to 1", f"max |row sum - 1| = {error:.3e}")
    if case.cls.interpolatory:
        nodal = b.evaluation_matrix(b.natural_collocation)
        error = np.abs(nodal - np.eye(n)).max()
        case.require(
            error <= tol,
            "interpolatory family: functions are nodal at natural_collocation",
            f"max |phi_a(x_b) - delta_ab| = {error:.3e}",
        )
        kept = np.abs(params - b.natural_collocation) <= tol
        error = np.abs(matrix[kept] - np.eye(n)[kept]).max(initial=0.0)
        case.require(
            error <= tol,
            "interpolatory family: E is the identity where points were not moved off the ends",
            f"max |E - I| on those rows = {error:.3e}",
        )


def _check_point_image(case: _Case) -> None:
    """A family that declares ``odd_in_geometry`` (the default) discretises the curve's point
    image (control points negated) into the same segment with its geometry negated, and its
    map negates points, tangents and normals exactly: the BEM assembly then takes one body's
    blocks for its image's bit for bit (:mod:`fretbem.bem.images`), so this is checked to
    the last bit; a family for which it does not hold must set ``odd_in_geometry = False``."""
    cls, curve, basis = case.cls, case.curve, case.basis
    if not cls.odd_in_geometry:
        return
    image_curve = NurbsCurve(curve.degree, curve.knots, -curve.control_points + 0.0, curve.weights)
    image = cls.discretise(image_curve, case.refinement)
    same = (
        np.array_equal(image.element_bounds, basis.element_bounds)
        and np.array_equal(image.connectivity, basis.connectivity)
        and np.array_equal(image.natural_collocation, basis.natural_collocation)
        and np.array_equal(image.geometry_coefficients, -basis.geometry_coefficients + 0.0)
    )
    case.require(
        same,
        "point image (odd_in_geometry)",
        "the reflected curve's segment differs from the segment reflected; set "
        f"{cls.__name__}.odd_in_geometry = False if the family cannot keep it",
    )
    elements, local = _element_samples(basis, _LOCAL)
    mine, theirs = basis.map(elements, local), image.map(elements, local)
    exact = (
        np.array_equal(theirs.values, mine.values)
        and np.array_equal(theirs.jacobians, mine.jacobians)
        and np.array_equal(theirs.points, -mine.points)
        and np.array_equal(theirs.tangents, -mine.tangents)
        and np.array_equal(theirs.normals, -mine.normals)
    )
    case.require(
        exact,
        "point image (odd_in_geometry)",
        "map() of the reflected segment is not the map reflected bit for bit (values and "
        f"Jacobians equal, points, tangents and normals negated); set {cls.__name__}."
        "odd_in_geometry = False if the family cannot keep it",
    )


def _check_refinement(
    cls: type[Basis], name: str, curve: NurbsCurve, refinement: Refinement, tol: float
) -> None:
    """Doubling the elements keeps the coarse space and the geometry (or improves it)."""
    coarse = _Case(cls, name, curve, refinement)
    fine = _Case(cls, name, curve, Refinement(2 * refinement.elements, refinement.degree))
    # every coarse function is a combination of fine ones (nested spaces)
    local = np.linspace(-0.95, 0.95, fine.basis.n_local + 2)
    params = fine.basis.to_parameter(*_element_samples(fine.basis, local))
    target = coarse.basis.evaluation_matrix(params)
    solution, *_ = np.linalg.lstsq(fine.basis.evaluation_matrix(params), target, rcond=None)
    residual = np.abs(fine.basis.evaluation_matrix(params) @ solution - target).max()
    fine.require(
        residual <= 10 * tol,
        f"refinement invariance (the {coarse.basis.n_elements}-element space is contained)",
        f"max least-squares residual {residual:.3e}",
    )
    # geometry: exact families reproduce it, others converge toward the curve
    exact = curve.points(_SAMPLES)
    x_coarse = coarse.basis.geometry(*coarse.basis.to_local(_SAMPLES))[0]
    x_fine = fine.basis.geometry(*fine.basis.to_local(_SAMPLES))[0]
    error_coarse = np.abs(x_coarse - exact).max() / coarse.size
    error_fine = np.abs(x_fine - exact).max() / coarse.size
    if error_coarse <= 10 * tol:
        change = np.abs(x_fine - x_coarse).max() / coarse.size
        fine.require(
            change <= 10 * tol,
            "refinement invariance (exact geometry reproduced)",
            f"refined geometry moved by {change:.3e} relative",
        )
    else:
        fine.require(
            error_fine < error_coarse,
            "refinement convergence (inexact geometry approaches the curve)",
            f"error {error_coarse:.3e} -> {error_fine:.3e} on doubling the elements",
        )


def check_basis(
    cls: type[Basis],
    *,
    curves: Mapping[str, NurbsCurve] | Sequence[NurbsCurve] | None = None,
    refinements: Sequence[Refinement] | None = None,
    tol: float = 1e-10,
) -> None:
    """Assert that basis family ``cls`` satisfies the contract of :class:`Basis`.

    Parameters
    ----------
    cls : type[Basis]
        The family to check.
    curves : mapping name -> NurbsCurve, or sequence of curves, optional
        Curves to discretise (reparametrised onto [0, 1]); :func:`default_curves` if None.
    refinements : sequence of Refinement, optional
        :func:`default_refinements` if None. Uniform ones are also doubled to check
        refinement invariance.
    tol : float
        Tolerance of the exact identities (relative to the curve size for positions);
        derivatives are checked to :data:`FD_TOL` and nested spaces to ``10 * tol``.

    Raises
    ------
    AssertionError
        Naming the family, curve, refinement and failing property.
    """
    if not (isinstance(cls, type) and issubclass(cls, Basis)):
        raise TypeError(f"check_basis needs a fretbem.basis.Basis subclass, got {cls!r}")
    if curves is None:
        curves = default_curves()
    elif not isinstance(curves, Mapping):
        curves = {f"curve {k}": curve for k, curve in enumerate(curves)}
    refinements = default_refinements() if refinements is None else tuple(refinements)
    for name, curve in curves.items():
        curve = curve.reparametrised((0.0, 1.0))
        for refinement in refinements:
            case = _Case(cls, name, curve, refinement)
            _check_structure(case)
            _check_partition_of_unity(case, tol)
            _check_derivatives(case)
            _check_geometry(case, tol)
            _check_collocation(case, tol)
            _check_point_image(case)
            if refinement.toward is None or refinement.ratio == 1.0:
                _check_refinement(cls, name, curve, refinement, tol)
