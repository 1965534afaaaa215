"""
Tilted pad: a moment on the loading block, and a rig compliant in rotation
==========================================================================

**Source.** Half-plane theory (K.L. Johnson, *Contact Mechanics*, 1985, sec. 5.2 and 7.1;
D.A. Hills and D. Nowell, *Mechanics of Fretting Fatigue*, 1994): tilting a parabolic
profile x^2 / (2R) by a small angle theta (counterclockwise, x right, y up) gives
x^2 / (2R) + theta x, the same parabola centred at d = -theta R. Under a normal load P
and a moment M the contact is therefore Hertz's, of the same half-width a and peak p0,
centred at d, and moment equilibrium about the original contact point gives M = -P d
(M the moment the block applies to the pad; the pressure's resultant acts at d), so
theta = M / (P R); under P, M and Q the shear is Cattaneo-Mindlin's about d (Mindlin-
Deresiewicz on unloading), and with a bulk stress Nowell and Hills' (Int. J. Mech. Sci. 29,
1987) about d. For a rig whose holder turns about a pivot a height h above the contact,
the tangential load Q acts below the pivot: the block carries M = h Q - d P, the holder's
rotational spring turns it by theta = -M / k_r, and so theta = -h Q / (k_r + R P).

**Inputs.** A cylindrical pad (R = 70 mm, 6.5 x 16.25 mm) on a flat specimen (40 x 13 mm),
similar aluminium (E = 73.4 GPa, nu = 0.33, plane strain), f = 0.3, P = 50 and 100 N/mm,
M = -25 to 10 N mm/mm, Q = 0.5 and 0.8 f P; the pivot at the first-contact point
(``[rig] pivot_height = 0``) except for the rig, whose pivot is 5 or 16.25 mm up and
k_r = 1e5 or 1e6 N mm/mm per rad.

**Models.** Both bodies half-planes (the closed forms' own idealisation), nurbs and
lagrange2 at 41 and 61 pairs over abs(x) < 0.83 mm; finite BEM bodies at the rig's size and
4x larger, 61 pairs.

**Compared.** p and q RMS over the pairs against the shifted closed forms, / p0 and / (f p0);
the rotation against M / (P R) (as the shift error over a); the moment balance between
the block and the contact tractions.

**Tolerances and measured differences** (tests/validation/test_tilted_pad.py, rows in
the validation table). Half-planes: p 0.9 % (nurbs; measured at most 0.75 %) and 1.2 %
(lagrange2 61; 0.62 %), 1.6 % at lagrange2 41 (1.3 %: P = 50 leaves 16 pairs in
contact); q 1.6 % (1.3 %) and 2 to 2.6 % (lagrange2; 1.7 and 2.1 % back at Q = 0): the
discretisation error over a zone wide enough for the shifted contact (0.83 mm, 1.8 a).
Nowell-Hills about d: 1.2 % (0.66 %). theta within 3e-3 a / R of M / (P R) (2.4e-3 at
lagrange2 41 pairs, P = 50; 7.6e-4 at 61 pairs). The block's moment balances the contact
tractions' to round-off (1e-12 of P a); with the rig the spring holds M = -k_r theta to
round-off and theta matches -h Q / (k_r + R P) within 3e-3 (measured 4.2e-5 to 3.4e-4).
BEM bodies: p 0.8 % (0.64 %), q 6.5 % nurbs / 4.5 % lagrange2 (5.6 / 3.2 %), within 1 % of
f p0 of the centred run's error, which is the flat specimen's finite-body difference; theta is 4.5 %
off at the rig's size (the finite pad turns under the moment too) and 0.16-0.40 % off on
bodies 4x larger. The rig spring on BEM bodies (pivot on the pad's top, k_r = 1e6): theta
2.8 % off -h Q / (k_r + R P) at the rig's size (the pad bends under Q), 0.26-0.35 % on
bodies 4x larger (tolerance 0.6 %); M = -k_r theta to round-off; the block's moment
balances the contact tractions' to 2.2e-3 of M, the discretisation's, like the force.

**Rounded-flat pad, unsymmetric contact.** A flat of half-width b = 0.3 mm with fillets of
R = 20 mm (P for b/a = 0.5 untilted, 228 N/mm) turned by theta = 1e-3, -2e-3 and 4e-3 rad
(``[load] rotation``), then Q = 0.5 f P. No closed form was readable here (Andresen,
Hills, Barber and Vazquez, arXiv 1902.08044 and 1908.07939, give them; only their
abstracts were available), so the reference is half-plane theory's integral solution of
the tilted profile evaluated independently by Gauss-Chebyshev quadrature
(:class:`fretbem.verification.tilted_contact.TiltedContact`; it reproduces Hertz about
-theta R and the untilted rounded flat's closed form to 1.6e-4, the circles against the
parabolas), with the shear by the Ciavarella-Jager superposition over the same tilted
profile. Half-planes, nurbs 60 pairs: p 0.9 % (measured at most 0.72 %), q 1.2 % (0.89 %),
M within 3e-3 (1.7e-3); lagrange2 63 pairs: 2.5 % and 2.5 % (1.8 %, 1.8 %). A moment
imposed instead (M = 0.1 and -0.2 P a) is also checked against the same problem at 480
pairs: p 0.7 % (0.51 %), q 2 % (1.5 % back at Q = 0), falling with the pairs.
"""

