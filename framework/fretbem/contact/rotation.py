"""The pad block's rotation: its condensed response, the pivot, and the rotating problem.

A body whose loading block can rotate gives its response to the rotation
(:class:`~fretbem.body.BlockRotation`); condensed onto the pair unknowns it is one column
(the relative displacement per unit rotation theta) and one row (the block's moment M on
the pad). Both refer first to the body's own centre; :func:`rotating` moves them to the
rig's pivot and adds theta to the unknowns x (after the block displacements) and the
moment row to the resultant rows (after the blocks' force rows), so a solver sees one more
unknown and one more equation and nothing else changes. A problem whose pad does not
rotate keeps neither: its unknowns and equations are exactly those of a non-rotating block.

Conventions: theta and M are counterclockwise positive (x to the right, y up); M is the
moment the block applies to the pad about the pivot, which lies on the block's line
(the pad's top; the datum depth of a half-plane pad) above the first-contact point unless
the rig gives its height above that point. The record, the first-contact point and the
pivot are in the pad's own axes (the pad as drawn): a pad placed elsewhere by its pairing
(slid by an offset, turned along an arc) carries its pivot with it, and M, a moment about
a point of the pad, is the same in its axes as in the global frame. So is theta: for a
pad turned along an arc it is the block's tilt from the turned pose, and every column and
row here is taken in the pad's axes (the pair frame seen from them,
:meth:`~fretbem.contact.pairing.Pairing.axes`; the specimen's force turned into them), so
the rotating problem of a turned pad is that of the scene turned back.
"""

from __future__ import annotations

import weakref
from typing import Any

import attrs
import numpy as np

from fretbem.errors import InputError

#: a :class:`~fretbem.contact.condensation.CondensedContact` (which imports this module)
CondensedContact = Any

#: the only body whose block may rotate: the pad's
PAD = "upper"


class RotationError(InputError):
    """A block rotation or moment the bodies or the solver cannot take."""


@attrs.frozen(eq=False)
class PadRotation:
    """The pad block's rotation and moment as affine maps of the pair unknowns x.

    With beta the load amplitudes and theta the block rotation (about ``centre``)::

        relative normal     += normal * theta
        relative tangential += tangential * theta
        block forces        += resultant_rotation * theta
        M = moment_base + moment_load @ beta + moment_map @ x + moment_rotation * theta

    Once :func:`rotating` has put theta in x (``in_unknowns``), its column is part of the
    maps and the record's columns and ``moment_rotation`` are those already in x.

    Attributes
    ----------
    centre : ndarray, shape (2,)
        The point rotation and moment refer to (the pivot once rotating).
    level : float
        y of the block's line (the default pivot height).
    normal, tangential : ndarray, shape (n,)
    moment_map, contact_moment_map : ndarray, shape (n_x,)
        The block's moment on the pad, and the moment of the contact tractions on the pad,
        about ``centre`` per unit x.
    moment_base, moment_rotation : float
    moment_load : ndarray, shape (k,)
    resultant_rotation : ndarray, shape (2 m,)
    scale : float
        A length (the candidate zone's half-width) turning the moment row into force units
        for the solvers' residual.
    in_unknowns : bool
    """

    centre: np.ndarray
    level: float
    normal: np.ndarray
    tangential: np.ndarray
    moment_map: np.ndarray
    moment_base: float
    moment_load: np.ndarray
    moment_rotation: float
    resultant_rotation: np.ndarray
    contact_moment_map: np.ndarray
    scale: float
    in_unknowns: bool = False

    def moment(self, x: np.ndarray, beta: np.ndarray = ()) -> float:
        """M (about ``centre``) at pair unknowns x (theta in x once rotating)."""
        beta = np.asarray(beta, float)  # (np.dot: `@`'s numbers for 1-D operands, cheaper)
        value = self.moment_base + np.dot(self.moment_map, x)
        return float(value + (np.dot(self.moment_load, beta) if beta.size else 0.0))

    def contact_moment(self, x: np.ndarray) -> float:
        """Moment of the contact tractions on the pad about ``centre`` (balances M)."""
        return float(self.contact_moment_map @ x)


