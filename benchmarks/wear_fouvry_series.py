"""The Ti-6Al-4V gross-slip radius series of Fouvry et al. (2017) run with fretbem.

Fouvry, Arnaud, Mignot, Neubauer, Tribology International 113 (2017) 460: a cylinder on a
plane, E = 119 GPa, nu = 0.29, a peak Hertz pressure of 525 MPa for every radius
(R = 10, 20, 40, 80 mm with P = 133, 267, 533, 1066 N/mm), a sliding amplitude of
+-75 um, 5000 cycles. Here: both bodies half-planes with finite sliding (the pairing
follows the pad, each face wears at its own points), friction 0.65, the energy law with a
total alpha of 3.55e-4 mm^3/J split equally between the faces (a secondary-source
figure), explicit jumps. The block's amplitude is set so that the centre pair's relative
tangential displacement swings +-75 um (the block's elastic part measured first on the
same scene). Prints one JSON row per radius (scar width and depth of each face, volume
and energy at every output N, peak pressure, contact width, the final profiles) and
writes them to fouvry_series.json.

    OPENBLAS_NUM_THREADS=1 python benchmarks/wear_fouvry_series.py 10,20,40,80 61 8

(arguments: the radii to run, mm; pairs, default 61; increments a stroke, default 8, so
24 a cycle)
"""

from __future__ import annotations

import json
import sys
import time

import numpy as np

from fretbem.scenes.builder import build
from fretbem.scenes.file import scene_from_data
from fretbem.sliding import solve_sliding
from fretbem.wear.jump import JumpControl
from fretbem.wear.law import EnergyWear
from fretbem.wear.run import WearSimulation, run_wear

E, NU, F, SLIDE, CYCLES = 119000.0, 0.29, 0.65, 0.075, 5000
ALPHA = 3.55e-4  # mm^3/J, both bodies together, split equally
#: the series: R (mm) -> P (N/mm), and the candidate zone's half-width (mm), room for the
#: flattened pad (b ~ (3 V R / 2)^(1/3) with V the pad's half of alpha E_d)
SERIES = {10: (133.0, 1.2), 20: (267.0, 1.8), 40: (533.0, 2.8), 80: (1066.0, 4.5)}
OUTPUTS = [250, 500, 1000, 2000, 3000, 4000]


def scene(radius, load, zone, delta, pairs, increments=10):
    """The cylinder on a flat, both half-planes, sliding, the block driven to +-delta."""
    data = {
        "pad": {"shape": "cylinder", "radius": radius, "width": 4 * zone, "height": 4 * zone,
                "model": "half-plane"},
        "specimen": {"shape": "flat", "length": 8 * zone, "thickness": 4 * zone,
                     "model": "half-plane"},
        "material": {"E": E, "nu": NU},
        "contact": {"friction": F, "pairs": pairs, "zone_width": zone,
                    "pairing": "node-to-segment", "sliding": True},
        "load": {"steps": ["A", "B", "C"], "P": load, "delta": [0.0, delta, -delta],
                 "increments": [1, increments, 2 * increments]},
    }  # fmt: skip
    return build(scene_from_data(data))[0]


def amplitude(simulation) -> float:
    """Half the range of the centre pair's relative tangential displacement (mm)."""
    steps = solve_sliding(simulation, say=lambda _: None).steps
    middle = [float(np.asarray(s.tangential_displacement)[s.x.shape[0] // 2]) for s in steps]
    return 0.5 * (middle[1] - middle[2])


def run_radius(radius: int, pairs: int, increments: int) -> dict:
    load, zone = SERIES[radius]
    a = np.sqrt(8 * load * radius * (1 - NU**2) / (np.pi * E))
    start = time.perf_counter()
    trial = 0.2
    delta = trial - amplitude(scene(radius, load, zone, trial, pairs)) + SLIDE
    simulation = scene(radius, load, zone, delta, pairs, increments)
    slide = amplitude(simulation)
    laws = {"upper": EnergyWear(ALPHA / 2), "lower": EnergyWear(ALPHA / 2)}
    wear = WearSimulation(simulation, laws, CYCLES, outputs=OUTPUTS, sliding=True,
                          control=JumpControl(relative_change=0.2))  # fmt: skip
    result = run_wear(wear)
    final = result.final
    prof = final.profile
    touching = [final.pair_x(k)[final.pressure[k] > 0] for k in range(2)]
    return {
        "R": radius, "P": load, "a": a, "p0": 2 * load / (np.pi * a), "zone": zone,
        "pairs": pairs, "increments": 3 * increments, "delta_block": delta, "delta_s": slide,
        "simulated": result.simulated, "seconds": time.perf_counter() - start,
        "scar_width_specimen": prof.scar_width("lower"),
        "scar_width_pad": prof.scar_width("upper"),
        "depth_specimen_um": 1e3 * prof.max_depth("lower"),
        "depth_pad_um": 1e3 * prof.max_depth("upper"),
        "contact_width": float(touching[0].max() - touching[0].min()),
        "peak_p": float(final.pressure.max()),
        "N": [s.cycles for s in result.snapshots],
        "energy_J_per_mm": [s.energy / 1000 for s in result.snapshots],
        "volume_total": [s.profile.volume("upper") + s.profile.volume("lower")
                         for s in result.snapshots],
        "x": prof.x.tolist(), "h_specimen": prof.lower.tolist(),
        "x_pad": prof.upper_x.tolist(), "h_pad": prof.upper.tolist(),
        "p_x": final.pair_x(0).tolist(), "p": final.pressure[0].tolist(),
    }  # fmt: skip


def main() -> None:
    radii = [int(r) for r in sys.argv[1].split(",")]
    pairs = int(sys.argv[2]) if len(sys.argv) > 2 else 61
    increments = int(sys.argv[3]) if len(sys.argv) > 3 else 8
    out = {}
    for radius in radii:
        row = run_radius(radius, pairs, increments)
        out[radius] = row
        shown = {k: v for k, v in row.items() if not isinstance(v, list) or k == "N"}
        print(json.dumps(shown), flush=True)
        with open(f"fouvry_series_{sys.argv[1].replace(',', '-')}.json", "w") as handle:
            json.dump(out, handle, indent=1)


if __name__ == "__main__":
    main()
