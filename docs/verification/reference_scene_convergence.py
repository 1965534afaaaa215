"""
Reference scene: error against theory and against time
======================================================

Both built-in families on the reference Cattaneo–Mindlin scene at increasing numbers of
node pairs in the contact zone. Every run is compared with half-plane theory (Hertz
pressure, Mindlin–Deresiewicz shear) at every step; the table and the figures give the
largest error over the steps B–E (the tangential part of the cycle) and the wall time of
the whole run (assembly, factorisation, condensation and the five steps). The numbers
below were computed while this page was built, on the machine that built it.

The scene's bodies are finite (width ≈ 20 a) while the theory is for half-planes: at the
finest levels part of what remains is that difference, not discretisation error (see
:doc:`/theory`). The last section runs the adaptive mode at a few pair budgets beside the
fixed pairs.
"""

# %%
# The study
# ---------
import time

import matplotlib.pyplot as plt

from fretbem.accuracy.adaptive import AdaptiveSettings, run_adaptive
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run

FAMILIES = ("nurbs", "lagrange2")
LEVELS = (11, 21, 31, 41, 61, 81)  # odd, so lagrange2 can place them too
KEYS = ("e_p_l2", "e_q_l2", "e_p_max", "e_q_max")
STEPS = ("B", "C", "D", "E")

REPEATS = 2  # the time of a run is the fastest of these (other work on the machine adds noise)


def timed_run(family: str, pairs: int):
    """Result of one run and its wall time (the fastest of REPEATS fresh runs)."""
    times = []
    for _ in range(REPEATS):
        simulation = cattaneo_mindlin(basis=family, pairs=pairs)  # fresh: nothing cached
        start = time.perf_counter()
        result = run(simulation)
        times.append(time.perf_counter() - start)
    return result, min(times)


rows = []
for family in FAMILIES:
    for pairs in LEVELS:
        result, seconds = timed_run(family, pairs)
        row = {"family": family, "pairs": pairs, "dofs": result.describe()["dofs"]}
        row.update({k: max(result[s].errors[k] for s in STEPS) for k in KEYS})
        row.update(seconds=seconds, iterations=sum(s.iterations for s in result.steps))
        rows.append(row)

# %%
# The table: errors in percent of p0 (pressure) and f p0 (shear), the largest over steps
# B–E; ``dofs`` counts the boundary unknowns of both bodies.
header = (
    f"{'family':<10} {'pairs':>5} {'dofs':>5} {'e_p L2%':>8} {'e_q L2%':>8} {'e_p max%':>9} "
    f"{'e_q max%':>9} {'Newton':>6} {'time s':>7}"
)
print(header)
print("-" * len(header))
for r in rows:
    print(
        f"{r['family']:<10} {r['pairs']:>5} {r['dofs']:>5} {100 * r['e_p_l2']:>8.3f} "
        f"{100 * r['e_q_l2']:>8.3f} {100 * r['e_p_max']:>9.3f} {100 * r['e_q_max']:>9.3f} "
        f"{r['iterations']:>6} {r['seconds']:>7.2f}"
    )

# %%
# Error against refinement
# ------------------------
#
# Most of the error sits at the contact edges x = ±a, where the pressure falls to zero
# like a square root and the shear has kinks: how the pairs fall with respect to ±a
# moves the error up or down from one level to the next (a pair close to the edge on
# either side is hardest). The trend, not each step, is the convergence.
fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True, layout="constrained")
for ax, kind in zip(axes, ("l2", "max"), strict=True):
    for family, marker in zip(FAMILIES, "os", strict=True):
        mine = [r for r in rows if r["family"] == family]
        pairs = [r["pairs"] for r in mine]
        e_p = [100 * r[f"e_p_{kind}"] for r in mine]
        e_q = [100 * r[f"e_q_{kind}"] for r in mine]
        ax.loglog(pairs, e_p, marker + "-", label=f"{family} $e_p$")
        ax.loglog(pairs, e_q, marker + "--", mfc="none", label=f"{family} $e_q$")
    ax.set_xlabel("node pairs in the contact zone")
    ax.set_title("L2 (root mean square)" if kind == "l2" else "largest pair error")
    ax.grid(True, which="both", alpha=0.3)
axes[0].set_ylabel("error over steps B–E (%)")
axes[0].legend(fontsize=8)

