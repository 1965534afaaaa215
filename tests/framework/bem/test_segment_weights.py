"""Resultant and moment weights of chosen segments only (the contact response reads the
face's and the block's): the full weights there, 0 elsewhere."""

from __future__ import annotations

import numpy as np
import pytest

from fretbem.scenes import cattaneo_mindlin


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
def test_chosen_segments_carry_the_full_weights(basis):
    body = cattaneo_mindlin(basis=basis, pairs=21).pair.upper
    full = body.resultant_weights()
    moments = body.moment_weights([0.1, 2.0])
    for chosen in ([1], [1, 4], []):
        inside = np.zeros(body.n_functions, dtype=bool)
        for k in chosen:
            inside[body.function_slice(k)] = True
        weights = body.resultant_weights(chosen)
        assert np.array_equal(weights[inside], full[inside]) and not weights[~inside].any()
        partial = body.moment_weights([0.1, 2.0], chosen)
        assert np.array_equal(partial[inside], moments[inside]) and not partial[~inside].any()
    assert body.resultant_weights() is full  # the whole array stays cached
