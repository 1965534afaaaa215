"""Two source trees' cycles by phase, interleaved: the driver of bem_phases.py and
halfplane_phases.py (each gives its child script and its phases, the last two being the
cycle's total and the peer's)."""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def tree_parser(description: str, rounds: int = 3) -> argparse.ArgumentParser:
    """The options every two-tree phase benchmark takes: --before, --after, --rounds and
    --cycles (a script adds its own)."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--before", type=Path, required=True, help="source tree of the old code")
    parser.add_argument("--after", type=Path, default=ROOT, help="source tree of the new code")
    parser.add_argument("--rounds", type=int, default=rounds)
    parser.add_argument("--cycles", type=int, default=5)
    return parser


def trees_of(args: argparse.Namespace) -> dict[str, Path]:
    """The two trees of :func:`tree_parser`'s options, by name."""
    return {"before": args.before.resolve(), "after": args.after.resolve()}


def interleaved(child: str, trees: dict[str, Path], rounds: int, args: list[str]) -> tuple:
    """``rounds`` rounds of one fresh process per tree (its ``framework`` and ``plugins`` on
    the path, one BLAS thread) running ``child`` with the benchmarks folder and ``args``;
    returns each tree's rows per pair count (the child's last JSON line) and the load before
    and after."""
    rows: dict[str, dict[str, list]] = {name: {} for name in trees}
    load = [os.getloadavg()[0]]
    for _ in range(rounds):
        for name, tree in trees.items():
            path = f"{tree / 'framework'}{os.pathsep}{tree / 'plugins'}"
            env = dict(os.environ, OPENBLAS_NUM_THREADS="1", PYTHONPATH=path)
            text = subprocess.run(
                [sys.executable, "-c", child, str(ROOT / "benchmarks"), *args],
                env=env, capture_output=True, text=True, check=True,
            ).stdout  # fmt: skip
            for pairs, values in json.loads(text.strip().splitlines()[-1]).items():
                rows[name].setdefault(pairs, []).extend(values)
    load.append(os.getloadavg()[0])
    return rows, load


def rounds_by_pairs(description: str, child: str) -> tuple:
    """Parse :func:`tree_parser`'s options and --pairs (comma-separated pair counts), then
    run ``child`` :func:`interleaved` with ``cycles`` and the pair counts as its arguments;
    returns ``(rows, load, args)``."""
    parser = tree_parser(description)
    parser.add_argument("--pairs", default="61,481", help="comma-separated pair counts")
    args = parser.parse_args()
    rows, load = interleaved(child, trees_of(args), args.rounds, [str(args.cycles), args.pairs])
    return rows, load, args


def medians(rows: dict, phases: tuple[str, ...], rounds: int, cycles: int, load) -> tuple:
    """Print each tree's median phases (CPU ms) and median cycle / peer per pair count;
    returns ``(medians_ms, ratios)`` keyed by tree, then pair count."""
    print(f"load {load[0]:.2f} -> {load[1]:.2f}; CPU ms, medians of "
          f"{rounds} rounds x {cycles} cycles")  # fmt: skip
    table: dict = {name: {} for name in rows}
    ratios: dict = {name: {} for name in rows}
    for pairs in next(iter(rows.values())):
        for name in rows:
            values = rows[name][pairs]
            ms = [statistics.median(v[i] for v in values) * 1e3 for i in range(len(phases))]
            ratio = statistics.median(v[-2] / v[-1] for v in values)
            text = ", ".join(f"{p} {m:6.1f}" for p, m in zip(phases, ms, strict=True))
            print(f"{name:6s} {pairs:>3s} pairs: {text}; cycle / peer {ratio:.2f}")
            table[name][pairs] = dict(zip(phases, ms, strict=True))
            ratios[name][pairs] = ratio
    return table, ratios
