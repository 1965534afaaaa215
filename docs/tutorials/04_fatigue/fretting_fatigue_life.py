"""
Fretting-fatigue life from the Cattaneo-Mindlin cycle
=====================================================

A cylindrical pad on a Ti-6Al-4V specimen, partial slip under a cyclic tangential load
with an in-phase bulk stress. The stress cycle here is the closed-form half-plane field
(Hertz + Cattaneo-Mindlin with Masing reversals + the Nowell-Hills offset,
:class:`~fretbem.fatigue.CattaneoMindlinCycle`); a simulation's stresses go through the
same calls. The tutorial finds

1. the hot spot and its critical plane for each parameter,
2. the critical-distance values and a life per method,
3. the Ruiz F2 along the surface,
4. the size effect: five pads at the same p0, Q/fP and bulk stress,
5. the same evaluation on the stresses of a boundary-element simulation.
"""

# %%
# The rig and its cycle
# ---------------------
#
# Units mm, N/mm, MPa. At constant peak pressure the contact half-width grows with the
# pad radius, a = 2 p0 R / E*. The load goes 0 -> +Q -> -Q -> +Q with the bulk stress in
# phase; the evaluated cycle is the last full reversal (+Q -> -Q -> +Q).
import matplotlib.pyplot as plt
import numpy as np

from fretbem.fatigue import (
    CattaneoMindlinCycle,
    critical_distance_values,
    critical_plane_parameters,
    fatigue_request_from_dict,
    last_full_reversal,
    run_fatigue,
)
from fretbem.fatigue.output import plot_depth_profile, plot_parameter_map, plot_ruiz

E, NU = 116000.0, 0.342  # Ti-6Al-4V, from the library's sources
E_STAR = E / (2 * (1 - NU**2))
P0, FRICTION, Q_RATIO, BULK = 300.0, 0.6, 0.5, 80.0
A = 0.5
RADIUS = A * E_STAR / (2 * P0)
print(f"pad radius R = {RADIUS:.1f} mm for a = {A} mm at p0 = {P0} MPa")

rig = CattaneoMindlinCycle(
    a=A, p0=P0, f=FRICTION, tangential_ratio=Q_RATIO, sigma_bulk_max=BULK, nu=NU
)
print("Q/(fP) per step:", np.round(rig.driver, 3))
print("cycle steps:", last_full_reversal(rig.driver))

# %%
# The request
# -----------
#
# Ti-6Al-4V's library entry has sourced strain-life constants (SWT and Fatemi-Socie lives
# follow) but no Findley or Fatemi-Socie factor k, no torsion fatigue limit and no
# threshold: the values below are **illustrative user input**, marked as such in the
# report. MWCM therefore gets a parameter and a plane but no life, and says why.
request = fatigue_request_from_dict(
    {
        "material": "Ti-6Al-4V",
        "constants": {"findley_k": 0.3, "fatemi_socie_k": 0.5},
        "critical_distance": 0.05,
        "map_points": [61, 31],
    }
)
report = run_fatigue(rig, request)
for note in report.notes:
    print("note:", note)

# %%
# Hot spot, critical plane, critical distances and life per method
# -----------------------------------------------------------------
#
# With these signs the surface tension peaks at x = -a at +Q; the bulk stress adds to it
# there, so the trailing edge x = -a is the hot spot of the tensile parameters.
HOT_SPOT = {}
LIFE = {}
print(
    f"{'method':<13} {'x (mm)':>8} {'theta':>6} {'tilt':>5} {'hot spot':>10} "
    f"{'L/2':>9} {'line':>9} {'area':>9}  life at hot spot / at L/2"
)
for m, rep in report.methods.items():
    t = rep.critical_distance
    HOT_SPOT[m] = rep.hot_spot[0]
    lives = [
        "-" if life is None else ("run-out" if life.runout else f"{life.cycles:.3g}")
        for life in (rep.life_hot_spot, rep.life_critical_distance)
    ]
    LIFE[m] = rep.life_hot_spot
    print(
        f"{m:<13} {rep.hot_spot[0]:8.4f} {rep.at_hot_spot.normal_angle_deg[0]:6.1f} "
        f"{rep.at_hot_spot.normal_tilt_deg[0]:5.1f} {rep.at_hot_spot.value[0]:10.4g} "
        f"{t.point_value:9.4g} {t.line_value:9.4g} {t.area_value:9.4g}  {' / '.join(lives)}"
    )
SWT_HOT_SPOT = report.methods["swt"].at_hot_spot.value[0]
SWT_LIFE = report.methods["swt"].life_hot_spot.cycles

# %%
# The SWT map below the contact: the ticks are the traces of the critical planes in the
# x-y plane; near the trailing edge they stand almost perpendicular to the surface.
plot_parameter_map(report, "swt")
plt.show()

# %%
# SWT along the critical direction (straight down) from the hot spot: the steep gradient
# is why the value at L/2 is far below the surface peak.
plot_depth_profile(report, "swt")
plt.show()

