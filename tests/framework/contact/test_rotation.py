"""The pad block's rotation: the unknowns' layout, the controls, bad inputs and the examples.

The closed-form checks (Hertz, Cattaneo-Mindlin, Nowell-Hills about the shifted centre, the
rotational rig spring) are in tests/validation/test_tilted_pad.py.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from fretbem.app import cli
from fretbem.contact import control
from fretbem.contact.unknowns import PairUnknowns, UnknownLayout
from fretbem.errors import InputError
from fretbem.scenes.builder import build
from fretbem.scenes.errors import SceneFileError
from fretbem.scenes.spec import scene_from_dict
from fretbem.simulation import LoadHistoryError, LoadStep, Simulation, run

EXAMPLES = Path(__file__).resolve().parents[3] / "examples"


def scene(model="half-plane", basis="nurbs", pairs=31, load=None, rig=None, **contact):
    data = {
        "pad": {"model": model},
        "specimen": {"model": model},
        "contact": {"pairs": pairs, "basis": basis, "estimate": False, **contact},
        "load": load or {"steps": ["A", "B"], "P": 100.0, "Q": [0.0, 18.0]},
    }
    if rig is not None:
        data["rig"] = rig
    return scene_from_dict(data)


def test_layout_puts_the_rotation_after_the_blocks():
    layout = UnknownLayout(3, ("upper",), ("upper",))
    assert layout.size == 3 * 2 + 2 + 1
    assert layout.rotation("upper") == 8
    x = np.arange(9.0)
    unknowns = PairUnknowns.from_vector(x, layout)
    assert unknowns.rotation("upper") == 8.0 and unknowns.rotation("lower") == 0.0
    np.testing.assert_array_equal(unknowns.vector, x)
    assert UnknownLayout(3, ("upper",)).size == 8  # no rotation: the old layout
    with pytest.raises(InputError, match="no block rotation"):
        UnknownLayout(3, ("upper",)).rotation("upper")


@pytest.mark.parametrize("model", ["half-plane", "bem"])
def test_default_problem_is_the_non_rotating_one(model):
    """Without a rotational spring, moment or rotation the prepared problem is the pair's
    condensed problem itself (the same object: the same unknowns and rows)."""
    simulation, _ = build(scene(model))
    assert not simulation.rotates
    assert simulation.prepare() is simulation.pair.condensed()


@pytest.mark.parametrize("model", ["half-plane", "bem"])
@pytest.mark.parametrize("basis", ["nurbs", pytest.param("lagrange2", marks=pytest.mark.slow)])
def test_a_stiff_rotational_spring_reproduces_the_rigid_block(model, basis):
    """k_r = 1e18 N mm/mm per rad puts theta among the unknowns but holds it (theta =
    -M / k_r ~ 2e-16): p, q, Q and delta equal the non-rotating block's to 1e-9 (relative),
    at every step."""
    load = {"steps": ["A", "B", "C"], "P": 100.0, "Q": [0.0, 18.0, -9.0]}
    rigid = run(build(scene(model, basis, load=load))[0])
    stiff_sim = build(scene(model, basis, load=load, rig={"stiffness_rotation": 1e18}))[0]
    stiff = run(stiff_sim)
    assert stiff_sim.rotates
    for a, b in zip(rigid.steps, stiff.steps, strict=True):
        scale = np.abs(a.pressure).max()
        assert np.abs(a.pressure - b.pressure).max() < 1e-9 * scale
        assert np.abs(a.shear - b.shear).max() < 1e-9 * scale
        assert abs(b.tilt) < 1e-15
        assert b.delta == pytest.approx(a.delta, rel=1e-9, abs=1e-15)
        assert b.moment == pytest.approx(a.moment, rel=1e-7, abs=1e-9)


def test_rigid_block_reports_its_reaction_moment():
    """A non-rotating block carries M = h Q - d P about its pivot: on half-planes, with the
    pivot at the datum depth (10 mm) and d = 0 (similar bodies), M = 10 Q, less the shear's
    moment over the pad's curved face (q acts x^2 / 2R above the lowest point: 5e-3)."""
    result = run(build(scene())[0])
    assert result.steps[0].moment == pytest.approx(0.0, abs=1e-9)
    assert result.steps[1].moment == pytest.approx(10.0 * 18.0, rel=1e-4)
    assert result.steps[1].rotation == 0.0 and result.steps[1].tilt == 0.0


