"""Finite sliding with a pad block that rotates: a rig's rotational spring, a moment or an
actuator's rotation, while the pad slides several contact widths along a flat.

The block's rotation is about the rig's pivot, a point of the pad found once where it
starts (in its own axes), so it moves with the pad. Checked: without re-pairing the sliding
loop solves the fixed run's problem; in full sliding each step equals the same bodies
solved in place where that step's pairs were (pressed, then driven into gross slip);
the block's moment balances the contact tractions' moment about the pivot (integrated
independently over the pad's face); and the closed forms of a cylinder on a half-plane:
a tilt theta moves the contact's centre by -R theta, so with a spring k_r (M = -k_r theta)
M = h Q / (1 + P R / k_r), and under a given moment theta = -(h Q - M) / (P R). Along an
arc: tests/validation/test_sliding_rotating_arc.py.
Tolerances: measured values (in the comments) plus a margin.
"""

from __future__ import annotations

import copy
import csv
import json
from pathlib import Path

import attrs
import numpy as np
import pytest
import tomllib

from fretbem.app import cli
from fretbem.contact import rotation as pad_rotation
from fretbem.contact.control import Rig
from fretbem.errors import InputError
from fretbem.scenes.builder import build
from fretbem.scenes.file import scene_from_data
from fretbem.simulation import LoadStep, Simulation, run
from fretbem.sliding import run_sliding
from fretbem.solvers.newton import SolverConvergenceError
from fretbem.testing.sliding import traction_moment

ROOT = Path(__file__).resolve().parents[2]
F, R, H = 0.3, 70.0, 10.0  # friction, pad radius (mm), pivot height of a half-plane pad (mm)


def scene(
    example: str = "gross_sliding.toml",
    *,
    pairs: int = 41,
    load: float = 100.0,
    a: float = 0.465,
    rig=None,
    moment=None,
    rotation=None,
    zone=None,
) -> Simulation:
    """``examples/<example>`` pressed by ``load``, slid 3 a and 6 a and back, with the
    block's rotation given by ``rig`` ([rig] keys), ``moment`` or ``rotation`` per step;
    five moments: a "turn" step before "back" turns the moment with the block driven 0.1 mm
    back (``zone``: [contact] zone)."""
    data = tomllib.loads((ROOT / "examples" / example).read_text())
    data.pop("stress", None)
    data["contact"]["pairs"] = pairs
    if zone is not None:
        data["contact"]["zone"] = zone
    turn = moment is not None and len(moment) == 5
    data["load"].update(
        steps=["press", "half", "slide", *(["turn"] if turn else []), "back"],
        P=load,
        delta=[0.0, 3 * a, 6 * a, *([6 * a - 0.1] if turn else []), 0.0],
        increments=[1, 6, 6, *([2] if turn else []), 12],
    )
    if rig is not None:
        data["rig"] = dict(rig)
    if moment is not None:
        data["load"]["moment"] = list(moment)
    if rotation is not None:
        data["load"]["rotation"] = list(rotation)
    return build(scene_from_data(copy.deepcopy(data)))[0]  # fmt: skip


def twins_of(simulation: Simulation, sliding) -> list:
    """Each step's fixed twin: the same bodies and rig paired where that step's pairs were,
    pressed and driven into gross slip the same way (0.1 mm further), with the step's
    moment or rotation."""
    twins = []
    for load, step, pair, offset, position in zip(
        simulation.steps, sliding.steps, sliding.pairs, sliding.offsets, sliding.positions,
        strict=True,
    ):  # fmt: skip
        placed = attrs.evolve(simulation.pair, offset=pair.offset)
        turn = {"moment": load.moment, "rotation": load.rotation}
        steps = (LoadStep("press", step.normal, delta=0.0, **turn),)
        sign = np.sign(step.tangential) if abs(step.tangential) > 0.5 * F * step.normal else 0
        if sign:
            delta = position - offset + 0.1 * sign
            steps += (LoadStep("slide", step.normal, delta=delta, increments=2, **turn),)
        twin = attrs.evolve(simulation, pair=placed, steps=steps, reference=None)
        twins.append(run(twin).steps[-1])
    return twins


