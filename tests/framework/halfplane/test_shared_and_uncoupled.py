"""Identical half-planes: the shared influence integrals and the uncoupled Newton solve.

Two half-planes of one material whose faces have the same x-projection (two cylinders)
share their influence integrals, which makes the condensed normal/tangential coupling
exactly zero; the Newton steps then solve the normal block and the tangential block apart.
Both must give what each body computed alone and the coupled solve give.
"""

from __future__ import annotations

import numpy as np
import pytest

from fretbem.basis import Refinement
from fretbem.bem import images
from fretbem.halfplane import shared, surface
from fretbem.scenes import reference as scenes
from fretbem.simulation import run
from fretbem.solvers import newton_linear, newton_uncoupled
from fretbem.solvers.newton_uncoupled import UncoupledSteps

HALF_PLANES = {"upper": "half-plane", "lower": "half-plane"}


def _condensed(**kwargs):
    simulation = scenes.cattaneo_mindlin(models=HALF_PLANES, **kwargs)
    return simulation, simulation.pair.condensed()


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
def test_twin_faces_share_their_integrals(basis, monkeypatch):
    """The specimen's traction map from the pad's integrals (reversed) equals its own."""
    simulation, problem = _condensed(basis=basis, pairs=41)
    upper, lower = simulation.pair.upper.surface, simulation.pair.lower.surface
    assert upper._cache["shared"].shared is lower._cache["shared"].shared
    layout = problem.layout
    assert not problem.normal_map[:, layout.shear].any()
    assert not problem.tangential_map[:, layout.pressure].any()
    maps = (problem.normal_map, problem.tangential_map, problem.resultant_map)
    assert newton_linear.normal_part(*maps) is not None
    alone = lower.node_map(lower.points[:, 0])
    scale = np.abs(alone).max()
    assert np.abs(lower.traction_map - alone).max() <= 1e-13 * scale
    assert upper._cache["shared"].shared.value is None  # both took them: nothing kept


@pytest.mark.parametrize(("basis", "pairs"), [("nurbs", 21), ("nurbs", 241), ("lagrange2", 61)])
def test_twin_takes_the_face_check_and_force_weights(basis, pairs):
    """The specimen joins the pad's entry: the face check it passed and its force per unit
    node traction (reversed) stand for the specimen's own, which maps no Gauss point and
    forms no E; the weights equal what it computes alone (measured: 5e-14 of the largest)."""
    simulation, _ = _condensed(basis=basis, pairs=pairs)
    upper, lower = simulation.pair.upper.surface, simulation.pair.lower.surface
    assert upper._cache["shared"].shared.checked
    assert "gauss_samples" not in lower._cache and "collocation_matrix" not in lower._cache
    alone = lower.per_node_value(surface._shape_integrals(lower.face, lower.gauss_samples)[None])
    taken = lower.contact_force()
    assert np.array_equal(taken[0, 0::2], taken[1, 1::2])
    assert np.abs(taken[0, 0::2] - alone[0]).max() <= 2e-13 * np.abs(alone).max()


@pytest.mark.parametrize(("basis", "pairs"), [("nurbs", 21), ("nurbs", 61), ("lagrange2", 41)])
def test_twin_face_is_the_pads_reflected_with_its_nodes(basis, pairs):
    """The specimen's face is the pad's discretisation reflected through the origin, and
    its nodes the pad's negated: bit for bit what its own discretisation and map give (signs
    of zeros included), and E the same."""
    simulation, _ = _condensed(basis=basis, pairs=pairs)
    upper, lower = simulation.pair.upper.surface, simulation.pair.lower.surface
    assert images.source(lower.face) is upper.face
    family = type(lower.face)
    own = family.discretise(simulation.pair.lower.face, simulation.pair.lower.refinement)
    assert own.geometry_coefficients.tobytes() == lower.face.geometry_coefficients.tobytes()
    mapped = own.map(*own.collocation())
    assert lower.points.tobytes() == mapped.points.tobytes()
    assert np.array_equal(lower.collocation_matrix, own.collocation_matrix())


