"""Write a wear history: wear.csv, wear_summary.csv, wear_jumps.csv, wear.json, the worn
profile and pressure figures, VTK of the worn faces, and the stresses and fatigue at each
assessed N (the "wear" writer of :func:`fretbem.output.write.write_results`).
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np

from fretbem.fatigue.output import fatigue_summary, write_fatigue
from fretbem.sliding.track import Track
from fretbem.stress.run import run_stress_request
from fretbem.verification.checks import safe_names
from fretbem.wear.assess import WearReport
from fretbem.wear.profile import BODIES

from .vtk import write_pvd, write_vtp

__all__ = ["ROTATION_COLUMNS", "WEAR_COLUMNS", "wear_rows", "wear_summary_rows", "write_wear"]

#: the body labels of the files: the pad is the upper body, the specimen the lower
LABEL = {"upper": "pad", "lower": "specimen"}

#: unit and meaning of every column of the wear files (written to wear.json)
WEAR_COLUMNS = {
    "wear.csv": {
        "N": ("cycles", "cycles done"),
        "step": ("", "cycle step at whose end p and q are taken"),
        "x": ("mm", "pair position (finite sliding: a point of the specimen's grid along "
              "the track; h_pad there is the pad's depth at its own x as drawn)"),
        "h_pad, h_specimen": ("mm", "wear depth of each face, along the pair normal"),
        "p": ("MPa", "contact pressure, > 0 in compression"),
        "q": ("MPa", "shear traction of the pad on the specimen, along +x"),
        "M": ("N mm/mm", "moment of the pad's loading block on the pad about the rig's pivot "
              "at the step's end, counterclockwise > 0 (a rotating block only)"),
        "theta": ("rad", "rotation of the actuator holding the pad's block (the block's plus "
                  "M / k_r), counterclockwise > 0 (a rotating block only)"),
        "tilt": ("rad", "the pad block's own rotation about the pivot, counterclockwise > 0 "
                 "(a rotating block only)"),
    },
    "wear_summary.csv": {
        "N": ("cycles", "cycles done"),
        "energy": ("N mm/mm", "friction energy dissipated over the N cycles, per unit thickness"),
        "archard_work": ("N mm/mm", "sum of w p |ds| over the N cycles"),
        "volume_pad, volume_specimen": ("mm^3/mm", "worn volume per unit thickness"),
        "max_depth_pad, max_depth_specimen": ("mm", "deepest wear"),
        "scar_width_pad, scar_width_specimen": ("mm", "extent of depth > 1 % of the deepest"),
        "peak_pressure": ("MPa", "largest p over the cycle's step ends"),
        "contact_width": ("mm", "extent of p > 0 at the end of the cycle's first step"),
        "M_amplitude": ("N mm/mm", "half the range of M over the cycle's step ends (a rotating "
                        "block only)"),
        "theta_amplitude": ("rad", "half the range of theta over the cycle's step ends (a "
                            "rotating block only)"),
        "tilt_amplitude": ("rad", "half the range of the tilt over the cycle's step ends (a "
                           "rotating block only)"),
    },
    "wear_jumps.csv": {
        "N": ("cycles", "cycle the jump starts from"),
        "delta_N": ("cycles", "cycles the simulated cycle was extrapolated over"),
        "limit": ("", "which limit chose delta_N: first cycle, profile, stability, max_jump, "
                  "output"),
        "lambda": ("1/cycle", "stability rate of the wear-contact system"),
        "max_rate": ("mm/cycle", "largest depth per cycle of either face"),
    },
    "wear_life.csv": {
        "N": ("cycles", "wear cycles before the assessment"),
        "method": ("", "fatigue parameter"),
        "life_hot_spot, life_critical_distance": ("cycles", "initiation life; empty: run-out "
                                                  "or none"),
        "parameter_at_hot_spot": ("parameter's unit", "see fatigue.json"),
        "hot_spot_x": ("mm", "x of the hot spot"),
    },
}  # fmt: skip


#: the columns of a rotating pad block, written only where the block rotates
ROTATION_COLUMNS = {
    "wear.csv": ("M", "theta", "tilt"),
    "wear_summary.csv": ("M_amplitude", "theta_amplitude", "tilt_amplitude"),
}


def _rotates(report: WearReport) -> bool:
    return report.result.snapshots[0].tilt is not None


def _block(snap) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A rotating block's M, theta and tilt at the end of each cycle step at N."""
    return snap.moment, snap.rotation, snap.tilt


