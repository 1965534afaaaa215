"""
A rounded-flat pad, your own bodies and load history
====================================================

The reference scene is one call; this tutorial builds a contact problem from the pieces:

1. two bodies from NURBS curves: a pad whose face is a straight flat with circular
   fillets, pressed on a flat specimen;
2. a basis family and a refinement per segment;
3. a load history of its own: several cycles of the tangential load with partial
   unloading, as a tuple of :class:`~fretbem.simulation.LoadStep` records;
4. the run, and p, q and the stick zone along the history, checked against the
   half-plane solution of a rounded flat punch (Ciavarella et al., 1998).
"""

# %%
# The pad's face
# --------------
#
# Units are mm, N/mm and MPa. The flat is 2 b wide; each fillet is a circular arc of
# radius R tangent to it, up to the pad's sides. A rounded-flat pad under P = 100 N/mm
# touches over about ±0.4 mm, so the candidate contact zone (where node pairs are placed)
# is taken as ±3 b = ±0.6 mm: the flat and the inner part of each fillet.
import math

import matplotlib.pyplot as plt
import numpy as np

from fretbem.geometry.boundary import Boundary, Segment
from fretbem.geometry.nurbs import NurbsCurve

WIDTH, HEIGHT = 8.0, 8.0  # both bodies
FLAT, RADIUS = 0.2, 20.0  # flat half-width b and fillet radius R
ZONE = 3 * FLAT  # half-width of the candidate contact zone
E, NU, FRICTION = 73400.0, 0.33, 0.3

half = WIDTH / 2
down = -math.pi / 2
to_side = math.asin((half - FLAT) / RADIUS)  # fillet angle from the flat to the side
to_zone = math.asin((ZONE - FLAT) / RADIUS)  # ... and to the edge of the candidate zone


def fillet(centre_x: float, start: float, end: float) -> NurbsCurve:
    """Exact circular arc of radius R centred at (centre_x, R), angles in radians."""
    return NurbsCurve.arc([centre_x, RADIUS], RADIUS, start, end)


# the face from left to right, as a counter-clockwise boundary runs along a body's bottom
face = [
    Segment("flank_left", fillet(-FLAT, down - to_side, down - to_zone)),
    Segment("contact", fillet(-FLAT, down - to_zone, down)),
    Segment("contact", NurbsCurve.line([-FLAT, 0.0], [FLAT, 0.0])),
    Segment("contact", fillet(FLAT, down, down + to_zone)),
    Segment("flank_right", fillet(FLAT, down + to_zone, down + to_side)),
]

# %%
# A :class:`~fretbem.geometry.boundary.Boundary` is a closed chain of tagged segments,
# counter-clockwise (the outward normal on the right of the direction of travel); it is
# checked closed, simple and counter-clockwise when it is built. Three segments share
# the tag ``"contact"``: a contact pair may span several segments.
left_end = face[0].curve.points([0.0])[0]
right_end = face[-1].curve.points([1.0])[0]
pad_boundary = Boundary(
    [
        *face,
        Segment("side_right", NurbsCurve.line(right_end, [half, HEIGHT])),
        Segment("top", NurbsCurve.line([half, HEIGHT], [-half, HEIGHT])),
        Segment("side_left", NurbsCurve.line([-half, HEIGHT], left_end)),
    ]
)

# %%
# The specimen's face, facing the pad node to node
# ------------------------------------------------
#
# Contact is resolved between *node pairs*: collocation points of the two contact faces
# at the same x. They face each other if the specimen's contact segments have the same
# x(ξ) as the pad's: ``NurbsCurve.flattened(y)`` is such a curve (same knots and weights,
# control points (x_i, y)). The specimen lies below, so its counter-clockwise boundary
# runs along its top face from right to left: each copy is reversed, and the copies are
# listed in reverse order.

