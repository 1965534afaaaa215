"""Finite sliding from the scene file: examples/gross_sliding.toml through ``fretbem run``.

A cylinder (R = 70 mm) on a flat of the same aluminium, both half-planes, P = 100 N/mm,
dragged 2.8 mm (about 6 a) by displacement and back. Checked from the files the run
writes: Q = +-f P and the integrals of p and q, q = f p at every pair in contact in the
direction of sliding, p Hertz's where the pad is (the tolerance of
tests/validation/test_sliding.py, 0.6 % of p0; measured 0.10 %), each step's own pair positions, the
new-contact note and the reversal. The Python route (``run_scene``) gives the same steps,
its pairings' offsets put the pad where the pressure is, and the VTK arrays carry the slide.
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest
import tomllib

from fretbem.app.cli import main
from fretbem.fretting import analyse
from fretbem.output.vtk import step_arrays
from fretbem.pipeline import run_scene
from fretbem.scenes.file import load_scene, scene_from_data
from fretbem.stress.closed_form import elliptical_pressure_stress, elliptical_shear_stress
from fretbem.verification.closed_forms import HertzLineContact

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "examples" / "gross_sliding.toml"
P, F, SLIDE = 100.0, 0.3, 2.8
HERTZ = HertzLineContact.from_bodies(
    load=P, radius_upper=70.0, radius_lower=math.inf,
    E_upper=73400.0, nu_upper=0.33, E_lower=73400.0, nu_lower=0.33,
)  # fmt: skip
P0, A = HERTZ.peak_pressure, HERTZ.half_width


@pytest.fixture(scope="module")
def cli_run(tmp_path_factory):
    """``fretbem run examples/gross_sliding.toml`` (no figures, no VTK): its files and stderr."""
    out = tmp_path_factory.mktemp("sliding") / "out"
    capture = pytest.MonkeyPatch()
    lines: list[str] = []
    capture.setattr("fretbem.app.commands._progress", lambda message: lines.append(message))
    try:
        code = main(["run", str(SCENE), "--out", str(out), "--no-figures", "--no-vtk", "--quiet"])
    finally:
        capture.undo()
    rows: dict[str, dict[str, list]] = {}
    with open(out / "results.csv", newline="") as handle:
        for row in csv.DictReader(handle):
            step = rows.setdefault(row["step"], {"x": [], "p": [], "q": [], "state": []})
            for name in ("x", "p", "q"):
                step[name].append(float(row[name]))
            step["state"].append(row["state"])
    fields = {s: {k: np.array(v) for k, v in f.items()} for s, f in rows.items()}
    summary = json.loads((out / "summary.json").read_text())
    with open(out / "stress_points.csv", newline="") as handle:
        stress = list(csv.DictReader(handle))
    return code, fields, {s["step"]: s for s in summary["steps"]}, summary, lines, stress


@pytest.fixture(scope="module")
def python_run():
    return run_scene(load_scene(SCENE), say=lambda message: None)


def test_the_run_succeeds_and_says_why_there_is_no_estimate(cli_run):
    code, _, _, summary, *_ = cli_run
    assert code == 0
    assert "finite sliding" in summary["accuracy"]["estimate_reason"]


def test_gross_slip_both_ways_is_coulomb(cli_run):
    """Sliding (+) and sliding back (-): Q = +-f P, the traction integrals P and +-f P
    (measured 100.0006 and 30.0002), every pair in contact slipping with q = +-f p."""
    _, fields, steps, *_ = cli_run
    for name, sign in (("slide", 1.0), ("back", -1.0)):
        step, field = steps[name], fields[name]
        assert abs(step["Q"] - sign * F * P) < 1e-9 * P
        assert abs(step["integral_p"] - P) < 1e-4 * P
        assert abs(step["integral_q"] - sign * F * P) < 1e-4 * P
        touching = field["p"] > 0
        assert touching.sum() > 20
        assert set(np.array(field["state"])[touching]) == {"slip"}
        assert np.max(np.abs(sign * field["q"] - F * field["p"])) < 1e-9 * P0


def test_pressure_is_hertz_where_the_pad_is(cli_run, python_run):
    """p within 0.6 % of p0 of Hertz's about the pad (as in test_sliding.py); the pairs are
    the step's own (x moved by the slide), and the pressure's centre is where the pairing
    put the pad's face (Python route: within 1e-4 a; measured 1e-6 a), which lags its block
    by the half-planes' give under Q (1.86e-3 mm, the same either way)."""
    _, fields, steps, *_ = cli_run
    offsets = {s.name: float(s.pair.offset[0]) for s in python_run.result.steps}
    lag = SLIDE - offsets["slide"]
    assert 1e-3 < lag < 3e-3 and offsets["back"] == pytest.approx(lag, rel=0.02)
    for name in ("press", "slide", "back"):
        field = fields[name]
        centre = np.sum(field["x"] * field["p"]) / np.sum(field["p"])
        assert abs(centre - offsets[name]) < 1e-4 * A
        assert np.max(np.abs(field["p"] - HERTZ.pressure(field["x"] - offsets[name]))) < 0.006 * P0
    assert np.allclose(fields["slide"]["x"], fields["press"]["x"] + offsets["slide"], atol=1e-9)
    assert steps["slide"]["delta"] == pytest.approx(SLIDE) and abs(steps["back"]["delta"]) < 1e-12


