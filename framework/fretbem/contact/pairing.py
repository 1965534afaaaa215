"""The pairing record: which points of two contact faces face each other, frame and gap.

Lowest layer of the contact package: the condensation and the solvers read a pairing
through :meth:`Pairing.gather` and :meth:`Pairing.scatter` only, whatever made it.
"""

from __future__ import annotations

from collections.abc import Mapping

import attrs
import numpy as np

__all__ = ["Pairing", "turning"]


def turning(angle: float) -> np.ndarray:
    """The 2 x 2 matrix turning a vector by ``angle`` (rad, counterclockwise)."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s], [s, c]])


def _frozen_array(value) -> np.ndarray:
    array = np.array(value)
    array.setflags(write=False)
    return array


@attrs.frozen(eq=False)
class Pairing:
    """Which points of the two faces face each other, in which frame, at which gap.

    Pair k joins a point of the lower face and a point of the upper face. Node-to-node
    pairings give the face nodes (``lower_nodes``, ``upper_nodes``, indices into each
    body's :meth:`~fretbem.body.Body.contact_face`). A pairing whose points are not face
    nodes (node to segment, mortar) also gives, per side, an interpolation matrix W
    (n_pairs, n_face_nodes): the displacement at the pair points is W @ (node values);
    ``*_nodes`` then name the nearest node, for reporting. The pair tractions reach the
    face nodes through a transfer matrix S (n_face_nodes, n_pairs), W.T unless the pairing
    gives its own (``transfer``: node to segment evaluates the pair traction field at the
    other face's nodes, which is not W.T). The condensation uses only :meth:`gather`,
    :meth:`pull` and :meth:`scatter`, so it works unchanged for any pairing.

    Attributes
    ----------
    lower_nodes, upper_nodes : ndarray of int, shape (n,)
    points : ndarray, shape (n, 2)
        Pair positions (on the lower face).
    normals, tangents : ndarray, shape (n, 2)
        The pair frame: the lower face's outward normal and the tangent (n_y, -n_x).
    gap : ndarray, shape (n,)
        Initial normal gap (>= 0).
    interpolation : mapping of "lower"/"upper" to ndarray (n, n_face), optional
    transfer : mapping of "lower"/"upper" to ndarray (n_face, n), optional
        Face-node tractions per unit pair traction (default: W.T, or the node selection).
    turn : float
        How far (rad, counterclockwise) the upper body is turned from its own axes, which
        its displacements, tractions and block are given in (0: the axes of the pair frame;
        a pad that slides along an arc turns with it). :meth:`axes` gives the pair frame in
        each body's axes.
    axis : ndarray, shape (2,), or None
        The normal the loads act along, when the pairs have frames of their own (a pad on a
        curved face: each pair's normal is the face's at its point); None: the pairs'
        mean normal (:meth:`load_frame`).
    """

    lower_nodes: np.ndarray = attrs.field(converter=_frozen_array)
    upper_nodes: np.ndarray = attrs.field(converter=_frozen_array)
    points: np.ndarray = attrs.field(converter=_frozen_array)
    normals: np.ndarray = attrs.field(converter=_frozen_array)
    tangents: np.ndarray = attrs.field(converter=_frozen_array)
    gap: np.ndarray = attrs.field(converter=_frozen_array)
    interpolation: Mapping[str, np.ndarray] = attrs.field(factory=dict)
    transfer: Mapping[str, np.ndarray] = attrs.field(factory=dict)
    turn: float = attrs.field(default=0.0, converter=float)
    axis: np.ndarray | None = attrs.field(
        default=None, converter=attrs.converters.optional(_frozen_array)
    )
    #: :meth:`load_frame` per side, read-only (the steps ask for it several times each)
    _frames: dict = attrs.field(init=False, factory=dict, repr=False)

    @property
    def n_pairs(self) -> int:
        """Number of pairs."""
        return len(self.gap)

    def nodes(self, side: str) -> np.ndarray:
        """Face node of each pair on ``side`` ("lower" or "upper")."""
        return {"lower": self.lower_nodes, "upper": self.upper_nodes}[side]

    def axes(self, side: str) -> tuple[np.ndarray, np.ndarray]:
        """The pair normals and tangents in the axes of the body on ``side``: those of the
        pair frame, or for a turned upper body the same directions seen from its axes."""
        if side != "upper" or self.turn == 0.0:
            return self.normals, self.tangents
        back = turning(-self.turn)
        return self.normals @ back.T, self.tangents @ back.T

    def load_frame(self, side: str | None = None) -> tuple[np.ndarray, np.ndarray]:
        """The normal and tangent the loads and the block motion act along: ``axis`` or the
        pairs' mean normal, in the axes of the body on ``side`` (None: the pair frame's);
        read-only arrays, kept."""
        kept = self._frames.get(side)
        if kept is not None:
            return kept
        if self.axis is None:
            normals = self.normals if side is None else self.axes(side)[0]
            normal = normals.mean(axis=0)
        else:
            normal = self.axis if side is None else self.to_body(side, self.axis)
        normal = normal / np.linalg.norm(normal)
        kept = normal, np.array([normal[1], -normal[0]])
        for vector in kept:
            vector.setflags(write=False)
        self._frames[side] = kept
        return kept

    def to_frame(self, side: str, vectors: np.ndarray, axis: int = -1) -> np.ndarray:
        """Vectors given in the axes of the body on ``side`` (components along ``axis``) in
        the pair frame's axes: turned by ``turn`` for the upper body, else unchanged."""
        if side != "upper" or self.turn == 0.0:
            return vectors
        return np.moveaxis(np.tensordot(turning(self.turn), vectors, axes=([1], [axis])), 0, axis)

    def to_body(self, side: str, vectors: np.ndarray, axis: int = -1) -> np.ndarray:
        """Vectors in the pair frame's axes seen from the axes of the body on ``side``."""
        if side != "upper" or self.turn == 0.0:
            return vectors
        return np.moveaxis(np.tensordot(turning(-self.turn), vectors, axes=([1], [axis])), 0, axis)

    def gather(self, side: str, values: np.ndarray, axis: int = 0) -> np.ndarray:
        """Face-node values along ``axis`` -> values at the pair points (W @ values)."""
        matrix = self.interpolation.get(side)
        if matrix is None:
            if type(values) is np.ndarray:  # np.take's numbers, without its dispatch frame
                return values.take(self.nodes(side), axis=axis)
            return np.take(values, self.nodes(side), axis=axis)
        return np.moveaxis(np.tensordot(matrix, values, axes=([1], [axis])), 0, axis)

    def pull(self, side: str, values: np.ndarray, axis: int = 0) -> np.ndarray:
        """Columns per face-node traction along ``axis`` -> columns per pair traction (S.T).

        An operator acting on face-node tractions, composed with the transfer S: what a
        unit pair traction does. For node to node (no S) it is the node selection.
        """
        matrix = self.transfer.get(side)
        if matrix is None:
            return self.gather(side, values, axis)
        return np.moveaxis(np.tensordot(matrix, values, axes=([0], [axis])), 0, axis)

    def scatter(self, side: str, pair_values: np.ndarray, n_nodes: int) -> np.ndarray:
        """Pair-point values (n, ...) -> face-node values (n_nodes, ...) (S @ values)."""
        matrix = self.transfer.get(side)
        if matrix is not None:
            return np.tensordot(matrix, pair_values, axes=1)
        matrix = self.interpolation.get(side)
        if matrix is not None:
            return np.tensordot(matrix.T, pair_values, axes=1)
        out = np.zeros((n_nodes, *pair_values.shape[1:]))
        out[self.nodes(side)] = pair_values
        return out
