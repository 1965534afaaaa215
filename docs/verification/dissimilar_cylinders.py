"""
Dissimilar cylinders: Goodman's microslip and Spence's stick zone
=================================================================

**Source.** For elastically dissimilar bodies (Dundurs' beta != 0) a normal load alone
makes the surfaces slide inward by different amounts and friction opposes it (L.E.
Goodman, J. Appl. Mech. 29 (1962) 515-522). Under a growing Hertz load the solution is
self-similar, with a central stick zone whose ratio c/a depends only on beta/f (D.A.
Spence, J. Elasticity 5 (1975) 297-319; D. Nowell, D.A. Hills and A. Sackfield, J. Mech.
Phys. Solids 36 (1988) 59-75). No closed form gives the tractions: the reference here is an
*independent computation*, :class:`fretbem.verification.dissimilar.DissimilarCylinders`:
two half-planes, tractions constant on 400 uniform cells, exact integrals of Flamant's
line loads with the beta coupling, collocation at the cell centres and an incremental
active-set solution with full normal-tangential coupling. It shares no code with fretbem's
solvers. For any force-controlled scene with Hertzian faces,
:func:`fretbem.verification.dissimilar.reference_for_scene` returns it by step name.

**Inputs.** A pad of radius 70 mm on a flat aluminium specimen (E = 72 GPa, nu = 0.33):
steel pad (210 GPa, 0.3; beta = -0.114) and titanium pad (116 GPa, 0.34; beta = -0.065),
plane strain, f = 0.3; P = 100 N/mm in 32 increments, then Q = 0.5 f P in 16. Both
computations use the same increments: the answer depends on the load path, and with 32
increments the path error of either is about 2 % of f p0 (the reference's measured
difference between 32, 64 and 128 increments).

**Compared.** p and q, RMS over the pairs inside the Hertz half-width, over p0 and f p0,
and the stick-zone half-width over a, for fretbem's half-plane bodies (nurbs, 61 pairs; in
the slow tests also lagrange2, 121 pairs and finite BEM bodies).

**Tolerances.** p 0.75 % of p0 (1.5 % for BEM bodies, whose finite size shifts p), q 3.5 %
of f p0, c 0.05 a: measured at most 0.46 %, 3.0 % and 0.041 a. The q difference sits in
the thin slip zones at the contact edges (c/a = 0.97-0.99 at the normal load) and falls
with the pairs (2.1 % at 61, 1.4 % at 121 under Q).
"""

# %%
import matplotlib.pyplot as plt
import numpy as np

from fretbem.scenes.builder import build
from fretbem.scenes.spec import scene_from_dict
from fretbem.simulation import run
from fretbem.verification.dissimilar import DissimilarCylinders, stick_half_width

F, P = 0.3, 100.0
AL = (72000.0, 0.33)
PADS = {"steel on aluminium": (210000.0, 0.3), "titanium on aluminium": (116000.0, 0.34)}

ERRORS = {}  # (pads, Q): (p RMS / p0, q RMS / f p0, |c - c_ref| / a)
fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True, layout="constrained")
for ax, (name, pad) in zip(axes, PADS.items(), strict=True):
    reference = DissimilarCylinders(70.0, *pad, *AL, F)
    states = reference.solve([(P, 0.0), (P, 0.5 * F * P)], cells=400, increments=[32, 16])
    data = {
        "pad": {"radius": 70.0, "width": 10.0, "height": 10.0, "model": "half-plane",
                "material": {"E": pad[0], "nu": pad[1]}},
        "specimen": {"shape": "flat", "length": 40.0, "thickness": 13.0, "model": "half-plane",
                     "support": "clamped-bottom", "material": {"E": AL[0], "nu": AL[1]}},
        "contact": {"friction": F, "pairs": 61, "estimate": False},
        "load": {"steps": ["A", "B"], "P": P, "Q": [0.0, 0.5 * F * P], "increments": [32, 16]},
    }  # fmt: skip
    simulation, _ = build(scene_from_dict(data))
    result = run(simulation)
    hertz = reference.hertz(P)
    a, p0 = hertz.half_width, hertz.peak_pressure
    print(f"{name}: beta = {reference.beta:.4f}, beta/f = {reference.beta / F:.3f}")
    for step, ref, style in zip(result.steps, states, ("o", "s"), strict=True):
        inside = np.abs(step.x) < a
        e_p = np.sqrt(
            np.mean((step.pressure - np.interp(step.x, ref.x, ref.pressure))[inside] ** 2)
        )
        e_q = np.sqrt(np.mean((step.shear - np.interp(step.x, ref.x, ref.shear))[inside] ** 2))
        stick = step.x[step.states == 1]
        c_bem = 0.5 * (stick.max() - stick.min()) / a
        c_ref = stick_half_width(ref.x, ref.states) / a
        ERRORS[name, step.tangential] = (e_p / p0, e_q / (F * p0), abs(c_bem - c_ref))
        print(
            f"  Q = {step.tangential:4.1f}: p {100 * e_p / p0:.2f} % of p0, "
            f"q {100 * e_q / (F * p0):.2f} % of f p0, c/a {c_bem:.3f} (reference {c_ref:.3f})"
        )
        ax.plot(ref.x / a, ref.shear / (F * p0), "k-", lw=1)
        ax.plot(step.x / a, step.shear / (F * p0), style, ms=3, mfc="none",
                label=f"fretbem, Q = {step.tangential:g} N/mm")  # fmt: skip
    ax.plot([], [], "k-", lw=1, label="independent reference")
    ax.plot(states[0].x / a, states[0].pressure / p0, "k:", lw=1, label="p / p0 (reference)")
    ax.set_xlim(-1.2, 1.2)
    ax.set_title(f"{name} (beta/f = {reference.beta / F:.2f})")
    ax.set_xlabel("x / a")
axes[0].set_ylabel("q / f p0")
axes[0].legend(fontsize=7)
