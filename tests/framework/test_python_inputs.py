"""Every number of the public records a user builds from Python for a run is checked as the
scene reader checks it: True, "3", NaN, infinity, an int too large for a float or a count
(10**400) and None (where a number is required) are refused with one InputError naming
``Record.field``, its cause and a fix; numpy scalars and ints are taken as before (the
record stores a plain float or int)."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from fretbem import KelvinKernel, LoadStep, Material, Refinement, SemiSmoothNewton
from fretbem.accuracy.adaptive import AdaptiveSettings
from fretbem.accuracy.modes import Accuracy
from fretbem.bem.integration import IntegrationSettings
from fretbem.bem.stresses import StressSettings
from fretbem.conditions import Displacement, LoadingBlock, Traction
from fretbem.contact.control import Rig
from fretbem.contact.law import CoulombFriction
from fretbem.errors import InputError
from fretbem.fatigue import PlaneSearch, fatigue_request_from_dict
from fretbem.fretting import Waveform
from fretbem.geometry.nurbs import NurbsCurve
from fretbem.geometry.shapes import (
    CylinderPad,
    CylinderSpecimen,
    FlatSpecimen,
    GrooveSpecimen,
    RoundedFlatPad,
)
from fretbem.halfplane.body import HalfPlaneBody
from fretbem.output import write_results
from fretbem.scenes.reference import CattaneoMindlinScene
from fretbem.scenes.spec import ContactSpec, LoadSpec, MeshSpec, SceneFileError
from fretbem.solvers.fallback import FallbackSolver
from fretbem.solvers.pivoting import LemkeSolver
from fretbem.stress import stress_request_from_dict
from fretbem.verification.closed_forms import HertzLineContact, MindlinDeresiewicz
from fretbem.verification.dissimilar import DissimilarCylinders
from fretbem.verification.nowell_hills import NowellHills
from fretbem.verification.rounded_flat import RoundedFlatPunch
from fretbem.verification.tilted_contact import TiltedContact
from fretbem.wear import ArchardWear, EnergyWear
from fretbem.wear.jump import JumpControl
from fretbem.wear.run import WearSimulation

_HERTZ = HertzLineContact(100.0, 70.0, 40000.0)
#: (record, valid keyword arguments): each builds a valid record
RECORDS = {
    "LoadStep": (LoadStep, {"name": "A", "normal": 100.0, "tangential": 5.0}),
    "LoadStep-delta": (LoadStep, {"name": "A", "normal": None, "approach": 1e-3, "delta": 1e-3}),
    "LoadStep-rotation": (LoadStep, {"name": "A", "normal": 100.0, "rotation": 1e-4}),
    "LoadStep-moment": (LoadStep, {"name": "A", "normal": 100.0, "moment": 5.0}),
    "Waveform": (
        Waveform,
        {
            "amplitude": 1e-3,
            "normal": 100.0,
            "normal_amplitude": 10.0,
            "normal_phase": 90.0,
            "bulk": 50.0,
            "bulk_amplitude": 20.0,
            "bulk_phase": 0.0,
            "moment": 1.0,
            "moment_amplitude": 2.0,
            "moment_phase": 0.0,
        },
    ),
    "Material": (Material, {"E": 73400.0, "nu": 0.33}),
    "CoulombFriction": (CoulombFriction, {"friction": 0.3}),
    "ArchardWear": (ArchardWear, {"k": 1e-8}),
    "EnergyWear": (EnergyWear, {"alpha": 2e-4}),
    "JumpControl": (
        JumpControl,
        {"max_change": 1e-4, "relative_change": 0.05, "safety": 0.5, "max_jump": 100},
    ),
    "Rig": (
        Rig,
        {"tangential": 1e4, "normal": 1e5, "rotational": 1e6, "pivot_height": 10.0},
    ),
    "CylinderPad": (CylinderPad, {"radius": 70.0, "width": 6.5, "height": 16.25}),
    "RoundedFlatPad": (
        RoundedFlatPad,
        {"flat": 2.0, "edge_radius": 5.0, "width": 10.0, "height": 10.0},
    ),
    "FlatSpecimen": (FlatSpecimen, {"length": 40.0, "thickness": 13.0}),
    "CylinderSpecimen": (CylinderSpecimen, {"radius": 70.0, "width": 6.5, "height": 16.25}),
    "GrooveSpecimen": (GrooveSpecimen, {"radius": 70.0, "width": 14.0, "height": 10.0}),
    "Displacement": (Displacement, {"tag": "bottom", "x": 0.0, "y": 1e-3}),
    "Traction": (Traction, {"tag": "end", "x": 1.0, "y": 0.0, "load": "bulk"}),
    "Refinement": (Refinement, {"elements": 8, "degree": 2, "toward": [(0.0, 0.0)], "ratio": 4.0}),
    "LoadStep-ints": (LoadStep, {"name": "A", "normal": 100.0, "increments": 2, "cycle": 1}),
    "Waveform-ints": (Waveform, {"amplitude": 1e-3, "normal": 100.0, "cycles": 2}),
    "CattaneoMindlinScene": (
        CattaneoMindlinScene,
        {
            "pairs": 21,
            "zone": 1.5,
            "radius": 70.0,
            "width": 6.5,
            "height": 16.25,
            "E_upper": 73400.0,
            "nu_upper": 0.33,
            "E_lower": 110000.0,
            "nu_lower": 0.3,
            "friction": 0.3,
            "normal": 100.0,
            "increments": 2,
            "flank_elements": 16,
            "side_elements": 12,
            "top_elements": 12,
        },
    ),
    "SemiSmoothNewton": (
        SemiSmoothNewton,
        {"tolerance": 1e-9, "max_iterations": 30, "max_substeps": 2},
    ),
    "FallbackSolver": (FallbackSolver, {"max_substeps": 2}),
    "LemkeSolver": (LemkeSolver, {"max_substeps": 2, "max_pivots": 500}),
    "Accuracy": (Accuracy, {"mesh": "adaptive", "tolerance": 0.01, "budget": 41}),
    "AdaptiveSettings": (
        AdaptiveSettings,
        {
            "tolerance": 0.01,
            "budget": 81,
            "first": 21,
            "ratio": 12.0,
            "max_levels": 3,
            "grading": 0.1,
            "edge_peak": 0.8,
            "edge_tolerance": 0.02,
            "edge_iterations": 2,
            "coarse_iterations": 2,
            "coarse_tolerance": 0.02,
        },
    ),
    "StressSettings": (
        StressSettings,
        {
            "far_points": 6,
            "near_factor": 0.5,
            "graded_points": 4,
            "graded_ratio": 0.3,
            "subtract_factor": 3.0,
            "boundary_tolerance": 1e-6,
            "outside_tolerance": 1e-4,
            "chunk": 128,
            "coarse_factor": 5.0,
            "far_factor": 20.0,
        },
    ),
    "IntegrationSettings": (
        IntegrationSettings,
        {
            "far_ratio": 3.0,
            "far_points": 4,
            "near_ratio": 0.4,
            "mid_points": 12,
            "graded_points": 8,
            "graded_ratio": 0.4,
            "singular_points": 12,
            "log_points": 6,
        },
    ),
    "PlaneSearch": (
        PlaneSearch,
        {"theta_step_deg": 10.0, "psi_step_deg": 30.0, "refine_levels": 2, "chunk_points": 100},
    ),
    "KelvinKernel": (KelvinKernel, {"shear_modulus": 27600.0, "nu": 0.33}),
    "HalfPlaneBody": (
        HalfPlaneBody,
        {
            "face": NurbsCurve.line([-1.0, 0.0], [1.0, 0.0]),
            "material": Material(73400.0, 0.33),
            "datum": 5.0,
            "bulk_origin": 1.0,
        },
    ),
    "HertzLineContact": (
        HertzLineContact,
        {"load": 100.0, "effective_radius": 70.0, "effective_modulus": 40000.0},
    ),
    "MindlinDeresiewicz": (MindlinDeresiewicz, {"hertz": _HERTZ, "friction": 0.6}),
    "NowellHills": (NowellHills, {"hertz": _HERTZ, "friction": 0.6, "shift": -1.0}),
    "RoundedFlatPunch": (
        RoundedFlatPunch,
        {"flat": 2.0, "edge_radius": 5.0, "effective_modulus": 40000.0, "friction": 0.3},
    ),
    "TiltedContact": (
        TiltedContact,
        {"slope": np.sin, "effective_modulus": 40000.0, "friction": 0.3},
    ),
    "DissimilarCylinders": (
        DissimilarCylinders,
        {
            "radius": 70.0,
            "E_upper": 110000.0,
            "nu_upper": 0.3,
            "E_lower": 73400.0,
            "nu_lower": 0.33,
            "friction": 0.5,
        },
    ),
}
#: the fields where None is a valid value (it then means something)
NONE_ALLOWED = {
    ("LoadStep", name) for name in ("normal", "approach", "delta", "moment", "rotation")
} | {("Rig", "pivot_height"), ("Waveform", "moment"), ("Refinement", "degree")}
NONE_ALLOWED |= {("JumpControl", "max_change"), ("JumpControl", "max_jump")}
NONE_ALLOWED |= {("LemkeSolver", "max_pivots")}
NONE_ALLOWED |= {("AdaptiveSettings", "ratio"), ("AdaptiveSettings", "edge_peak")}
NONE_ALLOWED |= {(record, axis) for record in ("Displacement", "Traction") for axis in "xy"}
#: the fields where infinity is valid (a rigid rig)
INFINITY_ALLOWED = {("Rig", "tangential"), ("Rig", "normal"), ("Rig", "rotational")}
BAD = {"True": True, "string": "3", "nan": math.nan, "inf": math.inf, "None": None}
BAD["huge"] = 10**400  # beyond a float and a 64-bit count: Python's float() overflows


def _cases():
    for label, (record, valid) in RECORDS.items():
        name = record.__name__
        for field, value in valid.items():
            if not isinstance(value, (int, float)) or field == "name":
                continue
            if label.startswith("LoadStep") and field == "normal" and label != "LoadStep":
                continue  # the other LoadStep rows carry P only to be valid
            for bad_label, bad in BAD.items():
                if bad is None and (name, field) in NONE_ALLOWED:
                    continue
                if bad_label in ("inf", "huge") and (name, field) in INFINITY_ALLOWED:
                    continue  # (an int past a float's range reads as infinity there)
                yield pytest.param(record, valid, field, bad, id=f"{label}.{field}={bad_label}")


@pytest.mark.parametrize(("record", "valid", "field", "bad"), list(_cases()))
def test_a_bad_number_is_refused_naming_the_field(record, valid, field, bad):
    with pytest.raises(InputError) as error:
        record(**{**valid, field: bad})
    message = str(error.value)
    assert field in message, message
    assert "\n" not in message
    # cause and fix: what was given is shown, and a way out is offered
    shown = "3" if isinstance(bad, str) else "10^400" if bad == 10**400 else repr(bad)
    assert shown in message, message
    assert any(word in message for word in ("give", "0: the body does not wear")), message


@pytest.mark.parametrize("label", list(RECORDS))
def test_numpy_scalars_and_ints_are_taken_as_before(label):
    record, valid = RECORDS[label]
    plain = record(**valid)
    as_numpy = {
        k: (np.int64(v) if isinstance(v, int) else np.float32(v))
        if isinstance(v, (int, float)) and not isinstance(v, bool)
        else v
        for k, v in valid.items()
    }
    converted = record(**as_numpy)
    for field, value in valid.items():
        if isinstance(value, (int, float)):
            got, want = getattr(converted, field), getattr(plain, field)
            assert type(got) is type(want), (field, type(got))
            assert got == pytest.approx(want, rel=1e-6), field
            assert not isinstance(got, np.generic), field


def test_whole_numbers_as_integral_floats_still_count():
    step = LoadStep("A", 100, 0, 2.0, cycle=np.int32(3))
    assert (step.increments, step.cycle, step.normal, step.tangential) == (2, 3, 100.0, 0.0)
    assert type(step.increments) is int and type(step.normal) is float
    with pytest.raises(
        InputError, match=r"LoadStep\.increments must be a whole number >= 1, got 2\.5"
    ):
        LoadStep("A", 100.0, increments=2.5)
    with pytest.raises(InputError, match=r"Refinement\.elements must be a whole number >= 1"):
        Refinement(elements=True)


@pytest.mark.parametrize(
    ("build", "message"),
    [
        (lambda: LoadStep("A", 100.0, loads={"bulk": "150"}), r"loads\['bulk'\] must be a number"),
        (lambda: LoadStep("A", 100.0, loads={"bulk": True}), r"loads\['bulk'\] must be a number"),
        (lambda: LoadStep("A", 100.0, loads={"bulk": math.nan}), r"LoadStep\.loads must be finite"),
        (lambda: LoadStep("A", 100.0, loads=None), r"LoadStep\.loads must be a mapping"),
        (lambda: Material(73400.0, 0.3, plane_stress="no"), r"plane_stress must be True or False"),
        (lambda: Material(73400.0, 0.3, plane_stress=1), r"plane_stress must be True or False"),
        (lambda: LoadingBlock("top", (0.0, "3")), r"LoadingBlock\.force Fy must be a number"),
        (lambda: LoadingBlock("top", (True, 0.0)), r"LoadingBlock\.force Fx must be a number"),
        (lambda: LoadingBlock("top", (0.0, math.nan)), r"LoadingBlock\.force Fy must be finite"),
        (lambda: LoadingBlock("top", (0.0, 1.0, 2.0)), r"LoadingBlock\.force must be a pair"),
        (lambda: Waveform(1e-3, 100.0, cycles=True), r"Waveform\.cycles must be a whole number"),
        (lambda: Waveform(1e-3, 100.0, increments="40"), r"Waveform\.increments must be a whole"),
        (lambda: Refinement(4, degree="2"), r"Refinement\.degree must be a whole number >= 1"),
        # the counts are converted before the simulation is looked at
        (lambda: WearSimulation(None, {}, True), r"WearSimulation\.cycles must be a whole"),
        (lambda: WearSimulation(None, {}, "1000"), r"WearSimulation\.cycles must be a whole"),
        (lambda: WearSimulation(None, {}, 10, outputs=[2.5]), r"outputs\[0\] must be a whole"),
        (lambda: CoulombFriction(-0.1), r"CoulombFriction\.friction must be >= 0, got -0\.1"),
        # the scene file's bound, from Python too (a percentage typed for a coefficient)
        (lambda: CoulombFriction(30), r"CoulombFriction\.friction must be <= 10, got 30"),
        (lambda: Material(73400.0, 0.5), r"Material\.nu: Poisson's ratio nu must lie in"),
        (
            lambda: CattaneoMindlinScene(tangential=(0.0, "18", 0.0, -18.0, 0.0)),
            r"CattaneoMindlinScene\.tangential\[1\] must be a number",
        ),
        (
            lambda: CattaneoMindlinScene(tangential=(0.0, 18.0, 0.0, -(10**400), 0.0)),
            r"CattaneoMindlinScene\.tangential\[3\] must be a finite number .* 10\^400",
        ),
        (
            lambda: DissimilarCylinders(70.0, 1e5, 0.7, 7e4, 0.3, 0.5),
            r"DissimilarCylinders\.nu_upper: Poisson's ratio nu must lie in",
        ),
        (lambda: KelvinKernel(1.0, 0.5), r"KelvinKernel\.nu: Poisson's ratio nu must lie in"),
    ],
)  # fmt: skip
def test_other_bad_inputs_are_named(build, message):
    with pytest.raises(InputError, match=message) as error:
        build()
    assert "; give" in str(error.value) or "mapping" in str(error.value)


def test_valid_records_keep_their_values():
    """No valid input changes: the stored values are what float()/int() gave before."""
    assert LoadingBlock("top", np.array([0, -100])).force == (0.0, -100.0)
    assert Displacement("bottom", x=np.float32(0.5), y=None).x == np.float32(0.5)
    assert Traction("end", x=lambda p: p[:, 0]).y == 0.0
    assert Material(73400, 0, np.bool_(True)).plane_stress is True
    assert CoulombFriction(0).friction == 0.0
    assert CoulombFriction(10).friction == 10.0
    assert Refinement(np.int64(3), degree=np.int64(2)).degree == 2
    # a 0-d array (what some numpy reductions give) is its number, as float() took it
    step = LoadStep("A", np.array(100.0), np.array(5), np.array(2))
    assert (step.normal, step.tangential, step.increments) == (100.0, 5.0, 2)
    assert type(step.normal) is float and type(step.increments) is int
    with pytest.raises(InputError, match=r"LoadStep\.tangential must be a number"):
        LoadStep("A", 100.0, np.array([1.0, 2.0]))


@pytest.mark.parametrize(
    ("build", "message"),
    [
        (lambda: ContactSpec(pairs="61"), r'\[contact\] pairs must be an integer, got the str'),
        (lambda: ContactSpec(pairs=True), r"\[contact\] pairs must be an integer, got True"),
        (lambda: ContactSpec(pairs=10**400), r"\[contact\] pairs must fit a 64-bit .*10\^400"),
        (lambda: ContactSpec(pairs=0), r"\[contact\] pairs must be >= 1, got 0"),
        (lambda: ContactSpec(friction="0.5"), r"\[contact\] friction must be an integer or a"),
        (lambda: ContactSpec(friction=math.nan), r"\[contact\] friction must be a finite number"),
        (lambda: ContactSpec(friction=30.0), r"\[contact\] friction is a Coulomb coefficient"),
        (lambda: ContactSpec(zone=True), r"\[contact\] zone must be an integer or a number"),
        (lambda: ContactSpec(degree=9), r"\[contact\] degree must be between 1 and 8"),
        (lambda: ContactSpec(tolerance="0.02"), r"\[contact\] tolerance must be an integer or a"),
        (lambda: ContactSpec(budget=3), r"\[contact\] budget must be >= 5 pairs"),
        (lambda: ContactSpec(sliding="yes"), r"\[contact\] sliding must be true or false"),
        (lambda: MeshSpec(flank_elements="16"), r"\[mesh\] flank_elements must be an integer"),
        (lambda: MeshSpec(top_elements=0), r"\[mesh\] top_elements must be >= 1"),
        (
            lambda: LoadSpec(("A",), ("100",), (0.0,), (0.0,), (1,)),
            r'\[load\] P\[0\] must be an integer or a number, got the string "100"',
        ),
        (
            lambda: LoadSpec(("A",), (100.0,), (10**400,), (0.0,), (1,)),
            r"\[load\] Q\[0\] must fit a 64-bit integer",
        ),
        (
            lambda: LoadSpec(("A",), (100.0,), (0.0,), (math.inf,), (1,)),
            r"\[load\] bulk\[0\] must be a finite number",
        ),
        (
            lambda: LoadSpec(("A",), (100.0,), (0.0,), (0.0,), (2.0,)),
            r"\[load\] increments\[0\] must be an integer",
        ),
    ],
)  # fmt: skip
def test_scene_records_from_python_are_checked_as_the_file_is(build, message):
    """A Scene built from Python (its ContactSpec, MeshSpec, LoadSpec) meets the reader's
    checks of the same keys, in the file's words: no traceback later, no coercion."""
    with pytest.raises(SceneFileError, match=message) as error:
        build()
    assert "\n" not in str(error.value)