specimen_contact = [
    Segment("contact", s.curve.flattened(0.0).reversed()) for s in face if s.tag == "contact"
]
specimen_boundary = Boundary(
    [
        Segment("bottom", NurbsCurve.line([-half, -HEIGHT], [half, -HEIGHT])),
        Segment("side_right", NurbsCurve.line([half, -HEIGHT], [half, 0.0])),
        Segment("flank_right", NurbsCurve.line([half, 0.0], [ZONE, 0.0])),
        *specimen_contact[::-1],
        Segment("flank_left", NurbsCurve.line([-ZONE, 0.0], [-half, 0.0])),
        Segment("side_left", NurbsCurve.line([-half, 0.0], [-half, -HEIGHT])),
    ]
)

# %%
# Basis family and refinement per segment
# ---------------------------------------
#
# Each body takes a basis family by name (any name ``fretbem bases`` lists, or a
# :class:`~fretbem.basis.Basis` subclass) and a :class:`~fretbem.basis.Refinement` per
# tag. The contact segments are uniform, and alike on both bodies so their points face
# each other; the flanks are graded toward the contact zone
# (:meth:`Refinement.graded <fretbem.basis.Refinement.graded>` with ``toward`` the end
# nearest the zone, in the segment's own parameter), and the sides, top and bottom toward
# their corners, where the traction is singular.
from fretbem.basis import Refinement
from fretbem.bem.body import BemBody
from fretbem.conditions import Displacement, LoadingBlock
from fretbem.material import Material

FAMILY = "nurbs"
CONTACT_ELEMENTS = 16  # per contact segment: 3 x (16 + 2) = 54 node pairs with nurbs
corners = Refinement.graded(12, toward=(0.0, 1.0), ratio=50.0)
shared = {"contact": Refinement(CONTACT_ELEMENTS), "side_left": corners, "side_right": corners}
pad_refinement = {
    **shared,
    "top": corners,
    "flank_left": Refinement.graded(16, toward=1.0, ratio=30.0),  # the zone is at its end
    "flank_right": Refinement.graded(16, toward=0.0, ratio=30.0),  # ... and at its start
}
specimen_refinement = {
    **shared,
    "bottom": corners,
    "flank_right": Refinement.graded(16, toward=1.0, ratio=30.0),  # runs toward the zone
    "flank_left": Refinement.graded(16, toward=0.0, ratio=30.0),
}

# %%
# The pad is loaded through a rigid :class:`~fretbem.conditions.LoadingBlock` on its top:
# the load history prescribes that block's force (P, Q), and its displacement is an
# unknown. The specimen is clamped at its bottom.
material = Material(E, NU)
pad = BemBody(
    pad_boundary,
    material,
    [LoadingBlock("top")],
    basis=FAMILY,
    refinement=pad_refinement,
    name="pad",
)
specimen = BemBody(
    specimen_boundary,
    material,
    [Displacement("bottom")],
    basis=FAMILY,
    refinement=specimen_refinement,
    name="specimen",
)

from fretbem.output import figures as plot

fig, (whole, zoom) = plt.subplots(1, 2, figsize=(10, 4.5), layout="constrained")
for body in (pad, specimen):
    plot.draw(body, whole, lw=0.8)
    plot.draw(body, zoom, lw=0.8)
whole.set_aspect("equal")
whole.set_title("both bodies, element ends marked")
zoom.set_xlim(-1.2 * ZONE, 1.2 * ZONE)
zoom.set_ylim(-0.05, 0.05)
zoom.set_title("contact zone, y exaggerated: facing points")

# %%
# The load history
# ----------------
#
# A history is data: a tuple of :class:`~fretbem.simulation.LoadStep` records, each
# giving P and Q at its end (reached linearly in ``increments`` sub-increments). The
# first step must press the bodies together with Q = 0, and :math:`|Q|` must stay below f P
# (else there is gross sliding). Here: press, then two cycles of ±15 N/mm with a partial
# unloading to ±5 N/mm inside the first. The two contact faces are paired node to node
# (:class:`~fretbem.contact.pairs.NodeToNodePair`), and friction is the contact law's
# (:class:`~fretbem.contact.law.CoulombFriction`), which the simulation holds.
from fretbem.contact.law import CoulombFriction
from fretbem.contact.pairs import NodeToNodePair
from fretbem.simulation import LoadStep, Simulation, run

