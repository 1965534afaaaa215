"""Wear volumes against the summed work: energy law V = alpha E_d, Archard V = k sum p |ds|,
per body, to round-off, for each body model and basis family; no wear where pairs stick."""

import numpy as np
import pytest

from fretbem.contact.law import ContactState, PairState
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.wear.law import JOULE, ArchardWear, EnergyWear
from fretbem.wear.run import WearSimulation, run_wear

CASES = [
    ("nurbs", {}, 21),
    ("lagrange2", {}, 21),
    ("nurbs", {"upper": "half-plane", "lower": "half-plane"}, 31),
    ("nurbs", {"lower": "half-plane"}, 21),
]


@pytest.mark.parametrize(("basis", "models", "pairs"), CASES)
def test_energy_and_archard_volumes_equal_the_summed_work(basis, models, pairs):
    simulation = cattaneo_mindlin(
        basis=basis, pairs=pairs, increments=4, models=models,
        lower="flat" if models.get("lower") == "half-plane" else "arc",
    )  # fmt: skip
    energy = {"upper": EnergyWear(1.16e-4), "lower": EnergyWear(3.55e-4)}
    result = run_wear(WearSimulation(simulation, energy, 20_000, outputs=[700]))
    for snap in result.snapshots[1:]:
        assert snap.energy > 0
        for body, law in energy.items():
            volume = snap.profile.volume(body)
            assert volume == pytest.approx(law.alpha / JOULE * snap.energy, rel=1e-12)
    archard = {"upper": ArchardWear(0.0), "lower": ArchardWear(2e-8)}
    result = run_wear(WearSimulation(simulation, archard, 20_000))
    final = result.final
    assert final.profile.volume("lower") == pytest.approx(2e-8 * final.work, rel=1e-12)
    assert final.profile.volume("upper") == 0.0


def test_no_wear_where_the_pairs_stick():
    """Partial slip: the stick zone (pairs that stick at every step end of the cycle) does
    not wear; the slip zones do."""
    simulation = cattaneo_mindlin(pairs=41, increments=5)
    laws = {"upper": EnergyWear(1e-4), "lower": EnergyWear(1e-4)}
    wear = WearSimulation(simulation, laws, 1000)
    result = run_wear(wear)
    problem = simulation.prepare()
    # the states over the cycle: a pair that never slips (stick at every increment end)
    state = ContactState.initial(problem)
    state, _, _ = simulation.step(problem, state, simulation.steps[0])
    slipped = np.zeros(problem.n_pairs, bool)

    def seen(reached):
        slipped[:] |= reached.states == PairState.SLIP

    for _ in range(2):
        for load in wear.cycle_steps:
            state, _, _ = simulation.step(problem, state, load, seen)
    depth = result.final.profile.lower
    stuck = ~slipped & (result.final.pressure[0] > 0)
    assert stuck.sum() >= 5 and slipped.sum() >= 4
    assert np.max(depth[stuck]) < 1e-9 * np.max(depth)
    assert np.all(depth[slipped & (result.final.pressure[0] > 0)] > 0)
