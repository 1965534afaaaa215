"""What the assembly's use of symmetry saves, in one process (issue 28 item 3).

The reference scene's cold build and both bodies' assembly (numpy loops, as a one-off
61-pair run assembles them), interleaved in four modes: point images and mirrors used
(the default), mirrors off (``fretbem.bem.mirror.permutation`` finds none), point images
off (no segment is discretised or assembled as another's image), both off. CPU ms, medians
over rounds; ``OPENBLAS_NUM_THREADS=1``.

    OPENBLAS_NUM_THREADS=1 python benchmarks/symmetry_assembly.py --rounds 15 --pairs 61
"""

from __future__ import annotations

import argparse
import contextlib
import os
import statistics
import time

from cold_caches import clear_scene_caches

from fretbem.bem import assembly, images, mirror
from fretbem.bem.integration import LOOP_CHOICE
from fretbem.bem.system import g_free_segments
from fretbem.scenes import reference as scenes

MODES = ("images and mirrors", "no mirrors", "no images", "neither")


@contextlib.contextmanager
def _mode(name: str):
    saved = mirror.permutation, assembly.BLOCKS.image, images.discretise
    try:
        if name in ("no mirrors", "neither"):
            mirror.permutation = lambda *args: None
        if name in ("no images", "neither"):
            assembly.BLOCKS.image = lambda basis: None
            images.discretise = lambda family, curve, refinement: family.discretise(
                curve, refinement
            )
        yield
    finally:
        mirror.permutation, assembly.BLOCKS.image, images.discretise = saved
        if "image" in vars(assembly.BLOCKS):
            del assembly.BLOCKS.image


def _cycle(pairs: int) -> tuple[float, float]:
    """CPU seconds of a cold build and of both bodies' assembly."""
    clear_scene_caches()
    LOOP_CHOICE.reset()  # the numpy loops, as in a one-off run
    start = time.process_time()
    simulation = scenes.cattaneo_mindlin(pairs=pairs, models={})
    pair = simulation.pair
    built = time.process_time()
    for body, tag in ((pair.upper, pair.upper_tag), (pair.lower, pair.lower_tag)):
        body.system_matrices(g_free_segments(body, body.layout((tag,))))
    return built - start, time.process_time() - built


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=15)
    parser.add_argument("--pairs", type=int, default=61)
    args = parser.parse_args()
    _cycle(args.pairs)  # imports
    times: dict = {name: [] for name in MODES}
    load = os.getloadavg()[0]
    for _ in range(args.rounds):
        for name in MODES:
            with _mode(name):
                times[name].append(_cycle(args.pairs))
    print(f"load {load:.2f} -> {os.getloadavg()[0]:.2f}; {args.pairs} pairs, CPU ms, "
          f"medians of {args.rounds} rounds")  # fmt: skip
    base = statistics.median(sum(t) for t in times["neither"])
    for name in MODES:
        build = statistics.median(t[0] for t in times[name]) * 1e3
        assembled = statistics.median(t[1] for t in times[name]) * 1e3
        both = statistics.median(sum(t) for t in times[name])
        print(f"{name:20s} build {build:6.1f}  assembly {assembled:6.1f}  "
              f"neither / this {base / both:5.2f}")  # fmt: skip


if __name__ == "__main__":
    main()
