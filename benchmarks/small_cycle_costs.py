"""Where the small cycles and the demo's figures spend their time (issue 28 items 3 and 4).

In one process, one BLAS thread, CPU seconds, medians of ``--rounds`` interleaved rounds:

- the reference cycle at 61 and 481 pairs, BEM bodies and half-plane bodies, split into the
  scene build (cold: the geometry cache cleared first), ``prepare`` (assembly,
  factorisation, condensation; for half-planes the influence coefficients), the five steps,
  and inside the steps the Newton iterations (their count and CPU per iteration); beside
  them the numpy Toeplitz peer (``benchmarks/halfplane_peer.py``) of the same cycle;
- the fixed price of a matplotlib Axes on the Agg canvas: a figure of 17 empty axes (the
  demo's three PNGs hold 17) drawn to PNG, with ticks and tick labels as matplotlib makes
  them, and without ticks, against one axes.

    OPENBLAS_NUM_THREADS=1 python benchmarks/small_cycle_costs.py --rounds 3 \\
        --json docs/results/small_cycle_costs.json
"""

from __future__ import annotations

import argparse
import io
import json
import os
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import halfplane_peer
from cold_caches import clear_scene_caches

from fretbem.scenes import reference as scenes
from fretbem.simulation import run
from fretbem.solvers import newton

MODELS = {"bem": {}, "halfplane": {"upper": "half-plane", "lower": "half-plane"}}
_newton = {"seconds": 0.0, "iterations": 0}
_solve_increment = newton.SemiSmoothNewton.solve_increment


def _timed_increment(self, *args, **kwargs):
    start = time.process_time()
    try:
        result = _solve_increment(self, *args, **kwargs)
        _newton["iterations"] += result.iterations
        return result
    finally:
        _newton["seconds"] += time.process_time() - start


def cycle(pairs: int, models: dict) -> dict:
    """CPU seconds of one cold cycle by phase, and its Newton iterations."""
    clear_scene_caches()  # cold: no shape, grading or refinement operator kept
    start = time.process_time()
    simulation = scenes.cattaneo_mindlin(pairs=pairs, models=models)
    built = time.process_time()
    simulation.prepare()
    prepared = time.process_time()
    _newton.update(seconds=0.0, iterations=0)
    run(simulation)
    done = time.process_time()
    return {
        "build": built - start,
        "prepare": prepared - built,
        "steps": done - prepared,
        "newton": _newton["seconds"],
        "iterations": _newton["iterations"],
        "total": done - start,
    }


def peer(pairs: int) -> float:
    start = time.process_time()
    halfplane_peer.cycle(pairs)
    return time.process_time() - start


def axes_figure(n_axes: int, ticks: bool) -> float:
    """CPU seconds to draw a figure of ``n_axes`` empty axes (titled) to PNG."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    start = time.process_time()
    fig = Figure(figsize=(14.0, 7.0))
    FigureCanvasAgg(fig)
    for ax in fig.subplots(1, n_axes, squeeze=False)[0]:
        ax.set_title("step B: P = 100, Q = 18 N/mm")
        if not ticks:
            ax.set_xticks([])
            ax.set_yticks([])
    fig.savefig(io.BytesIO(), format="png", dpi=100, pil_kwargs={"compress_level": 1})
    return time.process_time() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()
    newton.SemiSmoothNewton.solve_increment = _timed_increment
    load = [os.getloadavg()[0]]
    for pairs in (61, 481):  # imports, compiled loops, numba's choice: on another pad
        for models in MODELS.values():
            run(scenes.cattaneo_mindlin(pairs=pairs, models=models, radius=71.0))
        peer(pairs)
    axes_figure(1, True)
    rounds: dict[str, list] = {}
    for k in range(args.rounds):
        for pairs in (61, 481):
            for name, models in MODELS.items():
                rounds.setdefault(f"{name}_{pairs}", []).append(cycle(pairs, models))
            rounds.setdefault(f"peer_{pairs}", []).append(peer(pairs))
        for key, (n_axes, ticks) in {"axes_1": (1, True), "axes_17": (17, True),
                                     "axes_17_no_ticks": (17, False)}.items():  # fmt: skip
            rounds.setdefault(key, []).append(axes_figure(n_axes, ticks))
        print(f"round {k + 1} done, load {os.getloadavg()[0]:.2f}", flush=True)
    load.append(os.getloadavg()[0])

    def median(values):
        if isinstance(values[0], dict):
            return {key: statistics.median(v[key] for v in values) for key in values[0]}
        return statistics.median(values)

    result = {"load": load, "rounds": args.rounds}
    result.update({key: median(values) for key, values in rounds.items()})
    for pairs in (61, 481):
        for name in MODELS:
            c = result[f"{name}_{pairs}"]
            print(f"{name:9s} {pairs:3d} pairs: build {c['build'] * 1e3:6.1f} ms, prepare "
                  f"{c['prepare'] * 1e3:6.1f} ms, steps {c['steps'] * 1e3:6.1f} ms ("
                  f"{c['iterations']:.0f} Newton iterations, "
                  f"{c['newton'] / c['iterations'] * 1e6:.0f} us each), total "
                  f"{c['total'] * 1e3:6.1f} ms = {c['total'] / result[f'peer_{pairs}']:.1f}x "
                  f"the peer ({result[f'peer_{pairs}'] * 1e3:.2f} ms)")  # fmt: skip
    print({k: round(result[k], 3) for k in ("axes_1", "axes_17", "axes_17_no_ticks")})
    if args.json:
        args.json.write_text(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