def condensed(pairing, layout, names, body, response, frame, per_pair) -> PadRotation:
    """The pad's :class:`~fretbem.body.BlockRotation` condensed through the pairing.

    ``frame`` is the pad's traction frame per unit (p, q); ``per_pair`` the condensation's
    operator-to-pair-columns helper."""
    rotation = response.rotation
    face_nodes = response.n_nodes
    moved = pairing.gather(PAD, rotation.face_map)  # (n, 2): the pad's face moves by +theta
    normals, tangents = pairing.axes(PAD)  # the pair frame in the pad's axes
    moment_map = np.zeros(layout.size)
    contact_map = np.zeros(layout.size)
    traction = pairing.pull(PAD, rotation.m_traction.reshape(1, face_nodes, 2), 1)
    moment_map[layout.tractions] = per_pair(traction, frame)[0]
    contact = pairing.pull(PAD, rotation.contact_moment.reshape(1, face_nodes, 2), 1)
    contact_map[layout.tractions] = per_pair(contact, frame)[0]
    moment_map[layout.block(PAD)] = rotation.m_block
    load = np.zeros(len(names))
    # the pad's own loads (a pad responds to few or none), in the problem's order
    for value, name in zip(rotation.m_load, body.load_names, strict=True):
        load[names.index(name)] = value
    resultant = np.zeros(2 * len(layout.blocks))
    start = 2 * layout.blocks.index(PAD)
    resultant[start : start + 2] = rotation.r_rotation
    points = pairing.points[:, 0]
    return PadRotation(
        centre=np.asarray(rotation.centre, float),
        level=float(rotation.level),
        normal=np.einsum("pd,pd->p", normals, moved),
        tangential=np.einsum("pd,pd->p", tangents, moved),
        moment_map=moment_map,
        moment_base=float(rotation.m_base),
        moment_load=load,
        moment_rotation=float(rotation.m_rotation),
        resultant_rotation=resultant,
        contact_moment_map=contact_map,
        scale=max(0.5 * float(np.ptp(points)), 1e-12),
    )


def first_contact(problem: CondensedContact) -> np.ndarray:
    """The initial first-contact point (the middle of the pairs at the smallest gap), in
    the pad's own axes (read-only; found once per problem: every step's record asks)."""
    point = _FIRST_CONTACT.get(problem)
    if point is None:
        gap = problem.gap
        scale = max(float(np.ptp(gap)), 1e-300)
        closest = gap <= gap.min() + 1e-9 * scale
        points = in_pad_axes(problem.pair, problem.pairing.points[closest])
        point = np.array([0.5 * (points[:, 0].min() + points[:, 0].max()),
                          points[:, 1].mean()])  # fmt: skip
        point.setflags(write=False)
        _FIRST_CONTACT[problem] = point
    return point


#: :func:`first_contact` of each condensed problem (weakly: a dropped problem frees it)
_FIRST_CONTACT: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def in_pad_axes(pair, points: np.ndarray) -> np.ndarray:
    """``points`` (where the pairing placed the pad) in the pad's own axes: the placement
    undone by a pair that places the pad (slid or turned: its ``unplaced``); unchanged for
    a pair that leaves the pad where it was drawn."""
    unplaced = getattr(pair, "unplaced", None)
    return points if unplaced is None else unplaced(points)


def pivot(problem: CondensedContact, pivot_height: float | None = None) -> np.ndarray:
    """The rig's pivot: on the block's line above the first-contact point, or
    ``pivot_height`` (mm) above that point."""
    rotation = _rotation(problem)
    point = first_contact(problem)
    y = rotation.level if pivot_height is None else point[1] + float(pivot_height)
    return np.array([point[0], y])


def _rotation(problem: CondensedContact) -> PadRotation:
    if problem.rotation is None:
        raise RotationError(
            "the pad's loading block cannot rotate in this model: its body model gives no "
            "response to a block rotation (a BEM pad held by Displacement conditions besides "
            "its LoadingBlock, or a body model without rotation); hold the pad by its block "
            "alone, or leave [rig] stiffness_rotation, [load] moment and rotation out"
        )
    return problem.rotation


def _moved(problem: CondensedContact, target: np.ndarray) -> dict:
    """The rotation's column and moment rows referred to ``target`` instead of its centre.

    Rotation about P = rotation about C plus the translation e_z x (C - P); the moment
    about P = the moment about C plus (C - P) x F."""
    rotation = _rotation(problem)
    layout = problem.layout
    offset = rotation.centre - np.asarray(target, float)
    shift = np.array([-offset[1], offset[0]])  # e_z x (C - P)
    cols = layout.block(PAD)
    start = 2 * layout.blocks.index(PAD)
    fx, fy = start, start + 1

    def cross(rows):
        """(C - P) x F for the block force rows (map, base or load)."""
        return offset[0] * rows[fy] - offset[1] * rows[fx]

    resultant_rotation = rotation.resultant_rotation + problem.resultant_map[:, cols] @ shift
    moment_rotation = (
        rotation.moment_rotation + rotation.moment_map[cols] @ shift + cross(resultant_rotation)
    )
    # the contact tractions on the pad: the lower body's force reversed, in the pad's axes
    lower = problem.pairing.to_body(PAD, problem.lower_force_map, axis=0)
    contact_map = rotation.contact_moment_map - (offset[0] * lower[1] - offset[1] * lower[0])
    return {
        "normal": rotation.normal + problem.normal_map[:, cols] @ shift,
        "tangential": rotation.tangential + problem.tangential_map[:, cols] @ shift,
        "resultant_rotation": resultant_rotation,
        "moment_map": rotation.moment_map + cross(problem.resultant_map),
        "moment_base": float(rotation.moment_base + cross(problem.resultant_base)),
        "moment_load": rotation.moment_load + cross(problem.resultant_load),
        "moment_rotation": float(moment_rotation),
        "contact_moment_map": contact_map,
    }


