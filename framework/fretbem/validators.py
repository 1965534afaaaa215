"""Small attrs validators shared by the frozen records: finiteness, sign, shape."""

from __future__ import annotations

import math
from typing import Any

import numpy as np


def finite(instance: Any, attribute: Any, value: Any) -> None:
    """Reject NaN and infinite numbers, naming the field."""
    if not np.all(np.isfinite(np.asarray(value, dtype=float))):
        raise ValueError(
            f"{type(instance).__name__}.{attribute.name} must be finite, got {value!r}"
        )


def positive(instance: Any, attribute: Any, value: Any) -> None:
    """Require every entry to be finite and > 0."""
    finite(instance, attribute, value)
    if not np.all(np.asarray(value, dtype=float) > 0):
        raise ValueError(f"{type(instance).__name__}.{attribute.name} must be > 0, got {value!r}")


def non_negative(instance: Any, attribute: Any, value: Any) -> None:
    """Require every entry to be finite and >= 0."""
    finite(instance, attribute, value)
    if not np.all(np.asarray(value, dtype=float) >= 0):
        raise ValueError(f"{type(instance).__name__}.{attribute.name} must be >= 0, got {value!r}")


def shape(*dims: int | None):
    """Validator requiring an array of the given shape (None matches any length)."""

    def check(instance: Any, attribute: Any, value: Any) -> None:
        arr = np.asarray(value)
        ok = arr.ndim == len(dims) and all(
            d is None or d == n for d, n in zip(dims, arr.shape, strict=False)
        )
        if not ok:
            want = "(" + ", ".join("n" if d is None else str(d) for d in dims) + ")"
            raise ValueError(
                f"{type(instance).__name__}.{attribute.name} must have shape {want}, "
                f"got {arr.shape}"
            )

    return check


def float_array(value: Any) -> np.ndarray:
    """Converter to a read-only float array, so frozen records stay frozen."""
    arr = np.array(value, dtype=float)
    arr.setflags(write=False)
    return arr


def count(instance: Any, attribute: Any, value: Any) -> None:
    """Require a whole number >= 1 (booleans rejected)."""
    if isinstance(value, bool) or int(value) != value or value < 1:
        raise ValueError(f"{attribute.name} must be a whole number >= 1, got {value!r}")


def poisson(instance: Any, attribute: Any, value: Any) -> None:
    """Require a Poisson's ratio in (-1, 0.5), the range of a stable isotropic material."""
    if not (-1.0 < value < 0.5):
        raise ValueError(
            f"Poisson's ratio {attribute.name} must lie in (-1, 0.5) for a stable isotropic "
            f"material, got {value!r}"
        )


def check_positive(name: str, value: float) -> float:
    """``value`` as a float; ValueError naming ``name`` unless finite and > 0 (plain calls)."""
    value = float(value)
    if not (math.isfinite(value) and value > 0.0):
        raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    return value


def check_poisson(name: str, value: float) -> float:
    """``value`` as a float; ValueError naming ``name`` unless a Poisson's ratio in (-1, 0.5)."""
    value = float(value)
    if not (math.isfinite(value) and -1.0 < value < 0.5):
        raise ValueError(f"{name} must be a Poisson's ratio in (-1, 0.5), got {value!r}")
    return value