@pytest.mark.parametrize("model", ["half-plane", "bem"])
def test_prescribed_rotation_and_moment_agree(model):
    """Driving the rotation to the theta a moment produced gives that moment back."""
    moment = {"steps": ["A"], "P": 100.0, "Q": 0.0, "moment": 12.0}
    first = run(build(scene(model, load=moment, rig={"pivot_height": 0.0}))[0]).steps[0]
    turned = {"steps": ["A"], "P": 100.0, "Q": 0.0, "rotation": first.tilt}
    second = run(build(scene(model, load=turned, rig={"pivot_height": 0.0}))[0]).steps[0]
    assert second.moment == pytest.approx(12.0, rel=1e-8)
    np.testing.assert_allclose(second.pressure, first.pressure, atol=1e-8 * first.pressure.max())


def test_pairings_and_displacement_control_take_the_rotation():
    """Node-to-segment pairing and displacement control (delta imposed) with a moment."""
    load = {"steps": ["A", "B"], "P": 100.0, "delta": [0.0, 0.002], "moment": 8.0}
    for pairing in ("node-to-node", "node-to-segment"):
        sim, _ = build(scene(load=load, rig={"pivot_height": 0.0}, pairing=pairing))
        result = run(sim)
        assert result.steps[1].moment == pytest.approx(8.0, rel=1e-10)
        assert result.steps[1].delta == pytest.approx(0.002, rel=1e-10)
        assert result.steps[1].controls.rotation == "moment"


def test_cyclic_moment_from_the_waveform(tmp_path):
    """[load.cycle] M_amplitude and M_phase: the moment follows M + M_a w(t + phase)."""
    data = {
        "pad": {"model": "half-plane"},
        "specimen": {"model": "half-plane"},
        "contact": {"pairs": 21, "estimate": False, "zone": 2.0},
        "rig": {"pivot_height": 0.0},
        "load": {"P": 100.0, "moment": 2.0,
                 "cycle": {"Q": 9.0, "cycles": 2, "increments": 8, "M_amplitude": 5.0,
                           "M_phase": 90.0}},
    }  # fmt: skip
    simulation, _ = build(scene_from_dict(data))
    moments = [s.moment for s in simulation.steps]
    t = np.arange(0, 17) / 8
    np.testing.assert_allclose(moments, 2.0 + 5.0 * np.sin(2 * np.pi * (t + 0.25)), atol=1e-12)
    result = run(simulation)
    np.testing.assert_allclose([s.moment for s in result.steps], moments, atol=1e-9)
    from fretbem.fretting import analyse

    analysis = analyse(result)
    np.testing.assert_allclose(analysis.moment[1:], moments[1:], atol=1e-9)
    # over the second (closed) cycle the block's work, Q d delta + M d theta, is the
    # dissipation (the trapezoid rule over 8 increments a cycle: measured 0.11 %)
    cycle = analysis.cycles[1]
    assert cycle.loop_area == pytest.approx(cycle.dissipated_energy, rel=0.01)


BAD = [
    ({"rig": {"stiffness_rotation": -1.0}}, "stiffness_rotation must be > 0"),
    ({"rig": {"pivot_height": "top"}}, "pivot_height must be"),
    ({"load": {"steps": ["A"], "P": 100.0, "moment": 1.0, "rotation": 0.1}},
     "both moment and rotation"),
    ({"load": {"steps": ["A"], "P": 100.0, "moment": [1.0, 2.0]}}, "moment has 2 values"),
    ({"load": {"P": 100.0, "rotation": 0.1, "cycle": {"Q": 9.0}}}, "do not go with"),
]  # fmt: skip


@pytest.mark.parametrize("extra, message", BAD)
def test_bad_scene_keys_are_refused_with_the_key(extra, message):
    data = {"pad": {"model": "half-plane"}, "specimen": {"model": "half-plane"}, **extra}
    with pytest.raises(SceneFileError, match=message):
        scene_from_dict(data)


def test_bad_python_inputs_are_refused():
    with pytest.raises(LoadHistoryError, match="keep one of them"):
        LoadStep("A", 100.0, moment=1.0, rotation=0.1)
    with pytest.raises(ValueError, match="rotational must be > 0"):
        control.Rig(rotational=0.0)
    with pytest.raises(ValueError, match="pivot_height must be a finite"):
        control.Rig(pivot_height=math.nan)
    simulation, _ = build(scene(load={"steps": ["A"], "P": 100.0, "moment": 1.0}))
    with pytest.raises(LoadHistoryError, match="does not take"):
        Simulation(simulation.pair, simulation.steps, solver=_lcp(), law=simulation.law)


