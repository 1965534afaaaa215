"""Which load steps form the cycle that the fatigue parameters are evaluated over.

By default the last full reversal of a driving load history (e.g. the tangential load Q):
from the third-last turning point to the last one (max -> min -> max or min -> max -> min),
so that loading and unloading branches, which differ under partial slip, are both in the
cycle. The user may instead give the step indices explicitly.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from fretbem.validators import shown, whole_number

from .errors import FatigueInputError

__all__ = ["last_full_reversal", "select_cycle", "turning_points"]


def _history(driver) -> np.ndarray:
    """A load history as floats, finite (strings and NaN refused, naming the driver)."""
    try:
        values = np.asarray(driver, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise FatigueInputError(
            f"the cycle driver must be a 1D load history of numbers, got {shown(driver)}"
        ) from None
    if not np.isfinite(values).all():
        raise FatigueInputError("the cycle driver has NaN or infinite loads; give finite loads")
    return values


def turning_points(driver: np.ndarray) -> np.ndarray:
    """Indices of the local extrema of a load history, end points included; plateaus merged."""
    values = _history(driver)
    if values.ndim != 1 or values.size == 0:
        raise FatigueInputError(
            f"the cycle driver must be a non-empty 1D load history, got shape {values.shape}"
        )
    idx = [0]
    direction = 0.0
    last = 0
    for i in range(1, values.size):
        step = np.sign(values[i] - values[last])
        if step == 0:
            continue
        if direction != 0 and step != direction:
            idx.append(last)
        direction = step
        last = i
    if direction != 0:
        idx.append(last)
    return np.unique(np.array(idx, dtype=int))


def last_full_reversal(driver: np.ndarray) -> np.ndarray:
    """Step indices of the last closed load loop (three turning points), or the last half cycle.

    Raises :class:`FatigueInputError` when the driver never changes direction.
    """
    tp = turning_points(driver)
    if tp.size >= 3:
        return np.arange(tp[-3], tp[-1] + 1)
    if tp.size == 2:
        return np.arange(tp[-2], tp[-1] + 1)
    raise FatigueInputError(
        "the cycle driver never changes: give the cycle steps explicitly ([fatigue] cycle_steps)"
    )


def select_cycle(
    n_steps: int, *, driver: np.ndarray | None = None, steps: Sequence[int] | None = None
) -> np.ndarray:
    """Indices of the steps forming the evaluated cycle.

    ``steps`` (explicit, checked against ``n_steps``) wins; otherwise the last full reversal of
    ``driver``; with neither, every step.
    """
    n_steps = whole_number("select_cycle n_steps", n_steps, low=1, fix="give the history's steps",
                           error=FatigueInputError)  # fmt: skip
    if steps is not None:
        if isinstance(steps, (str, bytes)):
            raise FatigueInputError(f"cycle steps must list step indices, got {steps!r}")
        chosen = np.asarray(
            [whole_number(f"cycle steps[{k}]", s, low=0, fix="give step indices from 0",
                          error=FatigueInputError) for k, s in enumerate(steps)],
            dtype=int,
        )  # fmt: skip
        if chosen.ndim != 1 or chosen.size < 2:
            raise FatigueInputError(f"cycle steps must list at least two steps, got {steps!r}")
        if np.any(chosen >= n_steps):  # (negatives refused above, as whole numbers >= 0)
            raise FatigueInputError(
                f"cycle steps {chosen.tolist()} outside the history's 0..{n_steps - 1}"
            )
        return chosen
    if driver is not None:
        driver = _history(driver)
        if driver.shape != (n_steps,):
            raise FatigueInputError(
                f"the cycle driver has {driver.shape} values for a history of {n_steps} steps"
            )
        return last_full_reversal(driver)
    return np.arange(n_steps)
