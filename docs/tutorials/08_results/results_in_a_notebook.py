"""
A run in a notebook: display, xarray and the report
===================================================

What a run gives back in a notebook or a script: a one-line ``repr`` and an HTML table of
its steps (loads, errors beside their estimates, the stick zone beside the closed form's
[e - c, e + c], the checks), the same numbers as a labelled :class:`xarray.Dataset` with
units, a netCDF file, and the one-page report a test engineer keeps or sends.

The scene is the fretting rig of ``examples/fretting_rig.toml`` (a pad on a specimen with a
bulk stress in phase with Q), at 31 pairs, with a stress line below the trailing edge and a
quick fatigue map.
"""

# %%
# The scene, shown
# ----------------
# A scene file read into a record; in a notebook the last expression of a cell shows its
# table (``_repr_html_``), in a terminal its one line (``repr``).
from pathlib import Path

import attrs

import fretbem
from fretbem.scenes.file import load_scene

here = Path(fretbem.__file__).resolve().parents[2]
scene = load_scene(here / "examples" / "fretting_rig.toml", pairs=31)
scene = attrs.evolve(
    scene,
    extras={
        "stress": {"figures": False, "vtk": False,
                   "line": [{"x": "trailing-edge", "depth": 0.6, "n": 25}]},
        "fatigue": {"material": "Al 7050-T7451", "methods": ["swt"], "map_points": [21, 9]},
    },
)  # fmt: skip
print(repr(scene))
scene

# %%
# The run, shown
# --------------
# ``run_scene`` solves, estimates the discretisation error from a second level, checks every
# step and assesses the fatigue request. Its result prints in one line; in a notebook its
# table has one row per step.
run = fretbem.run_scene(scene)
result = run.result
print(repr(result))
result

# %%
# One step:
print(repr(result["B"]))
result["B"]

# %%
# Labelled: the run as an xarray Dataset
# --------------------------------------
# Dimensions ``step`` and ``pair``; the pair positions ``x`` and the step names are
# coordinates; every variable carries its unit, long name and sign convention (CF
# attributes); the zones, errors, estimates and checks are variables, the Hertz numbers and
# the accuracy record attributes.
ds = result.to_xarray()
ds

# %%
# Select by label: the shear at step B, its unit, and the closed form's stick zone.
q_B = ds.q.sel(step="B")
print(q_B.attrs["units"], q_B.attrs["comment"])
print("theory stick zone at B:", ds.theory_stick_zone.sel(step="B").values, "mm")
print("Hertz a =", round(ds.attrs["hertz_a"], 4), "mm, p0 =", round(ds.attrs["hertz_p0"], 2), "MPa")
HERTZ_A = ds.attrs["hertz_a"]

# %%
# xarray draws with the labels and units it carries:
import matplotlib.pyplot as plt

fig, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
for name in ("B", "C", "D"):
    ds.q.sel(step=name).plot.line(x="x", ax=ax, marker=".", label=f"step {name}")
ax.legend()
ax.set_title("shear traction q per step")

# %%
# The stresses below the trailing edge, labelled the same way (the line's x was given as
# ``"trailing-edge"``: placed at -a for this run):
from fretbem.stress import evaluate_stress_request, stress_request_from_dict

stresses = evaluate_stress_request(result, stress_request_from_dict(scene.extras["stress"]))
print(repr(stresses))
sds = stresses.to_xarray()
LINE_X = float(sds.line0_x)
sds.line0_sigma_xx

# %%
# and the fatigue report:
print(repr(run.fatigue))
run.fatigue.to_xarray().swt

# %%
# netCDF and the report page
# --------------------------
# ``fretbem run scene.toml --netcdf --report`` writes results.nc (and stress.nc,
# fatigue.nc) and report.html beside the other files; from Python, name the writers:
from fretbem.output.write import WRITERS
from fretbem.views import read_netcdf

out = run.write(
    "notebook-out", overwrite=True, writers=["csv", "json", "units", "figures", "stress",
                                             "fatigue", "netcdf", "report"],
)  # fmt: skip
back = read_netcdf(out / "results.nc")
print("round trip identical:", back.identical(ds))
REPORT = out / "report.html"
print(f"{REPORT}: {REPORT.stat().st_size / 1024:.0f} kB, figures embedded; writers:",
      ", ".join(WRITERS))  # fmt: skip