def _lcp():
    from fretbem import registry

    return registry.get("lemke", "solvers")()


def test_a_pad_held_by_displacements_cannot_rotate():
    """A BEM pad with a Displacement condition besides its block: the rotation is refused,
    naming the cause, when the run starts."""
    from fretbem.bem.body import BemBody
    from fretbem.conditions import Displacement

    simulation, _ = build(scene("bem", load={"steps": ["A"], "P": 100.0, "moment": 1.0}))
    pad = simulation.pair.upper
    held = BemBody(
        pad.boundary, pad.material, (*pad.conditions, Displacement("side_left", x=None, y=0.0)),
        pad.basis, pad.refinement, name=pad.name,
    )  # fmt: skip
    import attrs

    pair = attrs.evolve(simulation.pair, upper=held)
    with pytest.raises(LoadHistoryError, match="cannot rotate"):
        run(Simulation(pair, simulation.steps, law=simulation.law))


@pytest.mark.parametrize("name", ["tilted_pad", "fretting_rig_rotation"])
def test_examples_run(name, tmp_path):
    """The examples through ``fretbem run``: M and theta in summary.json, units.json and
    loops.csv; the tilted pad's contact moves to d = -M / P (within the finite pad's
    difference), the rig's pad tilts against Q."""
    out = tmp_path / "out"
    assert cli.main(["run", str(EXAMPLES / f"{name}.toml"), "--out", str(out),
                     "--no-figures", "--no-vtk"]) == 0  # fmt: skip
    summary = json.loads((out / "summary.json").read_text())
    units = json.loads((out / "units.json").read_text())
    assert {"M", "theta", "tilt"} <= set(units["summary.json"])
    assert {"M", "theta"} <= set(units["loops.csv"])
    steps = summary["steps"]
    if name == "tilted_pad":
        assert all(s["M"] == pytest.approx(-20.0, rel=1e-9) for s in steps)
        rows = np.genfromtxt(out / "results.csv", delimiter=",", names=True, dtype=None,
                             encoding="utf-8")  # fmt: skip
        a = rows[rows["step"] == "A"]
        centre = np.trapezoid(a["p"] * a["x"], a["x"]) / np.trapezoid(a["p"], a["x"])
        assert centre == pytest.approx(0.2, abs=0.01)
        assert steps[0]["tilt"] == pytest.approx(-20.0 / (100.0 * 70.0), rel=0.06)
    else:
        assert steps[1]["tilt"] < 0 < steps[3]["tilt"]  # Q > 0 tilts the pad clockwise
        assert steps[1]["M"] == pytest.approx(-2.0e5 * steps[1]["tilt"], rel=1e-9)
        assert steps[1]["theta"] == pytest.approx(0.0, abs=1e-15)


def _nurbs_pad(shape) -> dict:
    """A 'nurbs' pad table drawing ``shape``'s own segments."""
    segments = [
        {"tag": s.tag, "degree": int(s.curve.degree), "knots": [float(k) for k in s.curve.knots],
         "points": [[float(x), float(y)] for x, y in s.curve.control_points],
         "weights": [float(w) for w in s.curve.weights]}
        for s in shape.boundary(0.6).segments
    ]  # fmt: skip
    return {"shape": "nurbs", "segments": segments}


def _pads() -> dict:
    from fretbem.geometry.shapes import CylinderPad, RoundedFlatPad

    cylinder = {"shape": "cylinder", "radius": 70.0, "width": 6.5, "height": 6.5}
    rounded = {"shape": "rounded-flat", "flat": 0.3, "edge_radius": 20.0, "width": 6.5,
               "height": 6.5}  # fmt: skip
    return {
        "cylinder": (cylinder, cylinder),
        "rounded-flat": (rounded, rounded),
        "nurbs cylinder": (_nurbs_pad(CylinderPad(70.0, 6.5, 6.5)), cylinder),
        "nurbs rounded-flat": (_nurbs_pad(RoundedFlatPad(0.3, 20.0, 6.5, 6.5)), rounded),
    }


