"""One face map for a half-plane's Gauss samples and influence integrals, against two maps.

In one process, alternating, over cold reference cycles on half-plane bodies (scene caches
cleared): the ``prepare`` phase with the surface's rule map (``influence.rule_map``: the
samples are its first rows, the node integrals read the rest) and with the face mapped
twice, the samples alone and the integrals alone (the code before the rule map: the
surface's rule map taken away, so each maps its own points). CPU ms, medians; the results
are the same bits either way (tests/framework/halfplane/test_influence_fast_paths.py).

    OPENBLAS_NUM_THREADS=1 python benchmarks/halfplane_face_map.py --pairs 61 481
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

from cold_caches import clear_scene_caches

from fretbem.halfplane import influence
from fretbem.halfplane import surface as surfaces
from fretbem.scenes import reference as scenes
from fretbem.simulation import run

MODELS = {"upper": "half-plane", "lower": "half-plane"}
ONE_MAP = surfaces.HalfPlaneSurface.gauss_samples, surfaces.HalfPlaneSurface._rule_map


def _samples_alone(surface):
    if "gauss_samples" not in surface._cache:
        surface._cache["gauss_samples"] = influence.gauss_samples(surface.face)
    return surface._cache["gauss_samples"]


TWO_MAPS = property(_samples_alone), property(lambda surface: None)


def prepare_ms(pairs: int, cycles: int) -> dict:
    """Median ``prepare`` CPU ms of cold cycles, one map and two maps alternating."""
    run(scenes.cattaneo_mindlin(pairs=pairs, models=MODELS, radius=71.0))  # imports
    times: dict[str, list] = {"one map": [], "two maps": []}
    try:
        for _ in range(cycles):
            for name, (samples, rule_map) in (("two maps", TWO_MAPS), ("one map", ONE_MAP)):
                surfaces.HalfPlaneSurface.gauss_samples = samples
                surfaces.HalfPlaneSurface._rule_map = rule_map
                clear_scene_caches()
                simulation = scenes.cattaneo_mindlin(pairs=pairs, models=MODELS)
                start = time.process_time()
                simulation.prepare()
                times[name].append(time.process_time() - start)
    finally:
        surfaces.HalfPlaneSurface.gauss_samples, surfaces.HalfPlaneSurface._rule_map = ONE_MAP
    return {name: 1e3 * statistics.median(values) for name, values in times.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, nargs="+", default=[61, 481])
    parser.add_argument("--cycles", type=int, default=40)
    args = parser.parse_args()
    load = os.getloadavg()[0]
    for pairs in args.pairs:
        cycles = args.cycles if pairs <= 100 else max(args.cycles // 4, 5)
        ms = prepare_ms(pairs, cycles)
        one, two = ms["one map"], ms["two maps"]
        print(f"{pairs} pairs, {cycles} cycles: prepare {two:.2f} ms with two maps, "
              f"{one:.2f} ms with one ({one / two:.3f})")  # fmt: skip
    print(f"load {load:.2f} -> {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
