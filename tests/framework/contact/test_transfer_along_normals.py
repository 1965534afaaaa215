"""The pair tractions carried to the other face along each lower normal (a frame per pair).

Along an arc with local frames each pair joins a pad point and the specimen's point whose
normal passes through it; the specimen's nodes take the pair tractions the same way
(:data:`~fretbem.contact.transfer.ALONG_NORMALS`). Checked: on a flat face it is the shared
tangent's transfer (to round-off); the conservative one keeps each pair's force on an arc;
and on a solved slide the specimen's nodal tractions have the pad's force and moment, the
moment short only by the gap's lever int g q ds (the faces' tractions act on faces the
initial gap apart), to the quadrature's accuracy, where the mapping along the pad's tangent
was further off by int g p phi ds (phi: each pair's angle to the pad's axis). Tolerances:
measured values (in the comments) plus a margin.
"""

from __future__ import annotations

from pathlib import Path

import attrs
import numpy as np
import pytest
import tomllib

from fretbem.contact.faces import FaceField
from fretbem.contact.transfer import TRANSFERS
from fretbem.numerics.quadrature import QuadratureRule
from fretbem.scenes.builder import build
from fretbem.scenes.file import scene_from_data
from fretbem.sliding import run_sliding
from fretbem.sliding.track import Track
from fretbem.wear.profile import pair_weights

EXAMPLES = Path(__file__).resolve().parents[3] / "examples"
RULE = QuadratureRule.gauss_legendre(8)


def _pair(example: str, pairs: int, slide: float, slave: str = "upper", basis: str = "nurbs"):
    data = tomllib.loads((EXAMPLES / example).read_text())
    data["contact"].update(pairs=pairs, basis=basis)
    pair = attrs.evolve(build(scene_from_data(data))[0].pair, slave=slave, uncovered="open")
    return Track.of(pair).placed(pair, slide)


def _quadrature(field: FaceField):
    """Per segment: index, Gauss parameters, arc-length weights and points."""
    for index, basis in enumerate(field.segments):
        bounds = np.unique(basis.element_bounds)
        lo, hi = bounds[:-1], bounds[1:]
        s = (lo[:, None] + 0.5 * (RULE.points[None, :] + 1.0) * (hi - lo)[:, None]).ravel()
        w = (0.5 * RULE.weights[None, :] * (hi - lo)[:, None]).ravel()
        points, derivatives = basis.curve.points_and_derivatives(s)
        yield index, s, w * np.linalg.norm(derivatives, axis=1), points


def _integrals(field: FaceField) -> np.ndarray:
    """int L_i ds of each node's field (L = N E^-1: a unit node value)."""
    out = np.zeros(field.n_nodes)
    for index, s, ds, _ in _quadrature(field):
        out += ds @ field.interpolation(np.full(s.shape, index), s)
    return out


def _force_and_moment(field: FaceField, values: np.ndarray, shift) -> tuple:
    """Force and moment about the origin of the node tractions ``values`` (n, 2) on
    ``field`` placed at ``shift``."""
    force, moment = np.zeros(2), 0.0
    for index, s, ds, points in _quadrature(field):
        t = field.interpolation(np.full(s.shape, index), s) @ values
        x = points + shift
        force += ds @ t
        moment += ds @ (x[:, 0] * t[:, 1] - x[:, 1] * t[:, 0])
    return force, moment


@pytest.mark.parametrize("transfer", ["conservative", "pointwise"])
@pytest.mark.parametrize("slave", ["upper", "lower"])
def test_on_a_flat_face_the_normals_are_the_shared_tangent(transfer, slave):
    """examples/gross_sliding_bem.toml's flat specimen, the pad slid 0.7 mm: the transfer
    along each normal is the shared tangent's to round-off (measured 1.4e-14)."""
    pair = attrs.evolve(_pair("gross_sliding_bem.toml", 21, 0.7, slave), transfer=transfer)
    shared = pair.pairing().transfer
    local = attrs.evolve(pair, frame="local").pairing().transfer
    for side, matrix in shared.items():
        assert np.abs(local[side] - matrix).max() < 1e-12 * np.abs(matrix).max()


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
@pytest.mark.parametrize("example", ["gross_sliding_arc.toml", "gross_sliding_groove.toml"])
def test_the_conservative_transfer_keeps_each_pairs_force_on_an_arc(example, basis):
    """The pad's nodes the pairs: each pair's unit traction gives the specimen the pad
    node's force, int over the specimen of its field equal to the pad node's int L ds
    (measured 1.3e-15 to 3.4e-15 relative)."""
    pair = attrs.evolve(_pair(example, 21, 1.0, basis=basis), frame="local")
    pairing = pair.pairing()
    slave_force = _integrals(pair._field("upper"))[pairing.nodes("upper")]
    master_force = _integrals(pair._field("lower")) @ pairing.transfer["lower"]
    assert np.abs(master_force - slave_force).max() < 1e-12 * slave_force.max()


