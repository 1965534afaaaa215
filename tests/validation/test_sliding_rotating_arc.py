"""Finite sliding along an arc with a pad block that rotates: a rig's rotational spring, a
moment or an actuator's rotation while the pad slides several contact widths along a
convex cylindrical specimen or in a concave groove (BEM bodies: an arc refuses half-planes).

The pad turns with the arc (by s / R about its centre) and its block rotates by theta about
the pivot, a point of the pad in its own axes: theta is its tilt from the turned pose.
Checked at every step: against the same bodies and rig paired where that step's pairs were
(its "twin", run() on the turned pair), and against the specimen drawn turned back by the
pad's turn with the pad unturned, no turned axes anywhere (its "turned-back twin"); each
twin pressed, driven into gross slip against the step's sense and then to the step's block
position (a gross-slip state is that of the block's position alone); M against the
tractions' moment about the pivot by quadrature over the pad's face
(:func:`fretbem.testing.sliding.traction_moment`) and against M = h Q - e P with the
pressure's centre in the pad's axes; q = f p at every pair in contact and Q / f P from the
tractions its closed form for the pressure's centre e off the pad's axis; the spring's,
the moment's and the rotation's own rows. A stiff spring equals the held block and a
spring-free zero rotation the non-rotating run. Tolerances: measured values (in the
comments) plus a margin.
"""

from __future__ import annotations

import copy
import csv
import json
import math
from pathlib import Path

import attrs
import numpy as np
import pytest
import tomllib

from fretbem.app import cli
from fretbem.bem.body import BemBody
from fretbem.contact import rotation as pad_rotation
from fretbem.contact.pairing import turning
from fretbem.geometry.boundary import Boundary, Segment
from fretbem.scenes.builder import build
from fretbem.scenes.file import scene_from_data
from fretbem.simulation import LoadStep, run
from fretbem.sliding import run_sliding
from fretbem.sliding.track import Track
from fretbem.solvers.newton import SolverConvergenceError
from fretbem.testing.sliding import traction_moment

ROOT = Path(__file__).resolve().parents[2]
F = 0.3
#: the Hertz half-widths (mm) at P = 100 N/mm: the pad R 70 on the cylinder R 70, in the
#: groove R 70 (the pad R 40), and on the cylinder R 140
HALF = {"gross_sliding_arc.toml": 0.329, "gross_sliding_groove.toml": 0.537}
#: the pads' height (mm): the moments' scale H f P, whatever the pivot's height
H = 16.25


def scene(example="gross_sliding_arc.toml", *, pairs=21, load=100.0, basis="nurbs", rig=None,
          moment=None, rotation=None, specimen=None, contact=None, increments=4):  # fmt: skip
    """``examples/<example>`` pressed by ``load``, slid 3 a and 6 a along the arc and back,
    the block turned by ``rig`` ([rig] keys), ``moment`` or ``rotation`` per step."""
    data = tomllib.loads((ROOT / "examples" / example).read_text())
    a = HALF[example] * math.sqrt(load / 100.0)
    data["contact"].update(pairs=pairs, basis=basis, **(contact or {}))
    data["specimen"].update(specimen or {})
    data["load"].update(
        steps=["press", "half", "slide", "back"], P=load, delta=[0.0, 3 * a, 6 * a, 0.0],
        increments=[1, increments, increments, 2 * increments],
    )  # fmt: skip
    if rig is not None:
        data["rig"] = dict(rig)
    if moment is not None:
        data["load"]["moment"] = list(moment)
    if rotation is not None:
        data["load"]["rotation"] = list(rotation)
    return build(scene_from_data(copy.deepcopy(data)))[0]


def turned_back(body: BemBody, angle: float, centre: np.ndarray) -> BemBody:
    """``body`` drawn turned by ``angle`` about ``centre`` (the same segments, refinement,
    conditions: a rigid turn of the whole body, its clamped base with it)."""
    turn = turning(angle)
    segments = [
        Segment(s.tag, attrs.evolve(s.curve, control_points=centre + (s.curve.control_points
                                                                     - centre) @ turn.T))
        for s in body.boundary.segments
    ]  # fmt: skip
    return BemBody(Boundary(segments), body.material, body.conditions, basis=body.basis,
                   refinement=body.refinement, name=body.name)  # fmt: skip


