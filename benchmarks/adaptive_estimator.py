"""The adaptive mode on scene variants: true errors, the estimate and their ratio (issue 12).

For each variant (P, R, f, zone) runs the adaptive mode at a budget and a converged
adaptive reference at a large budget, and reports per variant the max over the cycle of

- the error against half-plane theory (discretisation + finite-body modelling),
- the error against the converged BEM reference (discretisation only),
- the two-level estimate, and its ratio to both,
- the wall time of all levels.

Writes docs/results/adaptive_estimator.csv.

    python benchmarks/adaptive_estimator.py [--budget 61] [--reference 161]
"""

from __future__ import annotations

import argparse
import csv
import platform
from pathlib import Path

from fretbem import adaptive, estimate
from fretbem.scenes import cattaneo_mindlin

OUT = Path(__file__).resolve().parents[1] / "docs" / "results"
KEYS = ("e_p_max", "e_q_max", "e_p_l2", "e_q_l2")

#: (label, scene overrides); tangential loads are 0.6 f P as in the reference scene
VARIANTS = (
    ("reference", {}),
    ("P=60", {"normal": 60.0}),
    ("P=250", {"normal": 250.0}),
    ("R=35", {"radius": 35.0}),
    ("R=140", {"radius": 140.0}),
    ("f=0.5", {"friction": 0.5}),
    ("zone=1.3", {"zone": 1.3}),
    ("zone=2.0", {"zone": 2.0}),
)


def scene(overrides: dict):
    load = overrides.get("normal", 100.0)
    q = 0.6 * overrides.get("friction", 0.3) * load
    return cattaneo_mindlin(pairs=31, tangential=(0.0, q, 0.0, -q, 0.0), **overrides)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--budget", type=int, default=61)
    parser.add_argument("--reference", type=int, default=161)
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args()
    rows = []
    for label, overrides in VARIANTS:
        out = adaptive.run_adaptive(scene(overrides), adaptive.AdaptiveSettings(budget=args.budget))
        ref = adaptive.run_adaptive(  # no early stop: the reference uses the whole budget
            scene(overrides),
            adaptive.AdaptiveSettings(budget=args.reference, tolerance=1e-9, max_levels=4),
        )
        result = out.result
        versus_bem = estimate.difference(result, ref.result, at="coarse")
        row = {"variant": label, "pairs": result.steps[0].x.size, "seconds": out.seconds}
        for key in KEYS:
            true = max(s.errors[key] for s in result.steps)
            bem = max(d[key[2:]] for d in versus_bem)
            est = max(e[key] for e in out.estimate.values())
            row |= {
                f"halfplane_{key}": true,
                f"bem_{key}": bem,
                f"estimate_{key}": est,
                f"ratio_halfplane_{key}": est / true if true > 1e-3 else None,
                f"ratio_bem_{key}": est / bem if bem > 1e-3 else None,
            }
        rows.append(row)
        print(
            f"{label:10s} pairs {row['pairs']:3d}  true p {100 * row['halfplane_e_p_max']:5.2f} "
            f"q {100 * row['halfplane_e_q_max']:5.2f} qL2 {100 * row['halfplane_e_q_l2']:5.2f} | "
            f"vs BEM p {100 * row['bem_e_p_max']:5.2f} q {100 * row['bem_e_q_max']:5.2f} | est p "
            f"{100 * row['estimate_e_p_max']:5.2f} q {100 * row['estimate_e_q_max']:5.2f} "
            f"| {out.seconds:5.2f} s",
            flush=True,
        )
    args.out.mkdir(parents=True, exist_ok=True)
    with open(args.out / "adaptive_estimator.csv", "w", newline="") as handle:
        handle.write(f"# {platform.node()} {platform.processor()} (shared machine)\n")
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


if __name__ == "__main__":
    main()
