"""Stress positions named by the contact edges: ``x = "trailing-edge"``, ``"leading-edge"``,
with an offset in units of the contact half-width a (``"trailing-edge + 0.05a"``).

The trailing edge is x = -a, the leading edge x = +a (for Q > 0 along +x, the pad's
trailing edge is at -a, where the surface tension peaks). a is the Hertz half-width of the
run's closed form when one applies, else half the largest computed contact extent; so a
request is written before solving and resolved against the result.
"""

from __future__ import annotations

import re

import attrs
import numpy as np

from .errors import StressRequestError

__all__ = ["EdgePosition", "contact_half_width", "parse_position"]

EDGES = {"trailing-edge": -1.0, "leading-edge": 1.0}
_PATTERN = re.compile(
    r"^\s*(trailing-edge|leading-edge)\s*(?:([+-])\s*((?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)"
    r"\s*\*?\s*a)?\s*$"
)


@attrs.frozen
class EdgePosition:
    """x at a contact edge plus ``offset`` half-widths (+ toward +x)."""

    edge: str
    offset: float = 0.0

    def resolve(self, a: float, centre: float = 0.0) -> float:
        """x in mm for the contact half-width ``a`` about ``centre``."""
        return float(centre + (EDGES[self.edge] + self.offset) * a)

    def __str__(self) -> str:
        if not self.offset:
            return self.edge
        sign = "+" if self.offset > 0 else "-"
        return f"{self.edge} {sign} {abs(self.offset):g}a"


def parse_position(value, where: str = "") -> float | EdgePosition:
    """A number (mm) or an edge name with an optional offset in units of a."""
    where = f"{where} x" if where else "x"
    if isinstance(value, EdgePosition):
        return value
    if isinstance(value, str):
        match = _PATTERN.match(value)
        if match is None:
            raise StressRequestError(
                f"{where} = {value!r} is not a position: give a number in mm, "
                "'trailing-edge' (x = -a), 'leading-edge' (x = +a), or one of them with an "
                "offset in units of the half-width a, e.g. 'trailing-edge + 0.05a'"
            )
        edge, sign, amount = match.groups()
        offset = 0.0 if amount is None else float(amount) * (-1.0 if sign == "-" else 1.0)
        return EdgePosition(edge, offset)
    if isinstance(value, bool):
        raise StressRequestError(f"{where} must be a number or an edge name, got {value!r}")
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise StressRequestError(
            f"{where} must be a number (mm) or an edge name such as 'trailing-edge', got {value!r}"
        ) from None
    if not np.isfinite(number):
        raise StressRequestError(f"{where} must be finite, got {value!r}")
    return number


def contact_half_width(result) -> tuple[float, float, str]:
    """(a, centre, source) for edge positions: the Hertz half-width about x = 0 when a closed
    form applies ("hertz"), else the widest computed contact ("computed contact")."""
    reference = result.simulation.reference
    if reference is not None:
        return float(reference.hertz.half_width), 0.0, "hertz"
    extents = [z.contact for z in (s.zones() for s in result.steps) if z.contact is not None]
    if not extents:
        raise StressRequestError(
            "[stress] edge positions need a contact half-width, and no step is in contact"
        )
    low, high = max(extents, key=lambda z: z[1] - z[0])
    if high <= low:
        raise StressRequestError("[stress] edge positions need a contact wider than one pair")
    return 0.5 * (high - low), 0.5 * (high + low), "computed contact"