def twin_steps(load: LoadStep, step, offset: float, position: float) -> tuple:
    """The twin's history: pressed; for a slid step driven 0.1 mm past the step's block
    position against its sense (gross slip that way), then to it (gross slip the step's way:
    the state is that of the block's position alone)."""
    turn = {"moment": load.moment, "rotation": load.rotation}
    steps = (LoadStep("press", step.normal, delta=0.0, **turn),)
    if abs(step.tangential) > 0.5 * F * step.normal:
        delta, sign = position - offset, math.copysign(1.0, step.tangential)
        steps += (
            LoadStep("against", step.normal, delta=delta - 0.1 * sign, increments=2, **turn),
            LoadStep("slide", step.normal, delta=delta, increments=2, **turn),
        )
    return steps


def twins_of(sliding, *, turned: bool = True) -> list[tuple]:
    """Each step's twin and (if ``turned``) turned-back twin: the last step of each."""
    simulation = sliding.simulation  # its pairs on the pad's nodes, the pivot pinned
    out = []
    for load, step, pair, offset, position in zip(
        simulation.steps, sliding.steps, sliding.pairs, sliding.offsets, sliding.positions,
        strict=True,
    ):  # fmt: skip
        steps = twin_steps(load, step, offset, position)
        twin = run(attrs.evolve(simulation, pair=pair, steps=steps, reference=None))
        back = None
        if turned:
            # the specimen turned back, the pad as drawn: the pair frame and the loads along
            # the pad's own axis (a turn of 1e-300 rad selects them; its matrix is identity)
            lower = turned_back(pair.lower, -pair.turn, pair.pivot)
            drawn = attrs.evolve(pair, lower=lower, turn=1e-300)
            back = run(attrs.evolve(simulation, pair=drawn, steps=steps, reference=None))
            back = back.steps[-1]
        out.append((twin.steps[-1], back))
    return out


def measures(sliding, twins) -> list[dict]:
    """Per step: the twins' differences (M of H f P), M against the tractions' moment and
    the lever rule, Coulomb, Q / f P from the tractions against its closed form and at the block."""
    simulation = sliding.simulation
    track, pivot = Track.of(simulation.pair), simulation.block_pivot()
    p0 = max(float(step.pressure.max()) for step in sliding.steps)
    rows = []
    for step, (twin, back), pair, offset in zip(
        sliding.steps, twins, sliding.pairs, sliding.offsets, strict=True
    ):
        p, q = step.pressure, step.shear
        scale = H * F * step.normal
        touching = p > 0
        points = pad_rotation.in_pad_axes(pair, pair.pairing().points)
        e = float(np.sum(points[:, 0] * p) / np.sum(p))
        h = pivot[1] - float(np.sum(points[:, 1] * p) / np.sum(p))
        s = track.along(pair.pairing().points)
        centre = float(np.sum(s * p) / np.sum(p))
        tilt = math.tan(-track.rate * (centre - offset)) if pair.frame == "local" else 0.0
        sign = math.copysign(1.0, step.tangential)
        normal, tangential = step.resultant
        row = {
            "name": step.name,
            "twin_p": float(np.max(np.abs(p - twin.pressure)) / p0),
            "twin_q": float(np.max(np.abs(q - twin.shear)) / p0),
            "twin_M": abs(step.moment - twin.moment) / scale,
            "twin_tilt": abs(step.tilt - twin.tilt),
            "quadrature": abs(step.moment - traction_moment(step, pair, pivot)[0]) / scale,
            "lever": abs(step.moment - (h * step.tangential - e * step.normal)) / scale,
            "coulomb": float(np.max(np.abs(np.abs(q) - F * p)[touching]) / p0),
            "tractions": tangential / (F * normal),
            "closed": (sign * F - tilt) / (F * (1.0 + sign * F * tilt)),
            "block": step.tangential / (F * step.normal),
            "M": step.moment,
            "tilt": step.tilt,
            "turn": pair.turn,
        }
        if back is not None:
            row["back_p"] = float(np.max(np.abs(p - back.pressure)) / p0)
            row["back_q"] = float(np.max(np.abs(q - back.shear)) / p0)
            row["back_M"] = abs(step.moment - back.moment) / scale
            row["back_tilt"] = abs(step.tilt - back.tilt)
        rows.append(row)
    return rows


