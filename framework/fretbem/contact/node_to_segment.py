"""Node-to-segment pairing: the lower face's nodes projected on the upper face's exact geometry.

The faces need not match: each may have its own family, degree, elements and node count.
The pairs are the lower (slave) face's collocation points; each is projected along the pair
normal onto the upper (master) face's exact NURBS curve, which gives the gap, and the upper
face's displacement there comes through its own basis functions (W = N(s) E^-1). The pair
tractions are a field on the lower face (its basis, its node values); the upper face's node
tractions are that field evaluated where its nodes project on the lower face, which is not
W.T. docs/explanation/pairing.rst gives the reasons and the measured accuracy and cost.
"""

from __future__ import annotations

import attrs
import numpy as np

from fretbem.errors import UnsupportedError

from .faces import FaceField, FaceProjectionError, nearest_nodes
from .pairing import Pairing, turning
from .pairs import ContactDiscretisationError, ContactPair, check_overlap
from .transfer import ALONG_NORMALS, TRANSFERS, NormalMap

__all__ = ["FRAMES", "NodeToSegmentPair"]

#: the pair frames: one for all pairs, or each pair's own
FRAMES = ("shared", "local")


@attrs.frozen(eq=False)
class NodeToSegmentPair(ContactPair):
    """Lower face nodes paired with the upper face by projection along the pair normal.

    By default all pairs share one frame, the lower face's mean normal (as node to node: the
    half-plane idealisation of a non-conformal contact); when the upper body is turned, its
    axis turned with it (its face's mean normal reversed): the frame turns with the pad.
    Matching faces give the pairs of :class:`~fretbem.contact.pairs.NodeToNodePair`
    (within round-off).

    Attributes
    ----------
    offset : ndarray, shape (2,)
        Rigid displacement of the upper body relative to the lower one added to the upper
        face's geometry before projecting (zero: the scene as drawn). A pair built at an
        offset is the re-pairing of a face that slid.
    transfer : str
        How the pair tractions reach the upper nodes (:mod:`fretbem.contact.transfer`):
        ``"conservative"`` (default: the force is kept exactly) or ``"pointwise"``.
    slave : str
        The face whose nodes are the pairs: ``"coarser"`` (default: the face with fewer
        nodes; on a tie a smooth family's face, else the lower one: measured more accurate,
        docs/explanation/pairing.rst),
        ``"lower"`` or ``"upper"``. The other face is projected on.
    uncovered : str
        A slave node past the ends of the other face: ``"refuse"`` (default: the faces
        must cover each other) or ``"open"`` (the pair faces nothing and stays open, at its
        distance from the nearer end; what a face sliding off the other's end needs).
    turn : float
        Rigid rotation (rad, counterclockwise) of the upper body about ``pivot``, applied
        before ``offset``: a pad slid along an arc turns about the arc's centre. The upper
        body keeps its own axes (:attr:`~fretbem.contact.pairing.Pairing.turn`); the pair
        frame turns with it.
    pivot : ndarray, shape (2,)
        The point the upper body turns about.
    frame : str
        The pair frame: ``"shared"`` (default: one for all pairs, as above) or ``"local"``:
        each pair's own, the lower face's outward normal and tangent at the pair's point on it
        (a pad's node projected on the specimen's exact face at its closest point; a specimen
        node's own normal, along which the pad's face is met), the gap along it. On a curved
        specimen the shared frame is the a/R simplification of a non-conformal contact; a pad
        slid along an arc has its pairs spread over a turning face and takes the local
        frames. The loads still act along the shared normal
        (:attr:`~fretbem.contact.pairing.Pairing.axis`). On a straight lower face both agree.
        The pair tractions reach the other face's nodes as the pairs meet it: along the
        shared tangent, or with local frames along each lower normal
        (:data:`~fretbem.contact.transfer.ALONG_NORMALS`), so that the other face's
        tractions have the pairs' moment (docs/explanation/pairing.rst).
    """

    offset: np.ndarray = attrs.field(
        factory=lambda: np.zeros(2), converter=lambda v: np.asarray(v, float).reshape(2)
    )

    transfer: str = attrs.field(default="conservative", validator=attrs.validators.in_(TRANSFERS))
    slave: str = attrs.field(
        default="coarser", validator=attrs.validators.in_(("coarser", "lower", "upper"))
    )
    uncovered: str = attrs.field(
        default="refuse", validator=attrs.validators.in_(("refuse", "open"))
    )
    turn: float = attrs.field(default=0.0, converter=float)
    pivot: np.ndarray = attrs.field(
        factory=lambda: np.zeros(2), converter=lambda v: np.asarray(v, float).reshape(2)
    )
    frame: str = attrs.field(default="shared", validator=attrs.validators.in_(FRAMES))

    description = "lower face nodes projected on the upper face's exact geometry (faces may differ)"

    def pairing(self) -> Pairing:
        """The lower nodes, their projections on the upper face and the transfers (once)."""
        if "pairing" not in self._cache:
            self._cache["pairing"] = self._pair_up()
        return self._cache["pairing"]

    def slave_side(self) -> str:
        """The face whose nodes are the pairs: ``slave`` or, for "coarser", the face with
        fewer nodes; on a tie the face of a smooth (non-interpolatory) family, else the lower."""
        if self.slave != "coarser":
            return self.slave
        n_lower = self.lower.contact_face(self.lower_tag).n_nodes
        n_upper = self.upper.contact_face(self.upper_tag).n_nodes
        if n_upper != n_lower:
            return "upper" if n_upper < n_lower else "lower"
        # a tie: the smoother (non-interpolatory) family's face, else the lower one
        smooth = {label: not _interpolatory(self.side(label)[0]) for label in ("lower", "upper")}
        return "upper" if smooth["upper"] and not smooth["lower"] else "lower"

    def covered(self) -> np.ndarray:
        """Per pair, whether the other face faces it (False only with uncovered = "open")."""
        self.pairing()
        return self._cache["covered"]

    def _field(self, side: str) -> FaceField:
        body, tag = self.side(side)
        try:
            field = FaceField.of(body, tag)
        except FaceProjectionError as err:
            raise ContactDiscretisationError(f"contact pair (node to segment): {err}") from None
        return field.turned(self.turn, self.pivot) if side == "upper" and self.turn else field

    def _face(self, side: str) -> tuple[np.ndarray, np.ndarray]:
        """The face's nodes and outward normals, the upper one's turned about the pivot."""
        face = self.side(side)[0].contact_face(self.side(side)[1])
        if side != "upper" or not self.turn:
            return face.points, face.normals
        turn = turning(self.turn)
        return self.pivot + (face.points - self.pivot) @ turn.T, face.normals @ turn.T

    def unplaced(self, points: np.ndarray) -> np.ndarray:
        """``points`` where the pairing placed the upper body, in its own axes (the
        ``offset`` undone, then the ``turn`` about the ``pivot``)."""
        points = np.asarray(points, float)
        if np.any(self.offset):
            points = points - self.offset
        if self.turn:
            points = self.pivot + (points - self.pivot) @ turning(-self.turn).T
        return points

    def placed(self, side: str) -> np.ndarray:
        """The face's nodes where the pairing places them (the upper turned, then offset)."""
        points = self._face(side)[0]
        return points + self.offset if side == "upper" else points

    def _pair_up(self) -> Pairing:
        slave = self.slave_side()
        master = "upper" if slave == "lower" else "lower"
        faces = {label: self._face(label) for label in ("lower", "upper")}
        normals = faces["lower"][1]
        mean_normal = normals.mean(axis=0) / np.linalg.norm(normals.mean(axis=0))
        if self.turn:  # the frame turns with the pad: its axis, the face's mean normal reversed
            normals = -faces["upper"][1]
            mean_normal = normals.mean(axis=0) / np.linalg.norm(normals.mean(axis=0))
        mean_tangent = np.array([mean_normal[1], -mean_normal[0]])
        # positions of each face as placed: the upper body displaced by ``offset``
        placed = {"lower": np.zeros(2), "upper": self.offset}
        fields = {label: self._field(label) for label in ("lower", "upper")}
        slave_points = faces[slave][0] + placed[slave]
        order = np.argsort(slave_points @ mean_tangent)
        points = slave_points[order]
        master_tag = self.side(master)[1]
        try:
            if self.frame == "shared":
                segment, params = fields[master].locate(
                    (points - placed[master]) @ mean_tangent, mean_tangent
                )
            elif master == "lower":  # the pad's nodes: the specimen's closest points
                segment, params = fields["lower"].project(points, mean_tangent)
            else:  # the specimen's nodes: the pad's face along each one's normal
                lower_normals = faces["lower"][1][order]
                segment, params = fields["upper"].locate_each(
                    points - placed["upper"], _tangents(lower_normals)
                )
        except FaceProjectionError as err:
            raise ContactDiscretisationError(
                f"contact pair: the {master} segment {master_tag!r}: {err}"
            ) from None
        spacing = np.min(np.linalg.norm(np.diff(points, axis=0), axis=1))
        off = np.flatnonzero(segment < 0)
        if off.size and self.uncovered == "refuse":
            k = int(off[0])
            raise ContactDiscretisationError(
                f"contact pair: the {slave} collocation point at {points[k].round(6)} has no "
                f"point of the {master} segment {master_tag!r} facing it (that face does not "
                "reach so far along the surface); both contact faces must cover the candidate "
                "zone: widen the shorter one, or narrow the zone"
            )
        covered = segment >= 0
        master_points = fields[master].points(segment, params) + placed[master]
        # a pair past the master's ends (uncovered = "open") faces nothing: its gap is its
        # distance from the nearer end of the master face, and it moves with neither face
        ends = np.concatenate(
            [fields[master].segments[0].curve.points([0.0]),
             fields[master].segments[-1].curve.points([1.0])]
        ) + placed[master]  # fmt: skip
        nearest = ends[
            np.argmin(
                np.abs((ends @ mean_tangent)[None, :] - (points @ mean_tangent)[:, None]), axis=1
            )
        ]
        distance = np.linalg.norm(nearest - points, axis=1)
        master_points[~covered] = points[~covered]
        upper_points = master_points if master == "upper" else points
        pair_normals = np.tile(mean_normal, (len(order), 1))
        if self.frame == "local":  # the lower face's normal where each pair meets it
            if master == "lower":
                pair_normals[covered] = fields["lower"].normals(segment[covered], params[covered])
            else:
                pair_normals = faces["lower"][1][order]
        if master == "upper":
            up_normals = fields["upper"].normals(segment, params)
            up_normals[~covered] = -pair_normals[~covered]
        else:
            up_normals = faces["upper"][1][order]
        facing = mean_normal if self.frame == "shared" else pair_normals
        self.check_facing(upper_points, up_normals, facing)
        lower_points = points if slave == "lower" else master_points
        if self.frame == "shared":
            gap = np.where(covered, (upper_points - lower_points) @ mean_normal, distance)
        else:
            along_normal = np.einsum("kd,kd->k", upper_points - lower_points, pair_normals)
            gap = np.where(covered, along_normal, distance)
        check_overlap(gap, lower_points, spacing)
        interpolation = fields[master].interpolation(segment, params)
        # the master nodes' tractions: the pair traction field (slave basis) carried over,
        # the faces met as the pairs meet them (along the shared tangent, or each lower normal)
        if self.frame == "shared":
            transfer = TRANSFERS[self.transfer](
                fields[master],
                fields[slave],
                (faces[master][0] + placed[master] - placed[slave]) @ mean_tangent,
                mean_tangent,
                order,
                shift=float((placed[master] - placed[slave]) @ mean_tangent),
            )
        else:
            mapping = NormalMap(
                fields[master], fields[slave], placed[master] - placed[slave],
                "master" if master == "lower" else "slave", mean_tangent,
            )  # fmt: skip
            transfer = ALONG_NORMALS[self.transfer](mapping, *faces[master], order)
        n = len(order)
        self._cache["covered"] = covered
        nodes = {slave: order, master: nearest_nodes(interpolation)}
        interpolations = {master: interpolation}
        if not covered.all():  # a pair facing nothing moves with neither face: it stays open
            select = np.zeros((n, len(faces[slave][0])))
            select[np.flatnonzero(covered), order[covered]] = 1.0
            interpolations[slave] = select
        return Pairing(
            lower_nodes=nodes["lower"],
            upper_nodes=nodes["upper"],
            points=lower_points,
            normals=pair_normals,
            tangents=_tangents(pair_normals),
            gap=np.maximum(gap, 0.0),
            interpolation=interpolations,
            transfer={master: transfer},
            turn=self.turn,
            axis=None if self.frame == "shared" else mean_normal,
        )


def _tangents(normals: np.ndarray) -> np.ndarray:
    """The pair tangents (n_y, -n_x) of unit normals (n, 2)."""
    return np.stack([normals[:, 1], -normals[:, 0]], axis=1)


def _interpolatory(body) -> bool:
    """Whether the body's face family interpolates its node values (lagrange2) or is smooth."""
    try:
        return bool(body.family.interpolatory)
    except UnsupportedError:  # a body model without a family: no preference
        return True
