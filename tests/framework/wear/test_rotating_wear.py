"""A wear history whose pad block rotates: its M, theta and tilt in wear.csv,
wear_summary.csv and wear.json, as the plain run reports them in summary.json; a wear
cycle whose moment rolls the contact off the zone is refused as a plain run's is."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest
import tomllib

from fretbem.app import cli
from fretbem.contact.law import ContactState
from fretbem.scenes.builder import build
from fretbem.scenes.file import scene_from_data
from fretbem.simulation import BlockTippingError
from fretbem.wear import run as wear_run
from fretbem.wear.cycle import simulate_cycle
from fretbem.wear.law import ArchardWear

ROOT = Path(__file__).resolve().parents[3]

SCENE = """
[pad]
radius = 70.0
model = "half-plane"
[specimen]
shape = "flat"
model = "half-plane"
[contact]
friction = 0.3
pairs = 21
[rig]
stiffness_rotation = 2.0e5
pivot_height = 5.0
[load]
steps = ["A", "B", "C", "D", "E"]
P = 100.0
Q = [0.0, 18.0, 0.0, -18.0, 0.0]
increments = 3
[wear]
law = "energy"
pad = 1e-4
specimen = 2e-4
cycles = 3000
output = [500]
"""


def _rows(path):
    with open(path) as handle:
        return list(csv.DictReader(handle))


def _run(tmp_path, scene: str):
    (tmp_path / "scene.toml").write_text(scene)
    out = tmp_path / "out"
    code = cli.main(["run", str(tmp_path / "scene.toml"), "--out", str(out), "--no-figures",
                     "--no-vtk"])  # fmt: skip
    assert code == 0
    return out


@pytest.mark.parametrize("rig", ["stiffness_rotation = 2.0e5", "pivot_height = 5.0"])
def test_wear_files_carry_the_rotating_blocks_moment_and_tilt(tmp_path, rig):
    """With a rotational spring the columns are there and at N = 0 equal summary.json's
    (the same cycle solved from the same pressing); a rig without one writes none."""
    scene = SCENE.replace("stiffness_rotation = 2.0e5\npivot_height = 5.0", rig)
    out = _run(tmp_path, scene)
    rotating = rig.startswith("stiffness_rotation")
    wear, summary = _rows(out / "wear.csv"), _rows(out / "wear_summary.csv")
    units = json.loads((out / "wear.json").read_text())["units"]
    names = {"wear.csv": ("M", "theta", "tilt"),
             "wear_summary.csv": ("M_amplitude", "theta_amplitude", "tilt_amplitude")}  # fmt: skip
    for file, rows in (("wear.csv", wear), ("wear_summary.csv", summary)):
        for name in names[file]:
            assert (name in rows[0]) == rotating and (name in units[file]) == rotating
    if not rotating:
        return
    assert (
        units["wear.csv"]["M"]["unit"] == "N mm/mm" and units["wear.csv"]["tilt"]["unit"] == "rad"
    )
    steps = {s["step"]: s for s in json.loads((out / "summary.json").read_text())["steps"]}
    first = {r["step"]: r for r in wear if int(r["N"]) == 0}
    assert sorted(first) == ["B", "C", "D", "E"]
    for name, row in first.items():
        for key in ("M", "theta", "tilt"):
            assert float(row[key]) == pytest.approx(steps[name][key], rel=1e-9, abs=1e-15)
    assert abs(float(first["B"]["tilt"])) > 1e-7  # Q below the pivot turns the block
    for line in summary:  # the amplitudes: half the ranges over the cycle's step ends
        at = [r for r in wear if r["N"] == line["N"]]
        for key in ("M", "theta", "tilt"):
            values = [float(r[key]) for r in at]
            assert float(line[f"{key}_amplitude"]) == pytest.approx(0.5 * np.ptp(values), rel=1e-12)
    # the spring's law at every N and step: theta = tilt + M / k_r, the actuator held at 0
    for r in wear:
        assert float(r["theta"]) == pytest.approx(0.0, abs=1e-15)
        assert float(r["tilt"]) == pytest.approx(-float(r["M"]) / 2.0e5, rel=1e-9, abs=1e-15)
    assert {int(r["N"]) for r in wear} == {0, 500, 3000}


def test_a_wear_cycle_refuses_a_contact_the_moment_rolls_off_the_zone():
    """A wear cycle steps its increments as a plain run does (Simulation.step), so a
    rotating block whose contact the moment rolls onto the zone's end mid-step is refused
    there with the tipping block's message (the drag of
    tests/validation/test_sliding_rotating.py in a zone reaching 1.38 mm), and the wear
    run does not retry it with finer increments: the moment has no answer in that zone."""
    data = tomllib.loads((ROOT / "examples" / "gross_sliding.toml").read_text())
    data.pop("stress", None)
    data["contact"].update(pairs=41, zone=3.0, sliding=False)
    data["load"].update(
        steps=["press", "drag"], P=100.0, delta=[0.0, 1.0], increments=[1, 2],
        moment=[0.0, 300.0],
    )  # fmt: skip
    simulation = build(scene_from_data(data))[0]
    problem = simulation.prepare()
    laws = {"upper": ArchardWear(1e-8), "lower": ArchardWear(1e-8)}
    pressed = simulation.step(problem, ContactState.initial(problem), simulation.steps[0])[0]
    with pytest.raises(BlockTippingError, match=r"'drag': .*the zone's end at x = 1.384 mm"):
        simulate_cycle(simulation, problem, pressed, simulation.steps[1:], laws)

    class Contact:  # the wear run's contact: each cycle solved afresh
        calls = 0

        def cycle(self, state, steps, laws, profile):
            Contact.calls += 1
            return simulate_cycle(simulation, problem, state, steps, laws)

    wear = type("Wear", (), {"cycle_steps": simulation.steps[1:], "laws": laws})()
    with pytest.raises(BlockTippingError):
        wear_run._cycle(Contact(), pressed, wear, 1, None)
    assert Contact.calls == 1
