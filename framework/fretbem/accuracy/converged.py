"""Errors of a level against a converged solution of the same scene, and that solution.

The adaptive mode's error is verified against a much finer solution of the same bodies
(:func:`reference`), not against half-plane theory, which finite bodies differ from by
more than the discretisation error near the contact edges (docs/explanation/adaptive.rst).
Near a transition the reference's own field between its points cannot follow the square
root (its element there has the reference's size), so :func:`errors_against` reports the
maxima away from the transitions beside the maxima everywhere.
"""

from __future__ import annotations

import numpy as np

from fretbem.verification.errors import l2

from . import estimate
from .adaptive import AdaptiveSettings, run_adaptive

__all__ = [
    "INTERPOLATORY_REFERENCE_BUDGET",
    "NEAR",
    "REFERENCE_BUDGET",
    "SECOND_BUDGET",
    "errors_against",
    "reference",
    "resolution",
]

#: pairs of the converged reference: NURBS faces 321 points, faces of an interpolatory
#: family (quadratic Lagrange) 241 (chosen when graded faces above about 360 points still
#: oscillated; that defect is fixed, docs/explanation/adaptive.rst, "Limits", and the
#: recorded benchmarks keep these references)
REFERENCE_BUDGET = 321
INTERPOLATORY_REFERENCE_BUDGET = 241

#: points closer than this many reference point spacings to a reference knot are "near"
NEAR = 2.0

#: pairs of the second converged solution that measures the reference's own resolution
#: (:func:`resolution`), per reference budget: about 7/8 of it
SECOND_BUDGET = {REFERENCE_BUDGET: 281, INTERPOLATORY_REFERENCE_BUDGET: 201}


def _reference_budget(simulation) -> int:
    pair = simulation.pair
    smooth = not any(
        getattr(body.family, "interpolatory", False) for body in (pair.upper, pair.lower)
    )
    return REFERENCE_BUDGET if smooth else INTERPOLATORY_REFERENCE_BUDGET


def reference(simulation, budget: int | None = None):
    """The converged solution: the adaptive mode at ``budget`` pairs with no early stop
    (levels of about 31, 61, 121 and ``budget`` pairs, knots settled on each). Returns its
    :class:`~fretbem.accuracy.adaptive.AdaptiveResult`."""
    if budget is None:
        budget = _reference_budget(simulation)

    return run_adaptive(simulation, AdaptiveSettings(budget=budget, tolerance=1e-9, max_levels=4))


def resolution(simulation, converged, budget: int | None = None) -> dict[str, float]:
    """How well ``converged`` (from :func:`reference`) knows the answer: the errors (keys of
    :func:`errors_against`) of a second converged solution of ``budget`` pairs (default
    :data:`SECOND_BUDGET` of the scene's reference budget) against it. An error against
    the reference is known to about this much, so a rise between two budgets smaller than
    twice it is not a measured rise (the band of ``benchmarks/adaptive_budgets.py`` and of
    the tests)."""
    if budget is None:
        budget = SECOND_BUDGET[_reference_budget(simulation)]
    return errors_against(reference(simulation, budget).result, converged)


def errors_against(result, converged) -> dict[str, float]:
    """Max over the steps of the error of ``result`` against ``converged`` (an
    AdaptiveResult), at ``result``'s own points, in units of p0 and f p0.

    Keys: ``p_max``, ``q_max`` (every point), ``p_far``, ``q_far`` (points farther than
    :data:`NEAR` reference spacings from every reference knot), ``p_l2``, ``q_l2``.
    """
    best = converged.result
    knots = converged.transitions[-1].all if converged.transitions else np.zeros(0)
    p0, fp0 = estimate.scales(best)
    fields = estimate.traction_fields(best)
    x = estimate.positions(result)
    order = np.argsort(x)
    xr = np.sort(estimate.positions(best))
    spacing = np.diff(xr)[np.clip(np.searchsorted(xr, x) - 1, 0, xr.size - 2)]
    if knots.size:
        far = np.min(np.abs(x[:, None] - knots[None, :]), axis=1) > NEAR * spacing
    else:
        far = np.ones(x.size, bool)
    out = dict.fromkeys(("p_max", "q_max", "p_far", "q_far", "p_l2", "q_l2"), 0.0)
    for field, step in zip(fields, result.steps, strict=True):
        po, qo = field(x)
        dp, dq = np.abs(step.pressure - po) / p0, np.abs(step.shear - qo) / fp0
        values = {
            "p_max": dp.max(),
            "q_max": dq.max(),
            "p_far": dp[far].max(initial=0.0),
            "q_far": dq[far].max(initial=0.0),
            "p_l2": l2(dp[order], x[order]),
            "q_l2": l2(dq[order], x[order]),
        }
        for key, value in values.items():
            out[key] = max(out[key], float(value))
    return out