# %%
# Error against time
# ------------------
#
# The cost of an accuracy: each point is one whole run, from building the bodies to the
# last step (filled: pressure, open: shear, labelled with the pairs). The NURBS family
# needs fewer unknowns for the same pairs (the ``dofs`` column: its functions span
# several elements); at these sizes every run takes about a second or less, most of it
# in assembling and factorising the two bodies (see ``result.timings``).
fig, ax = plt.subplots(layout="constrained")
for family, marker in zip(FAMILIES, "os", strict=True):
    mine = [r for r in rows if r["family"] == family]
    seconds = [r["seconds"] for r in mine]
    e_p = [100 * r["e_p_l2"] for r in mine]
    e_q = [100 * r["e_q_l2"] for r in mine]
    (points,) = ax.loglog(seconds, e_p, marker, label=f"{family} $e_p$ L2")
    color = points.get_color()
    ax.loglog(seconds, e_q, marker, mfc="none", color=color, label=f"{family} $e_q$ L2")
    for r, t, e in zip(mine, seconds, e_q, strict=True):
        ax.annotate(str(r["pairs"]), (t, e), xytext=(3, 3), textcoords="offset points", fontsize=7)
ax.set_xlabel("wall time of the run (s)")
ax.set_ylabel("error over steps B–E (%)")
ax.grid(True, which="both", alpha=0.3)
ax.legend(fontsize=8)

# %%
# The adaptive mode
# -----------------
#
# :func:`fretbem.accuracy.adaptive.run_adaptive` solves a first uniform level, finds the contact
# edges and stick–slip boundaries of every step, and solves again on contact faces with
# breakpoints on them, up to a pair budget (:doc:`/explanation/adaptive`). Its time counts
# every level (the fastest of REPEATS runs, as above); its DOFs are the finest level's. A
# tolerance below any estimate lets the budget end every run.
BUDGETS = (41, 61, 81)


def timed_adaptive(family: str, budget: int):
    """Result of one adaptive run and its wall time (the fastest of REPEATS fresh runs)."""
    times = []
    for _ in range(REPEATS):
        simulation = cattaneo_mindlin(basis=family, pairs=budget)
        start = time.perf_counter()
        out = run_adaptive(simulation, AdaptiveSettings(budget=budget, tolerance=1e-6))
        times.append(time.perf_counter() - start)
    return out, min(times)


adaptive_rows = []
for family in FAMILIES:
    for budget in BUDGETS:
        out, seconds = timed_adaptive(family, budget)
        row = {"family": family, "budget": budget, "dofs": out.result.describe()["dofs"]}
        row.update({k: max(out.result[s].errors[k] for s in STEPS) for k in KEYS})
        row.update(estimate=max(out.estimate[s]["e_q_max"] for s in STEPS), seconds=seconds)
        adaptive_rows.append(row)
        print(
            f"{family:<10} budget {budget:>3} {row['dofs']:>5} DOFs  e_q max "
            f"{100 * row['e_q_max']:6.3f} % (estimate {100 * row['estimate']:6.3f} %)  e_q L2 "
            f"{100 * row['e_q_l2']:6.3f} %  {seconds:5.2f} s"
        )

fig, ax = plt.subplots(layout="constrained")
for family, marker in zip(FAMILIES, "os", strict=True):
    fixed = [r for r in rows if r["family"] == family]
    mine = [r for r in adaptive_rows if r["family"] == family]
    (line,) = ax.loglog(
        [r["seconds"] for r in fixed], [100 * r["e_q_max"] for r in fixed], marker + "-",
        label=f"{family}, fixed pairs",
    )  # fmt: skip
    ax.loglog(
        [r["seconds"] for r in mine], [100 * r["e_q_max"] for r in mine], "D-", lw=2,
        color=line.get_color(), mec="k", label=f"{family}, adaptive (budgets {BUDGETS})",
    )  # fmt: skip
ax.legend(fontsize=8)
ax.set_xlabel("wall time of the run (s; adaptive: all levels)")
ax.set_ylabel("largest shear error over steps B–E (%)")
ax.grid(True, which="both", alpha=0.3)

# %%
# Key numbers: the finest level of each family.
FINEST = {r["family"]: r for r in rows if r["pairs"] == LEVELS[-1]}
for family, r in FINEST.items():
    print(f"{family}: e_p L2 {100 * r['e_p_l2']:.3f} %, e_q L2 {100 * r['e_q_l2']:.3f} % "
          f"at {r['pairs']} pairs in {r['seconds']:.2f} s")  # fmt: skip