P = 100.0
steps = (
    LoadStep("A", P, 0.0),  # press
    LoadStep("B1", P, 15.0, increments=2),
    LoadStep("B2", P, 5.0, increments=2),  # partial unloading
    LoadStep("B3", P, 15.0, increments=2),  # reloading: back on the first curve
    LoadStep("C1", P, -15.0, increments=2),
    LoadStep("C2", P, -5.0, increments=2),  # partial unloading
    LoadStep("D", P, 15.0, increments=2),  # second cycle
    LoadStep("E", P, -15.0, increments=2),
)
simulation = Simulation(
    NodeToNodePair(pad, specimen), steps, law=CoulombFriction(FRICTION), name="rounded flat"
)
result = run(simulation)
print(result.table())

# %%
# The errors columns say ``n/a``: :class:`~fretbem.simulation.Simulation` compares with
# theory only when it is given a ``reference`` (the Cattaneo–Mindlin scene does it), and
# the rounded flat is not a Hertz contact. Its theory is short enough to write here.
#
# The rounded-flat punch in theory
# --------------------------------
#
# For elastically similar half-planes and a profile whose gap is g(x), a contact
# :math:`|x| < a` with the pressure bounded at both ends carries
#
# .. math::
#
#    p(x) = \frac{E^*}{2\pi}\sqrt{a^2-x^2}\;\mathrm{PV}\!\!\int_{-a}^{a}
#           \frac{g'(s)\,ds}{\sqrt{a^2-s^2}\,(s-x)},
#    \qquad
#    P = \frac{E^*}{2}\int_{-a}^{a}\frac{s\,g'(s)\,ds}{\sqrt{a^2-s^2}} .
#
# With :math:`g'(s) = (|s| - b)\,\mathrm{sign}(s)/R` outside the flat and
# :math:`\sin\varphi_0 = b/a`, both integrals are closed (Ciavarella, Hills and Monno
# 1998): p(x) is the function ``pressure`` below, and the load is
#
# .. math::
#
#    P(a) = \frac{E^*}{R}\Big[a^2\Big(\frac{\pi/2-\varphi_0}{2}
#           + \frac{\sin 2\varphi_0}{4}\Big) - a b\cos\varphi_0\Big]
#
# and under a tangential load the shear is f p(x; a) minus a corrective f p(x; c) of the
# same profile (Ciavarella 1998, Jäger 1998), with the stick zone c given by
# :math:`P(c) = P - |Q|/f`. For a load reversal from :math:`Q^*` the corrective is
# :math:`2 f p(x; c')` with :math:`P(c') = P - |Q^* - Q|/(2f)`, as in Mindlin–Deresiewicz.
from scipy.optimize import brentq

from fretbem.verification.closed_forms import effective_modulus

E_STAR = effective_modulus(E, NU, E, NU)


def load(a: float) -> float:
    """Normal load P of the rounded flat at contact half-width a >= b."""
    phi = math.asin(min(FLAT / a, 1.0))
    bracket = a * a * ((math.pi / 2 - phi) / 2 + math.sin(2 * phi) / 4)
    return E_STAR / RADIUS * (bracket - a * FLAT * math.cos(phi))


def half_width(normal_load: float) -> float:
    """Contact half-width a with P(a) = normal_load (a = b at zero load)."""
    if normal_load <= 0.0:
        return FLAT
    return brentq(lambda a: load(a) - normal_load, FLAT, 100 * FLAT + 10 * RADIUS)