# %%
# Ruiz F2 along the surface
# -------------------------
#
# The closed-form slip is exact without bulk stress, so the Ruiz parameters use the same
# rig with sigma_B = 0 (a simulation provides its own slip). F2 peaks in the slip zone
# near the contact edges, where tension, shear and slip all are large.
ruiz_rig = CattaneoMindlinCycle(
    a=A, p0=P0, f=FRICTION, tangential_ratio=Q_RATIO, nu=NU, contact_modulus=E_STAR
)
ruiz_report = run_fatigue(
    ruiz_rig,
    fatigue_request_from_dict(
        {
            "material": "Ti-6Al-4V",
            "methods": ["swt"],
            "critical_distance": 0.05,
            "map_points": [21, 9],
        }
    ),
)
RUIZ_F2_MAX_X = ruiz_report.ruiz.f2_max_location
print(
    f"F2 largest at x = {RUIZ_F2_MAX_X:.4f} mm (contact edge at +-{A} mm, "
    f"stick zone +-{A * np.sqrt(1 - Q_RATIO):.4f} mm)"
)
plot_ruiz(ruiz_report)
plt.show()

# %%
# Size effect
# -----------
#
# Five pads at the same p0, Q/fP and bulk stress: the field is the same function of
# (x/a, depth/a), so the surface SWT is identical, while at a fixed L = 0.05 mm the
# smaller pads' steeper gradients lower the critical-distance values, and with them the
# predicted damage: the classical size effect of fretting tests.
L = 0.05
rows = []
for a in (0.125, 0.25, 0.5, 1.0, 2.0):
    cm = CattaneoMindlinCycle(
        a=a, p0=P0, f=FRICTION, tangential_ratio=Q_RATIO, sigma_bulk_max=BULK, nu=NU
    )
    steps = last_full_reversal(cm.driver)

    def swt_at(points, cm=cm, steps=steps):
        stress = cm.stress_at(points)[steps]
        return critical_plane_parameters(stress, E=E, nu=NU, methods=("swt",))["swt"].value

    surface = swt_at(np.array([[-a, 0.0]]))[0]
    tcd = critical_distance_values(swt_at, (-a, 0.0), L)
    rows.append(
        (a, a * E_STAR / (2 * P0), surface, tcd.point_value, tcd.line_value, tcd.area_value)
    )
SIZE_EFFECT = np.array(rows)
print(f"{'a (mm)':>7} {'R (mm)':>7} {'SWT surface':>12} {'point':>8} {'line':>8} {'area':>8}")
for row in SIZE_EFFECT:
    print(f"{row[0]:7.3f} {row[1]:7.1f} {row[2]:12.4f} {row[3]:8.4f} {row[4]:8.4f} {row[5]:8.4f}")

fig, ax = plt.subplots(figsize=(6, 3.6), layout="constrained")
ax.semilogx(SIZE_EFFECT[:, 1], SIZE_EFFECT[:, 2], "k--", label="surface (hot spot)")
for col, name in ((3, "point method"), (4, "line method"), (5, "area method")):
    ax.semilogx(SIZE_EFFECT[:, 1], SIZE_EFFECT[:, col], "o-", label=name)
ax.set_xlabel("pad radius R (mm)")
ax.set_ylabel("SWT (MPa)")
ax.set_title(f"Size effect at p0 = {P0:.0f} MPa, Q/fP = {Q_RATIO}, L = {L} mm")
ax.legend(fontsize=8)
plt.show()

# %%
# The same evaluation on a boundary-element simulation
# ----------------------------------------------------
#
# The reference scene (cylinder on a block, Q = 0 -> +Q -> 0 -> -Q -> 0, no bulk stress)
# solved by the boundary-element method:
# :class:`~fretbem.fatigue.from_simulation.SimulationStressHistory` evaluates the
# specimen's stresses at any points through
# :mod:`fretbem.stress.evaluate`. The cycle is B..E, the last full reversal of Q. The
# material is Al 7050-T7451 from the library, whose sourced Delta K_th and plain fatigue
# limit give L = 0.113 mm; its elastic constants are replaced by the scene's (user input),
# and as the library has no strain-life constants for it, the report gives parameters and
# critical-distance values but no life, and says which constants are missing.
from fretbem.fatigue.from_simulation import SimulationStressHistory
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run

simulation = cattaneo_mindlin(basis="nurbs", pairs=31)
bem_result = run(simulation)
scene_material = simulation.pair.lower.material
bem_report = run_fatigue(
    SimulationStressHistory(bem_result),
    fatigue_request_from_dict(
        {
            "material": "Al 7050-T7451",
            "constants": {"E": scene_material.E, "nu": scene_material.nu},
            "methods": ["swt", "mwcm"],
            "map_points": [21, 9],
        }
    ),
)
BEM_CYCLE = [bem_result.steps[i].name for i in bem_report.cycle_steps]
BEM_HOT_SPOT = {m: rep.hot_spot[0] for m, rep in bem_report.methods.items()}
BEM_HALF_WIDTH = simulation.reference.hertz.half_width
print("cycle:", BEM_CYCLE, f" L = {bem_report.request.critical_distance:.4f} mm")
for m, rep in bem_report.methods.items():
    t = rep.critical_distance
    print(
        f"{m}: hot spot x = {rep.hot_spot[0]:.4f} mm (a = {BEM_HALF_WIDTH:.4f} mm), "
        f"value {rep.at_hot_spot.value[0]:.4g}, point {t.point_value:.4g}, "
        f"line {t.line_value:.4g}, area {t.area_value:.4g}; {rep.life_message[:60]}..."
    )
plot_parameter_map(bem_report, "swt")
plt.show()