def check(rows, simulation, *, twin=1e-11, back=1e-9, quadrature=3e-3, closed=1.5e-4):
    """The twins (round-off), the moment's balance (the BEM pad's own equilibrium), Coulomb
    and Q's closed form in every slid step."""
    for row in rows:
        assert row["twin_p"] < twin and row["twin_q"] < twin  # measured 1e-14
        assert row["twin_M"] < twin and row["twin_tilt"] < 1e-14  # 2e-16, 6e-19 rad
        if "back_p" in row:  # measured 3.2e-11 p0, M 1e-13 h f P, tilt 5e-17 rad
            assert row["back_p"] < back and row["back_q"] < back
            assert row["back_M"] < back and row["back_tilt"] < 1e-13
        assert row["quadrature"] < quadrature  # 2.15e-3: as without rotation
        assert row["lever"] < quadrature  # 1.8e-3
    for row in rows[1:]:
        assert row["coulomb"] < 1e-12
        assert abs(row["tractions"] - row["closed"]) < closed  # measured 4e-6
        assert abs(row["block"] / row["tractions"] - 1.0) < 6e-4  # 4.1e-4: the BEM block
    rig = simulation.rig
    for load, row in zip(simulation.steps, rows, strict=True):
        if load.moment is not None:
            assert row["M"] == pytest.approx(load.moment, abs=1e-9)
        elif load.rotation is not None and not math.isfinite(rig.rotational):
            assert row["tilt"] == pytest.approx(load.rotation, abs=1e-15)
        elif load.rotation is not None:
            assert row["tilt"] == pytest.approx(load.rotation - row["M"] / rig.rotational,
                                                rel=1e-9, abs=1e-15)  # fmt: skip
        else:
            assert row["tilt"] == pytest.approx(-row["M"] / rig.rotational, rel=1e-9, abs=1e-15)


#: the cases: springs at two loads and stiffnesses, a moment about the first-contact point,
#: an actuator's rotation held rigidly and through a spring, a groove, a larger specimen
#: radius, quadratic Lagrange faces, the pads' shared turned frame instead of each pair's
CASES = {
    "spring": {"rig": {"stiffness_rotation": 1.0e6}},
    "spring-60": {"rig": {"stiffness_rotation": 2.0e5}, "load": 60.0, "contact": {"zone": 2.0}},
    "moment": {"rig": {"pivot_height": 0.0}, "moment": [0.0, 10.0, 10.0, 10.0],
               "contact": {"zone": 2.0}},
    "rotation": {"rotation": [0.0, -5e-4, -5e-4, 5e-4]},
    "rotation-spring": {"rig": {"stiffness_rotation": 5.0e5},
                        "rotation": [0.0, -5e-4, -5e-4, 5e-4]},
    "groove": {"example": "gross_sliding_groove.toml", "rig": {"stiffness_rotation": 5.0e5},
               "contact": {"zone": 2.0}},
    "radius-140": {"rig": {"stiffness_rotation": 5.0e5},
                   "specimen": {"radius": 140.0, "width": 14.0}},
    "lagrange2": {"rig": {"stiffness_rotation": 5.0e5}, "basis": "lagrange2"},
    "shared-frame": {"rig": {"stiffness_rotation": 1.0e6}, "frame": "shared"},
}  # fmt: skip
FAST = ("spring",)


@pytest.mark.parametrize(
    "case", [c if c in FAST else pytest.param(c, marks=pytest.mark.slow) for c in sorted(CASES)]
)
def test_each_step_along_the_arc_is_the_pad_solved_where_it_slid(case):
    """Every step equals its twin and its turned-back twin, M balances the tractions and
    the lever rule, q = f p and Q has its closed form; the block turns as its rows say."""
    keys = dict(CASES[case])
    frame = keys.pop("frame", "local")  # "shared": the a/R simplification, Q = f P exactly
    simulation = scene(**keys)
    sliding = run_sliding(simulation, note=None, frame=frame)
    assert sliding.repairings >= 8 and abs(sliding.offsets[2]) > 4.5 * 0.25
    rows = measures(sliding, twins_of(sliding))
    check(rows, simulation)
    assert abs(rows[2]["tilt"]) > 1e-4  # the block turns


def _steps_alike(one, other, p0: float, tolerance: float) -> float:
    """The largest difference of p, q (of p0) between two sliding runs' steps, checked
    below ``tolerance``."""
    worst = 0.0
    for a, b in zip(one.steps, other.steps, strict=True):
        worst = max(worst, float(np.max(np.abs(a.pressure - b.pressure))) / p0,
                    float(np.max(np.abs(a.shear - b.shear))) / p0)  # fmt: skip
    assert worst < tolerance
    return worst