def _tractions(snap, k: int) -> tuple[np.ndarray, np.ndarray]:
    """p and q at the end of cycle step ``k`` on the profile's points: the pairs' own values,
    or with finite sliding (the pairs moved) interpolated from where the pairs were, zero
    outside the pad."""
    if snap.positions is None:
        return snap.pressure[k], snap.shear[k]
    where, x = snap.positions[k], snap.profile.x
    return tuple(
        np.interp(x, where, v[k], left=0.0, right=0.0) for v in (snap.pressure, snap.shear)
    )


def wear_rows(report: WearReport) -> list[list]:
    """wear.csv rows: one per output N, cycle step and pair (finite sliding: track point);
    a rotating block's M, theta and tilt at the step's end close each row."""
    names = [s.name for s in report.result.wear.cycle_steps]
    turning = _rotates(report)
    rows = []
    for snap in report.result.snapshots:
        prof = snap.profile
        pad = prof.upper
        if prof.upper_x is not None:  # finite sliding: the pad's own points
            pad = np.interp(prof.x, prof.upper_x, prof.upper, left=0.0, right=0.0)
        for k, name in enumerate(names):
            p, q = _tractions(snap, k)
            block = [float(v[k]) for v in _block(snap)] if turning else []
            for j in range(len(prof.x)):
                rows.append([snap.cycles, name, prof.x[j], pad[j], prof.lower[j],
                             p[j], q[j], *block])  # fmt: skip
    return rows


def _contact_width(x: np.ndarray, p: np.ndarray) -> float:
    touching = x[p > 0]
    return float(touching.max() - touching.min()) if touching.size else 0.0


def wear_summary_rows(report: WearReport) -> list[list]:
    """wear_summary.csv rows: one per output N (a rotating block's amplitudes last)."""
    turning = _rotates(report)
    rows = []
    for snap in report.result.snapshots:
        prof = snap.profile
        rows.append(
            [snap.cycles, snap.energy, snap.work]
            + [prof.volume(b) for b in BODIES]
            + [prof.max_depth(b) for b in BODIES]
            + [prof.scar_width(b) for b in BODIES]
            + [float(np.max(snap.pressure)), _contact_width(snap.pair_x(0), snap.pressure[0])]
            + ([0.5 * float(np.ptp(v)) for v in _block(snap)] if turning else [])
        )
    return rows


def _csv(path: Path, header: list[str], rows: list[list]) -> Path:
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(header)
        writer.writerows(
            [[repr(float(v)) if isinstance(v, float) else v for v in row] for row in rows]
        )
    return path


def _life(life) -> float | str:
    if life is None or math.isinf(life.cycles):
        return ""
    return float(life.cycles)


def _settings(report: WearReport) -> dict:
    wear = report.result.wear
    control = wear.control
    return {
        "laws": {LABEL[b]: {"law": type(law).__name__, law.coefficient_name: law.coefficient}
                 for b, law in wear.laws.items()},
        "cycles": wear.cycles,
        "cycle_steps": [s.name for s in wear.cycle_steps],
        "increments": [s.increments for s in wear.cycle_steps],
        "max_change_mm": control.max_change,
        "relative_change": control.relative_change,
        "scheme": control.scheme,
        "safety": control.safety,
        "max_jump": control.max_jump,
        "outputs": list(wear.snapshot_cycles),
        "sliding": wear.sliding,
    }  # fmt: skip


