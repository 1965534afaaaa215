"""Number formats of the results page (docs/results.md): percent, seconds, MiB, BLAS threads."""

from __future__ import annotations

import math


def pct(value, digits: int = 3) -> str:
    """A fraction in percent ('–' for none)."""
    return "–" if value is None else f"{100 * value:.{digits}f}"


def seconds(value) -> str:
    """Seconds, three decimals below 10 s."""
    if value is None:
        return "–"
    return f"{value:.3f}" if value < 10 else f"{value:.1f}"


def mib(value) -> str:
    """MiB to the unit ('–' when not measured)."""
    return "–" if value is None or math.isnan(value) else f"{value:.0f}"


def threads(m: dict) -> str:
    """The BLAS thread settings of a machine record."""
    env = m.get("blas_threads_env")
    if isinstance(env, dict) and env:
        return ", ".join(f"{k}={v}" for k, v in env.items())
    return "default BLAS threads"


__all__ = ["mib", "pct", "seconds", "threads"]
