"""The sliding track read from the specimen's face: straight, a circular arc the pad turns
along (its centre, radius and turn per mm), or refused with the reason and the key."""

from __future__ import annotations

import math

import attrs
import numpy as np
import pytest

from fretbem.contact.node_to_segment import NodeToSegmentPair
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.sliding.track import Track, TrackError, _arc


def _pair(**overrides) -> NodeToSegmentPair:
    base = cattaneo_mindlin(pairs=21, **overrides)
    return NodeToSegmentPair(base.pair.upper, base.pair.lower)


def test_a_flat_specimen_is_a_straight_track():
    pair = _pair(lower="flat")
    track = Track.of(pair)
    assert track.straight and track.radius == math.inf and track.rate == 0.0
    moved = track.placed(pair, 0.7)
    assert np.allclose(moved.offset, [0.7, 0.0]) and moved.turn == 0.0
    assert track.slide_of(moved) == pytest.approx(0.7)


def test_the_reference_specimen_is_an_arc_the_pad_turns_along():
    """The reference scene's specimen face: an arc of R = 70 mm about (0, -70); sliding
    s towards +x turns the pad clockwise by s / R about that centre."""
    pair = _pair()
    track = Track.of(pair)
    assert not track.straight
    assert np.allclose(track.centre, [0.0, -70.0], atol=1e-9)
    # the circle through three nodes 1.6 mm apart: R to 2e-12 (measured)
    assert track.radius == pytest.approx(70.0, rel=1e-10)
    assert track.rate == pytest.approx(-1.0 / 70.0, rel=1e-10)
    moved = track.placed(pair, 1.4)
    assert moved.turn == pytest.approx(-0.02, rel=1e-10)
    assert np.allclose(moved.pivot, track.centre)
    assert track.slide_of(moved) == pytest.approx(1.4)
    # arc length along the track: a point at angle -0.02 from the top lies 1.4 mm along
    point = track.centre + 70.0 * np.array([math.sin(0.02), math.cos(0.02)])
    assert track.along(point[None, :])[0] == pytest.approx(1.4, rel=1e-10)
    # the pad's face turned with it: still on the arc, its lowest point 1.4 mm along
    lowest = moved.placed("upper")[np.argmin(np.linalg.norm(moved.placed("upper") - point, axis=1))]
    assert abs(np.linalg.norm(lowest - track.centre) - 70.0) < 1e-3


def test_the_block_keeps_the_pad_where_it_is_when_the_pairing_turns_it():
    """Carried 0.1 mm further along the arc, the block (in the pad's turned axes) gives the
    slide back along its tangent and turns its displacement with the pad's axes."""
    pair = _pair()
    track = Track.of(pair)
    block = np.array([0.03, -0.01])
    carried = track.carried(pair, block, 0.1)
    turn = track.rate * 0.1
    expected = np.array(
        [math.cos(turn) * 0.03 + math.sin(turn) * -0.01 - 0.1,
         -math.sin(turn) * 0.03 + math.cos(turn) * -0.01]
    )  # fmt: skip
    assert np.allclose(carried, expected, atol=1e-15)


def test_half_plane_bodies_cannot_turn_along_an_arc():
    pair = _pair(models={"upper": "half-plane", "lower": "half-plane"})
    with pytest.raises(TrackError, match=r"pad is a half-plane body.*\[pad\] model = 'bem'"):
        Track.of(pair)


def test_a_pad_that_starts_off_the_frame_point_is_refused():
    pair = attrs.evolve(_pair(), offset=[0.2, 0.0], uncovered="open")
    with pytest.raises(TrackError, match=r"the pad must start there"):
        Track.of(pair)


def test_an_already_turned_pair_is_refused():
    pair = attrs.evolve(_pair(), turn=0.01, pivot=[0.0, -70.0])
    with pytest.raises(TrackError, match=r"give the pair with turn = 0"):
        Track.of(pair)


class _Nodes:
    """A body exposing no discretised segments: its face is read from its nodes."""

    segments = ()
    segment_tags = ()
    name = "nodes"


def test_a_curved_face_that_is_not_a_circle_is_refused():
    x = np.linspace(-2.0, 2.0, 21)
    circle = np.column_stack([x, np.sqrt(70.0**2 - x**2) - 70.0])
    centre, radius = _arc(_Nodes(), "contact", circle)
    assert np.allclose(centre, [0.0, -70.0]) and radius == pytest.approx(70.0)
    parabola = np.column_stack([x, -(x**2) / 140.0 - x**4 / 1e3])
    with pytest.raises(TrackError, match=r"'contact' is curved and not a circular arc"):
        _arc(_Nodes(), "contact", parabola)
