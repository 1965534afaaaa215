"""The numbers an engineer looks for: sigma_B, Hertz a and p0, contact extent, stick zone
[e - c, e + c] and slip zones per step, in summary.json, the printed table and states.png."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from fretbem.contact.zones import step_zones, zone_table
from fretbem.output import figures
from fretbem.output.write import SUMMARY_KEYS


def test_hertz_numbers_are_the_closed_forms(demo_run, rig_run):
    # the reference scene's a and p0 (README: a = 0.3289 mm, p0 = 193.5 MPa)
    hertz = demo_run.result.summary()["hertz"]
    assert hertz["a"] == pytest.approx(0.3289, abs=5e-5)
    assert hertz["p0"] == pytest.approx(193.5, abs=0.05)
    assert hertz["P"] == 100.0
    # the rig: p0 = 2 P / (pi a)
    rig = rig_run.result.summary()["hertz"]
    assert rig["p0"] == pytest.approx(2 * 200.0 / (math.pi * rig["a"]), rel=1e-12)


def test_stick_zone_is_offset_by_the_bulk_stress(rig_run):
    result = rig_run.result
    summary = result.summary()
    a, p0, f = summary["hertz"]["a"], summary["hertz"]["p0"], 0.5
    step = summary["steps"][1]  # B: Q = 45, sigma_B = 90
    assert step["sigma_B"] == 90.0
    c = a * math.sqrt(1 - 45.0 / (f * 200.0))  # Cattaneo-Mindlin width
    e = a * 90.0 / (4 * f * p0)  # Nowell-Hills offset
    low, high = step["theory_stick_zone"]
    assert (low, high) == pytest.approx((e - c, e + c), rel=1e-12)
    assert abs(low + high) > 0.25 * a  # not mirrored about 0
    # the computed stick zone agrees within one pair spacing and a half (31 pairs)
    spacing = np.diff(result.steps[1].x).max()
    (stick,) = step["stick_zones"]
    assert stick == pytest.approx([low, high], abs=1.5 * spacing)
    # the main slip zone is on the trailing side, positive shear (at 31 pairs the leading
    # edge pair beyond e + c = 0.976 a slips too)
    slip = step["slip_zones"][0]
    assert slip["sign"] == "+" and slip["from"] < -0.9 * a and slip["to"] < low + 1.5 * spacing
    assert all(z["from"] > high for z in step["slip_zones"][1:])


def test_summary_zones_and_printed_table_share_one_source(rig_run):
    result = rig_run.result
    table = zone_table(result).splitlines()
    for step, line in zip(result.summary()["steps"], table[1:], strict=False):
        zones = step_zones(result[step["step"]])
        assert step["contact"] == list(zones.contact)
        low, high = step["stick_zones"][0]
        assert f"[{low:+.4f}, {high:+.4f}]" in line
        t_low, t_high = step["theory_stick_zone"]
        assert f"[{t_low:+.4f}, {t_high:+.4f}]" in line
        assert f"{step['sigma_B']:9.3f}" in line
    hertz = result.hertz()
    assert any(f"a = {hertz['a']:.4f} mm" in line for line in table)


def test_new_summary_keys_have_units(rig_run, tmp_path):
    out = rig_run.write(tmp_path / "out", writers=["json", "units"])
    summary = json.loads((out / "summary.json").read_text())
    units = json.loads((out / "units.json").read_text())["summary.json"]
    for key in ("sigma_B", "contact", "stick_zones", "slip_zones", "theory_stick_zone"):
        assert key in summary["steps"][0]
        assert key in SUMMARY_KEYS and units[key]["unit"]
    assert set(summary["hertz"]) == {"P", "a", "p0"} and "hertz" in units


def test_no_closed_form_gives_null_theory(rig_data):
    from fretbem.pipeline import run_scene
    from fretbem.scenes.file import scene_from_data

    data = rig_data(21)
    data["pad"]["material"] = {"E": 110000.0, "nu": 0.33}  # dissimilar: no closed form
    result = run_scene(scene_from_data(data)).result
    summary = result.summary()
    assert summary["hertz"] is None
    assert all(s["theory_stick_zone"] is None for s in summary["steps"])
    assert all(s["contact"] is not None for s in summary["steps"])


def test_states_figure_draws_the_offset_stick_zone(rig_run):
    result = rig_run.result
    fig = figures.stick_slip_figure(result)
    ax = fig.axes[0]
    (markers,) = [line for line in ax.lines if line.get_marker() == "|"]
    scale = result.hertz()["a"]
    zones = np.array(result.theory_stick_zones())
    drawn = np.asarray(markers.get_xdata()) * scale
    assert drawn == pytest.approx(np.concatenate([zones[:, 0], zones[:, 1]]), rel=1e-12)
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert "analytical stick zone [e − c, e + c]" in labels
    assert all(t.get_fontsize() >= 9 for t in fig.legends[0].get_texts())
