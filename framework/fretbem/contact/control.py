"""Loading by force or by displacement: the loading block's equations for each control.

Under force control the upper body's loading block carries the prescribed force
(-P n + Q t). Under displacement control one of its two resultant equations is replaced
by a constraint on the block's own displacement, measured against a datum:

- tangential: delta = t . (u_block(upper) - u_block(lower)), the pad's block against the
  specimen's held end (a specimen without a loading block is held: its block displacement
  is 0); Q is then an output;
- normal: the approach alpha = -n . (u_block(upper) - u_block(lower)) (> 0 presses); P is
  then an output.

A rig puts springs between the actuator and the pad's block (:class:`Rig`, stiffness per
unit thickness in x along t and y along n): the imposed displacement is then the
actuator's, delta_a = delta + Q / k_t and alpha_a = alpha + P / k_n, which is what a rig
measures; the springs are elastic, so they change the loop's shape, not its area.

The pad's block may also rotate (:mod:`fretbem.contact.rotation`): its rotation theta about
the rig's pivot is then an unknown and its moment M a resultant row, which a step drives by
the moment (M imposed) or by the actuator's rotation theta_a = theta + M / k_r through a
rotational spring k_r (the row k L (theta + M / k_r) = k L theta_a; a rigid rig holds
theta = theta_a, by default 0).

The replaced rows are scaled by a contact stiffness, so that the solvers' force-relative
residual measures them in force units too. A controlled problem is the same
:class:`~fretbem.contact.condensation.CondensedContact` with other resultant rows, so every
solver takes it unchanged.
"""

from __future__ import annotations

import math
import weakref

import attrs
import numpy as np

from fretbem.errors import InputError
from fretbem.validators import real_number

from . import rotation as pad_rotation
from .condensation import CondensedContact

#: the two controls of a loading-block direction
CONTROLS = ("force", "displacement")
#: the two controls of the pad block's rotation
ROTATION_CONTROLS = ("rotation", "moment")


#: the farthest a rig's pivot may sit from the contact, mm (10 m: beyond any fretting rig)
MAX_PIVOT_HEIGHT = 1.0e4
#: the unit of each rig stiffness
STIFFNESS_UNITS = {
    "tangential": "N/mm per mm of travel",
    "normal": "N/mm per mm of travel",
    "rotational": "N mm/mm per rad",
}


def check_stiffness(where: str, value: float, unit: str, *, rigid: str, error=InputError) -> float:
    """``value`` unless it is not > 0 (NaN included): the message names ``where``, the unit
    and ``rigid`` (how to ask for a rigid rig). The scene reader and :class:`Rig` share it."""
    if not value > 0:
        raise error(f"{where} must be > 0 ({unit}), got {value!r}; {rigid}")
    return value


def check_pivot_height(where: str, value: float, *, omit: str, error=InputError) -> float:
    """``value`` unless the pivot is farther than ``MAX_PIVOT_HEIGHT`` from the contact
    (NaN included); ``omit`` says how to ask for the block's line. Shared with the scene
    reader, so a file and a script get the same message."""
    if not abs(value) <= MAX_PIVOT_HEIGHT:
        raise error(
            f"{where} is the pivot's height above the first contact, within "
            f"{MAX_PIVOT_HEIGHT:g} mm of it (a rig's pivot; M = h Q grows with it), got "
            f"{value!r}; give the height in mm, or {omit} for the pad block's line"
        )
    return value


def _stiffness(value, field) -> float:
    where, unit = f"Rig.{field.name}", STIFFNESS_UNITS[field.name]
    rigid = "give math.inf (the default) for a rigid rig"
    value = real_number(where, value, what=unit, fix=rigid, infinite=True, error=InputError)
    return check_stiffness(where, value, unit, rigid=rigid)


def _pivot_height(value) -> float | None:
    if value is None:
        return None
    omit = "pass None"
    where = "Rig.pivot_height"
    fix = f"give the height in mm, or {omit} for the pad block's line"
    value = real_number(where, value, what="mm above the first contact", fix=fix, error=InputError)
    return check_pivot_height(where, value, omit=omit)


