"""Short text and HTML display of results in a notebook: ``repr`` in one line, and
``_repr_html_`` as a table of steps with loads, errors, zones and checks.

The functions read the records by duck typing; the records' ``__repr__`` and
``_repr_html_`` call them. A long history shows its first and last rows only.
"""

from __future__ import annotations

import html
import math
from collections.abc import Sequence

from fretbem.contact.law import STATE_NAMES
from fretbem.contact.zones import step_zones
from fretbem.verification.errors import ERROR_KEYS
from fretbem.verification.theory import theory_stick_zones

__all__ = [
    "MAX_ROWS",
    "html_table",
    "result_html",
    "result_repr",
    "scene_html",
    "scene_repr",
    "step_html",
    "step_repr",
]

#: rows of a step table before the middle is elided (half at each end)
MAX_ROWS = 20
STYLE = (
    "<style>.fretbem-table{border-collapse:collapse;font-size:12px}"
    ".fretbem-table td,.fretbem-table th{padding:2px 6px;border-bottom:1px solid #ddd;"
    "text-align:right}.fretbem-table caption{text-align:left;font-weight:bold}"
    ".fretbem-fail{color:#b00}</style>"
)


def _esc(value) -> str:
    return html.escape(str(value))


def percent(value) -> str:
    """A fraction as percent with 3 decimals; "n/a" for None or NaN."""
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "n/a"
    return f"{100 * value:.3f}"


def zone_text(zones: Sequence) -> str:
    """``[a, b]`` zones in mm (4 decimals), "none" without."""
    return " ".join(f"[{z[0]:+.4f}, {z[1]:+.4f}]" for z in zones) or "none"


def slip_text(zones: Sequence) -> str:
    """Signed slip zones ``+[a, b]``."""
    return " ".join(f"{z[2]}[{z[0]:+.4f}, {z[1]:+.4f}]" for z in zones) or "none"


def html_table(header: Sequence[str], rows: Sequence[Sequence], caption: str = "") -> str:
    """A small HTML table (cells escaped); a row of one cell spans every column."""
    head = "".join(f"<th>{_esc(h)}</th>" for h in header)
    body = []
    for row in rows:
        if len(row) == 1:
            body.append(
                f'<tr><td colspan="{len(header)}" style="text-align:center">'
                f"{_esc(row[0])}</td></tr>"
            )
        else:
            body.append("<tr>" + "".join(f"<td>{_esc(c)}</td>" for c in row) + "</tr>")
    cap = f"<caption>{_esc(caption)}</caption>" if caption else ""
    return (
        f'{STYLE}<table class="fretbem-table">{cap}<thead><tr>{head}</tr></thead>'
        f"<tbody>{''.join(body)}</tbody></table>"
    )


def _elide(rows: list, limit: int = MAX_ROWS) -> list:
    if len(rows) <= limit:
        return rows
    half = limit // 2
    return [*rows[:half], (f"... {len(rows) - limit} steps not shown ...",), *rows[-half:]]


def _checks_text(step) -> str:
    checks = step.checks or {}
    if not checks:
        return "not run"
    failed = [name for name, record in checks.items() if not record.passed]
    return "failed: " + ", ".join(failed) if failed else "passed"


def _worst(result, key: str):
    values = [(s.errors or {}).get(key) for s in result.steps]
    values = [v for v in values if v is not None]
    return max(values) if values else None


def _worst_estimate(result, key: str):
    values = [(s.estimate or {}).get(key) for s in result.steps]
    values = [v for v in values if v is not None]
    return max(values) if values else None


def result_repr(result) -> str:
    """One line: family, pairs, steps, the largest errors and estimates, checks, time."""
    info = result.describe()
    names = [s.name for s in result.steps]
    span = names[0] if len(names) == 1 else f"{names[0]}..{names[-1]}"
    parts = [
        f"{info['basis']} p={info['degree']}, {info['pairs']} pairs",
        f"{len(names)} steps {span}",
    ]
    for key, label in (("e_p_max", "max e_p"), ("e_q_max", "max e_q")):
        worst, estimate = _worst(result, key), _worst_estimate(result, key)
        if worst is not None or estimate is not None:
            parts.append(f"{label} {percent(worst)} % (est {percent(estimate)} %)")
    checks = {_checks_text(s) for s in result.steps}
    parts.append("checks " + ("passed" if checks == {"passed"} else "/".join(sorted(checks))))
    parts.append(f"{result.timings.get('total', math.nan):.3f} s")
    return f"<{type(result).__name__} " + ", ".join(parts) + ">"


def _step_rows(result) -> list:
    theory = theory_stick_zones(result.simulation.reference, [s.tangential for s in result.steps])
    rows = []
    for step, exact in zip(result.steps, theory, strict=True):
        e, est = step.errors or {}, step.estimate or {}
        zones = step_zones(step)
        rows.append(
            (
                step.name,
                f"{step.normal:g}",
                f"{step.tangential:g}",
                f"{float((step.loads or {}).get('bulk', 0.0)):g}",
                *(f"{percent(e.get(k))} / {percent(est.get(k))}" for k in ERROR_KEYS[:2]),
                zone_text(zones.stick),
                zone_text([exact]) if exact else "n/a",
                slip_text(zones.slip),
                step.iterations,
                _checks_text(step),
            )
        )
    return rows


STEP_HEADER = (
    "step",
    "P (N/mm)",
    "Q (N/mm)",
    "σ_B (MPa)",
    "e_p max % / est",
    "e_q max % / est",
    "stick zone (mm)",
    "theory [e−c, e+c]",
    "slip zones",
    "iters",
    "checks",
)


