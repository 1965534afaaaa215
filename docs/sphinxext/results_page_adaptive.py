"""The adaptive mode's section of the results page: its budget series, the cheapest run of
every series to a given error (which family is cheaper), and the sawtooth against pairs."""

from __future__ import annotations

import itertools
import statistics
from collections.abc import Sequence

from results_page_format import pct as _pct
from results_page_format import seconds as _seconds

from fretbem.studies.convergence.analysis import (
    LEVELS,
    adaptive_series,
    all_series,
    cheapest,
    family_label,
    sawtooth_families,
    series_label,
    settled_from,
)
from fretbem.studies.convergence.study import ERRORS

#: error levels of the sawtooth table (e_q max)
SETTLE_LEVELS = (0.05, 0.02, 0.01)
#: times closer than this ratio are not called different
NOISE = 1.25
_NAMES = {"e_q_max": "largest shear error", "e_q_l2": "L2 shear error"}

#: the series in docs/results were measured before the adaptive mode ran on any scene
PREVIOUS_MODE = (
    "*Measured with the previous adaptive mode (a knot margin of 0.1 % of a, before the "
    "adaptive mode ran on any scene); the current mode's budget table against converged "
    'solutions is in {doc}`explanation/adaptive` ("Any scene") and '
    "docs/results/adaptive_budgets.csv.*"
)


def adaptive_section(
    rows: Sequence[dict],
    adaptive: Sequence[dict],
    tooth: Sequence[dict] = (),
    figure: str | None = None,
) -> list[str]:
    """Markdown lines of the adaptive section (nothing without adaptive runs)."""
    if not adaptive:
        return []
    out = [
        "## The adaptive mode",
        "",
        PREVIOUS_MODE,
        "",
        *_intro(adaptive),
        *_budget_table(adaptive),
    ]
    out += _estimate_sentence(adaptive)
    out += _cheapest_section(rows, adaptive)
    if tooth:
        out += _sawtooth_section(tooth, figure)
    return out


def _intro(adaptive) -> list[str]:
    tolerances = sorted({r["tolerance"] for r in adaptive})
    repeats = sorted({r["repeats"] for r in adaptive})
    runs = "one run" if repeats == [1] else f"{'/'.join(str(r) for r in repeats)} runs"
    return [
        "`fretbem.accuracy.adaptive.run_adaptive` with a pair budget N: "
        "a uniform first level finds "
        "the contact edges and the stick–slip boundaries of every step, the contact faces are "
        "re-meshed with breakpoints on them and solved again at up to N pairs, and the last "
        "two levels give the mode's own error estimate ({doc}`explanation/adaptive`). The "
        f"study sets the tolerance to {', '.join(f'{t:g}' for t in tolerances)}, below any "
        "estimate, so the budget ends every run. *DOFs* are those of the finest level; "
        f"*wall* is all levels from building the scene, every assembly included (median of "
        f"{runs}); *levels* are the pair counts solved in turn (the last ones re-solve the "
        "finest level with its contact-edge breakpoints moved). Errors and estimates in %, "
        "largest over steps B–E.",
        "",
    ]


def _budget_table(adaptive) -> list[str]:
    head = " | ".join(f"{e[:3]} {e[4:].replace('l2', 'L2')} | est." for e in ERRORS)
    out = [
        f"| family | budget | levels | DOFs | {head} | iterations | wall |",
        "|---|---:|---|---:|" + "---:|" * (2 * len(ERRORS)) + "---:|---:|",
    ]
    for key, runs in adaptive_series(adaptive).items():
        for r in runs:
            cells = " | ".join(f"{_pct(r[e])} | {_pct(r[f'estimate_{e}'])}" for e in ERRORS)
            out.append(
                f"| {family_label(key)} | {r['budget']} | {r['levels']} | {r['dofs']} | "
                f"{cells} | {r['iterations']} | {_seconds(r['wall_s'])} |"
            )
    return [*out, ""]


def _estimate_sentence(adaptive) -> list[str]:
    parts = []
    for key, runs in adaptive_series(adaptive).items():
        ratios = [r["estimate_e_q_max"] / r["e_q_max"] for r in runs if r["e_q_max"] > 0]
        if ratios:
            parts.append(f"{min(ratios):.2f} to {max(ratios):.2f} ({family_label(key)})")
    if not parts:
        return []
    return [
        "The estimate of the largest shear error over the error against theory: "
        + ", ".join(parts)
        + " (1 is exact; below 1 the estimate promises too much).",
        "",
    ]


def _cell(found: tuple[dict | None, dict | None]) -> str:
    fewest, fastest = found
    if fewest is None:
        return "–"
    return f"{fewest['dofs']} / {_seconds(fastest['wall_s'])}"


def _which(row: dict, key: tuple) -> str:
    size = f"budget {row['budget']}" if key[2] == "adaptive" else f"{row['pairs']} pairs"
    return f"{series_label(key)} ({size}, {row['dofs']} DOFs, {_seconds(row['wall_s'])} s)"


