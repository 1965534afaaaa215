"""G's columns on traction-free segments, which a solve never reads, left out of the numpy
assembly (``BemBody.system_matrices``, ``fretbem.bem.system.g_free_segments``)."""

from __future__ import annotations

import attrs
import numpy as np
import pytest

from fretbem.bem import assembly, image_matrices, numpy_loops
from fretbem.bem.integration import IntegrationSettings
from fretbem.bem.system import g_free_segments
from fretbem.scenes import cattaneo_mindlin
from fretbem.simulation import run


def _fresh(body, compiled=False):
    return attrs.evolve(body, integration=IntegrationSettings(compiled=compiled))


def test_the_traction_free_segments_are_the_free_ones():
    pair = cattaneo_mindlin(pairs=21).pair
    for body, tag in ((pair.upper, pair.upper_tag), (pair.lower, pair.lower_tag)):
        tags = [s.tag for s in body.boundary.segments]
        free = [tags[k] for k in g_free_segments(body, body.layout((tag,)))]
        # the pad's top is its loading block, the specimen's bottom is held: G needed there
        assert sorted(free) == sorted({"flank_left", "flank_right", "side_left", "side_right"})
    # no contact left open: the contact face is traction-free as well
    body = pair.upper
    assert body.boundary.indices("contact")[0] in g_free_segments(body, body.layout(()))


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
def test_h_is_the_same_and_g_is_left_out_on_the_free_segments_only(basis, monkeypatch):
    # the assembly's own work: a point image's H and G permuted from the body before
    # (fretbem.bem.image_matrices) hold every column, which the contract allows
    monkeypatch.setattr(image_matrices, "permutation", lambda *args: None)
    pair = cattaneo_mindlin(basis=basis, pairs=21).pair
    for body, tag in ((pair.upper, pair.upper_tag), (pair.lower, pair.lower_tag)):
        assembly.BLOCKS.clear()
        h, g = _fresh(body).matrices()
        fresh = _fresh(body)
        free = g_free_segments(fresh, fresh.layout((tag,)))
        assembly.BLOCKS.clear()
        h_free, g_free = fresh.system_matrices(free)
        assert np.array_equal(h_free, h)  # bit for bit
        skipped = np.zeros(g.shape[1], dtype=bool)
        for k in free:
            skipped[2 * fresh.function_slice(k).start : 2 * fresh.function_slice(k).stop] = True
        assert np.array_equal(g_free[:, ~skipped], g[:, ~skipped])
        assert not g_free[:, skipped].any() and g[:, skipped].any()
        # kept apart from the full matrices, and released with them
        assert fresh.system_matrices(free)[0] is h_free
        assert fresh.matrices()[1][:, skipped].any()
        fresh.release_matrices()
        assert not any(isinstance(key, tuple) and key[0] == "system matrices"
                       for key in fresh._cache)  # fmt: skip


def test_reused_blocks_keep_g_apart():
    """A block assembled without G is not served to a body that wants G (and back)."""
    pair = cattaneo_mindlin(pairs=21).pair
    body, tag = pair.upper, pair.upper_tag
    assembly.BLOCKS.clear()
    full_h, full_g = _fresh(body).matrices()
    assembly.BLOCKS.clear()
    fresh = _fresh(body)
    fresh.system_matrices(g_free_segments(fresh, fresh.layout((tag,))))
    h, g = _fresh(body).matrices()  # the same segments: blocks from the store
    assert np.array_equal(h, full_h) and np.array_equal(g, full_g)


@pytest.mark.parametrize(("pairs", "overrides"), [(21, {}), (31, {"E_lower": 2.0e5})])
def test_runs_are_bit_identical_with_and_without_g_left_out(pairs, overrides, monkeypatch):
    results = []
    for skips in (True, False):
        monkeypatch.setattr(numpy_loops, "SKIPS_G", skips)
        assembly.BLOCKS.clear()
        simulation = cattaneo_mindlin(pairs=pairs, **overrides)
        simulation = attrs.evolve(
            simulation,
            pair=attrs.evolve(
                simulation.pair,
                upper=_fresh(simulation.pair.upper),
                lower=_fresh(simulation.pair.lower),
            ),
        )
        results.append(run(simulation))
    for with_skip, without in zip(*(r.steps for r in results), strict=True):
        assert np.array_equal(with_skip.unknowns, without.unknowns)
        assert with_skip.iterations == without.iterations


def test_compiled_loops_assemble_g_everywhere():
    pair = cattaneo_mindlin(pairs=21).pair
    body = _fresh(pair.upper, compiled=True)
    free = g_free_segments(body, body.layout((pair.upper_tag,)))
    _, g = body.system_matrices(free)
    columns = body.function_slice(free[0])
    assert g[:, 2 * columns.start : 2 * columns.stop].any()
