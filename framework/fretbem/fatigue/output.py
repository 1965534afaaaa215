"""Writers of a fatigue report: fatigue.json and the three figures (matplotlib, imported lazily).

Every number in fatigue.json says what it is (amplitude, range, max, mean) and its unit in its
key; a run-out is ``"cycles": null`` with ``"runout": true`` and a message.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from .critical_plane import CriterionResult
from .life import LifeEstimate
from .mean_stress import CORRECTIONS_OF
from .run import FatigueReport

__all__ = [
    "fatigue_summary",
    "plot_depth_profile",
    "plot_parameter_map",
    "plot_ruiz",
    "write_fatigue",
]

UNITS = {
    "swt": "MPa", "findley": "MPa", "fatemi_socie": "-", "mwcm": "MPa", "stress_life": "MPa",
    "strain_life": "-",
}  # fmt: skip
LABELS = {
    "swt": "SWT = sigma_n,max eps_a (MPa)",
    "findley": "Findley tau_a + k sigma_n,max (MPa)",
    "fatemi_socie": "Fatemi-Socie gamma_a (1 + k sigma_n,max / sigma_y)",
    "mwcm": "MWCM shear stress amplitude tau_a (MPa)",
    "stress_life": "equivalent fully reversed normal stress amplitude sigma_ar (MPa)",
    "strain_life": "normal strain amplitude eps_a",
}


def _finite(value: float) -> float | None:
    """A number for fatigue.json; None where the mean stress reaches the correction's limit."""
    return float(value) if math.isfinite(value) else None


def _life(life: LifeEstimate | None):
    if life is None:
        return None
    return {
        "cycles": None if math.isinf(life.cycles) else life.cycles,
        "runout": life.runout,
        "parameter": _finite(life.parameter),
        "message": life.message,
    }


def _plane(r: CriterionResult, i: int = 0) -> dict:
    return {
        "normal_angle_deg": float(r.normal_angle_deg[i]),
        "normal_tilt_deg": float(r.normal_tilt_deg[i]),
        "shear_stress_amplitude_MPa": float(r.shear_stress_amplitude[i]),
        "normal_stress_max_MPa": float(r.normal_stress_max[i]),
        "normal_stress_amplitude_MPa": float(r.normal_stress_amplitude[i]),
        "normal_stress_mean_MPa": float(r.normal_stress_mean[i]),
        "normal_strain_amplitude": float(r.normal_strain_amplitude[i]),
        "shear_strain_amplitude": float(r.shear_strain_amplitude[i]),
    }


def fatigue_summary(report: FatigueReport) -> dict:
    """The report as plain JSON-able data (what fatigue.json holds)."""
    req = report.request
    out = {
        "material": {
            "name": req.material.name,
            "constants": dict(req.material.values),
            "sources": dict(req.material.sources),
            "estimated": req.material.derived,
        },
        "cycle_steps": [int(s) for s in report.cycle_steps],
        "critical_distance_mm": req.critical_distance,
        "plane_search": "in-plane only (planes containing z)" if req.search.in_plane_only else "3D",
        "runout_cycles": req.runout_cycles,
        "methods": {},
        "notes": list(report.notes),
    }
    for m, rep in report.methods.items():
        entry = {
            "parameter_unit": UNITS[m],
            "hot_spot": {"x_mm": rep.hot_spot[0], "depth_mm": rep.hot_spot[1]},
            "parameter_at_hot_spot": _finite(rep.at_hot_spot.value[0]),
            "critical_plane_at_hot_spot": _plane(rep.at_hot_spot),
            "critical_direction": {"x": rep.direction[0], "depth": rep.direction[1]},
            "life_at_hot_spot": _life(rep.life_hot_spot),
            "life_at_critical_distance": _life(rep.life_critical_distance),
        }
        if m == "mwcm":
            entry["rho_at_hot_spot"] = float(rep.at_hot_spot.rho[0])
        if m in CORRECTIONS_OF:
            entry["mean_stress_correction"] = req.mean_stress
        if rep.critical_distance is not None:
            t = rep.critical_distance
            entry["critical_distance"] = {
                "L_mm": t.critical_distance,
                "point_method_value": _finite(t.point_value),
                "point_method_location_mm": list(t.point),
                "line_method_value": _finite(t.line_value),
                "area_method_value": _finite(t.area_value),
                "area_method_radius_mm": t.area_radius,
            }
        if rep.life_message:
            entry["life_message"] = rep.life_message
        out["methods"][m] = entry
    if report.ruiz is not None:
        r = report.ruiz
        i = int(np.argmax(r.f2))
        out["ruiz"] = {
            "f2_max_x_mm": float(r.x[i]),
            "f1_at_f2_max_N_per_mm": float(r.f1[i]),
            "f2_max_MPa_N_per_mm": float(r.f2[i]),
            "slip_amplitude_at_f2_max_mm": float(r.slip_amplitude[i]),
            "shear_traction_max_at_f2_max_MPa": float(r.shear_traction_max[i]),
            "surface_stress_xx_max_at_f2_max_MPa": float(r.surface_stress_xx_max[i]),
        }
    return out


