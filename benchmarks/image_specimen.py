"""The reference pad's and specimen's set-up by body, two source trees interleaved (issue 28).

The specimen of the reference scene is the pad's exact point image: its H and G are the
pad's permuted (``fretbem.bem.image_matrices``) and its system is solved with the pad's
factors; where the tree does so, the specimen's H and G are not even formed (its system
takes the pad's columns: ``BemBody.permuted_source``; its assembly then reads 0). Each
round runs one fresh process per tree (``PYTHONPATH`` = the tree's
``framework`` and ``plugins``, one BLAS thread); in it, per pair count, ``--cycles`` cold
cycles (scene caches cleared), each timing (CPU) the pad's assembly (its system matrices,
as the run asks for them), system and contact response, the specimen's three alike, and the
rest of ``prepare`` (the condensation); medians over cycles and rounds.

    OPENBLAS_NUM_THREADS=1 python benchmarks/image_specimen.py --before /tmp/before \\
        --rounds 3 --cycles 5 --pairs 61,481
"""

from __future__ import annotations

import statistics

from phase_rounds import rounds_by_pairs

CHILD = r"""
import json, sys, time
sys.path.insert(0, sys.argv[1])
from fretbem.scenes import reference as scenes
from fretbem.simulation import run
from fretbem.bem.system import g_free_segments
from cold_caches import clear_scene_caches
out = {}
for pairs in map(int, sys.argv[3].split(",")):
    for radius in (71.0, 72.0):  # imports, on other pads (twice: numba's loops at 481)
        run(scenes.cattaneo_mindlin(pairs=pairs, models={}, radius=radius))
    rows = []
    for _ in range(int(sys.argv[2])):
        clear_scene_caches()
        simulation = scenes.cattaneo_mindlin(pairs=pairs, models={})
        pair = simulation.pair
        row = []
        for body, tag in ((pair.upper, pair.upper_tag), (pair.lower, pair.lower_tag)):
            start = time.process_time()
            free = g_free_segments(body, body.layout((tag,)))
            if getattr(body, "permuted_source", lambda free: None)(free) is None:
                body.system_matrices(free)  # (the run never forms an image's H and G now)
            assembled = time.process_time()
            body.system((tag,))
            solved = time.process_time()
            body.contact_response(tag)
            row += [assembled - start, solved - assembled, time.process_time() - solved]
        start = time.process_time()
        simulation.prepare()
        rows.append(row + [time.process_time() - start])
    out[pairs] = rows
print(json.dumps(out))
"""
PHASES = ("pad assembly", "pad system", "pad response", "specimen assembly",
          "specimen system", "specimen response", "condensation")  # fmt: skip


def main() -> None:
    rows, load, args = rounds_by_pairs(__doc__.splitlines()[0], CHILD)
    print(f"load {load[0]:.2f} -> {load[1]:.2f}; CPU ms, medians of "
          f"{args.rounds} rounds x {args.cycles} cycles")  # fmt: skip
    for pairs in rows["before"]:
        for name in rows:
            values = rows[name][pairs]
            ms = [statistics.median(v[i] for v in values) * 1e3 for i in range(len(PHASES))]
            text = ", ".join(f"{p} {m:.1f}" for p, m in zip(PHASES, ms, strict=True))
            print(f"{name:6s} {pairs:>3s} pairs: {text}")


if __name__ == "__main__":
    main()