#: scene keyword arguments per case: the rig's spring at two loads, a moment, an
#: actuator's rotation held rigidly and through the spring
CASES = {
    "spring": {"rig": {"stiffness_rotation": 2.0e5}},
    "spring-60": {"rig": {"stiffness_rotation": 1.0e5}, "load": 60.0, "a": 0.360},
    "moment": {"moment": [0.0, 280.0, 280.0, -280.0, -280.0], "zone": 6.0, "pairs": 101},
    "rotation": {"rotation": [0.0, -2e-3, -2e-3, 2e-3]},
    "rotation-spring": {"rig": {"stiffness_rotation": 2.0e5},
                        "rotation": [0.0, -1e-3, -1e-3, 1e-3]},
}  # fmt: skip


@pytest.fixture(scope="module", params=sorted(CASES))
def slid(request):
    simulation = scene(**CASES[request.param])
    sliding = run_sliding(simulation, note=None)
    return request.param, simulation, sliding, twins_of(simulation, sliding)


def test_each_step_is_the_pad_solved_where_it_slid(slid):
    """In full sliding the state at a step's end is the same whatever the path: the slid
    pad equals its twin (measured 2.2e-14 p0, M 3e-16 h f P, tilt 5e-18 rad)."""
    name, _, sliding, twins = slid
    a = CASES[name].get("a", 0.465)  # slid 6 a: more than five contact half-widths
    assert sliding.repairings >= 10 and abs(sliding.offsets[2]) > 5 * a
    p0 = max(float(step.pressure.max()) for step in sliding.steps)
    for step, twin in zip(sliding.steps, twins, strict=True):
        scale = H * F * step.normal
        assert np.max(np.abs(step.pressure - twin.pressure)) < 1e-12 * p0
        assert np.max(np.abs(step.shear - twin.shear)) < 1e-12 * p0
        assert abs(step.moment - twin.moment) < 1e-12 * scale
        assert abs(step.tilt - twin.tilt) < 1e-15


def test_the_block_turns_as_the_closed_forms_say(slid):
    """q = f p and Q = f P while sliding; M balances the contact tractions' moment about the
    pivot (measured 4e-6 to 8e-6 of h f P); a tilt theta moves the cylinder's contact by
    -R theta, so theta = -(h Q - M) / (P R) (measured within 1.6e-3 of theta: the pressure's
    centre on 41 pairs), which with a spring gives M = h Q / (1 + P R / k_r) (6e-5 of h f P)
    and with a rigid actuator's rotation the tilt given; through a spring tilt = theta_a -
    M / k_r."""
    name, simulation, sliding, _ = slid
    k_r, pivot = simulation.rig.rotational, simulation.block_pivot()
    for load, step, pair in zip(simulation.steps, sliding.steps, sliding.pairs, strict=True):
        if step.name == "press":
            assert abs(step.moment) < 1e-9 and abs(step.tilt) < 1e-15
            continue
        P, Q, M, tilt = step.normal, step.tangential, step.moment, step.tilt
        scale = H * F * P
        touching = step.pressure > 0
        assert abs(abs(Q) - F * P) < 1e-9 * P
        assert np.max(np.abs(np.abs(step.shear) - F * step.pressure)[touching]) < 1e-9 * P
        assert abs(M - traction_moment(step, pair, pivot)[0]) < 3e-5 * scale
        assert abs(tilt + (H * Q - M) / (P * R)) < 3e-3 * abs(tilt)
        if name.startswith("spring"):
            assert abs(M - H * Q / (1 + P * R / k_r)) < 2e-4 * scale
        elif name == "moment":
            assert M == pytest.approx(load.moment, abs=1e-9)
        elif name == "rotation":
            assert tilt == pytest.approx(load.rotation, abs=1e-15)
        else:
            assert tilt == pytest.approx(load.rotation - M / k_r, rel=1e-12)


