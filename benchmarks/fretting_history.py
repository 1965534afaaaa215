"""Time of a fretting history: 10 cycles of 40 increments at 61 pairs (issue 22).

For each body model (bem, half-plane) and regime (partial slip at 0.4 delta_t, gross slip
at 1.1 delta_t, delta_t the model's own onset displacement) the 401-step history is solved
on the prepared (assembled and condensed) pair, then analysed (loops, slip, energy) and its
fretting files written (loops.csv, slip.csv, loops.png, slip.png). The peer measured in the
same runs is the reference five-step force cycle on the same pair, so the ratio per step
says what driving by displacement and keeping every increment cost. Every time is the
median of ``--runs`` interleaved runs after a warm-up; the machine load is printed.

    OPENBLAS_NUM_THREADS=1 python benchmarks/fretting_history.py --runs 5 --json fretting.json
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import tempfile
import time
from pathlib import Path

from fretbem.fretting import Waveform, analyse
from fretbem.fretting.cycles import onset_displacement
from fretbem.output.fretting import write_fretting
from fretbem.scenes.builder import build
from fretbem.scenes.spec import scene_from_dict
from fretbem.simulation import LoadStep, Simulation, run

P, F = 100.0, 0.3
CYCLES, INCREMENTS, PAIRS = 10, 40, 61


def prepared(model: str) -> Simulation:
    data = {
        "pad": {"model": model},
        "specimen": {"model": model},
        "contact": {"pairs": PAIRS, "friction": F},
        "load": {"steps": ["A", "B"], "P": P, "Q": [0.0, 18.0]},
    }
    simulation, _ = build(scene_from_dict(data))
    simulation.prepare()
    return simulation


def cases(model: str) -> dict[str, Simulation]:
    base = prepared(model)
    onset = onset_displacement(base.prepare(), run(base).steps[0], F)
    out = {}
    for regime, factor in (("partial slip", 0.4), ("gross slip", 1.1)):
        waveform = Waveform(factor * onset, P, cycles=CYCLES, increments=INCREMENTS)
        out[regime] = Simulation(base.pair, waveform.steps(), law=base.law)
    q = 0.6 * F * P
    peer = [LoadStep(n, P, v) for n, v in zip("ABCDE", (0.0, q, 0.0, -q, 0.0), strict=True)]
    out["five-step force cycle"] = Simulation(base.pair, peer, law=base.law)
    return out


def timed(simulation: Simulation, directory: Path) -> dict:
    tic = time.perf_counter()
    result = run(simulation)
    solve = time.perf_counter() - tic
    tic = time.perf_counter()
    analysis = analyse(result)
    analysed = time.perf_counter() - tic
    tic = time.perf_counter()
    write_fretting(result, directory)
    written = time.perf_counter() - tic
    steps = len(result.steps)
    regime = analysis.cycles[-1].regime if analysis.cycles else "-"
    return {"solve": solve, "analyse": analysed, "write": written, "steps": steps,
            "iterations": sum(s.iterations for s in result.steps), "regime": regime}  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()
    print(f"load average before: {os.getloadavg()}")
    runs = {model: cases(model) for model in ("bem", "half-plane")}
    samples: dict[tuple[str, str], list[dict]] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(args.runs + 1):  # the first round warms up
            for model, simulations in runs.items():
                for name, simulation in simulations.items():
                    record = timed(simulation, Path(tmp))
                    if k:
                        samples.setdefault((model, name), []).append(record)
    print(f"load average after: {os.getloadavg()}")
    table = []
    for (model, name), records in samples.items():
        row = {"model": model, "case": name, "steps": records[0]["steps"],
               "regime": records[0]["regime"], "iterations": records[0]["iterations"]}  # fmt: skip
        for key in ("solve", "analyse", "write"):
            row[key] = statistics.median(r[key] for r in records)
        table.append(row)
    for row in table:
        peer = next(r for r in table if r["model"] == row["model"] and r["steps"] == 5)
        row["per_step_vs_peer"] = (row["solve"] / row["steps"]) / (peer["solve"] / peer["steps"])
        print(
            f"{row['model']:>10} {row['case']:<22} {row['steps']:4d} steps "
            f"{row['iterations']:5d} its  solve {row['solve']:.3f} s  analyse "
            f"{row['analyse']:.3f} s  write {row['write']:.3f} s  per step x"
            f"{row['per_step_vs_peer']:.2f} the force cycle's  ({row['regime']})"
        )
    if args.json:
        args.json.write_text(json.dumps({"runs": args.runs, "table": table}, indent=2) + "\n")


if __name__ == "__main__":
    main()
