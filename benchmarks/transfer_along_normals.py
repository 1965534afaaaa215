"""Cost of the traction transfer along each pair's normal against the one along the shared
tangent, on examples/gross_sliding_arc.toml's faces (the pad slid 1 mm along the arc).

Along an arc with a frame per pair the specimen's nodes take the pad's tractions along the
lower face's normals (:data:`fretbem.contact.transfer.ALONG_NORMALS`); before, along the
pad's tangent (:data:`~fretbem.contact.transfer.TRANSFERS`). Each is computed once per
re-pairing. Interleaved rounds in one process, medians and their ratio (normals / tangent)
per pad pair count and transfer, and the whole pairing (projection and transfer) with
each frame.

    OPENBLAS_NUM_THREADS=1 python benchmarks/transfer_along_normals.py --sizes 31 61 121
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from pathlib import Path

import attrs
import numpy as np
import tomllib

from fretbem.contact.transfer import ALONG_NORMALS, TRANSFERS, NormalMap
from fretbem.scenes.builder import build
from fretbem.scenes.file import scene_from_data
from fretbem.sliding.track import Track

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "gross_sliding_arc.toml"


def pair_at(pairs: int):
    """The example's pair at ``pairs`` pad pairs, the pad slid 1 mm along the arc."""
    data = tomllib.loads(EXAMPLE.read_text())
    data["contact"]["pairs"] = pairs
    pair = build(scene_from_data(data))[0].pair
    return Track.of(pair).placed(attrs.evolve(pair, slave="upper"), 1.0)


def transfers(pair, name: str):
    """The two transfer calls of ``pair`` (the pad the slave, the specimen the master)."""
    lower, upper = pair._field("lower"), pair._field("upper")
    nodes, normals = pair._face("lower")
    mean = -pair._face("upper")[1].mean(axis=0)
    mean /= np.linalg.norm(mean)
    tangent = np.array([mean[1], -mean[0]])
    order = np.argsort(pair._face("upper")[0] @ tangent)
    mapping = NormalMap(lower, upper, np.zeros(2), "master", tangent)
    return {
        "tangent": lambda: TRANSFERS[name](lower, upper, nodes @ tangent, tangent, order),
        "normals": lambda: ALONG_NORMALS[name](mapping, nodes, normals, order),
    }


def seconds(call) -> float:
    tic = time.perf_counter()
    call()
    return time.perf_counter() - tic


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[31, 61, 121])
    parser.add_argument("--rounds", type=int, default=7)
    args = parser.parse_args(argv)
    print(f"load average {os.getloadavg()[0]:.2f}, {args.rounds} interleaved rounds, medians")
    print(f"{'pairs':>5} {'what':<22} {'tangent ms':>11} {'normals ms':>11} {'ratio':>7}")
    for pairs in args.sizes:
        pair = pair_at(pairs)
        calls = {name: transfers(pair, name) for name in ("conservative", "pointwise")}
        calls["pairing"] = {
            "tangent": lambda p=pair: attrs.evolve(p, frame="shared").pairing(),
            "normals": lambda p=pair: attrs.evolve(p, frame="local").pairing(),
        }
        samples = {(what, how): [] for what in calls for how in ("tangent", "normals")}
        for _ in range(args.rounds):
            for what, pair_calls in calls.items():
                for how, call in pair_calls.items():
                    samples[what, how].append(seconds(call))
        for what in calls:
            t, n = (statistics.median(samples[what, how]) for how in ("tangent", "normals"))
            print(f"{pairs:>5} {what:<22} {1e3 * t:>11.2f} {1e3 * n:>11.2f} {n / t:>7.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
