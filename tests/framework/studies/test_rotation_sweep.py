"""Sweeps over the new keys: the pad block's moment, the rig's rotational stiffness and
pivot, and the mean-stress correction. Every swept value is honoured (each case equals the
scene solved directly with that value) or refused before any case is solved."""

from __future__ import annotations

import copy

import numpy as np
import pytest

from fretbem.fatigue import fatigue_request_from_dict
from fretbem.fatigue.from_simulation import SimulationStressHistory
from fretbem.fatigue.run import run_fatigue
from fretbem.scenes.builder import build
from fretbem.scenes.spec import scene_from_dict
from fretbem.simulation import run
from fretbem.studies.sweep.cases import step_metrics
from fretbem.studies.sweep.run import sweep
from fretbem.studies.sweep.spec import SweepSpecError, set_path

#: half-plane bodies (fast), a flat specimen on its ends carrying a bulk stress
SCENE = {
    "pad": {"model": "half-plane", "radius": 70.0},
    "specimen": {"model": "half-plane", "shape": "flat", "length": 40.0, "thickness": 13.0,
                 "support": "ends"},
    "contact": {"pairs": 21, "estimate": False},
    "rig": {"pivot_height": 3.0},
    "load": {"steps": ["A", "B", "C"], "P": 100.0, "Q": [0.0, 18.0, -18.0],
             "bulk": [0.0, 40.0, -40.0]},
}  # fmt: skip
FATIGUE = {"material": "Ti-6Al-4V", "methods": ["stress_life"], "critical_distance": 0.05,
           "map_points": [9, 5]}  # fmt: skip


def _scene(**tables) -> dict:
    scene = copy.deepcopy(SCENE)
    for name, values in tables.items():
        scene[name] = {**scene.get(name, {}), **values}
    return scene


def _direct(scene: dict, path: str, value):
    data = copy.deepcopy(scene)
    set_path(data, path, value)
    return run(build(scene_from_dict(data))[0])


@pytest.mark.parametrize(
    ("path", "values", "tables"),
    [
        ("load.moment", [0.0, 3.0, -3.0], {"rig": {"pivot_height": 0.0}, "load": {"moment": 0.0}}),
        ("rig.stiffness_rotation", [3.0e4, 1.0e5, 1.0e6], {"rig": {"stiffness_rotation": 1e5}}),
        ("rig.pivot_height", [0.0, 2.0, 4.0], {"rig": {"stiffness_rotation": 1.0e5}}),
    ],
)
def test_a_swept_rotation_key_is_honoured(tmp_path, path, values, tables):
    """Each case's stick width, peak pressure and contact width at step B equal the direct
    solve's with that value (the same discretisation: to round-off), and the values change
    the answer (the block turns)."""
    scene = _scene(**tables)
    table = sweep(scene, {path: values}, out=tmp_path / "s", serial=True, progress=False).table
    table = table.sort_values("case")
    assert set(table["status"]) == {"ok"}
    tilts = []
    for value, (_, row) in zip(values, table.iterrows(), strict=True):
        step = _direct(scene, path, value).steps[1]
        tilts.append(step.tilt)
        for key, expected in step_metrics(step).items():
            if key in ("regime", "iterations"):
                assert row[f"{key}.B"] == expected
            else:
                assert row[f"{key}.B"] == pytest.approx(expected, rel=1e-9, abs=1e-12)
    if path != "load.moment":  # a moment about the contact shifts it without tilting much
        assert len(set(np.round(tilts, 12))) == len(values)


def test_a_swept_mean_stress_correction_is_honoured(tmp_path):
    """fatigue.mean_stress swept over two stress-life corrections: each case's hot-spot
    parameter and life equal run_fatigue's with that correction, and they differ (the
    benchmark's audit sweeps all four)."""
    corrections = ["goodman", "morrow"]
    result = sweep(SCENE, {"fatigue.mean_stress": corrections}, out=tmp_path / "m",
                   serial=True, progress=False, options={"fatigue": FATIGUE,
                                                         "outputs": ["fatigue"]})  # fmt: skip
    table = result.table.sort_values("case")
    assert set(table["status"]) == {"ok"}
    history = SimulationStressHistory(run(build(scene_from_dict(SCENE))[0]))
    got = table["stress_life.parameter"].to_numpy()
    for correction, value, life in zip(corrections, got, table["stress_life.life"], strict=True):
        request = fatigue_request_from_dict({**FATIGUE, "mean_stress": correction})
        entry = run_fatigue(history, request).methods["stress_life"]
        assert value == pytest.approx(float(entry.at_hot_spot.value[0]), rel=1e-9)
        expected = entry.life_hot_spot.cycles if entry.life_hot_spot is not None else np.nan
        assert life == pytest.approx(expected, rel=1e-9, nan_ok=True)
    assert len(set(np.round(got, 9))) == len(corrections)


@pytest.mark.parametrize(
    ("path", "values", "tables", "words"),
    [
        ("fatigue.mean_stress", ["none", "goodmann"], {}, "got 'goodmann'"),
        ("load.rotation", [0.0, 1e-3], {"load": {"moment": 0.0}}, "both moment and rotation"),
        ("load.moment", [[1.0, 2.0]], {}, "moment has 2 values for 3 steps"),
        ("rig.stiffness_rotation", [1.0e5, 0.0], {}, "stiffness_rotation must be > 0"),
        ("rig.pivot_height", [0.0, 1.0e9], {}, "pivot_height is the pivot's height"),
    ],
)
def test_a_bad_swept_rotation_or_correction_is_refused_before_solving(
    tmp_path, path, values, tables, words
):
    options = {"fatigue": FATIGUE, "outputs": ["fatigue"]} if path.startswith("fatigue") else {}
    with pytest.raises(SweepSpecError, match=rf"'{path}' = .*{words}"):
        sweep(_scene(**tables), {path: values}, out=tmp_path / "x", serial=True,
              progress=False, options=options)  # fmt: skip
    assert not (tmp_path / "x").exists() or not list((tmp_path / "x").glob("cases-*"))