@pytest.mark.parametrize(
    "example",
    ["gross_sliding_arc.toml", pytest.param("gross_sliding_groove.toml", marks=pytest.mark.slow)],
)
def test_a_stiff_spring_is_the_held_block_and_a_zero_rotation_the_plain_run(example):
    """k_r = 1e12 slides as the block that does not rotate (its tilt 4.8e-10 rad moves the
    contact by R theta: p and q within 5e-7 of p0, measured 1.7e-7 on the cylinder and
    2.3e-7 in the groove), and a rotation of 1e-300 rad without a spring (theta among the
    unknowns, held at it) as the plain run to round-off (measured 4.7e-14, M 1.7e-13)."""
    contact = {"zone": 2.0} if "groove" in example else None
    plain = run_sliding(scene(example, contact=contact), note=None)
    p0 = max(float(step.pressure.max()) for step in plain.steps)
    stiff = run_sliding(scene(example, contact=contact, rig={"stiffness_rotation": 1e12}),
                        note=None)  # fmt: skip
    assert max(abs(step.tilt) for step in stiff.steps) < 1e-9
    assert stiff.simulation.rotates and not plain.simulation.rotates
    _steps_alike(plain, stiff, p0, 5e-7)
    held = run_sliding(scene(example, contact=contact, rotation=[0.0, 0.0, 0.0, 1e-300]),
                       note=None)  # fmt: skip
    assert held.simulation.rotates
    _steps_alike(plain, held, p0, 1e-12)
    for a, b in zip(plain.steps, held.steps, strict=True):
        assert a.moment == pytest.approx(b.moment, rel=1e-12, abs=1e-10)


@pytest.mark.parametrize("end", [-150.0, -400.0])
@pytest.mark.parametrize("nudge", [0, 1, 2])
def test_a_block_that_rolls_its_contact_off_the_zone_is_named(end, nudge):
    """A moment about a pivot 5 mm up while the block is driven 0.25 mm per increment: in
    stick the block turns about its contact by about 0.25 / 5 = 0.047 rad (measured 0.0466),
    which rolls the contact R* theta = 1.6 mm along the pad (R* = 35 mm), beyond the
    0.48 mm zone: the contact reaches the zone's end pair at the half step's first
    increment, and that truncated answer is refused with the tipping block's message
    whatever the back step's moment and whatever round-off nudge (relative 2.2e-16 on P):
    not a tilt threshold (these paths used to run on at tilts of 0.05-0.29 rad with the
    contact pinned on its end pair, and round-off chose whether a step then converged)."""
    load = 100.0 * (1.0 + nudge * 2.2e-16)
    simulation = scene(rig={"pivot_height": 5.0}, moment=[0.0, 150.0, 150.0, end], load=load)
    with pytest.raises(SolverConvergenceError, match=r"'half': no balance found for the pad "
                       r"block's rotation \(the contact reached the zone's end at x = 0.4847 mm"
                       r".*tilt at -0.0466 rad.*\[load\] moment.*pivot_height"):  # fmt: skip
        run_sliding(simulation, note=None)


@pytest.mark.parametrize(
    ("load", "nudge"),
    [(100.0, 0), pytest.param(100.0, 1, marks=pytest.mark.slow),
     pytest.param(60.0, 0, marks=pytest.mark.slow)],
)  # fmt: skip
def test_a_moment_beyond_the_contacts_reach_is_refused(load, nudge):
    """With the pivot at the first contact (h = 0) the moment is carried by the pressure's
    centre alone, e = -M / P, and a non-negative Hertzian pressure of half-width a over a
    zone reaching r from the first contact carries at most |M| = P (r - a). At 0.9 of it,
    either sign, the slide balances M with the contact inside the zone; at 1.1 the contact
    reaches the zone's end and the step is refused (the BEM pad's bending under Q moves its
    contact 0.01-0.03 mm, measured: 0.97 of it is refused, 0.9 balanced)."""
    a = HALF["gross_sliding_arc.toml"] * math.sqrt(load / 100.0)
    keys = {"rig": {"pivot_height": 0.0}, "contact": {"zone": 2.0}}
    x = scene(load=load, moment=[0.0, 1.0, 1.0, 1.0], **keys).pair.pairing().points[:, 0]
    capacity = load * (0.5 * float(x.max() - x.min()) - a)
    load *= 1.0 + nudge * 2.2e-16
    for sign in (1.0, -1.0):
        m = 0.9 * sign * capacity
        sliding = run_sliding(scene(load=load, moment=[0.0, m, m, m], **keys), note=None)
        for step in sliding.steps[1:]:
            assert step.moment == pytest.approx(m, abs=1e-9) and step.states[[0, -1]].max() == 0
        m = 1.1 * sign * capacity
        with pytest.raises(SolverConvergenceError, match=r"'half': .*the zone's end"):
            run_sliding(scene(load=load, moment=[0.0, m, m, m], **keys), note=None)


