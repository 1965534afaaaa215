"""
Run the reference fretting scene
================================

The reference scene is a Cattaneo–Mindlin fretting cycle: a cylindrical pad (R = 70 mm)
pressed with P = 100 N/mm on a similar cylinder, then a tangential load Q taken to
+18 N/mm, back to 0, to −18 N/mm and back to 0 (steps A to E). Half-plane theory
(Hertz and Mindlin–Deresiewicz) gives the exact pressure, shear and stick zone at every
step, so every run reports its own error.

This tutorial runs the scene from the command line and from Python, reads the per-step
table, and opens the figures and the VTK files it writes. It uses 31 node pairs in the
contact zone to stay quick; ``fretbem demo`` uses 61.
"""

# %%
# From the command line
# ---------------------
#
# After ``pip install .`` (or ``pip install -e .`` in a checkout), the ``fretbem`` command
# lists the installed basis families and runs the demo:
#
# .. code-block:: bash
#
#    fretbem bases
#    fretbem demo --pairs 31 --compare lagrange2 --out quickstart-out
#
# ``--compare`` adds other families to the figures. Here the same entry point is called
# from Python, so the output below is the command's real output:
from pathlib import Path

from fretbem.app import cli

cli.main(["bases"])
cli.main(["demo", "--pairs", "31", "--compare", "lagrange2", "--out", "quickstart-out"])

# %%
# The command wrote these files:
OUT = Path("quickstart-out")
for path in sorted(OUT.rglob("*")):
    if path.is_file() and (path.parent == OUT or path.name.startswith("B_")):
        print(path.relative_to(OUT))

# %%
# ``results.csv`` has one row per node pair and step (``step, x, p, q, un, ut, state``);
# ``summary.json`` the per-step errors, iterations and timings; ``tractions.png``,
# ``displacements.png`` and ``states.png`` the figures; ``vtk/`` and the two ``.pvd``
# files the boundaries of both bodies for ParaView (one ``.vtp`` per body and step, the
# ``_deformed`` ones with displacements magnified).
#
# From Python
# -----------
#
# :func:`fretbem.scenes.reference.cattaneo_mindlin` builds the scene as a
# :class:`~fretbem.simulation.Simulation` (two :class:`~fretbem.bem.body.BemBody` objects, a
# :class:`~fretbem.contact.pairs.NodeToNodePair`, five :class:`~fretbem.simulation.LoadStep`
# records, the :class:`~fretbem.contact.law.CoulombFriction` law and the analytical reference);
# :func:`fretbem.simulation.run` assembles and condenses both bodies once, then steps
# through the history.
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run

simulation = cattaneo_mindlin(basis="nurbs", pairs=31)
result = run(simulation)
print(result.table())

# %%
# Reading the table
# -----------------
#
# One row per load step, with P and Q at its end:
#
# - ``e_p max%`` and ``e_q max%``: the largest error of the pressure p and of the shear q
#   over the node pairs, in percent of the Hertz peak pressure p0 and of f p0;
# - ``e_p L2%`` and ``e_q L2%``: their root mean square over the contact zone;
# - ``iters``: semi-smooth Newton iterations; ``stick`` and ``slip``: pairs in each state
#   (the others are separated);
# - the last line: assembly, factorisation and condensation are done once, the steps
#   reuse them.
#
# Each step is a :class:`~fretbem.results.StepResult`, found by name; its arrays hold the
# solution at the node pairs:
step = result["B"]
print(f"step {step.name}: P = {step.normal:g}, Q = {step.tangential:g} N/mm")
print(f"{len(step.x)} pairs, {step.count('stick')} stick, {step.count('slip')} slip")
print(f"integral of p = {step.resultant[0]:.3f} N/mm, integral of q = {step.resultant[1]:.3f}")
print({name: f"{100 * value:.3f} %" for name, value in step.errors.items()})

# %%
# The key numbers of this run, kept at module level (the docs tests check them):
E_P_MAX = max(s.errors["e_p_max"] for s in result.steps)
E_Q_MAX = max(s.errors["e_q_max"] for s in result.steps)
E_Q_L2 = max(s.errors["e_q_l2"] for s in result.steps)
STICK_B = result["B"].count("stick")
print(f"largest errors over the cycle: e_p {100 * E_P_MAX:.2f} %, e_q {100 * E_Q_MAX:.2f} %")

# %%
# The figures
# -----------
#
# :mod:`fretbem.output.figures` draws the same figures the command saves: p and q against theory at
# each step, and the state of every pair along the history with theory's stick zone ±c.
# Pass several results to compare families on one figure.
from fretbem.output import figures as plot

plot.traction_figure(result, steps=("B", "C", "D", "E"))

# %%
plot.stick_slip_figure(result)

# %%
# The VTK files
# -------------
#
# ``write_results(result, directory)`` checks every step, then writes the CSV, the summary,
# the figures and the VTK files into the directory as a whole.
# Every ``.vtp`` file is a pyvista (VTK) polyline of one body's boundary with point data
# ``displacement``, ``traction`` and ``traction_magnitude``:
import pyvista as pv

from fretbem.output.write import write_results

write_results(result, OUT / "python")
mesh = pv.read(OUT / "python" / "vtk" / "B_lower.vtp")
print(mesh)
print(list(mesh.point_data))

# %%
# In ParaView: *File → Open* ``quickstart-out/history.pvd`` (or ``history_deformed.pvd``),
# *Apply*, colour by ``traction_magnitude``, and step through A–E with the time controls;
# *Filters → Glyph* on ``traction`` draws the traction vectors. Without ParaView, the
# arrays are numpy arrays: here is the traction on the lower body's contact face at
# step B, straight from the file. Between the node pairs it is the basis functions'
# interpolant of the pair values, which overshoots a little at the contact edges, where
# the exact pressure falls to zero like a square root.
import matplotlib.pyplot as plt
import numpy as np

x, y = mesh.points[:, 0], mesh.points[:, 1]
a = simulation.reference.hertz.half_width
face = (np.abs(x) < 2 * a) & (y > -0.01)
order = np.argsort(x[face])
fig, ax = plt.subplots(layout="constrained")
for k, label in enumerate(("traction x", "traction y")):
    ax.plot(x[face][order] / a, mesh.point_data["traction"][face, k][order], label=label)
ax.set_xlabel("x / a")
ax.set_ylabel("traction on the lower body (MPa)")
ax.set_title("B_lower.vtp, contact face")
ax.legend()

# %%
# :func:`fretbem.output.vtk.render_step` renders the same data off screen with pyvista: both
# bodies with magnified displacements, and the contact zone at true scale with the
# traction arrows.
from fretbem.output import vtk as vtk_

picture = vtk_.render_step(result, "B", OUT / "step_B.png")
fig, ax = plt.subplots(figsize=(10, 5), layout="constrained")
ax.imshow(plt.imread(picture))
ax.set_axis_off()
