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
    """Root mean square over the zone, trapezoidal in x (np.trapezoid's arithmetic, written
    out for the usual one-dimensional case: every step's record forms two)."""
    width = x[-1] - x[0]
    if not width > 0:
        return math.nan
    squared = values**2
    if squared.ndim != 1 or np.ndim(x) != 1:
        return float(np.sqrt(np.trapezoid(squared, x) / width))
    integral = ((x[1:] - x[:-1]) * (squared[1:] + squared[:-1]) / 2.0).sum()
    return float(np.sqrt(integral / width))


def errors_against_theory(
    reference, x: np.ndarray, p: np.ndarray, q: np.ndarray, history
) -> tuple[dict[str, float], tuple[np.ndarray, np.ndarray]]:
    """The four errors (keys :data:`ERROR_KEYS`) of tractions p, q at pair positions x
    against ``reference`` after the tangential ``history``, and the exact (p, q)."""
    p_exact = reference.hertz.pressure(x)
    q_exact = reference.shear_traction(x, np.asarray(history))
    p0 = reference.hertz.peak_pressure
    fp0 = reference.friction * p0
    e_p, e_q = p - p_exact, q - q_exact
    errors = {
        "e_p_max": float(np.max(np.abs(e_p)) / p0),
        "e_q_max": float(np.max(np.abs(e_q)) / fp0),
        "e_p_l2": l2(e_p, x) / p0,
        "e_q_l2": l2(e_q, x) / fp0,
    }
    return errors, (p_exact, q_exact)
