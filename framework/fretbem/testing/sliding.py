"""Test helpers for sliding contacts: the block's moment recomputed independently, the
slip amplitude a sliding history gives."""

from __future__ import annotations

import numpy as np

from fretbem.contact import rotation as pad_rotation
from fretbem.contact.faces import FaceField
from fretbem.sliding import solve_sliding

__all__ = ["slip_amplitude", "traction_moment"]

#: Gauss points per interval, intervals per face segment of the independent quadrature
GAUSS, INTERVALS = 8, 400


def traction_moment(step, pair, pivot: np.ndarray | None = None) -> tuple[float, np.ndarray]:
    """Minus the moment of the contact tractions on the pad about its pivot (what the block
    must apply) and their resultant force, in the pad's axes, integrated over its face.
    ``pivot``: in the pad's axes (None: the rig's default above the pair's first contact)."""
    pairing, problem = pair.pairing(), pair.condensed()
    normals, tangents = pairing.axes("upper")
    traction = step.pressure[:, None] * normals - step.shear[:, None] * tangents  # on the pad
    assert pair.slave_side() == "upper"  # the pairs are the pad's nodes, in its order
    body, tag = pair.side("upper")
    field = FaceField.of(body, tag)
    nodes = pairing.pull("upper", traction, axis=0)
    pivot = pad_rotation.pivot(problem) if pivot is None else np.asarray(pivot, float)
    gauss, weights = np.polynomial.legendre.leggauss(GAUSS)
    moment, force = 0.0, np.zeros(2)
    for k, basis in enumerate(field.segments):
        breaks = np.linspace(*basis.curve.domain, INTERVALS + 1)
        low, high = breaks[:-1, None], breaks[1:, None]
        params = (0.5 * (low + high) + 0.5 * (high - low) * gauss).ravel()
        length = (0.5 * (high - low) * weights).ravel() * basis.curve.jacobians(params)
        segment = np.full(params.shape, k)
        values = field.interpolation(segment, params) @ nodes
        arm = field.points(segment, params) - pivot
        moment += float(np.sum((arm[:, 0] * values[:, 1] - arm[:, 1] * values[:, 0]) * length))
        force += values.T @ length
    return -moment, force


def slip_amplitude(simulation) -> float:
    """delta_s of a press-forth-back history with finite sliding: half the range of the
    centre pair's relative tangential displacement between the second and third steps."""
    steps = solve_sliding(simulation, say=lambda _: None).steps
    centre = len(steps[0].pressure) // 2
    middle = [float(np.asarray(s.tangential_displacement)[centre]) for s in steps]
    return 0.5 * (middle[1] - middle[2])
