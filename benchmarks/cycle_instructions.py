"""Instructions of a cold scene build and ``prepare``, two source trees, counted by callgrind.

On a loaded machine the CPU times of a 5 ms phase move by 10-20 % between runs; the
instructions executed do not. Each tree runs the reference scene (``--model`` bodies,
``--pairs``) in a fresh process under ``valgrind --tool=callgrind`` twice: with
``--cycles`` cold cycles (scene caches cleared, build then prepare) after the warm-up, and
with none; the difference over the cycles is the instructions per cycle (imports, byte
compilation and the warm-up cancel). The numpy Toeplitz peer (``halfplane_peer.py``) is
counted the same way, for a ratio. Instructions are not time (cache misses are not in
them), so this complements ``halfplane_phases.py``, it does not replace it.

    python benchmarks/cycle_instructions.py --before /tmp/before --pairs 61 --cycles 20
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

CHILD = r"""
import sys
sys.path.insert(0, sys.argv[1])
from fretbem.scenes import reference as scenes
from fretbem.simulation import run
from cold_caches import clear_scene_caches
import halfplane_peer
what, model, pairs, cycles = sys.argv[2], sys.argv[3], int(sys.argv[4]), int(sys.argv[5])
models = {"upper": model, "lower": model}
run(scenes.cattaneo_mindlin(pairs=pairs, models=models, radius=71.0))  # imports: another pad
halfplane_peer.cycle(pairs)
for _ in range(3 + cycles):  # three warm-up cycles, then the counted ones
    if what == "peer":
        halfplane_peer.cycle(pairs)
    else:
        clear_scene_caches()
        scenes.cattaneo_mindlin(pairs=pairs, models=models).prepare()
"""


def instructions(tree: Path, what: str, model: str, pairs: int, cycles: int) -> int:
    """Instructions callgrind collects for the child on ``tree`` (the whole process)."""
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1",
               PYTHONPATH=f"{tree / 'framework'}{os.pathsep}{tree / 'plugins'}")  # fmt: skip
    with tempfile.TemporaryDirectory() as scratch:
        out = subprocess.run(
            ["valgrind", "--tool=callgrind", f"--callgrind-out-file={scratch}/out",
             sys.executable, "-c", CHILD, str(ROOT / "benchmarks"), what, model,
             str(pairs), str(cycles)],
            env=env, capture_output=True, text=True, check=True,
        ).stderr  # fmt: skip
    return int(re.search(r"Collected : (\d+)", out).group(1))


def per_cycle(tree: Path, what: str, model: str, pairs: int, cycles: int) -> float:
    """Instructions of one cycle: the run with ``cycles`` cycles minus the one with none."""
    counted = instructions(tree, what, model, pairs, cycles)
    return (counted - instructions(tree, what, model, pairs, 0)) / cycles


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", type=Path, required=True, help="source tree of the old code")
    parser.add_argument("--after", type=Path, default=ROOT, help="source tree of the new code")
    parser.add_argument("--model", default="half-plane", help="both bodies' model")
    parser.add_argument("--pairs", type=int, default=61)
    parser.add_argument("--cycles", type=int, default=20)
    args = parser.parse_args()
    peer = per_cycle(args.after, "peer", args.model, args.pairs, args.cycles)
    print(f"{args.model} bodies, {args.pairs} pairs, callgrind instructions per cold build + "
          f"prepare ({args.cycles} cycles); the numpy Toeplitz peer's whole cycle: "
          f"{peer / 1e6:.2f} M")  # fmt: skip
    counts = {}
    for name in ("before", "after"):
        counts[name] = per_cycle(getattr(args, name).resolve(), "scene", args.model,
                                 args.pairs, args.cycles)  # fmt: skip
        print(f"{name:6s}: {counts[name] / 1e6:7.2f} M, {counts[name] / peer:.2f} x the peer")
    print(f"after / before: {counts['after'] / counts['before']:.3f}")


if __name__ == "__main__":
    main()
