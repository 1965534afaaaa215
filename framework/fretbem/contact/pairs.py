"""Contact pairs: which points of two contact faces face each other, their frame and gap.

A :class:`ContactPair` knows two bodies and the tags of their faces that may touch; its
:meth:`~ContactPair.pairing` says how the faces are paired (the :class:`Pairing` record).
The pair's unknowns are the pressure p and shear q at each pair point (the traction the
upper body exerts on the lower one, in the pair frame: t_lower = -p n + q t). The
condensation (:class:`~fretbem.contact.condensation.CondensedContact`) and the solvers use only
the Pairing, so a new pairing (node to segment, mortar) needs no change to either.
"""

from __future__ import annotations

from abc import ABC, abstractmethod

import attrs
import numpy as np

from fretbem.body import Body
from fretbem.errors import InputError

from .condensation import CondensedContact
from .law import STATE_NAMES, PairState
from .pairing import Pairing

#: pair states (kept as plain names for array comparisons)
SEPARATED, STICK, SLIP = PairState.SEPARATED, PairState.STICK, PairState.SLIP

__all__ = [
    "SEPARATED",
    "SLIP",
    "STATE_NAMES",
    "STICK",
    "ContactDiscretisationError",
    "ContactPair",
    "NodeToNodePair",
    "check_overlap",
]


def _shown(values: np.ndarray) -> np.ndarray:
    """Coordinates for a message: 6 decimals, a round-off -0 shown as 0."""
    return np.round(values, 6) + 0.0


class ContactDiscretisationError(InputError):
    """The two sides of a contact pair cannot be paired as the pairing requires."""


def check_overlap(gap: np.ndarray, points: np.ndarray, spacing: float) -> None:
    """Refuse an initial gap that is negative beyond round-off: the bodies interpenetrate."""
    if np.any(gap < -1e-9 * max(spacing, 1e-300)):
        k = int(np.argmin(gap))
        raise ContactDiscretisationError(
            f"contact pair: the bodies overlap at the start by {-gap[k]:.3g} at "
            f"{_shown(points[k])}; move the upper body up so the surfaces touch "
            "without interpenetration"
        )


@attrs.frozen(eq=False)
class ContactPair(ABC):
    """Two bodies and the tagged faces that may touch; subclasses say how they pair.

    Friction is not a property of the pair: it belongs to the contact law
    (:class:`~fretbem.contact.law.CoulombFriction`) the Simulation holds.

    Attributes
    ----------
    upper, lower : Body
        The lower body's outward normal on its face defines the pair frame.
    upper_tag, lower_tag : str
        Tags of the faces that may touch.
    """

    upper: Body = attrs.field(validator=attrs.validators.instance_of(Body))
    lower: Body = attrs.field(validator=attrs.validators.instance_of(Body))
    upper_tag: str = "contact"
    lower_tag: str = "contact"
    _cache: dict = attrs.field(init=False, factory=dict, repr=False)

    def __attrs_post_init__(self) -> None:
        for body, tag in ((self.upper, self.upper_tag), (self.lower, self.lower_tag)):
            body.contact_face(tag)  # an unknown tag is a KeyError naming it, now

    @abstractmethod
    def pairing(self) -> Pairing:
        """The pairing of the two faces (compute it once and cache it in ``self._cache``).

        Raises ContactDiscretisationError naming the cause if the faces cannot be paired.
        """

    def check_facing(
        self, upper_points: np.ndarray, upper_normals: np.ndarray, mean_normal: np.ndarray
    ) -> None:
        """Refuse faces that do not look at each other: the upper face's outward normals must
        point back toward the lower face (else a segment on the far side of the upper body
        would "touch" through that body after a rigid translation)."""
        if np.ndim(mean_normal) == 1:
            facing = upper_normals @ mean_normal
        else:  # a normal per pair (the pairs' own frames)
            facing = np.einsum("kd,kd->k", upper_normals, mean_normal)
        if np.any(facing >= 0.0):
            k = int(np.argmax(facing))
            which = "mean outward normal is" if np.ndim(mean_normal) == 1 else "normal there is"
            mean_normal = mean_normal if np.ndim(mean_normal) == 1 else mean_normal[k]
            raise ContactDiscretisationError(
                f"contact pair: the contact segments do not face each other: at "
                f"{_shown(upper_points[k])} the outward normal of the upper segment "
                f"{self.upper_tag!r} is {_shown(upper_normals[k])}, pointing away from the "
                f"lower segment {self.lower_tag!r} (whose {which} {_shown(mean_normal)}); "
                "tag the faces that touch, with the upper body on the side the lower face's "
                "normal points to"
            )

    def side(self, label: str) -> tuple[Body, str]:
        """(body, face tag) of ``label`` ("upper" or "lower")."""
        return {"upper": (self.upper, self.upper_tag), "lower": (self.lower, self.lower_tag)}[label]

    @property
    def n_pairs(self) -> int:
        """Number of pairs."""
        return self.pairing().n_pairs

    def condensed(self) -> CondensedContact:
        """Both bodies condensed onto the pair unknowns (computed once)."""
        if "condensed" not in self._cache:
            self._cache["condensed"] = CondensedContact.build(self)
        return self._cache["condensed"]


