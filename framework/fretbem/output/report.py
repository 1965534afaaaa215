"""One self-contained HTML page per run (report.html): scene and loads, Hertz a and p0, the
zones per step beside theory, the checks, the error estimate, the timings, every figure
(embedded), the stress and fatigue hot spots and lives, and the loops and wear results.

The page is built from the files of an output folder, so ``fretbem report OUT`` can make it
for any finished run; it reads whatever result files exist and leaves out the sections of
those that do not (summary.json is the only one it needs). No script, no external file:
the page can be kept or sent as it is.
"""

from __future__ import annotations

import base64
import csv
import html
import json
import math
import time
from collections.abc import Sequence
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

from fretbem.errors import InputError
from fretbem.views.display import html_table, percent, slip_text, zone_text

__all__ = ["REPORT", "build_report", "write_report"]

REPORT = "report.html"
#: rows of an extra result table shown (its first and last ones)
TABLE_ROWS = 12
#: what each known figure shows (other PNG files are shown under their name)
FIGURES = {
    "tractions.png": "Contact pressure p and shear q at each step, beside the closed form",
    "displacements.png": "Relative normal and tangential displacements at the pairs, per step",
    "states.png": "Pair states at every step, with the closed form's stick zone [e − c, e + c]",
    "history.png": "The load history, stick-zone width and peak shear, step by step",
    "surface_sigma_xx.png": "Surface sigma_xx of the stressed body over the steps",
    "stress_contours.png": "Stress contours below the contact at the most loaded step",
}
LOOPS = ("loops.csv", "slip.csv")
WEAR = ("wear_summary.csv", "wear_life.csv", "wear.csv", "wear_jumps.csv")

CSS = """
body{font-family:system-ui,-apple-system,'Segoe UI',sans-serif;margin:2em auto;max-width:1100px;
color:#222;padding:0 1em}
h1{font-size:1.6em;margin-bottom:0.2em}h2{border-bottom:2px solid #4c72b0;padding-bottom:2px;
margin-top:1.6em}
.meta{color:#666;font-size:0.9em}.fail{color:#b00;font-weight:bold}.ok{color:#171}
figure{margin:1em 0}figure img{max-width:100%;border:1px solid #ddd}
figcaption{font-size:0.9em;color:#444}
.fretbem-table{margin:0.5em 0 1em 0}
"""


class ReportError(InputError):
    """The folder is not a fretbem output with a summary.json."""


def _esc(value) -> str:
    return html.escape(str(value))


def _num(value, spec: str = ".4g") -> str:
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "n/a"
    return format(value, spec) if isinstance(value, (int, float)) else str(value)


def _read_json(path: Path):
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError):
        return None


def _read_csv(path: Path) -> tuple[list[str], list[list[str]]]:
    with path.open(newline="") as handle:
        rows = list(csv.reader(handle))
    return (rows[0], rows[1:]) if rows else ([], [])


def _section(title: str, body: str, anchor: str) -> str:
    return f'<section id="{anchor}"><h2>{_esc(title)}</h2>{body}</section>'


def _p(text: str) -> str:
    return f"<p>{_esc(text)}</p>"


def _scene(summary: dict) -> str:
    scene = summary.get("scene", {})
    models = scene.get("models") or {}
    rows = [
        ("basis family", f"{scene.get('basis')} (degree {scene.get('degree')})"),
        ("node pairs, boundary DOFs", f"{scene.get('pairs')}, {scene.get('dofs')}"),
        ("body models", f"pad {models.get('upper')}, specimen {models.get('lower')}"),
        ("solver", scene.get("solver")),
        ("friction coefficient f", scene.get("friction")),
    ]
    hertz = summary.get("hertz")
    if hertz:
        rows += [
            ("Hertz half-width a", f"{hertz['a']:.4f} mm (at P = {hertz['P']:g} N/mm)"),
            ("Hertz peak pressure p0", f"{hertz['p0']:.2f} MPa"),
        ]
    else:
        rows.append(("Hertz a and p0", "no closed form applies to this scene"))
    steps = summary.get("steps", [])
    loads = [
        (s["step"], _num(s.get("P"), "g"), _num(s.get("Q"), "g"), _num(s.get("sigma_B", 0.0), "g"))
        for s in steps
    ]
    header = ("step", "P (N/mm)", "Q (N/mm)", "σ_B (MPa)")
    if any(s.get("tilt") for s in steps):  # a rotating block: its moment and tilt per step
        header += ("M (N mm/mm)", "tilt (rad)")
        loads = [(*row, _num(s.get("M"), ".4g"), _num(s.get("tilt"), ".3g"))
                 for row, s in zip(loads, steps, strict=True)]  # fmt: skip
    return html_table(("", ""), rows, caption="scene") + html_table(header, loads, caption="loads")


