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

Both map the faces onto each other along the pairs' shared tangent. With a frame per pair
(``NodeToSegmentPair(frame="local")``, a pad sliding along an arc) each pair joins its
points along the lower face's own normal there, and :data:`ALONG_NORMALS` maps the faces
the same way: a point of the upper face meets the lower face at its closest point, a point
of the lower face the upper one along its own normal. The conservative one then integrates
over the slave face, its own measure, so the force is kept without a Jacobian of the map.
"""

from __future__ import annotations

import attrs
import numpy as np

from fretbem.numerics.quadrature import QuadratureRule

from .faces import FaceField

__all__ = [
    "ALONG_NORMALS",
    "TRANSFERS",
    "NormalMap",
    "conservative",
    "conservative_along_normals",
    "pointwise",
    "pointwise_along_normals",
]

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
        mass += _products(w_master, cols_m, vals_m, cols_m, vals_m, (n_m, n_m))
        coupling += _products(w_slave, cols_m, vals_m, cols_s, vals_s, (n_m, n_s))
    return _node_map(master, slave, mass, coupling, order)


#: transfer name -> function
TRANSFERS = {"conservative": conservative, "pointwise": pointwise}


@attrs.frozen(eq=False)
class NormalMap:
    """How the points of two faces meet along the lower face's normals.

    Attributes
    ----------
    master, slave : FaceField
        The faces, each in its own coordinates.
    moved : ndarray, shape (2,)
        Where the master face is placed relative to the slave (a point x of the slave is at
        x - moved in the master's coordinates).
    lower : str
        Which of them is the lower face, whose normals join the points: ``"master"`` or
        ``"slave"``.
    tangent : ndarray, shape (2,)
        The pairs' mean tangent: where the closest-point search starts.
    """

    master: FaceField
    slave: FaceField
    moved: np.ndarray
    lower: str
    tangent: np.ndarray

    def to_master(self, points: np.ndarray, normals: np.ndarray) -> tuple:
        """Where slave points (with the slave's normals there) meet the master face."""
        points = np.asarray(points, float) - self.moved
        if self.lower == "master":  # the lower face's point whose normal passes through
            return self.master.closest(points, self.tangent)
        return self.master.locate_each(points, _tangents(normals))

    def to_slave(self, points: np.ndarray, normals: np.ndarray) -> tuple:
        """Where master points (with the master's normals there) meet the slave face."""
        points = np.asarray(points, float) + self.moved
        if self.lower == "master":
            return self.slave.locate_each(points, _tangents(normals))
        return self.slave.closest(points, self.tangent)


def _tangents(normals: np.ndarray) -> np.ndarray:
    return np.stack([normals[:, 1], -normals[:, 0]], axis=1)


def pointwise_along_normals(mapping: NormalMap, nodes, normals, order) -> np.ndarray:
    """:func:`pointwise` with the faces met along the lower face's normals: the slave field
    where each master node (``nodes``, ``normals``: the master face's, in its coordinates)
    meets the slave face."""
    return mapping.slave.interpolation(*mapping.to_slave(nodes, normals))[:, order]


def conservative_along_normals(mapping: NormalMap, nodes, normals, order) -> np.ndarray:
    """:func:`conservative` with the faces met along the lower face's normals.

    The coupling of the master basis with the slave field, int N_m(X(r)) t_slave(r)
    ds_slave, is integrated over the slave face (X(r): where its point r meets the master
    face), on sub-intervals between the slave's breakpoints and the master's mapped onto
    it, so the force the master receives is the slave's to the quadrature's accuracy
    (partition of unity) and no Jacobian of the map is needed; the mass is the master's own.
    ``nodes`` and ``normals`` are unused (the signature of :func:`pointwise_along_normals`).
    """
    master, slave = mapping.master, mapping.slave
    rule = QuadratureRule.gauss_legendre(POINTS_PER_INTERVAL)
    n_m, n_s = master.n_nodes, slave.n_nodes
    mass = np.zeros(n_m * n_m)
    breaks, break_normals = [], []
    for index, basis in enumerate(master.segments):
        bounds = np.unique(basis.element_bounds)
        s, w = _gauss(rule, bounds[:-1], bounds[1:])
        w_master = w * np.linalg.norm(basis.curve.derivatives(s), axis=1)
        cols, vals = master.local(np.full(s.shape, index), s)
        mass += _products(w_master, cols, vals, cols, vals, (n_m, n_m))
        breaks.append(basis.curve.points(bounds))
        break_normals.append(basis.curve.normals(bounds))
    on_slave = mapping.to_slave(np.concatenate(breaks), np.concatenate(break_normals))
    coupling = np.zeros(n_m * n_s)
    for index, basis in enumerate(slave.segments):
        curve = basis.curve
        bounds = np.unique(basis.element_bounds)
        cuts = np.unique(np.concatenate([bounds, on_slave[1][on_slave[0] == index]]))
        lo, hi = cuts[:-1], cuts[1:]
        keep = hi - lo > 1e-14
        s, w = _gauss(rule, lo[keep], hi[keep])
        points, derivatives = curve.points_and_derivatives(s)
        w_slave = w * np.linalg.norm(derivatives, axis=1)
        m_seg, m_par = mapping.to_master(points, curve.normals(s))
        cols_m, vals_m = master.local(m_seg, m_par)  # zero off the master face
        cols_s, vals_s = slave.local(np.full(s.shape, index), s)
        coupling += _products(w_slave, cols_m, vals_m, cols_s, vals_s, (n_m, n_s))
    return _node_map(master, slave, mass, coupling, order)


def _products(weights, rows, row_values, cols, col_values, shape: tuple) -> np.ndarray:
    """Sum over quadrature points of w N_row N_col, as a flat ``shape`` matrix, from the few
    functions alive at each point (``rows``/``cols``: their numbers, per point)."""
    return np.bincount(
        (rows[:, :, None] * shape[1] + cols[:, None, :]).ravel(),
        (weights[:, None, None] * row_values[:, :, None] * col_values[:, None, :]).ravel(),
        minlength=shape[0] * shape[1],
    )


def _node_map(master: FaceField, slave: FaceField, mass, coupling, order) -> np.ndarray:
    """Node values of the master field per unit slave node value: E_m M^-1 B E_s^-1."""
    n_m, n_s = master.n_nodes, slave.n_nodes
    coefficients = np.linalg.solve(
        mass.reshape(n_m, n_m), coupling.reshape(n_m, n_s) @ slave.inverse_values_matrix()
    )
    return (master.values_matrix() @ coefficients)[:, order]


def _gauss(rule: QuadratureRule, lo: np.ndarray, hi: np.ndarray) -> tuple:
    """Gauss points and parameter weights of ``rule`` on each interval [lo, hi]."""
    s = (lo[:, None] + 0.5 * (rule.points[None, :] + 1.0) * (hi - lo)[:, None]).ravel()
    w = (0.5 * rule.weights[None, :] * (hi - lo)[:, None]).ravel()
    return s, w


#: transfer name -> function, the faces met along the lower face's normals (a frame per pair)
ALONG_NORMALS = {"conservative": conservative_along_normals, "pointwise": pointwise_along_normals}
