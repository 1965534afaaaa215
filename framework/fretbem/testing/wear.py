"""Conformance check for wear laws (re-exported by :mod:`fretbem.testing`).

Only the :class:`~fretbem.wear.law.WearLaw` API is used. A failure raises
``AssertionError`` naming the law and the property that does not hold.
"""

from __future__ import annotations

import numpy as np

from fretbem.wear.law import WearLaw

__all__ = ["check_wear_law"]


def _require(ok: bool, who: str, prop: str, detail: str = "") -> None:
    if not ok:
        raise AssertionError(f"{who}: {prop} does not hold" + (f" ({detail})" if detail else ""))


def check_wear_law(law: WearLaw) -> None:
    """Check ``law`` on pairs in slip, in stick and separated: depths finite and >= 0 of the
    pairs' shape, nothing worn without slip or without pressure, the same depth for slip
    either way, depth additive over split increments (so a cycle's wear can be summed and
    extrapolated), and a finite, non-negative pressure sensitivity."""
    who = type(law).__name__
    _require(isinstance(law, WearLaw), who, "the law is a WearLaw")
    rng = np.random.default_rng(7)
    p = rng.uniform(10.0, 500.0, 12)
    q = 0.5 * p * rng.choice([-1.0, 1.0], 12)
    ds = rng.uniform(1e-4, 1e-2, 12) * np.sign(q)
    depth = np.asarray(law.depth(p, q, ds), float)
    _require(depth.shape == p.shape, who, "depth has one value per pair", f"got {depth.shape}")
    _require(bool(np.all(np.isfinite(depth))), who, "depths are finite")
    _require(bool(np.all(depth >= 0)), who, "depths are >= 0", f"min {depth.min():g}")
    _require(bool(np.any(depth > 0)) or law.coefficient == 0, who, "slipping pairs wear")
    stick = np.asarray(law.depth(p, q, np.zeros_like(p)), float)
    _require(bool(np.all(stick == 0)), who, "no wear without slip", f"max {stick.max():g}")
    apart = np.asarray(law.depth(np.zeros_like(p), np.zeros_like(q), ds), float)
    _require(bool(np.all(apart == 0)), who, "no wear without contact", f"max {apart.max():g}")
    flipped = np.asarray(law.depth(p, -q, -ds), float)
    _require(np.allclose(flipped, depth, rtol=1e-12, atol=0), who, "wear is even in the slip")
    halves = 2 * np.asarray(law.depth(p, q, 0.5 * ds), float)
    _require(
        np.allclose(halves, depth, rtol=1e-12, atol=0), who,
        "two half increments wear as much as the whole one",
    )  # fmt: skip
    sensitivity = np.asarray(law.pressure_sensitivity(p, q, ds), float)
    _require(sensitivity.shape == p.shape, who, "pressure_sensitivity has one value per pair")
    _require(
        bool(np.all(np.isfinite(sensitivity)) and np.all(sensitivity >= 0)), who,
        "pressure_sensitivity is finite and >= 0",
    )  # fmt: skip
