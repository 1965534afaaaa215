"""Hostile values by class, on every key: read strictly (no int/bool/string coercion), the key
named in the message, physical ranges checked, sizes estimated and refused up front, and
text encodings read or refused by name. Reproducers of issue 24 are marked as such."""

from __future__ import annotations

import codecs
import math

import numpy as np
import pytest

from fretbem.errors import InputError, ResourceLimitError, ResultCheckError
from fretbem.fatigue import fatigue_request_from_dict
from fretbem.fatigue.material import CONSTANTS, RANGES
from fretbem.scenes import limits
from fretbem.scenes.builder import build
from fretbem.scenes.file import load_scene, scene_from_dict
from fretbem.scenes.spec import KEYS
from fretbem.scenes.text import MAX_BYTES
from fretbem.stress.request import stress_request_from_dict

BASE = {
    "pad": {"shape": "cylinder", "radius": 70.0},
    "specimen": {"shape": "cylinder"},
    "contact": {"pairs": 11},
    "load": {"steps": ["A", "B"], "P": 100.0, "Q": [0.0, 18.0]},
}

#: values of the wrong kind for each kind of key: a bool for a number, a float with a
#: fraction or 2.0 for a count, a string of a number, a list, a table
WRONG = {
    "number": [True, "1.5", [1.0], {"a": 1}],
    "count": [2.5, 2.0, True, "5", [5]],
    "string": [1, True, 1.5, ["x"]],
    "bool": ["false", 0, 1, "true"],
}


def _kind(key) -> str | None:
    if key.kind == (bool,):
        return "bool"
    if key.kind == (int,):
        return "count"
    if key.kind == (str,):
        return "string"
    if set(key.kind) == {int, float}:
        return "number"
    return None


def _scene(table: str, name: str, value) -> dict:
    data = {k: dict(v) for k, v in BASE.items()}
    if table == "contact" and name in ("tolerance", "budget"):
        data["contact"] = {"mesh": "adaptive"}
    if table == "contact" and name == "zone_width":
        data["contact"].pop("zone", None)
    node = data
    for part in table.split("."):  # [load.cycle] is the table cycle inside [load]
        node = node.setdefault(part, {})
    node[name] = value
    return data


SCALAR_KEYS = [k for k in KEYS if not k.shapes and _kind(k)]


@pytest.mark.parametrize(
    ("table", "name", "value"),
    [(k.table, k.name, v) for k in SCALAR_KEYS for v in WRONG[_kind(k)]],
    ids=lambda v: repr(v),
)
def test_every_scene_key_refuses_a_value_of_the_wrong_kind(table, name, value):
    """No silent coercion: n = 2.7 is not 2, "false" is not true; the key is named."""
    with pytest.raises(InputError, match=rf"\[{table}\] {name}"):
        scene_from_dict(_scene(table, name, value))


@pytest.mark.parametrize(
    ("table", "name"),
    [(k.table, k.name) for k in SCALAR_KEYS if _kind(k) in ("number", "count")],
)
@pytest.mark.parametrize("value", [9223372036854775807, -9223372036854775808, 0, -1, 1e308])
def test_every_numeric_key_takes_extremes_without_a_traceback(table, name, value):
    """Huge, zero and negative values: refused by name, or refused by the size estimate,
    or built; never an IndexError, ZeroDivisionError or a run that never ends."""
    try:
        scene = scene_from_dict(_scene(table, name, value))
        limits.check_scene(scene, available=16 * 2**30)
        build(scene)
    except InputError as err:
        assert name in str(err) or "[" in str(err)
    except ResourceLimitError as err:
        assert "estimated" in str(err) and "[" in str(err)


def test_zone_and_zone_width_together_are_refused():
    """Reproducer: both given, one was silently ignored."""
    with pytest.raises(InputError, match="zone and zone_width"):
        scene_from_dict({**BASE, "contact": {"zone": 1.5, "zone_width": 0.8}})


def test_empty_step_lists_name_the_key():
    """Reproducer: "max() arg is an empty sequence"."""
    for key in ("steps", "P", "Q"):
        data = _scene("load", key, [])
        with pytest.raises(InputError, match=rf"\[load\] {key} is an empty list"):
            scene_from_dict(data)


def test_material_message_names_the_table_the_file_has():
    """Reproducer: a bad [material] plane was reported in [pad.material]."""
    with pytest.raises(InputError, match=r"^\[material\] plane"):
        scene_from_dict(_scene("material", "plane", "strainn"))
    data = _scene("material", "E", 1.0)
    data["pad"]["material"] = {"nu": 0.7}
    with pytest.raises(InputError, match=r"^\[pad\.material\] nu"):
        scene_from_dict(data)