def write_wear(
    directory: Path, report: WearReport, *, stress=None, figures: bool = True, vtk: bool = True
) -> list[Path]:
    """Write ``report`` into ``directory`` (see the module docstring); returns the paths."""
    out = Path(directory)
    result = report.result
    extra = ROTATION_COLUMNS if _rotates(report) else {}
    written = [
        _csv(out / "wear.csv", ["N", "step", "x", "h_pad", "h_specimen", "p", "q",
                                *extra.get("wear.csv", ())], wear_rows(report)),
        _csv(out / "wear_summary.csv",
             ["N", "energy", "archard_work", "volume_pad", "volume_specimen", "max_depth_pad",
              "max_depth_specimen", "scar_width_pad", "scar_width_specimen", "peak_pressure",
              "contact_width", *extra.get("wear_summary.csv", ())], wear_summary_rows(report)),
        _csv(out / "wear_jumps.csv", ["N", "delta_N", "limit", "lambda", "max_rate"],
             [[n, j.cycles, j.limit, j.stability, j.rate] for n, j in result.jumps]),
    ]  # fmt: skip
    lives = []
    for item in report.assessments:
        folder = out / f"wear_N{item.cycles}"
        folder.mkdir()
        if stress is not None:
            run_stress_request(item.result, stress, folder)
        if item.fatigue is not None:
            write_fatigue(folder, item.fatigue, figures=figures)
            for method, rep in item.fatigue.methods.items():
                lives.append([item.cycles, method, _life(rep.life_hot_spot),
                              _life(rep.life_critical_distance),
                              float(rep.at_hot_spot.value[0]), rep.hot_spot[0]])  # fmt: skip
        written.append(folder)
    if lives:
        written.append(_csv(out / "wear_life.csv", ["N", "method", "life_hot_spot",
                            "life_critical_distance", "parameter_at_hot_spot", "hot_spot_x"],
                            lives))  # fmt: skip
    summary = {
        "settings": _settings(report),
        "simulated_cycles": result.simulated,
        "seconds": result.seconds,
        "assessed": [a.cycles for a in report.assessments],
        "life": {str(a.cycles): fatigue_summary(a.fatigue)["methods"]
                 for a in report.assessments if a.fatigue is not None},
        "units": {f: {k: {"unit": u, "meaning": m} for k, (u, m) in cols.items()
                      if k in extra.get(f, ()) or k not in ROTATION_COLUMNS.get(f, ())}
                  for f, cols in WEAR_COLUMNS.items()},
    }  # fmt: skip
    path = out / "wear.json"
    path.write_text(json.dumps(summary, indent=2, default=float) + "\n")
    written.append(path)
    if figures:
        written += save_wear_figures(report, out)
    if vtk:
        written += save_worn_faces(report, out)
    return written


