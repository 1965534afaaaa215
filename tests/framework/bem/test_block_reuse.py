"""Regular H/G blocks and segment rules reused between bodies that share segments."""

from __future__ import annotations

import attrs
import numpy as np
import pytest

from fretbem.accuracy.adaptive import remesh
from fretbem.bem import assembly
from fretbem.bem.integration import IntegrationSettings
from fretbem.scenes import cattaneo_mindlin


def _with_loops(body, compiled: bool):
    return attrs.evolve(body, integration=IntegrationSettings(compiled=compiled))


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
@pytest.mark.parametrize("compiled", [False, True])
def test_remeshed_body_reuses_blocks_and_equals_a_fresh_assembly(basis, compiled):
    simulation = cattaneo_mindlin(basis=basis, pairs=21)
    first = remesh(simulation, np.array([]), 21, ratio=1.0).pair.upper
    second = remesh(simulation, np.array([0.1]), 31, ratio=4.0).pair.upper
    first, second = _with_loops(first, compiled), _with_loops(second, compiled)
    shared = [a is b for a, b in zip(first.segments, second.segments, strict=True)]
    assert sum(shared) == len(shared) - 1  # only the contact face was re-meshed

    assembly.BLOCKS.clear()
    fresh_h, fresh_g = attrs.evolve(second).matrices()  # a fresh cache, nothing stored before
    assembly.BLOCKS.clear()
    first.matrices()
    key_segments = [s for s, same in zip(second.segments, shared, strict=True) if same]
    assert assembly.BLOCKS.rules(key_segments[0], second.integration) is not None
    h, g = second.matrices()
    # the same sums in the same order: equal to the last bit
    assert np.array_equal(h, fresh_h)
    assert np.array_equal(g, fresh_g)


def test_large_bodies_keep_nothing(monkeypatch):
    monkeypatch.setattr(assembly, "REUSE_MAX_FUNCTIONS", 10)
    monkeypatch.setattr(assembly, "LEND_MAX_FUNCTIONS", 10)
    assembly.BLOCKS.clear()
    body = cattaneo_mindlin(pairs=11).pair.upper
    body.matrices()
    assert all(assembly.BLOCKS.rules(s, body.integration) is None for s in body.segments)
    assert assembly.BLOCKS.get(body.segments[0], body.segments[0], None) is None


def test_blocks_go_with_their_segments():
    """A segment's rules are dropped with the segment. The pad's radius is this test's own:
    a simulation another test keeps (test_properties caches the reference scene) would
    otherwise hold the same flank segments, and their rules, alive."""
    import gc

    from fretbem.scenes import builder

    assembly.BLOCKS.clear()
    body = cattaneo_mindlin(pairs=11, radius=71.25).pair.upper
    body.matrices()
    assert len(assembly.BLOCKS._rules) == len(body.segments)
    del body
    builder._built.cache_clear()  # the scene builder keeps recent shapes' faces and segments
    gc.collect()
    assert len(assembly.BLOCKS._rules) == 0


def test_only_recent_bodies_keep_their_blocks():
    """Each re-meshed face's blocks go once RECENT_BODIES later bodies were assembled; the
    segments every body shares stay."""
    assembly.BLOCKS.clear()
    simulation = cattaneo_mindlin(pairs=21)
    bodies = [
        remesh(simulation, np.array([0.05 * k]), 21, ratio=4.0).pair.upper
        for k in range(assembly.RECENT_BODIES + 2)
    ]
    for body in bodies:
        body.matrices()
    first_face = bodies[0].face_segment(simulation.pair.upper_tag)[1]
    last_face = bodies[-1].face_segment(simulation.pair.upper_tag)[1]
    shared = next(s for s in bodies[0].segments if s is bodies[-1].segments[0])
    settings = bodies[0].integration
    assert assembly.BLOCKS.rules(first_face, settings) is None
    assert assembly.BLOCKS.rules(last_face, settings) is not None
    assert assembly.BLOCKS.rules(shared, settings) is not None
    assert first_face not in assembly.BLOCKS._blocks
    assert all(first_face not in rows for rows in assembly.BLOCKS._blocks.values())


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
def test_face_values_from_the_kept_rules_equal_a_new_evaluation(basis):
    """E of a graded face from the assembly's kept collocation values, bit for bit the
    matrix the basis evaluates again (and that one when nothing is kept)."""
    from fretbem.bem.system import face_values_matrix

    simulation = cattaneo_mindlin(basis=basis, pairs=21)
    body = remesh(simulation, np.array([-0.1, 0.2]), 31, ratio=4.0).pair.upper
    _, face = body.face_segment("contact")
    expected = face.collocation_matrix()
    assembly.BLOCKS.clear()
    assert assembly.BLOCKS.collocation_values(face, body.integration) is None
    assert np.array_equal(face_values_matrix(body, "contact"), expected)
    body.matrices()
    assert assembly.BLOCKS.collocation_values(face, body.integration) is not None
    assert np.array_equal(face_values_matrix(body, "contact"), expected)


