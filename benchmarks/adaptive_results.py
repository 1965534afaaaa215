"""The adaptive mode's results of two source trees, compared array by array.

Runs the adaptive mode (default settings, each configuration's budget) on nine
configurations in a fresh process per tree (``PYTHONPATH`` on each tree's framework/ and
plugins/), keeps every level's pair positions, p, q, relative displacements, states and
unknowns, the transitions, the estimate and the notes, and prints how many arrays are
bit-identical and, per configuration and field, the largest difference over that field's
largest value in its level (estimates: in units of p0 and f p0). Integer arrays (states)
and notes must be equal; a different number of levels is reported as missing arrays.

    git archive 8ac34c8 | tar -x -C /tmp/adres-before
    OPENBLAS_NUM_THREADS=1 python benchmarks/adaptive_results.py --before /tmp/adres-before
"""

from __future__ import annotations

import argparse
import collections
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
FIELDS = ("x", "pressure", "shear", "normal_displacement", "tangential_displacement",
          "states", "unknowns")  # fmt: skip


def configurations(root: Path) -> dict:
    """Name -> (simulation factory, budget)."""
    from fretbem.scenes import cattaneo_mindlin
    from fretbem.scenes.builder import build
    from fretbem.scenes.file import load_scene

    def example(name):
        return lambda: build(load_scene(root / "examples" / name))[0]

    half = {"upper": "half-plane", "lower": "half-plane"}
    return {
        "ref61": (lambda: cattaneo_mindlin(pairs=61), 61),
        "ref36": (lambda: cattaneo_mindlin(pairs=61), 36),
        "ref121": (lambda: cattaneo_mindlin(pairs=61), 121),
        "lagrange61": (lambda: cattaneo_mindlin(pairs=61, basis="lagrange2"), 61),
        "halfplane61": (lambda: cattaneo_mindlin(pairs=61, models=half), 61),
        "wide61": (example("adaptive_wide_contact.toml"), 61),
        "dissimilar51": (example("adaptive_dissimilar.toml"), 51),
        "rig61": (example("fretting_rig.toml"), 61),
        "mixed61": (example("mismatched_faces.toml"), 61),
    }


def dump(out: Path, root: Path) -> None:
    """Every array of the adaptive runs of this process's fretbem into ``out`` (npz)."""
    from fretbem.accuracy import adaptive

    arrays = {}
    for name, (make, budget) in configurations(root).items():
        result = adaptive.run_adaptive(make(), adaptive.AdaptiveSettings(budget=budget))
        iterations = [sum(s.iterations for s in level.steps) for level in result.levels]
        print(f"{name}: levels {[lv.steps[0].x.size for lv in result.levels]}, Newton "
              f"iterations {iterations}", flush=True)  # fmt: skip
        for i, level in enumerate(result.levels):
            for step in level.steps:
                for field in FIELDS:
                    arrays[f"{name}/L{i}/{step.name}/{field}"] = np.asarray(getattr(step, field))
        for i, found in enumerate(result.transitions):
            arrays[f"{name}/T{i}/transitions"] = np.asarray(found.all)
        for step, errors in result.estimate.items():
            for key, value in errors.items():
                arrays[f"{name}/est/{step}/{key}"] = np.asarray(value, float)
        arrays[f"{name}/notes"] = np.array(list(result.notes), dtype=str)
    np.savez(out, **arrays)


def compare(before: Path, after: Path) -> float:
    """Print the comparison; returns the largest relative difference."""
    a, b = np.load(before), np.load(after)
    scale: dict = collections.defaultdict(float)
    for key in a:
        if a[key].dtype.kind == "f":
            name, level, *_, field = key.split("/")
            largest = np.abs(a[key]).max(initial=0)
            scale[name, level, field] = max(scale[name, level, field], largest)
    worst: dict = {}
    same = 0
    for key in sorted(set(a) | set(b)):
        if key not in a or key not in b:
            print(f"missing in {'after' if key in a else 'before'}: {key}")
            continue
        x, y = a[key], b[key]
        if x.shape == y.shape and np.array_equal(x, y):
            same += 1
            continue
        if x.shape != y.shape or x.dtype.kind in "iubUS":
            print(f"differs: {key}")
            continue
        name, level, *_, field = key.split("/")
        if level == "est":
            label, size = f"estimate {field}", 1.0
        else:
            label, size = field, max(scale[name, level, field], 1e-300)
        worst[name, label] = max(worst.get((name, label), 0.0), np.abs(x - y).max() / size)
    print(f"{same} of {len(set(a) | set(b))} arrays bit-identical")
    for (name, label), value in sorted(worst.items()):
        print(f"  {name:14s} {label:28s} {value:.2e}")
    return max(worst.values(), default=0.0)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", type=Path, help="source tree of the old code")
    parser.add_argument("--after", type=Path, default=ROOT, help="source tree (this checkout)")
    parser.add_argument("--dump", type=Path, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.dump is not None:
        dump(args.dump, args.after)
        return
    if args.before is None:
        parser.error("give --before TREE (git archive <commit> | tar -x -C TREE)")
    with tempfile.TemporaryDirectory() as tmp:
        files = {}
        for label, tree in (("before", args.before.resolve()), ("after", args.after.resolve())):
            env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
            env["PYTHONPATH"] = f"{tree / 'framework'}{os.pathsep}{tree / 'plugins'}"
            files[label] = Path(tmp) / f"{label}.npz"
            print(f"-- {label} ({tree})", flush=True)
            subprocess.run([sys.executable, __file__, "--dump", str(files[label]),
                            "--after", str(tree)], env=env, check=True, cwd=tree)  # fmt: skip
        largest = compare(files["before"], files["after"])
    print(f"largest difference: {largest:.2e}")


if __name__ == "__main__":
    main()
