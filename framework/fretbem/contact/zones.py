"""Per-step zone report: loads, stick zone, slip zones and whether a closed form applies.

Zones are read from the pair states: a zone runs from its first to its last pair (the
transition lies within one pair spacing of either end). A slip zone is marked ``+`` or
``-`` by the sign of its shear, so reverse slip at one edge shows as the opposite sign.
:func:`step_zones` is the one source of these numbers: the printed table, summary.json,
the labelled views and the run report all read it.
"""

from __future__ import annotations

import attrs
import numpy as np

from .law import PairState

__all__ = ["StepZones", "runs", "step_zones", "zone_table"]


def runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) index of every run of True in ``mask``."""
    mask = np.asarray(mask, bool)
    edges = np.flatnonzero(np.diff(np.concatenate([[0], mask.astype(int), [0]])))
    return [(int(a), int(b) - 1) for a, b in zip(edges[::2], edges[1::2], strict=True)]


@attrs.frozen
class StepZones:
    """The zones of one step, x in mm of the lower body's contact nodes.

    Attributes
    ----------
    contact : (float, float) or None
        First to last pair in contact (stick or slip); None when nothing touches.
    stick : tuple of (float, float)
        Every stick zone, from its first to its last pair.
    slip : tuple of (float, float, str)
        Every slip zone and the sign of its mean shear ("+" or "-").
    """

    contact: tuple[float, float] | None
    stick: tuple[tuple[float, float], ...]
    slip: tuple[tuple[float, float, str], ...]

    def as_dict(self) -> dict:
        """summary.json's form: lists of [from, to] and {from, to, sign}."""
        return {
            "contact": None if self.contact is None else list(self.contact),
            "stick_zones": [list(z) for z in self.stick],
            "slip_zones": [{"from": a, "to": b, "sign": s} for a, b, s in self.slip],
        }


def step_zones(step) -> StepZones:
    """Contact extent, stick zones and signed slip zones of one step (from its pair states)."""
    x, states = np.asarray(step.x, float), np.asarray(step.states)
    touching = np.flatnonzero(states != PairState.SEPARATED)
    contact = (float(x[touching[0]]), float(x[touching[-1]])) if touching.size else None
    stick = tuple((float(x[a]), float(x[b])) for a, b in runs(states == PairState.STICK))
    slips = []
    for a, b in runs(states == PairState.SLIP):
        sign = "+" if np.mean(np.asarray(step.shear)[a : b + 1]) >= 0 else "-"
        slips.append((float(x[a]), float(x[b]), sign))
    return StepZones(contact, stick, tuple(slips))


def _zones(step) -> tuple[str, str]:
    zones = step_zones(step)
    stick_text = " ".join(f"[{a:+.4f}, {b:+.4f}]" for a, b in zones.stick) or "none"
    slips = [f"{s}[{a:+.4f}, {b:+.4f}]" for a, b, s in zones.slip]
    return stick_text, " ".join(slips) or "none"


def zone_table(result, reason: str | None = None) -> str:
    """P, Q, sigma_B, the stick zone (from, to), the closed form's stick zone [e - c, e + c]
    and the slip zones of every step, in mm, with Hertz a and p0 and the contact extent.

    The last line says which closed form the errors above compare with, or why none does.
    """
    width = max(4, *(len(s.name) for s in result.steps))
    reference = result.simulation.reference
    theory = result.theory_stick_zones() if reference is not None else [None] * len(result.steps)
    lines = [
        f"{'step':<{width}}        P         Q   sigma_B  stick zone (mm)        "
        f"{'theory [e-c, e+c]      ' if reference is not None else ''}slip zones"
    ]
    for step, zone in zip(result.steps, theory, strict=True):
        stick, slip = _zones(step)
        bulk = step.loads.get("bulk", 0.0)
        exact = f"[{zone[0]:+.4f}, {zone[1]:+.4f}]  " if zone is not None else ""
        lines.append(
            f"{step.name:<{width}} {step.normal:9.3f} {step.tangential:9.3f} {bulk:9.3f}  "
            f"{stick:<22} {exact}{slip}"
        )
    extents = [z.contact for z in (step_zones(s) for s in result.steps) if z.contact]
    if extents:
        low, high = min(e[0] for e in extents), max(e[1] for e in extents)
        lines.append(f"contact extent over the steps: [{low:+.4f}, {high:+.4f}] mm")
    if reference is not None:
        name = type(getattr(reference, "closed_form", reference)).__name__
        pair = result.simulation.pair
        hertz = reference.hertz
        lines.append(
            f"Hertz: a = {hertz.half_width:.4f} mm, p0 = {hertz.peak_pressure:.2f} MPa at "
            f"P = {hertz.load:g} N/mm"
        )
        finite = any(body.finite for body in (pair.upper, pair.lower))
        lines.append(
            f"errors against the closed form: {name} (half-plane theory)"
            + (
                "; for finite bodies they are the difference from half-plane theory (the "
                "bodies' size and the pad's tilt under Q move the contact too), not the "
                "discretisation error: that is the est columns"
                if finite
                else ""
            )
        )
    else:
        why = f" ({reason})" if reason else ""
        lines.append(f"no closed form applies to this scene{why}: the errors columns are n/a")
    return "\n".join(lines)
