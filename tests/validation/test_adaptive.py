"""Adaptive contact meshes and the two-level error estimate (issue 12).

Tolerances are the errors measured on the shared 2-core machine (November 2026) plus a
margin; see docs/explanation/adaptive.rst for the numbers and what is not yet reached.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from fretbem import adaptive, estimate
from fretbem.basis import Refinement
from fretbem.geometry.nurbs import NurbsCurve
from fretbem.scenes import cattaneo_mindlin
from fretbem.simulation import run
from fretbem_lagrange.quadratic import QuadraticLagrangeBasis
from fretbem_nurbs.basis import NurbsBasis

KEYS = ("e_p_max", "e_q_max", "e_p_l2", "e_q_l2")


def worst(result) -> dict[str, float]:
    return {k: max(s.errors[k] for s in result.steps) for k in KEYS}


def exact_transitions(simulation) -> np.ndarray:
    """+-a, +-c (step B) and +-c' (unloading) of the reference cycle, from the closed form."""
    a = simulation.reference.hertz.half_width
    f, load = estimate.friction_of(simulation), simulation.steps[0].normal
    q = max(abs(s.tangential) for s in simulation.steps)
    c = a * math.sqrt(1 - q / (f * load))
    c2 = a * math.sqrt(1 - q / (2 * f * load))
    return np.array([-a, -c2, -c, c, c2, a])


# -- the refinement record ------------------------------------------------------------------
def test_explicit_breakpoints_with_c0_put_a_greville_point_on_the_knot():
    curve = NurbsCurve.arc([0.0, 70.0], 70.0, -1.6, -1.5)
    basis = NurbsBasis.discretise(curve, Refinement.explicit([0, 0.3, 0.5, 1], c0_at=[0.5]))
    assert np.count_nonzero(basis.curve.knots == 0.5) == 2
    assert np.any(np.isclose(basis.natural_collocation, 0.5, atol=1e-14))
    np.testing.assert_allclose(basis.element_bounds[:, 0], [0, 0.3, 0.5])


@pytest.mark.parametrize("family", [NurbsBasis, QuadraticLagrangeBasis])
def test_explicit_breakpoints_keep_the_geometry_and_partition_of_unity(family):
    curve = NurbsCurve.arc([0.0, 70.0], 70.0, -1.6, -1.5)
    basis = family.discretise(curve, Refinement.explicit([0, 0.1, 0.45, 0.7, 1.0], c0_at=[0.7]))
    np.testing.assert_allclose(basis.element_bounds[:, 0], [0, 0.1, 0.45, 0.7])
    params = np.linspace(0.0, 1.0, 41)
    matrix = basis.evaluation_matrix(params)
    np.testing.assert_allclose(matrix.sum(axis=1), 1.0, atol=1e-12)
    elements, local = basis.to_local(params)
    points = basis.geometry(elements, local)[0]
    # exact for NURBS; quadratic interpolation of the 7 mm arc for Lagrange (measured 3.6e-5)
    np.testing.assert_allclose(points, curve.points(params), atol=1e-4)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"elements": 3, "at": (0.0, 0.5, 1.0)},
        {"elements": 2, "at": (0.0, 0.6, 0.5, 1.0)},
        {"elements": 2, "at": (0.1, 0.5, 1.0)},
        {"elements": 2, "at": (0.0, 0.5, 1.0), "c0_at": (0.3,)},
    ],
)
def test_bad_explicit_refinements_are_refused_by_name(kwargs):
    with pytest.raises(ValueError, match="Refinement"):
        Refinement(**kwargs)


def test_aligned_breakpoints_count_anchor_and_grade():
    anchors = np.array([0.2, 0.33, 0.67, 0.8])
    bounds = adaptive.aligned_breakpoints(anchors, 40, ratio=10.0)
    assert bounds.size == 41 and bounds[0] == 0.0 and bounds[-1] == 1.0
    assert np.all(np.diff(bounds) > 0)
    for t in anchors:
        assert np.min(np.abs(bounds - t)) < 1e-12
    sizes = np.diff(bounds)
    assert 6.0 < sizes.max() / sizes.min() < 16.0
    centred = adaptive.aligned_breakpoints(anchors, 40, ratio=4.0, centred=True)
    mids = 0.5 * (centred[1:] + centred[:-1])
    for t in anchors:
        assert np.min(np.abs(mids - t)) < 1e-12


