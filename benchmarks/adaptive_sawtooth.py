"""Error against pair count: the fixed-pairs sawtooth beside the adaptive mode (issue 12).

Runs the reference Cattaneo-Mindlin cycle with ``pairs = N`` (uniform zone) and with the
adaptive mode at budget N, for every N in the range (odd N only for quadratic Lagrange,
whose faces hold odd pair counts), and writes docs/results/sawtooth[_<basis>].csv and .png:
max over steps of e_p max, e_q max and e_q L2 against the closed form, the adaptive
estimate and its ratio to the true error, the error against a converged BEM reference (the
discretisation alone, without the finite bodies' departure from half-plane theory), and
the whole-cycle time of every level.

    python benchmarks/adaptive_sawtooth.py [--first 31] [--last 121] [--basis nurbs] [--P 100]
    python benchmarks/adaptive_sawtooth.py --timing [--repeats 5] [--budget 61]
"""

from __future__ import annotations

import argparse
import csv
import os
import platform
import statistics
import time
from pathlib import Path

from fretbem.accuracy import adaptive, estimate
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run

OUT = Path(__file__).resolve().parents[1] / "docs" / "results"
KEYS = ("e_p_max", "e_q_max", "e_p_l2", "e_q_l2")
#: the converged BEM reference: adaptive at this budget, no early stop
REFERENCE_BUDGET = 161


def worst(steps) -> dict[str, float]:
    """Max over steps of each error (fractions)."""
    return {k: max(s.errors[k] for s in steps) for k in KEYS}


def scene(pairs: int, basis: str, load: float, **overrides):
    q = 0.18 * load
    return cattaneo_mindlin(
        pairs=pairs, basis=basis, normal=load, tangential=(0.0, q, 0.0, -q, 0.0), **overrides
    )


def reference(simulation):
    """A converged adaptive BEM solution of the same scene (the discretisation reference)."""
    settings = adaptive.AdaptiveSettings(budget=REFERENCE_BUDGET, tolerance=1e-9, max_levels=4)
    return adaptive.run_adaptive(simulation, settings).result


def versus(result, ref) -> dict[str, float]:
    """Max over steps of the error against ``ref`` at the result's own points."""
    change = estimate.difference(result, ref, at="coarse")
    return {k: max(d[k[2:]] for d in change) for k in KEYS}


def ratio(estimated: float, true: float) -> float | None:
    """Estimate over true error where the true error is above 0.1 %."""
    return estimated / true if true > 1e-3 else None


def sweep(first: int, last: int, basis: str, load: float) -> list[dict]:
    rows = []
    step = 2 if basis == "lagrange2" else 1
    ref = reference(scene(31, basis, load))
    for n in range(first, last + 1, step):
        tic = time.perf_counter()
        fixed = run(scene(n, basis, load))
        fixed_seconds = time.perf_counter() - tic
        out = adaptive.run_adaptive(scene(n, basis, load), adaptive.AdaptiveSettings(budget=n))
        true, bem = worst(out.result.steps), versus(out.result, ref)
        est = {k: max(e[k] for e in out.estimate.values()) for k in KEYS}
        rows.append(
            {
                "pairs": n,
                "basis": basis,
                "P": load,
                **{f"fixed_{k}": v for k, v in worst(fixed.steps).items()},
                "fixed_seconds": fixed_seconds,
                "adaptive_pairs": out.result.steps[0].x.size,
                "levels": "/".join(str(r.steps[0].x.size) for r in out.levels),
                **{f"adaptive_{k}": v for k, v in true.items()},
                **{f"bem_{k}": v for k, v in bem.items()},
                **{f"estimate_{k}": v for k, v in est.items()},
                **{f"ratio_{k}": ratio(est[k], true[k]) for k in KEYS},
                **{f"ratio_bem_{k}": ratio(est[k], bem[k]) for k in KEYS},
                "adaptive_seconds": out.seconds,
                "load": os.getloadavg()[0],
            }
        )
        r = rows[-1]
        print(
            f"{n:4d} fixed p {100 * r['fixed_e_p_max']:5.2f} q {100 * r['fixed_e_q_max']:5.2f} | "
            f"adaptive {r['adaptive_pairs']:3d} p {100 * true['e_p_max']:4.2f} q "
            f"{100 * true['e_q_max']:4.2f} qL2 {100 * true['e_q_l2']:4.2f} | BEM p "
            f"{100 * bem['e_p_max']:4.2f} q {100 * bem['e_q_max']:4.2f} | est p "
            f"{100 * est['e_p_max']:4.2f} q {100 * est['e_q_max']:4.2f} | {out.seconds:5.2f} s",
            flush=True,
        )
    return rows