def pressure(x: np.ndarray, a: float) -> np.ndarray:
    """Pressure p(x) of the rounded flat with contact half-width a."""
    x = np.asarray(x, float)
    out = np.zeros_like(x)
    inside = np.abs(x) < a
    xi = x[inside]
    root = np.sqrt(a * a - xi * xi)

    def log_term(s: float) -> np.ndarray:
        return np.log(np.abs((a * a - xi * s + root * math.sqrt(a * a - s * s)) / (s - xi)))

    phi = math.asin(min(FLAT / a, 1.0))
    out[inside] = (
        E_STAR
        / (2 * math.pi * RADIUS)
        * (
            (math.pi - 2 * phi) * root
            + (xi - FLAT) * (log_term(FLAT) - math.log(a))
            + (xi + FLAT) * (math.log(a) - log_term(-FLAT))
        )
    )
    return out


A_THEORY = half_width(P)
C_THEORY = half_width(P - 15.0 / FRICTION)  # stick zone at Q = 15 on first loading
C_UNLOAD_THEORY = half_width(P - 10.0 / (2 * FRICTION))  # after unloading 15 -> 5
print(f"theory: a = {A_THEORY:.4f} mm, c = {C_THEORY:.4f} mm at Q = 15, "
      f"c' = {C_UNLOAD_THEORY:.4f} mm after unloading to Q = 5")  # fmt: skip

# %%
# p, q and the stick zone along the history
# -----------------------------------------
#
# Each :class:`~fretbem.results.StepResult` holds p, q and the state of every pair. The
# pressure does not change with Q (similar materials); the shear follows the load, and
# returning to +15 after the partial unloading (B3) gives back the first +15 state (B1)
# exactly: the memory of friction.
first, unloaded, again = result["B1"], result["B2"], result["B3"]
x = first.x
fine = np.linspace(-ZONE, ZONE, 801)
q_first = FRICTION * (pressure(fine, A_THEORY) - pressure(fine, C_THEORY))
q_unloaded = q_first - 2 * FRICTION * (pressure(fine, A_THEORY) - pressure(fine, C_UNLOAD_THEORY))

fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True, layout="constrained")
for ax, step, theory in ((axes[0], first, q_first), (axes[1], unloaded, q_unloaded)):
    ax.plot(x, step.pressure, "o", ms=3, label="p, BEM")
    ax.plot(x, step.shear, "s", ms=3, mfc="none", label="q, BEM")
    ax.plot(fine, pressure(fine, A_THEORY), "k-", lw=1, label="p, theory")
    ax.plot(fine, theory, "k--", lw=1, label="q, theory")
    ax.axvspan(-FLAT, FLAT, color="0.9", zorder=0, label="flat")
    ax.set_title(f"Q = {step.tangential:g} N/mm ({step.name})")
    ax.set_xlabel("x (mm)")
axes[0].set_ylabel("traction (MPa)")
axes[0].legend(fontsize=8)
# sphinx_gallery_thumbnail_number = 2

# %%
# The state of every pair at every step (the thin lines mark the flat). Where a pair's
# shear sits exactly on the friction bound, as after reloading to the same load (B3), it
# may be reported as stick or as slip: the tractions are the same.
from fretbem.contact.pairs import STICK

fig = plot.stick_slip_figure(result)
fig.axes[0].axvline(-FLAT, color="k", lw=0.5)
fig.axes[0].axvline(FLAT, color="k", lw=0.5)

# %%
# The stick zone's half-width against theory. A reversal of Q by a swing ΔQ shrinks the
# stick zone to the c with :math:`P(c) = P - |\Delta Q|/(2f)`; the first loading from
# zero uses :math:`P - |Q|/f`. With Q cycled between ±15 and a partial unloading to ±5
# that gives three values: a (step A), c for a swing of 15 from zero or of 30 between
# ±15, and c' for a swing of 10. Reloading from +5 to +15 (B3) slips only outside c'
# and ends on the B1 tractions: the pairs between c and c' are on the friction bound
# without slipping, so either state is right for them; the figure marks both values.


