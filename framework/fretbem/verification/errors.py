"""Errors of a computed step against a closed form (Hertz, Mindlin-Deresiewicz, Nowell-Hills).

The errors are e_p = |p - p_exact| / p0 and e_q = |q - q_exact| / (f p0), as maxima over the
pairs and in the root-mean-square sense over the zone (trapezoidal in x).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["ERROR_KEYS", "errors_against_theory", "l2"]

ERROR_KEYS = ("e_p_max", "e_q_max", "e_p_l2", "e_q_l2")


def l2(values: np.ndarray, x: np.ndarray) -> float:
    """Root mean square over the zone, trapezoidal in x."""
    width = x[-1] - x[0]
    return float(np.sqrt(np.trapezoid(values**2, x) / width)) if width > 0 else math.nan


def errors_against_theory(
    reference, x: np.ndarray, p: np.ndarray, q: np.ndarray, history
) -> tuple[dict[str, float], tuple[np.ndarray, np.ndarray]]:
    """The four errors (keys :data:`ERROR_KEYS`) of tractions p, q at pair positions x
    against ``reference`` after the tangential ``history``, and the exact (p, q)."""
    p_exact = reference.hertz.pressure(x)
    q_exact = reference.shear_traction(x, np.asarray(history))
    p0 = reference.hertz.peak_pressure
    fp0 = reference.friction * p0
    errors = {
        "e_p_max": float(np.max(np.abs(p - p_exact)) / p0),
        "e_q_max": float(np.max(np.abs(q - q_exact)) / fp0),
        "e_p_l2": l2(p - p_exact, x) / p0,
        "e_q_l2": l2(q - q_exact, x) / fp0,
    }
    return errors, (p_exact, q_exact)
