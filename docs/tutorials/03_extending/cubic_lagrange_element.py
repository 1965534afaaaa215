"""
A new element type: cubic Lagrange elements as a plugin
=======================================================

fretbem ships two basis families, ``nurbs`` and ``lagrange2``, and both are plugins: they
are found through the ``fretbem.bases`` entry-point group, the same way as a family in
someone else's package. Adding an element type takes two steps:

1. subclass :class:`fretbem.basis.Basis`: set ``name``, ``description`` and
   ``interpolatory``, and implement :meth:`~fretbem.basis.Basis.discretise` and
   :meth:`~fretbem.basis.Basis.shape_functions`;
2. declare the class under ``[project.entry-points."fretbem.bases"]`` in your package's
   ``pyproject.toml``.

Then ``pip install`` the package, and ``fretbem bases``, scene files,
:class:`~fretbem.bem.body.BemBody` and :func:`~fretbem.scenes.reference.cattaneo_mindlin`
accept its name.
This tutorial walks through ``examples/custom_basis/``, a complete plugin package that
adds continuous cubic Lagrange elements (``lagrange3``), and runs it on the reference
scene beside the built-in families. The :doc:`how-to page </how-to/add-element-type>`
is the same recipe in short.
"""

# %%
# Step 1: subclass ``Basis``
# --------------------------
#
# A family discretises one boundary segment, a :class:`~fretbem.geometry.nurbs.NurbsCurve`
# with parameter in [0, 1]. ``discretise`` splits the parameter range into elements
# (``refinement.breakpoints()`` gives their ends, uniform or graded), numbers the
# functions, and returns the geometry coefficients (here: nodes sampled on the exact
# curve, so the geometry is their cubic interpolant) and the natural collocation
# parameters (the nodes). ``shape_functions`` gives the values and d/d(local) of each
# element's functions at local coordinates in [−1, 1]. Everything else — points, normals,
# Jacobians, the E matrix, moving collocation points off the corners, integration — is
# done once by :class:`~fretbem.basis.Basis` and the assembler.
#
# ``examples/custom_basis/fretbem_cubic/cubic.py``, the whole family:
#
# .. literalinclude:: ../../../examples/custom_basis/fretbem_cubic/cubic.py
#    :language: python
#
# Step 2: declare the entry point
# -------------------------------
#
# ``examples/custom_basis/pyproject.toml``; the entry point's name is the family's name,
# its value ``module:class``:
#
# .. literalinclude:: ../../../examples/custom_basis/pyproject.toml
#    :language: toml
#
# Install it
# ----------
#
# From the repository root, ``pip install ./examples/custom_basis`` (add ``-e`` to edit it
# in place). The docs build installs it first (see :doc:`/how-to/build-docs`); if it is
# missing, this script installs it the same way.
import importlib
import subprocess
import sys
from pathlib import Path

from fretbem import registry as bases

if "lagrange3" not in bases.available():
    # this script's folder (sphinx-gallery runs a script in its folder, without __file__)
    here = Path(globals().get("__file__", "cubic_lagrange_element.py")).resolve().parent
    plugin = here.parents[2] / "examples" / "custom_basis"
    command = [sys.executable, "-m", "pip", "install", "--quiet", "--no-deps", str(plugin)]
    print("$", " ".join(command[2:]))
    subprocess.run(command, check=True)
    importlib.invalidate_caches()  # let this running Python see the new package
    bases.refresh()  # forget the families found so far; the next call looks again

# %%
# ``fretbem bases`` now lists it beside the built-in families (the registry reads the
# installed packages' entry points; nothing in fretbem names ``lagrange3``):
from fretbem.app import cli

cli.main(["bases"])

CubicLagrangeBasis = bases.get("lagrange3")
print(CubicLagrangeBasis, "from", CubicLagrangeBasis.__module__)

# %%
# Check it
# --------
#
# :func:`fretbem.testing.conformance.check_basis` is the conformance suite every family passes, the
# built-in ones included: partition of unity, derivatives against finite differences,
# element ends on the exact curve, a square non-singular E matrix, nodality for an
# interpolatory family, nested spaces under refinement, on lines, arcs and a cubic
# B-spline, uniform and graded. Put the same call in your package's tests
# (``examples/custom_basis/tests/test_cubic.py``). It raises ``AssertionError`` naming
# the curve, the refinement and the property that fails.
from fretbem.testing.conformance import check_basis

