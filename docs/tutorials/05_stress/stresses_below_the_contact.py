"""
Stresses below the contact: depth profile at the trailing edge and contour maps
===============================================================================

Fretting cracks start at the contact edge where the surface tension peaks and grow in the
first tens of micrometres below it. This tutorial solves the reference Cattaneo-Mindlin
cycle (61 pairs) and evaluates the stress tensor

1. along the contact surface for every step,
2. on a depth profile below the trailing edge, against the closed form
   (McEwen + Smith-Liu superposed),
3. on a grid below the contact, as contour maps of sigma_xx and von Mises with the stick
   and slip zones marked, and as files (CSV, ParaView time series).
"""

# %%
# Solve the reference cycle
# -------------------------
#
# Units mm, N/mm, MPa. Steps A..E: P = 100 N/mm, Q = 0, +18, 0, -18, 0 N/mm.
import matplotlib.pyplot as plt
import numpy as np

from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run
from fretbem.stress import StressEvaluator, run_stress_request, stress_request_from_dict
from fretbem.stress import closed_form as cf
from fretbem.stress.figures import plot_contour_maps
from fretbem.stress.output import von_mises
from fretbem.stress.request import StressGrid, grid_points

simulation = cattaneo_mindlin()
result = run(simulation)
hertz = simulation.reference.hertz
A, P0, F = hertz.half_width, hertz.peak_pressure, 0.3
RADIUS = 70.0
C = A * np.sqrt(1 - 18.0 / (F * 100.0))  # stick half-width at step B
print(f"a = {A:.4f} mm, p0 = {P0:.1f} MPa, c/a = {C / A:.3f}")

# %%
# The surface stress along the contact
# ------------------------------------
#
# Points on the specimen's top face (an arc of radius 70 mm through the origin). On the
# boundary the stress comes from the traction and the tangential derivative of the
# displacement (Hooke's law in the local frame). At step B the shear on the specimen acts
# in +x and stretches the surface behind it: sigma_xx peaks at the edge x = -a.
x = np.linspace(-1.5 * A, 1.5 * A, 301)
surface = np.column_stack([x, np.sqrt(RADIUS**2 - x**2) - RADIUS])
on_surface = StressEvaluator(result, surface, "lower").steps()  # (5 steps, 301, 4)
fig, ax = plt.subplots(figsize=(6.4, 4))
for k, step in enumerate(result.steps):
    ax.plot(x / A, on_surface[k, :, 0] / P0, label=f"{step.name}: Q = {step.tangential:g}")
exact = cf.surface_sigma_xx(x, a=A, p0=P0, f=F, c=C)
ax.plot(x / A, exact / P0, "k:", label="B, half-plane closed form")
ax.set_xlabel("x / a")
ax.set_ylabel(r"surface $\sigma_{xx} / p_0$")
ax.legend(fontsize=8)
PEAK_X = x[np.argmax(on_surface[1, :, 0])]
PEAK_SXX = on_surface[1, :, 0].max()
print(f"step B: peak surface sigma_xx {PEAK_SXX:.1f} MPa at x = {PEAK_X / A:.3f} a "
      f"(closed form {cf.surface_sigma_xx(-A, a=A, p0=P0, f=F, c=C):.1f} MPa at -a)")  # fmt: skip

# %%
# Depth profile below the trailing edge
# -------------------------------------
#
# Depths from 0 to 3 a below x = -a, graded toward the surface. The closed form is the
# half-plane's; the finite specimen (6.5 mm wide) adds a nearly uniform sigma_xx of a few
# MPa: its free sides do not carry the compressive side tractions of the half-plane.
depth = np.concatenate([[0.0], np.geomspace(1e-3, 3.0, 60)]) * A
x_edge = -A
y_surface = np.sqrt(RADIUS**2 - x_edge**2) - RADIUS
profile = StressEvaluator(result, np.column_stack([np.full_like(depth, x_edge), y_surface - depth]))
below = profile.step("B")
closed = cf.cattaneo_mindlin_stress(x_edge, depth, a=A, p0=P0, f=F, c=C, nu=0.33)
fig, ax = plt.subplots(figsize=(6.4, 4))
names = [r"$\sigma_{xx}$", r"$\sigma_{yy}$", r"$\sigma_{xy}$", r"$\sigma_{zz}$"]
for k, name in enumerate(names):
    line = ax.semilogx(depth[1:] / A, below[1:, k] / P0, label=name)[0]
    ax.semilogx(depth[1:] / A, closed[1:, k] / P0, ":", color=line.get_color())
ax.set_xlabel("depth / a below x = -a")
ax.set_ylabel("stress / p0 (dotted: half-plane closed form)")
ax.legend(fontsize=8)
PROFILE_ERROR = np.abs(below - closed).max(axis=0) / P0
print("max |BEM - closed form| / p0 on the profile (sxx, syy, sxy, szz):",
      np.round(PROFILE_ERROR, 4))  # fmt: skip

# %%
# Contour maps at the most loaded step
# ------------------------------------
#
# A ``[stress]`` request (the same table a scene file takes) evaluates a grid graded toward
# the surface for every step, writes CSV tables and a ParaView time series
# (``stress_grid.pvd``), and draws the contour maps at the step of largest absolute Q with the
# stick (blue) and slip (red) pairs on the surface.
request = stress_request_from_dict(
    {
        "line": {"x": -A, "depth": 3 * A, "n": 40},
        "grid": {"x": [-2 * A, 2 * A], "depth": 1.5 * A, "nx": 121, "ny": 45, "grading": 10.0},
    }
)
files = run_stress_request(result, request, "stress-out")
for role, path in files.items():
    print(f"{role:>9}: {path}")

# %%
# The same grid drawn here: sigma_xx (tension behind the trailing edge, compression under
# the contact) and von Mises (its maximum below the surface, shifted by the shear).
model = simulation.prepare().pair.side("lower")[0]
grid = StressGrid(x=(-2 * A, 2 * A), depth=1.5 * A, nx=121, ny=45, grading=10.0)
points, xs, depths = grid_points(model, grid, "lower")
stress_b = StressEvaluator(result, points.reshape(-1, 2)).step("B").reshape(*points.shape[:2], 4)
VM_MAX = von_mises(stress_b).max()
VM_MAX_DEPTH = depths[np.unravel_index(np.argmax(von_mises(stress_b)), stress_b.shape[:2])[0]]
print(f"step B: von Mises max {VM_MAX:.1f} MPa at depth {VM_MAX_DEPTH / A:.2f} a")

step_b = result.steps[1]
plot_contour_maps("contours.png", xs, depths, stress_b, pair_x=step_b.x, states=step_b.states,
                  title="specimen at step B (Q = +18 N/mm)")  # fmt: skip
image = plt.imread("contours.png")
fig, ax = plt.subplots(figsize=(11, 4.2))
ax.imshow(image)
ax.set_axis_off()
plt.show()
