"""
Lamé cylinder: elastostatics without contact
============================================

The BEM core on its own: a quarter of a thick cylinder (a = 1, b = 2) under internal
pressure p = 10 (E = 1000, ν = 0.3, plane strain), on rollers along both straight edges,
whose exact solution is Lamé's. This page runs the project's benchmark,
``benchmarks/lame_convergence.py``, at a few levels (elements per segment) for both
families: the radial displacement error on the outer arc, the hoop-stress error on the
left edge (max and L2), and the assembly and solve times.
"""

# %%
# The benchmark's ``run(family, elements)`` solves once and returns the errors and times
# (the full study is ``python benchmarks/lame_convergence.py``).
import runpy
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

# this script's folder (sphinx-gallery runs a script in its folder, without __file__)
HERE = Path(globals().get("__file__", "lame_cylinder_convergence.py")).resolve().parent
benchmark = runpy.run_path(str(HERE.parents[1] / "benchmarks" / "lame_convergence.py"))
FAMILIES = ("nurbs", "lagrange2")
LEVELS = (2, 4, 8, 16)
rows = [benchmark["run"](family, n) for family in FAMILIES for n in LEVELS]

header = (
    f"{'family':<10} {'elements':>8} {'dofs':>5} {'u error':>10} {'hoop max':>10} "
    f"{'hoop L2':>10} {'assembly s':>10} {'solve s':>8}"
)
print(header)
print("-" * len(header))
for r in rows:
    print(
        f"{r['family']:<10} {r['elements']:>8} {r['dofs']:>5} {r['displacement_error']:>10.3e} "
        f"{r['hoop_error_max']:>10.3e} {r['hoop_error_l2']:>10.3e} {r['assembly_s']:>10.3f} "
        f"{r['solve_s']:>8.3f}"
    )

# %%
# Convergence rates: the slope of log(error) against log(h), h = 1 / elements.
RATES = {}
for family in FAMILIES:
    mine = [r for r in rows if r["family"] == family]
    levels = [r["elements"] for r in mine]
    RATES[family] = {
        key: benchmark["rate"](levels, [r[key] for r in mine])
        for key in ("displacement_error", "hoop_error_l2")
    }
    print(
        f"{family:<10} displacement {RATES[family]['displacement_error']:.2f}, "
        f"hoop L2 {RATES[family]['hoop_error_l2']:.2f}"
    )

# %%
fig, axes = plt.subplots(1, 2, figsize=(10, 4), layout="constrained")
for family, marker in zip(FAMILIES, "os", strict=True):
    mine = [r for r in rows if r["family"] == family]
    dofs = np.array([r["dofs"] for r in mine])
    seconds = np.array([r["assembly_s"] + r["solve_s"] for r in mine])
    u_error = [r["displacement_error"] for r in mine]
    hoop_error = [r["hoop_error_l2"] for r in mine]
    for ax, x in zip(axes, (dofs, seconds), strict=True):
        ax.loglog(x, u_error, marker + "-", label=f"{family} $u_r$")
        ax.loglog(x, hoop_error, marker + "--", mfc="none", label=f"{family} hoop L2")
axes[0].set_xlabel("boundary unknowns")
axes[1].set_xlabel("assembly + solve time (s)")
for ax in axes:
    ax.set_ylabel("relative error")
    ax.grid(True, which="both", alpha=0.3)
axes[0].legend(fontsize=8)