def _zones(summary: dict) -> str:
    rows = []
    for s in summary.get("steps", []):
        if "stick_zones" not in s:
            return _p("this summary.json has no zones (written by an older fretbem)")
        theory = s.get("theory_stick_zone")
        slips = [(z["from"], z["to"], z["sign"]) for z in s.get("slip_zones", [])]
        contact = s.get("contact")
        rows.append(
            (s["step"], zone_text([contact]) if contact else "none", zone_text(s["stick_zones"]),
             zone_text([theory]) if theory else "n/a", slip_text(slips))
        )  # fmt: skip
    header = ("step", "contact (mm)", "stick zone (mm)", "theory [e − c, e + c] (mm)",
              "slip zones (mm)")  # fmt: skip
    note = (
        "Zones run from their first to their last pair (a transition lies within one pair "
        "spacing of either end); a slip zone's sign is that of its shear."
    )
    return html_table(header, rows) + _p(note)


def _checks(summary: dict) -> tuple[str, bool]:
    """A step x check table of "residual <= limit" cells, and whether every check passed."""
    steps = summary.get("steps", [])
    names = list(dict.fromkeys(n for s in steps for n in (s.get("checks") or {})))
    if not names:
        return _p("no result checks were recorded"), True
    rows, passed = [], True
    for s in steps:
        cells = []
        for name in names:
            record = (s.get("checks") or {}).get(name)
            if record is None:
                cells.append("not run")
                continue
            ok = bool(record.get("passed"))
            passed &= ok
            relation = "<=" if ok else "> (FAILED)"
            cells.append(f"{_num(record.get('residual'), '.3g')} {relation} "
                         f"{_num(record.get('limit'), '.3g')}")  # fmt: skip
        rows.append((s["step"], *cells))
    verdict = "all result checks passed" if passed else "a result check failed"
    body = html_table(("step", *(f"{n}: residual vs limit" for n in names)), rows)
    return f'<p class="{"ok" if passed else "fail"}">{verdict}</p>{body}', passed


def _errors(summary: dict) -> str:
    rows = []
    keys = ("e_p_max", "e_q_max", "e_p_l2", "e_q_l2")
    for s in summary.get("steps", []):
        cells = [f"{percent(s.get(k))} / {percent(s.get('est' + k[1:]))}" for k in keys]
        rows.append((s["step"], *cells, s.get("iterations"), _num(s.get("seconds"), ".3f")))
    header = ("step", "e_p max % / est", "e_q max % / est", "e_p L2 % / est", "e_q L2 % / est",
              "iterations", "time (s)")  # fmt: skip
    accuracy = summary.get("accuracy") or {}
    levels = ", ".join(str(n) for n in accuracy.get("levels", []))
    line = f"{accuracy.get('mesh', 'fixed')} mesh, levels {levels} pairs"
    if accuracy.get("estimate_reason"):
        line += f"; no estimate: {accuracy['estimate_reason']}"
    else:
        line += "; the estimate (est) comes from the two finest levels"
    note = ("errors against the closed form (n/a where none applies) beside the estimated "
            "discretisation error, in percent of p0 (pressure) and f p0 (shear)")  # fmt: skip
    return _p(line) + html_table(header, rows) + _p(note)