def test_settings_refuse_bad_input():
    with pytest.raises(adaptive.AdaptiveError, match="tolerance"):
        adaptive.AdaptiveSettings(tolerance=2.0)
    with pytest.raises(adaptive.AdaptiveError, match="budget"):
        adaptive.AdaptiveSettings(budget=3)
    with pytest.raises(adaptive.AdaptiveError, match="max_levels"):
        adaptive.AdaptiveSettings(max_levels=1)


# -- meshes aligned with the transitions ------------------------------------------------------
def test_remesh_keeps_pairs_facing_and_puts_points_on_transitions():
    simulation = cattaneo_mindlin(pairs=31)
    exact = exact_transitions(simulation)
    fine = adaptive.remesh(simulation, exact, 45, ratio=10.0)
    x = estimate.pair_frame(fine.pair)[0][:, 0]
    assert x.size <= 45
    for t in exact:
        assert np.min(np.abs(x - t)) < 1e-9 * simulation.reference.hertz.half_width


def test_aligned_meshes_converge_without_sawtooth():
    """Transitions on C0 knots: errors fall with pairs (measured 1.05/3.26 % at 45 pairs,
    1.14/1.80 % at 61, ratio 10) where the uniform zone jumps 0.3 -> 6 %."""
    simulation = cattaneo_mindlin(pairs=31)
    exact = exact_transitions(simulation)
    errors = {n: worst(run(adaptive.remesh(simulation, exact, n, ratio=10.0))) for n in (45, 61)}
    assert errors[61]["e_q_max"] < 0.021
    assert errors[61]["e_q_l2"] < 0.0035
    assert errors[61]["e_p_max"] < 0.014
    assert errors[61]["e_q_l2"] < errors[45]["e_q_l2"]


# -- transitions found from a solve and the adaptive loop -------------------------------------
@pytest.mark.parametrize("pairs", [31, 41, 45])
def test_transitions_found_near_the_closed_form(pairs):
    """From a uniform zone (the first level): measured edges within 0.36 % of a before the
    0.3 % outward margin (0.66 % after), stick-slip boundaries within 1.5 % of a."""
    simulation = cattaneo_mindlin(pairs=pairs)
    exact = exact_transitions(simulation)
    a = simulation.reference.hertz.half_width
    found = adaptive.transitions(run(simulation)).all
    assert found.size == exact.size
    np.testing.assert_allclose(found[[0, -1]], exact[[0, -1]], atol=8e-3 * a)
    np.testing.assert_allclose(found[1:-1], exact[1:-1], atol=2.5e-2 * a)


def test_adaptive_run_reference_scene():
    """Budget 61 on the reference scene: measured e_p 0.71 %, e_q 1.88 %, e_q L2 0.28 %."""
    out = adaptive.run_adaptive(cattaneo_mindlin(pairs=31), adaptive.AdaptiveSettings(budget=61))
    assert out.result.steps[0].x.size <= 61
    e = worst(out.result)
    assert e["e_p_max"] < 0.009
    assert e["e_q_max"] < 0.022
    assert e["e_q_l2"] < 0.0035
    assert set(out.estimate) == {s.name for s in out.result.steps}
    for name, est in out.estimate.items():
        assert set(est) == set(KEYS)
        true = out.result[name].errors
        # the estimate does not miss a large error: never below half the true max error
        for key in ("e_p_max", "e_q_max"):
            if true[key] > 1e-3:
                assert est[key] > 0.5 * true[key], (name, key, est[key], true[key])


def test_edge_knot_carries_no_pressure_after_correction():
    """The edge iteration brings the pressure at the point on each edge knot to ~0: the
    knot sits on the discrete contact edge (P = 250: 0.9981 a, half-plane a = 1)."""
    load = 250.0
    simulation = cattaneo_mindlin(
        pairs=31, normal=load, tangential=(0.0, 0.18 * load, 0.0, -0.18 * load, 0.0)
    )
    out = adaptive.run_adaptive(simulation)
    p0 = simulation.reference.hertz.peak_pressure
    knots = adaptive.knot_pressures(out.result, out.transitions[-1].edges)
    assert np.all(knots < 0.005 * p0)