def moment_about(problem: CondensedContact, x, beta, target, *, base=None) -> float:
    """The block's moment about ``target`` at x (a problem not yet rotating): the moment
    about the record's centre plus (C - P) x F, F the block's force. ``base``: the
    resultant rows' base at beta (``problem.base_at("resultant", beta)``), if at hand."""
    rotation = _rotation(problem)
    beta = np.asarray(beta, float)
    offset = rotation.centre - np.asarray(target, float)
    start = 2 * problem.layout.blocks.index(PAD)
    if base is None:
        base = problem.base_at("resultant", beta)
    force = base[start : start + 2] + np.dot(problem.resultant_map[start : start + 2], x)
    return rotation.moment(x, beta) + float(offset[0] * force[1] - offset[1] * force[0])


def about(problem: CondensedContact, target) -> PadRotation:
    """The problem's rotation record referred to ``target`` (a problem not yet rotating)."""
    moved = _moved(problem, target)
    return attrs.evolve(_rotation(problem), centre=np.asarray(target, float), **moved)


def rotating(problem: CondensedContact, target) -> CondensedContact:
    """``problem`` with the pad block's rotation theta about ``target`` added to x and its
    moment about ``target`` (scaled by the record's length) as the last resultant row."""
    if problem.rotation is not None and problem.rotation.in_unknowns:
        return problem
    record = about(problem, target)
    layout = attrs.evolve(problem.layout, rotations=(PAD,))
    column = layout.rotation(PAD)

    def widened(matrix, values):
        out = np.zeros((matrix.shape[0], layout.size))
        out[:, : matrix.shape[1]] = matrix
        out[:, column] = values
        return out

    moment_map = np.append(record.moment_map, record.moment_rotation)
    contact_map = np.append(record.contact_moment_map, 0.0)
    scale = record.scale
    resultant_map = np.vstack(
        [widened(problem.resultant_map, record.resultant_rotation), moment_map / scale]
    )
    resultant_base = np.append(problem.resultant_base, record.moment_base / scale)
    resultant_load = np.vstack([problem.resultant_load, record.moment_load / scale])
    return attrs.evolve(
        problem,
        layout=layout,
        normal_map=widened(problem.normal_map, record.normal),
        tangential_map=widened(problem.tangential_map, record.tangential),
        resultant_map=resultant_map,
        resultant_base=resultant_base,
        resultant_load=resultant_load.reshape(len(resultant_base), -1),
        lower_force_map=widened(problem.lower_force_map, 0.0),
        rotation=attrs.evolve(
            record,
            moment_map=moment_map,
            contact_moment_map=contact_map,
            in_unknowns=True,
        ),
    )


def moment_row(problem: CondensedContact) -> int:
    """Index of the moment row among the resultant rows of a rotating problem."""
    return 2 * len(problem.blocks)


def lever(problem: CondensedContact) -> tuple[float, tuple[float, float]]:
    """The pivot's height h above the first contact, and the candidate zone's ends (mm)
    from that point along x: where the contact's centre can lie at all."""
    rotation = _rotation(problem)
    point = first_contact(problem)
    points = in_pad_axes(problem.pair, problem.pairing.points)[:, 0]
    reach = (float(points.min() - point[0]), float(points.max() - point[0]))
    return float(rotation.centre[1] - point[1]), reach


def no_balance(problem: CondensedContact, step: str, reason: str, *, normal=None,
               tangential=None, moment=None, keys=()) -> str:  # fmt: skip
    """The message for a rotating block whose increment found no solution: the likely
    cause (the block tips: the moment about the pivot needs the contact's centre outside
    the zone) with the pivot's height, the zone and the scene keys that change them.

    ``normal``, ``tangential`` and ``moment`` are the step's P, Q and M when force and
    moment drive it (the needed centre d = (h Q - M) / P is then stated); ``keys`` the scene
    keys that turn the block in this simulation."""
    height, reach = lever(problem)
    numbers = f"h = {height:.4g} mm (the pivot's height above the first contact)"
    if None not in (normal, tangential, moment) and normal > 0:
        centre = (height * tangential - moment) / normal
        numbers += f", d = {centre:.4g} mm, the zone from {reach[0]:.4g} to {reach[1]:.4g} mm"
    else:
        numbers += f", the candidate zone from {reach[0]:.4g} to {reach[1]:.4g} mm about it"
    turning = " or ".join(keys) or "a moment or rotation"
    return (
        f"load step {step!r}: no balance found for the pad block's rotation ({reason}); a "
        f"block turned by {turning} tips when the moment about the pivot needs the contact's "
        f"centre d = (h Q - M) / P outside the contact zone: here {numbers}; lower the moment "
        "or rotation, give a stiffer [rig] stiffness_rotation, put [rig] pivot_height nearer "
        "the contact (0: at it), or widen [contact] zone"
    )