def test_new_contact_is_noted_once(cli_run):
    """The slide brings the flat from about a to 7 a into contact; sliding back, none."""
    *_, lines, _ = cli_run
    notes = [line for line in lines if "came into contact" in line]
    assert len(notes) == 1 and notes[0].startswith("step 'slide'")
    start, end = (float(v) for v in notes[0].split("from ")[1].split(" mm")[0].split(" to "))
    assert abs(start - A) < 2 * 3 * A / 60 and abs(end - (A + SLIDE)) < 2 * 3 * A / 60
    assert any("re-pairing" in line for line in lines)


def test_python_route_matches_the_cli(cli_run, python_run):
    """run_scene (run_simulation with sliding=True) and fretbem run solve the same history."""
    _, fields, *_ = cli_run
    for step in python_run.result.steps:
        assert np.allclose(step.pressure, fields[step.name]["p"], rtol=0, atol=1e-9 * P0)
        assert np.allclose(step.shear, fields[step.name]["q"], rtol=0, atol=1e-9 * P0)
        assert np.allclose(step.x, fields[step.name]["x"], rtol=0, atol=1e-12)


def test_vtk_arrays_carry_the_slide(python_run):
    """The pad's boundary displacement written to VTK includes the slide (2.8 mm), on the
    step's own pairing; the specimen's stays small."""
    result = python_run.result
    arrays = step_arrays(result, result["slide"], points_per_element=1)
    pad = arrays["upper"]["point_data"]["displacement"][:, 0]
    flat = arrays["lower"]["point_data"]["displacement"][:, 0]
    assert np.all(np.abs(pad - SLIDE) < 1e-2 * SLIDE) and np.max(np.abs(flat)) < 1e-2 * SLIDE


def test_fretting_analysis_reads_a_sliding_cycle():
    """[load.cycle] delta* = 1 mm (about two contact widths), triangle, 8 increments per
    cycle, sliding: the second cycle's E_d from the pairs' slips equals the Q-delta loop's
    area and the rigid-plastic loop sampled at these increments (4 f P delta* less the two
    reversals' corners: 120 - 30 = 90, measured 90.000), A = 0.75, gross slip with no
    caution (the pairs follow the pad), the slip amplitude delta* at the pad's centre."""
    data = tomllib.loads(SCENE.read_text())
    data["load"] = {"P": P, "cycle": {"delta": 1.0, "cycles": 2, "increments": 8,
                                      "shape": "triangle"}}  # fmt: skip
    result = run_scene(scene_from_data(data), say=lambda message: None).result
    cycle = analyse(result).cycles[1]
    step = 1.0 / 2  # delta per increment
    expected = 4 * F * P * 1.0 - 2 * 0.5 * step * 2 * F * P
    assert cycle.dissipated_energy == pytest.approx(expected, rel=1e-3)
    assert cycle.loop_area == pytest.approx(expected, rel=1e-3)
    assert cycle.energy_ratio == pytest.approx(0.75, rel=1e-3)
    assert cycle.regime == "gross slip" and cycle.caution is None
    centre = np.argmin(np.abs(cycle.x))
    assert cycle.slip_amplitude[centre] == pytest.approx(1.0, rel=1e-2)


def test_specimen_stresses_follow_the_pad(cli_run, python_run):
    """[stress] points 0.5 a deep below the slide's start and end (stress_points.csv), each
    step on its own pairing: McEwen's pressure plus Smith-Liu's shear q = +-f p centred where
    the pad's face is (sliding), or nothing but the far field where it is not (measured
    within 0.03 % of p0 below the pad)."""
    *_, stress = cli_run
    centre = {s.name: float(s.pair.offset[0]) for s in python_run.result.steps}
    shear = {"press": 0.0, "slide": F, "back": -F}
    for row in stress:
        x, depth, name = float(row["x_mm"]), -float(row["y_mm"]), row["step"]
        exact = elliptical_pressure_stress(x, depth, a=A, p0=P0, centre=centre[name], nu=0.33)
        exact = exact + elliptical_shear_stress(
            x, depth, b=A, q0=shear[name] * P0, centre=centre[name], nu=0.33
        )
        got = [float(row[f"sigma_{c}_MPa"]) for c in ("xx", "yy", "xy")]
        assert np.max(np.abs(np.array(got) - exact[:3])) < 1e-3 * P0, (name, x)