@pytest.mark.parametrize(
    ("load", "zone", "fractions", "nudges"),
    [(100.0, 6.0, (0.95, 1.05), 1),
     pytest.param(100.0, 6.0, (0.98, 1.02), 3, marks=pytest.mark.slow),
     pytest.param(60.0, 8.5, (0.98, 1.02), 2, marks=pytest.mark.slow),
     pytest.param(140.0, 5.0, (0.98, 1.02), 2, marks=pytest.mark.slow)],
)  # fmt: skip
def test_a_moment_beyond_the_contacts_capacity_tips_the_block(load, zone, fractions, nudges):
    """Slid in gross slip under M = 2.8 P N mm/mm, then M turned to M_1 while the block is
    driven 0.1 mm back (Q = -f P): the pressure's centre must be e = (h Q - M_1) / P, and a
    Hertzian contact of half-width a inside a zone reaching r carries at most
    |M_1| = h f P + P (r - a). Below it (0.95, 0.98 of it) the turn balances with
    theta = -(h Q - M_1) / (P R) and the contact inside the zone; beyond it (1.02, 1.05) the
    contact reaches the zone's end and the turn is refused with the tipping block's
    message: at three loads and under round-off nudges of P (relative 2.2e-16), the same
    answer each time."""
    a = 0.465 * np.sqrt(load / 100.0)
    keys = {"a": a, "zone": zone, "pairs": 101}
    m = 2.8 * load
    reach = float(np.max(scene(load=load, moment=[0.0, m, m, 0.0, 0.0], **keys)
                         .pair.pairing().points[:, 0]))  # fmt: skip
    capacity = H * F * load + load * (reach - a)
    for fraction in fractions:
        for nudge in range(nudges):
            P = load * (1.0 + nudge * 2.2e-16)
            turned = -fraction * capacity
            simulation = scene(load=P, moment=[0.0, m, m, turned, turned], **keys)
            if fraction > 1.0:
                with pytest.raises(SolverConvergenceError, match=r"'turn': .*the zone's end"):
                    run_sliding(simulation, note=None)
                continue
            step = run_sliding(simulation, note=None)["turn"]
            assert step.tangential == pytest.approx(-F * P, rel=1e-9)
            assert step.moment == pytest.approx(turned, abs=1e-9)
            assert step.states[[0, -1]].max() == 0
            centre = (H * step.tangential - turned) / P
            assert abs(step.tilt + centre / R) < 1e-2 * abs(step.tilt)  # 5e-3: 16 pairs in contact


def dragged(zone: float) -> Simulation:
    """examples/gross_sliding.toml not sliding (41 pairs, [contact] ``zone``): pressed at
    P = 100, then in two increments driven 1 mm into gross slip while M ramps to h f P, so
    the pressure's centre d = (h Q - M) / P is 1.5 mm after the first increment and 0 at
    the step's end."""
    data = tomllib.loads((ROOT / "examples" / "gross_sliding.toml").read_text())
    data.pop("stress", None)
    data["contact"].update(pairs=41, zone=zone, sliding=False)
    data["load"].update(
        steps=["press", "drag"], P=100.0, delta=[0.0, 1.0], increments=[1, 2],
        moment=[0.0, H * F * 100.0],
    )  # fmt: skip
    return build(scene_from_data(data))[0]


@pytest.mark.parametrize("zone", [3.0, 4.0])
def test_a_plain_run_refuses_a_contact_truncated_mid_step(zone):
    """The drag's first increment needs the contact (half-width 0.465 mm) centred 1.5 mm
    off, beyond a zone reaching 1.38 or 1.84 mm, though at the step's end it is back at the
    centre: run() refuses it at that increment (before, the end pair carried the truncated
    contact and the step's end passed its checks), with the tipping block's message, the
    same as finite sliding's on the same problem, with or without the step-end checks."""
    simulation = dragged(zone)
    with pytest.raises(SolverConvergenceError, match=r"'drag': .*the zone's end") as plain:
        run(simulation)
    with pytest.raises(SolverConvergenceError) as unchecked:
        run(simulation, check=False)
    with pytest.raises(SolverConvergenceError) as slid:
        run_sliding(simulation, every=1e6, note=None)
    assert str(plain.value) == str(unchecked.value) == str(slid.value)


def test_a_plain_run_balances_a_contact_inside_the_zone():
    """The same drag in a zone reaching 2.77 mm balances: after the first increment the
    tilt is theta = -(h Q - M) / (P R) (measured within 4.6e-3 of it: the pressure's centre
    on 41 pairs) with the zone's end pairs apart, and the step ends with the block level."""
    step = run(dragged(6.0))["drag"]
    first = step.increments[0]
    P, Q, M = first.normal, first.tangential, first.moment
    assert Q == pytest.approx(F * P, rel=1e-9) and M == pytest.approx(0.5 * H * F * P)
    assert abs(first.tilt + (H * Q - M) / (P * R)) < 6e-3 * abs(first.tilt)
    assert first.states[[0, -1]].max() == 0 and step.states[[0, -1]].max() == 0
    assert abs(step.tilt) < 1e-5