# %%
import matplotlib.pyplot as plt
import numpy as np

from fretbem.contact import control
from fretbem.scenes.builder import build
from fretbem.scenes.spec import scene_from_dict
from fretbem.simulation import run
from fretbem.verification.closed_forms import (
    HertzLineContact,
    MindlinDeresiewicz,
    effective_modulus,
)

E, NU, F, R = 73400.0, 0.33, 0.3, 70.0
E_STAR = effective_modulus(E, NU, E, NU)


def solve(load, rig=None, model="half-plane"):
    data = {
        "pad": {"shape": "cylinder", "radius": R, "width": 6.5, "height": 16.25,
                "model": model},
        "specimen": {"shape": "flat", "length": 40.0, "thickness": 13.0, "model": model},
        "material": {"E": E, "nu": NU},
        "contact": {"friction": F, "pairs": 61, "zone_width": 0.83, "estimate": False},
        "load": load,
        "rig": rig or {"pivot_height": 0.0},
    }  # fmt: skip
    simulation, _ = build(scene_from_dict(data))
    result = run(simulation)
    problem = simulation.prepare()
    measured = [
        control.measure(problem, s.unknowns, problem.amplitudes(s.loads), simulation.rig)
        for s in result.steps
    ]
    return result, measured


def rms(v) -> float:
    return float(np.sqrt(np.mean(np.square(v))))


P = 100.0
hertz = HertzLineContact(P, R, E_STAR)
theory = MindlinDeresiewicz(hertz, F)
fine = np.linspace(-0.83, 0.83, 801)
ERRORS = {}  # M: (p RMS / p0, q RMS / (f p0), theta / (M / (P R)) - 1)
fig, axes = plt.subplots(1, 2, figsize=(11, 4), layout="constrained")
print(f"{'M':>6} {'d mm':>7} {'theta/(M/PR)':>13} {'e_p':>7} {'e_q':>7}")
for moment, colour in ((10.0, "C0"), (-25.0, "C1")):
    q = 0.5 * F * P
    result, measured = solve({"steps": ["A", "B"], "P": P, "Q": [0.0, q], "moment": moment})
    d = -moment / P
    A, B = result["A"], result["B"]
    e_p = rms(A.pressure - hertz.pressure(A.x - d)) / hertz.peak_pressure
    e_q = rms(B.shear - theory.shear_traction(B.x - d, [0.0, q])) / (F * hertz.peak_pressure)
    ratio = measured[0]["tilt"] / (moment / (P * R))
    ERRORS[moment] = (e_p, e_q, ratio - 1.0)
    print(f"{moment:>6g} {d:>7.3f} {ratio:>13.5f} {100 * e_p:>6.2f}% {100 * e_q:>6.2f}%")
    axes[0].plot(fine, hertz.pressure(fine - d), "-", color=colour, lw=1,
                 label=f"Hertz about d = {d:+.2f} mm")  # fmt: skip
    axes[0].plot(A.x, A.pressure, "o", ms=3, color=colour, label=f"fretbem, M = {moment:g}")
    axes[0].plot(fine, theory.shear_traction(fine - d, [0.0, q]), "--", color=colour, lw=1)
    axes[0].plot(B.x, B.shear, "s", ms=3, mfc="none", color=colour)
axes[0].set_xlabel("x (mm)")
axes[0].set_ylabel("p, q at Q = 0.5 f P (MPa)")
axes[0].set_title("P = 100 N/mm, moment M about the contact point")
axes[0].legend(fontsize=7)

