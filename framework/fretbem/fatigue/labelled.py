"""A fatigue report as an xarray Dataset: the parameter maps over (depth, x), the profiles
below each hot spot, the Ruiz parameters along the surface, and the hot spots, critical
distance values and lives as attributes of each method's map."""

from __future__ import annotations

import html
import math

import numpy as np

from fretbem.views.cf import CONVENTIONS, attributes, clean_attrs
from fretbem.views.display import html_table

__all__ = ["fatigue_dataset", "fatigue_html", "fatigue_repr", "life_text"]

#: units of each parameter (CF: "1" dimensionless)
PARAMETER_UNITS = {
    "swt": "MPa", "findley": "MPa", "fatemi_socie": "1", "mwcm": "MPa", "stress_life": "MPa",
    "strain_life": "1",
}  # fmt: skip
RUIZ = {
    "shear_traction_max": ("MPa", "largest |q| over the cycle"),
    "slip_amplitude": ("mm", "slip amplitude over the cycle"),
    "surface_stress_xx_max": ("MPa", "largest surface sigma_xx over the cycle"),
    "f1": ("N mm-1", "Ruiz F1 = tau delta"),
    "f2": ("MPa N mm-1", "Ruiz F2 = sigma_xx tau delta"),
}


def _cycles(life) -> float:
    if life is None or math.isinf(life.cycles):
        return math.nan
    return float(life.cycles)


def fatigue_dataset(report):
    """:class:`xarray.Dataset` of a :class:`~fretbem.fatigue.run.FatigueReport`."""
    import xarray as xr

    nx, nz = len(report.map_x), len(report.map_depth)
    coords = {
        "x": ("x", np.asarray(report.map_x, float), attributes("x")),
        "depth": ("depth", np.asarray(report.map_depth, float), attributes("depth")),
        "cycle_step": (
            "cycle_step",
            np.asarray(report.cycle_steps, np.int32),
            {"long_name": "step index of the evaluated cycle"},
        ),
    }
    data = {}
    for method, rep in report.methods.items():
        unit = PARAMETER_UNITS.get(method, "1")
        life_hot, life_cd = rep.life_hot_spot, rep.life_critical_distance
        meta = {
            "units": unit,
            "long_name": f"{method} critical-plane parameter",
            "hot_spot_x": rep.hot_spot[0],
            "hot_spot_depth": rep.hot_spot[1],
            "value_at_hot_spot": float(rep.at_hot_spot.value[0]),
            "critical_plane_normal_angle_deg": float(rep.at_hot_spot.normal_angle_deg[0]),
            "life_at_hot_spot_cycles": _cycles(life_hot),
            "runout_at_hot_spot": None if life_hot is None else life_hot.runout,
            "life_at_critical_distance_cycles": _cycles(life_cd),
            "life_message": rep.life_message or None,
        }
        if rep.critical_distance is not None:
            t = rep.critical_distance
            meta.update(
                critical_distance_mm=t.critical_distance,
                point_method_value=t.point_value,
                line_method_value=t.line_value,
                area_method_value=t.area_value,
            )
        values = np.asarray(rep.map.value, float).reshape(nz, nx)
        data[method] = (("depth", "x"), values, clean_attrs(meta))
        dim = f"{method}_distance"
        coords[dim] = (
            dim,
            np.asarray(rep.profile_distance, float),
            {"units": "mm", "long_name": "distance from the hot spot along the critical direction"},
        )
        data[f"{method}_profile"] = (
            (dim,),
            np.asarray(rep.profile_value, float),
            {"units": unit, "long_name": f"{method} below the hot spot"},
        )
    if report.ruiz is not None:
        coords["ruiz_x"] = ("ruiz_x", np.asarray(report.ruiz.x, float), attributes("x"))
        for name, (unit, long_name) in RUIZ.items():
            data[f"ruiz_{name}"] = (
                ("ruiz_x",),
                np.asarray(getattr(report.ruiz, name), float),
                {"units": unit, "long_name": long_name},
            )
    material = report.request.material
    meta = {
        "Conventions": CONVENTIONS,
        "title": "fretbem fretting-fatigue assessment",
        "material": material.name,
        "methods": " ".join(report.methods),
        "notes": list(report.notes),
        "depth_convention": "depth > 0 into the body from its contact surface",
    }
    return xr.Dataset(data, coords=coords, attrs=clean_attrs(meta))


def life_text(life) -> str:
    """Cycles of a life estimate ("run-out", "none" without one)."""
    if life is None:
        return "none"
    if life.runout or math.isinf(life.cycles):
        return "run-out"
    return f"{life.cycles:.3g}"


def fatigue_repr(report) -> str:
    """One line: material, and per method the hot spot, its value and life."""
    parts = []
    for method, rep in report.methods.items():
        unit = PARAMETER_UNITS.get(method, "1")
        parts.append(
            f"{method} {float(rep.at_hot_spot.value[0]):.4g}"
            f"{'' if unit == '1' else ' ' + unit} at x={rep.hot_spot[0]:.4g} "
            f"depth={rep.hot_spot[1]:.4g}, life {life_text(rep.life_hot_spot)}"
        )
    return f"<FatigueReport {report.request.material.name}: " + "; ".join(parts) + ">"


def fatigue_rows(report) -> list[tuple]:
    """Per method: hot spot x and depth (mm), value, unit, the critical-distance value and
    the lives at the hot spot and at the critical distance."""
    rows = []
    for method, rep in report.methods.items():
        cd = rep.critical_distance
        rows.append(
            (
                method,
                f"{rep.hot_spot[0]:.4g}",
                f"{rep.hot_spot[1]:.4g}",
                f"{float(rep.at_hot_spot.value[0]):.4g}",
                PARAMETER_UNITS.get(method, "1"),
                "n/a" if cd is None else f"{cd.point_value:.4g}",
                life_text(rep.life_hot_spot),
                life_text(rep.life_critical_distance),
            )
        )
    return rows


FATIGUE_HEADER = (
    "method",
    "hot spot x (mm)",
    "depth (mm)",
    "value",
    "unit",
    "point method",
    "life at hot spot",
    "life at L",
)


def fatigue_html(report) -> str:
    """The methods' hot spots and lives as an HTML table, with the notes."""
    caption = f"fatigue: {report.request.material.name}"
    notes = "".join(f"<div>note: {html.escape(n)}</div>" for n in report.notes)
    return f"<div>{html_table(FATIGUE_HEADER, fatigue_rows(report), caption)}{notes}</div>"