# -- sizes: estimated from the keys, refused with the estimate, before anything is built ----
@pytest.mark.parametrize(
    ("table", "name", "value", "words"),
    [
        ("contact", "pairs", 9223372036854775807, "[contact] pairs"),
        ("contact", "pairs", 200001, "[contact] pairs"),
        ("mesh", "flank_elements", 10**9, "[mesh]"),
        ("load", "increments", 10**9, "[load] increments"),
    ],
)
def test_hopeless_sizes_are_refused_up_front_with_the_estimate(table, name, value, words):
    scene = scene_from_dict(_scene(table, name, value))
    with pytest.raises(ResourceLimitError, match="estimated") as info:
        build(scene)
    assert words in str(info.value)


def test_a_long_history_is_refused_by_its_stored_results():
    n = 200_000
    data = _scene("load", "Q", [0.0] * n)
    data["load"].pop("steps")
    with pytest.raises(ResourceLimitError, match="steps store about"):
        limits.check_scene(scene_from_dict(data), available=512 * 2**20)


def test_the_estimate_is_quick_and_close_for_the_reference_scene():
    scene = scene_from_dict(_scene("contact", "pairs", 61))
    estimate = limits.check_scene(scene)
    simulation, _ = build(scene)
    dofs = simulation.pair.upper.dofs + simulation.pair.lower.dofs
    assert 0.8 < estimate.dofs / dofs < 1.25  # measured 0.99
    assert estimate.seconds < 5


# -- text files ---------------------------------------------------------------------------
TEXT = """# pad: radius 70 mm, \u00b5 = 0.3, 20 \u00b0C
[pad]
shape = "cylinder"
[contact]
pairs = 11
"""


@pytest.mark.parametrize("encoding", ["utf-8", "utf-8-sig", "utf-16"])
def test_unicode_files_with_a_mark_are_read(tmp_path, encoding):
    path = tmp_path / "scene.toml"
    path.write_bytes(TEXT.encode(encoding))
    assert load_scene(path).contact.pairs == 11


@pytest.mark.parametrize(
    ("data", "words"),
    [
        (TEXT.encode("latin-1"), "not UTF-8 (byte 0xb5 on line 1"),
        (TEXT.encode("cp1252"), "Latin-1 or Windows-1252"),
        (TEXT.encode("utf-16-le"), "not a text file"),
        (codecs.BOM_UTF16_LE + b"\x00\xd8", "UTF-16 mark"),
    ],
)
def test_other_encodings_are_refused_by_name(tmp_path, data, words):
    path = tmp_path / "scene.toml"
    path.write_bytes(data)
    with pytest.raises(InputError, match="save it as UTF-8") as info:
        load_scene(path)
    assert words in str(info.value)


def test_a_huge_file_is_refused_before_it_is_read(tmp_path):
    path = tmp_path / "scene.toml"
    with open(path, "wb") as handle:
        handle.truncate(MAX_BYTES + 10)
    with pytest.raises(InputError, match="larger than"):
        load_scene(path)


# -- [fatigue] and [stress]: strict values, physical ranges --------------------------------
FATIGUE_WRONG = [
    ("in_plane_only", "false"),
    ("in_plane_only", 1),
    ("cycle_steps", [1.7, 2.2, 3.9]),
    ("cycle_steps", [True, 2]),
    ("map_points", [9.5, 5]),
    ("map_points", [1, 5]),
    ("runout_cycles", True),
    ("runout_cycles", -5.0),
    ("critical_distance", "0.05"),
    ("critical_distance", -0.1),
    ("area_radius_factor", -1.0),
    ("area_radius_factor", 0.0),
    ("map_depth", -1.0),
    ("surface_depth", -0.1),
    ("methods", [1, 2]),
    ("methods", ["dang_van"]),
    ("direction", 1),
    ("hot_spot", [0.0, -1.0]),
    ("map_x", [1.0, -1.0]),
]


@pytest.mark.parametrize(("key", "value"), FATIGUE_WRONG, ids=lambda v: repr(v))
def test_fatigue_keys_are_strict(key, value):
    with pytest.raises(InputError, match=rf"\[fatigue\] {key}"):
        fatigue_request_from_dict({"material": "Ti-6Al-4V", key: value})


def _outside(key: str) -> list[float]:
    low, high, open_ = RANGES[key]
    values = []
    if low is not None:
        values.append(low if open_ else low - 1.0)
    if high is not None:
        values.append(high if open_ else high + 1.0)
    return values


@pytest.mark.parametrize(
    ("key", "value"), [(k, v) for k in CONSTANTS for v in _outside(k)], ids=lambda v: repr(v)
)
def test_fatigue_constants_outside_their_physical_range_are_refused(key, value):
    """Reproducer: fatigue_strength_exponent = 0.5 turned lives into run-outs, exit 0."""
    with pytest.raises(InputError, match=rf"constant {key} = .* physical range"):
        fatigue_request_from_dict({"material": "Ti-6Al-4V", "constants": {key: value}})