def test_a_body_above_the_reuse_size_lends_to_the_next_body_only(monkeypatch):
    """The pad lends its rules (no blocks: its point image takes its H and G permuted) to
    the specimen assembled next, which equals its own assembly bit for bit; then the pad's
    are forgotten."""
    monkeypatch.setattr(assembly, "REUSE_MAX_FUNCTIONS", 10)
    pair = cattaneo_mindlin(pairs=21).pair
    fresh = []
    for lend in (10, 10**6):
        monkeypatch.setattr(assembly, "LEND_MAX_FUNCTIONS", lend)
        assembly.BLOCKS.clear()
        pad, specimen = attrs.evolve(pair.upper), attrs.evolve(pair.lower)
        pad.matrices()
        lent = [basis in assembly.BLOCKS._rules for basis in pad.segments]
        assert not any(basis in assembly.BLOCKS._blocks for basis in pad.segments)  # rules only
        fresh.append(specimen.matrices())
        assert all(lent) == (lend > 10)
        assert not any(basis in assembly.BLOCKS._rules for basis in pad.segments)
    (own_h, own_g), (h, g) = fresh
    assert np.array_equal(h, own_h)
    assert np.array_equal(g, own_g)


@pytest.mark.parametrize("compiled", [False, True])
@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
def test_a_mirrored_body_keeping_no_blocks_fills_its_rows_once_to_the_same_numbers(
    compiled, basis, monkeypatch
):
    """A mirror-symmetric body that keeps no blocks skips the fill before the singular terms
    (only the kept blocks read it): H and G equal, bit for bit, those of the same body
    assembled keeping its blocks (both fills)."""
    if compiled:
        pytest.importorskip("numba")
    body = _with_loops(cattaneo_mindlin(pairs=21, basis=basis).pair.upper, compiled)
    assembly.BLOCKS.clear()
    kept_h, kept_g = attrs.evolve(body).matrices()
    assert any(basis in assembly.BLOCKS._blocks for basis in body.segments)
    monkeypatch.setattr(assembly, "REUSE_MAX_FUNCTIONS", 10)
    monkeypatch.setattr(assembly, "LEND_MAX_FUNCTIONS", 10)
    assembly.BLOCKS.clear()
    calls = []
    fill = assembly.mirror.Fill.__call__
    monkeypatch.setattr(assembly.mirror.Fill, "__call__", lambda *a: calls.append(1) or fill(*a))
    h, g = attrs.evolve(body).matrices()
    assert len(calls) == 2  # H and G once each: the body is mirrored, nothing kept
    assert np.array_equal(h, kept_h)
    assert np.array_equal(g, kept_g)


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
def test_singular_rules_evaluated_for_some_pairs_are_those_of_every_pair(basis):
    """A segment's singular rules evaluated at a subset of its pairs (a mirrored body's
    integrated rows) are the rows of the evaluation at every pair, bit for bit (the basis
    evaluation is pointwise)."""
    body = cattaneo_mindlin(pairs=21, basis=basis).pair.upper
    colloc = body.collocation
    for k, segment in enumerate(body.segments):
        rows = colloc.segment == k
        rules = assembly._segment_rules(
            segment, body.integration, colloc.element[rows], colloc.local[rows],
            colloc.parameter[rows],
        )  # fmt: skip
        singular = rules["singular_sides"]
        every = singular.arrays()
        assert singular.arrays() is every  # kept
        on = np.random.default_rng(k).random(len(singular.elements)) < 0.5
        both = np.concatenate([on, on])  # side -1's pairs, then side +1's
        for part, whole in zip(singular.arrays(on), every, strict=True):
            assert np.array_equal(part, whole[both])
