"""Two small costs of every run, against a warm 61-pair reference cycle in one process:
reading the available memory (``/proc/meminfo``, once per resource check) and building a
step's result record a second time (``attrs.evolve`` to add its checks, as the runs did
before 0.2.0); with the number of memory reads of a run, a sweep batch and a scene run.

Run from the repository root::

    OPENBLAS_NUM_THREADS=1 python benchmarks/run_overheads.py
"""

from __future__ import annotations

import json
import os
import statistics
import time
import timeit

import attrs

from fretbem.bem import resources
from fretbem.pipeline import run_scene
from fretbem.scenes import cattaneo_mindlin
from fretbem.scenes.file import load_scene
from fretbem.simulation import run
from fretbem.studies.sweep import cases as sweep_cases

SWEEP_SCENE = {
    "scene": {"basis": "nurbs", "pairs": 61},
    "geometry": {"radius": 70.0, "width": 6.5, "height": 16.25, "lower": "arc"},
    "material": {"E": 73400.0, "nu": 0.33},
    "contact": {"friction": 0.3},
    "load": {"P": 100.0, "Q": [0.0, 18.0, 0.0, -18.0, 0.0], "steps": ["A", "B", "C", "D", "E"]},
}


def per_call(function, number: int = 2000) -> float:
    """Seconds per call: the best of 7 repeats."""
    return min(timeit.repeat(function, number=number, repeat=7)) / number


def reads(action) -> int:
    """How many times ``action()`` reads the available memory."""
    real, count = resources.available_memory, [0]

    def counting():
        count[0] += 1
        return real()

    resources.available_memory = counting
    try:
        action()
    finally:
        resources.available_memory = real
    return count[0]


def main() -> None:
    simulation = cattaneo_mindlin(pairs=61)
    result = run(simulation)  # assembled and condensed once: the runs below are warm
    cycles = []
    for _ in range(41):
        tic = time.perf_counter()
        run(simulation)
        cycles.append(time.perf_counter() - tic)
    cycle = statistics.median(cycles)
    step = result.steps[-1]
    meminfo = per_call(resources.available_memory)
    evolve = per_call(lambda: attrs.evolve(step, checks=step.checks))
    steps = len(result.steps)
    batch = [(k, {}, SWEEP_SCENE) for k in range(4)]
    scene = load_scene("examples/cattaneo_mindlin.toml")
    print(json.dumps({
        "load": os.getloadavg()[0],
        "warm_cycle_ms": round(1e3 * cycle, 3),
        "meminfo_read_us": round(1e6 * meminfo, 1),
        "second_record_us_per_step": round(1e6 * evolve, 1),
        "second_records_share_of_the_cycle": round(steps * evolve / cycle, 4),
        "meminfo_read_share_of_the_cycle": round(meminfo / cycle, 4),
        "reads": {
            "run": reads(lambda: run(simulation)),
            "sweep batch of 4 cases": reads(lambda: sweep_cases.run_batch(SWEEP_SCENE, batch)),
            "run_scene, fixed mesh with its estimate": reads(lambda: run_scene(scene)),
        },
    }))  # fmt: skip


if __name__ == "__main__":
    main()