def test_estimate_of_identical_levels_is_zero_and_order_is_checked():
    simulation = cattaneo_mindlin(pairs=31)
    result = run(simulation)
    change = estimate.difference(result, result)
    assert max(max(c.values()) for c in change) < 1e-10
    with pytest.raises(estimate.EstimateInputError, match="fine level"):
        estimate.estimate_errors(result, result)
    assert estimate.richardson_factor(31, 61) == pytest.approx(1 / ((61 / 31) ** 3 - 1))


def _reference_with_load(load: float):
    q = 0.18 * load
    return cattaneo_mindlin(pairs=31, normal=load, tangential=(0.0, q, 0.0, -q, 0.0))


@pytest.mark.parametrize("budget", [41, 81])
def test_adaptive_meets_the_targets_at_budgets_off_the_lucky_counts(budget):
    """41 put a node on the edge in the fixed mode (6.05 %); measured adaptive: 41: e_p
    0.72 %, e_q 1.10 %, e_q L2 0.24 %; 81 stops at 61 pairs (estimate 1.85 % < 2 %)."""
    out = adaptive.run_adaptive(
        _reference_with_load(100.0), adaptive.AdaptiveSettings(budget=budget)
    )
    e = worst(out.result)
    assert out.result.steps[0].x.size <= 61
    assert e["e_p_max"] <= 0.01 and e["e_q_max"] <= 0.02 and e["e_q_l2"] <= 0.005


@pytest.mark.slow
@pytest.mark.parametrize("budget", range(39, 122))
def test_adaptive_sweep_over_budgets_reference_load(budget):
    """Budgets 39..121 on the reference scene (benchmarks/adaptive_sawtooth.py): measured
    worst e_p 1.07 % (budgets 57, 58), e_q 1.88 %, e_q L2 0.28 %, never more than 61 pairs.
    The e_p target of 1 % is missed by 0.07 points at 57 and 58 pairs."""
    out = adaptive.run_adaptive(
        _reference_with_load(100.0), adaptive.AdaptiveSettings(budget=budget)
    )
    e = worst(out.result)
    assert out.result.steps[0].x.size <= 61
    assert e["e_p_max"] < 0.0115 and e["e_q_max"] < 0.02 and e["e_q_l2"] < 0.005


@pytest.mark.slow
@pytest.mark.parametrize("budget", range(31, 39))
def test_adaptive_small_budgets_are_reported_not_reached(budget):
    """Budgets 31..38 cannot resolve six transitions: measured e_q max 3.7 to 5.6 %."""
    out = adaptive.run_adaptive(
        _reference_with_load(100.0), adaptive.AdaptiveSettings(budget=budget)
    )
    e = worst(out.result)
    assert e["e_p_max"] < 0.012 and e["e_q_max"] < 0.065


@pytest.mark.slow
@pytest.mark.parametrize("load", [60.0, 150.0, 250.0])
@pytest.mark.parametrize("budget", [41, 61, 81, 121])
def test_adaptive_sweep_over_load(budget, load):
    """Other loads: at P = 250 the BEM's own contact edge lies 0.2 % of a inside the
    half-plane one (finite bodies) and a point on it sees 6.2 % of p0 of half-plane
    pressure; these bounds guard the measured state (docs/explanation/adaptive.rst)."""
    out = adaptive.run_adaptive(
        _reference_with_load(load), adaptive.AdaptiveSettings(budget=budget)
    )
    e = worst(out.result)
    assert e["e_p_max"] < 0.08 and e["e_q_max"] < 0.08


def test_table_and_summary_show_estimate_beside_true_error():
    out = adaptive.run_adaptive(
        cattaneo_mindlin(pairs=31), adaptive.AdaptiveSettings(budget=31, first=21)
    )
    table = out.table()
    assert "levels (pairs)" in table and len(table.splitlines()) == 2 + len(out.result.steps)
    summary = out.summary()
    assert summary["levels"][0] == 21 and summary["levels"][-1] <= 31
    assert set(summary["estimate"]) == {s.name for s in out.result.steps}