def stick_half_width(step) -> float:
    """Edge of the stick zone: midway between the outermost sticking pair and the next pair
    outward, averaged over both sides."""
    edges = []
    for side in (step.x > 0, step.x < 0):
        x = np.abs(step.x[side])
        order = np.argsort(x)
        x, stick = x[order], (step.states[side] == STICK)[order]
        k = np.flatnonzero(stick).max()
        edges.append(0.5 * (x[k] + x[k + 1]) if k + 1 < len(x) else x[k])
    return float(np.mean(edges))


theory_c = {
    "A": A_THEORY,  # no tangential load: the whole contact sticks
    "B1": C_THEORY,  # 0 -> +15, first loading
    "B2": C_UNLOAD_THEORY,  # +15 -> +5, a swing of 10
    "B3": C_THEORY,  # +5 -> +15: back on the B1 tractions (c' also right, see above)
    "C1": C_THEORY,  # +15 -> -15, a swing of 30: P - 30 / (2 f) = P - 15 / f
    "C2": C_UNLOAD_THEORY,  # -15 -> -5, a swing of 10
    "D": C_THEORY,  # -15 -> -5 -> +15, one upward swing of 30
    "E": C_THEORY,  # +15 -> -15, a swing of 30
}
names = [s.name for s in result.steps]
bem_c = [stick_half_width(s) for s in result.steps]
fig, ax = plt.subplots(layout="constrained")
ax.plot(names, bem_c, "o-", label="BEM: edge of the sticking pairs")
ax.plot(names, [theory_c[n] for n in names], "kx", ms=10, mew=2, label="theory")
ax.plot(["B3"], [C_UNLOAD_THEORY], "k+", ms=10, mew=1, label="B3: c' (bound without slip)")
ax.axhline(A_THEORY, color="k", ls=":", lw=1, label="contact half-width a")
ax.set_ylabel("stick zone half-width c (mm)")
ax.set_xlabel("load step")
ax.legend()

# %%
# Key numbers
# -----------
#
# The pressure against the closed form (in percent of the peak pressure, root mean
# square over the pairs in contact, and the largest error, which sits at the contact edge), the
# stick zone against theory (within a pair spacing), and the memory of friction:
press = result["A"]
p_exact = pressure(press.x, A_THEORY)
P_PEAK = float(p_exact.max())
touching = np.abs(press.x) < A_THEORY
E_P_L2 = float(np.sqrt(np.mean((press.pressure - p_exact)[touching] ** 2)) / P_PEAK)
E_P_MAX = float(np.abs(press.pressure - p_exact).max() / P_PEAK)
q_exact = FRICTION * (pressure(x, A_THEORY) - pressure(x, C_THEORY))
E_Q_L2 = float(np.sqrt(np.mean((first.shear - q_exact)[touching] ** 2)) / (FRICTION * P_PEAK))
SPACING = float(np.diff(x).max())
STICK_ERROR = max(abs(c - theory_c[n]) for n, c in zip(names, bem_c, strict=True) if n != "B3")
MEMORY = float(np.abs(again.shear - first.shear).max() / (FRICTION * P_PEAK))
LOAD_BALANCE = abs(press.resultant[0] - P) / P
print(f"{len(x)} node pairs, largest spacing {SPACING:.4f} mm")
print(f"e_p: L2 {100 * E_P_L2:.3f} %, max {100 * E_P_MAX:.2f} % (at the contact edge)")
print(f"e_q at Q = +15: L2 {100 * E_Q_L2:.3f} %")
print(f"stick zone at Q = +15: {stick_half_width(first):.4f} mm, theory {C_THEORY:.4f} mm")
print(f"largest stick-zone error over the history (B3 aside): {STICK_ERROR:.4f} mm")
print(f"B3 (+15 again) against B1 (+15): max |dq| = {MEMORY:.1e} f p_peak")
print(f"integral of p = {press.resultant[0]:.4f} N/mm for P = {P:g}")
