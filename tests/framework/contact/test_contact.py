"""The fretting cycle on the reference scene against Mindlin-Deresiewicz (issue: contact).

Tolerances are the values measured at 61 pairs (given in the comments) plus a margin;
the paper's 4.104 % and the 2 % pressure bound are the acceptance thresholds.
"""

import numpy as np
import pytest

from fretbem.contact.pairs import ContactDiscretisationError, NodeToNodePair
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import GrossSlidingError, LoadHistoryError, LoadStep, Simulation, run
from fretbem.solvers.newton import NewtonConvergenceError, SemiSmoothNewton

PAPER_MAX_ERROR = 0.04104


@pytest.fixture(scope="module", params=["nurbs", "lagrange2"])
def cycle(request):
    return run(cattaneo_mindlin(basis=request.param, pairs=61))


def test_equilibrium_integrals(cycle):
    """int p dx = P and int q dx = Q to 0.1 % at every step (measured 5e-5 and 4e-4)."""
    for step in cycle.steps:
        assert step.resultant[0] == pytest.approx(step.normal, rel=1e-3)
        assert abs(step.resultant[1] - step.tangential) <= 1e-3 * 18.0


def test_step_a_has_no_shear(cycle):
    """Similar bodies under normal load only: q = 0 (measured 1e-13 f p0)."""
    fp0 = 0.3 * cycle.simulation.reference.hertz.peak_pressure
    assert np.max(np.abs(cycle["A"].shear)) < 1e-8 * fp0


def test_reversal_mirrors(cycle):
    """Step D is the mirror of step B and E of C (measured 1e-12 f p0)."""
    fp0 = 0.3 * cycle.simulation.reference.hertz.peak_pressure
    np.testing.assert_allclose(cycle["B"].x, -cycle["B"].x[::-1], atol=1e-12)
    for loaded, mirrored in (("B", "D"), ("C", "E")):
        np.testing.assert_allclose(cycle[mirrored].shear, -cycle[loaded].shear, atol=1e-8 * fp0)
        np.testing.assert_allclose(
            cycle[mirrored].pressure, cycle[loaded].pressure, atol=1e-8 * fp0
        )


def test_friction_cone_and_states(cycle):
    """|q| <= f p everywhere; slip pairs sit on the cone, separated pairs carry nothing."""
    for step in cycle.steps:
        assert np.all(np.abs(step.shear) <= 0.3 * step.pressure + 1e-9)
        slip = step.states == 2
        np.testing.assert_allclose(np.abs(step.shear[slip]), 0.3 * step.pressure[slip], rtol=1e-9)
        separated = step.states == 0
        assert np.all(np.abs(step.pressure[separated]) < 1e-12)
        assert np.all(np.abs(step.shear[separated]) < 1e-12)


def test_nurbs_beats_the_paper():
    """NURBS at 61 pairs: e_q below 4.104 % at B-E (measured 1.68/4.00) and e_p below 2 % (0.65)."""
    result = run(cattaneo_mindlin(basis="nurbs", pairs=61))
    for name in "BCDE":
        errors = result[name].errors
        assert errors["e_q_max"] < PAPER_MAX_ERROR
        assert errors["e_p_max"] < 0.02
        assert errors["e_q_l2"] < 0.0085  # measured 0.36 % (B) and 0.80 % (C)


def test_lagrange_errors_as_measured():
    """lagrange2 at 61 pairs: e_p 2.20 %, e_q 2.20 % (B) and 7.23 % (C), measured."""
    result = run(cattaneo_mindlin(basis="lagrange2", pairs=61))
    assert result["B"].errors["e_q_max"] < 0.025
    assert result["C"].errors["e_q_max"] < 0.075
    assert result["B"].errors["e_p_max"] < 0.025


def test_path_dependence_matches_mindlin_deresiewicz():
    """0 -> Q -> 0 leaves a locked-in shear the virgin state does not have, as M-D predicts."""
    result = run(cattaneo_mindlin(tangential=(0.0, 18.0, 0.0), names=("A", "B", "C")))
    virgin, unloaded = result["A"], result["C"]
    fp0 = 0.3 * result.simulation.reference.hertz.peak_pressure
    assert np.max(np.abs(virgin.shear)) < 1e-8 * fp0
    assert np.max(np.abs(unloaded.shear)) > 0.2 * fp0  # measured 0.26 f p0
    assert unloaded.count("slip") > 0 and unloaded.count("stick") > unloaded.count("slip")
    assert unloaded.errors["e_q_max"] < PAPER_MAX_ERROR


def test_larger_bodies_converge_in_l2():
    """On 4x larger bodies (finite-body effect removed), L2 errors fall from 61 to 121 pairs."""
    errors = [
        run(cattaneo_mindlin(pairs=pairs, width=26.0, height=65.0))["C"].errors
        for pairs in (61, 121)
    ]
    # measured: e_p L2 0.033 % -> 0.016 %, e_q L2 0.78 % -> 0.50 %
    assert errors[1]["e_p_l2"] < errors[0]["e_p_l2"] < 0.0005
    assert errors[1]["e_q_l2"] < errors[0]["e_q_l2"] < 0.009


