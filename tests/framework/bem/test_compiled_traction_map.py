"""The contact response's traction map written by the compiled pass (a process that has
loaded numba, a face of more than ROW_SOLVE_MIN nodes) equals the numpy path's bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from fretbem.bem import system
from fretbem.scenes import cattaneo_mindlin

pytest.importorskip("numba")
from fretbem.bem import compiled_loops  # noqa: F401 - loads numba as the assembly does


@pytest.mark.parametrize(("pairs", "basis"), [(241, "nurbs"), (241, "lagrange2"), (301, "nurbs")])
def test_the_compiled_traction_map_gives_the_numpy_numbers(pairs, basis, monkeypatch):
    pair = cattaneo_mindlin(pairs=pairs, basis=basis).pair
    pad, tag = pair.upper, pair.upper_tag
    assert len(system.face_rows(pad, tag)[1]) > system.ROW_SOLVE_MIN
    compiled = system.contact_response(pad, tag)
    monkeypatch.setattr(system, "_COMPILED", "no such module")
    numpy = system.contact_response(pad, tag)
    for name in ("traction_map", "r_traction", "base", "load_map", "block_map"):
        assert np.array_equal(getattr(compiled, name), getattr(numpy, name)), name
    assert compiled.traction_map.shape == numpy.traction_map.shape
    assert compiled.traction_map.flags.c_contiguous


def test_the_compiled_pass_is_a_banded_product():
    """E @ x along the node axis, transposed into the map's order, against a dense product."""
    from fretbem.bem import compiled_band

    rng = np.random.default_rng(3)
    n, rows = 37, 2 * 37 + 5
    matrix = np.zeros((n, n))
    for d in (-1, 0, 1, 2):
        matrix += np.diag(rng.uniform(0.5, 1.5, n - abs(d)), d)
    solved = rng.standard_normal((n, 2, rows))
    band = system._Band(matrix)
    got = band.left_compiled(solved).reshape(n, 2, n, 2)
    faces = solved[:, :, : 2 * n].reshape(n, 2, n, 2)  # [a, j, c, k]
    expected = np.einsum("bc,ajck->bkaj", matrix, faces)
    np.testing.assert_allclose(got, expected, rtol=1e-13, atol=1e-13)
    assert compiled_band.traction_map is not None