def test_a_face_that_fails_its_check_joins_nothing():
    """The check runs before joining: a failing face leaves the entry unchecked and
    memberless, and the next face is checked again."""
    nodes = np.linspace(0.0, 1.0, 5)
    key = ("nurbs-check", (), Refinement(), "upper", 10.0)

    def bad():
        raise ValueError("x turns back")

    with pytest.raises(ValueError, match="turns back"):
        shared.node_integrals(*key, nodes, check=bad)
    calls = []
    joined = shared.node_integrals(*key, nodes, check=lambda: calls.append(1))
    again = shared.node_integrals(*key, nodes, check=lambda: calls.append(2))
    assert calls == [1] and joined.shared is again.shared and again.shared.members == 2


def test_a_face_without_twin_keeps_nothing():
    """Half-plane pad on a BEM specimen: the pad's integrals are not kept after use."""
    simulation = scenes.cattaneo_mindlin(models={"upper": "half-plane"}, pairs=41)
    simulation.pair.condensed()
    sharing = simulation.pair.upper.surface._cache["shared"].shared
    assert sharing.value is None  # (an earlier scene's pad of this shape may have joined)
    assert sharing.served == sharing.members


def test_faces_that_differ_share_nothing():
    """A flat specimen under a cylinder, or another radius, computes its own integrals."""
    simulation, _ = _condensed(pairs=41, lower="flat")
    upper, lower = simulation.pair.upper.surface, simulation.pair.lower.surface
    assert upper._cache["shared"].shared is not lower._cache["shared"].shared
    other, _ = _condensed(pairs=41, radius=50.0)
    assert other.pair.upper.surface._cache["shared"].shared is not upper._cache["shared"].shared


def test_a_twin_with_other_nodes_computes_its_own():
    """An entry is shared only with a face whose nodes it has."""
    nodes = np.linspace(0.0, 1.0, 5)
    first = shared.node_integrals("nurbs", (), Refinement(), "upper", 10.0, nodes)
    again = shared.node_integrals("nurbs", (), Refinement(), "upper", 10.0, nodes + 1e-14)
    moved = shared.node_integrals("nurbs", (), Refinement(), "upper", 10.0, nodes + 1e-6)
    assert again.shared is first.shared
    assert moved.shared is not first.shared
    # computed once by the first member to ask, handed to the second, then dropped
    calls = []
    value = first.get(lambda: calls.append(1) or np.arange(50.0).reshape(10, 5))
    assert np.array_equal(again.get(lambda: calls.append(2)), value) and calls == [1]
    assert first.shared.value is None


def _cycle(monkeypatch, coupled: bool, **kwargs):
    if coupled:
        monkeypatch.setattr(newton_linear, "normal_part", lambda *maps: None)
        monkeypatch.setattr(newton_uncoupled, "LEAN_BELOW", 0)
    else:  # the split solve at this small size too (it is the default from SPLIT_FROM)
        monkeypatch.setattr(newton_linear, "SPLIT_FROM", 0)
    simulation = scenes.cattaneo_mindlin(models=HALF_PLANES, **kwargs)
    result = run(simulation)
    linear = simulation.solver._linear[simulation.pair.condensed()]
    # small systems take the lean iteration (newton_uncoupled), larger ones the split factor
    split = isinstance(linear, UncoupledSteps) or linear.maps.normal_part is not None
    assert split != coupled
    monkeypatch.undo()
    return result


@pytest.mark.parametrize(
    "kwargs",
    [dict(pairs=61), dict(pairs=61, basis="lagrange2"), dict(pairs=241),
     dict(pairs=41, increments=3, tangential=(0.0, 25.0, -25.0, 29.0), names=tuple("ABCD"))],
)  # fmt: skip
def test_uncoupled_solve_gives_the_coupled_answer(kwargs, monkeypatch):
    """The reference cycles (and one to near gross slip, by increments; 241 pairs through
    bordered solves): the same unknowns to 1e-12 and the same iterations, through the split
    solve and the coupled one."""
    split = _cycle(monkeypatch, False, **kwargs)
    coupled = _cycle(monkeypatch, True, **kwargs)
    for a, b in zip(split.steps, coupled.steps, strict=True):
        assert a.iterations == b.iterations
        assert np.abs(a.unknowns - b.unknowns).max() <= 1e-12 * np.abs(b.unknowns).max()


def test_dissimilar_half_planes_keep_the_coupled_solve():
    """beta != 0: the gap depends on the shear, so the maps have no normal part."""
    _, problem = _condensed(pairs=41, E_lower=200000.0, nu_lower=0.3)
    maps = (problem.normal_map, problem.tangential_map, problem.resultant_map)
    assert newton_linear.normal_part(*maps) is None
