"""Speed of a wear history: 10,000 cycles of the reference scene under gross slip.

examples/fretting_wear_gross_slip.toml (two BEM cylinders, 61 pairs, 30 increments a cycle,
energy law on both faces, implicit jumps) is built and its wear history solved ``--rounds``
times, interleaved with one plain five-step reference run (the floor: the same assembly
and a few Newton increments), so both see the same machine load. Printed: the medians of
the wall and CPU time of the wear history (assembly included), the simulated cycles, the
floor and the machine load; ``--json`` writes them.

    OPENBLAS_NUM_THREADS=1 python benchmarks/wear_gross_slip.py --rounds 3
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import time
from pathlib import Path

from fretbem.pipeline import wear_request
from fretbem.scenes.builder import build
from fretbem.scenes.file import load_scene
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run
from fretbem.wear.run import run_wear

SCENE = Path(__file__).resolve().parents[1] / "examples" / "fretting_wear_gross_slip.toml"


def wear_once(cycles: int | None) -> dict:
    """One wear history from scratch (scene read, bodies assembled): wall, CPU, cycles."""
    wall, cpu = time.perf_counter(), time.process_time()
    scene = load_scene(SCENE)
    simulation, _ = build(scene)
    request = wear_request(scene.extras)
    wear = request.simulation(simulation)
    if cycles is not None:
        import attrs

        wear = attrs.evolve(wear, cycles=cycles, outputs=(0, cycles))
    result = run_wear(wear)
    return {
        "wall": time.perf_counter() - wall,
        "cpu": time.process_time() - cpu,
        "simulated": result.simulated,
        "cycles": wear.cycles,
        "depth_um": 1e3 * result.final.profile.max_depth("lower"),
    }


def floor_once() -> float:
    """The plain reference run (assembly and five steps), wall seconds."""
    start = time.perf_counter()
    run(cattaneo_mindlin(pairs=61))
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--cycles", type=int, default=None, help="default: the scene's 10,000")
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args()
    wear, floor = [], []
    for _ in range(args.rounds):
        floor.append(floor_once())
        wear.append(wear_once(args.cycles))
    out = {
        "cycles": wear[0]["cycles"],
        "simulated_cycles": wear[0]["simulated"],
        "depth_um": wear[0]["depth_um"],
        "wear_wall_median_s": statistics.median(w["wall"] for w in wear),
        "wear_cpu_median_s": statistics.median(w["cpu"] for w in wear),
        "floor_wall_median_s": statistics.median(floor),
        "loadavg": os.getloadavg(),
        "openblas_threads": os.environ.get("OPENBLAS_NUM_THREADS"),
    }
    for key, value in out.items():
        print(f"{key}: {value}")
    if args.json:
        args.json.write_text(json.dumps(out, indent=2) + "\n")


if __name__ == "__main__":
    main()
