"""Cycle jumping: how many cycles one simulated cycle's wear may be extrapolated over.

A jump adds Delta N times the last simulated cycle's wear to the profile: an explicit
(forward Euler) step of dh/dN = r(h). The pressure answers the wear depth through the
elastic contact (dp = -C^-1 dh on the contact pairs, C the pairs' normal compliance), so
the step is stable only when Delta N lambda < 2, lambda the largest eigenvalue of
D C^-1 with D the wear rate's sensitivity to the pressure per cycle (and free of
oscillation when Delta N lambda < 1). lambda grows as the pairs get closer (C^-1 scales
with E / spacing), which is why a limit on the profile change alone diverges on fine grids.
Delta N is the smallest of: the profile limit ``max_change / max r``, the stability limit
``safety / lambda``, ``max_jump`` and the cycles left to the next requested N.
"""

from __future__ import annotations

import math

import attrs
import numpy as np

from fretbem.contact.condensation import CondensedContact

from .cycle import CycleWear
from .law import WearInputError

__all__ = ["Jump", "JumpControl", "stability_rate"]


def _positive(instance, attribute, value) -> None:
    if isinstance(value, bool) or not (math.isfinite(value) and value > 0):
        raise WearInputError(f"[wear] {attribute.name} must be a finite number > 0, got {value!r}")


def _whole(instance, attribute, value) -> None:
    if value is not None and (isinstance(value, bool) or int(value) != value or value < 1):
        raise WearInputError(f"[wear] {attribute.name} must be a whole number >= 1, got {value!r}")


@attrs.frozen
class JumpControl:
    """How far one simulated cycle is extrapolated.

    Attributes
    ----------
    max_change : float
        Largest change of either face's wear depth at any pair in one jump, mm.
    safety : float
        Delta N lambda stays at or below this (1 is the edge of oscillation, 2 of
        divergence; the default 0.5 keeps the explicit step smooth).
    max_jump : int or None
        An upper bound on Delta N (None: none).
    stability : bool
        Apply the stability limit (default). False leaves only the profile limit, to show
        the instability it lets through; never for results.
    """

    max_change: float = attrs.field(default=1e-3, converter=float, validator=_positive)
    safety: float = attrs.field(default=0.5, converter=float, validator=_positive)
    max_jump: int | None = attrs.field(default=None, validator=_whole)
    stability: bool = attrs.field(default=True, validator=attrs.validators.instance_of(bool))

    def __attrs_post_init__(self) -> None:
        if self.safety >= 2.0:
            raise WearInputError(
                f"[wear] safety = {self.safety:g} lets the jump diverge (an explicit jump is "
                "stable only for Delta N lambda < 2); use a safety below 1, e.g. 0.5"
            )

    def jump(self, problem: CondensedContact, cycle: CycleWear, left: int, first=False) -> Jump:
        """Delta N after ``cycle`` (at most ``left``, >= 1) and which limit chose it; 1 after
        the ``first`` cycle, which starts from the unworn contact's first loading and so is
        not yet the repeated cycle."""
        rate = max(float(np.max(d, initial=0.0)) for d in cycle.depth.values())
        lam = stability_rate(problem, cycle)
        limits = {"output": float(left)}
        if rate > 0:
            limits["profile"] = self.max_change / rate
        if lam > 0 and self.stability:
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


def stability_rate(problem: CondensedContact, cycle: CycleWear) -> float:
    """lambda (1/cycle): the largest eigenvalue of D C^-1 on the pairs in contact at the end
    of the cycle's steps, D the per-cycle pressure sensitivity, C the normal compliance.

    The loading blocks' rigid approach is left out (it only removes the uniform mode), so
    lambda is an upper estimate and the jump it allows is on the safe side.
    """
    touching = np.flatnonzero(np.any(cycle.pressure > 0, axis=0) & (cycle.sensitivity > 0))
    if touching.size == 0:
        return 0.0
    columns = np.arange(problem.layout.pressure.start, problem.layout.pressure.stop)[touching]
    compliance = problem.normal_map[np.ix_(touching, columns)]
    stiffness = np.linalg.inv(compliance)
    scale = np.sqrt(cycle.sensitivity[touching])
    eigen = np.linalg.eigvals(scale[:, None] * stiffness * scale[None, :])
    return float(np.max(eigen.real))
