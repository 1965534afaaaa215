"""Loading by displacement: the pad's block driven by delta or by the approach (issue 22).

Displacement control must give the force-control solution where both exist, hold the pad
in gross slip (Q = +-f P while sliding) and come back through partial slip on reversal.
Tolerances: measured values in the comments, with a margin.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

from fretbem.contact.control import Rig
from fretbem.scenes.builder import build
from fretbem.scenes.spec import SceneFileError, scene_from_dict
from fretbem.simulation import GrossSlidingError, LoadHistoryError, LoadStep, Simulation, run
from fretbem.solvers.pivoting import LemkeSolver
from fretbem.verification.checks import TangentialIndeterminacyError, tangential_hold
from fretbem.verification.closed_forms import SlidingPath

P, F = 100.0, 0.3


@functools.cache
def simulation(model: str, basis: str, pairs: int):
    """A Hertz scene of ``model`` bodies, prepared once (steps A: P, B: Q = 18)."""
    data = {
        "pad": {"model": model},
        "specimen": {"model": model},
        "contact": {"pairs": pairs, "basis": basis, "friction": F},
        "load": {"steps": ["A", "B"], "P": P, "Q": [0.0, 18.0]},
    }
    sim, _ = build(scene_from_dict(data))
    sim.prepare()
    return sim


def on(base: Simulation, steps, reference=True) -> Simulation:
    return Simulation(
        base.pair, steps, base.solver, law=base.law,
        reference=base.reference if reference else None,
    )  # fmt: skip


CASES = [("half-plane", "nurbs", 21), ("half-plane", "lagrange2", 31), ("bem", "nurbs", 21),
         ("bem", "lagrange2", 31)]  # fmt: skip


@pytest.mark.parametrize(("model", "basis", "pairs"), CASES)
@pytest.mark.parametrize("ratio", [0.3, 0.8])
def test_displacement_control_reproduces_force_control(model, basis, pairs, ratio):
    """delta of a force-controlled step, imposed, gives back its Q and tractions
    (measured: Q to 4e-15 relative, q to 1e-11 f p0)."""
    base = simulation(model, basis, pairs)
    q = ratio * F * P
    forced = run(on(base, (LoadStep("A", P), LoadStep("B", P, q, increments=3))))["B"]
    assert forced.controls.tangential == "force"
    driven = run(on(base, (LoadStep("A", P), LoadStep("B", P, delta=forced.delta, increments=3))))
    step = driven["B"]
    assert step.controls.tangential == "displacement"
    assert step.tangential == pytest.approx(q, rel=1e-9)
    assert step.delta == pytest.approx(forced.delta, rel=1e-12)
    fp0 = F * base.reference.hertz.peak_pressure
    assert np.max(np.abs(step.shear - forced.shear)) < 1e-8 * fp0
    assert np.array_equal(step.states, forced.states)
    assert step.errors["e_q_max"] == pytest.approx(forced.errors["e_q_max"], abs=1e-8)


@pytest.mark.parametrize(("model", "basis", "pairs"), CASES)
def test_approach_control_reproduces_the_normal_load(model, basis, pairs):
    """The approach of P = 100 N/mm, imposed, gives P back (measured 1e-14 relative)."""
    base = simulation(model, basis, pairs)
    pressed = run(on(base, (LoadStep("A", P),)))["A"]
    assert pressed.approach > 0
    driven = run(on(base, (LoadStep("A", None, approach=pressed.approach),), reference=False))
    assert driven["A"].normal == pytest.approx(P, rel=1e-9)
    assert driven["A"].controls.normal == "displacement"
    np.testing.assert_allclose(
        driven["A"].pressure, pressed.pressure, atol=1e-8 * pressed.pressure.max()
    )


@pytest.mark.parametrize(("model", "basis", "pairs"), CASES)
def test_gross_slip_plateau_and_reversal(model, basis, pairs):
    """Beyond the sliding displacement Q stays at f P while every contact pair slips; a
    reversal goes back through partial slip (stick pairs return) to -f P.

    Plateau: half-plane exact (measured 1e-15 f P); BEM within the equilibrium tolerance
    of the finite bodies (measured 4.4e-4 f P at 21 nurbs pairs, 2.3e-4 at 31 lagrange2)."""
    base = simulation(model, basis, pairs)
    slide = run(on(base, (LoadStep("A", P), LoadStep("B", P, 0.999 * F * P, increments=4))))
    d = slide["B"].delta
    steps = (LoadStep("A", P), LoadStep("B", P, delta=2 * d, increments=8),
             LoadStep("C", P, delta=-2 * d, increments=16))  # fmt: skip
    result = run(Simulation(base.pair, steps, law=base.law, reference=SlidingPath(base.reference)))
    if model == "half-plane":  # Q reaches f P: the plain closed form does not follow it
        plain = run(on(base, steps))
        assert plain["B"].errors is None and plain["A"].errors is not None
    plateau = 1e-12 if model == "half-plane" else 1e-3
    sliding = [i for s in result.steps for i in s.increments if not np.any(i.states == 1)]
    assert sliding, "no increment slid"
    for inc in sliding:
        assert abs(inc.tangential) == pytest.approx(F * inc.normal, rel=plateau)
    b, c = result["B"], result["C"]
    assert b.tangential == pytest.approx(F * P, rel=plateau)
    assert c.tangential == pytest.approx(-F * P, rel=plateau)
    assert b.count("stick") == 0 and c.count("stick") == 0
    # the first reversal increment sticks everywhere the contact is closed, Q falls
    first = c.increments[0]
    assert first.tangential < F * P * (1 - 1e-3)
    assert np.count_nonzero(first.states == 1) > np.count_nonzero(first.states == 2)
    # under displacement control nothing but the block holds the pad: the check passes
    assert b.checks["tangential_hold"].passed
    # sliding: q = f p at every pair, and the closed form along the clamped path (q = f p
    # of Hertz) is off by the pressure's own error only
    fp0 = F * base.reference.hertz.peak_pressure
    assert np.max(np.abs(b.shear - F * b.pressure)) < 1e-9 * fp0
    assert b.errors["e_q_max"] == pytest.approx(b.errors["e_p_max"], rel=1e-6)


def test_force_control_still_refuses_gross_sliding_and_no_stick():
    """Force control keeps refusing |Q| >= f P; the hold check still fails without a stick
    pair unless the block is held by displacement."""
    base = simulation("half-plane", "nurbs", 21)
    with pytest.raises(GrossSlidingError, match="gross sliding"):
        on(base, (LoadStep("A", P), LoadStep("B", P, F * P)))
    x = np.linspace(-1, 1, 5)
    slipping = np.array([0, 2, 2, 2, 0])
    with pytest.raises(TangentialIndeterminacyError, match="no pair sticks"):
        tangential_hold(x, slipping, P, F * P, F)
    assert tangential_hold(x, slipping, P, F * P, F, held=True).passed


def test_bad_displacement_steps_are_refused():
    base = simulation("half-plane", "nurbs", 21)
    with pytest.raises(LoadHistoryError, match=r"both Q = 5\.0 and delta"):
        LoadStep("B", P, 5.0, delta=0.001)
    with pytest.raises(LoadHistoryError, match="exactly one of them"):
        LoadStep("B", P, approach=0.01)
    with pytest.raises(LoadHistoryError, match="exactly one of them"):
        LoadStep("B", None)
    with pytest.raises(ValueError, match=r"LoadStep\.delta must be finite"):
        LoadStep("B", P, delta=float("nan"))
    with pytest.raises(LoadHistoryError, match=r"first load step \('A'.*delta = 0.001"):
        on(base, (LoadStep("A", P, delta=0.001),))
    with pytest.raises(LoadHistoryError, match="LemkeSolver solver does not take"):
        Simulation(base.pair, (LoadStep("A", P), LoadStep("B", P, delta=1e-3)), LemkeSolver(),
                   law=base.law)  # fmt: skip


def _scene(**load):
    return {"pad": {"model": "half-plane"}, "specimen": {"model": "half-plane"},
            "contact": {"pairs": 21}, "load": {"steps": ["A", "B"], **load}}  # fmt: skip


def test_scene_keys_delta_and_approach():
    """[load] delta / approach build displacement-controlled steps; bad use is refused."""
    scene = scene_from_dict(_scene(P=100.0, delta=[0.0, 0.004], increments=[1, 4]))
    sim, reason = build(scene)
    assert reason is None
    assert [s.controls.tangential for s in sim.steps] == ["displacement"] * 2
    assert [s.delta for s in sim.steps] == [0.0, 0.004]
    result = run(sim)
    assert result["B"].tangential == pytest.approx(F * P, rel=1e-9)  # slides beyond 2.4 um
    with pytest.raises(SceneFileError, match=r"\[load\] gives both Q and delta"):
        scene_from_dict(_scene(Q=[0.0, 1.0], delta=[0.0, 0.1]))
    with pytest.raises(SceneFileError, match=r"\[load\] gives both P and approach"):
        scene_from_dict(_scene(P=100.0, approach=0.01))
    with pytest.raises(SceneFileError, match=r"\[load\] delta\[1\] must be an integer or a number"):
        scene_from_dict(_scene(delta=[0.0, "x"]))
    with pytest.raises(SceneFileError, match=r"\[load\] approach has 3 values for 2 steps"):
        scene_from_dict(_scene(approach=[0.01, 0.01, 0.01]))
    approach = scene_from_dict(_scene(approach=0.006, delta=[0.0, 0.0005]))
    with pytest.raises(SceneFileError, match="zone_width"):
        build(approach)
    with_zone = scene_from_dict(
        {**_scene(approach=0.006, delta=[0.0, 0.0005]), "contact": {"pairs": 21, "zone_width": 0.6}}
    )
    sim, reason = build(with_zone)
    assert "approach is imposed" in reason
    result = run(sim)
    assert 0 < result["A"].normal < 200 and result["B"].normal == pytest.approx(result["A"].normal)


@pytest.mark.parametrize(("model", "basis", "pairs"), CASES[:1] + CASES[2:3])
def test_rig_springs_add_their_travel(model, basis, pairs):
    """With springs k_t, k_n between actuator and block, the actuator's delta = the block's
    + Q / k_t and approach + P / k_n; the contact sees the same Q (measured 1e-14)."""
    base = simulation(model, basis, pairs)
    forced = run(on(base, (LoadStep("A", P), LoadStep("B", P, 18.0, increments=2))))
    k_t, k_n = 2.0e4, 5.0e4
    rig = Rig(tangential=k_t, normal=k_n)
    steps = (LoadStep("A", None, approach=forced["A"].approach + P / k_n),
             LoadStep("B", None, approach=forced["A"].approach + P / k_n,
                      delta=forced["B"].delta + 18.0 / k_t, increments=2))  # fmt: skip
    sim = Simulation(base.pair, steps, law=base.law, rig=rig)
    result = run(sim)
    assert result["A"].normal == pytest.approx(P, rel=1e-9)
    assert result["B"].tangential == pytest.approx(18.0, rel=1e-9)
    assert result["B"].delta == pytest.approx(forced["B"].delta + 18.0 / k_t, rel=1e-12)
    np.testing.assert_allclose(result["B"].shear, forced["B"].shear, atol=1e-8 * P)
    # force control ignores the springs; a rigid rig is the default
    assert run(Simulation(base.pair, forced.simulation.steps, law=base.law, rig=rig))[
        "B"
    ].delta == pytest.approx(forced["B"].delta + 18.0 / k_t, rel=1e-12)
    with pytest.raises(ValueError, match=r"Rig\.tangential must be > 0"):
        Rig(tangential=0.0)


def test_rig_table_in_the_scene_file():
    data = {**_scene(P=100.0, delta=[0.0, 0.004]), "rig": {"stiffness_x": 1.0e4}}
    sim, _ = build(scene_from_dict(data))
    assert sim.rig == Rig(tangential=1.0e4)
    result = run(sim)
    b = result["B"]
    assert b.tangential < F * P  # the springs took 30 / 1e4 = 3 um of the 4 um: still sticking
    assert b.delta == pytest.approx(0.004, rel=1e-12)
    assert b.increments[-1].delta == pytest.approx(0.004, rel=1e-12)
    with pytest.raises(SceneFileError, match=r"\[rig\] stiffness_y must be > 0"):
        scene_from_dict({**_scene(P=100.0), "rig": {"stiffness_y": 0.0}})
    with pytest.raises(SceneFileError, match=r"unknown key \['rotation'\] in \[rig\]"):
        scene_from_dict({**_scene(P=100.0), "rig": {"rotation": 1.0}})


@pytest.mark.parametrize("model", ["bem", "half-plane"])
def test_measured_moment_is_the_moment_about_the_rig_s_pivot(model):
    """measure's M (the pivot kept per problem and height, the resultant base shared) is
    rotation.moment_about's at rotation.pivot, for two pivot heights in turn."""
    from fretbem.contact import control
    from fretbem.contact import rotation as pad_rotation

    problem = simulation(model, "nurbs", 31).prepare()
    state = run(simulation(model, "nurbs", 31)).steps[-1]
    x, beta = np.asarray(state.unknowns), problem.amplitudes(state.loads)
    for height in (None, 2.0, None):
        rig = Rig(pivot_height=height)
        target = pad_rotation.pivot(problem, height)
        expected = pad_rotation.moment_about(problem, x, beta, target)
        assert control.measure(problem, x, beta, rig)["moment"] == expected
        assert np.array_equal(control._pivot(problem, height), target)
    assert np.isfinite(expected)