def test_scene_records_from_python_keep_valid_values():
    assert type(ContactSpec(pairs=np.int64(31)).pairs) is int
    assert ContactSpec(friction=1, zone=2).zone == 2
    assert MeshSpec(8, 6, 6).side_elements == 6
    load = LoadSpec(("A", "B"), (None, None), (0.0, 0.0), (0.0, 0.0), (1, 1), approach=(1e-3, 2e-3))
    assert load.approach == (1e-3, 2e-3)


@pytest.fixture(scope="module")
def small_run():
    from fretbem.scenes.reference import cattaneo_mindlin
    from fretbem.simulation import run

    return run(cattaneo_mindlin(pairs=21))


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda r, d: write_results(r, d, overwrite="no"), r"overwrite must be True or Fal"),
        (lambda r, d: write_results(r, d, overwrite=1), r"overwrite must be True or False, got 1"),
        (lambda r, d: write_results(r, d, check="no"), r"check must be True or False"),
        (lambda r, d: write_results(r, d, figures="no"), r"figures must be True or False, or None"),
        (lambda r, d: write_results(r, d, vtk=0), r"vtk must be True or False, or None"),
        (lambda r, d: write_results(r, d, writers="csv"), r"writers must be a list of writer"),
    ],
)  # fmt: skip
def test_a_yes_no_argument_of_the_writers_is_true_or_false(small_run, tmp_path, call, message):
    """``overwrite="no"`` was true: it overwrote the directory it was meant to keep."""
    target = tmp_path / "kept"
    target.mkdir()
    (target / "mine.txt").write_text("the user's file")
    with pytest.raises(InputError, match=message):
        call(small_run, target)
    assert [p.name for p in target.iterdir()] == ["mine.txt"]


