"""The contact response from banded face operators equals the plain dense formulation.

bem_system builds the face response from one LU solve, banded E products and E^T solves on
the face rows only; here it is recomputed the direct way (a dense solve of the collocation
system and the dense inverse of E, as before those shortcuts) on a small scene.
"""

import numpy as np
import pytest

from fretbem.bem.layout import BLOCK, CONTACT, DISPLACEMENT, TRACTION
from fretbem.bem.system import face_rows, face_values_matrix
from fretbem.scenes.reference import cattaneo_mindlin


def dense_response(body, tag):
    """Traction map (n, 2, 2 n), block resultant per traction (2, 2 n) and face force map."""
    h, g = body.matrices()
    layout = body.layout((tag,))
    kinds, known = layout.kinds.ravel(), layout.known.ravel()
    solves_u = (kinds == TRACTION) | (kinds == CONTACT)
    matrix = np.where(solves_u[None, :], h, -g)
    contact = np.flatnonzero(kinds == CONTACT)
    fixed_u, fixed_t = kinds == DISPLACEMENT, kinds == TRACTION
    rhs = g[:, fixed_t] @ known[fixed_t] - h[:, fixed_u] @ known[fixed_u]
    z_contact = np.linalg.solve(matrix, g[:, contact])
    z_base = np.linalg.solve(matrix, rhs)
    e_matrix = face_values_matrix(body, tag)
    n = len(e_matrix)
    inverse = np.linalg.inv(e_matrix)
    per_node = z_contact.reshape(-1, n, 2).transpose(0, 2, 1).reshape(-1, n) @ inverse
    per_node = per_node.reshape(-1, 2, n).transpose(0, 2, 1).reshape(-1, 2 * n)
    traction_map = (e_matrix @ per_node[contact].reshape(n, -1)).reshape(n, 2, 2 * n)
    base = (e_matrix @ z_base[contact].reshape(n, 2)).reshape(n, 2)
    block = np.flatnonzero(kinds == BLOCK)
    weights = np.repeat(body.resultant_weights(), 2)[block]
    select = np.zeros((2, block.size))
    select[block % 2, np.arange(block.size)] = weights
    force = body.resultant_weights()[face_rows(body, tag)[1]] @ inverse
    return traction_map, base, select @ per_node[block], force


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
def test_face_response_equals_the_dense_formulation(basis):
    simulation = cattaneo_mindlin(pairs=41, basis=basis)
    pair = simulation.pair
    for body, tag in ((pair.upper, pair.upper_tag), (pair.lower, pair.lower_tag)):
        traction_map, base, r_traction, force = dense_response(body, tag)
        response = body.contact_response(tag)
        scale = np.max(np.abs(traction_map))
        # measured up to 1e-14 of the largest entry (both bases); the block force 8e-15
        assert np.max(np.abs(response.traction_map - traction_map)) <= 1e-12 * scale
        assert np.max(np.abs(response.base - base)) <= 1e-12 * max(np.max(np.abs(base)), 1e-300)
        assert np.allclose(response.contact_force[0, 0::2], force, rtol=1e-12, atol=0.0)
        if response.has_block:
            r_scale = np.max(np.abs(r_traction))
            assert np.max(np.abs(response.r_traction - r_traction)) <= 1e-12 * r_scale
