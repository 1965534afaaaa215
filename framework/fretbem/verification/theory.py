"""The closed-form numbers an engineer reads beside a run: Hertz a and p0, and per step the
theoretical stick zone [e - c, e + c] (offset e by a bulk stress, Nowell-Hills).

Every function takes the run's ``reference`` (a closed form with ``hertz`` and
``stick_zone(history)``, or None) so the summary, the figures, the labelled views and the
report read the same numbers.
"""

from __future__ import annotations

from collections.abc import Sequence

__all__ = ["hertz_numbers", "theory_stick_zones"]


def hertz_numbers(reference) -> dict | None:
    """``{"P", "a", "p0"}`` of the reference's Hertz contact (N/mm, mm, MPa); None without."""
    if reference is None:
        return None
    hertz = reference.hertz
    return {
        "P": float(hertz.load),
        "a": float(hertz.half_width),
        "p0": float(hertz.peak_pressure),
    }


def theory_stick_zones(reference, tangential: Sequence[float]) -> list:
    """Per step the closed form's stick zone ``(e - c, e + c)`` after the Q values of the
    steps so far (``tangential``); None for every step without a reference."""
    if reference is None:
        return [None] * len(tangential)
    history, zones = [], []
    for q in tangential:
        history.append(float(q))
        low, high = reference.stick_zone(list(history))
        zones.append((float(low), float(high)))
    return zones