def test_the_example_scene_turns_the_block_along_the_arc(tmp_path):
    """examples/gross_sliding_arc_rotating.toml through fretbem run (21 pairs, VTK on):
    summary.json and loops.csv carry M, theta and tilt; M = -k_r tilt, M = h Q - e P with
    the contact ahead of the axis (0.94 to 1.0 of h Q; 0.984 measured at 61 pairs), the
    same slid and back; the same as the scene run from Python."""
    text = (ROOT / "examples" / "gross_sliding_arc_rotating.toml").read_text()
    assert "\npairs = 61" in text
    scene_file = tmp_path / "scene.toml"
    scene_file.write_text(text.replace("\npairs = 61", "\npairs = 21"))
    out = tmp_path / "out"
    assert cli.main(["run", str(scene_file), "--out", str(out), "--no-figures"]) == 0
    steps = {s["step"]: s for s in json.loads((out / "summary.json").read_text())["steps"]}
    k_r = tomllib.loads(text)["rig"]["stiffness_rotation"]
    data = tomllib.loads(scene_file.read_text())
    sliding = run_sliding(build(scene_from_data(data))[0], note=None)
    for name, sign in (("slide", 1.0), ("back", -1.0)):
        step = steps[name]
        assert 0.94 < step["M"] / (H * step["Q"]) < 1.0 and sign * step["M"] > 0
        assert step["tilt"] == pytest.approx(-step["M"] / k_r, rel=1e-9)
        assert step["M"] == pytest.approx(sliding[name].moment, rel=1e-12)
    with open(out / "loops.csv") as handle:
        rows = list(csv.DictReader(handle))
    assert {"M", "theta"} <= set(rows[0]) and len(rows) == 49
    assert (out / "history.pvd").exists()


def _centre(sliding, k: int) -> float:
    """The pressure's centre of step ``k`` in the pad's axes (mm ahead of its axis)."""
    step, pair = sliding.steps[k], sliding.pairs[k]
    points = pad_rotation.in_pad_axes(pair, pair.pairing().points)
    return float(np.sum(points[:, 0] * step.pressure) / np.sum(step.pressure))


@pytest.mark.slow
@pytest.mark.parametrize(
    ("example", "specimen", "radius"),
    [("gross_sliding_arc.toml", None, 35.0),
     ("gross_sliding_arc.toml", {"radius": 140.0, "width": 14.0}, 140.0 * 70.0 / 210.0),
     ("gross_sliding_groove.toml", None, 40.0 * 70.0 / 30.0)],
)  # fmt: skip
def test_a_tilt_moves_the_contact_by_the_effective_radius(example, specimen, radius):
    """In gross slip the tilt rolls the pad about its point at the contact: its centre moves
    -R_p theta, the contact on the line of centres -R* theta in the pad's axes (R* =
    R_p R_s / (R_p + R_s), in a groove R_p R_g / (R_g - R_p)). The pressure's centre with
    springs of 1e6 and 2e5 against the held block's, over the tilt: 0.88 to 0.99 of R*
    (measured; the BEM pad's own compliance: 0.95 on the flat BEM track)."""
    contact = {"zone": 2.0}
    held = run_sliding(scene(example, specimen=specimen, contact=contact), note=None)
    for k_r in (1.0e6, 2.0e5):
        rig = {"stiffness_rotation": k_r}
        turned = run_sliding(scene(example, specimen=specimen, contact=contact, rig=rig),
                             note=None)  # fmt: skip
        shift = (_centre(turned, 2) - _centre(held, 2)) / turned.steps[2].tilt
        assert 0.85 < -shift / radius < 1.0
