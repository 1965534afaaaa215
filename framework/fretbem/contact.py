"""Contact pairs: facing collocation points, local frames, gaps, and the condensed problem.

The pair's unknowns are the pressure p and shear q at each node pair (the traction the
upper body exerts on the lower one, in the lower body's frame: t_lower = -p n + q t).
Each body's collocation system is condensed onto them once, so relative displacements
are an affine function of (p, q, loading-block displacements).
"""

from __future__ import annotations

import time

import attrs
import numpy as np

from ._validators import non_negative
from .body import Body

SEPARATED, STICK, SLIP = 0, 1, 2
STATE_NAMES = ("separated", "stick", "slip")


class ContactDiscretisationError(ValueError):
    """The two sides of a contact pair cannot be paired node to node."""


@attrs.frozen(eq=False)
class ContactPair:
    """Two bodies and the tagged segments that may touch, with Coulomb friction.

    Attributes
    ----------
    upper, lower : Body
        The lower body's normal on the contact segment defines the pair frame.
    friction : float
        Coulomb coefficient f >= 0.
    upper_tag, lower_tag : str
        Tags of the segments that may touch.
    """

    upper: Body
    lower: Body
    friction: float = attrs.field(converter=float, validator=non_negative)
    upper_tag: str = "contact"
    lower_tag: str = "contact"
    _cache: dict = attrs.field(init=False, factory=dict, repr=False)

    def __attrs_post_init__(self) -> None:
        for body, tag in ((self.upper, self.upper_tag), (self.lower, self.lower_tag)):
            body._indices(tag, "the contact pair")

    def _side(self, body: Body, tag: str):
        """Rows of the body's collocation points on the tagged segments, and their E blocks."""
        indices = body.boundary.indices(tag)
        colloc = body.collocation
        rows = np.flatnonzero(np.isin(colloc.segment, indices))
        return rows, colloc.points[rows], colloc.normals[rows]

    @property
    def geometry(self) -> dict[str, np.ndarray]:
        """Pairing and frames: lower/upper collocation rows, positions, normal, tangent, gap."""
        if "geometry" not in self._cache:
            self._cache["geometry"] = self._pair_up()
        return self._cache["geometry"]

    def _pair_up(self) -> dict[str, np.ndarray]:
        low_rows, low_points, normals = self._side(self.lower, self.lower_tag)
        up_rows, up_points, up_normals = self._side(self.upper, self.upper_tag)
        if len(low_rows) != len(up_rows):
            raise ContactDiscretisationError(
                f"contact pair: the lower segment {self.lower_tag!r} has {len(low_rows)} "
                f"collocation points but the upper {self.upper_tag!r} has {len(up_rows)}; "
                "discretise both contact segments alike (same family, degree and number of "
                "elements, mirrored parameters) so their points face each other"
            )
        # facing = same position along the mean tangent (the direction the surfaces share)
        mean_normal = normals.mean(axis=0) / np.linalg.norm(normals.mean(axis=0))
        mean_tangent = np.array([mean_normal[1], -mean_normal[0]])
        offsets = up_points[None, :, :] - low_points[:, None, :]
        along = np.abs(offsets @ mean_tangent)
        partner = np.argmin(along, axis=1)
        spacing = np.min(np.linalg.norm(np.diff(low_points, axis=0), axis=1))
        miss = along[np.arange(len(low_rows)), partner]
        bad = np.flatnonzero(miss > 1e-3 * spacing)
        if bad.size or np.unique(partner).size != partner.size:
            k = int(bad[0]) if bad.size else int(np.argmax(np.bincount(partner)))
            raise ContactDiscretisationError(
                f"contact pair: the lower collocation point at {low_points[k].round(6)} has no "
                f"facing point on the upper segment {self.upper_tag!r} (nearest is "
                f"{miss[k]:.3g} off along the surface, point spacing {spacing:.3g}); the "
                "discretisations must match node to node: use the same family and refinement "
                "on both contact segments, with facing parameters"
            )
        order = np.argsort(low_points[:, 0] if np.ptp(low_points[:, 0]) > 0 else low_points[:, 1])
        low, up = order, partner[order]
        # the faces must look at each other: the upper face's outward normal points back
        # toward the lower face (a segment on the far side of the upper body would
        # otherwise "touch" through that body after a rigid translation)
        facing = up_normals[up] @ mean_normal
        if np.any(facing >= 0.0):
            k = int(np.argmax(facing))
            raise ContactDiscretisationError(
                f"contact pair: the contact segments do not face each other: at "
                f"{up_points[up][k].round(6)} the outward normal of the upper segment "
                f"{self.upper_tag!r} is {up_normals[up][k].round(6)}, pointing away from the "
                f"lower segment {self.lower_tag!r} (whose mean outward normal is "
                f"{mean_normal.round(6)}); tag the faces that touch, with the upper body on "
                "the side the lower face's normal points to"
            )
        # one frame for all pairs: the mean normal, along which the points face each other
        # (the half-plane idealisation of a non-conformal contact; a per-point normal of
        # one curved face would turn part of the normal approach into spurious slip)
        pair_normals = np.tile(mean_normal, (len(low), 1))
        pair_tangents = np.tile(mean_tangent, (len(low), 1))
        gap = np.einsum("pd,pd->p", up_points[up] - low_points[low], pair_normals)
        if np.any(gap < -1e-9 * max(spacing, 1e-300)):
            k = int(np.argmin(gap))
            raise ContactDiscretisationError(
                f"contact pair: the bodies overlap at the start by {-gap[k]:.3g} at "
                f"{low_points[low][k].round(6)}; move the upper body up so the surfaces touch "
                "without interpenetration"
            )
        return {
            "lower_rows": low_rows[low],
            "upper_rows": up_rows[up],
            "points": low_points[low],
            "normals": pair_normals,
            "tangents": pair_tangents,
            "gap": np.maximum(gap, 0.0),
        }

    @property
    def n_pairs(self) -> int:
        """Number of node pairs."""
        return len(self.geometry["gap"])

    def condensed(self) -> CondensedContact:
        """Both bodies condensed onto the pair unknowns (computed once)."""
        if "condensed" not in self._cache:
            self._cache["condensed"] = CondensedContact.build(self)
        return self._cache["condensed"]


