"""One simulated load cycle on a worn contact: the wear each body takes per cycle.

The cycle's steps are solved increment by increment (:meth:`Simulation.step` with one
increment at a time, so the friction memory is the simulation's own). After each increment
the slip increment ds of every pair (the change of the relative tangential displacement,
zero where the pair sticks) and the tractions p, q at the increment's end give each body's
depth increment through its wear law; sums over the cycle give the per-cycle wear, the
dissipated energy sum(w |q| |ds|) and the Archard work sum(w p |ds|).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import attrs
import numpy as np

from fretbem.contact.condensation import CondensedContact
from fretbem.contact.law import ContactState
from fretbem.simulation import LoadStep, Simulation

from .law import WearLaw
from .profile import BODIES

__all__ = ["CycleWear", "simulate_cycle"]


@attrs.frozen(eq=False)
class CycleWear:
    """What one simulated cycle did to the faces.

    Attributes
    ----------
    depth : mapping "upper"/"lower" -> ndarray
        Wear depth each body takes in the cycle, per pair (mm).
    sensitivity : ndarray
        d(depth of both bodies)/dp summed over the cycle, per pair (mm/MPa): the wear
        rate's answer to the pressure, for the jump's stability estimate.
    energy : ndarray
        Dissipated energy density sum |q| |ds| per pair (N mm / mm^2).
    work : ndarray
        Archard work density sum p |ds| per pair (N mm / mm^2).
    slip_path : ndarray
        sum |ds| per pair over the cycle (mm).
    pressure, shear : ndarray, shape (n_steps, n)
        p and q at the end of each step of the cycle.
    state : ContactState
        The contact state at the end of the cycle (the start of the next).
    iterations : int
        Newton iterations of the cycle.
    """

    depth: Mapping[str, np.ndarray]
    sensitivity: np.ndarray
    energy: np.ndarray
    work: np.ndarray
    slip_path: np.ndarray
    pressure: np.ndarray
    shear: np.ndarray
    state: ContactState
    iterations: int


def _between(start: Mapping[str, float], end: Mapping[str, float], frac: float) -> dict:
    names = dict.fromkeys([*start, *end])
    return {k: start.get(k, 0.0) + frac * (end.get(k, 0.0) - start.get(k, 0.0)) for k in names}


def increments(start: ContactState, load: LoadStep) -> list[LoadStep]:
    """The single increments of ``load`` from ``start``: one LoadStep per increment."""
    out = []
    for k in range(1, load.increments + 1):
        frac = k / load.increments
        out.append(
            LoadStep(
                f"{load.name}.{k}",
                start.normal + frac * (load.normal - start.normal),
                start.tangential + frac * (load.tangential - start.tangential),
                1,
                _between(start.loads, load.loads, frac),
            )
        )
    return out


def simulate_cycle(
    simulation: Simulation,
    problem: CondensedContact,
    state: ContactState,
    cycle: Sequence[LoadStep],
    laws: Mapping[str, WearLaw],
) -> CycleWear:
    """Solve ``cycle`` on ``problem`` (a worn contact) from ``state``; the wear it causes."""
    n = problem.n_pairs
    layout = problem.layout
    depth = {body: np.zeros(n) for body in BODIES}
    sensitivity, energy, work, path = (np.zeros(n) for _ in range(4))
    pressures, shears, iterations = [], [], 0
    for load in cycle:
        for step in increments(state, load):
            new, its, _ = simulation.step(problem, state, step)
            iterations += its
            ds = np.asarray(new.slip) - np.asarray(state.slip)
            p, q = new.x[layout.pressure], new.x[layout.shear]
            for body in BODIES:
                depth[body] += laws[body].depth(p, q, ds)
                sensitivity += laws[body].pressure_sensitivity(p, q, ds)
            touching = p > 0
            energy += np.where(touching, np.abs(q) * np.abs(ds), 0.0)
            work += np.where(touching, p * np.abs(ds), 0.0)
            path += np.abs(ds)
            state = new
        pressures.append(state.x[layout.pressure].copy())
        shears.append(state.x[layout.shear].copy())
    return CycleWear(
        depth, sensitivity, energy, work, path, np.array(pressures), np.array(shears), state,
        iterations,
    )  # fmt: skip
