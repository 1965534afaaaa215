"""The condensation reads node-to-node responses through views: the same values as the
pairing's gather and pull, for pairs in face order, against it, permuted or interpolated."""

import numpy as np
import pytest

from fretbem.contact.condensation import _gather
from fretbem.contact.pairing import Pairing


def pairing(nodes: np.ndarray, interpolation=None) -> Pairing:
    n = len(nodes)
    return Pairing(
        lower_nodes=nodes, upper_nodes=nodes, points=np.zeros((n, 2)),
        normals=np.tile([0.0, 1.0], (n, 1)), tangents=np.tile([1.0, 0.0], (n, 1)),
        gap=np.zeros(n), interpolation=interpolation or {},
    )  # fmt: skip


@pytest.mark.parametrize("order", ["in order", "reversed", "permuted", "fewer pairs"])
@pytest.mark.parametrize("axis", [0, 1])
def test_views_equal_gather_and_pull(order, axis):
    rng = np.random.default_rng(4)
    face = 9
    nodes = {
        "in order": np.arange(face), "reversed": np.arange(face)[::-1],
        "permuted": rng.permutation(face), "fewer pairs": np.arange(1, face - 1),
    }[order]  # fmt: skip
    values = rng.standard_normal((face, face, 2) if axis else (face, 2, 2 * face))
    pairs = pairing(nodes)
    for pull in (False, True):
        expected = (pairs.pull if pull else pairs.gather)("lower", values, axis)
        got = _gather(pairs, "lower", values, axis, pull=pull)
        assert np.array_equal(got, expected)
        if order in ("in order", "reversed"):
            assert np.shares_memory(got, values)  # a view, no copy


def test_interpolated_pairs_go_through_the_pairing():
    rng = np.random.default_rng(5)
    weights = rng.uniform(size=(4, 6))
    pairs = pairing(np.arange(4), {"lower": weights})
    values = rng.standard_normal((6, 2, 12))
    assert np.array_equal(_gather(pairs, "lower", values), pairs.gather("lower", values))
    assert np.array_equal(_gather(pairs, "lower", values, pull=True), pairs.pull("lower", values))
