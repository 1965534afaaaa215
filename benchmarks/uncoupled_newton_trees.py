"""Every Newton increment of a matrix of half-plane runs in two source trees, compared.

The lean uncoupled iteration (``fretbem.solvers.newton_uncoupled``) must give the general
iteration's unknowns to round-off (1e-10 of p_max at most) in as many iterations or fewer.
Each tree runs the same cases in a process of its own (``PYTHONPATH`` its ``framework`` and
``plugins``): the half-plane reference cycle (nurbs and lagrange2; 21, 41, 61, 75 pairs at
four loads, one and three increments each; 241 and 481 pairs), a flat specimen,
dissimilar materials, BEM and mixed bodies, a Q ramp, delta-driven cycles (partial slip;
to gross slip over three increments), approach-driven steps, and the example scenes with
half-plane bodies run by the command line (fretting cycles: partial slip, gross slip,
stick; the rounded-flat pad). It records every increment's unknowns, states and
iterations, then prints each case whose numbers differ, by how much.

    OPENBLAS_NUM_THREADS=1 python benchmarks/uncoupled_newton_trees.py --before /tmp/before
"""

from __future__ import annotations

import argparse
import os
import pickle
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]

CHILD = r"""
import attrs, contextlib, io, os, pickle, sys, tempfile
from fretbem.app import cli
from fretbem.scenes import reference as scenes
from fretbem.simulation import LoadStep, run
from fretbem.solvers import newton

tree, out_path = sys.argv[1], sys.argv[2]
HP = {"upper": "half-plane", "lower": "half-plane"}
records, current = {}, []
solve = newton.SemiSmoothNewton.solve_increment

def recorded(self, problem, law, **kwargs):
    result = solve(self, problem, law, **kwargs)
    current.append((result.x.copy(), result.states.copy(), result.iterations, problem.n_pairs))
    return result

newton.SemiSmoothNewton.solve_increment = recorded

def case(name, build):
    current.clear()
    try:
        build()
        records[name] = list(current)
    except Exception as error:
        records[name] = f"{type(error).__name__}: {error}"

def cycle(basis, pairs, **kwargs):
    return lambda: run(scenes.cattaneo_mindlin(basis=basis, pairs=pairs, models=HP, **kwargs))

def driven(basis, pairs, steps, **kwargs):
    simulation = scenes.cattaneo_mindlin(basis=basis, pairs=pairs, models=HP, **kwargs)
    return lambda: run(attrs.evolve(simulation, steps=steps))

def displaced(delta, increments):
    return (LoadStep("A", normal=100.0),
            *(LoadStep(name, normal=100.0, delta=sign * delta, increments=increments)
              for name, sign in zip("BCDE", (1.0, 0.0, -1.0, 0.0))))

approached = (LoadStep("A", normal=None, approach=0.004),
              LoadStep("B", normal=None, approach=0.004, tangential=10.0),
              LoadStep("C", normal=None, approach=0.004, delta=-0.001))
for basis in ("nurbs", "lagrange2"):
    for pairs in (21, 41, 61, 75, 241, 481):
        small = pairs < 241
        loads = [(100.0, 18.0)]
        if small:
            loads += [(50.0, 9.0), (100.0, 27.0), (200.0, 50.0)]
        for normal, tangential in loads:
            for increments in ((1, 3) if small else (1,)):
                case(f"reference {basis} {pairs} P={normal} Q={tangential} x{increments}",
                     cycle(basis, pairs, normal=normal, increments=increments,
                           tangential=(0.0, tangential, 0.0, -tangential, 0.0)))
        case(f"flat specimen {basis} {pairs}", cycle(basis, pairs, lower="flat"))
        case(f"dissimilar {basis} {pairs}", cycle(basis, pairs, E_lower=200000.0, nu_lower=0.3))
        if pairs > 61:
            continue
        case(f"BEM bodies {basis} {pairs}",
             lambda: run(scenes.cattaneo_mindlin(basis=basis, pairs=pairs)))
        case(f"BEM pad on a half-plane {basis} {pairs}", lambda: run(scenes.cattaneo_mindlin(
            basis=basis, pairs=pairs, models={"lower": "half-plane"})))
        ramp = (0.0, 10.0, 25.0, -25.0, 25.0)
        case(f"Q ramp {basis} {pairs}",
             cycle(basis, pairs, tangential=ramp, names=tuple("ABCDE"), increments=2))
        case(f"delta partial slip {basis} {pairs}", driven(basis, pairs, displaced(0.0015, 1)))
        case(f"delta gross slip x3 {basis} {pairs}", driven(basis, pairs, displaced(0.004, 3)))
        case(f"approach {basis} {pairs}", driven(basis, pairs, approached))
examples = ("rounded_flat_half_plane", "gross_sliding", "gross_sliding_rotating",
            "fretting_wear_sliding", "fretting_partial_slip", "fretting_gross_slip",
            "fretting_stick", "cattaneo_mindlin", "tilted_pad")
for example in examples:
    text = open(os.path.join(tree, "examples", example + ".toml")).read()
    if "half-plane" not in text:  # the scene with both bodies half-planes
        text = text.replace("[pad]\n", '[pad]\nmodel = "half-plane"\n', 1)
        text = text.replace("[specimen]\n", '[specimen]\nmodel = "half-plane"\n', 1)
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, example + ".toml")
        open(path, "w").write(text)
        def command():
            quiet = io.StringIO()
            with contextlib.redirect_stdout(quiet), contextlib.redirect_stderr(quiet):
                if cli.main(["run", path, "--out", os.path.join(folder, "out")]):
                    raise RuntimeError("the command failed")
        case(f"scene file {example}", command)
pickle.dump(records, open(out_path, "wb"))
"""


