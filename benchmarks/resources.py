"""Peak memory and time of the reference scene against its DOF count (fretbem.bem.resources).

Each size runs in a fresh process so ``ru_maxrss`` is that run's peak. Prints one JSON line
per size and the factor peak / (8 dofs^2) that fretbem.bem.resources.BYTES_PER_DOF2 bounds.
Usage: python benchmarks/resources.py [pairs ...]   (default 121 241 481)
"""

from __future__ import annotations

import json
import subprocess
import sys

CHILD = """
import json, resource, sys, time
from fretbem.scenes import cattaneo_mindlin
from fretbem.simulation import run
base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
simulation = cattaneo_mindlin(basis="nurbs", pairs=int(sys.argv[1]))
dofs = simulation.pair.upper.dofs + simulation.pair.lower.dofs
start = time.perf_counter()
run(simulation)
seconds = time.perf_counter() - start
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
print(json.dumps({"pairs": int(sys.argv[1]), "dofs": int(dofs), "base_kb": base,
                  "peak_kb": peak, "seconds": seconds}))
"""


def main(sizes: list[int]) -> None:
    for pairs in sizes:
        line = subprocess.run(
            [sys.executable, "-c", CHILD, str(pairs)], capture_output=True, text=True, check=True
        ).stdout.strip()
        row = json.loads(line)
        arrays = (row["peak_kb"] - row["base_kb"]) * 1024 / (8 * row["dofs"] ** 2)
        print(json.dumps({**row, "dense_arrays": round(arrays, 2)}))


if __name__ == "__main__":
    main([int(a) for a in sys.argv[1:]] or [121, 241, 481])
