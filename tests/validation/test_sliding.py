"""Finite sliding: a cylinder on a flat of the same material slides three contact widths in
gross slip, unloads, and slides back.

Both bodies are elastic half-planes (the pad's face a cylinder of R = 70 mm), where Hertz
and Mindlin-Deresiewicz are exact. The pad is driven by displacement (delta), so it slides
in gross slip with Q = f P; its 61 nodes are the pairs, and the flat's face is the track,
re-paired whenever the pad moves more than a pair spacing. At every position the pressure
must be Hertz's where the pad is, q = f p at every pair in contact, Q = f P; unloading to
Q = 0 after the slide must give Mindlin-Deresiewicz's unloading from full slip.
Tolerances: measured values (in the comments) plus a margin.
"""

from __future__ import annotations

import numpy as np
import pytest

from fretbem.basis import Refinement
from fretbem.contact.node_to_segment import NodeToSegmentPair
from fretbem.geometry.nurbs import NurbsCurve
from fretbem.halfplane.body import HalfPlaneBody
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import LoadStep, Simulation, run
from fretbem.sliding import SlidingError, run_sliding

P, F = 100.0, 0.3
HALF_PLANES = {"upper": "half-plane", "lower": "half-plane"}


def _base():
    return cattaneo_mindlin(pairs=61, lower="flat", models=HALF_PLANES)


def _track(base, reach: float) -> HalfPlaneBody:
    """The flat with a face from -reach to reach, nodes about as dense as the pad's."""
    a = base.reference.hertz.half_width
    return HalfPlaneBody(
        NurbsCurve.line([-reach, 0.0], [reach, 0.0], degree=1),
        base.pair.lower.material,
        side="lower",
        refinement=Refinement(elements=round(2 * reach / (3 * a / 60))),
        name="specimen",
    )


def _history(a: float):
    return (
        LoadStep("press", P, 0.0),
        LoadStep("slide", P, delta=6 * a, increments=24),
        LoadStep("unload", P, 0.0, increments=4),
        LoadStep("back", P, delta=0.0, increments=24),
    )


@pytest.fixture(scope="module")
def sliding():
    base = _base()
    a = base.reference.hertz.half_width
    pair = NodeToSegmentPair(base.pair.upper, _track(base, 9.5 * a))
    simulation = Simulation(pair, _history(a), solver=base.solver, law=base.law)
    notes = []
    return run_sliding(simulation, note=notes.append), base.reference, notes


def test_the_pairing_follows_three_contact_widths(sliding):
    """The pad reaches 6 a and comes back; the faces were paired again 48 times (each
    quarter a: five pair spacings) and the pressure is centred where the pad is."""
    result, reference, _ = sliding
    a = reference.hertz.half_width
    assert result.repairings >= 48
    assert abs(result.positions[1] - 6 * a) < 1e-9 and abs(result.positions[3]) < 1e-9
    for step, offset in zip(result.steps, result.offsets, strict=True):
        centre = np.sum(step.x * step.pressure) / np.sum(step.pressure)
        assert abs(centre - offset) < 1e-4 * a  # measured 7.5e-7 a


def test_gross_slip_is_coulomb_everywhere(sliding):
    """Sliding either way: Q = +-f P (measured 30.00017 / 30), every pair in contact slips
    with q = f p in the direction of sliding (to round-off), p Hertz's (0.40 % of p0)."""
    result, reference, _ = sliding
    hertz = reference.hertz
    for name, sign in (("slide", 1.0), ("back", -1.0)):
        step = result[name]
        offset = result.offsets[[s.name for s in result.steps].index(name)]
        assert abs(step.tangential - sign * F * P) < 1e-9 * P
        normal, shear = step.resultant
        assert abs(normal - P) < 1e-4 * P and abs(shear - sign * F * P) < 1e-4 * P
        touching = step.pressure > 0
        assert np.all(step.states[touching] == 2)  # slip
        assert np.max(np.abs(sign * step.shear - F * step.pressure)) < 1e-9 * hertz.peak_pressure
        exact = hertz.pressure(step.x - offset)
        assert np.max(np.abs(step.pressure - exact)) < 0.006 * hertz.peak_pressure


