"""A load a step drops ramps down to 0 over the step's increments in every stepping loop:
the Simulation's, finite sliding's (run_sliding) and the sliding wear track's (Track.step),
by one rule, :func:`fretbem.simulation.loads_between`."""

from __future__ import annotations

import attrs
import numpy as np
import pytest

from fretbem.contact.law import ContactState
from fretbem.scenes.builder import build
from fretbem.scenes.spec import scene_from_dict
from fretbem.simulation import loads_between, run
from fretbem.sliding import run_sliding
from fretbem.wear.slide import Track

BULK = 40.0


def bulk_history(increments: int = 4):
    """A cylinder on a flat held at its ends (half-planes, node-to-segment pairs): the press
    carries a bulk stress, the second step adds Q and drops the bulk (Python only: a scene
    file gives every step its bulk)."""
    data = {
        "pad": {"model": "half-plane", "radius": 70.0},
        "specimen": {"model": "half-plane", "shape": "flat", "length": 40.0,
                     "thickness": 13.0, "support": "ends"},
        "contact": {"pairs": 21, "estimate": False, "pairing": "node-to-segment"},
        "load": {"steps": ["press", "B"], "P": 100.0, "Q": [0.0, 12.0], "bulk": [BULK, 0.0],
                 "increments": [1, increments]},
    }  # fmt: skip
    simulation, _ = build(scene_from_dict(data))
    press, second = simulation.steps
    assert press.loads == {"bulk": BULK}
    return attrs.evolve(simulation, steps=(press, attrs.evolve(second, loads={})))


def test_loads_between_ramps_a_dropped_load_down_and_an_added_one_up():
    assert loads_between({"a": 4.0, "b": 2.0}, {"b": 6.0, "c": 8.0}, 0.25) == {
        "a": 3.0, "b": 3.0, "c": 2.0,
    }  # fmt: skip
    assert loads_between({"a": 4.0}, {}, 1.0) == {"a": 0.0}


@pytest.mark.parametrize("increments", [2, 4])
def test_run_sliding_ramps_a_dropped_load_as_the_simulation_does(increments):
    """Without re-pairing (the pad moves less than a pair spacing) the sliding loop solves
    the Simulation's problem on its pairs stood on the pad's nodes (as sliding always
    stands them): every increment's loads and tractions equal run()'s on that pairing."""
    simulation = bulk_history(increments)
    on_the_pad = attrs.evolve(simulation, pair=attrs.evolve(simulation.pair, slave="upper"))
    plain = run(on_the_pad).steps[1].increments
    sliding = run_sliding(simulation, every=1e6, note=None)
    assert sliding.repairings == 0
    slid = sliding.steps[1].increments
    assert len(slid) == len(plain) == increments
    for k, (a, b) in enumerate(zip(plain, slid, strict=True), 1):
        assert b.loads == pytest.approx({"bulk": BULK * (1 - k / increments)}, abs=1e-12)
        assert b.loads == pytest.approx(a.loads, abs=1e-12)
        scale = float(np.max(np.abs(a.pressure)))
        np.testing.assert_allclose(b.pressure, a.pressure, atol=1e-10 * scale)
        np.testing.assert_allclose(b.shear, a.shear, atol=1e-10 * scale)


@pytest.mark.parametrize("increments", [2, 4])
def test_track_step_ramps_a_dropped_load_as_the_simulation_does(increments):
    """The track's first pairing (the pad has not slid) is a condensed problem of its own:
    each increment's loads equal the Simulation's rule and its tractions Simulation.step's
    on that problem."""
    track = Track.start(bulk_history(increments))
    press, second = track.simulation.steps
    state = ContactState.initial(track.problem)
    track, state, _ = track.step(state, press)
    assert state.loads == {"bulk": BULK}
    expected = []
    track.simulation.step(track.problem, state, second, expected.append)
    reached = []
    track.step(state, second, lambda _, before, after: reached.append(after))
    assert len(reached) == len(expected) == increments
    for k, (a, b) in enumerate(zip(expected, reached, strict=True), 1):
        assert b.loads == pytest.approx({"bulk": BULK * (1 - k / increments)}, abs=1e-12)
        scale = float(np.max(np.abs(a.x)))
        np.testing.assert_allclose(b.x, a.x, atol=1e-10 * scale)