def save_wear_figures(report: WearReport, directory: Path) -> list[Path]:
    """wear_profiles.png (depth of each face for each N), wear_pressure.png (p and q at the
    end of the cycle's first step for each N) and wear_evolution.png (depth, scar width
    and peak pressure against N)."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    snaps = report.result.snapshots
    colours = plt.cm.viridis(np.linspace(0.0, 0.9, len(snaps)))
    written = []
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8), sharex=True)
    for ax, body in zip(axes, BODIES, strict=True):
        for snap, colour in zip(snaps, colours, strict=True):
            ax.plot(snap.profile.grid(body)[0], 1e3 * snap.profile.depth(body), color=colour,
                    label=f"N = {snap.cycles:g}")  # fmt: skip
        ax.set(title=f"{LABEL[body]} wear", xlabel="x (mm)", ylabel="wear depth (um)")
        ax.invert_yaxis()
    axes[1].legend(fontsize=7)
    written.append(_save(fig, directory / "wear_profiles.png", plt))
    first = report.result.wear.cycle_steps[0].name
    fig, ax = plt.subplots(figsize=(6.5, 4))
    for snap, colour in zip(snaps, colours, strict=True):
        x = snap.pair_x(0)
        ax.plot(x, snap.pressure[0], color=colour, label=f"p, N = {snap.cycles:g}")
        ax.plot(x, snap.shear[0], color=colour, ls="--", lw=0.8)
    ax.set(title=f"p (solid) and q (dashed) at the end of step {first}", xlabel="x (mm)",
           ylabel="traction (MPa)")  # fmt: skip
    ax.legend(fontsize=7)
    written.append(_save(fig, directory / "wear_pressure.png", plt))
    rows = np.array(wear_summary_rows(report), dtype=float)
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.5))
    n = rows[:, 0]
    axes[0].plot(n, 1e3 * rows[:, 5], "o-", label="pad")
    axes[0].plot(n, 1e3 * rows[:, 6], "s-", label="specimen")
    axes[0].set(xlabel="N", ylabel="max depth (um)")
    axes[0].legend()
    axes[1].plot(n, rows[:, 7], "o-", label="pad")
    axes[1].plot(n, rows[:, 8], "s-", label="specimen")
    axes[1].set(xlabel="N", ylabel="scar width (mm)")
    axes[2].plot(n, rows[:, 9], "o-")
    axes[2].set(xlabel="N", ylabel="peak pressure (MPa)")
    written.append(_save(fig, directory / "wear_evolution.png", plt))
    return written


def _save(fig, path: Path, plt) -> Path:
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def save_worn_faces(report: WearReport, directory: Path) -> list[Path]:
    """vtk/wear_N<N>_<body>.vtp: each contact face at its worn position (point data
    wear_depth, the vector "wear" = -h n to magnify with Warp By Vector, p and q at the end
    of the cycle's first step) and wear.pvd, one time step per output N. With finite
    sliding each face is drawn at all its nodes where it was drawn, its depth read at its
    material points (by arc length along a circular track); p and q (on the specimen's
    nodes) where the pad was at that step's end."""
    folder = directory / "vtk"
    folder.mkdir(exist_ok=True)
    wear_run = report.result.wear
    pair = wear_run.simulation.pair
    track = Track.of(pair) if wear_run.sliding else None
    track = None if track is None or track.straight else track  # an arc: by arc length
    entries = []
    for index, snap in enumerate(report.result.snapshots):
        for part, body in enumerate(BODIES):
            owner, tag = pair.side(body)
            face = owner.contact_face(tag)
            if wear_run.sliding:
                x = face.points[:, 0] if track is None else track.along(face.points)
                nodes = np.argsort(x)
                x = x[nodes]
                depth = np.interp(x, snap.profile.grid(body)[0], snap.profile.depth(body))
                p, q = (np.interp(x, snap.pair_x(0), v[0], left=0.0, right=0.0)
                        for v in (snap.pressure, snap.shear))  # fmt: skip
                tractions = {"p": p, "q": q} if body == "lower" else {}
            else:
                nodes = pair.pairing().nodes(body)
                depth = snap.profile.depth(body)
                tractions = {"p": snap.pressure[0], "q": snap.shear[0]}
            wear = -depth[:, None] * face.normals[nodes]
            points = face.points[nodes] + wear
            arrays = {
                "points": np.column_stack([points, np.zeros(len(points))]),
                "lines": [np.arange(len(points))],
                "point_data": {"wear_depth": depth, "wear": np.column_stack(
                    [wear, np.zeros(len(wear))]), **tractions},
                "cell_data": {},
                "field_data": {"N": np.array([snap.cycles])},
            }  # fmt: skip
            name = safe_names([f"wear_N{snap.cycles}_{LABEL[body]}"])[0]
            path = write_vtp(folder / f"{name}.vtp", arrays)
            entries.append((index, part, LABEL[body], path))
    pvd = write_pvd(directory / "wear.pvd", entries)
    return [folder, pvd]
