"""The half-plane reference cycle by phase, two source trees interleaved (issue 28 item 3).

Each round runs one fresh process per tree (``PYTHONPATH`` = the tree's ``framework`` and
``plugins``, one BLAS thread); in it, at 61 and 481 pairs, ``--cycles`` cold cycles (scene
cache cleared) with half-plane bodies, each split into the scene build, ``prepare`` and the
five steps, each followed by the numpy Toeplitz peer (``benchmarks/halfplane_peer.py``); CPU
seconds, medians over cycles and rounds, and the median ratio of cycle to peer.

    OPENBLAS_NUM_THREADS=1 python benchmarks/halfplane_phases.py --before /tmp/before \\
        --rounds 4 --cycles 5 --json docs/results/halfplane_phases.json

``--json`` keeps the medians and ratios for ``benchmarks/performance_page.py``.
"""

from __future__ import annotations

import json
import os
import platform
from pathlib import Path

from phase_rounds import interleaved, medians, tree_parser, trees_of

CHILD = r"""
import json, statistics, sys, time
sys.path.insert(0, sys.argv[1])
from fretbem.scenes import reference as scenes
from fretbem.simulation import run
import halfplane_peer
from cold_caches import clear_scene_caches
models = {"upper": "half-plane", "lower": "half-plane"}
out = {}
for pairs in (61, 481):
    run(scenes.cattaneo_mindlin(pairs=pairs, models=models, radius=71.0))  # imports: another pad
    rows = []
    for _ in range(int(sys.argv[2])):
        clear_scene_caches()
        start = time.process_time()
        simulation = scenes.cattaneo_mindlin(pairs=pairs, models=models)
        built = time.process_time()
        simulation.prepare()
        prepared = time.process_time()
        run(simulation)
        done = time.process_time()
        halfplane_peer.cycle(pairs)
        rows.append((built - start, prepared - built, done - prepared, done - start,
                     time.process_time() - done))
    out[pairs] = rows
print(json.dumps(out))
"""
PHASES = ("build", "prepare", "steps", "total", "peer")


def main() -> None:
    parser = tree_parser(__doc__.splitlines()[0], rounds=4)
    parser.add_argument("--json", type=Path, help="write the medians and ratios here")
    args = parser.parse_args()
    trees = trees_of(args)
    rows, load = interleaved(CHILD, trees, args.rounds, [str(args.cycles)])
    table, ratios = medians(rows, PHASES, args.rounds, args.cycles, load)
    if args.json:
        result = {
            "machine": f"{os.cpu_count()} cores, {platform.platform()}, Python "
            f"{platform.python_version()}",
            "load": load,
            "rounds": args.rounds,
            "cycles": args.cycles,
            "medians_ms": table,
            "ratios": ratios,
        }
        args.json.write_text(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