def _life_text(life: LifeEstimate | None, message: str) -> str:
    if life is None:
        return "none (missing constants: see the notes)" if message else "none"
    return "run-out" if life.runout else f"N = {life.cycles:.3g}"


def format_report(report: FatigueReport) -> str:
    """Plain-text summary for a terminal: hot spot, critical plane, values and lives."""
    req = report.request
    lines = [
        f"fatigue: material {req.material.name}, cycle steps {report.cycle_steps.tolist()}, "
        f"planes {'in-plane only' if req.search.in_plane_only else '3D'}"
        + (f", L = {req.critical_distance:.4g} mm" if req.critical_distance else ""),
    ]
    for m, rep in report.methods.items():
        hot = rep.at_hot_spot
        lines.append(
            f"  {m}: hot spot x = {rep.hot_spot[0]:.4g} mm, depth = {rep.hot_spot[1]:.4g} mm; "
            f"plane normal {hot.normal_angle_deg[0]:.1f} deg (tilt {hot.normal_tilt_deg[0]:.1f}); "
            f"value {hot.value[0]:.4g} {UNITS[m]}"
        )
        t = rep.critical_distance
        if t is not None:
            lines.append(
                f"      critical distance: point {t.point_value:.4g}, line {t.line_value:.4g}, "
                f"area {t.area_value:.4g}"
            )
        lines.append(
            f"      life: hot spot {_life_text(rep.life_hot_spot, rep.life_message)}; "
            f"critical distance {_life_text(rep.life_critical_distance, rep.life_message)}"
        )
    if report.ruiz is not None:
        lines.append(f"  Ruiz F2 largest at x = {report.ruiz.f2_max_location:.4g} mm")
    lines.extend(f"  note: {n}" for n in report.notes)
    return "\n".join(lines)


