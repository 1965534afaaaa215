"""Finite sliding: a cylinder on a flat of the same material slides three contact widths
under Q just below f P, then reverses and slides back.

Both bodies are elastic half-planes (the pad's face a cylinder of R = 70 mm), where Hertz
and Mindlin-Deresiewicz are exact: at every position the pressure must be Hertz's, centred
where the pad is, the shear f p outside the small stick zone, and the resultants P and Q.
The pairs are the pad's 61 nodes; the flat's face is the 3.3-contact-width-long track,
re-paired at every increment (a quarter of the contact half-width, 5 pair spacings).
Tolerances: measured values in the comments plus a margin.
"""

from __future__ import annotations

import attrs
import numpy as np
import pytest

from fretbem.basis import Refinement
from fretbem.contact.node_to_segment import NodeToSegmentPair
from fretbem.geometry.nurbs import NurbsCurve
from fretbem.halfplane.body import HalfPlaneBody
from fretbem.material import Material
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import LoadStep
from fretbem.sliding import SlideStep, SlidingError, run_sliding

P, F, WIDTHS, INCREMENTS = 100.0, 0.3, 3, 24
Q = 0.99 * F * P


def _setup(widths: float = WIDTHS):
    simulation = cattaneo_mindlin(
        pairs=61, lower="flat", models={"upper": "half-plane", "lower": "half-plane"}
    )
    hertz = simulation.reference.hertz
    a = hertz.half_width
    track = 1.5 * a + (widths + 1) * 2 * a
    flat = HalfPlaneBody(
        NurbsCurve.line([-track, 0.0], [track, 0.0], degree=1),
        Material(73400.0, 0.33),
        side="lower",
        refinement=Refinement(elements=round(2 * track / (3 * a / 60))),
        name="specimen",
    )
    pair = NodeToSegmentPair(simulation.pair.upper, flat)
    return attrs.evolve(simulation, pair=pair), hertz


def _history(slide: float):
    return [
        SlideStep(LoadStep("press", P, 0.0)),
        SlideStep(LoadStep("shear", P, Q, increments=4)),
        SlideStep(LoadStep("slide", P, Q, increments=INCREMENTS), slide),
        SlideStep(LoadStep("reverse", P, -Q, increments=8)),
        SlideStep(LoadStep("back", P, -Q, increments=INCREMENTS), -slide),
    ]


@pytest.fixture(scope="module")
def sliding():
    simulation, hertz = _setup()
    notes = []
    result = run_sliding(simulation, _history(WIDTHS * 2 * hertz.half_width), note=notes.append)
    return result, hertz, notes


def test_the_pairing_follows_three_contact_widths(sliding):
    """Offsets 0, 6 a, 6 a, 0; the pairs (the pad's nodes) sit where the pad is."""
    result, hertz, _ = sliding
    a = hertz.half_width
    assert np.allclose(result.offsets, [0, 0, 6 * a, 6 * a, 0], atol=1e-12)
    for step, offset in zip(result.steps, result.offsets, strict=True):
        centre = np.sum(step.x * step.pressure) / np.sum(step.pressure)
        assert abs(centre - offset) < 1e-4 * a  # measured 7.5e-7 a


def test_pressure_is_hertzian_at_every_position(sliding):
    """max |p - p_Hertz(x - offset)| / p0: measured 0.40 % at every step."""
    result, hertz, _ = sliding
    for step, offset in zip(result.steps, result.offsets, strict=True):
        exact = hertz.pressure(step.x - offset)
        assert np.max(np.abs(step.pressure - exact)) <= 0.006 * hertz.peak_pressure


def test_equilibrium_and_full_slip_outside_the_stick_zone(sliding):
    """Integrals of p and q are P and Q (measured 6e-6 x P); q = f p (sign of Q) at every
    pair in contact outside the stick zone of Mindlin-Deresiewicz, c = a sqrt(1 - Q / f P)
    = 0.1 a, plus two pair spacings."""
    result, hertz, _ = sliding
    a = hertz.half_width
    spacing = 3 * a / 60
    stick = a * np.sqrt(1 - Q / (F * P)) + 2 * spacing
    for step, offset in zip(result.steps[1:], result.offsets[1:], strict=True):
        normal, shear = step.resultant
        assert abs(normal - P) <= 1e-4 * P
        assert abs(shear - step.tangential) <= 1e-4 * P
        outside = (np.abs(step.x - offset) > stick) & (step.pressure > 0)
        sign = np.sign(step.tangential)
        assert outside.sum() >= 30
        slip = np.abs(sign * step.shear[outside] - F * step.pressure[outside])
        assert np.max(slip) <= 1e-9 * hertz.peak_pressure


def test_memory_is_carried_exactly(sliding):
    """Half-planes are translation invariant: after 24 re-pairings the tractions are those
    before the slide (measured 1e-13 p0), and after reversing and sliding back the mirror
    image of the first loading (Mindlin-Deresiewicz: a full reversal mirrors it)."""
    result, hertz, _ = sliding
    p0 = hertz.peak_pressure
    shear, slid, back = result["shear"], result["slide"], result["back"]
    assert np.max(np.abs(slid.pressure - shear.pressure)) <= 1e-9 * p0
    assert np.max(np.abs(slid.shear - shear.shear)) <= 1e-9 * p0
    assert np.max(np.abs(back.pressure - shear.pressure[::-1])) <= 1e-9 * p0
    assert np.max(np.abs(back.shear + shear.shear[::-1])) <= 1e-9 * p0


def test_new_contact_is_reported(sliding):
    """One note for the slide: the track from the first contact's edge (a) to where the
    pad's leading edge arrives (7 a); none for sliding back over ground already touched."""
    result, hertz, notes = sliding
    a = hertz.half_width
    assert notes == list(result.notes) and len(notes) == 1
    assert "step 'slide'" in notes[0] and "lower face came into contact" in notes[0]
    start, end = (float(v) for v in notes[0].split("from ")[1].split(" mm")[0].split(" to "))
    spacing = 3 * a / 60  # the edges fall between pairs: measured 0.5 and 1.5 spacings off
    assert abs(start - a) < 2 * spacing and abs(end - 7 * a) < 2 * spacing


def test_a_slide_off_the_track_is_refused():
    """Sliding farther than the flat reaches: the error says how far and what to lengthen."""
    simulation, hertz = _setup(widths=0.5)
    with pytest.raises(SlidingError, match=r"no longer cover each other.*lengthen the face"):
        run_sliding(simulation, _history(6 * hertz.half_width)[:3], note=None)


def test_node_to_node_cannot_slide():
    """Finite sliding needs the projection pairing."""
    simulation = cattaneo_mindlin(pairs=21)
    with pytest.raises(SlidingError, match="NodeToSegmentPair"):
        run_sliding(simulation, _history(0.1)[:2], note=None)
