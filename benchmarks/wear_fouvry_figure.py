"""The figure of the Fouvry et al. (2017) radius series run by wear_fouvry_series.py.

Reads the fouvry_series_<R>.json files given (or every one in the current folder) and draws
docs/results/wear_fouvry_series.png: the specimen's and the pad's worn profiles after 5000
cycles for each radius, and the total wear volume against the accumulated friction energy.

    python benchmarks/wear_fouvry_figure.py r10/fouvry_series_10.json ... --out fig.png
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np


def pad_points(row: dict) -> np.ndarray:
    """The pad's own points of a row written without them: its scene built again."""
    from wear_fouvry_series import scene

    from fretbem.wear.slide import Track

    simulation = scene(row["R"], row["P"], row["zone"], row["delta_block"], row["pairs"])
    return Track.start(simulation).unworn().upper_x


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="*", type=Path)
    parser.add_argument("--out", type=Path, default=Path("wear_fouvry_series.png"))
    args = parser.parse_args()
    rows = {}
    for path in args.files or sorted(Path().glob("fouvry_series_*.json")):
        rows.update({int(k): v for k, v in json.loads(path.read_text()).items()})
    fig, (specimen, pad, volume) = plt.subplots(1, 3, figsize=(14, 3.8))
    for radius in sorted(rows):
        row = rows[radius]
        label = f"R = {radius} mm"
        specimen.plot(row["x"], 1e3 * np.array(row["h_specimen"]), label=label)
        pad.plot(row.get("x_pad") or pad_points(row), 1e3 * np.array(row["h_pad"]), label=label)
        volume.plot(row["energy_J_per_mm"], row["volume_total"], "o-", label=label)
    specimen.set(xlabel="x on the specimen (mm)", ylabel="wear depth (um)",
                 title="specimen scars, N = 5000")  # fmt: skip
    pad.set(xlabel="x on the pad (mm)", title="pad scars, N = 5000")
    for ax in (specimen, pad):
        ax.invert_yaxis()
        ax.set_xlim(-5, 5)
    volume.set(xlabel="accumulated friction energy (J/mm)", ylabel="wear volume (mm^3/mm)",
               title="volume against energy")  # fmt: skip
    volume.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
