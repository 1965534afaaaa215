"""Cycle jumping: how many cycles one simulated cycle's wear may be extrapolated over.

A jump adds Delta N cycles of wear to the profile. The pressure answers the wear depth
through the elastic contact (on the pairs in contact dp = -K dh, K the contact stiffness at
constant load), so the wear rate r(h) is a stiff function of the profile:

``explicit`` (default)
    Delta N times the last simulated cycle's wear: forward Euler for dh/dN = r(h). It is
    stable only for Delta N lambda < 2 (and free of oscillation for < 1), lambda the
    largest eigenvalue of D C^-1 (D the wear rate's sensitivity to the pressure per cycle,
    C the pairs' normal compliance). lambda grows as the pairs get closer (C^-1 scales with
    E / spacing), which is why a limit on the profile change alone diverges on fine grids:
    Delta N is the smallest of the profile limit ``max_change / max r``, the stability
    limit ``safety / lambda``, ``max_jump`` and the cycles left to the next requested N.
``implicit``
    Linearly implicit Euler: the wear rate taken at the end of the jump, linearised,
    (I + Delta N D K) dh = Delta N r. Stable for any Delta N (the stiff pressure modes are
    damped, as they are physically), so Delta N is limited by the profile change, ``max_jump``
    and the outputs only; a jump whose linearisation would make any depth increment negative
    is halved.

The energy and the Archard work of a jump are extrapolated with the same linearisation, so
a body's volume is its coefficient times the summed energy (or work) in both schemes.
"""

from __future__ import annotations

import math
import numbers

import attrs
import numpy as np

from fretbem.contact.condensation import CondensedContact
from fretbem.validators import as_float, as_scalar, shown, whole_number

from .cycle import CycleWear
from .law import WearInputError
from .profile import BODIES

__all__ = ["SCHEMES", "Jump", "JumpControl", "JumpWear", "extrapolate", "stability_rate"]

#: the jump schemes
SCHEMES = ("explicit", "implicit")


def _positive(value, field) -> float | None:
    """A finite number > 0 (numpy's too, as a float; no True, no "0.5"); None for max_change."""
    if value is None and field.name == "max_change":
        return None
    value = as_scalar(value)
    number = isinstance(value, numbers.Real) and not isinstance(value, (bool, np.bool_))
    if not (number and math.isfinite(as_float(value)) and value > 0):
        fix = "give a number > 0" + (", or None" if field.name == "max_change" else "")
        raise WearInputError(
            f"[wear] {field.name} must be a finite number > 0, got {shown(value)}; {fix}"
        )
    return float(value)


def _whole(value) -> int | None:
    """None, or a whole number >= 1 (numpy's too; no True, no "3", no 2.5)."""
    if value is None:
        return None
    return whole_number(
        "[wear] max_jump",
        value,
        low=1,
        fix="give the most cycles of one jump, or None for no bound",
        error=WearInputError,
    )


def _scheme(instance, attribute, value) -> None:
    if value not in SCHEMES:
        raise WearInputError(f"[wear] scheme must be one of {list(SCHEMES)}, got {value!r}")


@attrs.frozen
class JumpControl:
    """How far one simulated cycle is extrapolated.

    Attributes
    ----------
    max_change : float or None
        Largest change of either face's wear depth at any pair in one jump, mm; None (the
        default): ``relative_change`` times the relief of the unworn contact.
    relative_change : float
        The profile limit as a fraction of the relief of the unworn contact: the spread of
        the initial gap over the pairs in contact (a^2 / 2R for a cylinder on a flat), the
        profile the elastic deformation makes up for. Default 0.02.
    safety : float
        Delta N lambda stays at or below this under the explicit scheme (1 is the edge of
        oscillation, 2 of divergence; the default 0.5 keeps the explicit step smooth).
    max_jump : int or None
        An upper bound on Delta N (None: none).
    stability : bool
        Apply the stability limit (default). False leaves only the profile limit, to show
        the instability it lets through; never for results.
    scheme : str
        "explicit" (default) or "implicit" (module docstring).
    """

    max_change: float | None = attrs.field(
        default=None, converter=attrs.Converter(_positive, takes_field=True)
    )
    relative_change: float = attrs.field(
        default=0.02, converter=attrs.Converter(_positive, takes_field=True)
    )
    safety: float = attrs.field(default=0.5, converter=attrs.Converter(_positive, takes_field=True))
    max_jump: int | None = attrs.field(default=None, converter=_whole)
    stability: bool = attrs.field(default=True, validator=attrs.validators.instance_of(bool))
    scheme: str = attrs.field(default="explicit", validator=_scheme)

    def __attrs_post_init__(self) -> None:
        if self.safety >= 2.0:
            raise WearInputError(
                f"[wear] safety = {self.safety:g} lets the jump diverge (an explicit jump is "
                "stable only for Delta N lambda < 2); use a safety below 1, e.g. 0.5"
            )

    def change(self, relief: float) -> float:
        """The profile limit (mm) for a contact of ``relief`` (mm)."""
        return self.max_change if self.max_change is not None else self.relative_change * relief

    def jump(
        self, problem: CondensedContact, cycle: CycleWear, left: int, first=False, relief=0.0
    ) -> Jump:
        """Delta N after ``cycle`` (at most ``left``, >= 1) and which limit chose it; 1 after
        the ``first`` cycle, which starts from the unworn contact's first loading and so is
        not yet the repeated cycle. ``relief``: the unworn contact's (see relative_change)."""
        rate = max(float(np.max(d, initial=0.0)) for d in cycle.depth.values())
        lam = stability_rate(problem, cycle)
        limits = {"output": float(left)}
        change = self.change(relief)
        if rate > 0 and change > 0:
            limits["profile"] = change / rate
        if lam > 0 and self.stability and self.scheme == "explicit":
            limits["stability"] = self.safety / lam
        if self.max_jump is not None:
            limits["max_jump"] = float(self.max_jump)
        if first:
            limits["first cycle"] = 1.0
        reason = min(limits, key=limits.get)
        cycles = max(1, min(left, math.floor(limits[reason])))
        return Jump(cycles, reason, lam, rate)


