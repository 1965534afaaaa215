"""Mirrored adaptive levels on mirror-symmetric faces (fretbem.accuracy.remesh, adaptive)."""

from __future__ import annotations

import numpy as np
import pytest

from fretbem.accuracy import adaptive
from fretbem.accuracy.knots import Transitions
from fretbem.accuracy.remesh import (
    aligned_breakpoints,
    mirror_symmetric,
    point_image,
    remesh,
    symmetric_anchors,
)
from fretbem.bem import assembly, images
from fretbem.geometry.nurbs import NurbsCurve
from fretbem.scenes import cattaneo_mindlin

ANCHORS = np.array([0.164, 0.221, 0.289, 0.711, 0.779, 0.836])


def mirrored(bounds: np.ndarray) -> bool:
    """Whether the right half of ``bounds`` is the left half mirrored (1 - b), exactly."""
    n = bounds.size
    left, right = bounds[: n // 2], bounds[(n + 1) // 2 :]
    return bool(np.array_equal(right, (1.0 - left)[::-1]) and (n % 2 == 0 or bounds[n // 2] == 0.5))


@pytest.mark.parametrize("elements", [23, 24, 45, 58])
def test_symmetric_breakpoints_are_their_own_mirror(elements):
    bounds = aligned_breakpoints(ANCHORS, elements, ratio=20.0, grading=0.06, symmetric=True)
    assert mirrored(bounds)
    # a middle gap takes the odd element: the count asked for, each anchor a breakpoint
    assert bounds.size == elements + 1
    assert all(np.min(np.abs(bounds - t)) < 1e-12 for t in ANCHORS)


def test_symmetric_breakpoints_with_an_anchor_in_the_middle_fall_short_of_an_odd_count():
    anchors = np.array([0.3, 0.5, 0.7])
    odd = aligned_breakpoints(anchors, 21, ratio=10.0, symmetric=True)
    assert mirrored(odd) and odd.size == 21  # 20 elements
    even = aligned_breakpoints(anchors, 20, ratio=10.0, symmetric=True)
    assert even.size == 21


def test_free_breakpoints_are_unchanged_by_the_option():
    """Anchors not symmetric: the caller never asks for a mirrored layout; without the option
    the layout is the one the free rounding gives (here unsymmetric counts)."""
    free = aligned_breakpoints(ANCHORS, 23, ratio=20.0, grading=0.06)
    assert not mirrored(free)


def test_face_and_anchor_symmetry_checks():
    points = np.array([[-0.5, 0.002], [0.0, -0.002], [0.5, 0.002]])
    arc = NurbsCurve(2, [0, 0, 0, 1, 1, 1], points, [1, 0.9, 1])
    tangent = np.array([1.0, 0.0])
    assert mirror_symmetric(arc, tangent)
    image = NurbsCurve(2, arc.knots, -points, arc.weights)
    assert point_image(image, arc) and mirror_symmetric(image, tangent)
    tilted = NurbsCurve(2, arc.knots, points + np.array([0.0, 1e-6]) * [[0], [0], [1]], arc.weights)
    assert not mirror_symmetric(tilted, tangent)
    assert not point_image(tilted, arc)
    assert symmetric_anchors(np.array([0.3, -0.1, 0.1, -0.3]), np.ones(4), 1.0)
    assert not symmetric_anchors(np.array([-0.3, 0.3]), np.array([1.0, 0.5]), 1.0)
    assert not symmetric_anchors(np.array([-0.3, 0.3 + 1e-9]), np.ones(2), 1.0)


def test_symmetrised_transitions_within_the_merge_distance_only():
    found = Transitions(np.array([-0.33, 0.3302]), np.array([-0.2, 0.2001]))
    mirrored = adaptive.symmetrised(found, 1e-3)
    assert np.array_equal(mirrored.edges, -mirrored.edges[::-1])
    np.testing.assert_allclose(mirrored.edges, [-0.3301, 0.3301])
    np.testing.assert_allclose(mirrored.boundaries, [-0.20005, 0.20005])
    assert adaptive.symmetrised(found, 1e-4) is None
    one_sided = Transitions(np.array([-0.33, 0.33]), np.array([0.1]))
    assert adaptive.symmetrised(one_sided, 1e-3) is None


def test_similar_faces_are_laid_out_as_point_images_and_share_blocks():
    """The reference pad and specimen (similar cylinders, one material) re-meshed on mirrored
    anchors: the lower face takes the upper's refinement, its segment is the upper's point
    image to the last bit and the assembly takes its blocks from the upper body's."""
    simulation = cattaneo_mindlin(pairs=31)
    assert adaptive.symmetric_faces(simulation)
    level = remesh(simulation, np.array([-0.3, -0.2, 0.2, 0.3]), 45, ratio=20.0, grading=0.06)
    pair = level.pair
    upper = pair.upper.face_refinement(pair.upper_tag)
    assert pair.lower.face_refinement(pair.lower_tag) is upper
    bounds = upper.breakpoints()
    assert mirrored(bounds)
    up_face = pair.upper.face_segment(pair.upper_tag)[1]
    low_face = pair.lower.face_segment(pair.lower_tag)[1]
    assert images.signatures(low_face)[0] == images.signatures(up_face)[1]
    assembly.BLOCKS.clear()
    pair.upper.matrices()
    assert assembly.BLOCKS.image(low_face) is up_face


def test_unsymmetric_anchors_keep_the_free_layout():
    simulation = cattaneo_mindlin(pairs=31)
    level = remesh(simulation, np.array([-0.3, 0.25]), 45, ratio=20.0, grading=0.06)
    pair = level.pair
    assert pair.lower.face_refinement(pair.lower_tag) != pair.upper.face_refinement(pair.upper_tag)


def test_reference_levels_stay_mirrored_point_images():
    """Every level of the reference scene's adaptive run is mirrored (knots and layout) and
    its faces are point images; the run's errors are as before the mirroring or smaller
    (max p and q error of the 61-pair level against Mindlin: 0.848 %, before 0.855 %)."""
    out = adaptive.run_adaptive(cattaneo_mindlin(pairs=61), adaptive.AdaptiveSettings(budget=61))
    for found in out.transitions:
        assert np.array_equal(found.edges, -found.edges[::-1])
        assert np.array_equal(found.boundaries, -found.boundaries[::-1])
    for level in out.levels:
        pair = level.simulation.pair
        assert pair.lower.face_refinement(pair.lower_tag) is pair.upper.face_refinement(
            pair.upper_tag
        )
    worst = max(max(s.errors["e_p_max"], s.errors["e_q_max"]) for s in out.result.steps)
    assert worst < 0.0086
    assert out.notes == ()


@pytest.mark.parametrize("common", [0.0, 0.004])
def test_knots_move_in_mirrored_pairs_until_their_common_move_counts(monkeypatch, common):
    """Measured moves whose common part (the same shift of a knot and its mirror) is small
    move the knots in mirrored pairs; a common move that would not count as settled on its
    own releases them, each knot moving on its own from there (and on later levels)."""
    simulation = cattaneo_mindlin(pairs=21)
    found = Transitions(np.array([-0.33, 0.33]), np.array([-0.27, -0.21, 0.21, 0.27]))
    odd = 0.002

    def moves(level, used, reach=None):
        edges = np.array([-odd, odd]) + common
        return edges, np.zeros(used.boundaries.size)

    monkeypatch.setattr(adaptive, "knot_moves", moves)
    settings = adaptive.AdaptiveSettings().for_family(simulation.pair.upper.family)
    _, used, _, mirrored = adaptive.settle(
        simulation, found, 21, settings, iterations=1, tolerance=1e-6, symmetric=True
    )
    moved = next(u for u in used if not np.array_equal(u.edges, found.edges))
    assert mirrored is (common == 0.0)
    assert np.array_equal(moved.edges, -moved.edges[::-1]) is (common == 0.0)
    expected = found.edges + np.array([-odd, odd]) + common
    np.testing.assert_allclose(moved.edges, expected, atol=1e-15)
