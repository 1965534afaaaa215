"""The adaptive mode on any scene (issue 27): larger contacts, dissimilar materials, the rig,
mixed families, and budgets 31 to 241 against a converged solution of the same bodies.

Errors are against :func:`fretbem.accuracy.converged.reference` (the adaptive mode at 321
pairs, 241 with a Lagrange face), not against half-plane theory, which these finite bodies
miss by up to 14 % of p0 at the contact edges (the model, not the mesh). Bounds are the
measured values plus a margin (``python benchmarks/adaptive_budgets.py``,
docs/results/adaptive_budgets.csv; docs/explanation/adaptive.rst has the tables).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from fretbem.accuracy import adaptive, converged
from fretbem.accuracy import modes as accuracy
from fretbem.accuracy.remesh import knots_for
from fretbem.contact.node_to_segment import NodeToSegmentPair
from fretbem.contact.pairs import NodeToNodePair
from fretbem.scenes.builder import build
from fretbem.scenes.file import load_scene
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem_lagrange.quadratic import QuadraticLagrangeBasis
from fretbem_nurbs.basis import NurbsBasis

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def from_file(name: str):
    return build(load_scene(EXAMPLES / name))[0]


def reference_scene(load: float = 100.0):
    q = 0.18 * load
    return cattaneo_mindlin(pairs=31, normal=load, tangential=(0.0, q, 0.0, -q, 0.0))


def spend(simulation, budget: int):
    """The adaptive mode with a tolerance no estimate meets: every budget is spent."""
    return adaptive.run_adaptive(
        simulation, adaptive.AdaptiveSettings(budget=budget, tolerance=1e-9)
    )


# -- what a level can place -------------------------------------------------------------------
def test_knots_a_face_can_place():
    """NURBS p = 2: a C0 knot costs a point and needs an element beside it (pairs 16, 31,
    61: 6, 14, 29 knots); quadratic Lagrange is C0 everywhere, same counts at odd pairs."""
    assert [knots_for(NurbsBasis, n, 2) for n in (16, 31, 61)] == [6, 14, 29]
    assert [knots_for(QuadraticLagrangeBasis, n) for n in (15, 31, 61)] == [6, 14, 29]


def test_transitions_merge_closest_first_and_keep_edges():
    found = adaptive.Transitions(np.array([-1.0, -0.97, 1.0]), np.array([-0.95, -0.5, -0.49, 0.5]))
    fitted = adaptive.fit_transitions(found, 5)
    # -0.5/-0.49 (0.01 apart) merge into their middle; then -0.97 edge with -0.95 boundary:
    # the edge stays
    np.testing.assert_allclose(fitted.edges, [-1.0, -0.97, 1.0])
    np.testing.assert_allclose(fitted.boundaries, [-0.495, 0.5])
    assert adaptive.fit_transitions(found, 7).all.size == 7
    assert adaptive.fit_transitions(found, 0).all.size == 0


# -- the scenes the mode refused --------------------------------------------------------------
def test_dissimilar_materials_run_and_say_where_the_estimate_stops():
    """Steel on aluminium: 18 transitions over the cycle, 14 fit a 31-pair level; the mode
    merges them (it refused before: '13 elements cannot place 16 transitions') and the
    caution says so."""
    simulation = from_file("adaptive_dissimilar.toml")
    result = accuracy.solve(simulation, accuracy.Accuracy(mesh="adaptive", budget=61))
    assert result.accuracy["levels"][-1] == 61
    assert "merged" in result.accuracy["caution"] and "caution:" in result.table()
    steps = result.steps
    assert all(s.estimate is not None for s in steps)
    # Goodman: the normal load alone gives a shear traction and slip at both edges
    first = steps[0]
    assert np.abs(first.shear).max() > 0.05 * 0.3 * first.pressure.max()
    assert (first.states == 2).sum() >= 4 and (first.states == 1).sum() >= 10


def test_wide_contact_runs_mirrored_node_to_node_or_paired_by_projection():
    """The reference bodies at P = 900 (a = 0.99 mm, 3.3 a wide): an unsymmetric layout tilts
    the pair frame and the curved faces no longer face node to node (it refused before: 'no
    facing point ... 1.1e-05 off'); such a layout is paired node to segment instead. The
    adaptive levels of these mirror-symmetric faces, whose transitions are mirrored, are
    mirrored too (adaptive.symmetric_faces): they face node to node."""
    from fretbem.accuracy.remesh import remesh

    simulation = from_file("adaptive_wide_contact.toml")
    unsymmetric = remesh(
        simulation, np.array([-0.99, -0.7, 0.7, 0.98]), 61, ratio=20.0, grading=0.06
    )
    assert isinstance(unsymmetric.pair, NodeToSegmentPair)
    assert adaptive.symmetric_faces(simulation)
    out = spend(simulation, 61)
    assert out.result.steps[0].x.size == 61
    assert {type(level.simulation.pair) for level in out.levels} == {NodeToNodePair}
    assert max(max(e["e_p_max"], e["e_q_max"]) for e in out.estimate.values()) < 0.01


def test_mixed_families_each_face_on_its_own():
    """A lagrange2 pad on a nurbs specimen (examples/mismatched_faces.toml): each face is
    laid out in its own family and parameter, paired by projection."""
    out = spend(from_file("mismatched_faces.toml"), 41)
    pair = out.result.simulation.pair
    assert isinstance(pair, NodeToSegmentPair)
    assert pair.upper.family is not pair.lower.family
    assert out.result.steps[0].x.size <= 41
    assert all(np.isfinite(e["e_q_max"]) for e in out.estimate.values())


def test_budget_above_the_verified_levels_is_capped_and_said(monkeypatch):
    monkeypatch.setattr(accuracy, "MAX_ADAPTIVE_PAIRS", 41)
    result = accuracy.solve(
        reference_scene(), accuracy.Accuracy(mesh="adaptive", budget=61, tolerance=1e-6)
    )
    assert result.accuracy["levels"][-1] == 41
    assert "capped at 41 pairs" in result.accuracy["caution"]


# -- a larger budget never gives a larger error -----------------------------------------------
def test_error_falls_with_the_budget_reference_scene():
    """P = 160 (the issue's case: 'e_p and e_q 3.0 % at budgets 71 and 83 against 0.8 to
    1.3 % at 41 to 61'): against half-plane theory the error rises with the budget because
    these bodies' contact is 0.2 % of a narrower than the half-planes' (a square root of
    6 % of p0 that finer meshes resolve); against a converged solution of the same bodies it
    falls: away from the transitions and in L2, measured 0.49 -> 0.13 % (p max) and 0.10 ->
    0.02 % (p L2) from budget 41 to 83. Reference: 161 pairs here (the slow sweep: 321)."""
    simulation = reference_scene(160.0)
    best = converged.reference(simulation, budget=161)
    runs = {b: spend(simulation, b) for b in (41, 83)}
    errors = {b: converged.errors_against(out.result, best) for b, out in runs.items()}
    for key in ("p_far", "q_far", "p_l2", "q_l2"):
        assert errors[83][key] <= errors[41][key], (key, errors)
    # matching faces stay node to node (the fast path)
    assert all(type(level.simulation.pair) is NodeToNodePair for level in runs[41].levels)
    assert errors[83]["p_far"] < 0.0025 and errors[83]["p_l2"] < 0.0008, errors


#: budgets of the slow sweep and its scenes
BUDGETS = (31, 36, 41, 51, 61, 71, 83, 101, 121, 161, 201, 241)
SCENES = {
    "ref60": lambda: reference_scene(60.0),
    "ref100": lambda: reference_scene(100.0),
    "ref160": lambda: reference_scene(160.0),
    "wide": lambda: from_file("adaptive_wide_contact.toml"),
    "mixed": lambda: from_file("mismatched_faces.toml"),
    "rig": lambda: from_file("fretting_rig.toml"),
    "dissimilar": lambda: from_file("adaptive_dissimilar.toml"),
}
#: per sweep: (scene, first budget, last budget, most error everywhere from budget 61 up,
#: measured plus a margin, fractions of p0 and f p0); the mixed faces' reference is 241
#: pairs, so their sweep stops at 201
SWEEPS = {
    "ref60": ("ref60", 31, 241, 0.006),
    "ref100": ("ref100", 31, 241, 0.006),
    "ref160": ("ref160", 31, 241, 0.006),
    "wide": ("wide", 31, 241, 0.006),
    "mixed": ("mixed", 31, 201, 0.011),
    "rig from 61": ("rig", 61, 241, 0.021),
    "rig": ("rig", 31, 241, 0.021),
    "dissimilar from 61": ("dissimilar", 61, 241, 0.05),
    "dissimilar": ("dissimilar", 31, 241, 0.05),
}
#: sweeps whose error still rises by more than the band, with the measured rises
#: (docs/results/adaptive_budgets.csv, docs/explanation/adaptive.rst, "Limits"); strict:
#: a sweep that meets the band fails here until it is moved out of this list
MISSES = {
    "dissimilar": "away: q 1.01 % at 61 pairs and p 0.94 % at 71 against 0.77 % at 51 "
    "(band 0.084 %); L2: q 1.17 % at 41 against 0.93 % at 36, p 0.50 % against 0.27 % at "
    "31 (band 0.14 %); seven more layout rules measured and left out "
    "(docs/explanation/adaptive.rst, 'Limits')",
}


def _sweep_param(name):
    if name in MISSES:
        return pytest.param(name, marks=pytest.mark.xfail(strict=True, reason=MISSES[name]))
    return name


@pytest.mark.slow
@pytest.mark.parametrize("name", [_sweep_param(n) for n in SWEEPS])
def test_error_non_increasing_with_the_budget(name):
    """Every budget of BUDGETS: away from the transitions and in L2 the error against the
    converged solution never rises over the best smaller budget's by more than the band,
    twice the converged solution's own resolution (:func:`converged.resolution`: a second
    converged solution of 281 pairs against it; each error is known to that much). The
    band is measured, not set: 0.046 to 0.059 % away and 0.021 to 0.023 % in L2 on the
    reference scene and the wide contact, 0.26 / 0.046 % on the mixed faces, 0.16 /
    0.085 % on the rig, 0.084 / 0.14 % on steel on aluminium. Everywhere (the
    reference's own element at a transition cannot follow the square root between its
    points: 0.3 to 0.5 % of p0 at 321 pairs) the error stays below the measured bound from
    budget 61 up. On the reference scene and the wide
    contact the estimate is 0.1 to 5 times the error away from the transitions wherever
    that is above 0.1 %."""
    scene, first, last, top = SWEEPS[name]
    simulation = SCENES[scene]()
    best = converged.reference(simulation)
    known = converged.resolution(simulation, best)
    bands = {
        "far": 2.0 * max(known["p_far"], known["q_far"]),
        "l2": 2.0 * max(known["p_l2"], known["q_l2"]),
    }
    rows = []
    for budget in (b for b in BUDGETS if first <= b <= last):
        out = spend(simulation, budget)
        est = {k: max(e[f"e_{k}_max"] for e in out.estimate.values()) for k in "pq"}
        rows.append((budget, converged.errors_against(out.result, best), est))
    for key in ("p_far", "q_far", "p_l2", "q_l2"):
        band = bands["l2" if key.endswith("l2") else "far"]
        values = [e[key] for _, e, _ in rows]
        for i in range(1, len(values)):
            assert values[i] <= min(values[:i]) + band, (key, rows[i][0], band, values)
    for budget, e, est in rows:
        if budget >= 61:
            assert max(e["p_max"], e["q_max"]) <= top, (budget, e)
        if scene.startswith("ref") or scene == "wide":
            for k in "pq":
                if e[f"{k}_far"] > 0.001:
                    assert 0.1 <= est[k] / e[f"{k}_far"] <= 5.0, (budget, k, est, e)