@pytest.mark.slow
@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
def test_refinement_lowers_l2_errors(basis):
    """61 -> 121 -> 241 pairs on 4x bodies: e_p and e_q (L2) decrease at every step B-E."""
    runs = [
        run(cattaneo_mindlin(basis=basis, pairs=pairs, width=26.0, height=65.0))
        for pairs in (61, 121, 241)
    ]
    for name in "BC":
        for key in ("e_p_l2", "e_q_l2"):
            values = [r[name].errors[key] for r in runs]
            assert values[0] > values[1] > values[2], (name, key, values)


def test_flat_specimen_variant():
    """Pad on flat (R_eff = R): pressure within 2 % of Hertz (measured 1.5 %)."""
    result = run(cattaneo_mindlin(lower="flat"))
    assert result.simulation.reference.hertz.effective_radius == pytest.approx(70.0)
    assert result["B"].errors["e_p_max"] < 0.02
    assert result["B"].errors["e_q_max"] < PAPER_MAX_ERROR


def test_dissimilar_materials_report_no_errors():
    """E differing 1000x: no analytical reference, errors n/a, equilibrium and cone hold."""
    result = run(cattaneo_mindlin(E_lower=73400.0 * 1000))
    assert result.simulation.reference is None
    summary = result.summary()
    assert all(step["e_q_max"] is None for step in summary["steps"])
    assert "n/a" in result.table()
    for step in result.steps:
        assert step.resultant[0] == pytest.approx(100.0, rel=1e-3)
        assert abs(step.resultant[1] - step.tangential) < 1e-3 * 18
        assert np.all(np.abs(step.shear) <= 0.3 * step.pressure + 1e-9)


def test_gross_sliding_is_refused_before_iterating():
    """Q >= f P under force control has no equilibrium: one clear sentence, no Newton."""
    with pytest.raises(GrossSlidingError, match=r"\|Q\| = 30 >= f P = 30.*gross sliding"):
        cattaneo_mindlin(tangential=(0.0, 30.0), names=("A", "B"))


def test_first_step_must_be_normal_load():
    """A history starting with a tangential load is refused, naming the step."""
    with pytest.raises(LoadHistoryError, match=r"first load step .* pure normal load"):
        cattaneo_mindlin(tangential=(5.0, 0.0), names=("A", "B"))


def test_mismatched_discretisation_names_the_point():
    """Contact segments discretised differently cannot be paired; the error says where."""
    sim = cattaneo_mindlin()
    upper = sim.pair.upper
    other = cattaneo_mindlin(pairs=59).pair.upper
    pair = NodeToNodePair(other, sim.pair.lower)
    with pytest.raises(ContactDiscretisationError, match="collocation points"):
        _ = pair.pairing()
    assert upper is not other


def test_overlapping_bodies_are_refused():
    """An upper body pushed into the lower one is an error stating the overlap."""
    from fretbem.bem.body import BemBody
    from fretbem.geometry.boundary import Boundary, Segment

    sim = cattaneo_mindlin()
    upper = sim.pair.upper
    shifted = Boundary(
        [
            Segment(
                s.tag,
                type(s.curve)(
                    s.curve.degree,
                    s.curve.knots,
                    s.curve.control_points - [0.0, 0.01],
                    s.curve.weights,
                ),
            )
            for s in upper.boundary.segments
        ]
    )
    moved = BemBody(
        shifted,
        upper.material,
        upper.conditions,
        basis=upper.basis,
        refinement=upper.refinement,
        name="upper",
    )
    with pytest.raises(ContactDiscretisationError, match="overlap at the start"):
        _ = NodeToNodePair(moved, sim.pair.lower).pairing()


def test_newton_failure_carries_history():
    """Too few iterations and no sub-stepping: the error names pairs and suggests fixes."""
    sim = cattaneo_mindlin()
    strict = Simulation(
        sim.pair,
        sim.steps,
        SemiSmoothNewton(max_iterations=2, max_substeps=0),
        law=sim.law,
        reference=sim.reference,
    )
    with pytest.raises(NewtonConvergenceError, match="sub-increments") as info:
        run(strict)
    assert len(info.value.residuals) == 2 and info.value.changing_pairs.size > 0


def test_substeps_and_increments_agree():
    """Sub-increments inside monotonic steps reproduce the single-increment cycle."""
    one = run(cattaneo_mindlin())
    four = run(cattaneo_mindlin(increments=4))
    for a, b in zip(one.steps, four.steps, strict=True):
        np.testing.assert_allclose(a.shear, b.shear, atol=1e-8)
        assert b.iterations >= a.iterations


def test_load_step_validation():
    """Non-finite loads and zero increments are refused by the record itself."""
    with pytest.raises(ValueError, match="finite"):
        LoadStep("A", float("nan"), 0.0)
    with pytest.raises(ValueError):
        LoadStep("A", 100.0, 0.0, increments=0)