def _timings(summary: dict) -> str:
    rows = [(k, f"{v:.3f}") for k, v in (summary.get("timings") or {}).items()
            if isinstance(v, (int, float))]  # fmt: skip
    phases = summary.get("phases") or {}
    rows += [(f"phase: {k}", f"{v:.3f}") for k, v in phases.items() if isinstance(v, (int, float))]
    return html_table(("timing", "seconds"), rows) if rows else _p("no timings recorded")


def _figures(directory: Path) -> str:
    known = [n for n in FIGURES if (directory / n).is_file()]
    others = sorted(p.name for p in directory.glob("*.png") if p.name not in FIGURES)
    parts = []
    for name in [*known, *others]:
        data = base64.b64encode((directory / name).read_bytes()).decode("ascii")
        caption = FIGURES.get(name, name)
        parts.append(
            f'<figure><img src="data:image/png;base64,{data}" alt="{_esc(name)}">'
            f"<figcaption>{_esc(name)}: {_esc(caption)}</figcaption></figure>"
        )
    return "".join(parts)


def _stress(directory: Path) -> str:
    rows = []
    for path in sorted(directory.glob("stress_*.csv")):
        header, data = _read_csv(path)
        if "sigma_xx_MPa" not in header or not data:
            continue
        index = {name: k for k, name in enumerate(header)}
        for column, label in (("sigma_xx_MPa", "max sigma_xx"), ("von_mises_MPa", "max von Mises")):
            if column not in index:
                continue
            best = max(data, key=lambda r: float(r[index[column]]))
            depth = best[index["depth_mm"]] if "depth_mm" in index else ""
            rows.append((path.name, label, _num(float(best[index[column]])), best[0],
                         _num(float(best[index["x_mm"]])), _num(float(best[index["y_mm"]])),
                         _num(float(depth)) if depth else ""))  # fmt: skip
    if not rows:
        return ""
    header = ("file", "quantity", "value (MPa)", "step", "x (mm)", "y (mm)", "depth (mm)")
    return html_table(header, rows)


def _life(life) -> str:
    if not life:
        return "none"
    if life.get("runout"):
        return "run-out"
    return _num(life.get("cycles"), ".3g")


def _fatigue(directory: Path) -> str:
    data = _read_json(directory / "fatigue.json")
    if not isinstance(data, dict):
        return ""
    rows = []
    for method, entry in (data.get("methods") or {}).items():
        hot = entry.get("hot_spot") or {}
        cd = entry.get("critical_distance") or {}
        rows.append((method, _num(hot.get("x_mm")), _num(hot.get("depth_mm")),
                     _num(entry.get("parameter_at_hot_spot")), entry.get("parameter_unit", ""),
                     _num(cd.get("point_method_value")), _life(entry.get("life_at_hot_spot")),
                     _life(entry.get("life_at_critical_distance"))))  # fmt: skip
    material = (data.get("material") or {}).get("name", "")
    head = _p(f"material {material}; cycle steps {data.get('cycle_steps')}; critical distance "
              f"L = {_num(data.get('critical_distance_mm'))} mm")  # fmt: skip
    header = ("method", "hot spot x (mm)", "depth (mm)", "value", "unit", "point method",
              "life at hot spot", "life at L")  # fmt: skip
    notes = "".join(_p(f"note: {n}") for n in data.get("notes", []))
    ruiz = data.get("ruiz")
    if ruiz:
        notes += _p(f"Ruiz F2 largest at x = {_num(ruiz.get('f2_max_x_mm'))} mm "
                    f"({_num(ruiz.get('f2_max_MPa_N_per_mm'))} MPa N/mm)")  # fmt: skip
    return head + html_table(header, rows) + notes


def _cell(text: str) -> str:
    """A number to 6 significant digits (the files keep every digit); text as it is."""
    try:
        value = float(text)
    except ValueError:
        return text
    return text if text.strip().isdigit() else f"{value:.6g}"