def _records(tree: Path, folder: str, label: str) -> dict:
    """The tree's cases run in a process of its own."""
    path = os.path.join(folder, label + ".pkl")
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1",
               PYTHONPATH=f"{tree / 'framework'}{os.pathsep}{tree / 'plugins'}")  # fmt: skip
    subprocess.run([sys.executable, "-c", CHILD, str(tree), path], env=env, check=True)
    with open(path, "rb") as handle:
        return pickle.load(handle)


def compare(before: dict, after: dict) -> None:
    """Print each case whose unknowns, states or iterations differ, and the largest."""
    worst, identical = 0.0, 0
    for name, old in before.items():
        new = after.get(name)
        if isinstance(old, str) or isinstance(new, str):
            print(f"{name}: {old if isinstance(old, str) else 'ran'} / "
                  f"{new if isinstance(new, str) else 'ran'}")  # fmt: skip
            continue
        if len(old) != len(new):
            print(f"{name}: {len(old)} increments before, {len(new)} after")
            continue
        pairs = old[0][3]
        scale = max(np.abs(x[:pairs]).max() for x, *_ in old)
        moved = max(np.abs(a[0] - b[0]).max() for a, b in zip(old, new, strict=True)) / scale
        states = all(np.array_equal(a[1], b[1]) for a, b in zip(old, new, strict=True))
        iterations = [a[2] for a in old], [b[2] for b in new]
        worst = max(worst, moved)
        if moved == 0.0 and iterations[0] == iterations[1]:
            identical += 1
            continue
        fewer = (
            ""
            if iterations[0] == iterations[1]
            else (
                f" (fewer in {sum(a > b for a, b in zip(*iterations, strict=True))} increments)"
                if sum(iterations[1]) < sum(iterations[0])
                else "  MORE: " + str(iterations)
            )
        )
        print(f"{name}: unknowns within {moved:.1e} of p_max, states "
              f"{'equal' if states else 'DIFFER'}, iterations {sum(iterations[0])} -> "
              f"{sum(iterations[1])}{fewer}")  # fmt: skip
    print(f"{len(before)} cases, {identical} bit-identical; unknowns within {worst:.1e} of p_max")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", type=Path, required=True)
    parser.add_argument("--after", type=Path, default=ROOT)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        before = _records(args.before.resolve(), folder, "before")
        after = _records(args.after.resolve(), folder, "after")
    compare(before, after)


if __name__ == "__main__":
    main()
