"""Bodies symmetric about the y axis: half of the rows integrated (regular, rigid-body and
singular terms), the others mirrored, within round-off of integrating every row."""

from __future__ import annotations

import attrs
import numpy as np
import pytest

from fretbem.accuracy.adaptive import remesh
from fretbem.bem import assembly, image_matrices, mirror
from fretbem.bem.integration import IntegrationSettings
from fretbem.bem.system import g_free_segments
from fretbem.scenes import cattaneo_mindlin


@pytest.fixture(autouse=True)
def _assembled_not_permuted(monkeypatch):
    """These tests are of the assembly: a point image's H and G assembled (taking the pad's
    blocks), not permuted from the pad's whole (:mod:`fretbem.bem.image_matrices`)."""
    monkeypatch.setattr(image_matrices, "permutation", lambda *args: None)


def _matrices(body, free, monkeypatch, symmetric: bool):
    assembly.BLOCKS.clear()
    with monkeypatch.context() as patch:
        if not symmetric:
            patch.setattr(mirror, "permutation", lambda *args: None)
        return attrs.evolve(body).system_matrices(free)


@pytest.mark.parametrize(("basis", "pairs", "lower"), [("nurbs", 21, "arc"),
                         ("lagrange2", 31, "flat"), ("nurbs", 41, "flat")])  # fmt: skip
@pytest.mark.parametrize("compiled", [False, True])
def test_mirrored_rows_agree_with_their_own_integration(basis, pairs, lower, compiled,
                                                        monkeypatch):  # fmt: skip
    simulation = cattaneo_mindlin(basis=basis, pairs=pairs, lower=lower)
    pair = simulation.pair
    for body, tag in ((pair.upper, pair.upper_tag), (pair.lower, pair.lower_tag)):
        body = attrs.evolve(body, integration=IntegrationSettings(compiled=compiled))
        free = g_free_segments(body, body.layout((tag,)))
        h, g = _matrices(body, free, monkeypatch, symmetric=True)
        own_h, own_g = _matrices(body, free, monkeypatch, symmetric=False)
        # measured, of the largest entry: H 4.3e-13 (nurbs) and 3.4e-13 (lagrange2), its
        # singular and rigid-body terms mirrored too (row sums in the mirrored order); G
        # 2.3e-14 and 3.6e-14
        assert np.abs(h - own_h).max() <= 6e-13 * np.abs(own_h).max()
        assert np.abs(g - own_g).max() <= 1e-13 * np.abs(own_g).max()
        assert not np.array_equal(h, own_h)  # the mirror was used


def test_the_permutation_pairs_mirrored_points():
    body = cattaneo_mindlin(pairs=21).pair.upper
    rules = [assembly.BLOCKS.rules(b, body.integration) for b in body.segments]
    if any(r is None for r in rules):
        body.matrices()
        rules = [assembly.BLOCKS.rules(b, body.integration) for b in body.segments]
    points = body.collocation.points
    q = mirror.permutation(body.segments, [r["far"] for r in rules], points, body.offsets)
    assert np.array_equal(q[q], np.arange(len(q)))  # an involution
    assert np.allclose(points[q] * [-1, 1], points, atol=1e-12)
    integrated = mirror.integrated_rows(q, points)
    # one row of each pair, and the row on the axis (the contact face's middle; the top's
    # 14 functions have none)
    assert np.all(integrated | integrated[q])
    assert np.sum(integrated & integrated[q]) == np.sum(q == np.arange(len(q))) == 1


def test_an_asymmetric_body_integrates_every_row(monkeypatch):
    simulation = cattaneo_mindlin(pairs=21)
    body = remesh(simulation, np.array([0.1]), 21, ratio=4.0).pair.upper  # a kink off centre
    calls = []
    original = mirror.Fill
    monkeypatch.setattr(mirror, "Fill", lambda *a: calls.append(1) or original(*a))
    assembly.BLOCKS.clear()
    attrs.evolve(body).matrices()
    assert calls == []


@pytest.mark.parametrize("chunk", [3, 16])
def test_a_large_fill_by_slices_equals_the_gathered_fill(monkeypatch, chunk):
    """Above FILL_CHUNK rows the fill goes chunk by chunk through strided slices: the same
    numbers, signed zeros included, as the one gathered fill (segments reversed whole, a
    row that is its own mirror, zeros of both signs)."""
    rng = np.random.default_rng(3)
    n = 40
    q = np.r_[np.arange(19, -1, -1), 20, np.arange(39, 20, -1)]  # two reversed runs, 20 own
    points = np.c_[np.linspace(-1.0, 1.0, n), np.ones(n)]
    integrated = mirror.integrated_rows(q, points)
    matrix = rng.standard_normal((2 * n, 2 * n))
    matrix[::7, ::5] = 0.0
    matrix[::11, ::3] = -0.0
    gathered, sliced = matrix.copy(), matrix.copy()
    mirror.fill(gathered, q, integrated)  # 2 * (n // 2) rows < FILL_CHUNK: gathered
    monkeypatch.setattr(mirror, "FILL_CHUNK", chunk)
    mirror.fill(sliced, q, integrated)
    assert np.array_equal(gathered, sliced)
    assert np.array_equal(np.signbit(gathered), np.signbit(sliced))


def test_the_compiled_fill_gives_the_numpy_numbers(monkeypatch):
    """Once numba is loaded a fill is one compiled pass: the numpy paths' numbers, signed
    zeros included, for a small and a chunked fill."""
    pytest.importorskip("numba")
    from fretbem.bem import compiled_loops  # noqa: F401 - loads numba as the assembly does

    rng = np.random.default_rng(5)
    for size in (12, 2 * mirror.FILL_CHUNK + 40):  # pairs of rows mirrored, q reversing
        q = np.arange(size)[::-1].copy()
        integrated = np.arange(size) < size // 2
        matrix = rng.standard_normal((2 * size, 2 * size))
        matrix[rng.random(matrix.shape) < 0.05] = 0.0
        compiled, numpy = matrix.copy(), matrix.copy()
        mirror.fill(compiled, q, integrated)
        with monkeypatch.context() as patch:
            patch.setattr(mirror, "_COMPILED", "no such module")
            mirror.fill(numpy, q, integrated)
        assert np.array_equal(compiled, numpy)
        assert np.array_equal(np.signbit(compiled), np.signbit(numpy))
        assert not np.array_equal(compiled, matrix)  # rows were filled
