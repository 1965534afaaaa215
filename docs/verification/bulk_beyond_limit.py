"""
Bulk stress beyond the Nowell-Hills limit: slip reversed at one edge
====================================================================

**Source.** With a bulk stress sigma_B in phase with Q, Nowell and Hills (Int. J. Mech.
Sci. 29 (1987) 355-365) give the shear in closed form while the shifted stick zone stays
inside the contact, sigma_B <= 4 f p0 (1 - sqrt(1 - Q/(f P))). Beyond that the slip at one
edge reverses; the explicit solutions for general loading (Andresen, Hills, Barber and
Vázquez, arXiv 1908.07939, 2019) stop there, and the asymptotic description of Andresen et
al. (arXiv 2103.15647, 2021) approximates only the slip zones' size. The reference here is
therefore an *independent computation*,
:class:`fretbem.verification.dissimilar.DissimilarCylinders` with a bulk stress: two
half-planes, 400 cells of constant traction, exact Flamant integrals, incremental active
sets. It is first checked against the Nowell-Hills closed form inside the limit.

**Inputs.** R = 50 mm, E = 115 GPa, nu = 0.3 (both bodies, half-planes), f = 0.6,
P = 120 N/mm; Q = 0.4 f P with sigma_B = 0.5, 0.8, 1.5 and 2.5 times the limit
(118.9 MPa), in 32 increments, then -Q, -sigma_B in 32.

**Compared.** The shear at (Q, sigma_B) and (-Q, -sigma_B), RMS over the pairs inside the
contact over f p0, the stick-zone edges over a, and whether the slip zones carry shear of
both signs (slip reversed at one edge).

**Tolerances.** Reference against Nowell-Hills 0.5 % of f p0 (measured 0.11 %, the cell
discretisation); fretbem (half-plane bodies, nurbs, 61 pairs) against the reference 0.7 %
of f p0 (measured at most 0.43 %) and 0.05 a on the stick edges (at most 0.037 a: one pair
spacing is 0.05 a). Not covered: a moment or a tilted pad (fretbem's loading block is rigid
and does not rotate).
"""

# %%
import matplotlib.pyplot as plt
import numpy as np

from fretbem.scenes.builder import build
from fretbem.scenes.spec import scene_from_dict
from fretbem.simulation import run
from fretbem.verification.dissimilar import DissimilarCylinders
from fretbem.verification.nowell_hills import NowellHills

F, P, E, NU, R = 0.6, 120.0, 115000.0, 0.3, 50.0
Q = 0.4 * F * P
model = DissimilarCylinders(R, E, NU, E, NU, F)
hertz = model.hertz(P)
a, p0 = hertz.half_width, hertz.peak_pressure
limit = NowellHills(hertz, F).limit(Q)
print(f"a = {a:.4f} mm, p0 = {p0:.1f} MPa, Nowell-Hills limit {limit:.1f} MPa at Q = {Q:g}")

inside_check = model.solve([(P, 0.0, 0.0), (P, Q, 0.8 * limit)], cells=400, increments=[1, 32])
closed = NowellHills(hertz, F).shear_traction(inside_check[1].x, [0.0, Q], [0.0, 0.8 * limit])
inside = np.abs(inside_check[1].x) < a
rms = np.sqrt(np.mean((inside_check[1].shear - closed)[inside] ** 2)) / (F * p0)
print(f"reference vs Nowell-Hills at 0.8 x limit: {100 * rms:.2f} % of f p0")

ERRORS = {}  # sigma_B / limit: q RMS / f p0 against the reference
REVERSED = {}  # sigma_B / limit: slip zones carry shear of both signs
fig, axes = plt.subplots(1, 3, figsize=(12, 3.8), sharey=True, layout="constrained")
for ax, fraction in zip(axes, (0.8, 1.5, 2.5), strict=True):
    sigma = fraction * limit
    states = model.solve([(P, 0.0, 0.0), (P, Q, sigma)], cells=400, increments=[1, 32])
    data = {
        "pad": {"radius": R, "width": 10.0, "height": 10.0, "model": "half-plane"},
        "specimen": {"shape": "flat", "length": 40.0, "thickness": 13.0, "model": "half-plane"},
        "material": {"E": E, "nu": NU},
        "contact": {"friction": F, "pairs": 61, "estimate": False},
        "load": {"steps": ["A", "B"], "P": P, "Q": [0.0, Q], "bulk": [0.0, sigma],
                 "increments": [1, 32]},
    }  # fmt: skip
    simulation, _ = build(scene_from_dict(data))
    step = run(simulation)["B"]
    ref = states[1]
    mask = np.abs(step.x) < a
    q = np.interp(step.x, ref.x, ref.shear)
    error = np.sqrt(np.mean((step.shear - q)[mask] ** 2)) / (F * p0)
    stick = step.x[step.states == 1]
    slipping = step.shear[step.states == 2]
    ERRORS[fraction] = error
    REVERSED[fraction] = bool(np.any(slipping > 0) and np.any(slipping < 0))
    print(
        f"sigma_B = {fraction} x limit: q {100 * error:.2f} % of f p0, stick zone "
        f"[{stick.min() / a:.3f}, {stick.max() / a:.3f}] a"
    )
    ax.plot(ref.x / a, ref.shear / (F * p0), "k-", lw=1, label="reference")
    ax.plot(ref.x / a, ref.pressure / p0, "k:", lw=1, label="p / p0")
    ax.plot(step.x / a, step.shear / (F * p0), "o", ms=3, mfc="none", label="fretbem")
    ax.set_title(f"sigma_B = {fraction} x limit")
    ax.set_xlim(-1.2, 1.2)
    ax.set_xlabel("x / a")
axes[0].set_ylabel("q / f p0")
axes[0].legend(fontsize=7)
