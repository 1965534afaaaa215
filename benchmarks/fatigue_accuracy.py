"""How close the critical-plane search comes to a dense search, criterion by criterion.

For each history (contact cycles below a Cattaneo-Mindlin / Nowell-Hills contact at several
loads and depths, random plane-strain histories, random histories with a free sigma_zz) and
each search (in-plane, 3D; compiled and numpy), every parameter of
:data:`fretbem.fatigue.METHODS` (stress_life with no mean-stress correction, Goodman and
Gerber) against a dense reference: in-plane a scan every 0.01 degree in double, 3D the
search itself on a 1 x 1 degree grid with 10 refinement levels. Printed per criterion: the
largest shortfall (reference - found) and overshoot (found - reference) over the largest
reference value of that history, and the largest angle between the found and the reference
normals where the found value is within 1e-9 of the reference (0 unless two planes tie).

Run from the repository root::

    OPENBLAS_NUM_THREADS=1 python benchmarks/fatigue_accuracy.py
    OPENBLAS_NUM_THREADS=1 python benchmarks/fatigue_accuracy.py --points 60 --paths compiled
"""

from __future__ import annotations

import argparse

import numpy as np

from fretbem.fatigue import METHODS, PlaneSearch, critical_plane_parameters
from fretbem.fatigue.mean_stress import MeanStressCorrection
from fretbem.testing.fatigue import contact_stress_history, in_plane_scan, random_stress_history

E, NU = 116000.0, 0.342
KW = {"E": E, "nu": NU, "findley_k": 0.3, "fatemi_socie_k": 0.5, "yield_strength": 941.8}
CORRECTIONS = {
    "none": None,
    "goodman": MeanStressCorrection(name="goodman", limit=900.0),
    "gerber": MeanStressCorrection(name="gerber", limit=900.0),
}


def free_history(n: int, seed: int) -> np.ndarray:
    """Random histories with an independent sigma_zz: critical planes tilted out of plane."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 2 * np.pi, 9)
    a, b = rng.normal(size=(n, 4)) * 100, rng.normal(size=(n, 4)) * 60
    s = a[None] * np.sin(t)[:, None, None] + b[None] * np.cos(3 * t)[:, None, None]
    return s + rng.normal(size=(1, n, 4)) * 50


def histories(n: int) -> dict[str, np.ndarray]:
    out = {}
    for depth, steps in ((0.3, 3), (0.5, 2), (1.0, 4)):
        out[f"contact depth {depth}"] = contact_stress_history(
            n, 11, depth=depth, steps_per_branch=steps, nu=NU
        )
    out["random plane strain"] = random_stress_history(n, 5, nu=NU)
    out["free szz"] = free_history(n, 7)
    return out


def scan_in_plane(stress, mean_stress, step_deg=0.01):
    """Each parameter's maximum and its plane over in-plane planes every ``step_deg``."""
    return in_plane_scan(stress, E=E, nu=NU, step_deg=step_deg, mean_stress=mean_stress)


def dense_3d(stress, mean_stress, methods):
    dense = PlaneSearch(theta_step_deg=1.0, psi_step_deg=1.0, refine_levels=10, compiled=True)
    found = critical_plane_parameters(
        stress, methods=methods, mean_stress=mean_stress, search=dense, **KW
    )
    return {m: r.value for m, r in found.items()}, {m: r.normal for m, r in found.items()}


def normal_of(angle_deg):
    th = np.deg2rad(angle_deg)
    return np.stack([np.cos(th), np.sin(th), 0 * th], -1)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=120, help="points per history")
    parser.add_argument("--paths", nargs="+", default=["compiled", "numpy"])
    args = parser.parse_args()
    worst: dict = {}
    for name, stress in histories(args.points).items():
        for label, correction in CORRECTIONS.items():
            # the corrections change stress_life alone
            methods = METHODS if correction is None else ("stress_life",)
            for in_plane in (True, False):
                if in_plane:
                    ref_value, angle = scan_in_plane(stress, correction)
                    ref_normal = {m: normal_of(a) for m, a in angle.items()}
                else:
                    ref_value, ref_normal = dense_3d(stress, correction, methods)
                for path in args.paths:
                    search = PlaneSearch(in_plane_only=in_plane, compiled=path == "compiled")
                    found = critical_plane_parameters(
                        stress, methods=methods, mean_stress=correction, search=search, **KW
                    )
                    for method, result in found.items():
                        ref = ref_value[method]
                        finite = np.isfinite(ref) & np.isfinite(result.value)
                        scale = np.abs(ref[finite]).max(initial=1e-300)
                        gap = (ref[finite] - result.value[finite]) / scale
                        cos = np.abs((result.normal * ref_normal[method]).sum(-1))
                        turn = np.rad2deg(np.arccos(np.clip(cos, 0.0, 1.0)))
                        same = finite.copy()
                        same[finite] = np.abs(gap) <= 1e-9
                        row = method if correction is None else f"{method} {label}"
                        key = ("in-plane" if in_plane else "3D", path, row)
                        w = worst.setdefault(key, [0.0, 0.0, 0.0])
                        w[0] = max(w[0], gap.max(initial=0.0))
                        w[1] = max(w[1], -gap.min(initial=0.0))
                        w[2] = max(w[2], turn[same].max(initial=0.0))
        print(f"done: {name}", flush=True)
    print(f"{'search':<10}{'path':<10}{'criterion':<22}{'shortfall':>11}{'overshoot':>11}"
          f"{'turn at equal value (deg)':>28}")  # fmt: skip
    for (kind, path, method), (short, over, turn) in sorted(worst.items()):
        print(f"{kind:<10}{path:<10}{method:<22}{short:11.2e}{over:11.2e}{turn:28.2e}")


if __name__ == "__main__":
    main()