def _table_file(path: Path) -> str:
    """An extra result table: its columns, row count and first and last rows."""
    try:
        header, data = _read_csv(path)
    except (OSError, UnicodeDecodeError, csv.Error) as err:
        return _p(f"{path.name}: could not be read ({err})")
    if not header:
        return _p(f"{path.name}: empty")
    shown = [[_cell(c) for c in row] for row in data]
    if len(data) > TABLE_ROWS:
        half = TABLE_ROWS // 2
        shown = [*shown[:half], (f"... {len(data) - TABLE_ROWS} rows not shown ...",),
                 *shown[-half:]]  # fmt: skip
    caption = f"{path.name}: {len(data)} rows"
    return html_table(header, [tuple(r) for r in shown], caption=caption)


def _extra(directory: Path, names: Sequence[str], json_name: str | None = None) -> str:
    parts = [_table_file(directory / n) for n in names if (directory / n).is_file()]
    if json_name and (directory / json_name).is_file():
        data = _read_json(directory / json_name)
        if isinstance(data, dict):
            plain = [(k, v) for k, v in data.items() if isinstance(v, (int, float, str))]
            if plain:
                parts.append(html_table(("", ""), plain, caption=json_name))
    return "".join(parts)


def _version() -> str:
    try:
        return version("fretbem")
    except PackageNotFoundError:  # pragma: no cover - not installed
        return "unknown"


def build_report(directory: str | Path, name: str | None = None) -> str:
    """The report page of the output folder ``directory`` (HTML text); ``name`` titles it
    (default: the folder's name)."""
    directory = Path(directory)
    summary = _read_json(directory / "summary.json")
    if not isinstance(summary, dict) or "steps" not in summary:
        raise ReportError(
            f"{directory} has no readable summary.json: give the folder a fretbem run wrote "
            "(--out of fretbem run or demo), with the json writer"
        )
    checks, passed = _checks(summary)
    sections = [
        _section("Scene and loads", _scene(summary), "scene"),
        _section("Zones per step beside theory", _zones(summary), "zones"),
        _section("Result checks", checks, "checks"),
        _section("Errors and the error estimate", _errors(summary), "errors"),
        _section("Timings", _timings(summary), "timings"),
    ]
    for title, body, anchor in (
        ("Stresses: hot spots", _stress(directory), "stress"),
        ("Fretting fatigue: hot spots and lives", _fatigue(directory), "fatigue"),
        ("Loops and slip", _extra(directory, LOOPS), "loops"),
        ("Wear", _extra(directory, WEAR, "wear.json"), "wear"),
        ("Figures", _figures(directory), "figures"),
    ):
        if body:
            sections.append(_section(title, body, anchor))
    files = sorted(
        p.name for p in directory.iterdir() if p.is_file() and not p.name.startswith(".")
    )
    sections.append(_section("Files", _p(", ".join(files)), "files"))
    scene = summary.get("scene", {})
    title = f"fretbem run report: {name if name is not None else directory.resolve().name}"
    verdict = "all result checks passed" if passed else "A RESULT CHECK FAILED"
    meta = (f"{scene.get('basis')} {scene.get('pairs')} pairs, {len(summary['steps'])} steps; "
            f"{verdict}; fretbem {_version()}, {time.strftime('%Y-%m-%d %H:%M')}")  # fmt: skip
    return (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        f'<meta name="viewport" content="width=device-width, initial-scale=1">'
        f"<title>{_esc(title)}</title><style>{CSS}</style></head><body>"
        f'<h1>{_esc(title)}</h1><div class="meta">{_esc(meta)}</div>'
        + "".join(sections)
        + "</body></html>\n"
    )


def write_report(
    directory: str | Path, target: str | Path | None = None, name: str | None = None
) -> Path:
    """Write the report of ``directory`` to ``target`` (default ``directory/report.html``)."""
    directory = Path(directory)
    path = Path(target) if target is not None else directory / REPORT
    path.write_text(build_report(directory, name), encoding="utf-8")
    return path
