"""Fretting outputs: loops.csv, slip.csv, summary.json's fretting table, units, figures."""

from __future__ import annotations

import csv
import json

import matplotlib.image as mpimg
import numpy as np
import pytest

from fretbem.fretting import analyse
from fretbem.output.write import write_results
from fretbem.pipeline import run_scene
from fretbem.scenes.spec import scene_from_dict

SCENE = {
    "pad": {"model": "half-plane"},
    "specimen": {"model": "half-plane"},
    "contact": {"pairs": 21},
    "load": {"P": 100.0, "cycle": {"delta": 0.003, "cycles": 2, "increments": 8}},
}


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    run = run_scene(scene_from_dict(SCENE))
    out = run.write(tmp_path_factory.mktemp("fretting") / "out", writers=(
        "csv", "json", "units", "figures", "fretting"))  # fmt: skip
    return run.result, out


def _rows(path):
    with open(path, newline="") as handle:
        return list(csv.reader(handle))


def test_loops_csv_has_every_increment(saved):
    result, out = saved
    rows = _rows(out / "loops.csv")
    assert rows[0] == ["increment", "cycle", "Q", "delta", "P", "M", "theta", "step"]
    assert len(rows) - 1 == 1 + 2 * 8
    analysis = analyse(result)
    np.testing.assert_allclose([float(r[2]) for r in rows[1:]], analysis.tangential, rtol=1e-15)
    np.testing.assert_allclose([float(r[3]) for r in rows[1:]], analysis.delta, rtol=1e-15)
    assert [int(r[1]) for r in rows[1:]] == [0] + [1] * 8 + [2] * 8
    assert max(float(r[2]) for r in rows[1:]) == pytest.approx(0.3 * 100.0)  # gross slip


def test_slip_csv_and_summary_cycles(saved):
    result, out = saved
    rows = _rows(out / "slip.csv")
    assert rows[0] == ["cycle", "x", "slip_amplitude", "energy_density"]
    pairs = len(result.steps[0].x)
    assert len(rows) - 1 == 2 * pairs
    summary = json.loads((out / "summary.json").read_text())
    cycles = summary["fretting"]["cycles"]
    assert [c["cycle"] for c in cycles] == [1, 2]
    assert all(c["regime"] == "gross slip" for c in cycles)
    weights = analyse(result).weights
    density = np.array([float(r[3]) for r in rows[1:] if r[0] == "2"])
    assert weights @ density == pytest.approx(cycles[1]["dissipated_energy"], rel=1e-12)
    assert cycles[1]["energy_ratio"] > summary["fretting"]["transition_ratio"] > 0
    assert cycles[1]["energy_ratio"] == pytest.approx(
        cycles[1]["dissipated_energy"]
        / (4 * cycles[1]["delta_amplitude"] * cycles[1]["Q_amplitude"])
    )
    assert summary["units"]["fretting"]["dissipated_energy"] == "N mm/mm"
    assert summary["steps"][1]["control"] == {"normal": "force", "tangential": "displacement"}
    units = json.loads((out / "units.json").read_text())
    assert set(units["loops.csv"]) == {
        "increment",
        "cycle",
        "Q",
        "delta",
        "P",
        "M",
        "theta",
        "step",
    }
    assert units["slip.csv"]["slip_amplitude"]["unit"] == "mm"


def test_figures_of_the_loops(saved):
    _, out = saved
    for name in ("loops.png", "slip.png"):
        height, width = mpimg.imread(out / name).shape[:2]
        assert 300 < width <= 1800 and 300 < height <= 1000


def test_history_without_cycles_writes_loops_only(tmp_path):
    named = {**SCENE, "load": {"steps": ["A", "B"], "P": 100.0, "delta": [0.0, 0.001]}}
    run = run_scene(scene_from_dict(named))
    out = write_results(run.result, tmp_path / "out", writers=("json", "fretting", "figures"))
    assert (out / "loops.csv").exists()
    assert not (out / "slip.csv").exists() and not (out / "loops.png").exists()
    assert "fretting" not in json.loads((out / "summary.json").read_text())
