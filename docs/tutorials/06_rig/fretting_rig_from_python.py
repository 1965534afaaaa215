"""
A fretting-fatigue rig from Python
==================================

The rig of ``examples/fretting_rig.toml``, built from the scene records instead of the
file: a cylindrical pad (R = 70 mm) pressed on a flat aluminium specimen 40 mm long and
13 mm thick, the specimen held at its -x end and pulled at its +x end by a bulk stress
sigma_B in phase with the pad's tangential load Q. The bulk stress moves the stick zone by
e = a sigma_B / (4 f p0) (Nowell and Hills, 1987) while its width stays the
Cattaneo-Mindlin c; this tutorial measures that shift on the finite rig and on the
idealised half-plane rig, where the closed form is exact.

The record fields are the scene file's keys (``docs/scene-format.md``), so anything built
here can be written as a file and the other way round.
"""

# %%
# The scene as records
# --------------------
import numpy as np

from fretbem.contact.zones import zone_table
from fretbem.geometry.shapes import CylinderPad, FlatSpecimen
from fretbem.material import Material
from fretbem.scenes.builder import build, hertz
from fretbem.scenes.spec import BodySpec, ContactSpec, LoadSpec, Scene
from fretbem.simulation import run

aluminium = Material(E=72000.0, nu=0.33)
P, F = 200.0, 0.5
Q_MAX = 0.45 * F * P
SIGMA_MAX = 90.0  # MPa, in phase with Q

load = LoadSpec(
    steps=("A", "B", "C", "D", "E"),
    P=(P,) * 5,
    Q=(0.0, Q_MAX, 0.0, -Q_MAX, 0.0),
    bulk=(0.0, SIGMA_MAX, 0.0, -SIGMA_MAX, 0.0),
    increments=(1,) * 5,
)
scene = Scene(
    pad=BodySpec(CylinderPad(radius=70.0, width=10.0, height=10.0), aluminium),
    specimen=BodySpec(FlatSpecimen(length=40.0, thickness=13.0), aluminium, support="ends"),
    contact=ContactSpec(friction=F, pairs=61),
    load=load,
)
contact = hertz(scene)
A, P0 = contact.half_width, contact.peak_pressure
print(f"a = {A:.4f} mm, p0 = {P0:.1f} MPa")

# %%
# Run it
# ------
# ``build`` returns the Simulation and, when no closed form applies, the reason. With
# sigma_B in phase with Q and inside the validity limit the reference is Nowell-Hills.
simulation, reason = build(scene)
result = run(simulation)
print(result.table())
print(zone_table(result, reason))

# %%
# The stick zone's shift
# ----------------------
# The stick zone runs from its first to its last stick pair. On the finite rig the pad
# is 10 mm wide and tilts a little under Q, so the shift is not exactly the half-plane
# value; on two half-planes (``model = "half-plane"``) it is.


def stick_centre(step) -> float:
    x = step.x[step.states == 1]
    return 0.5 * (x.min() + x.max())


E_THEORY = A * SIGMA_MAX / (4 * F * P0)
half_planes = Scene(
    pad=BodySpec(scene.pad.shape, aluminium, model="half-plane"),
    specimen=BodySpec(scene.specimen.shape, aluminium, model="half-plane", support="ends"),
    contact=scene.contact,
    load=load,
)
ideal = run(build(half_planes)[0])
SHIFT_RIG = stick_centre(result["B"])
SHIFT_HALF_PLANE = stick_centre(ideal["B"])
SPACING = float(np.max(np.diff(ideal["B"].x)))
print(f"stick-zone shift at B: theory {E_THEORY:.4f} mm, half-planes {SHIFT_HALF_PLANE:.4f} mm, "
      f"finite rig {SHIFT_RIG:.4f} mm (pair spacing {SPACING:.4f} mm)")  # fmt: skip

# %%
# Shear traction against Nowell-Hills
# -----------------------------------
import matplotlib.pyplot as plt

fig, axes = plt.subplots(1, 2, figsize=(10, 3.8), sharey=True)
for ax, name in zip(axes, ("B", "D"), strict=True):
    for res, label in ((result, "finite rig"), (ideal, "two half-planes")):
        step = res[name]
        ax.plot(step.x / A, step.shear / (F * P0), ".", ms=3, label=label)
    step = ideal[name]
    ax.plot(step.x / A, step.exact[1] / (F * P0), "k-", lw=1, label="Nowell-Hills")
    ax.axvline(E_THEORY / A, color="grey", ls=":", lw=1)  # the stick zone centre, theory
    ax.set_title(f"step {name}: Q = {step.tangential:g} N/mm, $\\sigma_B$ = "
                 f"{step.loads['bulk']:g} MPa")  # fmt: skip
    ax.set_xlabel("x / a")
axes[0].set_ylabel("q / (f p0)")
axes[0].legend(fontsize=8)
fig.tight_layout()

E_Q_L2_HALF_PLANE = ideal["B"].errors["e_q_l2"]
E_Q_L2_RIG = result["B"].errors["e_q_l2"]
print(f"e_q L2 at B: half-planes {100 * E_Q_L2_HALF_PLANE:.2f} %, rig {100 * E_Q_L2_RIG:.2f} %")

# %%
# The same rig from the command line::
#
#     fretbem run examples/fretting_rig.toml --out rig-out
#
# prints the same tables and writes ``results.csv``, ``summary.json``, the figures (their
# titles give sigma_B) and VTK files.
