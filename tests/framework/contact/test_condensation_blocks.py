"""The condensation's node-to-node fast paths give the generic path's numbers: a map of two
blocks [[A, B], [-B, A]] (a half-plane's) condenses on its (n, n) blocks, and responses are
read through views where the pairs take the face nodes in order or reversed."""

import types

import numpy as np
import pytest

from fretbem.contact.condensation import _add_blocks, _add_traction_map, _gather, _node_to_node
from fretbem.contact.pairing import Pairing
from fretbem.contact.unknowns import UnknownLayout
from fretbem.scenes import reference


def pairing(nodes: np.ndarray, interpolation=None) -> Pairing:
    n = len(nodes)
    return Pairing(
        lower_nodes=nodes, upper_nodes=nodes, points=np.zeros((n, 2)),
        normals=np.tile([0.0, 1.0], (n, 1)), tangents=np.tile([1.0, 0.0], (n, 1)),
        gap=np.zeros(n), interpolation=interpolation or {},
    )  # fmt: skip


def interleaved(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    n = a.shape[0]
    out = np.empty((n, 2, n, 2))
    out[:, 0, :, 0], out[:, 0, :, 1], out[:, 1, :, 0], out[:, 1, :, 1] = a, b, -b, a
    return out.reshape(n, 2, 2 * n)


@pytest.mark.parametrize("order", ["in order", "reversed"])
@pytest.mark.parametrize("axes", ["flat", "tilted"])
@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_blocks_equal_the_generic_condensation(order, axes, sign):
    rng = np.random.default_rng(7)
    n, blocks = 11, ("upper",)
    a, b = rng.standard_normal((n, n)), rng.standard_normal((n, n))
    nodes = np.arange(n) if order == "in order" else np.arange(n)[::-1]
    pairs = pairing(nodes)
    if axes == "flat":  # exact zeros in the directions and the frame: skipped terms
        normals, tangents = np.tile([0.0, 1.0], (n, 1)), np.tile([1.0, 0.0], (n, 1))
    else:
        angle = rng.uniform(-0.3, 0.3, n)
        normals = np.stack([-np.sin(angle), np.cos(angle)], axis=1)
        tangents = np.stack([np.cos(angle), np.sin(angle)], axis=1)
    frame = sign * np.stack([-normals, tangents], axis=-1)
    layout = UnknownLayout(n, blocks)
    response = types.SimpleNamespace(traction_map=interleaved(a, b), n_nodes=n)
    expected = [rng.standard_normal((n, layout.size)) for _ in range(2)]
    got = [m.copy() for m in expected]
    directions = (normals, tangents)
    _add_traction_map(pairs, "lower", response, sign,
                      tuple(zip(expected, directions, strict=True)), frame, layout)  # fmt: skip
    step = _node_to_node(pairs, "lower", n)
    assert step == (1 if order == "in order" else -1)
    _add_blocks((a, b), step, sign, tuple(zip(got, directions, strict=True)), frame, layout)
    for want, have in zip(expected, got, strict=True):
        assert np.array_equal(have, want)


def test_only_node_to_node_pairs_take_the_blocks():
    rng = np.random.default_rng(8)
    assert _node_to_node(pairing(np.array([3, 0, 5, 1, 2, 4])), "lower", 6) == 0
    assert _node_to_node(pairing(np.array([0, 2, 1, 3])), "lower", 4) == 0
    assert _node_to_node(pairing(np.arange(1, 5)), "lower", 6) == 0  # fewer pairs
    interpolated = pairing(np.arange(4), {"lower": rng.uniform(size=(4, 6))})
    assert _node_to_node(interpolated, "lower", 6) == 0


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
def test_half_plane_response_gives_its_map_as_two_blocks(basis):
    simulation = reference.cattaneo_mindlin(
        pairs=21, basis=basis, models={"upper": "half-plane", "lower": "half-plane"}
    )
    pair = simulation.pair
    for label in ("upper", "lower"):
        body, tag = pair.side(label)
        response = body.contact_response(tag)
        a, b = response.traction_blocks
        assert np.array_equal(response.traction_map, interleaved(a, b))


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


@pytest.mark.parametrize("step", [1, -1])
def test_per_pair_adds_each_product_as_the_plain_expression(step):
    """Each component gathered into contiguous rows first, the products into one buffer:
    the numbers of ``view += operator[..., j] * frame[:, j, s]`` term by term, bit for bit,
    on a reversed, strided operator (a node-to-node pairing's view)."""
    from fretbem.contact.condensation import _per_pair

    rng = np.random.default_rng(7)
    n = 9
    operator = rng.standard_normal((n, 2 * n)).reshape(n, n, 2)[:, ::step]
    frame = rng.standard_normal((n, 2, 2))
    start = rng.standard_normal((n, 2 * n + 3))
    expected = start.copy()
    view = expected[:, : 2 * n].reshape(n, 2, n)
    for s in range(2):
        view[:, s, :] += operator[..., 0] * frame[:, 0, s]
        view[:, s, :] += operator[..., 1] * frame[:, 1, s]
    out = start.copy()
    _per_pair(operator, frame, add_to=out[:, : 2 * n])
    assert np.array_equal(out, expected)
