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
from fretbem.studies.sweep.cases import rotation_metrics, step_metrics
from fretbem.studies.sweep.run import sweep, sweep_columns
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
    """Each case's stick width, peak pressure, contact width and the block's M, theta and
    tilt at step B equal the direct solve's with that value (the same discretisation: to
    round-off), and the values change the answer (the block turns)."""
    scene = _scene(**tables)
    table = sweep(scene, {path: values}, out=tmp_path / "s", serial=True, progress=False).table
    table = table.sort_values("case")
    assert set(table["status"]) == {"ok"}
    tilts = []
    for value, (_, row) in zip(values, table.iterrows(), strict=True):
        step = _direct(scene, path, value).steps[1]
        tilts.append(step.tilt)
        for key, expected in {**step_metrics(step), **rotation_metrics(step)}.items():
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


def test_the_rotation_columns_come_with_a_rotating_block_only(tmp_path):
    """A rig without a rotational spring and no moment: no M, theta or tilt columns (the
    block does not rotate), and the columns a [[maps]] may name say so before solving."""
    from fretbem.studies.sweep.spec import Parameter, SweepSpec

    plain = sweep(SCENE, {"load.P": [90.0, 110.0]}, out=tmp_path / "p", serial=True,
                  progress=False).table  # fmt: skip
    assert "stick_width.B" in plain and not {"M.B", "theta.B", "tilt.B"} & set(plain.columns)
    spring = _scene(rig={"stiffness_rotation": 1.0e5})
    for scene, turning in ((SCENE, False), (spring, True)):
        spec = SweepSpec(scene=scene, parameters=[Parameter("load.P", (90.0, 110.0))])
        assert ({"M.B", "theta.C", "tilt.A"} <= sweep_columns(spec, ())) == turning


def test_a_cyclic_rotating_case_gives_its_last_cycles_amplitudes(tmp_path):
    """One row per cyclic case: M, theta and tilt amplitudes (half the ranges over the
    last cycle, its start increment included) as the direct run's increments give them;
    the spring holds tilt = -M / k_r (the actuator at 0), so tilt* = M* / k_r."""
    scene = _scene(rig={"stiffness_rotation": 1.0e5})
    scene["load"] = {"P": 100.0, "cycle": {"Q": 12.0, "cycles": 2, "increments": 8}}
    stiffness = [5.0e4, 2.0e5]
    table = sweep(scene, {"rig.stiffness_rotation": stiffness}, out=tmp_path / "c",
                  serial=True, progress=False).table.sort_values("case")  # fmt: skip
    assert set(table["status"]) == {"ok"} and "tilt.B" not in table
    for k_r, (_, row) in zip(stiffness, table.iterrows(), strict=True):
        result = _direct(scene, "rig.stiffness_rotation", k_r)
        records = [r for s in result.steps for r in s.increments]
        cycle = [load.cycle for load in result.simulation.steps for _ in range(load.increments)]
        loop = records[cycle.index(2) - 1 :]
        for column, name in (("M_amplitude", "moment"), ("theta_amplitude", "rotation"),
                             ("tilt_amplitude", "tilt")):  # fmt: skip
            expected = 0.5 * np.ptp([getattr(r, name) for r in loop])
            assert row[column] == pytest.approx(expected, rel=1e-9, abs=1e-18)
        assert row["M_amplitude"] > 12.0  # Q* = 12 N/mm 3 mm below the pivot: M* ~ 3 Q*
        assert row["theta_amplitude"] < 1e-15
        assert row["tilt_amplitude"] == pytest.approx(row["M_amplitude"] / k_r, rel=1e-9)
