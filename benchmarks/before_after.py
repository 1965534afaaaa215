"""Before against after on a shared machine: the old and new code timed in alternation.

Each round runs every case once with the old tree and once with the new one (fresh
processes, ``PYTHONPATH`` pointing at each tree's framework/ and plugins/), so both see
the same load; the medians and their ratio go into the JSON under "interleaved".

    git archive a3483b2 | tar -x -C /tmp/before    # the code before issue 16
    git archive HEAD | tar -x -C /tmp/after
    python benchmarks/before_after.py --before /tmp/before --after /tmp/after \\
        --json docs/results/performance.json
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time

CYCLE = """
import json, sys
from threadpoolctl import threadpool_limits
from fretbem.scenes import cattaneo_mindlin
from fretbem.simulation import run
with threadpool_limits(limits=1, user_api="blas"):
    result = run(cattaneo_mindlin(basis="nurbs", pairs={pairs}))
print(json.dumps(dict(result.timings)))
"""


def _env(tree: str) -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(
        [os.path.join(tree, "framework"), os.path.join(tree, "plugins")]
    )
    return env


def _cases(out_dir: str) -> dict:
    demo = [sys.executable, "-m", "fretbem.app.cli", "demo"]
    return {
        "demo_bare": [*demo, "--no-figures", "--no-vtk", "--out"],
        "demo_full": [*demo, "--out"],
        "cycle_61": [sys.executable, "-c", CYCLE.format(pairs=61)],
        "cycle_961": [sys.executable, "-c", CYCLE.format(pairs=961)],
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--before", required=True, help="tree of the old code")
    parser.add_argument("--after", required=True, help="tree of the new code")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--only", nargs="+")
    parser.add_argument("--json")
    args = parser.parse_args(argv)
    results: dict = {}
    with tempfile.TemporaryDirectory() as tmp:
        cases = _cases(tmp)
        names = args.only or list(cases)
        for k in range(args.rounds):
            for name in names:
                for label, tree in (("before", args.before), ("after", args.after)):
                    command = list(cases[name])
                    if command[-1] == "--out":
                        command.append(os.path.join(tmp, f"{name}-{label}-{k}"))
                    tic = time.perf_counter()
                    done = subprocess.run(
                        command, env=_env(tree), capture_output=True, text=True, check=True
                    )
                    seconds = time.perf_counter() - tic
                    row = results.setdefault(name, {}).setdefault(label, {"process": []})
                    row["process"].append(seconds)
                    if name.startswith("cycle"):
                        row.setdefault("in_process", []).append(
                            json.loads(done.stdout.strip().splitlines()[-1])["total"]
                        )
                    print(f"round {k}: {name} {label} {seconds:.3f} s", flush=True)
    summary = {}
    for name, rows in results.items():
        summary[name] = {}
        for label, row in rows.items():
            summary[name][label] = {key: statistics.median(v) for key, v in row.items()}
        key = "in_process" if name.startswith("cycle") else "process"
        summary[name]["speedup"] = summary[name]["before"][key] / summary[name]["after"][key]
        print(
            f"{name}: before {summary[name]['before'][key]:.3f} s, after "
            f"{summary[name]['after'][key]:.3f} s ({summary[name]['speedup']:.1f}x)"
        )
    summary["load_average"] = os.getloadavg()[0]
    if args.json:
        with open(args.json) as handle:
            data = json.load(handle)
        data.setdefault("interleaved", {}).update(summary)
        with open(args.json, "w") as handle:
            json.dump(data, handle, indent=1)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
