"""Tables of the fixed-pairs runs on the results page: every run, errors per step, finite
bodies, refinement of the rest and fitted exponents, each a list of markdown lines."""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence

from results_page_format import mib as _mib
from results_page_format import pct as _pct
from results_page_format import seconds as _seconds

from fretbem.scenes.reference import CattaneoMindlinScene
from fretbem.studies.convergence.study import (
    ERROR_STEPS,
    ERRORS,
    LARGE,
    PAPER_PAIRS,
    STEPS,
    exponents,
    family_label,
    series,
)


def _iterations(row) -> str:
    return "/".join(str(row[f"iterations_{s}"]) for s in STEPS)


def main_table(rows) -> list[str]:
    out = [
        "## All runs on the scene's bodies",
        "",
        "Errors in % (largest over steps B–E); iterations per step A/B/C/D/E; times in s "
        "(condense includes the LU factorisation; solve is the mean per step); memory is the "
        "tracemalloc peak of one run in MiB.",
        "",
        "| family | p | pairs | DOFs | e_p max | e_q max | e_p L2 | e_q L2 | iterations "
        "| assembly | condense | solve/step | wall | memory |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|",
    ]
    for key, runs in sorted(series(rows, 1.0).items()):
        for r in runs:
            out.append(
                f"| {key[0]} | {key[1]} | {r['pairs']} | {r['dofs']} | {_pct(r['e_p_max'])} | "
                f"{_pct(r['e_q_max'])} | {_pct(r['e_p_l2'])} | {_pct(r['e_q_l2'])} | "
                f"{_iterations(r)} | {_seconds(r['assembly_s'])} | "
                f"{_seconds(r['condensation_s'])} | {_seconds(r['steps_s'] / len(STEPS))} | "
                f"{_seconds(r['wall_s'])} | {_mib(r['peak_memory_mib'])} |"
            )
    return [*out, ""]


def step_tables(rows) -> list[str]:
    out = ["### Errors per step (scene's bodies, %)", ""]
    for errors in (("e_q_max", "e_q_l2"), ("e_p_max", "e_p_l2")):
        header = "| family | p | pairs | " + " | ".join(
            f"{e[:3]} {e[4:]} {s}" for e in errors for s in ERROR_STEPS
        )
        out += [header + " |", "|---|---:|---:|" + "---:|" * (2 * len(ERROR_STEPS))]
        for key, runs in sorted(series(rows, 1.0).items()):
            for r in runs:
                cells = [_pct(r[f"{e}_{s}"]) for e in errors for s in ERROR_STEPS]
                out.append(f"| {key[0]} | {key[1]} | {r['pairs']} | " + " | ".join(cells) + " |")
        out.append("")
    return out