check_basis(CubicLagrangeBasis)
print("check_basis(CubicLagrangeBasis): all properties hold")

# %%
# A discretised segment is a frozen record of arrays; :func:`fretbem.output.figures.draw` draws it.
# Here a quarter circle in three cubic elements, against the exact arc:
import math

import matplotlib.pyplot as plt
import numpy as np

from fretbem.basis import Refinement
from fretbem.geometry.nurbs import NurbsCurve
from fretbem.output import figures as plot

arc = NurbsCurve.arc([0.0, 0.0], 1.0, 0.0, math.pi / 2)
segment = CubicLagrangeBasis.discretise(arc, Refinement(3))
print(f"{segment.n_elements} elements, {segment.n_functions} functions, degree {segment.degree}")
print("connectivity:\n", segment.connectivity)
ax = plot.draw(segment, label="lagrange3, 3 elements")
ax.plot(*arc.points(np.linspace(0, 1, 200)).T, "k:", lw=1, label="exact arc")
ax.plot(*segment.geometry_coefficients.T, "k.", label="nodes")
ax.legend()

# %%
# Run it on the reference scene
# -----------------------------
#
# The reference scene places exactly ``pairs`` collocation points in the candidate
# contact zone. A cubic continuous family has 3 k + 1 points on k elements, so the pair
# count must be of that form; 61 suits all three families (``lagrange2`` needs an odd
# number). Any other count is an error that says which counts work:
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run

try:
    cattaneo_mindlin(basis="lagrange3", pairs=60)
except ValueError as err:
    print(err)

# %%
# The three families on the same scene, 61 pairs each (step C, after the first load
# reversal, has the most complex shear; errors in percent of p0 and f p0):
PAIRS = 61
FAMILIES = ("nurbs", "lagrange2", "lagrange3")
results = {name: run(cattaneo_mindlin(basis=name, pairs=PAIRS)) for name in FAMILIES}
print(f"{'family':<10} {'dofs':>5} {'e_p L2%':>8} {'e_q L2%':>8} {'e_q max%':>9} {'time s':>7}")
for name, result in results.items():
    errors = result["C"].errors
    print(
        f"{name:<10} {result.describe()['dofs']:>5} {100 * errors['e_p_l2']:>8.3f} "
        f"{100 * errors['e_q_l2']:>8.3f} {100 * errors['e_q_max']:>9.3f} "
        f"{result.timings['total']:>7.2f}"
    )
E_Q_L2_61 = {name: r["C"].errors["e_q_l2"] for name, r in results.items()}

# %%
# :func:`fretbem.output.figures.traction_figure` draws several results on one figure. The Lagrange
# families interpolate the circle through their nodes; the NURBS family carries the exact
# arc, which shows in the pressure: the initial gap of a 70 mm radius over ±0.5 mm is only
# a few micrometres, so a small geometric error is a visible pressure error.
plot.traction_figure(list(results.values()), steps=("B", "C"))
# sphinx_gallery_thumbnail_number = 2

# %%
# Convergence
# -----------
#
# The new family converges as the contact zone is refined: the shear error of step C
# at 31, 61 and 91 pairs (k = 10, 20 and 30 cubic elements in the zone).
LEVELS = (31, 61, 91)
cubic = {PAIRS: results["lagrange3"]}
cubic.update({n: run(cattaneo_mindlin(basis="lagrange3", pairs=n)) for n in LEVELS if n != PAIRS})
CUBIC_E_Q_L2 = {n: cubic[n]["C"].errors["e_q_l2"] for n in LEVELS}
CUBIC_E_P_L2 = {n: cubic[n]["C"].errors["e_p_l2"] for n in LEVELS}
for n in LEVELS:
    e_p, e_q = 100 * CUBIC_E_P_L2[n], 100 * CUBIC_E_Q_L2[n]
    print(f"{n:3d} pairs: e_p L2 {e_p:.3f} %, e_q L2 {e_q:.3f} %")

fig, ax = plt.subplots(layout="constrained")
ax.loglog(LEVELS, [100 * CUBIC_E_P_L2[n] for n in LEVELS], "o-", label="$e_p$ L2")
ax.loglog(LEVELS, [100 * CUBIC_E_Q_L2[n] for n in LEVELS], "s-", label="$e_q$ L2")
ax.set_xlabel("node pairs in the contact zone")
ax.set_ylabel("error at step C (%)")
ax.set_title("lagrange3 on the reference scene")
ax.legend()
