"""A discretised half-plane surface: nodes, and displacement as an affine map of node tractions.

The face is any curve running monotonically in x (a flat line, or the profile of a pad):
its points give the contact geometry (and so the initial gap), while the elasticity is that
of the half-plane below (or above) the straight surface the profile is drawn over, the usual
half-plane idealisation of a non-conformal contact (Johnson 1985, sec. 4.1).
"""

from __future__ import annotations

import attrs
import numpy as np

from fretbem.basis import Basis
from fretbem.material import Material
from fretbem.numerics.quadrature import QuadratureRule
from fretbem.validators import positive

from .influence import DEFAULT_DATUM, FlamantCompliance, check_face, side_sign, surface_integrals
from .joined import JoinedFace


@attrs.frozen(eq=False)
class HalfPlaneSurface:
    """The surface operator of one half-plane on its discretised contact face.

    Attributes
    ----------
    face : Basis or JoinedFace
        The discretised face (one segment, or several joined); its collocation points are
        the nodes where traction and displacement are given. Traction is interpolated by the
        shape functions.
    material : Material
    side : str
        "lower" for a body occupying y < surface (its outward normal +y), "upper" for y >
        surface (outward normal -y).
    datum : float
        Distance d0 (> 0, mm) from a line load at which its ln r displacement is zero (10 mm by
        default). Only a rigid translation of each body depends on it, never the contact
        tractions.
    bulk_origin : float
        x at which the bulk-stress displacement u_x = eps (x - bulk_origin) is zero.
    """

    face: Basis | JoinedFace = attrs.field(
        validator=attrs.validators.instance_of((Basis, JoinedFace))
    )
    material: Material = attrs.field(validator=attrs.validators.instance_of(Material))
    side: str = attrs.field(default="lower")
    datum: float = attrs.field(default=DEFAULT_DATUM, converter=float, validator=positive)
    bulk_origin: float = attrs.field(default=0.0, converter=float)
    _cache: dict = attrs.field(init=False, factory=dict, repr=False)

    def __attrs_post_init__(self) -> None:
        side_sign(self.side)
        check_face(self.face)

    @property
    def compliance(self) -> FlamantCompliance:
        """The line-load constants A, B of the material."""
        return FlamantCompliance.of(self.material)

    @property
    def points(self) -> np.ndarray:
        """Node positions (n, 2): the face's collocation points."""
        if "points" not in self._cache:
            elements, local = self.face.collocation()
            points = self.face.map(elements, local).points
            points.setflags(write=False)
            self._cache["points"] = points
        return self._cache["points"]

    @property
    def normals(self) -> np.ndarray:
        """Outward unit normals (n, 2) of the half-plane: (0, 1) below, (0, -1) above."""
        normal = np.array([0.0, side_sign(self.side)])
        return np.tile(normal, (len(self.points), 1))

    @property
    def collocation_matrix(self) -> np.ndarray:
        """E: traction coefficients to node values."""
        return self.face.collocation_matrix()

    def coefficient_map(self, x) -> np.ndarray:
        """Displacement (m, 2, 2N) at surface abscissae ``x`` per traction coefficient.

        Column 2 b + j: unit coefficient of traction component j on shape function b.
        """
        integrals = surface_integrals(self.face, x, self.datum)
        c, sigma = self.compliance, side_sign(self.side)
        m, n_f = integrals.log.shape
        out = np.zeros((m, 2, n_f, 2))
        log, jump = -c.log * integrals.log, sigma * c.jump * integrals.sign
        out[:, 0, :, 0] = log
        out[:, 0, :, 1] = jump
        out[:, 1, :, 0] = -jump
        out[:, 1, :, 1] = log
        return out.reshape(m, 2, 2 * n_f)

    @property
    def traction_map(self) -> np.ndarray:
        """Displacement (n, 2, 2n) at the nodes per unit node traction (column 2 a + j)."""
        if "traction_map" not in self._cache:
            self._cache["traction_map"] = self.node_map(self.points[:, 0])
            self._cache["traction_map"].setflags(write=False)
        return self._cache["traction_map"]

    def node_map(self, x) -> np.ndarray:
        """Displacement (m, 2, 2n) at surface abscissae ``x`` per unit node traction."""
        per_coefficient = self.coefficient_map(x)
        m = per_coefficient.shape[0]
        n = self.face.n_functions
        # per node value = per coefficient @ E^-1 (coefficients = E^-1 values), as one solve
        blocks = np.moveaxis(per_coefficient.reshape(m, 2, n, 2), 2, -1).reshape(-1, n)
        per_value = np.linalg.solve(self.collocation_matrix.T, blocks.T).T
        return np.moveaxis(per_value.reshape(m, 2, 2, n), -1, 2).reshape(m, 2, 2 * n)

    def bulk_displacement(self, x) -> np.ndarray:
        """Surface displacement (m, 2) per unit far-field stress sigma_xx (the "bulk" load).

        A uniform sigma_xx leaves the straight surface traction free; Hooke's law gives
        u_x = eps (x - bulk_origin) with eps = (1 - nu^2) / E (plane strain) or 1 / E (plane
        stress), and u_y = 0 on the surface.
        """
        x = np.asarray(x, dtype=float)
        out = np.zeros((*x.shape, 2))
        out[..., 0] = self.compliance.bulk_strain(self.material) * (x - self.bulk_origin)
        return out

    def contact_force(self) -> np.ndarray:
        """Resultant force (2, 2n) of the face tractions per unit node traction."""
        # int phi_b |dx| per coefficient, then per node value through E^-1
        weights = np.linalg.solve(self.collocation_matrix.T, _shape_integrals(self.face))
        n = len(weights)
        out = np.zeros((2, n, 2))
        out[0, :, 0] = weights
        out[1, :, 1] = weights
        return out.reshape(2, 2 * n)


def _shape_integrals(face: Basis) -> np.ndarray:
    """int phi_b dx over the projected face, for each shape function b."""
    rule = QuadratureRule.gauss_legendre(12)
    elements = np.repeat(np.arange(face.n_elements), rule.points.size)
    local = np.tile(rule.points, face.n_elements)
    m = face.map(elements, local)
    weights = np.abs(m.tangents[:, 0]) * np.tile(rule.weights, face.n_elements)
    out = np.zeros(face.n_functions)
    np.add.at(out, face.connectivity[elements], m.values * weights[:, None])
    return out
