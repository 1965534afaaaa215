"""
Worn profiles in gross slip and in partial slip
===============================================

A cylinder (R = 70 mm) on a flat, both elastic half-planes of the reference aluminium
(E = 73.4 GPa, nu = 0.33), P = 100 N/mm, f = 0.3. Both faces wear by Fouvry's energy law,
each with its own coefficient alpha: a body's worn volume is its alpha times the dissipated
friction energy. Two regimes:

* gross slip: the pad's block driven +-0.02 mm, so the whole contact slides; the scar
  widens and the pressure flattens from Hertz's ellipse toward a flat punch's;
* partial slip: the same contact under Q = +-0.6 f P (force control): only the slip
  zones at the contact edges wear, and the pressure peak moves to the stick-slip boundary.

Thousands of cycles are not solved one by one: one cycle is solved and its wear
extrapolated over Delta N cycles (docs/explanation/wear.rst says how Delta N is chosen).
"""

# %%
# Gross slip
# ----------
# The scene as a TOML table, with a ``[wear]`` table; ``scheme = "implicit"`` takes jumps far
# beyond the explicit stability limit, accurately in gross slip.
import matplotlib.pyplot as plt
import numpy as np

from fretbem.pipeline import wear_request
from fretbem.scenes.builder import build
from fretbem.scenes.file import scene_from_data
from fretbem.wear.law import JOULE
from fretbem.wear.run import run_wear

data = {
    "pad": {"shape": "cylinder", "radius": 70.0, "model": "half-plane"},
    "specimen": {"shape": "flat", "model": "half-plane"},
    "material": {"E": 73400.0, "nu": 0.33},
    "contact": {"friction": 0.3, "pairs": 41, "zone": 2.5},
    "load": {"steps": ["A", "B", "C"], "P": 100.0, "delta": [0.0, 0.02, -0.02],
             "increments": [1, 5, 10]},
    "wear": {"law": "energy", "pad": 1e-4, "specimen": 3e-4, "cycles": 5000,
             "scheme": "implicit", "relative_change": 0.1, "output": [250, 1000, 2500]},
}  # fmt: skip
scene = scene_from_data(data)
simulation, _ = build(scene)
gross = run_wear(wear_request(scene.extras).simulation(simulation))
print(f"{gross.simulated} cycles simulated for {gross.wear.cycles}")

fig, (left, right) = plt.subplots(1, 2, figsize=(10, 3.8))
for snap in gross.snapshots:
    prof = snap.profile
    left.plot(prof.x, 1e3 * prof.lower, label=f"N = {snap.cycles}")
    right.plot(prof.x, snap.pressure[0], label=f"N = {snap.cycles}")
left.set(xlabel="x (mm)", ylabel="specimen wear depth (um)", title="gross slip: the scar")
left.invert_yaxis()
right.set(xlabel="x (mm)", ylabel="p (MPa)", title="gross slip: p at the end of a stroke")
right.legend(fontsize=7)
fig.tight_layout()

PEAKS = [float(s.pressure[0].max()) for s in gross.snapshots]
WIDTHS = [s.profile.scar_width("lower") for s in gross.snapshots]
print("peak p (MPa):", np.round(PEAKS, 1))
print("scar width (mm):", np.round(WIDTHS, 3))

# %%
# The load stays P, and the volumes are the energy times alpha
# ------------------------------------------------------------
# Each body loses its own alpha times the summed dissipated energy; with 1e-4 and
# 3e-4 mm^3/J the specimen loses three times the pad's volume.
final = gross.final
LOAD = float(final.profile.weights @ final.pressure[0])
VOLUME_RATIO = final.profile.volume("lower") / (3e-4 / JOULE * final.energy)
print(f"integral of p = {LOAD:.6f} N/mm; specimen volume / (alpha E_d) = {VOLUME_RATIO:.12f}")

# %%
# Partial slip
# ------------
# Force control, Q cycled to +-0.6 f P: the stick zone does not wear. 1e5 cycles with
# Archard's law; the explicit jumps (the default) are limited by the stability estimate.
data_partial = {
    **{k: data[k] for k in ("pad", "specimen", "material")},
    "contact": {"friction": 0.3, "pairs": 41, "zone": 1.5},
    "load": {"steps": ["A", "B", "C", "D", "E"], "P": 100.0,
             "Q": [0.0, 18.0, 0.0, -18.0, 0.0], "increments": 5},
    "wear": {"law": "archard", "pad": 1e-7, "specimen": 1e-7, "cycles": 100000,
             "output": [10000, 30000]},
}  # fmt: skip
scene = scene_from_data(data_partial)
simulation, _ = build(scene)
partial = run_wear(wear_request(scene.extras).simulation(simulation))
limits = sorted({j.limit for _, j in partial.jumps})
print(f"{partial.simulated} cycles simulated; jumps limited by {limits}")

fig, (left, right) = plt.subplots(1, 2, figsize=(10, 3.8))
for snap in partial.snapshots:
    left.plot(snap.profile.x, 1e3 * snap.profile.lower, label=f"N = {snap.cycles}")
    right.plot(snap.profile.x, snap.pressure[0], label=f"N = {snap.cycles}")
left.set(xlabel="x (mm)", ylabel="specimen wear depth (um)", title="partial slip: slip zones")
left.invert_yaxis()
right.set(xlabel="x (mm)", ylabel="p (MPa)", title="partial slip: p at Q = +0.6 f P")
right.legend(fontsize=7)
fig.tight_layout()

prof = partial.final.profile
STICK_DEPTH = float(np.max(prof.lower[np.abs(prof.x) < 0.2]))  # inside the stick zone
SLIP_DEPTH = prof.max_depth("lower")
PEAK_X = float(abs(prof.x[np.argmax(partial.final.pressure[0])]))
print(f"deepest wear {1e3 * SLIP_DEPTH:.3f} um, in the stick zone {1e3 * STICK_DEPTH:.2e} um; "
      f"the pressure peak now at |x| = {PEAK_X:.3f} mm")  # fmt: skip