def test_the_conservative_transfer_keeps_the_force_of_specimen_pairs_on_an_arc():
    """The specimen's nodes the pairs (slave = "lower"), most facing nothing: a traction
    field on them within the pad's face (a cos^2 bump over half of it) gives the pad its
    force (measured 2e-12 relative: the field's interpolation tails past the pad's ends,
    which fall by 0.17 an element)."""
    pair = attrs.evolve(_pair("gross_sliding_arc.toml", 21, 1.0, "lower"), frame="local")
    pairing = pair.pairing()
    tangent = pairing.load_frame()[1]
    pad = pair.placed("upper") @ tangent
    centre, half = 0.5 * (pad.max() + pad.min()), 0.25 * np.ptp(pad)
    x = (pairing.points @ tangent - centre) / half
    bump = np.where(np.abs(x) < 1.0, np.cos(0.5 * np.pi * x) ** 2, 0.0)
    slave_force = _integrals(pair._field("lower"))[pairing.nodes("lower")] @ bump
    master_force = _integrals(pair._field("upper")) @ pairing.transfer["upper"] @ bump
    assert abs(master_force - slave_force) < 1e-10 * slave_force


def _slid(example: str, pairs: int):
    data = tomllib.loads((EXAMPLES / example).read_text())
    data["contact"]["pairs"] = pairs
    data["load"]["increments"] = [1, 6, 6]
    return run_sliding(build(scene_from_data(data))[0], note=None)


def _old_transfer(pair) -> np.ndarray:
    """The specimen's transfer of a pad-slave pairing along the pad's tangent (before)."""
    normals = -pair._face("upper")[1]
    axis = normals.mean(axis=0) / np.linalg.norm(normals.mean(axis=0))
    tangent = np.array([axis[1], -axis[0]])
    upper, lower = pair._face("upper"), pair._face("lower")
    order = np.argsort((upper[0] + pair.offset) @ tangent)
    return TRANSFERS[pair.transfer](
        pair._field("lower"), pair._field("upper"), (lower[0] - pair.offset) @ tangent,
        tangent, order, shift=float(-pair.offset @ tangent),
    )  # fmt: skip


@pytest.mark.parametrize("example", ["gross_sliding_arc.toml", "gross_sliding_groove.toml"])
def test_the_specimen_takes_the_pads_force_and_moment(example):
    """The slide and back of the example (21 pairs): the specimen's nodal tractions balance
    the pad's force to round-off (measured 1.1e-15 P) and their moment but for the gap's
    lever int g q ds (3.1e-4 to 4.3e-4 P a) to 4e-7 P a at most (measured: the pairs' sum
    for the lever's integral; 1e-9 to 9e-8 at 31 pairs). Along the pad's tangent the moment
    was off by int g p phi ds further (3.5e-6 to 6.5e-6 P a; the difference of the two
    mappings' moments is it to 0.3 %, measured)."""
    sliding = _slid(example, 21)
    for step in sliding.steps[1:]:
        pair, pairing = step.pair, step.pair.pairing()
        frame = np.stack([-pairing.normals, pairing.tangents], axis=-1)
        traction = (frame @ np.stack([step.pressure, step.shear], axis=-1)[..., None])[..., 0]
        lower, upper = pair._field("lower"), pair._field("upper")
        pad = _force_and_moment(upper, pairing.scatter("upper", -traction, upper.n_nodes),
                                pair.offset)  # fmt: skip
        weights = pair_weights(pair.condensed())
        scale = float(weights @ step.pressure)  # P
        scale *= 0.5 * np.ptp(pairing.points[step.pressure > 0] @ pairing.load_frame()[1])
        lever = float(np.sum(weights * pairing.gap * step.shear))
        axis = pairing.load_frame()[0]
        phi = np.arcsin(axis[0] * pairing.normals[:, 1] - axis[1] * pairing.normals[:, 0])
        tilt = float(np.sum(weights * pairing.gap * step.pressure * phi))
        moments = {}
        for name, transfer in (("normals", pairing.transfer["lower"]),
                               ("tangent", _old_transfer(pair))):  # fmt: skip
            force, moment = _force_and_moment(lower, transfer @ traction, np.zeros(2))
            assert np.linalg.norm(force + pad[0]) < 1e-13 * scale
            moments[name] = moment + pad[1]
        assert 3e-4 < abs(lever) / scale < 5e-4
        assert abs(moments["normals"] - lever) < 6e-7 * scale
        assert 3e-6 < abs(tilt) / scale < 8e-6
        assert moments["tangent"] - moments["normals"] == pytest.approx(tilt, rel=0.01)
