"""The adaptive mode on scene variants: true errors, the estimate and their ratio (issue 12).

For each variant (P, R, f, zone; the wide contacts also on a body four times larger, where
half-plane theory holds) and each pair budget, runs the adaptive mode, and once per
variant a converged adaptive reference; reports per row the max over the cycle of

- the error against half-plane theory (discretisation + the finite bodies' model error),
- the error against the converged BEM reference (discretisation only),
- the estimate, and its ratio to both (where the error is above 0.1 %),
- the wall time of all levels.

Writes docs/results/adaptive_estimator.csv.

    python benchmarks/adaptive_estimator.py [--budgets 31,35,41,45,51,55,61,81,121]
        [--basis nurbs] [--reference 161]
"""

from __future__ import annotations

import argparse
import csv
import os
import platform
from pathlib import Path

from adaptive_sawtooth import KEYS, ratio, versus, worst

from fretbem.accuracy import adaptive

OUT = Path(__file__).resolve().parents[1] / "docs" / "results"
#: a body four times the reference one (6.5 x 16.25 mm): a / w = 0.02 at P = 250
LARGE = {"width": 26.0, "height": 65.0}

#: (label, scene overrides); tangential loads are 0.6 f P as in the reference scene
VARIANTS = (
    ("reference", {}),
    ("P=60", {"normal": 60.0}),
    ("P=175", {"normal": 175.0}),
    ("P=250", {"normal": 250.0}),
    ("P=175 large", {"normal": 175.0, **LARGE}),
    ("P=250 large", {"normal": 250.0, **LARGE}),
    ("R=35", {"radius": 35.0}),
    ("R=140", {"radius": 140.0}),
    ("R=140 large", {"radius": 140.0, **LARGE}),
    ("f=0.5", {"friction": 0.5}),
    ("zone=1.3", {"zone": 1.3}),
    ("zone=2.0", {"zone": 2.0}),
    ("large", dict(LARGE)),
)


def scene(overrides: dict, basis: str = "nurbs"):
    from fretbem.scenes.reference import cattaneo_mindlin

    load = overrides.get("normal", 100.0)
    q = 0.6 * overrides.get("friction", 0.3) * load
    return cattaneo_mindlin(pairs=31, basis=basis, tangential=(0.0, q, 0.0, -q, 0.0), **overrides)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--budgets", default="31,35,41,45,51,55,61,81,121")
    parser.add_argument("--basis", default="nurbs")
    parser.add_argument("--reference", type=int, default=161)
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args()
    budgets = [int(b) for b in args.budgets.split(",")]
    rows = []
    for label, overrides in VARIANTS:
        settings = adaptive.AdaptiveSettings(budget=args.reference, tolerance=1e-9, max_levels=4)
        ref = adaptive.run_adaptive(scene(overrides, args.basis), settings).result
        for budget in budgets:
            out = adaptive.run_adaptive(
                scene(overrides, args.basis), adaptive.AdaptiveSettings(budget=budget)
            )
            true, bem = worst(out.result.steps), versus(out.result, ref)
            est = {k: max(e[k] for e in out.estimate.values()) for k in KEYS}
            row = {
                "variant": label,
                "basis": args.basis,
                "budget": budget,
                "pairs": out.result.steps[0].x.size,
                "seconds": out.seconds,
                "load": os.getloadavg()[0],
            }
            for key in KEYS:
                row |= {
                    f"halfplane_{key}": true[key],
                    f"bem_{key}": bem[key],
                    f"estimate_{key}": est[key],
                    f"ratio_halfplane_{key}": ratio(est[key], true[key]),
                    f"ratio_bem_{key}": ratio(est[key], bem[key]),
                }
            rows.append(row)
            print(
                f"{label:12s} {budget:3d} pairs {row['pairs']:3d}  half-plane p "
                f"{100 * true['e_p_max']:5.2f} q {100 * true['e_q_max']:5.2f} qL2 "
                f"{100 * true['e_q_l2']:5.2f} | BEM p {100 * bem['e_p_max']:5.2f} q "
                f"{100 * bem['e_q_max']:5.2f} | est p {100 * est['e_p_max']:5.2f} q "
                f"{100 * est['e_q_max']:5.2f} | {out.seconds:5.2f} s",
                flush=True,
            )
    args.out.mkdir(parents=True, exist_ok=True)
    name = (
        "adaptive_estimator.csv"
        if args.basis == "nurbs"
        else f"adaptive_estimator_{args.basis}.csv"
    )
    with open(args.out / name, "w", newline="") as handle:
        handle.write(f"# {platform.node()} {platform.processor()} (shared machine)\n")
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


if __name__ == "__main__":
    main()