def test_run_and_run_sliding_check_their_arguments():
    from fretbem.scenes.builder import build
    from fretbem.scenes.file import load_scene
    from fretbem.simulation import run
    from fretbem.sliding import run_sliding
    from fretbem.sliding.slide import SlidingError

    examples = Path(__file__).parents[2] / "examples"
    with pytest.raises(InputError, match=r"run check must be True or False"):
        run(build(load_scene(examples / "cattaneo_mindlin.toml"))[0], check="no")
    sliding, _ = build(load_scene(examples / "gross_sliding.toml"))
    for every, words in (("1", "a number"), (10**400, "10^400"), (math.nan, "a finite number")):
        with pytest.raises(SlidingError, match=rf"every must be {re.escape(words)}|10\^400"):
            run_sliding(sliding, every=every, note=None)
    with pytest.raises(SlidingError, match=r"check must be True or False"):
        run_sliding(sliding, check="yes", note=None)


_TI = {"material": "Ti-6Al-4V"}
_GRID = {"x": [0, 1], "depth": 1.0, "nx": 3, "ny": 3}
REQUESTS = [
    (fatigue_request_from_dict, {**_TI, "critical_distance": 10**400}, r"critical_dist.*10\^400"),
    (fatigue_request_from_dict, {**_TI, "runout_cycles": 10**400}, r"runout_cycles must be a fin"),
    (fatigue_request_from_dict, {**_TI, "cycle_steps": [0, 10**400]}, r"cycle_steps\[1\] must fit"),
    (stress_request_from_dict, {"points": [[10**400, -0.5]]}, r"\[stress\] points must be a lis"),
    (stress_request_from_dict, {"points": [["trailing-edge", "0.5"]]}, r"points y must be a num"),
    (stress_request_from_dict, {"grid": {**_GRID, "x": [0, 10**400]}}, r"x\[1\] must be a finite"),
    (stress_request_from_dict, {"grid": {**_GRID, "nx": 10**400}}, r"nx must fit a 64-bit int"),
]


@pytest.mark.parametrize(("read", "table", "message"), REQUESTS)
def test_requests_from_python_dicts_refuse_what_a_file_cannot_hold(read, table, message):
    """A TOML file's numbers are 64-bit; a dict from Python can hold 10**400 (it ended in an
    OverflowError) or text where a number goes (a y of "0.5" was taken)."""
    with pytest.raises(InputError, match=message):
        read(table)
