"""Per-step zone report: loads, stick zone, slip zones and whether a closed form applies.

Zones are read from the pair states: a zone runs from its first to its last pair (the
transition lies within one pair spacing of either end). A slip zone is marked ``+`` or
``-`` by the sign of its shear, so reverse slip at one edge shows as the opposite sign.
"""

from __future__ import annotations

import numpy as np

from .law import PairState

__all__ = ["runs", "zone_table"]


def runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) index of every run of True in ``mask``."""
    mask = np.asarray(mask, bool)
    edges = np.flatnonzero(np.diff(np.concatenate([[0], mask.astype(int), [0]])))
    return [(int(a), int(b) - 1) for a, b in zip(edges[::2], edges[1::2], strict=True)]


def _zones(step) -> tuple[str, str]:
    x, states = step.x, step.states
    stick = runs(states == PairState.STICK)
    stick_text = " ".join(f"[{x[a]:+.4f}, {x[b]:+.4f}]" for a, b in stick) or "none"
    slips = []
    for a, b in runs(states == PairState.SLIP):
        sign = "+" if np.mean(step.shear[a : b + 1]) >= 0 else "-"
        slips.append(f"{sign}[{x[a]:+.4f}, {x[b]:+.4f}]")
    return stick_text, " ".join(slips) or "none"


def zone_table(result, reason: str | None = None) -> str:
    """P, Q, sigma_B, the stick zone (from, to) and the slip zones of every step, in mm.

    The last line says which closed form the errors above compare with, or why none does.
    """
    width = max(4, *(len(s.name) for s in result.steps))
    lines = [f"{'step':<{width}}        P         Q   sigma_B  stick zone (mm)        slip zones"]
    for step in result.steps:
        stick, slip = _zones(step)
        bulk = step.loads.get("bulk", 0.0)
        lines.append(
            f"{step.name:<{width}} {step.normal:9.3f} {step.tangential:9.3f} {bulk:9.3f}  "
            f"{stick:<22} {slip}"
        )
    reference = result.simulation.reference
    if reference is not None:
        name = type(getattr(reference, "closed_form", reference)).__name__
        finite = any(
            getattr(body, "describe", dict)().get("model") == "bem"
            for body in (result.simulation.pair.upper, result.simulation.pair.lower)
        )
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
