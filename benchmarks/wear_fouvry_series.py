"""The Ti-6Al-4V gross-slip radius series of Fouvry et al. (2017) run with fretbem.

Half-plane bodies, E = 119 GPa, nu = 0.29, friction 0.65, 5000 cycles, the pad's block
driven to a sliding amplitude of 75 um (the elastic part measured first), the energy law
with a total alpha of 3.55e-4 mm^3/J split equally; prints one JSON row per radius (scar
width, depth, volume, energy) and writes them to fouvry_<series>.json.

    OPENBLAS_NUM_THREADS=1 python benchmarks/wear_fouvry_series.py 81 10:133,80:1066 20

(arguments: pairs, radius:load list, increments of the first stroke)
"""

from __future__ import annotations

import json
import sys
import time

import numpy as np

from fretbem.contact.law import ContactState
from fretbem.scenes.builder import build
from fretbem.scenes.file import scene_from_data
from fretbem.wear.cycle import simulate_cycle
from fretbem.wear.jump import JumpControl
from fretbem.wear.law import EnergyWear
from fretbem.wear.run import WearSimulation, run_wear

E, NU, F, SLIDE = 119000.0, 0.29, 0.65, 0.075
ALPHA = 3.55e-4  # mm^3/J, both bodies together, split equally


def scene(radius, load, pairs, zone, delta, increments=10):
    """The cylinder on a flat, both half-planes, driven to +-delta."""
    data = {
        "pad": {"shape": "cylinder", "radius": radius, "width": 20.0, "height": 20.0,
                "model": "half-plane"},
        "specimen": {"shape": "flat", "model": "half-plane"},
        "material": {"E": E, "nu": NU},
        "contact": {"friction": F, "pairs": pairs, "zone": zone},
        "load": {"steps": ["A", "B", "C"], "P": load, "delta": [0.0, delta, -delta],
                 "increments": [1, increments, 2 * increments]},
    }  # fmt: skip
    return build(scene_from_data(data))[0]


def sliding(simulation) -> float:
    """Sliding amplitude (mm) of the second cycle, from the pairs' slip path."""
    problem = simulation.prepare()
    state = ContactState.initial(problem)
    state, _, _ = simulation.step(problem, state, simulation.steps[0])
    laws = {"upper": EnergyWear(0.0), "lower": EnergyWear(0.0)}
    cycle = None
    for _ in range(2):
        cycle = simulate_cycle(simulation, problem, state, simulation.steps[1:], laws)
        state = cycle.state
    return float(cycle.slip_path[cycle.pressure[0] > 0].mean() / 4)


def main() -> None:
    pairs, series, increments = int(sys.argv[1]), sys.argv[2], int(sys.argv[3])
    out = {}
    for radius, load in [tuple(map(int, s.split(":"))) for s in series.split(",")]:
        a = np.sqrt(8 * load * radius * (1 - NU**2) / (np.pi * E))
        start = time.time()
        delta = 0.2 - sliding(scene(radius, load, 41, 2.0, 0.2)) + SLIDE
        zone = max(3.0, 6.0 * 0.16 / a + 1.5) if radius < 80 else 3.0
        simulation = scene(radius, load, pairs, zone, delta, increments)
        laws = {"upper": EnergyWear(ALPHA / 2), "lower": EnergyWear(ALPHA / 2)}
        wear = WearSimulation(simulation, laws, 5000, outputs=[1000, 2500],
                              control=JumpControl(scheme="implicit"))  # fmt: skip
        result = run_wear(wear)
        final, profile = result.final, result.final.profile
        out[radius] = {
            "R": radius, "P": load, "a": a, "delta": delta, "zone": zone,
            "simulated": result.simulated, "seconds": time.time() - start,
            "width_specimen": profile.scar_width("lower"),
            "depth_specimen_um": 1e3 * profile.max_depth("lower"),
            "volume_total": profile.volume("upper") + profile.volume("lower"),
            "energy_J_per_mm": final.energy / 1000,
            "peak_p": float(final.pressure[0].max()),
        }  # fmt: skip
        print(json.dumps(out[radius]), flush=True)
    with open(f"fouvry_{series.replace(':', '-')}.json", "w") as handle:
        json.dump(out, handle, indent=1)


if __name__ == "__main__":
    main()
