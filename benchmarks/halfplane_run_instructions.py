"""Instructions executed by the reference cycle's ``run()`` (half-plane bodies), two trees.

A count, not a time: on a machine shared with other work the CPU time of a 3 ms ``run()``
moves by 10-20 % between runs of the same code, while the instructions it executes move by
well under 1 %. Each tree runs two processes under valgrind's callgrind (``PYTHONPATH`` the
tree's ``framework`` and ``plugins``, one BLAS thread, hash seed 0): both build and prepare
``--cycles`` cold scenes of ``--model`` bodies (half-plane, or bem) at ``--pairs`` pairs
after a warm-up run,
one of them runs each too; the difference over the cycles is one ``run()``'s count. Needs
``valgrind`` on the path (minutes: the interpreter runs about 50x slower under it).

    OPENBLAS_NUM_THREADS=1 python benchmarks/halfplane_run_instructions.py \\
        --before /tmp/before --cycles 10
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

from phase_rounds import ROOT, tree_parser, trees_of

CHILD = r"""
import sys
sys.path.insert(0, sys.argv[1])
from fretbem.scenes import reference as scenes
from fretbem.simulation import run
from cold_caches import clear_scene_caches
models = {"upper": sys.argv[5], "lower": sys.argv[5]}
pairs = int(sys.argv[4])
run(scenes.cattaneo_mindlin(pairs=pairs, models=models, radius=71.0))  # imports: another pad
for _ in range(int(sys.argv[3])):
    clear_scene_caches()
    simulation = scenes.cattaneo_mindlin(pairs=pairs, models=models)
    simulation.prepare()
    if sys.argv[2] == "run":
        run(simulation)
"""


def instructions(tree: Path, mode: str, cycles: int, pairs: int, model: str) -> int:
    """Instructions callgrind counts in one process of ``tree`` (``mode`` "run" or "set-up")."""
    path = f"{tree / 'framework'}{os.pathsep}{tree / 'plugins'}"
    # (a fixed hash seed: an import's count moved by ~5 M instructions between seeds)
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", PYTHONHASHSEED="0", PYTHONPATH=path)
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / "callgrind.out"
        command = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}",
                   os.path.realpath(sys.executable), "-c", CHILD,
                   str(ROOT / "benchmarks"), mode, str(cycles), str(pairs), model]  # fmt: skip
        report = subprocess.run(command, env=env, capture_output=True, text=True, check=True)
    found = re.search(r"Collected\s*:\s*([\d,]+)", report.stderr)
    if found is None:
        raise SystemExit(f"no instruction count in valgrind's report:\n{report.stderr[-2000:]}")
    return int(found.group(1).replace(",", ""))


def main() -> None:
    parser = tree_parser(__doc__.splitlines()[0], rounds=1)
    parser.add_argument("--pairs", type=int, default=61)
    parser.add_argument("--model", choices=("half-plane", "bem"), default="half-plane")
    args = parser.parse_args()
    counts = {}
    for name, tree in trees_of(args).items():
        counts[name] = [
            (instructions(tree, "run", args.cycles, args.pairs, args.model)
             - instructions(tree, "set-up", args.cycles, args.pairs, args.model)) / args.cycles
            for _ in range(args.rounds)
        ]  # fmt: skip
        print(f"{name:6s} {args.model} {args.pairs} pairs: run() "
              + ", ".join(f"{c / 1e6:.2f}" for c in counts[name]) + " M instructions",
              flush=True)  # fmt: skip
    before, after = min(counts["before"]), min(counts["after"])
    print(f"after / before: {after / before:.3f} ({(after - before) / 1e6:+.2f} M a run)")


if __name__ == "__main__":
    main()