def test_unloading_after_the_slide_is_mindlin_deresiewicz(sliding):
    """Q from f P to 0 after sliding 6 a: the shear of unloading from full slip, e_q 3.95 %
    of f p0, within the fixed mode's 4.66 % on the same scene without sliding (node to
    node, 61 pairs, unloaded from 0.9999 f P); p within 0.40 % of p0 (fixed mode 0.08 %)."""
    result, reference, _ = sliding
    step, offset = result["unload"], result.offsets[2]
    hertz = reference.hertz
    exact_q = reference.shear_traction(step.x - offset, [0.0, F * P * (1 - 1e-12), 0.0])
    assert np.max(np.abs(step.shear - exact_q)) < 0.0466 * F * hertz.peak_pressure
    exact_p = hertz.pressure(step.x - offset)
    assert np.max(np.abs(step.pressure - exact_p)) < 0.006 * hertz.peak_pressure


def test_new_contact_is_reported(sliding):
    """One note for the slide: the track from the first contact's edge (a) to where the
    pad's leading edge arrives (7 a); none for sliding back over ground already touched."""
    result, reference, notes = sliding
    a = reference.hertz.half_width
    assert notes == list(result.notes) and len(notes) == 1
    assert "step 'slide'" in notes[0] and "lower face came into contact" in notes[0]
    start, end = (float(v) for v in notes[0].split("from ")[1].split(" mm")[0].split(" to "))
    spacing = 3 * a / 60  # the edges fall between pairs: measured 0.5 and 1.5 spacings off
    assert abs(start - a) < 2 * spacing and abs(end - 7 * a) < 2 * spacing


def test_repairing_keeps_the_cycle():
    """Re-paired before every increment (every = 0) or never (run): a fretting cycle in
    partial and gross slip on matching half-plane faces gives the same tractions to the
    discretisation's level (measured 0.14 % of p0 for p, 0.08 % for q; 0.30 and 0.09 % when
    the pairs followed the pad's block instead of its face)."""
    base = _base()
    pair = NodeToSegmentPair(base.pair.upper, base.pair.lower, slave="upper")
    steps = (
        LoadStep("A", P, 0.0),
        LoadStep("B", P, delta=0.004, increments=4),
        LoadStep("C", P, delta=-0.004, increments=8),
        LoadStep("D", P, 18.0, increments=4),
    )
    simulation = Simulation(pair, steps, solver=base.solver, law=base.law)
    plain = run(simulation)
    repaired = run_sliding(simulation, every=0.0, note=None)
    assert repaired.repairings >= 10
    p0 = base.reference.hertz.peak_pressure
    for one, other in zip(plain.steps, repaired.steps, strict=True):
        assert np.max(np.abs(one.pressure - other.pressure)) < 0.002 * p0
        assert np.max(np.abs(one.shear - other.shear)) < 0.001 * p0
        assert abs(one.tangential - other.tangential) < 1e-6 * P


def test_a_slide_off_the_track_is_refused():
    """Sliding the contact past the flat's end: the error says how far and what to lengthen."""
    base = _base()
    a = base.reference.hertz.half_width
    pair = NodeToSegmentPair(base.pair.upper, _track(base, 2.5 * a))
    simulation = Simulation(pair, _history(a)[:2], solver=base.solver, law=base.law)
    with pytest.raises(SlidingError, match=r"slid past the end of the other face.*lengthen"):
        run_sliding(simulation, note=None)


def test_node_to_node_cannot_slide():
    """Finite sliding needs the projection pairing."""
    with pytest.raises(SlidingError, match="NodeToSegmentPair"):
        run_sliding(cattaneo_mindlin(pairs=21), note=None)
