"""Waveform histories: shapes, phases, cycles and the [load.cycle] scene table (issue 22)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fretbem.fretting.waveform import Waveform, WaveformError, shape_value
from fretbem.scenes.builder import build
from fretbem.scenes.spec import SceneFileError, markdown_table, scene_from_dict


def test_shapes_reach_the_peaks_at_quarter_cycles():
    t = np.array([0.0, 0.25, 0.5, 0.75, 1.0, 0.125])
    np.testing.assert_allclose(shape_value("sine", t)[:5], [0, 1, 0, -1, 0], atol=1e-15)
    np.testing.assert_allclose(shape_value("triangle", t), [0, 1, 0, -1, 0, 0.5], atol=1e-15)


@pytest.mark.parametrize("shape", ["sine", "triangle"])
@pytest.mark.parametrize("control", ["force", "displacement"])
def test_steps_one_per_increment_tagged_with_their_cycle(shape, control):
    w = Waveform(2.5, 100.0, control=control, cycles=3, increments=8, shape=shape)
    steps = w.steps()
    assert len(steps) == 1 + 3 * 8
    assert steps[0].name == "press" and steps[0].cycle == 0
    assert steps[0].tangential_target == 0.0 and steps[0].normal == 100.0
    assert [s.cycle for s in steps[1:]] == [1] * 8 + [2] * 8 + [3] * 8
    drive = np.array([s.tangential_target for s in steps[1:]])
    assert drive.max() == pytest.approx(2.5) and drive.min() == pytest.approx(-2.5)
    assert drive[1] == pytest.approx(2.5) and drive[5] == pytest.approx(-2.5)  # t = 1/4, 3/4
    assert all(s.controls.tangential == control for s in steps)
    assert steps[8].name == "c1.8" and steps[9].name == "c2.1"


def test_normal_load_and_bulk_in_and_out_of_phase():
    w = Waveform(1e-3, 100.0, cycles=1, increments=4, normal_amplitude=20.0, normal_phase=0.0,
                 bulk=50.0, bulk_amplitude=10.0, bulk_phase=180.0)  # fmt: skip
    steps = w.steps()
    P = [s.normal for s in steps]
    bulk = [s.loads["bulk"] for s in steps]
    np.testing.assert_allclose(P, [100, 120, 100, 80, 100], atol=1e-12)
    np.testing.assert_allclose(bulk, [50, 40, 50, 60, 50], atol=1e-12)  # out of phase
    quarter = Waveform(1e-3, 100.0, increments=4, normal_amplitude=20.0, normal_phase=90.0)
    np.testing.assert_allclose([s.normal for s in quarter.steps()], [120, 100, 80, 100, 120])


@pytest.mark.parametrize(
    ("fields", "message"),
    [
        ({"amplitude": 0.0}, "amplitude must be > 0"),
        ({"increments": 10}, "multiple of 4"),
        ({"cycles": 0}, "cycles must be a whole number >= 1"),
        ({"shape": "square"}, "shape must be one of"),
        ({"control": "speed"}, "control must be one of"),
        ({"normal_amplitude": 150.0}, "must stay below the mean"),
        ({"normal": -1.0}, "must be > 0"),
        ({"cycles": 9223372036854775807}, "more than 100,000"),
        ({"cycles": 2501, "increments": 40}, "more than 100,000"),
    ],
)
def test_bad_waveforms_are_refused(fields, message):
    values = {"amplitude": 1.0, "normal": 100.0, **fields}
    with pytest.raises(WaveformError, match=message):
        Waveform(**values)


def _scene(load):
    return {"pad": {"model": "half-plane"}, "specimen": {"model": "half-plane"},
            "contact": {"pairs": 21}, "load": load}  # fmt: skip


def test_scene_cycle_table_builds_the_waveform():
    cycle = {"delta": 0.002, "cycles": 2, "increments": 8, "shape": "triangle"}
    scene = scene_from_dict(_scene({"P": 80.0, "cycle": cycle}))
    assert scene.load.waveform == Waveform(0.002, 80.0, cycles=2, increments=8, shape="triangle")
    sim, reason = build(scene)
    assert reason is None
    assert len(sim.steps) == 17 and sim.steps[2].delta == pytest.approx(0.002)
    assert sim.steps[-1].cycle == 2
    force = scene_from_dict(_scene({"cycle": {"Q": 12.0, "increments": 4}}))
    sim, _ = build(force)
    assert [s.tangential for s in sim.steps] == pytest.approx([0, 12, 0, -12, 0], abs=1e-12)
    assert "[load.cycle]" in markdown_table()


@pytest.mark.parametrize(
    ("load", "message"),
    [
        ({"cycle": {}}, r"\[load.cycle\] needs exactly one amplitude"),
        ({"cycle": {"delta": 1e-3, "Q": 2.0}}, r"\[load.cycle\] needs exactly one amplitude"),
        ({"cycle": {"delta": 1e-3, "shape": "square"}}, r"\[load.cycle\] shape must be one"),
        ({"cycle": {"delta": 1e-3, "wave": 1}}, r"unknown key \['wave'\] in \[load.cycle\]"),
        ({"cycle": {"delta": "big"}}, r"\[load.cycle\] delta must be"),
        ({"cycle": {"delta": -1e-3}}, r"\[load.cycle\]: delta must be > 0"),
        ({"cycle": {"delta": 1e-3, "increments": 30}}, r"\[load.cycle\]: .*multiple of 4"),
        ({"Q": 5.0, "cycle": {"delta": 1e-3}}, r"\[load\] \['Q'\] do not go with"),
        ({"P": [1.0, 2.0], "cycle": {"delta": 1e-3}}, r"\[load\] P must be one number"),
        ({"cycle": 3}, r"\[load.cycle\] must be a table"),
        ({"cycle": {"delta": 1e-3, "P_amplitude": 200.0}}, r"P_amplitude .* below the mean"),
        ({"cycle": {"delta": 1e-3, "cycles": 10**12}}, r"\[load.cycle\]: cycles x increments"),
        ({"cycle": {"Q": 40.0}}, None),
    ],
)
def test_bad_cycle_tables_are_refused(load, message):
    if message is None:  # Q* >= f P under force control: refused before any solve
        from fretbem.contact.law import GrossSlidingError

        with pytest.raises(GrossSlidingError, match="gross sliding"):
            build(scene_from_dict(_scene(load)))
        return
    with pytest.raises(SceneFileError, match=message):
        scene_from_dict(_scene(load))


@pytest.mark.parametrize("field", ["moment", "moment_amplitude", "moment_phase"])
@pytest.mark.parametrize("value", [math.nan, -math.inf, "2.0", False])
def test_moment_fields_from_python_name_the_field_cause_and_fix(field, value):
    with pytest.raises(
        WaveformError, match=rf"^Waveform\.{field} must be a (finite )?number .*; give"
    ):
        Waveform(amplitude=1.0, normal=100.0, **{field: value})