@pytest.mark.parametrize("value", [True, "1000.0", math.nan])
def test_fatigue_constants_are_numbers(value):
    with pytest.raises(InputError, match="fatigue_strength_coefficient"):
        fatigue_request_from_dict(
            {"material": "Ti-6Al-4V", "constants": {"fatigue_strength_coefficient": value}}
        )


STRESS_WRONG = [
    ("line", "n", 2.7),
    ("line", "n", True),
    ("line", "depth", "1.0"),
    ("line", "grading", False),
    ("line", "x", True),
    ("grid", "nx", 20.5),
    ("grid", "ny", "5"),
    ("grid", "depth", True),
    ("grid", "x", [True, 1.0]),
]


@pytest.mark.parametrize(("where", "key", "value"), STRESS_WRONG, ids=lambda v: repr(v))
def test_stress_keys_are_strict(where, key, value):
    table = {"x": 0.0, "depth": 1.0, "n": 5} if where == "line" else {"x": [-1.0, 1.0],
                                                                      "depth": 1.0}  # fmt: skip
    table[key] = value
    with pytest.raises(InputError, match=rf"\[stress\.{where}\] {key}"):
        stress_request_from_dict({where: table})


@pytest.mark.parametrize(("key", "value"), [("steps", [1, 2]), ("body", 1), ("vtk", "no")])
def test_stress_table_keys_are_strict(key, value):
    with pytest.raises(InputError, match=rf"\[stress\] {key}"):
        stress_request_from_dict({key: value})


@pytest.mark.parametrize("body", ["pad", "specimen"])
def test_a_body_lower_than_its_face_sag_names_the_height(body):
    """Reproducer: reported as a boundary that runs clockwise or crosses itself."""
    data = {k: dict(v) for k, v in BASE.items()}
    data["pad"] = {"shape": "cylinder", "radius": 5.0}
    data["specimen"] = {"shape": "cylinder", "radius": 5.0}
    data[body].update(width=9.0, height=0.5)
    with pytest.raises(InputError, match=rf"\[{body}\]: a {body} 0.5 mm high .* sag"):
        build(scene_from_dict(data))


# -- the pad block's rotation: its keys, a block that tips, the checks that name it ---------

#: half-plane bodies (fast) with the pivot at the contact
TURNING = {
    "pad": {"model": "half-plane"},
    "specimen": {"model": "half-plane"},
    "contact": {"pairs": 21, "estimate": False},
    "rig": {"pivot_height": 0.0},
    "load": {"steps": ["A", "B"], "P": 100.0, "Q": [0.0, 18.0]},
}


def _turning(**tables) -> dict:
    data = {k: dict(v) for k, v in TURNING.items()}
    for name, values in tables.items():
        data[name] = {**data.get(name, {}), **values}
    return data


@pytest.mark.parametrize("name", ["moment", "rotation"])
@pytest.mark.parametrize(
    "value",
    [True, "1.5", {"a": 1}, math.nan, math.inf, [True, 1.0], ["x", 1.0], [math.nan, 0.0], []],
    ids=repr,
)
def test_moment_and_rotation_refuse_every_wrong_value(name, value):
    """[load] moment and rotation take a number or one per step: the key named otherwise
    (they are not in the scalar-key matrix above, since they also take lists)."""
    with pytest.raises(InputError, match=rf"\[load\] {name}"):
        scene_from_dict(_turning(load={name: value}))


@pytest.mark.parametrize("name", ["M_amplitude", "M_phase"])
@pytest.mark.parametrize("value", [True, "1.0", [1.0], math.nan, -math.inf], ids=repr)
def test_cyclic_moment_keys_refuse_wrong_values(name, value):
    load = {"P": 100.0, "moment": 1.0, "cycle": {"Q": 9.0, "increments": 8, name: value}}
    with pytest.raises(InputError, match=rf"\[load\.cycle\] {name}"):
        scene_from_dict({**TURNING, "load": load})


@pytest.mark.parametrize("value", [1.0e5, -1.0e5, 1.0e308, -1.0e308])
def test_a_pivot_beyond_any_rig_is_refused(value):
    """Reproducer: pivot_height = 1e308 ran, and M = h Q overflowed to null in summary.json."""
    with pytest.raises(InputError, match=r"\[rig\] pivot_height .* within 10000 mm"):
        scene_from_dict(_turning(rig={"pivot_height": value}))
    scene_from_dict(_turning(rig={"pivot_height": -1.0e4}))  # the limit itself is taken


def _solve(data):
    from fretbem.pipeline import run_scene

    return run_scene(scene_from_dict(data))


