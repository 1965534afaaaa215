"""The node-to-node pairing's nearest facing point, by sorting, against every offset."""

import numpy as np
import pytest

from fretbem.contact.pairs import _facing


@pytest.mark.parametrize("seed", range(3))
def test_facing_equals_the_nearest_of_every_offset(seed):
    """Partners equal the argmin over all (lower, upper) offsets along the tangent (first
    in upper order on ties, with repeated and rounded points), distances to 1e-15."""
    rng = np.random.default_rng(seed)
    for trial in range(400):
        n, m = rng.integers(1, 30, size=2)
        low, up = rng.standard_normal((n, 2)), rng.standard_normal((m, 2))
        if trial % 3 == 0:  # facing faces, as the pairing meets them
            up = low[rng.permutation(n)] + 1e-9 * rng.standard_normal((n, 2))
        if trial % 4 == 0:  # exact ties
            low, up = np.round(low, 1), np.round(up, 1)
        tangent = np.array([1.0, 0.0]) if trial % 5 == 0 else rng.standard_normal(2)
        tangent /= np.linalg.norm(tangent)
        along = np.abs((up[None] - low[:, None]) @ tangent)
        partner, miss = _facing(low, up, tangent)
        assert np.array_equal(partner, np.argmin(along, axis=1))
        assert np.allclose(miss, along.min(axis=1), rtol=0, atol=1e-15)
