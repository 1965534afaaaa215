"""How the pair tractions (a field on the slave face) reach the master face's nodes.

Node-to-segment pairing puts the pairs on one face (the slave) and projects them on the
other (the master). Two transfers, both giving a matrix S (n_master_nodes, n_pairs) of
master node tractions per unit pair traction (the sign is the condensation's):

``pointwise``
    the slave face's traction field evaluated where each master node projects;
``conservative``
    its projection onto the master face's basis in the L2 sense, weighted so that the
    integral is kept: the force the master face receives equals the force on the slave
    face exactly (both bases reproduce constants), which the pointwise values do only to
    the interpolation error (0.11 % of P with a lagrange2 slave face, measured).

On faces that match node to node both give the node selection of node-to-node pairing.
"""

from __future__ import annotations

import numpy as np

from fretbem.numerics.quadrature import QuadratureRule

from .faces import FaceField

__all__ = ["TRANSFERS", "conservative", "pointwise"]

#: Gauss points per sub-interval between the breakpoints of both faces (the integrand is
#: a product of two piecewise polynomials, rational for NURBS: 8 points integrate it to
#: round-off at the element sizes of a contact zone)
POINTS_PER_INTERVAL = 8


def pointwise(
    master: FaceField, slave: FaceField, master_along, tangent, order, shift: float = 0.0
) -> np.ndarray:
    """The slave field at the master nodes' projections (zero for nodes off the slave face).

    ``master_along``: the master nodes' positions along the pair tangent in the slave face's
    own coordinates (where they are, less the slave face's placement: a pad slid along the
    track is the slave); ``shift``: the master face's displacement along it relative to the
    slave (used by :func:`conservative`); ``order``: the slave face nodes in pair order.
    """
    at_slave = slave.locate(np.asarray(master_along), tangent)
    return slave.interpolation(*at_slave)[:, order]


def conservative(
    master: FaceField, slave: FaceField, master_along, tangent, order, shift: float = 0.0
) -> np.ndarray:
    """The slave field projected on the master basis, its integral (the force) kept exactly.

    Arguments as :func:`pointwise` (``master_along`` unused: the projection integrates).
    Minimises the integral over the master face of (t_master - g)^2, g the slave field per
    unit master arc length (t_slave ds_slave / ds_master), on sub-intervals between the
    breakpoints of both faces (each mapped along the pair tangent).
    """
    rule = QuadratureRule.gauss_legendre(POINTS_PER_INTERVAL)
    slave_breaks = np.concatenate(
        [b.curve.points(np.unique(b.element_bounds)) @ tangent for b in slave.segments]
    )
    n_m, n_s = master.n_nodes, slave.n_nodes
    mass = np.zeros(n_m * n_m)
    coupling = np.zeros(n_m * n_s)
    for index, basis in enumerate(master.segments):
        curve = basis.curve
        seg, params = master.locate(slave_breaks - shift, tangent)
        cuts = np.unique(np.concatenate([np.unique(basis.element_bounds), params[seg == index]]))
        lo, hi = cuts[:-1], cuts[1:]
        keep = hi - lo > 1e-14
        lo, hi = lo[keep], hi[keep]
        s = (lo[:, None] + 0.5 * (rule.points[None, :] + 1.0) * (hi - lo)[:, None]).ravel()
        w = (0.5 * rule.weights[None, :] * (hi - lo)[:, None]).ravel()
        d_master = curve.derivatives(s)
        s_seg, r = slave.locate(curve.points(s) @ tangent + shift, tangent)
        # slave arc length per unit master parameter: |C_s'(r)| |dxi/ds| / |dxi/dr|
        d_slave = np.zeros_like(d_master)
        for k, slave_basis in enumerate(slave.segments):
            here = s_seg == k
            if here.any():
                d_slave[here] = slave_basis.curve.derivatives(r[here])
        along = np.abs(d_slave @ tangent)
        ratio = np.divide(np.abs(d_master @ tangent), along, out=np.zeros_like(w), where=along > 0)
        w_master = w * np.linalg.norm(d_master, axis=1)
        w_slave = w * np.linalg.norm(d_slave, axis=1) * ratio
        # mass and coupling in coefficient space, from the few functions alive at each point
        cols_m, vals_m = master.local(np.full(s.shape, index), s)
        cols_s, vals_s = slave.local(s_seg, r)
        mass += np.bincount(
            (cols_m[:, :, None] * n_m + cols_m[:, None, :]).ravel(),
            (w_master[:, None, None] * vals_m[:, :, None] * vals_m[:, None, :]).ravel(),
            minlength=n_m * n_m,
        )
        coupling += np.bincount(
            (cols_m[:, :, None] * n_s + cols_s[:, None, :]).ravel(),
            (w_slave[:, None, None] * vals_m[:, :, None] * vals_s[:, None, :]).ravel(),
            minlength=n_m * n_s,
        )
    # node values of the master field per unit slave node value: E_m M^-1 B E_s^-1
    coefficients = np.linalg.solve(
        mass.reshape(n_m, n_m), coupling.reshape(n_m, n_s) @ slave.inverse_values_matrix()
    )
    return (master.values_matrix() @ coefficients)[:, order]


#: transfer name -> function
TRANSFERS = {"conservative": conservative, "pointwise": pointwise}
