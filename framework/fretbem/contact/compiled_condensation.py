"""The condensation's projection of a body's traction map in one compiled pass (numba).

:func:`fretbem.contact.condensation._add_traction_map` projects a body's traction map
(face node rows, node traction columns) on the pair frame with a dozen numpy passes over
(pairs x pairs) arrays, each through a temporary; where the pairs take the face nodes one
each (node to node, in order or reversed) this loop reads each entry of the map once and
adds into the normal and tangential maps the same products in the same order (so the same
numbers, bit for bit). Importing this module imports numba: the condensation uses it only
once the compiled assembly loops have loaded numba (:mod:`fretbem.bem.compiled_loops`).
"""

from __future__ import annotations

import numba
import numpy as np


@numba.njit(cache=True, nogil=True, error_model="numpy")
def add_node_to_node(traction_map, step, normals, tangents, frame, normal_map, tangential_map):
    """Add one body's node-to-node traction map, projected, into both maps' traction columns.

    ``traction_map`` (face nodes, 2, 2 face nodes): displacement component i at node r per
    unit traction component j at node c (column 2 c + j); pair p takes node p (``step`` 1)
    or node n - 1 - p (``step`` -1). ``normals``, ``tangents`` (n, 2): the pair directions
    in the body's axes times the body's sign; ``frame`` (n, 2, 2): the traction components
    per unit (p, q) of each pair; ``normal_map``, ``tangential_map`` (n, 2 n): the traction
    columns of the maps (column s n + k: unit s of pair k), added to in place.
    """
    n = traction_map.shape[0]
    for p in range(n):
        r = p if step == 1 else n - 1 - p
        n0, n1 = normals[p, 0], normals[p, 1]
        t0, t1 = tangents[p, 0], tangents[p, 1]
        for k in range(n):
            c = k if step == 1 else n - 1 - k
            a0, a1 = traction_map[r, 0, 2 * c], traction_map[r, 0, 2 * c + 1]
            b0, b1 = traction_map[r, 1, 2 * c], traction_map[r, 1, 2 * c + 1]
            # the projected row (direction_0 x row_0 + direction_1 x row_1), per j
            pn0, pn1 = n0 * a0 + n1 * b0, n0 * a1 + n1 * b1
            pt0, pt1 = t0 * a0 + t1 * b0, t0 * a1 + t1 * b1
            for s in range(2):
                f0, f1 = frame[k, 0, s], frame[k, 1, s]
                column = s * n + k
                normal_map[p, column] = (normal_map[p, column] + pn0 * f0) + pn1 * f1
                tangential_map[p, column] = (tangential_map[p, column] + pt0 * f0) + pt1 * f1


def add_traction_map(traction_map, step, sign, directions, frame, targets) -> None:
    """:func:`add_node_to_node` for the condensation's arguments: ``directions`` the
    (normal, tangential) pair directions in the body's axes, ``targets`` the (normal,
    tangential) maps' traction columns."""
    normals, tangents = (np.ascontiguousarray(sign * d) for d in directions)
    add_node_to_node(traction_map, step, normals, tangents, np.ascontiguousarray(frame), *targets)
