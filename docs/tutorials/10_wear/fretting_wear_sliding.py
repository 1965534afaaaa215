"""
Sliding wear: the specimen's scar spans the contact plus the stroke
===================================================================

A cylinder (R = 70 mm) on a flat, both elastic half-planes of the reference aluminium
(E = 73.4 GPa, nu = 0.33), P = 100 N/mm, f = 0.3, the pad's block driven +-0.2 mm: gross
slip with a stroke (0.4 mm) close to the contact's width (2a = 0.93 mm). Both faces wear by
the energy law.

On fixed pairs a pair stands for one point of each face, so the specimen would wear only
under the contact. With ``[contact] sliding = true`` the pairing follows the pad and each
face wears at its own material points: the specimen's scar spans the contact plus the
stroke, 2 a + 2 delta_s, while every point of the pad's contact is rubbed the whole cycle.
"""

# %%
# The sliding wear history
# ------------------------
# ``pairing = "node-to-segment"`` and ``sliding = true`` in ``[contact]``; the explicit jump
# (the only one with sliding), ``relative_change`` raised so that the stability limit
# chooses the jumps.
import matplotlib.pyplot as plt
import numpy as np

from fretbem.pipeline import wear_request
from fretbem.scenes.builder import build
from fretbem.scenes.file import scene_from_data
from fretbem.wear.run import run_wear

data = {
    "pad": {"shape": "cylinder", "radius": 70.0, "width": 6.5, "height": 16.25,
            "model": "half-plane"},
    "specimen": {"shape": "flat", "length": 20.0, "thickness": 10.0, "model": "half-plane"},
    "material": {"E": 73400.0, "nu": 0.33},
    "contact": {"friction": 0.3, "pairs": 31, "zone": 2.0, "pairing": "node-to-segment",
                "sliding": True},
    "load": {"steps": ["press", "A", "B", "C"], "P": 100.0, "delta": [0.0, 0.2, -0.2, 0.0],
             "increments": [1, 6, 12, 6]},
    "wear": {"law": "energy", "pad": 1e-5, "specimen": 2e-5, "cycles": 2000,
             "relative_change": 0.2, "output": [250, 500, 1000]},
}  # fmt: skip
scene = scene_from_data(data)
simulation, _ = build(scene)
sliding = run_wear(wear_request(scene.extras).simulation(simulation, sliding=True))
print(f"{sliding.simulated} cycles simulated for {sliding.wear.cycles}")

# %%
# Worn profiles of both faces
# ---------------------------
# Each face's depth at its own points: the specimen's on a grid along its face, the pad's
# at its nodes (``profile.upper_x``, its x as drawn, before it slid). The specimen's scar
# is U-shaped and wider by the stroke.
fig, (pad, specimen) = plt.subplots(1, 2, figsize=(10, 3.8), sharex=True)
for snap in sliding.snapshots[1:]:
    prof = snap.profile
    pad.plot(prof.upper_x, 1e3 * prof.upper, label=f"N = {snap.cycles}")
    specimen.plot(prof.x, 1e3 * prof.lower, label=f"N = {snap.cycles}")
pad.set(xlabel="x on the pad (mm)", ylabel="wear depth (um)", title="pad")
specimen.set(xlabel="x on the specimen (mm)", title="specimen")
for ax in (pad, specimen):
    ax.invert_yaxis()
    ax.set_xlim(-1.2, 1.2)
specimen.legend(fontsize=7)
fig.tight_layout()

final = sliding.final.profile
WIDTHS = {body: final.scar_width(body) for body in ("upper", "lower")}
print(f"scar width: pad {WIDTHS['upper']:.3f} mm, specimen {WIDTHS['lower']:.3f} mm")

# %%
# Pressure at the two ends of the stroke
# --------------------------------------
# Where the pairs were at the end of strokes A (+0.2 mm) and B (-0.2 mm), at each output
# N: the pad flattens, and at each end of the stroke it bears on the edge of the
# specimen's scar.
fig, ax = plt.subplots(figsize=(6.5, 4))
colours = plt.cm.viridis(np.linspace(0.0, 0.9, len(sliding.snapshots)))
for snap, colour in zip(sliding.snapshots, colours, strict=True):
    for step, style in ((0, "-"), (1, "--")):
        ax.plot(snap.pair_x(step), snap.pressure[step], style, color=colour,
                label=f"N = {snap.cycles}" if step == 0 else None)  # fmt: skip
ax.set(xlabel="x on the specimen (mm)", ylabel="p (MPa)",
       title="p at the end of stroke A (solid) and B (dashed)")  # fmt: skip
ax.legend(fontsize=7)
fig.tight_layout()
PEAKS = [float(s.pressure.max()) for s in sliding.snapshots]
print("peak p (MPa):", np.round(PEAKS, 1))

# %%
# Against fixed pairs
# -------------------
# The same history on fixed node-to-node pairs: the specimen wears only under the
# contact, so its scar lacks the stroke.
fixed_data = {**data, "contact": {"friction": 0.3, "pairs": 31, "zone": 2.0}}
fixed_scene = scene_from_data(fixed_data)
fixed = run_wear(wear_request(fixed_scene.extras).simulation(build(fixed_scene)[0]))
FIXED_WIDTH = fixed.final.profile.scar_width("lower")
print(f"specimen scar on fixed pairs {FIXED_WIDTH:.3f} mm, with sliding {WIDTHS['lower']:.3f} mm")
