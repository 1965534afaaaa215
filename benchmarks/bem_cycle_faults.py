"""The BEM reference cycle inside ``run`` (as a user runs it), two source trees interleaved:
CPU of the preparation and of the steps, and the preparation's page faults.

:mod:`bem_phases` calls the phases itself (the assembly apart from the rest of the
preparation); here each cold cycle is one ``run`` (scene cache cleared), its ``prepare``
and steps timed by wrapping ``Simulation.prepare`` and
``Simulation.step`` (CPU: user + system, as ``time.process_time``), the minor page faults of
the preparation counted (``getrusage``), then the numpy Toeplitz peer
(``benchmarks/halfplane_peer.py``). Warm-ups as in :mod:`bem_phases`. Medians over cycles
and rounds; the faults column is a count, not ms.

    OPENBLAS_NUM_THREADS=1 python benchmarks/bem_cycle_faults.py --before /tmp/before \\
        --rounds 3 --cycles 5 --pairs 481
"""

from __future__ import annotations

from phase_rounds import medians, rounds_by_pairs

CHILD = r"""
import json, resource, sys, time
sys.path.insert(0, sys.argv[1])
from fretbem import simulation as sim
from fretbem.scenes import reference as scenes
from fretbem.simulation import run
import halfplane_peer
from cold_caches import clear_scene_caches
spent = {}
def timed(name):
    method = getattr(sim.Simulation, name)
    def wrapper(self, *args, **kwargs):
        before, start = resource.getrusage(resource.RUSAGE_SELF).ru_minflt, time.process_time()
        try:
            return method(self, *args, **kwargs)
        finally:
            cpu, faults = spent.get(name, (0.0, 0))
            spent[name] = (cpu + time.process_time() - start,
                           faults + resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before)
    setattr(sim.Simulation, name, wrapper)
timed("prepare")
timed("step")
out = {}
for pairs in map(int, sys.argv[3].split(",")):
    for radius in (71.0, 72.0):  # imports and compiled loops on other pads (bem_phases.py)
        run(scenes.cattaneo_mindlin(pairs=pairs, models={}, radius=radius))
    rows = []
    for _ in range(int(sys.argv[2])):
        clear_scene_caches()
        spent.clear()
        start = time.process_time()
        run(scenes.cattaneo_mindlin(pairs=pairs, models={}))
        done = time.process_time()
        halfplane_peer.cycle(pairs)
        rows.append((spent["prepare"][0], spent["step"][0], spent["prepare"][1] * 1e-3,
                     done - start, time.process_time() - done))
    out[pairs] = rows
print(json.dumps(out))
"""
PHASES = ("prepare", "steps", "prepare faults (count)", "total", "peer")


def main() -> None:
    rows, load, args = rounds_by_pairs(__doc__.splitlines()[0], CHILD)
    medians(rows, PHASES, args.rounds, args.cycles, load)


if __name__ == "__main__":
    main()