@attrs.frozen(eq=False)
class NodeToNodePair(ContactPair):
    """Face nodes paired one to one: the two faces are discretised alike, nodes facing.

    Facing means the same position along the mean tangent of the lower face; all pairs
    share one frame (the lower face's mean normal), the half-plane idealisation of a
    non-conformal contact.
    """

    def pairing(self) -> Pairing:
        """Face nodes paired by position along the lower face (computed once)."""
        if "pairing" not in self._cache:
            self._cache["pairing"] = self._pair_up()
        return self._cache["pairing"]

    def _pair_up(self) -> Pairing:
        lower_face = self.lower.contact_face(self.lower_tag)
        upper_face = self.upper.contact_face(self.upper_tag)
        low_points, normals = lower_face.points, lower_face.normals
        up_points, up_normals = upper_face.points, upper_face.normals
        if len(low_points) != len(up_points):
            raise ContactDiscretisationError(
                f"contact pair: the lower segment {self.lower_tag!r} has {len(low_points)} "
                f"collocation points but the upper {self.upper_tag!r} has {len(up_points)}; "
                "discretise both contact segments alike (same family, degree and number of "
                "elements, mirrored parameters) so their points face each other"
            )
        # facing = same position along the mean tangent (the direction the surfaces share);
        # np.mean's, np.linalg.norm's and np.diff's numbers, by the ufuncs they call
        mean_normal = np.add.reduce(normals, axis=0) / len(normals)
        mean_normal = mean_normal / np.sqrt(np.dot(mean_normal, mean_normal))
        mean_tangent = np.array([mean_normal[1], -mean_normal[0]])
        partner, miss = _facing(low_points, up_points, mean_tangent)
        step = low_points[1:] - low_points[:-1]
        step *= step
        spacing = np.minimum.reduce(np.sqrt(np.add.reduce(step, axis=1)))
        bad = (miss > 1e-3 * spacing).nonzero()[0]  # np.flatnonzero's, without its frames
        # partners are upper node indices: a node taken twice counts above one
        if bad.size or (partner.size and np.bincount(partner).max() > 1):
            k = int(bad[0]) if bad.size else int(np.argmax(np.bincount(partner)))
            raise ContactDiscretisationError(
                f"contact pair: the lower collocation point at {_shown(low_points[k])} has no "
                f"facing point on the upper segment {self.upper_tag!r} (nearest is "
                f"{miss[k]:.3g} off along the surface, point spacing {spacing:.3g}); the "
                "discretisations must match node to node: use the same family and refinement "
                "on both contact segments, with facing parameters"
            )
        along_x = low_points[:, 0]
        along = (
            along_x if np.maximum.reduce(along_x) > np.minimum.reduce(along_x) else low_points[:, 1]
        )
        order = along.argsort()
        low, up = order, partner[order]
        # the faces must look at each other: the upper face's outward normal points back
        # toward the lower face (a segment on the far side of the upper body would
        # otherwise "touch" through that body after a rigid translation)
        self.check_facing(up_points[up], up_normals[up], mean_normal)
        # one frame for all pairs: the mean normal, along which the points face each other
        # (a per-point normal of one curved face would turn part of the normal approach
        # into spurious slip)
        pair_normals, pair_tangents = np.empty((len(low), 2)), np.empty((len(low), 2))
        pair_normals[:] = mean_normal
        pair_tangents[:] = mean_tangent
        gap = np.einsum("pd,pd->p", up_points[up] - low_points[low], pair_normals)
        check_overlap(gap, low_points[low], spacing)
        return Pairing(
            lower_nodes=low,
            upper_nodes=up,
            points=low_points[low],
            normals=pair_normals,
            tangents=pair_tangents,
            gap=np.maximum(gap, 0.0),
        )


def _facing(low_points: np.ndarray, up_points: np.ndarray, tangent: np.ndarray):
    """For each lower point the upper point nearest along ``tangent`` (the first in upper
    order on a tie) and that distance, |(up - low) . t|.

    The upper points sorted by their position along t, each lower point's two neighbours
    in that order are the candidates (the nearest is one of them): O(n log n) where every
    (lower, upper) offset cost O(n^2) (a 3.7 MB array at 481 pairs); the candidates'
    distances are computed as the offsets' were.
    """
    along_up = up_points @ tangent
    order = along_up.argsort(kind="stable")  # (the methods: the functions' numbers, no frames)
    ranked = along_up[order]
    right = np.minimum(ranked.searchsorted(low_points @ tangent), len(ranked) - 1)
    # the left neighbour's group of equal positions starts where its first member stands
    left = ranked.searchsorted(ranked[np.maximum(right - 1, 0)])
    neighbours = np.empty((len(left), 2), dtype=left.dtype)  # np.stack([left, right], axis=1)
    neighbours[:, 0], neighbours[:, 1] = left, right
    candidates = order[neighbours]
    offsets = up_points[candidates] - low_points[:, None, :]
    along = np.abs(offsets @ tangent)
    # the nearer candidate; on equal distances the one first in upper order, as argmin
    pick = (along[:, 1] < along[:, 0]) | (
        (along[:, 1] == along[:, 0]) & (candidates[:, 1] < candidates[:, 0])
    )
    at = (np.arange(len(low_points)), pick.astype(int))
    return candidates[at], along[at]