# %%
# A rig whose holder turns: Q acts 16.25 mm below the pivot. The pad tilts by
# theta = -h Q / (k_r + R P) and the contact moves by d = -theta R with Q; a stiffer holder
# turns less.
h = 16.25
RIG = {}  # k_r: largest |theta - exact| / max |exact| over the history
for k_r, colour in ((1e5, "C2"), (1e6, "C3")):
    history = [0.0, 15.0, 0.0, -15.0, 0.0]
    result, measured = solve(
        {"steps": list("ABCDE"), "P": P, "Q": history},
        rig={"stiffness_rotation": k_r, "pivot_height": h},
    )
    tilt = np.array([m["tilt"] for m in measured])
    exact = -h * np.array(history) / (k_r + R * P)
    RIG[k_r] = float(np.abs(tilt - exact).max() / np.abs(exact).max())
    print(f"k_r {k_r:g}: theta {tilt} vs {exact}")
    axes[1].plot(
        history, 1e3 * exact, "-", color=colour, lw=1, label=f"-h Q / (k_r + R P), k_r {k_r:g}"
    )
    axes[1].plot(history, 1e3 * tilt, "o", color=colour, label="fretbem (half-planes)")
axes[1].set_xlabel("Q (N/mm)")
axes[1].set_ylabel("pad tilt theta (mrad)")
axes[1].set_title("rotational rig spring, pivot 16.25 mm up")
axes[1].legend(fontsize=7)

# %%
# The rounded-flat pad turned by theta: the unsymmetric contact against the quadrature
# solution of half-plane theory for the tilted profile.
from fretbem.verification.rounded_flat import RoundedFlatPunch
from fretbem.verification.tilted_contact import TiltedContact

FLAT, EDGE = 0.3, 20.0
a = FLAT / 0.5
load = RoundedFlatPunch(FLAT, EDGE, E_STAR, F).load(a)


def slope(x):
    beyond = np.maximum(np.abs(x) - FLAT, 0.0)
    return np.sign(x) * beyond / np.sqrt(EDGE**2 - beyond**2)


reference = TiltedContact(slope, E_STAR, F)
ROUNDED = {}  # theta: (p RMS / p_peak, q RMS / f p_peak, M / M_quadrature - 1)
fig, ax = plt.subplots(figsize=(7, 4), layout="constrained")
fine = np.linspace(-1.5 * a, 1.5 * a, 601)
for theta, colour in ((1e-3, "C0"), (4e-3, "C1")):
    data = {
        "pad": {"shape": "rounded-flat", "flat": FLAT, "edge_radius": EDGE, "width": 10.0,
                "height": 10.0, "model": "half-plane"},
        "specimen": {"shape": "flat", "length": 40.0, "thickness": 13.0,
                     "model": "half-plane"},
        "material": {"E": E, "nu": NU},
        "contact": {"friction": F, "pairs": 60, "zone_width": 1.5 * a, "estimate": False},
        "load": {"steps": ["A", "B"], "P": load, "Q": [0.0, 0.5 * F * load],
                 "rotation": theta},
        "rig": {"pivot_height": 0.0},
    }  # fmt: skip
    simulation, _ = build(scene_from_dict(data))
    result = run(simulation)
    edges = reference.edges(load, theta, (-a, a))
    A, B = result["A"], result["B"]
    exact = reference.pressure(A.x, load, theta, edges)
    e_p = rms(A.pressure - exact) / exact.max()
    e_q = rms(B.shear - reference.shear(B.x, load, 0.5 * F * load, theta, edges)) / (
        F * exact.max()
    )
    moment = reference.moment(load, theta, edges)
    ROUNDED[theta] = (e_p, e_q, A.moment / moment - 1.0)
    print(f"theta {theta:g}: edges {edges[0]:.4f}, {edges[1]:.4f} mm; e_p {100 * e_p:.2f} %, "
          f"e_q {100 * e_q:.2f} %; M {A.moment:.3f} vs {moment:.3f}")  # fmt: skip
    ax.plot(fine, reference.pressure(fine, load, theta, edges), "-", color=colour, lw=1,
            label=f"quadrature, theta = {theta:g}")  # fmt: skip
    ax.plot(A.x, A.pressure, "o", ms=3, color=colour, label="fretbem (half-planes, 60 pairs)")
    ax.plot(fine, reference.shear(fine, load, 0.5 * F * load, theta, edges), "--",
            color=colour, lw=1)  # fmt: skip
    ax.plot(B.x, B.shear, "s", ms=3, mfc="none", color=colour)
ax.axvspan(-FLAT, FLAT, color="0.92", zorder=0)
ax.set_xlabel("x (mm)")
ax.set_ylabel("p, and q at Q = 0.5 f P (MPa)")
ax.set_title("rounded-flat pad turned by theta (the flat shaded)")
ax.legend(fontsize=7)
