"""The alternative to the gap offset, for comparison: the worn face refitted as NURBS.

The face's exact curve, refined at the breakpoints of its elements, has its control points
fitted by least squares (weights and knots kept, so the fit is linear) to the face moved
inward by the wear depth. The fit error is what a refitted boundary would carry into the
solution; a refit also needs the body re-assembled and re-factorised after every jump.
docs/explanation/wear.rst compares both on one case.
"""

from __future__ import annotations

import itertools

import attrs
import numpy as np

from fretbem.body import Body
from fretbem.geometry.nurbs import NurbsCurve

__all__ = ["FaceRefit", "refit_face"]


@attrs.frozen(eq=False)
class FaceRefit:
    """A worn face refitted as NURBS.

    Attributes
    ----------
    curve : NurbsCurve
        The fitted curve.
    error : float
        Largest normal distance (mm) between the fitted curve and the worn face, sampled
        between the fitting points.
    depth : float
        Largest wear depth of the face (mm), the scale of ``error``.
    """

    curve: NurbsCurve
    error: float
    depth: float


def _worn_points(curve: NurbsCurve, xi: np.ndarray, x: np.ndarray, depth: np.ndarray):
    points, normals = curve.points(xi), curve.normals(xi)
    h = np.interp(points[:, 0], x, depth, left=0.0, right=0.0)
    return points - h[:, None] * normals, normals


def refit_face(
    body: Body, tag: str, x: np.ndarray, depth: np.ndarray, samples: int = 8
) -> FaceRefit:
    """Fit the face ``tag`` of ``body`` worn by ``depth`` (mm, at abscissae x, increasing)
    with the face's curve refined at its element breakpoints; ``samples`` fitting points
    per knot span."""
    curve = body.face_curve(tag)
    _, segment = body.face_segment(tag)
    breaks = np.unique(np.asarray(segment.element_bounds).ravel())
    inner = breaks[1:-1]
    present = np.unique(curve.knots)
    new = inner[np.min(np.abs(inner[:, None] - present[None, :]), axis=1) > 1e-12]
    refined, _ = curve.insert_knots(new) if new.size else (curve, None)
    spans = np.unique(refined.knots)
    fit_xi = np.concatenate(
        [np.linspace(a, b, samples, endpoint=False) for a, b in itertools.pairwise(spans)]
        + [spans[-1:]]
    )
    target, _ = _worn_points(refined, fit_xi, x, depth)
    basis, _ = refined.basis_functions(fit_xi)
    control, *_ = np.linalg.lstsq(basis, target, rcond=None)
    fitted = attrs.evolve(refined, control_points=control)
    check_xi = 0.5 * (fit_xi[1:] + fit_xi[:-1])
    target, normals = _worn_points(refined, check_xi, x, depth)
    error = np.abs(np.einsum("kd,kd->k", fitted.points(check_xi) - target, normals))
    return FaceRefit(fitted, float(error.max()), float(np.max(depth, initial=0.0)))