@pytest.mark.parametrize("model", ["half-plane", pytest.param("bem", marks=pytest.mark.slow)])
@pytest.mark.parametrize("pad", list(_pads()))
def test_every_pad_shape_turns(pad, model):
    """Every pad shape (a nurbs pad drawing a library shape's segments gives that shape's
    answer) under Q against a rotational spring, in both body models: Q > 0 below the pivot
    tilts the pad clockwise, and the spring holds M = -k_r theta."""
    table, library = _pads()[pad]

    def solve(pad_table):
        data = {
            "pad": {**pad_table, "model": model},
            "specimen": {"shape": "flat", "length": 12.0, "thickness": 6.0, "model": model},
            "material": {"E": 73400.0, "nu": 0.33},
            "contact": {"pairs": 33, "zone_width": 0.6, "estimate": False},
            "rig": {"stiffness_rotation": 1e6},
            "load": {"steps": ["A", "B"], "P": 100.0, "Q": [0.0, 15.0]},
        }
        return run(build(scene_from_dict(data))[0])

    result = solve(table)
    b = result.steps[1]
    assert b.tilt < 0 < b.moment
    assert abs(result.steps[0].tilt) < 1e-3 * abs(b.tilt)  # P alone: the discretisation's
    assert b.moment == pytest.approx(-1e6 * b.tilt, rel=1e-9) and b.rotation == pytest.approx(
        0.0, abs=1e-15
    )
    if table is not library:
        same = solve(library)
        for mine, theirs in zip(result.steps, same.steps, strict=True):
            np.testing.assert_allclose(mine.pressure, theirs.pressure, atol=1e-9 * 200.0)
            assert mine.tilt == pytest.approx(theirs.tilt, rel=1e-9, abs=1e-15)


# a rig value from Python and the same value in a scene file: one message after the key
RIG_VALUES = [
    ("pivot_height", "pivot_height", 2.0e4, "within 10000 mm of it"),
    ("pivot_height", "pivot_height", -2.0e4, "within 10000 mm of it"),
    ("rotational", "stiffness_rotation", -1.0, r"must be > 0 \(N mm/mm per rad\)"),
    ("rotational", "stiffness_rotation", 0.0, r"must be > 0 \(N mm/mm per rad\)"),
    ("tangential", "stiffness_x", -5.0, r"must be > 0 \(N/mm per mm of travel\)"),
]


@pytest.mark.parametrize("field, key, value, cause", RIG_VALUES)
def test_rig_from_python_is_checked_as_the_scene_file_is(field, key, value, cause):
    with pytest.raises(InputError, match=cause) as from_python:
        control.Rig(**{field: value})
    data = {"pad": {"model": "half-plane"}, "specimen": {"model": "half-plane"}}
    with pytest.raises(SceneFileError, match=cause) as from_file:
        scene_from_dict({**data, "rig": {key: value}})
    python, file = str(from_python.value), str(from_file.value)
    assert python.startswith(f"Rig.{field} ") and file.startswith(f"[rig] {key} ")
    # the same cause and range; the fix says how each writes a rigid rig / the block's line
    cause_of = lambda message, key: message.removeprefix(key).split(";")[0]  # noqa: E731
    assert cause_of(python, f"Rig.{field}") == cause_of(file, f"[rig] {key}")


@pytest.mark.parametrize("value", [math.nan, -math.inf, "3.0", True, [1.0]])
@pytest.mark.parametrize("field", ["pivot_height", "rotational", "tangential", "normal"])
def test_rig_refuses_what_a_scene_file_refuses(field, value):
    with pytest.raises(InputError, match=rf"^Rig\.{field} must be .*; give (.* )?(None|math\.inf)"):
        control.Rig(**{field: value})


def test_rig_takes_infinity_as_rigid_but_not_as_a_pivot():
    assert control.Rig(math.inf, math.inf, rotational=math.inf) == control.RIGID
    with pytest.raises(InputError, match="pivot_height must be a finite number"):
        control.Rig(pivot_height=math.inf)


def test_rig_takes_numpy_numbers_and_a_pivot_within_reach():
    rig = control.Rig(np.float32(2.0), np.int64(3), rotational=np.float64(4.0), pivot_height=-1e4)
    assert (rig.tangential, rig.normal, rig.rotational, rig.pivot_height) == (2.0, 3.0, 4.0, -1e4)
    assert type(rig.normal) is float and control.Rig(pivot_height=None).pivot_height is None


@pytest.mark.parametrize("field", ["moment", "rotation"])
@pytest.mark.parametrize("value", [math.nan, math.inf, "1.0", True, None])
def test_step_rotation_drives_from_python_are_checked(field, value):
    if value is None:
        assert getattr(LoadStep("A", 100.0, **{field: value}), field) is None
        return
    with pytest.raises(
        InputError, match=rf"^LoadStep\.{field} must be a (finite )?number .*; give"
    ):
        LoadStep("A", 100.0, **{field: value})
    assert getattr(LoadStep("A", 100.0, **{field: np.float32(0.5)}), field) == 0.5