@pytest.mark.parametrize(
    ("tables", "words"),
    [
        # Q = 18 N/mm 10 mm below the datum's pivot with the block free: d = 1.8 mm
        ({"rig": {}, "load": {"moment": 0.0}}, ("[load] moment", "d = 1.8 mm", "pivot_height")),
        # reproducer: the Lemke fallback returned a solution that did not balance the loads
        ({"load": {"moment": 1.0e6}}, ("[load] moment", "d = -1e+04 mm")),
        # reproducers: IndexError in Lemke's ratio test on an overflowed tableau
        ({"load": {"moment": 1.0e308}}, ("[load] moment",)),
        ({"rig": {"stiffness_rotation": 1.0e-12}}, ("[rig] stiffness_rotation",)),
        ({"load": {"P": 100.0, "moment": 1.0e308, "cycle": {"Q": 9.0, "increments": 8}}},
         ("[load.cycle] M_amplitude",)),
    ],
)  # fmt: skip
def test_a_block_that_tips_is_refused_naming_its_keys(tables, words):
    """A rotating block whose step has no balance: one message naming the step, the likely
    cause (the contact's centre d = (h Q - M) / P outside the zone) and the keys; never a
    retry with Lemke's method (its LCP form holds a non-rotating block's balance)."""
    from fretbem.solvers.newton import SolverConvergenceError

    data = _turning(**{k: v for k, v in tables.items() if k != "load"})
    if "load" in tables:
        load = tables["load"]
        data["load"] = load if "cycle" in load else {**data["load"], **load}
    if tables.get("rig") == {}:
        data["rig"] = {}
    with pytest.raises((InputError, SolverConvergenceError)) as failure:
        _solve(data)  # refused before solving where P, Q and M give d, else when solving
    message = str(failure.value)
    assert "no balance found for the pad block's rotation" in message
    assert all(w in message for w in words), message
    assert "Lemke" not in message and "lemke" not in message


@pytest.mark.parametrize("stiffness", [1.0e-308, 1.0e-250])
def test_a_spring_too_soft_for_floating_point_is_refused(stiffness):
    """Reproducer: k_r = 1e-308 ended in an IndexError in Lemke's ratio test (after
    overflow warnings); the spring is named, a free block is a zero moment."""
    with pytest.raises(InputError, match=r"\[rig\] stiffness_rotation = .* so soft .* moment = 0"):
        _solve(_turning(rig={"stiffness_rotation": stiffness}))


def test_lemke_refuses_a_problem_that_is_not_finite():
    """Reproducer: NaN ratios emptied the tie set: IndexError instead of a LemkeError."""
    from fretbem.solvers.lemke import LemkeError, solve_lcp

    with pytest.raises(LemkeError, match="not finite"):
        solve_lcp(np.eye(2), np.array([-1.0, math.inf]))
    with pytest.raises(LemkeError, match="not finite"):
        solve_lcp(np.array([[1.0, math.nan], [0.0, 1.0]]), np.array([-1.0, -1.0]))


def test_a_rotating_simulation_gets_no_lemke_fallback():
    from fretbem.solvers.fallback import with_fallback

    simulation, _ = build(scene_from_dict(_turning(rig={"stiffness_rotation": 1.0e5})))
    assert simulation.rotates and with_fallback(simulation) is None
    held, _ = build(scene_from_dict(TURNING))
    assert not held.rotates and with_fallback(held) is not None


def test_a_displacement_driven_simulation_gets_no_lemke_fallback():
    """Lemke's LCP keeps the block's force rows: a history with a step driven by delta is
    not retried by it (the Simulation refuses Lemke there), so a Newton failure is reported."""
    from fretbem.solvers.fallback import FallbackSolver, with_fallback

    data = _turning(load={"steps": ["A", "B"], "P": 100.0, "Q": [0.0, 0.0], "delta": [0.0, 1e-4]})
    del data["load"]["Q"]
    driven, _ = build(scene_from_dict(data))
    assert any(not s.controls.by_force for s in driven.steps)
    assert with_fallback(driven) is None
    assert not FallbackSolver().displacement_control


def test_a_rotation_the_contact_cannot_follow_is_refused_at_its_increment():
    """A 1 rad rotation pushes the contact to the zone's end: the increment that reaches it
    is refused with the tipping block's message (as in finite sliding), which names the
    rotation key and the fixes, not only 'widen the zone'."""
    from fretbem.simulation import BlockTippingError

    with pytest.raises(
        BlockTippingError, match=r"the zone's end .*turned by \[load\] rotation .*\[rig\] stiff"
    ) as refused:
        _solve(_turning(load={"rotation": [0.0, 1.0]}))
    # the zone-edge check at every increment: a failed result check (fretbem run exits 1)
    assert isinstance(refused.value, ResultCheckError) and refused.value.check == "zone_edge"
