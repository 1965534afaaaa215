"""The cold scene build of small cycles, this tree against another (issue 28 item 3).

CPU milliseconds to build the Simulation from its scene with no geometry cached (the
builder's shape cache and the graded-breakpoint cache cleared before each build, as a
fresh process would find them), medians of ``--builds`` builds per round and of
``--rounds`` rounds; each round runs one process per tree, the trees interleaved, one BLAS
thread. Scenes: the reference scene at 61 pairs (``scenes.reference.cattaneo_mindlin``) and
``examples/cattaneo_mindlin.toml``, each with BEM bodies and with half-plane bodies; beside
them the numpy Toeplitz peer's whole cycle (``benchmarks/halfplane_peer.py``), the yardstick
of the issue's ratios.

    OPENBLAS_NUM_THREADS=1 python benchmarks/scene_build.py --before /tmp/build-before \\
        --rounds 5 --json docs/results/scene_build.json
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

CHILD = r"""
import json, statistics, sys, time
import attrs
sys.path.insert(0, sys.argv[2])
from fretbem.scenes import builder, reference as scenes
from fretbem.scenes.file import load_scene
from fretbem.simulation import run
import halfplane_peer
from cold_caches import clear_scene_caches

builds = int(sys.argv[1])
example = load_scene(sys.argv[3])
HALF = {"upper": "half-plane", "lower": "half-plane"}


def half_planes(scene):
    return attrs.evolve(scene, pad=attrs.evolve(scene.pad, model="half-plane"),
                        specimen=attrs.evolve(scene.specimen, model="half-plane"))


CASES = {
    "reference_bem": lambda: scenes.cattaneo_mindlin(pairs=61),
    "reference_halfplane": lambda: scenes.cattaneo_mindlin(pairs=61, models=HALF),
    "example_bem": lambda: builder.build(example)[0],
    "example_halfplane": lambda: builder.build(half_planes(example))[0],
}


for case in CASES.values():  # imports and first calls
    clear_scene_caches()
    run(case())
out = {}
for name, case in CASES.items():
    times = []
    for _ in range(builds):
        clear_scene_caches()
        start = time.process_time()
        case()
        times.append(time.process_time() - start)
    out[name] = statistics.median(times)
halfplane_peer.cycle(61)
start = time.process_time()
for _ in range(builds):
    halfplane_peer.cycle(61)
out["peer"] = (time.process_time() - start) / builds
print(json.dumps(out))
"""


def _child(tree: Path, builds: int) -> dict:
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1",
               PYTHONPATH=f"{tree / 'framework'}{os.pathsep}{tree / 'plugins'}")  # fmt: skip
    text = subprocess.run(
        [sys.executable, "-c", CHILD, str(builds), str(ROOT / "benchmarks"),
         str(tree / "examples" / "cattaneo_mindlin.toml")],
        env=env, cwd=tree, check=True, capture_output=True, text=True,
    ).stdout  # fmt: skip
    return json.loads(text.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", type=Path, help="another tree (e.g. git archive of main)")
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--builds", type=int, default=15)
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()
    trees = {"after": ROOT} if args.before is None else {"before": args.before, "after": ROOT}
    load = [os.getloadavg()[0]]
    rounds: dict[str, list[dict]] = {name: [] for name in trees}
    for k in range(args.rounds):
        for name, tree in trees.items():
            rounds[name].append(_child(tree, args.builds))
        print(f"round {k + 1} done, load {os.getloadavg()[0]:.2f}", flush=True)
    load.append(os.getloadavg()[0])
    result: dict = {"load": load, "rounds": args.rounds, "builds": args.builds}
    for name, values in rounds.items():
        result[name] = {key: statistics.median(v[key] for v in values) for key in values[0]}
    for key in result["after"]:
        if key == "peer":
            continue
        shown = "  ".join(
            f"{name} {result[name][key] * 1e3:6.2f} ms "
            f"({result[name][key] / result[name]['peer']:.1f}x the peer's cycle)"
            for name in trees
        )
        ratio = (
            f"  after/before {result['after'][key] / result['before'][key]:.2f}"
            if "before" in trees
            else ""
        )
        print(f"{key:20s} {shown}{ratio}")
    print("peer cycle: " + ", ".join(f"{n} {result[n]['peer'] * 1e3:.2f} ms" for n in trees))
    if args.json:
        args.json.write_text(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
