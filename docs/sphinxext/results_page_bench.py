"""The performance section of the results page, from ``benchmarks/performance.py --json``."""

from __future__ import annotations

import math
import statistics
from collections.abc import Sequence

from results_page_format import threads as _threads


def benchmark_section(runs: Sequence[dict]) -> list[str]:
    """Benchmark medians of one or more ``benchmarks/performance.py --json`` files."""
    runs = [runs] if isinstance(runs, dict) else list(runs)
    out = ["## Performance budget", ""]
    m = runs[0].get("machine", {})
    out += [
        f"`benchmarks/performance.py` on {m.get('cores')} cores, {m.get('processor')}, "
        f"Python {m.get('python')}, numpy {m.get('numpy')}; medians of at least 5 runs. "
        "Columns: the BLAS thread setting and the machine's 1-minute load average at the start "
        "(the machine was shared).",
        "",
    ]
    labels = [
        f"{_threads(r['machine'])}, load {r['machine'].get('load_average_1min', math.nan):.1f}"
        for r in runs
    ]
    out += [
        "| benchmark | target | " + " | ".join(labels) + " |",
        "|---|---:|" + "---:|" * len(runs),
    ]
    order: dict[str, dict] = {}
    for r in runs:
        for item in r.get("results", []):
            order.setdefault(item["key"], item)
    for key, first in order.items():
        unit = first.get("unit", "s")
        target = first.get("target")
        cells = []
        for r in runs:
            item = next((i for i in r.get("results", []) if i["key"] == key), None)
            if item is None:
                cells.append("–")
                continue
            verdict = ""
            if target is not None:
                verdict = " ✓" if item["median"] <= target else " **missed**"
            value = f"{item['median']:.0f}" if unit == "MiB" else f"{item['median']:.3g}"
            cells.append(f"{value} {unit}{verdict}")
        out.append(
            f"| {first['name']} | {'–' if target is None else f'≤ {target:g} {unit}'} | "
            + " | ".join(cells)
            + " |"
        )
    for key, first in order.items():
        target = first.get("target")
        if target is None:
            continue
        missed = [
            label
            for label, r in zip(labels, runs, strict=True)
            for item in r.get("results", [])
            if item["key"] == key and item["median"] > target
        ]
        if missed:
            out += ["", f"Target missed: {first['name']} with {'; '.join(missed)}."]
    if len({_threads(r["machine"]) for r in runs}) > 1:
        out += [
            "",
            "The columns differ in the environment's BLAS thread setting. With OpenBLAS's "
            "default (one thread per core) every dense solve is split across both cores; when "
            "another process occupies one of them, each call waits for the descheduled helper "
            "thread, and the small solves of the contact iteration became one to two orders "
            "of magnitude slower (1.65 s for the 61-pair cycle on a loaded machine). The "
            "Newton iteration therefore limits BLAS to one thread itself (threadpoolctl), "
            "which costs little at these matrix sizes and makes the two columns agree; the "
            "environment setting still governs assembly and factorisation.",
        ]
    for r in runs:
        for item in r.get("results", []):
            if item["key"] == "assembly_largest" and "series" in item:
                sizes = ", ".join(
                    f"{p['dofs']} DOFs {statistics.median(p['times']):.3g} s"
                    for p in item["series"]
                )
                out += [
                    "",
                    f"Assembly of one body ({_threads(r['machine'])}): {sizes}; fitted exponent "
                    f"{item['exponent']:.2f} over all sizes, {item['exponent_upper_half']:.2f} "
                    "over the upper half.",
                ]
            if item["key"] == "step_481" and "series" in item:
                sizes = ", ".join(
                    f"{p['pairs']} pairs {1e3 * statistics.median(p['times']):.3g} ms"
                    for p in item["series"]
                )
                out += [
                    "",
                    f"One load step on the condensed problem ({_threads(r['machine'])}): {sizes}; "
                    f"fitted exponent {item['exponent']:.2f} against pairs.",
                ]
    return [*out, ""]


__all__ = ["benchmark_section"]