@attrs.frozen
class Jump:
    """One jump: its Delta N, the limit that chose it, lambda (1/cycle) and the largest
    depth rate (mm/cycle) of the cycle it extrapolates."""

    cycles: int
    limit: str
    stability: float
    rate: float


@attrs.frozen(eq=False)
class JumpWear:
    """What a jump adds: each body's depth (mm per pair), the energy and the Archard work
    (N mm per mm of thickness)."""

    depth: dict
    energy: float
    work: float


def _touching(cycle: CycleWear) -> np.ndarray:
    return np.flatnonzero(np.any(cycle.pressure > 0, axis=0) & (cycle.sensitivity > 0))


def _compliance(problem: CondensedContact, touching: np.ndarray) -> np.ndarray:
    columns = np.arange(problem.layout.pressure.start, problem.layout.pressure.stop)[touching]
    return problem.normal_map[np.ix_(touching, columns)]


def stability_rate(problem: CondensedContact, cycle: CycleWear) -> float:
    """lambda (1/cycle): the largest eigenvalue of D C^-1 on the pairs in contact at the end
    of the cycle's steps, D the per-cycle pressure sensitivity, C the normal compliance.

    The loading blocks' rigid approach is left out (it only removes the uniform mode), so
    lambda is an upper estimate and the jump it allows is on the safe side.
    """
    touching = _touching(cycle)
    if touching.size == 0:
        return 0.0
    stiffness = np.linalg.inv(_compliance(problem, touching))
    scale = np.sqrt(cycle.sensitivity[touching])
    eigen = np.linalg.eigvals(scale[:, None] * stiffness * scale[None, :])
    return float(np.max(eigen.real))


def load_stiffness(problem: CondensedContact, touching: np.ndarray, weights: np.ndarray):
    """K with dp = -K dh on the ``touching`` pairs at constant load: the pairs' stiffness
    C^-1 with the rigid approach that keeps sum(w p) fixed taken out (w^T K = 0)."""
    stiffness = np.linalg.inv(_compliance(problem, touching))
    w = weights[touching]
    column = stiffness.sum(axis=1)  # K 1
    return stiffness - np.outer(column, w @ stiffness) / (w @ column)


def extrapolate(
    problem: CondensedContact, cycle: CycleWear, cycles: int, scheme: str, weights: np.ndarray
) -> tuple[JumpWear, int]:
    """The wear of ``cycles`` cycles like ``cycle`` under ``scheme``; with the implicit
    scheme ``cycles`` is halved until no depth increment is negative. Returns the jump's
    wear and the cycles it covers."""
    explicit = JumpWear(
        {b: cycles * cycle.depth[b] for b in BODIES},
        cycles * float(weights @ cycle.energy),
        cycles * float(weights @ cycle.work),
    )
    single = JumpWear(dict(cycle.depth), float(weights @ cycle.energy), float(weights @ cycle.work))
    touching = _touching(cycle)
    if scheme == "explicit" or touching.size == 0:
        return explicit, cycles
    stiffness = load_stiffness(problem, touching, weights)
    sensitivity = cycle.sensitivity[touching]
    rate = sum(cycle.depth[b] for b in BODIES)[touching]
    while True:
        matrix = np.eye(touching.size) + cycles * sensitivity[:, None] * stiffness
        total = np.linalg.solve(matrix, cycles * rate)
        dp = np.zeros(len(weights))
        dp[touching] = -stiffness @ total  # the pressure change at the end of the jump
        depth = {b: cycles * (cycle.depth[b] + cycle.sensitivities[b] * dp) for b in BODIES}
        floor = -1e-12 * max(float(np.max(np.abs(d), initial=0.0)) for d in depth.values())
        if min(float(d.min(initial=0.0)) for d in depth.values()) >= floor:
            break
        if cycles == 1:  # one cycle: the simulated cycle itself
            return single, 1
        cycles = max(1, cycles // 2)
    energy = cycles * float(weights @ (cycle.energy + cycle.energy_sensitivity * dp))
    work = cycles * float(weights @ (cycle.work + cycle.work_sensitivity * dp))
    depth = {b: np.maximum(d, 0.0) for b, d in depth.items()}
    return JumpWear(depth, energy, work), cycles