@attrs.frozen
class Rig:
    """Springs between the actuator and the pad's loading block.

    Attributes
    ----------
    tangential, normal : float
        Stiffness k_t, k_n (N/mm per mm of travel = MPa), > 0; ``math.inf`` (the default)
        is a rigid connection.
    rotational : float
        Rotational stiffness k_r (N mm/mm per rad), > 0, about the pivot; ``math.inf``
        (the default) holds the block's rotation at the actuator's (0 unless a step gives
        one): the block then does not rotate, as in a rig without this spring.
    pivot_height : float or None
        Height (mm) of the pivot above the initial first-contact point, where the block's
        rotation and moment are taken; None (the default): on the block's line (the pad's
        top, the datum depth of a half-plane pad) above that point; at most
        ``MAX_PIVOT_HEIGHT`` (mm) above or below it.
    """

    tangential: float = attrs.field(
        default=float("inf"), converter=attrs.Converter(_stiffness, takes_field=True)
    )
    normal: float = attrs.field(
        default=float("inf"), converter=attrs.Converter(_stiffness, takes_field=True)
    )
    rotational: float = attrs.field(
        default=float("inf"), converter=attrs.Converter(_stiffness, takes_field=True), kw_only=True
    )
    pivot_height: float | None = attrs.field(default=None, converter=_pivot_height, kw_only=True)

    @property
    def compliances(self) -> tuple[float, float]:
        """(1 / k_n, 1 / k_t): the springs' travel per unit P and Q."""
        return 1.0 / self.normal, 1.0 / self.tangential

    @property
    def rotational_compliance(self) -> float:
        """1 / k_r: the spring's rotation per unit moment (rad per N mm/mm)."""
        return 1.0 / self.rotational


RIGID = Rig()


@attrs.frozen
class Controls:
    """Which loading-block directions are driven by displacement.

    Attributes
    ----------
    normal : str
        ``"force"`` (P imposed) or ``"displacement"`` (the approach imposed).
    tangential : str
        ``"force"`` (Q imposed) or ``"displacement"`` (delta imposed).
    rotation : str
        ``"rotation"`` (the actuator's rotation imposed, 0 by default: the held block of a
        pad that does not rotate) or ``"moment"`` (M imposed).
    """

    normal: str = attrs.field(default="force", validator=attrs.validators.in_(CONTROLS))
    tangential: str = attrs.field(default="force", validator=attrs.validators.in_(CONTROLS))
    rotation: str = attrs.field(
        default="rotation", validator=attrs.validators.in_(ROTATION_CONTROLS), kw_only=True
    )

    @property
    def by_force(self) -> bool:
        """True when both directions are force controlled and the rotation is held (the
        problem's rows are those it was built with)."""
        return self.normal == "force" and self.tangential == "force" and self.rotation == "rotation"


