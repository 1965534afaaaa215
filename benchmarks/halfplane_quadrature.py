"""The half-plane influence integrals: accuracy against a converged quadrature and cost
against another source tree's (issue 28 item 3).

Accuracy: ``fretbem.halfplane.influence.surface_integrals`` at the reference scene's nodes
and at random surface points (nurbs degree 2-4 and lagrange2, 21, 61 and 481 pairs, both
faces) with the module's rules, against the same with 30 Gauss-Legendre and Gauss-log points
(16 far): the largest difference of the ln and sign integrals over their largest entry.

Cost: the integrals at the pad's nodes (a fresh discretisation each time, as a cold build
makes it) by this tree's module and by ``--before``'s ``halfplane/influence.py`` loaded from
that tree, alternating in one process; CPU ms, medians.

    OPENBLAS_NUM_THREADS=1 python benchmarks/halfplane_quadrature.py --before /tmp/before
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from pathlib import Path

import numpy as np
from tree_module import tree_module

from fretbem.halfplane import influence
from fretbem.scenes import reference as scenes

MODELS = {"upper": "half-plane", "lower": "half-plane"}
CONVERGED = {"SMOOTH_POINTS": 30, "NEAR_POINTS": 30, "LOG_POINTS": 30, "FAR_POINTS": 16}


def _integrals(face, x, datum, at, rules=None):
    """The ln and sign integrals with ``rules`` (module constants) set for the call."""
    saved = {name: getattr(influence, name) for name in CONVERGED if hasattr(influence, name)}
    try:
        for name, value in (rules or {}).items():
            setattr(influence, name, value)
        result = influence.surface_integrals(face, x, datum, at)
    finally:
        for name, value in saved.items():
            setattr(influence, name, value)
    return result.log, result.sign


def accuracy() -> float:
    """Print each case's relative differences; return the largest."""
    rng = np.random.default_rng(1)
    worst = 0.0
    for basis, degree in (("nurbs", None), ("nurbs", 3), ("nurbs", 4), ("lagrange2", None)):
        for pairs in (21, 61, 481):
            extra = {} if degree is None else {"degree": degree}
            simulation = scenes.cattaneo_mindlin(pairs=pairs, models=MODELS, basis=basis, **extra)
            for body in (simulation.pair.upper, simulation.pair.lower):
                face, datum = body.surface.face, body.datum
                nodes = body.surface.points[:, 0]
                spread = rng.uniform(nodes.min() * 1.2, nodes.max() * 1.2, 200)
                for x, at, where in ((nodes, face.collocation(), "nodes"),
                                     (np.sort(spread), None, "random")):  # fmt: skip
                    exact = _integrals(face, x, datum, at, CONVERGED)
                    rules = _integrals(face, x, datum, at)
                    errors = [np.abs(r - e).max() / np.abs(e).max()
                              for r, e in zip(rules, exact, strict=True)]  # fmt: skip
                    worst = max(worst, *errors)
                    case = f"{basis:9s} degree {degree or 'default':7} {pairs:3d} pairs"
                    print(f"{case} {body.side:5s} {where:6s}: ln {errors[0]:.1e}, "
                          f"sign {errors[1]:.1e}")  # fmt: skip
    print(f"largest: {worst:.2e}")
    return worst


def _module(tree: Path):
    """``halfplane/influence.py`` of ``tree``, loaded beside this tree's fretbem."""
    return tree_module(tree, "fretbem.halfplane.influence", "influence_before")


def cost(before: Path, pairs: int, rounds: int) -> None:
    """Print both trees' median CPU ms at ``pairs``."""
    simulation = scenes.cattaneo_mindlin(pairs=pairs, models=MODELS)
    body = simulation.pair.upper
    face = body.surface.face
    x, at = body.surface.points[:, 0], face.collocation()
    trees = {"before": _module(before), "after": influence}
    seconds: dict[str, list[float]] = {name: [] for name in trees}
    for _ in range(rounds):
        for name, module in trees.items():
            fresh = type(face).discretise(body.face, body.refinement)
            start = time.process_time()
            module.surface_integrals(fresh, x, body.datum, at)
            seconds[name].append(time.process_time() - start)
    text = ", ".join(f"{k} {statistics.median(v) * 1e3:.3f} ms" for k, v in seconds.items())
    print(f"{pairs} pairs: {text} (load {os.getloadavg()[0]:.2f})")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--before", type=Path, help="source tree of the old code (for the cost)")
    parser.add_argument("--rounds", type=int, default=60)
    args = parser.parse_args()
    accuracy()
    if args.before is not None:
        cost(args.before.resolve(), 61, args.rounds)
        cost(args.before.resolve(), 481, max(args.rounds // 6, 3))


if __name__ == "__main__":
    main()
