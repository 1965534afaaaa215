"""Cost of node-to-segment pairing against node-to-node: the reference cycle at several sizes.

Each round builds the reference scene afresh (assembly included) and runs its five-step
cycle once per pairing, alternating the pairings so both see the same machine load; the
medians over rounds and their ratio (node-to-segment / node-to-node) are printed and, with
``--json``, written. "total" is the whole run; "contact" the pairing, condensation and
Newton steps (the part the pairing changes: assembly and factorisation are the same).

    OPENBLAS_NUM_THREADS=1 python benchmarks/pairing_cost.py --sizes 61 121 241 --rounds 5
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import time

import attrs

from fretbem.contact.node_to_segment import NodeToSegmentPair
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run


def cycle(pairs: int, pairing: str, upper_pairs: int | None = None) -> dict[str, float]:
    """Timings (s) of one fresh reference cycle with ``pairing``; ``upper_pairs`` gives the
    pad its own count (node-to-segment only)."""
    start = time.perf_counter()
    simulation = cattaneo_mindlin(pairs=pairs)
    if pairing == "node-to-segment":
        upper = simulation.pair.upper
        if upper_pairs is not None:
            upper = cattaneo_mindlin(pairs=upper_pairs).pair.upper
        simulation = attrs.evolve(simulation, pair=NodeToSegmentPair(upper, simulation.pair.lower))
    result = run(simulation)
    timings = dict(result.timings)
    timings["total"] = time.perf_counter() - start
    timings["contact"] = timings["condensation"] + timings["steps"]
    return timings


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[61, 121, 241])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--json")
    args = parser.parse_args(argv)
    cases = [(n, p, None) for n in args.sizes for p in ("node-to-node", "node-to-segment")]
    cases.append((61, "node-to-segment", 97))  # mismatched faces: a 97-point pad on 61
    samples: dict[tuple, list[dict]] = {case: [] for case in cases}
    cycle(21, "node-to-segment")  # warm the imports and caches
    for _ in range(args.rounds):
        for case in cases:
            samples[case].append(cycle(*case))
    out = {"load": os.getloadavg(), "rounds": args.rounds, "cases": []}
    print(f"load average {os.getloadavg()[0]:.2f}, {args.rounds} interleaved rounds, medians (s)")
    print(f"{'pairs':>5} {'pairing':<24} {'total':>8} {'contact':>8} {'ratio total':>12} "
          f"{'ratio contact':>14}")  # fmt: skip
    for case in cases:
        n, pairing, upper = case
        median = {k: statistics.median(s[k] for s in samples[case]) for k in ("total", "contact")}
        peer = samples.get((n, "node-to-node", None))
        ratio = {
            k: median[k] / statistics.median(s[k] for s in peer) for k in median
        } if peer else {}  # fmt: skip
        label = pairing + (f" (pad {upper})" if upper else "")
        r_total, r_contact = (ratio.get(k, float("nan")) for k in ("total", "contact"))
        print(f"{n:>5} {label:<24} {median['total']:8.3f} {median['contact']:8.4f} "
              f"{r_total:12.2f} {r_contact:14.2f}")  # fmt: skip
        out["cases"].append({"pairs": n, "pairing": label, **median, "ratio": ratio})
    if args.json:
        with open(args.json, "w") as handle:
            json.dump(out, handle, indent=2)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
