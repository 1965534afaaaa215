"""The condensation's compiled projection (a process that has loaded numba) gives the numpy
path's normal and tangential maps bit for bit, for node-to-node pairs in order and in
reverse, both basis families, and leaves other pairings to the numpy path."""

from __future__ import annotations

import numpy as np
import pytest

from fretbem.contact import condensation
from fretbem.scenes import cattaneo_mindlin

pytest.importorskip("numba")
from fretbem.bem import compiled_loops  # noqa: F401 - loads numba as the assembly does


def _maps(simulation, compiled: bool, monkeypatch):
    name = condensation._COMPILED if compiled else "no such module"
    with monkeypatch.context() as patch:
        patch.setattr(condensation, "_COMPILED", name)
        built = condensation.CondensedContact._build(simulation.pair)
    return built


@pytest.mark.parametrize(
    ("basis", "pairs", "lower"), [("nurbs", 41, "arc"), ("lagrange2", 31, "flat")]
)
def test_the_compiled_projection_gives_the_same_maps(basis, pairs, lower, monkeypatch):
    simulation = cattaneo_mindlin(pairs=pairs, models={}, basis=basis, lower=lower)
    steps = {
        label: condensation._node_to_node(
            simulation.pair.pairing(), label, simulation.pair.side(label)[0]
            .contact_face(simulation.pair.side(label)[1]).n_nodes,
        )
        for label in ("upper", "lower")
    }  # fmt: skip
    assert all(steps.values())  # both bodies take the compiled pass
    calls = []
    add = condensation._add_traction_map

    def counted(*args):
        calls.append(args[1])
        return add(*args)

    monkeypatch.setattr(condensation, "_add_traction_map", counted)
    compiled = _maps(simulation, True, monkeypatch)
    numpy = _maps(simulation, False, monkeypatch)
    assert len(calls) == 4
    for name in ("normal_map", "tangential_map", "resultant_map", "lower_force_map"):
        assert np.array_equal(getattr(compiled, name), getattr(numpy, name)), name
    assert np.abs(compiled.normal_map).max() > 0


def test_the_compiled_kernel_adds_in_reverse_order():
    """A reversed pairing (step -1) reads node n - 1 - p for pair p, rows and columns."""
    from fretbem.contact import compiled_condensation

    rng = np.random.default_rng(3)
    n = 5
    traction_map = rng.standard_normal((n, 2, 2 * n))
    normals, tangents = rng.standard_normal((n, 2)), rng.standard_normal((n, 2))
    frame = rng.standard_normal((n, 2, 2))
    got = [np.zeros((n, 2 * n)), np.zeros((n, 2 * n))]
    compiled_condensation.add_traction_map(traction_map, -1, -1.0, (normals, tangents), frame, got)
    reversed_map = traction_map[::-1].reshape(n, 2, n, 2)[:, :, ::-1]  # [p, i, k, j]
    for direction, out in zip((normals, tangents), got, strict=True):
        projected = np.einsum("pi,pikj->pkj", -direction, reversed_map)
        expected = np.einsum("pkj,kjs->psk", projected, frame).reshape(n, 2 * n)
        np.testing.assert_allclose(out, expected, rtol=1e-13, atol=1e-13)