def _best_per_family(found: dict, column: str) -> list[tuple[tuple, dict]]:
    """(series key, run) with the least ``column`` per family (any degree or mode), best
    family first."""
    slot = 0 if column == "dofs" else 1
    best: dict[str, tuple[tuple, dict]] = {}
    for key, runs in found.items():
        run = runs[slot]
        if run is not None and (key[0] not in best or run[column] < best[key[0]][1][column]):
            best[key[0]] = (key, run)
    return sorted(best.values(), key=lambda kr: kr[1][column])


def _family_answer(error: str, level: float, found: dict) -> str:
    """Which family reaches ``level`` in the least time (and which in the fewest DOFs)."""
    name = f"{_NAMES[error]} ≤ {100 * level:g} %"
    by_time, by_dofs = _best_per_family(found, "wall_s"), _best_per_family(found, "dofs")
    if not by_time:
        return f"- {name}: no run of the study gets there."
    (key, row), others = by_time[0], by_time[1:]
    text = f"- {name}: **{key[0]}** is cheapest in time, {_which(row, key)}"
    text += "".join(f"; {k[0]} at best {_which(r, k)}" for k, r in others)
    if others and others[0][1]["wall_s"] < NOISE * row["wall_s"]:
        text += " (a difference of times within the noise of a shared machine)"
    missing = sorted({k[0] for k in found} - {k[0] for k, _ in by_time})
    if missing:
        text += f"; {', '.join(missing)} never"
    if by_dofs[0][0][0] != key[0]:
        text += f". In DOFs {by_dofs[0][0][0]} is cheaper: {_which(by_dofs[0][1], by_dofs[0][0])}"
    return text + "."


def _cheapest_section(rows, adaptive) -> list[str]:
    everything = all_series(rows, adaptive)
    keys = sorted(everything, key=lambda k: (k[2] == "adaptive", k[:2]))
    pairs = sorted({r["pairs"] for k, runs in everything.items() if k[2] == "fixed" for r in runs})
    budgets = sorted({r["budget"] for r in adaptive})
    span = lambda v: f"{v[0]} to {v[-1]}" if len(v) > 1 else str(v[0])  # noqa: E731
    fixed = f"fixed pairs at {span(pairs)} pairs on the scene's bodies, " if pairs else ""
    out = [
        "### Which family is cheaper for a given error",
        "",
        "Per series, the fewest DOFs and the least wall time of the runs at or below each "
        f"error level ({fixed}the adaptive mode at budgets {span(budgets)}; – none). A "
        "largest error over the pairs falls unevenly with refinement (the sawtooth below), "
        "so a run below a level does not promise that the next finer one is.",
        "",
        "| error ≤ | " + " | ".join(series_label(k) for k in keys) + " |",
        "|---|" + "---:|" * len(keys),
    ]
    answers = []
    for error, levels in LEVELS.items():
        for level in levels:
            found = cheapest(rows, adaptive, error, level)
            name = "e_q max" if error == "e_q_max" else "e_q L2"
            cells = " | ".join(_cell(found.get(k, (None, None))) for k in keys)
            out.append(f"| {name} {100 * level:g} % | {cells} |")
            answers.append(_family_answer(error, level, found))
    head = "Which family is cheaper, with the adaptive mode included (every degree and mode):"
    return [*out, "", head, "", *answers, ""]


def _jump(values: Sequence[float]) -> float:
    """Largest ratio between neighbouring values (either way)."""
    return max((max(a / b, b / a) for a, b in itertools.pairwise(values)), default=1.0)


def _sawtooth_section(tooth, figure) -> list[str]:
    families = sawtooth_families(tooth)
    lo = min(r["pairs"] for r in tooth)
    hi = max(r["pairs"] for r in tooth)
    out = [
        "### Error against pair count: the sawtooth",
        "",
        f"At every pair count N from {lo} to {hi} that the family can place (odd N for "
        "lagrange2), one run with `pairs = N` (uniform zone) and one adaptive run with budget "
        "N. The largest error of the fixed mode jumps with where the pairs fall relative to "
        "the contact edges and stick–slip boundaries; the adaptive mode puts breakpoints on "
        "them.",
        "",
    ]
    if figure:
        out += [f"![e_q max against pair count, fixed and adaptive]({figure})", ""]
    heads = " | ".join(f"≤ {100 * v:g} % from N" for v in SETTLE_LEVELS)
    out += [
        f"e_q max over N = {lo}–{hi}: its range, the largest ratio between neighbouring N, "
        "the pair count from which it stays at or below each level up to "
        f"N = {hi} (– not within the range), and the median single-run wall time:",
        "",
        f"| family | mode | e_q max | jump | {heads} | wall |",
        "|---|---|---:|---:|" + "---:|" * len(SETTLE_LEVELS) + "---:|",
    ]
    for key, runs in families.items():
        for mode in ("fixed", "adaptive"):
            values = [r[f"{mode}_e_q_max"] for r in runs]
            settle = [settled_from(runs, f"{mode}_e_q_max", v) for v in SETTLE_LEVELS]
            wall = statistics.median(r[f"{mode}_wall_s"] for r in runs)
            out.append(
                f"| {family_label(key)} | {mode} | {_pct(min(values), 2)}–{_pct(max(values), 2)}"
                f" | {_jump(values):.1f}× | "
                + " | ".join("–" if n is None else str(n) for n in settle)
                + f" | {_seconds(wall)} |"
            )
    return [*out, ""]


__all__ = ["adaptive_section"]
