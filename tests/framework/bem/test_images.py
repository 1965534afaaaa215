"""A body whose segments are point images of another's takes that body's blocks and rules,
and its H and G equal a fresh assembly's to the last bit."""

from __future__ import annotations

import importlib

import attrs
import numpy as np
import pytest

from fretbem.basis import Refinement
from fretbem.bem import assembly, image_matrices, images
from fretbem.bem.body import _segment_samples
from fretbem.bem.integration import Collocation, IntegrationSettings
from fretbem.bem.system import g_free_segments
from fretbem.scenes import cattaneo_mindlin


@pytest.fixture(autouse=True)
def _assembled_not_permuted(monkeypatch):
    """These tests are of the assembly: a point image's H and G assembled (taking the pad's
    blocks), not permuted from the pad's whole (:mod:`fretbem.bem.image_matrices`)."""
    monkeypatch.setattr(image_matrices, "permutation", lambda *args: None)


def _bodies(basis: str, compiled: bool, **overrides):
    simulation = cattaneo_mindlin(basis=basis, pairs=21, **overrides)
    pair = simulation.pair
    settings = IntegrationSettings(compiled=compiled)
    out = []
    for body, tag in ((pair.upper, pair.upper_tag), (pair.lower, pair.lower_tag)):
        body = attrs.evolve(body, integration=settings)
        out.append((body, g_free_segments(body, body.layout((tag,)))))
    return out


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
@pytest.mark.parametrize("compiled", [False, True])
def test_the_specimen_of_similar_cylinders_takes_the_pads_blocks(basis, compiled, monkeypatch):
    (pad, pad_free), (specimen, free) = _bodies(basis, compiled)
    assembly.BLOCKS.clear()
    fresh_h, fresh_g = attrs.evolve(specimen).system_matrices(free)
    assembly.BLOCKS.clear()
    attrs.evolve(pad).system_matrices(pad_free)
    assert all(assembly.BLOCKS.image(s) in pad.segments for s in specimen.segments)
    calls = []
    loops = importlib.import_module(f"fretbem.bem.{'compiled' if compiled else 'numpy'}_loops")
    original = loops.classify_and_integrate
    monkeypatch.setattr(loops, "classify_and_integrate", lambda *a: calls.append(1) or original(*a))
    h, g = attrs.evolve(specimen).system_matrices(free)
    assert calls == []  # every regular block came from the pad's
    assert np.array_equal(h, fresh_h)
    assert np.array_equal(g, fresh_g)


def test_a_flat_specimen_takes_only_its_bottoms_blocks():
    """Its bottom is the image of the pad's top, its other segments are its own."""
    (pad, pad_free), (specimen, free) = _bodies("nurbs", False, lower="flat")
    assembly.BLOCKS.clear()
    fresh_h, fresh_g = attrs.evolve(specimen).system_matrices(free)
    assembly.BLOCKS.clear()
    attrs.evolve(pad).system_matrices(pad_free)
    found = [assembly.BLOCKS.image(s) for s in specimen.segments]
    assert found[0] is pad.segments[4] and not any(found[1:])
    h, g = attrs.evolve(specimen).system_matrices(free)
    assert np.array_equal(h, fresh_h)
    assert np.array_equal(g, fresh_g)


def test_a_family_whose_map_is_not_odd_has_no_image(monkeypatch):
    (pad, _), (specimen, _) = _bodies("nurbs", False)
    segment = specimen.segments[3]
    assert images.signatures(segment)[1] == images.signatures(pad.segments[1])[0]
    monkeypatch.setattr(type(segment), "odd_in_geometry", False)
    assert images.signatures(segment) is None


def test_reflected_rules_are_the_images_own():
    (pad, _), (specimen, _) = _bodies("lagrange2", False)
    settings = IntegrationSettings()
    for k, segment in enumerate(specimen.segments):
        image = pad.segments[(k - 2) % len(pad.segments)]
        rows = specimen.collocation.segment == k
        colloc = specimen.collocation
        own = assembly._segment_rules(
            segment, settings, colloc.element[rows], colloc.local[rows], colloc.parameter[rows]
        )
        rows = pad.collocation.segment == (k - 2) % len(pad.segments)
        reflected = images.reflected_rules(
            assembly._segment_rules(
                image, settings, pad.collocation.element[rows], pad.collocation.local[rows],
                pad.collocation.parameter[rows],
            )
        )  # fmt: skip
        assert own.keys() == reflected.keys()
        for name, value in own.items():
            pairs = [(value, reflected[name])]
            if isinstance(value, assembly.SingularRules):  # evaluated when used: every pair,
                # and a mirrored body's half of them
                half = np.arange(len(value.elements)) % 2 == 0
                pairs = [(value.arrays(), reflected[name].arrays()),
                         (value.arrays(half), reflected[name].arrays(half))]  # fmt: skip
            for pair in pairs:
                mine, theirs = (v if isinstance(v, tuple) else (v,) for v in pair)
                assert all(np.array_equal(a, b) for a, b in zip(mine, theirs, strict=True)), name


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
def test_a_point_image_is_discretised_and_collocated_as_its_own(basis):
    """The specimen's segments, taken reflected from the pad's, equal the family's own
    discretisation of its curves, and so do their collocation points."""
    simulation = cattaneo_mindlin(basis=basis, pairs=21, radius=70.5)
    pad, specimen = simulation.pair.upper, simulation.pair.lower
    pad.collocation  # noqa: B018 - the pad's points first, as a run computes them
    for k, segment in enumerate(specimen.segments):
        assert images.source(segment) is pad.segments[(k - 2) % len(pad.segments)]
        boundary_segment = specimen.boundary.segments[k]
        refinement = specimen.refinement.get(boundary_segment.tag, Refinement())
        own = specimen.family.discretise(boundary_segment.curve, refinement)
        for field in attrs.fields(type(own)):
            a, b = getattr(segment, field.name), getattr(own, field.name)
            if attrs.has(type(a)):
                assert all(np.array_equal(getattr(a, f.name), getattr(b, f.name))
                           for f in attrs.fields(type(a)))  # fmt: skip
            else:
                assert np.array_equal(a, b), field.name
    fresh = Collocation.of([attrs.evolve(s) for s in specimen.segments])
    for name in ("segment", "element", "local", "parameter", "points", "normals"):
        assert np.array_equal(getattr(specimen.collocation, name), getattr(fresh, name)), name
    pad.resultant_weights()  # the pad's 8-point samples first
    for segment in specimen.segments:
        mine, own = _segment_samples(segment), _segment_samples(attrs.evolve(segment))
        assert all(np.array_equal(a, b) for a, b in zip(mine, own, strict=True))


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
def test_a_point_image_takes_its_source_digests_swapped(basis):
    """The block store signs a segment discretised as a kept one's point image with that
    one's digests swapped: the digests its own fields give, on every segment of both bodies
    (an aligned level's new faces included)."""
    from fretbem.accuracy.remesh import remesh

    store = assembly.BlockStore()
    level = remesh(cattaneo_mindlin(pairs=31, basis=basis), np.array([-0.2, 0.2]), 31)
    imaged = 0
    for body in (level.pair.upper, level.pair.lower):  # sources signed first
        for segment in body.segments:
            imaged += images.source(segment) is not None
            assert store._signature(segment) == images.signatures(segment)
    assert imaged >= 5  # of 6 lower segments (nurbs 6, lagrange2 5)
