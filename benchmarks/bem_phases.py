"""The BEM reference cycle by phase, two source trees interleaved (issue 28 item 3).

Each round runs one fresh process per tree (``PYTHONPATH`` = the tree's ``framework`` and
``plugins``, one BLAS thread); in it, at 61 and 481 pairs, ``--cycles`` cold cycles (scene
cache cleared) with BEM bodies, each split into the scene build, the assembly of both
bodies' H and G as the run assembles them (G's columns on traction-free segments left out
by the numpy loops where the tree does so: ``BemBody.system_matrices``; none for a point
image whose system takes the pad's columns without forming them, where the tree does so:
``BemBody.permuted_source``), the rest of
``prepare`` (factorisation, contact responses, condensation) and the five steps, each
followed by the numpy Toeplitz peer
(``benchmarks/halfplane_peer.py``); CPU seconds, medians over cycles and rounds, and the
median ratio of cycle to peer. As in ``benchmarks/workflows.py``, each pair count first
runs two cycles on other pads (imports; at 481 pairs numba's compiled loops, which one
pad's assembly alone does not reach), so the 61-pair cycle assembles with the numpy loops
and the 481-pair one with the compiled loops. The phases run inside the run's resource block
(``fretbem.simulation.run_resources``), as ``run`` prepares a simulation: from 2,048 DOFs
the allocator keeps large arrays' memory there. Prepared outside it (before 2026-11-27),
the allocator's state after the cycle depended on what the preparation had freed: against
83d0dc3, the peer after this tree's cycle took 12,600-13,300 page faults where it took
2,100-2,200 after 83d0dc3's, and read 35 % slower (481 pairs, load 3.6-4.5), which made
the cycle / peer ratio read 4.1 where, prepared inside the block, it reads 5.2.

    OPENBLAS_NUM_THREADS=1 python benchmarks/bem_phases.py --before /tmp/before \\
        --rounds 3 --cycles 5
"""

from __future__ import annotations

from phase_rounds import medians, rounds_by_pairs

CHILD = r"""
import json, sys, time
sys.path.insert(0, sys.argv[1])
from fretbem.scenes import reference as scenes
from fretbem.simulation import run, run_resources
import halfplane_peer
from cold_caches import clear_scene_caches
def assemble(body, tag):  # what the run assembles (older trees: all of H and G)
    try:
        from fretbem.bem.system import g_free_segments
    except ImportError:
        return body.matrices()
    free = g_free_segments(body, body.layout((tag,)))
    if getattr(body, "permuted_source", lambda free: None)(free) is not None:
        return None  # the run never forms them: the pad's taken permuted, column by column
    return body.system_matrices(free)
out = {}
for pairs in map(int, sys.argv[3].split(",")):
    for radius in (71.0, 72.0):  # imports, on other pads: twice, as workflows.py does, since
        # one pad's assembly (its image specimen takes its H and G) stays below the compiled
        # loops' threshold at 481 pairs and numba would load in the first timed cycle
        run(scenes.cattaneo_mindlin(pairs=pairs, models={}, radius=radius))
    rows = []
    for _ in range(int(sys.argv[2])):
        clear_scene_caches()
        start = time.process_time()
        simulation = scenes.cattaneo_mindlin(pairs=pairs, models={})
        built = time.process_time()
        pair = simulation.pair
        with run_resources(simulation):  # as run() prepares: the allocator keeps memory
            assemble(pair.upper, pair.upper_tag)
            assemble(pair.lower, pair.lower_tag)
            assembled = time.process_time()
            simulation.prepare()
            prepared = time.process_time()
            run(simulation)
        done = time.process_time()
        halfplane_peer.cycle(pairs)
        rows.append((built - start, assembled - built, prepared - assembled, done - prepared,
                     done - start, time.process_time() - done))
    out[pairs] = rows
print(json.dumps(out))
"""
PHASES = ("build", "assembly", "rest of prepare", "steps", "total", "peer")


def main() -> None:
    rows, load, args = rounds_by_pairs(__doc__.splitlines()[0], CHILD)
    medians(rows, PHASES, args.rounds, args.cycles, load)


if __name__ == "__main__":
    main()
