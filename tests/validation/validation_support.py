"""Shared scenes for the hard cases: assemble a scene once, then run many load histories on it.

A ``Simulation`` is a contact pair plus a history; building new ``Simulation`` objects on the
same ``ContactPair`` reuses its assembled, factorised and condensed problem, so each extra
history costs only the small dense Newton solves.
"""

from __future__ import annotations

import functools

import numpy as np

from fretbem.contact.law import CoulombFriction
from fretbem.scenes.reference import CattaneoMindlinScene, cattaneo_mindlin
from fretbem.simulation import LoadStep, Simulation, run
from fretbem.solvers.newton import SemiSmoothNewton, Solver
from fretbem.verification.closed_forms import MindlinDeresiewicz

P = 100.0  # the reference scene's normal load, N/mm


@functools.cache
def scene(**fields) -> Simulation:
    """The reference scene with ``fields`` overridden, prepared (assembled) once per session."""
    simulation = cattaneo_mindlin(**fields)
    simulation.prepare()
    return simulation


def history(
    base: Simulation,
    tangential,
    *,
    friction: float | None = None,
    normal: float = P,
    solver: Solver | None = None,
    increments: int = 1,
    reference: bool = True,
) -> Simulation:
    """A new load history (steps named A, B, C, ... unless 26 are exceeded) on ``base``'s pair.

    A different ``friction`` gets a new law on the same (already condensed) pair.
    """
    pair = base.pair
    law = base.law if friction is None else CoulombFriction(friction)
    steps = [LoadStep(_name(k), normal, q, increments) for k, q in enumerate(tangential)]
    ref = None
    if reference and base.reference is not None:
        ref = MindlinDeresiewicz(base.reference.hertz, law.friction)
    return Simulation(
        pair, steps, solver or SemiSmoothNewton(), law=law, reference=ref, name=base.name
    )


def _name(k: int) -> str:
    return chr(ord("A") + k) if k < 26 else f"S{k}"


def cycle(
    base: Simulation,
    ratio: float,
    *,
    friction: float | None = None,
    check: bool = True,
    **kwargs,
):
    """Run A (P), B (+Q), C (0), D (-Q), E (0) with Q = ratio f P on ``base``'s pair.

    ``check=False`` keeps a run the result checks would refuse (a deliberately coarse mesh
    whose error a test measures); such tests assert the refusal too.
    """
    f = base.law.friction if friction is None else friction
    q = ratio * f * P
    simulation = history(base, (0.0, q, 0.0, -q, 0.0), friction=friction, **kwargs)
    return run(simulation, check=check)


def hertz_of(**fields):
    return CattaneoMindlinScene(**fields).hertz()


def check_physics(result, *, p_rel: float, q_abs: float) -> None:
    """Every step: |q| <= f p, p >= 0, slip pairs on the cone, separated pairs carry nothing,
    int p = P to ``p_rel`` (relative) and |int q - Q| <= ``q_abs``."""
    f = result.simulation.law.friction
    for step in result.steps:
        scale = np.max(step.pressure)
        assert np.all(step.pressure >= -1e-12 * scale), step.name
        assert np.all(np.abs(step.shear) <= f * step.pressure + 1e-12 * scale), step.name
        slip = step.states == 2
        np.testing.assert_allclose(
            np.abs(step.shear[slip]), f * step.pressure[slip], rtol=1e-9, atol=1e-12 * scale
        )
        separated = step.states == 0
        assert np.all(np.abs(step.pressure[separated]) <= 1e-12 * scale), step.name
        assert np.all(np.abs(step.shear[separated]) <= 1e-12 * scale), step.name
        assert abs(step.resultant[0] - step.normal) <= p_rel * step.normal, step.name
        assert abs(step.resultant[1] - step.tangential) <= q_abs, step.name


def l2_difference(step, reference_step, field: str) -> float:
    """RMS over the coarse pairs of (coarse - fine interpolated), fields 'pressure'/'shear'."""
    fine = np.interp(step.x, reference_step.x, getattr(reference_step, field))
    return float(np.sqrt(np.mean((getattr(step, field) - fine) ** 2)))
