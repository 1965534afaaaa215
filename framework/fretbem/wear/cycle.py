"""One simulated load cycle on a worn contact: the wear each body takes per cycle.

The cycle's steps are solved by :meth:`Simulation.step` (force or displacement control, the
friction memory the simulation's own), which reports every increment. After each increment
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

#: what a rotating pad block reports at each step's end (CycleWear's fields)
BLOCK_ROTATION = ("moment", "rotation", "tilt")


@attrs.frozen(eq=False)
class CycleWear:
    """What one simulated cycle did to the faces.

    Attributes
    ----------
    depth : mapping "upper"/"lower" -> ndarray
        Wear depth each body takes in the cycle, per pair (mm).
    sensitivities : mapping "upper"/"lower" -> ndarray
        d(depth)/dp of each body summed over the cycle, per pair (mm/MPa): the wear rate's
        answer to the pressure, for the jump's stability estimate and the implicit jump.
    energy : ndarray
        Dissipated energy density sum |q| |ds| per pair (N mm / mm^2).
    energy_sensitivity : ndarray
        sum (|q| / p) |ds| per pair (mm): the energy density's answer to the pressure (in
        slip |q| = f p), so that an implicit jump extrapolates the energy as it does the
        depth.
    work : ndarray
        Archard work density sum p |ds| per pair (N mm / mm^2).
    work_sensitivity : ndarray
        sum |ds| over the increments in contact, per pair (mm): d(work)/dp.
    slip_path : ndarray
        sum |ds| per pair over the cycle (mm).
    pressure, shear : ndarray, shape (n_steps, n)
        p and q at the end of each step of the cycle.
    state : ContactState
        The contact state at the end of the cycle (the start of the next).
    iterations : int
        Newton iterations of the cycle.
    positions : ndarray (n_steps, n) or None
        The pairs' positions along the specimen at the end of each step, where they move
        (finite sliding: :mod:`fretbem.wear.slide`); None: the pairs stay where they are.
        With sliding, ``depth``, ``energy`` and ``work`` (and their sensitivities to p) are
        on the track's grid, not per pair.
    moment, rotation, tilt : ndarray (n_steps,) or None
        Where the pad's block rotates (:attr:`fretbem.simulation.Simulation.rotates`), its
        M, the actuator's rotation theta and the block's tilt at the end of each step (as
        :class:`fretbem.results.StepResult` names them); None: the block does not rotate.
    """

    depth: Mapping[str, np.ndarray]
    sensitivities: Mapping[str, np.ndarray]
    energy: np.ndarray
    energy_sensitivity: np.ndarray
    work: np.ndarray
    work_sensitivity: np.ndarray
    slip_path: np.ndarray
    pressure: np.ndarray
    shear: np.ndarray
    state: ContactState
    iterations: int
    positions: np.ndarray | None = None
    moment: np.ndarray | None = None
    rotation: np.ndarray | None = None
    tilt: np.ndarray | None = None

    @property
    def sensitivity(self) -> np.ndarray:
        """d(depth of both bodies)/dp per pair, summed over the cycle (mm/MPa)."""
        return sum(self.sensitivities.values())


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
    sensitivities = {body: np.zeros(n) for body in BODIES}
    energy, energy_sensitivity, work, work_sensitivity, path = (np.zeros(n) for _ in range(5))
    pressures, shears, iterations = [], [], 0
    previous = [state]

    def wear(reached: ContactState) -> None:
        ds = np.asarray(reached.slip) - np.asarray(previous[0].slip)
        p, q = reached.x[layout.pressure], reached.x[layout.shear]
        for body in BODIES:
            depth[body] += laws[body].depth(p, q, ds)
            sensitivities[body] += laws[body].pressure_sensitivity(p, q, ds)
        touching = p > 0
        energy[:] += np.where(touching, np.abs(q) * np.abs(ds), 0.0)
        ratio = np.divide(np.abs(q), p, out=np.zeros(n), where=touching)
        energy_sensitivity[:] += ratio * np.abs(ds)
        work[:] += np.where(touching, p * np.abs(ds), 0.0)
        work_sensitivity[:] += np.where(touching, np.abs(ds), 0.0)
        path[:] += np.abs(ds)
        previous[0] = reached

    turns = []  # the rotating block's M, theta and tilt at each step's end
    for load in cycle:
        state, its, _ = simulation.step(problem, state, load, wear)
        iterations += its
        pressures.append(state.x[layout.pressure].copy())
        shears.append(state.x[layout.shear].copy())
        if simulation.rotates:
            measured = simulation.measure(problem, state)
            turns.append([measured[k] for k in BLOCK_ROTATION])
    block = dict(zip(BLOCK_ROTATION, np.array(turns).T, strict=True)) if turns else {}
    return CycleWear(
        depth, sensitivities, energy, energy_sensitivity, work, work_sensitivity, path,
        np.array(pressures), np.array(shears), state, iterations, **block,
    )  # fmt: skip