def frame(problem: CondensedContact, side: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Mean normal n and tangent t of the pair: the loads and the block motion act along them;
    in the axes of the body on ``side`` (its block's), or of the pair frame (None). They
    differ only for a turned pad (:attr:`~fretbem.contact.pairing.Pairing.turn`)."""
    return problem.pairing.load_frame(side)


def _block_rows(problem: CondensedContact) -> slice:
    blocks = problem.blocks
    start = 2 * blocks.index("upper")
    return slice(start, start + 2)


def _motion_rows(problem: CondensedContact) -> np.ndarray:
    """:func:`motion_rows`, read-only, kept per problem (every increment's record reads it)."""
    rows = _MOTION_ROWS.get(problem)
    if rows is None:
        rows = _MOTION_ROWS[problem] = motion_rows(problem)
        rows.setflags(write=False)
    return rows


#: :func:`motion_rows` of each condensed problem (weakly: a dropped problem frees it)
_MOTION_ROWS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def motion_rows(problem: CondensedContact) -> np.ndarray:
    """(2, n_x): approach and delta of the pad's block against the datum, per unit x."""
    n, t = frame(problem, "upper")
    layout = problem.layout
    rows = np.zeros((2, layout.size))
    rows[0, layout.block("upper")] = -n
    rows[1, layout.block("upper")] = t
    if "lower" in problem.blocks:
        n, t = frame(problem, "lower")
        rows[0, layout.block("lower")] = n
        rows[1, layout.block("lower")] = -t
    return rows


def stiffness(problem: CondensedContact) -> float:
    """A tangential contact stiffness (force per thickness per mm): the scale of the rows."""
    layout = problem.layout
    weights = np.abs(problem.resultant_map[_block_rows(problem), layout.tractions]).sum(axis=1)
    compliance = np.mean(np.abs(np.diag(problem.tangential_map[:, layout.shear])))
    return float(max(weights.max(initial=0.0), 1e-300) / max(compliance, 1e-300))


def measure(
    problem: CondensedContact, x: np.ndarray, beta: np.ndarray = (), rig: Rig = RIGID
) -> dict:
    """P, Q, the approach and delta at pair unknowns x (force-control problem): the
    actuator's (the block's plus the rig springs' travel, P / k_n and Q / k_t); M, the
    block's moment about the pivot, ``rotation`` the actuator's (theta + M / k_r) and
    ``tilt`` the block's own theta (M is NaN where the pad's model gives no moment)."""
    n, t = frame(problem, "upper")
    beta = np.asarray(beta, float)
    base = problem.base_at("resultant", beta)
    force = (base + np.dot(problem.resultant_map, x))[_block_rows(problem)]
    approach, delta = np.dot(_motion_rows(problem), x)  # np.dot: `@`'s numbers, less overhead
    normal, tangential = float(-np.dot(force, n)), float(np.dot(force, t))
    c_n, c_t = rig.compliances
    moment, tilt = _moment(problem, x, beta, rig, base), 0.0
    if pad_rotation.PAD in problem.layout.rotations:
        tilt = float(x[problem.layout.rotation(pad_rotation.PAD)])
    turns = math.isfinite(rig.rotational)
    rotation = tilt + (moment * rig.rotational_compliance if turns else 0.0)
    return {
        "normal": normal,
        "tangential": tangential,
        "approach": float(approach) + c_n * normal,
        "delta": float(delta) + c_t * tangential,
        "moment": moment,
        "rotation": float(rotation),
        "tilt": tilt,
    }


def _moment(problem: CondensedContact, x, beta, rig: Rig, base=None) -> float:
    """The pad block's moment about the pivot (NaN without a rotation record); ``base``:
    the resultant rows' base at beta, where the caller has it."""
    record = problem.rotation
    if record is None:
        return float("nan")
    if not record.in_unknowns:
        target = _pivot(problem, rig.pivot_height)
        return pad_rotation.moment_about(problem, x, beta, target, base=base)
    return record.moment(x, beta)


def _pivot(problem: CondensedContact, height: float | None) -> np.ndarray:
    """``pad_rotation.pivot(problem, height)``, kept per problem and height (every
    increment's record reads it)."""
    kept = _PIVOTS.get(problem)
    if kept is None or kept[0] != height:
        point = pad_rotation.pivot(problem, height)
        point.setflags(write=False)
        kept = _PIVOTS[problem] = (height, point)
    return kept[1]


#: :func:`_pivot` of each condensed problem, with its height (weakly, as _MOTION_ROWS)
_PIVOTS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def controlled(problem: CondensedContact, controls: Controls, rig: Rig = RIGID) -> CondensedContact:
    """``problem`` with the pad block's resultant rows replaced as ``controls`` says.

    The two rows of the upper block become (P row or k x approach row, Q row or k x delta
    row), in the pair frame, the approach and delta the actuator's (through ``rig``);
    :func:`targets` gives the values they must reach.
    """
    if controls.by_force:
        return problem
    if controls.rotation == "moment":
        problem = _moment_controlled(problem)
    n, t = frame(problem, "upper")
    rows = _block_rows(problem)
    k = stiffness(problem)
    motion = motion_rows(problem) * k
    resultant_map = problem.resultant_map.copy()
    resultant_base = problem.resultant_base.copy()
    resultant_load = problem.resultant_load.copy()
    block_map = problem.resultant_map[rows]
    block_base = problem.resultant_base[rows]
    block_load = problem.resultant_load[rows]
    compliances = rig.compliances
    for i, (control, direction, sign) in enumerate(
        ((controls.normal, n, -1.0), (controls.tangential, t, 1.0))
    ):
        if controls.normal == "force" and controls.tangential == "force":
            break
        row = rows.start + i
        force_map = sign * direction @ block_map
        force_base = sign * direction @ block_base
        force_load = sign * direction @ block_load
        if control == "force":
            resultant_map[row], resultant_base[row] = force_map, force_base
            resultant_load[row] = force_load
        else:  # k (block motion + spring travel)
            spring = k * compliances[i]
            resultant_map[row] = motion[i] + spring * force_map
            resultant_base[row] = spring * force_base
            resultant_load[row] = spring * force_load
    return attrs.evolve(
        problem,
        resultant_map=resultant_map,
        resultant_base=resultant_base,
        resultant_load=resultant_load,
    )


def rotating(problem: CondensedContact, rig: Rig, target=None) -> CondensedContact:
    """``problem`` with the pad block's rotation about the rig's pivot (``target``, or the
    problem's own :func:`~fretbem.contact.rotation.pivot`) among the unknowns; its last
    resultant row holds the rotation: k L (theta + M / k_r) = k L theta_a."""
    if target is None:
        target = pad_rotation.pivot(problem, rig.pivot_height)
    out = pad_rotation.rotating(problem, target)
    row = pad_rotation.moment_row(out)
    scale = out.rotation.scale
    spring = rotation_stiffness(out) * rig.rotational_compliance * scale  # k L / k_r, per M / L
    # beyond ~1e150 the row's products overflow in the solver's iterations
    if not spring * np.max(np.abs(out.resultant_map[row]), initial=1.0) <= 1e150:
        raise pad_rotation.RotationError(
            f"[rig] stiffness_rotation = {rig.rotational:g} N mm/mm per rad is so soft that the "
            "block's rotation row leaves the floating-point range; a block free to turn is "
            "[load] moment = 0 (leave the spring out), a held one a stiffer spring"
        )
    resultant_map = out.resultant_map.copy()
    resultant_base = out.resultant_base.copy()
    resultant_load = out.resultant_load.copy()
    resultant_map[row] *= spring
    resultant_map[row, out.layout.rotation(pad_rotation.PAD)] += rotation_stiffness(out)
    resultant_base[row] *= spring
    resultant_load[row] *= spring
    return attrs.evolve(
        out,
        resultant_map=resultant_map,
        resultant_base=resultant_base,
        resultant_load=resultant_load,
    )


def rotation_stiffness(problem: CondensedContact) -> float:
    """k L: the scale (force per thickness per rad) of the held rotation's row."""
    return stiffness(problem) * problem.rotation.scale


def _moment_controlled(problem: CondensedContact) -> CondensedContact:
    """A rotating problem with its rotation row back to the moment M / L."""
    record = problem.rotation
    if record is None or not record.in_unknowns:
        raise pad_rotation.RotationError(
            "a step imposes the pad block's moment, but the problem's block does not rotate; "
            "build the simulation with the step (Simulation adds the rotation when a step "
            "gives a moment)"
        )
    row = pad_rotation.moment_row(problem)
    resultant_map = problem.resultant_map.copy()
    resultant_base = problem.resultant_base.copy()
    resultant_load = problem.resultant_load.copy()
    resultant_map[row] = record.moment_map / record.scale
    resultant_base[row] = record.moment_base / record.scale
    resultant_load[row] = record.moment_load / record.scale
    return attrs.evolve(
        problem,
        resultant_map=resultant_map,
        resultant_base=resultant_base,
        resultant_load=resultant_load,
    )


def targets(
    problem: CondensedContact,
    controls: Controls,
    normal: float,
    tangential: float,
    forces,
    rotation: float = 0.0,
) -> np.ndarray:
    """The values the resultant rows of ``controlled(problem, controls)`` must reach.

    ``normal`` is P or the approach, ``tangential`` Q or delta, ``rotation`` the actuator's
    rotation theta_a or the moment M, as ``controls`` says; ``forces`` are the force-control
    targets of every block (returned as they are when both directions are force
    controlled), with the rotation's entry after them in a rotating problem.
    """
    forces = np.array(forces, dtype=float)
    record = problem.rotation
    if record is not None and record.in_unknowns:
        row = pad_rotation.moment_row(problem)
        if controls.rotation == "moment":
            forces[row] = rotation / record.scale
        else:
            forces[row] = rotation_stiffness(problem) * rotation
    if controls.normal == "force" and controls.tangential == "force":
        return forces
    k = stiffness(problem)
    rows = _block_rows(problem)
    forces[rows.start] = normal if controls.normal == "force" else k * normal
    forces[rows.start + 1] = tangential if controls.tangential == "force" else k * tangential
    return forces