def test_finite_bodies_slide_with_a_rotating_block():
    """BEM bodies (21 pairs) with a stiff spring: every step equals its twin (measured
    1.8e-13 p0), M balances the tractions within the BEM pad's own equilibrium (2.15e-3 of
    h f P, as without rotation) and the levers M = h Q - e P with e the pressure's centre
    in the pad's axes (the pad's bending under Q moves it beyond -R theta)."""
    simulation = scene("gross_sliding_bem.toml", pairs=21, rig={"stiffness_rotation": 1.0e6})
    sliding = run_sliding(simulation, note=None)
    pivot = simulation.block_pivot()
    p0 = max(float(step.pressure.max()) for step in sliding.steps)
    for step, twin, pair in zip(
        sliding.steps, twins_of(simulation, sliding), sliding.pairs, strict=True
    ):
        scale = pivot[1] * F * step.normal
        assert np.max(np.abs(step.pressure - twin.pressure)) < 1e-11 * p0
        assert abs(step.moment - twin.moment) < 1e-11 * scale
        assert abs(step.moment - traction_moment(step, pair, pivot)[0]) < 3e-3 * scale
        points = pad_rotation.in_pad_axes(pair, pair.pairing().points)
        p = step.pressure
        e = float(np.sum(points[:, 0] * p) / np.sum(p))
        h = pivot[1] - float(np.sum(points[:, 1] * p) / np.sum(p))
        assert abs(step.moment - (h * step.tangential - e * step.normal)) < 3e-3 * scale
        assert step.moment == pytest.approx(-simulation.rig.rotational * step.tilt, rel=1e-9)


def test_without_repairing_the_loop_solves_the_fixed_run():
    """With no re-pairing (every = 1e6 spacings) the sliding loop solves run()'s rotating
    problem on the same pairs: every increment equal to 1e-12."""
    for kwargs in (CASES["spring"], CASES["moment"], CASES["rotation-spring"]):
        simulation = scene(**{"pairs": 21, **kwargs})
        sliding = run_sliding(simulation, every=1e6, note=None)
        assert sliding.repairings == 0
        plain = run(simulation)
        for a, b in zip(plain.steps, sliding.steps, strict=True):
            for x, y in zip(a.increments, b.increments, strict=True):
                assert np.allclose(x.pressure, y.pressure, rtol=0, atol=1e-12 * 150)
                assert x.moment == pytest.approx(y.moment, abs=1e-10)
                assert x.tilt == pytest.approx(y.tilt, abs=1e-16)


def test_the_example_scene_writes_the_blocks_turn(tmp_path):
    """examples/gross_sliding_rotating.toml through fretbem run (31 pairs, VTK on: each
    step's fields on its own pairing with the block's rotation): summary.json and
    loops.csv carry M, theta and tilt, M = h Q / (1 + P R / k_r) slid and back."""
    text = (ROOT / "examples" / "gross_sliding_rotating.toml").read_text()
    assert "\npairs = 61" in text
    scene_file = tmp_path / "scene.toml"
    scene_file.write_text(text.replace("\npairs = 61", "\npairs = 31"))
    data = tomllib.loads(text)
    out = tmp_path / "out"
    assert cli.main(["run", str(scene_file), "--out", str(out), "--no-figures"]) == 0
    steps = {s["step"]: s for s in json.loads((out / "summary.json").read_text())["steps"]}
    k_r = data["rig"]["stiffness_rotation"]
    for name, sign in (("slide", 1.0), ("back", -1.0)):
        expected = sign * H * F * 100.0 / (1 + 100.0 * R / k_r)
        assert abs(steps[name]["M"] - expected) < 4e-4 * H * F * 100.0
        assert steps[name]["tilt"] == pytest.approx(-steps[name]["M"] / k_r, rel=1e-9)
    with open(out / "loops.csv") as handle:
        rows = list(csv.DictReader(handle))
    assert {"M", "theta"} <= set(rows[0]) and len(rows) == 49
    assert (out / "history.pvd").exists()


@pytest.mark.parametrize("bad", [True, "3", np.nan, np.inf, [1.0, 2.0, 3.0], {"x": 1.0}])
def test_a_bad_pivot_is_refused_naming_the_field(bad):
    simulation = scene(pairs=21, **CASES["spring"])
    with pytest.raises(InputError, match=r"Simulation\.pivot .*; give two numbers"):
        attrs.evolve(simulation, pivot=[0.0, bad] if not isinstance(bad, list) else bad)
    pinned = simulation.pinned()
    assert pinned.pivot is not None and np.array_equal(pinned.pivot, simulation.block_pivot())
    assert pinned.pinned() is pinned and attrs.evolve(simulation, rig=Rig()).pinned().pivot is None