def result_html(result) -> str:
    """The run as HTML: a heading line (family, Hertz a and p0, accuracy) and the step table."""
    info = result.describe()
    lines = [
        f"{info['basis']} (degree {info['degree']}), {info['pairs']} node pairs, "
        f"{info['dofs']} boundary DOFs, friction {info['friction']}"
    ]
    reference = result.simulation.reference
    if reference is not None:
        hertz = reference.hertz
        lines.append(
            f"Hertz: a = {hertz.half_width:.4f} mm, p0 = {hertz.peak_pressure:.2f} MPa"
            f" at P = {hertz.load:g} N/mm"
        )
    lines.append(result.accuracy_line())
    head = "".join(f"<div>{_esc(line)}</div>" for line in lines)
    return (
        f"<div><b>{_esc(type(result).__name__)}</b>{head}"
        f"{html_table(STEP_HEADER, _elide(_step_rows(result)))}</div>"
    )


def step_repr(step) -> str:
    """One line: loads, pair counts by state, errors and iterations of one step."""
    counts = ", ".join(f"{step.count(n)} {n}" for n in STATE_NAMES)
    e = step.errors or {}
    errors = "".join(f", {k} {percent(e[k])} %" for k in ERROR_KEYS[:2] if e.get(k) is not None)
    bulk = float((step.loads or {}).get("bulk", 0.0))
    loads = f"P={step.normal:g}, Q={step.tangential:g}" + (f", sigma_B={bulk:g}" if bulk else "")
    return (
        f"<{type(step).__name__} {step.name}: {loads}; {len(step.x)} pairs ({counts})"
        f"{errors}; {step.iterations} iterations>"
    )


def step_html(step) -> str:
    """One step as a two-column HTML table."""
    zones = step_zones(step)
    e, est = step.errors or {}, step.estimate or {}
    rows = [
        ("P, Q (N/mm)", f"{step.normal:g}, {step.tangential:g}"),
        ("σ_B (MPa)", f"{float((step.loads or {}).get('bulk', 0.0)):g}"),
        ("pairs", f"{len(step.x)}: " + ", ".join(f"{step.count(n)} {n}" for n in STATE_NAMES)),
        ("contact (mm)", zone_text([zones.contact]) if zones.contact else "none"),
        ("stick zones (mm)", zone_text(zones.stick)),
        ("slip zones (mm)", slip_text(zones.slip)),
    ]
    rows += [(f"{k} % / est", f"{percent(e.get(k))} / {percent(est.get(k))}") for k in ERROR_KEYS]
    rows += [
        ("iterations", step.iterations),
        ("checks", _checks_text(step)),
        ("time (s)", f"{step.seconds:.4f}"),
    ]
    return html_table(("", ""), rows, caption=f"step {step.name}")


def _shape(body) -> str:
    shape = body.shape
    fields = ", ".join(
        f"{a.name}={getattr(shape, a.name)!r}"
        for a in getattr(type(shape), "__attrs_attrs__", ())[:3]
    )
    return f"{type(shape).__name__}({fields}) {body.model}"


def _range(values) -> str:
    values = list(values)
    low, high = min(values), max(values)
    return f"{low:g}" if low == high else f"{low:g}..{high:g}"


def scene_repr(scene) -> str:
    """One line: pad, specimen, contact and the load history's ranges."""
    c, load = scene.contact, scene.load
    parts = [
        f"pad {_shape(scene.pad)}",
        f"specimen {_shape(scene.specimen)}",
        f"{c.basis} {c.pairs} pairs, f={c.friction:g}, mesh {c.mesh}",
    ]
    if load is not None:
        names = list(load.steps)
        span = names[0] if len(names) == 1 else f"{names[0]}..{names[-1]}"
        parts.append(
            f"{len(names)} steps {span}: P {_range(load.P)}, Q {_range(load.Q)}"
            + (f", sigma_B {_range(load.bulk)}" if any(load.bulk) else "")
        )
    extras = sorted(scene.extras or {})
    if extras:
        parts.append("with " + ", ".join(f"[{e}]" for e in extras))
    return "<Scene " + "; ".join(parts) + ">"


def scene_html(scene) -> str:
    """The scene's bodies and contact, then its load steps, as HTML tables."""
    c = scene.contact
    rows = [
        ("pad", _shape(scene.pad), f"E={scene.pad.material.E:g} MPa, ν={scene.pad.material.nu:g}"),
        (
            "specimen",
            _shape(scene.specimen),
            f"E={scene.specimen.material.E:g} MPa, ν={scene.specimen.material.nu:g}",
        ),
        (
            "contact",
            f"{c.basis}, {c.pairs} pairs, zone {c.zone:g} a",
            f"f={c.friction:g}, solver {c.solver}, mesh {c.mesh}",
        ),
    ]
    out = html_table(("", "", ""), rows, caption="scene")
    load = scene.load
    if load is not None:
        steps = [
            (n, f"{p:g}", f"{q:g}", f"{b:g}", k)
            for n, p, q, b, k in zip(
                load.steps, load.P, load.Q, load.bulk, load.increments, strict=True
            )
        ]
        out += html_table(
            ("step", "P (N/mm)", "Q (N/mm)", "σ_B (MPa)", "increments"),
            _elide(steps),
            caption="load history",
        )
    return f"<div>{out}</div>"
