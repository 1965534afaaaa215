"""The last adaptive level's own transitions (fretbem.accuracy.adaptive.own_transitions)."""

from __future__ import annotations

import numpy as np

from fretbem.accuracy.adaptive import Transitions, own_transitions

#: the rig at 61 pairs (mm): edge knots ... 0.6461, boundary knots ... 0.6121, 0.6532
SETTLED = Transitions(np.array([-0.6822, 0.6461, 0.6814]), np.array([0.6121, 0.6532]))
APART = 0.004  # the layout's merge distance, 2e-3 of the 2 mm face


def test_a_boundary_beside_an_edge_knot_gets_a_knot_of_its_own():
    """Step C's stick-slip boundary 0.005 mm inside an edge knot: the edge's knot does not
    serve the cusp of q, so the level is settled again with a boundary knot on it."""
    handed = Transitions(SETTLED.edges, np.array([0.6121, 0.6412, 0.6532]))
    own = own_transitions(SETTLED, handed, APART)
    np.testing.assert_array_equal(own.edges, SETTLED.edges)
    np.testing.assert_array_equal(own.boundaries, [0.6121, 0.6412, 0.6532])


def test_a_transition_beside_a_knot_of_its_kind_adds_nothing():
    """A boundary 0.003 mm from a boundary knot and an edge 0.001 mm from an edge knot are
    served by those knots (three C0 knots inside 0.008 mm made the rig worse): None."""
    handed = Transitions(np.array([-0.6822, 0.6451, 0.6814]), np.array([0.6121, 0.6502, 0.6532]))
    assert own_transitions(SETTLED, handed, APART) is None


def test_a_new_edge_is_added_and_the_settled_knots_stay():
    handed = Transitions(np.array([-0.6822, -0.6456, 0.6461, 0.6814]), SETTLED.boundaries)
    own = own_transitions(SETTLED, handed, APART)
    np.testing.assert_array_equal(own.edges, [-0.6822, -0.6456, 0.6461, 0.6814])
    np.testing.assert_array_equal(own.boundaries, SETTLED.boundaries)
    # a level with no boundary knot takes every boundary it found
    bare = Transitions(SETTLED.edges, np.zeros(0))
    np.testing.assert_array_equal(own_transitions(bare, handed, APART).boundaries, [0.6121, 0.6532])
