"""
Fretting loops: partial slip, gross slip and the energy ratio
=============================================================

A fretting test imposes a displacement amplitude delta* and records the tangential load Q:
the Q-delta loop. Its area is the energy dissipated per cycle, and the energy ratio
A = E_d / (4 delta* Q*) tells partial slip (a stick zone survives) from gross slip (the
whole contact slides at Q = +-f P). This tutorial drives two half-plane cylinders
(Hertz contact, P = 100 N/mm, f = 0.3) by a sine displacement below and above the onset
of gross slip, draws the loops, and checks the partial-slip cycle against the closed
forms of Cattaneo and Mindlin (slip amplitude s(x) and the energy W(c/a)).

delta is the pad's loading block against the specimen's held end: a 2D displacement
needs such a datum (docs/explanation/fretting.rst); the slip and the energy do not.
"""

# %%
# The scene and the onset of gross slip
# -------------------------------------
import matplotlib.pyplot as plt
import numpy as np

from fretbem.fretting import Waveform, analyse
from fretbem.fretting.cycles import onset_displacement
from fretbem.scenes.builder import build
from fretbem.scenes.spec import scene_from_dict
from fretbem.simulation import Simulation, run
from fretbem.verification import fretting as closed

P, F = 100.0, 0.3
scene = {
    "pad": {"model": "half-plane"},
    "specimen": {"model": "half-plane"},
    "contact": {"pairs": 61, "friction": F},
    "load": {"P": P, "cycle": {"delta": 0.001, "cycles": 1, "increments": 4}},
}
base, _ = build(scene_from_dict(scene))
pressed = run(base)
ONSET = onset_displacement(base.prepare(), pressed.steps[0], F)
hertz = base.reference.hertz
print(f"a = {hertz.half_width:.4f} mm; gross slip starts at delta = {1e3 * ONSET:.3f} um")

# %%
# Two displacement amplitudes, two cycles each
# --------------------------------------------
# Waveform(amplitude, P, ...) expands into one load step per increment; the second cycle
# is the stabilised one.
analyses = {}
for label, factor in (("partial slip", 0.8), ("gross slip", 2.0)):
    waveform = Waveform(factor * ONSET, P, control="displacement", cycles=2, increments=40)
    simulation = Simulation(base.pair, waveform.steps(), law=base.law, reference=base.reference)
    analyses[label] = analyse(run(simulation, check=True))

print(analyses["gross slip"].table())
PARTIAL = analyses["partial slip"].cycles[-1]
GROSS = analyses["gross slip"].cycles[-1]
TRANSITION = analyses["gross slip"].transition_ratio

fig, ax = plt.subplots(figsize=(6.4, 4.4))
for label, analysis in analyses.items():
    cycle = analysis.cycles[-1]
    ax.plot(1e3 * cycle.delta, cycle.tangential, label=f"{label}: A = {cycle.energy_ratio:.3f}")
ax.axhline(F * P, color="k", lw=0.6, ls=":")
ax.axhline(-F * P, color="k", lw=0.6, ls=":")
ax.set_xlabel("delta (um)")
ax.set_ylabel("Q (N/mm)")
ax.set_title(f"Q-delta loops (transition at A = {TRANSITION:.3f})")
ax.legend()

# %%
# The partial-slip cycle against the closed forms
# -----------------------------------------------
# Under +-Q* the slip amplitude is Cattaneo's s(x) with c = a sqrt(1 - Q*/fP), and the
# energy per cycle is W = 32 f^2 P^2 I(c/a) / (pi^2 E*).
ratio = PARTIAL.tangential_amplitude / (F * P)
c = closed.stick_ratio(ratio) * hertz.half_width
exact = closed.cattaneo_slip(hertz, F, c, PARTIAL.x)
inside = np.isfinite(exact)
SLIP_ERROR = float(np.max(np.abs(PARTIAL.slip_amplitude - exact)[inside]) / np.max(exact[inside]))
W = closed.cycle_energy(hertz, F, PARTIAL.tangential_amplitude)
ENERGY_ERROR = PARTIAL.dissipated_energy / W - 1
LOOP_ERROR = PARTIAL.loop_area / PARTIAL.dissipated_energy - 1
print(f"Q*/fP = {ratio:.3f}: slip amplitude within {100 * SLIP_ERROR:.2f} % of Cattaneo,")
print(f"E_d = {PARTIAL.dissipated_energy:.4g} N mm/mm, W = {W:.4g} ({100 * ENERGY_ERROR:+.2f} %),")
print(f"loop area - E_d = {LOOP_ERROR:+.1e} of E_d")

fig, (top, bottom) = plt.subplots(2, 1, figsize=(6.4, 5.6), sharex=True)
top.plot(PARTIAL.x, 1e3 * PARTIAL.slip_amplitude, "o", ms=3, label="fretbem")
top.plot(PARTIAL.x[inside], 1e3 * exact[inside], "-", label="Cattaneo s(x)")
top.set_ylabel("slip amplitude (um)")
top.legend()
bottom.plot(PARTIAL.x, PARTIAL.energy_density, "o-", ms=3, label="partial slip")
bottom.plot(GROSS.x, GROSS.energy_density, "s-", ms=3, label="gross slip")
bottom.set_ylabel("energy density (N/mm per cycle)")
bottom.set_xlabel("x (mm)")
bottom.legend()

# %%
# Gross slip: plateaus at +-f P
# -----------------------------
# While the contact slides Q stays at f P; the energy is the sliding part 4 f P delta_s
# (delta_s the centre's slip amplitude) plus the partial-slip part W(0) = 2 f^2 P^2 /
# (pi E*) the stick zone dissipates while it shrinks to a point.
centre = int(np.argmin(np.abs(GROSS.x)))
SLIDING = 4 * F * P * GROSS.slip_amplitude[centre]
TRANSITION_PART = (GROSS.dissipated_energy - SLIDING) / closed.onset_energy(hertz, F)
print(f"Q* = {GROSS.tangential_amplitude:.6g} N/mm (f P = {F * P:g}); "
      f"(E_d - 4 f P delta_s) / W(0) = {TRANSITION_PART:.3f}")  # fmt: skip