def timing(budget: int, repeats: int, basis: str) -> None:
    """Median whole-cycle times, fixed pairs and adaptive, interleaved in one process."""
    fixed_s, adaptive_s, loads = [], [], []
    run(scene(budget, basis, 100.0))  # warm up (compiled kernels, caches)
    for _ in range(repeats):
        loads.append(os.getloadavg()[0])
        tic = time.perf_counter()
        run(scene(budget, basis, 100.0))
        fixed_s.append(time.perf_counter() - tic)
        tic = time.perf_counter()
        out = adaptive.run_adaptive(
            scene(budget, basis, 100.0), adaptive.AdaptiveSettings(budget=budget)
        )
        adaptive_s.append(time.perf_counter() - tic)
    levels = "/".join(str(r.steps[0].x.size) for r in out.levels)
    print(
        f"{basis} budget {budget}: fixed {statistics.median(fixed_s):.3f} s, adaptive "
        f"{statistics.median(adaptive_s):.3f} s (levels {levels}; median of {repeats}, "
        f"load {min(loads):.1f} to {max(loads):.1f})"
    )


def figure(rows: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = [r["pairs"] for r in rows]
    fig, axes = plt.subplots(1, 3, figsize=(14, 4))
    for ax, key, label in zip(axes, ("e_p_max", "e_q_max"), ("p", "q"), strict=False):
        ax.semilogy(n, [100 * r[f"fixed_{key}"] for r in rows], "o-", ms=3, label="fixed pairs")
        ax.semilogy(n, [100 * r[f"adaptive_{key}"] for r in rows], "s-", ms=3, label="adaptive")
        ax.semilogy(
            n, [100 * r[f"bem_{key}"] for r in rows], ":", lw=1, label="adaptive vs converged BEM"
        )
        ax.semilogy(
            n, [100 * r[f"estimate_{key}"] for r in rows], "--", lw=1, label="adaptive estimate"
        )
        ax.axhline(1.0 if label == "p" else 2.0, color="k", lw=0.6, ls=":", label="target")
        ax.set_xlabel("pairs (fixed) / pair budget (adaptive)")
        ax.set_title(f"max over the cycle of e_{label} max (%)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("error, % of p0 (p) or f p0 (q)")
    axes[0].legend(fontsize=8)
    ax = axes[2]
    ax.semilogy(
        [r["fixed_seconds"] for r in rows],
        [100 * r["fixed_e_q_max"] for r in rows],
        "o",
        ms=3,
        label="fixed pairs",
    )
    ax.semilogy(
        [r["adaptive_seconds"] for r in rows],
        [100 * r["adaptive_e_q_max"] for r in rows],
        "s",
        ms=3,
        label="adaptive (all levels)",
    )
    ax.set_xlabel("whole-cycle wall time, s (shared machine, single runs)")
    ax.set_title("e_q max (%) against time")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.suptitle(f"Reference scene, {rows[0]['basis']}, P = {rows[0]['P']:g} N/mm")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _number(value: str):
    return None if value == "" else float(value)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--first", type=int, default=31)
    parser.add_argument("--last", type=int, default=121)
    parser.add_argument("--basis", default="nurbs")
    parser.add_argument("--P", type=float, default=100.0)
    parser.add_argument("--out", type=Path, default=OUT)
    parser.add_argument("--replot", action="store_true", help="redraw from the CSV")
    parser.add_argument("--timing", action="store_true", help="median times at --budget")
    parser.add_argument("--budget", type=int, default=61)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    if args.timing:
        timing(args.budget, args.repeats, args.basis)
        return
    stem = "sawtooth" if args.basis == "nurbs" else f"sawtooth_{args.basis}"
    if args.replot:
        with open(args.out / f"{stem}.csv") as handle:
            lines = [line for line in handle if not line.startswith("#")]
        rows = [
            {k: (v if k in ("basis", "levels") else _number(v)) for k, v in row.items()}
            for row in csv.DictReader(lines)
        ]
        figure(rows, args.out / f"{stem}.png")
        return
    rows = sweep(args.first, args.last, args.basis, args.P)
    args.out.mkdir(parents=True, exist_ok=True)
    with open(args.out / f"{stem}.csv", "w", newline="") as handle:
        handle.write(f"# {platform.node()} {platform.processor()} (shared machine)\n")
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    figure(rows, args.out / f"{stem}.png")


if __name__ == "__main__":
    main()