def _side_operator(body: Body, tag: str, rows: np.ndarray, frame_t: np.ndarray):
    """Affine map from pair tractions (p, q) and block delta to displacement values at ``rows``.

    ``frame_t`` (n_pairs, 2, 2) gives the traction vector on this body at each pair per unit
    (p, q). Returns (base (n,2), d_lambda (n,2,2n), d_delta (n,2,2), and the block resultant
    map (r0, R_lambda, R_delta)) or None parts for a body without a block.
    """
    contact = (tag,)
    system = body.system(contact)
    colloc_rows_all = np.flatnonzero(np.isin(body.collocation.segment, body.boundary.indices(tag)))
    segments = body.boundary.indices(tag)
    functions = np.concatenate(
        [np.arange(*body.function_slice(k).indices(body.n_functions)) for k in segments]
    )
    # E restricted to the contact segments: values at their collocation points
    e_matrix = np.zeros((len(colloc_rows_all), len(functions)))
    r0 = 0
    for k in segments:
        basis = body.segments[k]
        block = basis.collocation_matrix()
        n = basis.n_functions
        e_matrix[r0 : r0 + n, r0 : r0 + n] = block
        r0 += n
    position = {int(r): i for i, r in enumerate(colloc_rows_all)}
    pick = np.array([position[int(r)] for r in rows])  # pair order -> contact-local row
    n_pairs = len(rows)
    # pair tractions -> traction values at contact collocation points -> coefficients
    values = np.zeros((len(functions), 2, 2 * n_pairs))
    values[pick, :, np.arange(n_pairs)] = frame_t[:, :, 0]
    values[pick, :, n_pairs + np.arange(n_pairs)] = frame_t[:, :, 1]
    coefficients = np.linalg.solve(e_matrix, values.reshape(len(functions), -1))
    coefficients = coefficients.reshape(len(functions), 2, 2 * n_pairs)
    # system.contact_dofs are function-major (2 a + i) over these functions, in this order
    contact_coeff = coefficients.reshape(2 * len(functions), 2 * n_pairs)
    z_lambda = system.contact_response @ contact_coeff  # (2N, 2n)

    def values_at_pairs(z: np.ndarray) -> np.ndarray:
        """Displacement values at the pairs from unknown vector(s) z (contact u part)."""
        u_coefficients = z[system.contact_dofs].reshape(len(functions), 2, *z.shape[1:])
        return np.einsum("cf,f...->c...", e_matrix[pick], u_coefficients)

    base = values_at_pairs(system.base)
    d_lambda = values_at_pairs(z_lambda)
    d_delta = values_at_pairs(system.block_response)
    resultant = None
    if system.block_dofs.size:
        resultant = tuple(
            system.block_resultant(z) for z in (system.base, z_lambda, system.block_response)
        )
    return base, d_lambda, d_delta, resultant, (functions, coefficients)