def plot_parameter_map(report: FatigueReport, method: str, ax=None, ticks: int = 12):
    """Parameter map below the contact with the critical-plane traces as short ticks."""
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection

    rep = report.methods[method]
    xs, zs = report.map_x, report.map_depth
    values = rep.map.value.reshape(zs.size, xs.size)
    if not np.all(np.isfinite(values)):  # stress_life where the mean reaches the limit stress
        values = np.ma.masked_invalid(values)
    if ax is None:
        _, ax = plt.subplots(figsize=(7, 3.6), layout="constrained")
    mesh = ax.pcolormesh(xs, zs, values, shading="gouraud", cmap="viridis")
    ax.figure.colorbar(mesh, ax=ax, label=LABELS[method])
    ix = np.unique(np.linspace(0, xs.size - 1, ticks).round().astype(int))
    iz = np.unique(np.linspace(0, zs.size - 1, max(ticks // 2, 2)).round().astype(int))
    theta = np.deg2rad(rep.map.normal_angle_deg.reshape(zs.size, xs.size))[np.ix_(iz, ix)]
    length = 0.35 * (xs[-1] - xs[0]) / ticks
    # the plane's trace in the x-y plane is perpendicular to the normal's projection; shown
    # in (x, depth) axes, depth = -y; all traces are one artist
    tx, ty = length * -np.sin(theta), length * np.cos(theta)
    x, z = np.meshgrid(xs[ix], zs[iz])
    ends = np.stack([np.stack([x - tx, z + ty], -1), np.stack([x + tx, z - ty], -1)], -2)
    traces = LineCollection(ends.reshape(-1, 2, 2), colors="white", linewidths=0.8,
                            capstyle="projecting", zorder=2)  # fmt: skip
    ax.add_collection(traces)
    ax.plot(*rep.hot_spot, marker="*", color="red", ms=12, label="hot spot")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("depth (mm)")
    ax.set_xlim(xs[0], xs[-1])
    ax.set_ylim(zs[-1], zs[0])
    ax.set_aspect("equal", adjustable="box")
    ax.legend(loc="lower right", fontsize=9)
    ax.set_title(f"{method}: parameter map, ticks = critical-plane traces")
    return ax


def plot_depth_profile(report: FatigueReport, method: str, ax=None):
    """Parameter against distance from the hot spot along the critical direction, L marked."""
    import matplotlib.pyplot as plt

    rep = report.methods[method]
    if ax is None:
        _, ax = plt.subplots(figsize=(6, 3.6), layout="constrained")
    ax.plot(rep.profile_distance, rep.profile_value, color="C0")
    tcd = rep.critical_distance
    if tcd is not None:
        L = tcd.critical_distance
        ax.axvline(L / 2, color="C1", ls="--", label=f"L/2 = {L / 2:.4g} mm (point method)")
        ax.axvline(2 * L, color="C2", ls=":", label=f"2L = {2 * L:.4g} mm (line method)")
        ax.plot([L / 2], [tcd.point_value], "o", color="C1")
        ax.legend(fontsize=9)
    ax.set_xlabel("distance from the hot spot along the critical direction (mm)")
    ax.set_ylabel(LABELS[method])
    ax.set_title(f"{method} below the hot spot x = {rep.hot_spot[0]:.4g} mm")
    return ax


def plot_ruiz(report: FatigueReport, ax=None):
    """Ruiz F2 = sigma_xx tau delta along the surface."""
    import matplotlib.pyplot as plt

    r = report.ruiz
    if r is None:
        raise ValueError("this report has no Ruiz parameters (the provider gave no surface data)")
    if ax is None:
        _, ax = plt.subplots(figsize=(6, 3.6), layout="constrained")
    ax.plot(r.x, r.f2, color="C3")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("F2 = sigma_xx,max tau_max delta_a (MPa N/mm)")
    ax.set_title("Ruiz F2 along the surface")
    return ax


def write_fatigue(directory, report: FatigueReport, *, figures: bool = True) -> list[Path]:
    """Write fatigue.json (and the figures) into ``directory``; returns the written paths."""
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    path = out / "fatigue.json"
    path.write_text(json.dumps(fatigue_summary(report), indent=2, allow_nan=False) + "\n")
    written.append(path)
    if not figures:
        return written
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    for m in report.methods:
        for name, plot in (("map", plot_parameter_map), ("depth", plot_depth_profile)):
            ax = plot(report, m)
            p = out / f"fatigue_{m}_{name}.png"
            ax.figure.savefig(p, dpi=130)
            plt.close(ax.figure)
            written.append(p)
    if report.ruiz is not None:
        ax = plot_ruiz(report)
        p = out / "fatigue_ruiz_f2.png"
        ax.figure.savefig(p, dpi=130)
        plt.close(ax.figure)
        written.append(p)
    return written
