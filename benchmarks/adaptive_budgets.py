"""The adaptive mode at budgets 31 to 241 on several scenes, against a converged solution.

For each scene: the converged reference (:func:`fretbem.accuracy.converged.reference`, the
adaptive mode at 321 pairs without early stop) and its resolution
(:func:`fretbem.accuracy.converged.resolution`: a second converged solution, 281 pairs,
against it), then the adaptive mode at every budget of the list with a tolerance no
estimate meets (so each budget is spent), its errors against the reference
(:func:`fretbem.accuracy.converged.errors_against`: max everywhere, max away from the
transitions, L2), its estimate and its time, and how far each error away from the
transitions and in L2 rises above the best smaller budget's ("rise_*"; the band is twice
the resolution, "band_far" and "band_l2"). Writes docs/results/adaptive_budgets.csv (the
machine's load average is a column).

    python benchmarks/adaptive_budgets.py [--scenes ref100 wide ...] [--budgets 31 41 ...]
"""

from __future__ import annotations

import argparse
import csv
import os
import time
from pathlib import Path

from fretbem.accuracy import adaptive, converged
from fretbem.scenes.builder import build
from fretbem.scenes.file import load_scene
from fretbem.scenes.reference import cattaneo_mindlin

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "results" / "adaptive_budgets.csv"
BUDGETS = (31, 36, 41, 51, 61, 71, 83, 101, 121, 161, 201, 241)


def reference_scene(load: float):
    """The reference cycle at normal load ``load`` (Q = 0.6 f P)."""
    q = 0.18 * load
    return cattaneo_mindlin(pairs=31, normal=load, tangential=(0.0, q, 0.0, -q, 0.0))


def from_file(name: str):
    return build(load_scene(ROOT / "examples" / name))[0]


SCENES = {
    "ref60": lambda: reference_scene(60.0),
    "ref100": lambda: reference_scene(100.0),
    "ref160": lambda: reference_scene(160.0),
    "wide": lambda: from_file("adaptive_wide_contact.toml"),
    "dissimilar": lambda: from_file("adaptive_dissimilar.toml"),
    "rig": lambda: from_file("fretting_rig.toml"),
    "mixed": lambda: from_file("mismatched_faces.toml"),
}


def study(name: str, budgets) -> list[dict]:
    simulation = SCENES[name]()
    tic = time.perf_counter()
    best = converged.reference(simulation)
    known = converged.resolution(simulation, best)
    band_far = 2 * max(known["p_far"], known["q_far"])
    band_l2 = 2 * max(known["p_l2"], known["q_l2"])
    print(f"{name}: reference {best.result.steps[0].x.size} pairs, "
          f"{time.perf_counter() - tic:.1f} s; band away {100 * band_far:.3f} %, "
          f"L2 {100 * band_l2:.3f} %", flush=True)  # fmt: skip
    rows = []
    for budget in budgets:
        tic = time.perf_counter()
        out = adaptive.run_adaptive(
            simulation, adaptive.AdaptiveSettings(budget=budget, tolerance=1e-9)
        )
        seconds = time.perf_counter() - tic
        error = converged.errors_against(out.result, best)
        est = {k: max(e[k] for e in out.estimate.values()) for k in ("e_p_max", "e_q_max")}
        row = {
            "scene": name,
            "budget": budget,
            "pairs": out.result.steps[0].x.size,
            "pairing": type(out.result.simulation.pair).__name__,
            **{k: round(100 * v, 4) for k, v in error.items()},
            "est_p_max": round(100 * est["e_p_max"], 4),
            "est_q_max": round(100 * est["e_q_max"], 4),
            **{f"rise_{k}": 0.0 for k in ("p_far", "q_far", "p_l2", "q_l2")},
            "band_far": round(100 * band_far, 4),
            "band_l2": round(100 * band_l2, 4),
            "seconds": round(seconds, 3),
            "notes": " | ".join(out.notes),
            "load": os.getloadavg()[0],
        }
        rows.append(row)
        print(
            f"  {budget:4d} {row['pairs']:4d}  max p {row['p_max']:.3f} q {row['q_max']:.3f}  "
            f"far p {row['p_far']:.3f} q {row['q_far']:.3f}  L2 p {row['p_l2']:.3f} "
            f"q {row['q_l2']:.3f}  est p {row['est_p_max']:.3f} q {row['est_q_max']:.3f}  "
            f"{seconds:.2f} s {'(notes)' if row['notes'] else ''}",
            flush=True,
        )
    for key in ("p_far", "q_far", "p_l2", "q_l2"):
        for i, row in enumerate(rows[1:], start=1):
            row[f"rise_{key}"] = round(max(0.0, row[key] - min(r[key] for r in rows[:i])), 4)
    worst = {k: max(r[f"rise_{k}"] for r in rows) for k in ("p_far", "q_far", "p_l2", "q_l2")}
    print(f"  most rise over a smaller budget (%): {worst}", flush=True)
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", nargs="*", default=list(SCENES), choices=list(SCENES))
    parser.add_argument("--budgets", nargs="*", type=int, default=list(BUDGETS))
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args()
    rows = [row for name in args.scenes for row in study(name, args.budgets)]
    args.out.parent.mkdir(parents=True, exist_ok=True)
    with args.out.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