@attrs.frozen(eq=False)
class CondensedContact:
    """Relative displacements and block resultants as affine maps of x = (p, q, deltas).

    Attributes
    ----------
    normal_map, tangential_map : ndarray, shape (n, n_x)
        Relative normal / tangential displacement (upper minus lower) per unit of x.
    normal_base, tangential_base : ndarray, shape (n,)
    resultant_map : ndarray, shape (2 n_blocks, n_x); resultant_base : (2 n_blocks,)
        Loading-block resultant forces.
    blocks : tuple of str
        Which bodies ("upper", "lower") carry a loading block, in the order of x.
    gap : ndarray
        Initial normal gap of each pair.
    seconds : float
        Wall time of the condensation (excluding assembly).
    """

    pair: ContactPair
    normal_map: np.ndarray
    tangential_map: np.ndarray
    normal_base: np.ndarray
    tangential_base: np.ndarray
    resultant_map: np.ndarray
    resultant_base: np.ndarray
    blocks: tuple[str, ...]
    gap: np.ndarray
    traction_coefficients: dict
    seconds: float

    @classmethod
    def build(cls, pair: ContactPair) -> CondensedContact:
        """Assemble, factorise and condense both bodies of ``pair`` (timed)."""
        geo = pair.geometry
        n = len(geo["gap"])
        for body, tag in ((pair.upper, pair.upper_tag), (pair.lower, pair.lower_tag)):
            body.check_supported((tag,), in_contact=True)
            body.matrices()
        start = time.perf_counter()
        normals, tangents = geo["normals"], geo["tangents"]
        # traction per unit (p, q): on the lower body -p n + q t; on the upper the opposite
        lower_frame = np.stack([-normals, tangents], axis=-1)
        sides = {}
        for label, body, tag, rows, frame in (
            ("upper", pair.upper, pair.upper_tag, geo["upper_rows"], -lower_frame),
            ("lower", pair.lower, pair.lower_tag, geo["lower_rows"], lower_frame),
        ):
            sides[label] = _side_operator(body, tag, rows, frame)
        blocks = tuple(label for label in ("upper", "lower") if sides[label][3] is not None)
        n_x = 2 * n + 2 * len(blocks)
        relative_map = np.zeros((n, 2, n_x))
        relative_base = np.zeros((n, 2))
        resultant_map = np.zeros((2 * len(blocks), n_x))
        resultant_base = np.zeros(2 * len(blocks))
        for label, sign in (("upper", 1.0), ("lower", -1.0)):
            base, d_lambda, d_delta, resultant, _ = sides[label]
            relative_base += sign * base
            relative_map[:, :, : 2 * n] += sign * d_lambda
            if label in blocks:
                k = blocks.index(label)
                cols = slice(2 * n + 2 * k, 2 * n + 2 * k + 2)
                relative_map[:, :, cols] += sign * d_delta
                r0, r_lambda, r_delta = resultant
                resultant_base[2 * k : 2 * k + 2] = r0
                resultant_map[2 * k : 2 * k + 2, : 2 * n] = r_lambda
                resultant_map[2 * k : 2 * k + 2, cols] = r_delta
        return cls(
            pair=pair,
            normal_map=np.einsum("pd,pdx->px", normals, relative_map),
            tangential_map=np.einsum("pd,pdx->px", tangents, relative_map),
            normal_base=np.einsum("pd,pd->p", normals, relative_base),
            tangential_base=np.einsum("pd,pd->p", tangents, relative_base),
            resultant_map=resultant_map,
            resultant_base=resultant_base,
            blocks=blocks,
            gap=geo["gap"],
            traction_coefficients={k: v[4] for k, v in sides.items()},
            seconds=time.perf_counter() - start,
        )

    @property
    def n_pairs(self) -> int:
        return len(self.gap)
