"""Node-to-segment pairing: matching faces give node-to-node's numbers, mismatched faces
keep equilibrium, and every refusal names its cause.

Tolerances are measured values (in the comments) plus a margin.
"""

import attrs
import numpy as np
import pytest

from fretbem import registry
from fretbem.contact.node_to_segment import NodeToSegmentPair
from fretbem.contact.pairs import ContactDiscretisationError, NodeToNodePair
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run


@pytest.fixture(scope="module")
def matching():
    """The reference scene at 61 nurbs pairs (both faces alike), its node-to-node cycle."""
    simulation = cattaneo_mindlin(pairs=61)
    return simulation, run(simulation)


def _with_pair(simulation, pair):
    return attrs.evolve(simulation, pair=pair)


def test_matching_faces_give_the_node_to_node_unknowns(matching):
    """Projection on faces that match node to node: the same unknowns (measured 4e-11 MPa,
    p0 about 230 MPa) and the same Newton iterations."""
    simulation, reference = matching
    pair = NodeToSegmentPair(simulation.pair.upper, simulation.pair.lower)
    result = run(_with_pair(simulation, pair))
    for mine, theirs in zip(result.steps, reference.steps, strict=True):
        assert np.max(np.abs(mine.unknowns - theirs.unknowns)) <= 1e-9
        assert mine.iterations == theirs.iterations
    pairing, nodal = pair.pairing(), simulation.pair.pairing()
    assert np.array_equal(pairing.lower_nodes, nodal.lower_nodes)
    assert np.array_equal(pairing.upper_nodes, nodal.upper_nodes)
    # interpolation and transfer are the node selection (to round-off)
    select = np.zeros_like(pairing.interpolation["upper"])
    select[np.arange(pairing.n_pairs), nodal.upper_nodes] = 1.0
    assert np.max(np.abs(pairing.interpolation["upper"] - select)) < 1e-9
    assert np.max(np.abs(pairing.transfer["upper"] - select.T)) < 1e-9


def _faces_force(pair, result):
    """Contact force on the lower face and on the upper face (global x, y), last step."""
    problem = pair.condensed()
    unknowns = problem.unknowns(result.steps[-2].unknowns)
    pairing = pair.pairing()
    frame = np.stack([-pairing.normals, pairing.tangents], axis=-1)
    on_lower = (frame @ np.stack([unknowns.pressure, unknowns.shear], -1)[..., None])[..., 0]
    forces = {}
    for label, sign in (("lower", 1.0), ("upper", -1.0)):
        body, tag = pair.side(label)
        nodes = pairing.scatter(label, sign * on_lower, body.contact_face(tag).n_nodes)
        forces[label] = body.contact_response(tag).contact_force @ nodes.ravel()
    return forces


@pytest.mark.parametrize(
    ("upper", "lower"),
    [(("nurbs", 97), ("nurbs", 61)), (("nurbs", 61), ("lagrange2", 61))],
)
def test_mismatched_faces_keep_equilibrium(upper, lower):
    """The upper face receives exactly the force the lower face carries (measured 1e-13 x P
    with the conservative transfer), and the integrals of p and q give P and Q as in the
    node-to-node run (5e-5 x P); the pointwise transfer loses up to 1.1e-3 x P."""
    simulation = cattaneo_mindlin(pairs=lower[1], basis=lower[0])
    other = cattaneo_mindlin(pairs=upper[1], basis=upper[0]).pair.upper
    pair = NodeToSegmentPair(other, simulation.pair.lower)
    result = run(_with_pair(simulation, pair))
    for step in result.steps:
        normal, shear = step.resultant
        assert abs(normal - step.normal) <= 1e-4 * step.normal
        assert abs(shear - step.tangential) <= 1e-4 * step.normal
    forces = _faces_force(pair, result)
    assert np.max(np.abs(forces["upper"] + forces["lower"])) <= 1e-10 * 100.0
    if lower[0] == "lagrange2":
        pointwise = NodeToSegmentPair(other, simulation.pair.lower, transfer="pointwise")
        loose = run(_with_pair(simulation, pointwise), check=False)
        assert abs(loose.steps[0].resultant[0] - 100.0) > 5e-4 * 100.0


def test_coarser_face_is_the_slave():
    """The pairs are the nodes of the face with fewer of them, whichever body it is."""
    fine = cattaneo_mindlin(pairs=97)
    coarse = cattaneo_mindlin(pairs=61)
    down = NodeToSegmentPair(fine.pair.upper, coarse.pair.lower)
    up = NodeToSegmentPair(coarse.pair.upper, fine.pair.lower)
    assert (down.slave_side(), down.n_pairs) == ("lower", 61)
    assert (up.slave_side(), up.n_pairs) == ("upper", 61)
    # the pair points lie on the lower face, whichever face is the slave
    assert np.all(np.abs(up.pairing().points[:, 1] + up.pairing().points[:, 0] ** 2 / 140) < 1e-6)
    mixed = NodeToSegmentPair(
        cattaneo_mindlin(pairs=61, basis="lagrange2").pair.upper, coarse.pair.lower
    )
    assert mixed.slave_side() == "lower"  # a tie: the smooth (nurbs) face


def test_registered_and_named_in_scenes():
    """Both pairings are plugins of the fretbem.pairings group."""
    assert registry.get("node-to-segment", "pairings") is NodeToSegmentPair
    assert registry.get("node-to-node", "pairings") is NodeToNodePair


def test_upper_face_too_short_is_refused():
    """A lower node no upper point faces is an error naming the point and the fix."""
    simulation = cattaneo_mindlin(pairs=31)
    narrow = cattaneo_mindlin(pairs=31, zone=1.2).pair.upper
    pair = NodeToSegmentPair(narrow, simulation.pair.lower, slave="lower")
    with pytest.raises(ContactDiscretisationError, match="has no point of the upper segment"):
        pair.pairing()


def test_bad_settings_are_refused():
    """transfer and slave take named values only."""
    simulation = cattaneo_mindlin(pairs=21)
    with pytest.raises(ValueError, match="transfer"):
        NodeToSegmentPair(simulation.pair.upper, simulation.pair.lower, transfer="mortar")
    with pytest.raises(ValueError, match="slave"):
        NodeToSegmentPair(simulation.pair.upper, simulation.pair.lower, slave="finer")