def finite_body_section(rows) -> list[str]:
    large = series(rows, LARGE)
    if not large:
        return []
    scene = series(rows, 1.0)
    out = [
        "## Finite bodies against half-plane theory",
        "",
        f"The scene's bodies are {CattaneoMindlinScene().width:g} mm wide, about 20 contact "
        "half-widths; the theory is for half-planes. The same discretisations on bodies "
        f"{LARGE:g}× larger (width {LARGE * CattaneoMindlinScene().width:g} mm, height "
        f"{LARGE * CattaneoMindlinScene().height:g} mm) separate the finite-body effect from "
        "the discretisation error. Errors in % (largest over steps B–E), scene → larger.",
        "",
        "| family | p | pairs | e_p max | e_p L2 | e_q max | e_q L2 |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    for key, runs in sorted(large.items()):
        base = {r["pairs"]: r for r in scene.get(key, [])}
        for r in runs:
            b = base.get(r["pairs"])
            cells = [
                f"{_pct(b[e]) if b else '–'} → {_pct(r[e])}"
                for e in ("e_p_max", "e_p_l2", "e_q_max", "e_q_l2")
            ]
            out.append(f"| {key[0]} | {key[1]} | {r['pairs']} | " + " | ".join(cells) + " |")
    finest = [
        (key, runs[-1], {r["pairs"]: r for r in scene.get(key, [])}.get(runs[-1]["pairs"]))
        for key, runs in large.items()
    ]
    finest = [(k, r, b) for k, r, b in finest if b is not None]
    if finest:
        dl2 = [b["e_p_l2"] - r["e_p_l2"] for _, r, b in finest]
        dmax = [b["e_p_max"] - r["e_p_max"] for _, r, b in finest]
        out += [
            "",
            f"At the finest level ({finest[0][1]['pairs']} pairs) the L2 pressure error is "
            + ", ".join(
                f"{_pct(b['e_p_l2'])} → {_pct(r['e_p_l2'])} % ({family_label(k)})"
                for k, r, b in sorted(finest)
            )
            + f" on the scene's → larger bodies (a difference of {_pct(min(dl2), 2)} to "
            f"{_pct(max(dl2), 2)} % of p0), and the largest pressure error changes by "
            f"{_pct(min(dmax), 2)} to {_pct(max(dmax), 2)} % of p0. The part of the scene's "
            "error that enlarging the bodies removes is the finite-body effect, which no "
            "refinement of the contact zone removes. The largest errors sit at the contact "
            "edges and stick–slip boundaries, where the exact traction has a square-root or "
            "kink singularity, and need not fall monotonically with refinement.",
        ]
    out += ["", _monotonic_sentence(rows)]
    return [*out, ""]


def _falls(values: Sequence[float]) -> bool:
    return all(b < a for a, b in itertools.pairwise(values))


def _monotonic_sentence(rows) -> str:
    """Which error series fall at every level, from 31 pairs on, per body size."""
    parts = []
    for bodies, where in ((1.0, "the scene's bodies"), (LARGE, f"the {LARGE:g}× bodies")):
        runs = {k: [r for r in v if r["pairs"] >= 31] for k, v in series(rows, bodies).items()}
        runs = {k: v for k, v in runs.items() if len(v) >= 3}
        if not runs:
            continue
        for error in ("e_q_l2", "e_q_max"):
            falling = [
                family_label(k) for k, v in sorted(runs.items()) if _falls([r[error] for r in v])
            ]
            name = "L2" if error == "e_q_l2" else "largest"
            parts.append(
                f"on {where} the {name} shear error falls at every level from 31 pairs for "
                + (", ".join(falling) if falling else "no family")
                + f" (of {len(runs)})"
            )
    return ("Monotonic convergence: " + "; ".join(parts) + ".") if parts else ""


def _factors(rows) -> str:
    return ", ".join(f"×{f:g}" for f in sorted({r["rest"] for r in rows}))


def rest_section(rows) -> list[str]:
    checks = [r for r in rows if r["rest"] != 1]
    if not checks:
        return []
    out = [
        "## Refinement of the rest of the bodies",
        "",
        "The contact zone is kept; the element counts of the flanks, sides and top/bottom "
        "(scene: 16, 12, 12 per body) are scaled. Change of the tractions at any pair and step "
        "against the scene's refinement, in % of p0 (pressure) and of f p0 (shear):",
        "",
        "| family | p | pairs | rest × | DOFs | change p | change q | e_q max | e_q L2 |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in sorted(checks, key=lambda r: (r["family"], r["degree"], r["pairs"], r["rest"])):
        out.append(
            f"| {r['family']} | {r['degree']} | {r['pairs']} | {r['rest']:g} | {r['dofs']} | "
            f"{_pct(r['rest_change_p'], 4)} | {_pct(r['rest_change_q'], 4)} | "
            f"{_pct(r['e_q_max'])} | {_pct(r['e_q_l2'])} |"
        )
    finer = [r for r in checks if r["rest"] > 1]
    coarser = [r for r in checks if r["rest"] < 1]
    if finer:
        worst = max(max(r["rest_change_p"], r["rest_change_q"]) for r in finer)
        out += [
            "",
            f"Refining the rest further ({_factors(finer)}) "
            f"changes no traction by more than {_pct(worst, 3)} % of p0 (or f p0)",
        ]
        if coarser:
            worst_c = max(max(r["rest_change_p"], r["rest_change_q"]) for r in coarser)
            out[-1] += (
                f"; coarsening it ({_factors(coarser)}) changes them by up to {_pct(worst_c, 3)} %"
            )
        out[-1] += "."
    return [*out, ""]


def exponent_section(rows) -> list[str]:
    out = [
        "## Fitted exponents",
        "",
        "Least-squares slopes of log(error) against log(pairs) (the zone's element size is "
        "2 × 1.5 a / pairs), over all levels and, in brackets, from 61 pairs on; negative is "
        "converging. The max errors are dominated by single nodes at the contact edges and "
        "stick–slip boundaries, so their slopes are rough. The last two columns are slopes "
        "against DOFs: of the L2 shear error (from 61 pairs on) and of the wall time.",
        "",
        "| bodies | family | p | e_p max | e_q max | e_p L2 | e_q L2 | e_q L2 vs DOFs "
        "| wall vs DOFs |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for bodies in (1.0, LARGE):
        tails = exponents(rows, bodies, min_pairs=PAPER_PAIRS)
        for key, fit in sorted(exponents(rows, bodies).items()):
            if math.isnan(fit["e_q_l2_pairs"]):
                continue
            tail = tails.get(key, {})
            cells = [
                f"{fit[f'{e}_pairs']:.2f} ({tail.get(f'{e}_pairs', math.nan):.2f})" for e in ERRORS
            ]
            out.append(
                f"| ×{bodies:g} | {key[0]} | {key[1]} | "
                + " | ".join(cells)
                + f" | {tail.get('e_q_l2_dofs', math.nan):.2f} | {fit['wall_dofs']:.2f} |"
            )
    return [*out, ""]


__all__ = ["exponent_section", "finite_body_section", "main_table", "rest_section", "step_tables"]
