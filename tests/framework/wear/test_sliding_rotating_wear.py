"""Wear with finite sliding and a pad block that rotates (a rig's rotational spring).

A cylinder (R = 70 mm) on a flat, both half-planes, P = 100 N/mm, f = 0.3, the block driven
+-0.2 mm in gross slip, the holder's spring k_r about the pivot 10 mm above the contact:
the volumes are the laws' closed forms of the dissipated energy and the summed work, the
energy per cycle is 4 f P delta_s, the block's M and tilt of the first cycle are the
sliding run's, the worn contact re-solved from pressing turns the block as the cycles did,
and a stiff spring gives the wear of a block that does not rotate. Along an arc (bem
bodies, the pad turning with it) the same closed forms and the same stiff-spring limit.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest
import tomllib

from fretbem.app import cli
from fretbem.scenes.builder import build
from fretbem.scenes.file import scene_from_data
from fretbem.sliding import solve_sliding
from fretbem.testing.sliding import slip_amplitude
from fretbem.wear.law import JOULE, ArchardWear, EnergyWear
from fretbem.wear.run import WearSimulation, run_wear

ROOT = Path(__file__).resolve().parents[3]
P, F, DELTA, H = 100.0, 0.3, 0.2, 10.0
LAWS = {"upper": EnergyWear(1e-5), "lower": EnergyWear(2e-5)}


def _scene(stiffness: float | None = 2.0e5, pairs: int = 21):
    data = {
        "pad": {"shape": "cylinder", "radius": 70.0, "width": 6.5, "height": 16.25,
                "model": "half-plane"},
        "specimen": {"shape": "flat", "length": 20.0, "thickness": 10.0, "model": "half-plane"},
        "material": {"E": 73400.0, "nu": 0.33},
        "contact": {"friction": F, "pairs": pairs, "pairing": "node-to-segment",
                    "sliding": True, "zone": 2.0},
        "load": {"steps": ["press", "A", "B", "C"], "P": P, "delta": [0.0, DELTA, -DELTA, 0.0],
                 "increments": [1, 6, 12, 6]},
    }  # fmt: skip
    if stiffness is not None:
        data["rig"] = {"stiffness_rotation": stiffness}
    return build(scene_from_data(data))[0]


@pytest.fixture(scope="module")
def rotating():
    simulation = _scene()
    return simulation, run_wear(WearSimulation(simulation, LAWS, 400, outputs=[200],
                                               sliding=True))  # fmt: skip


def test_the_volumes_are_the_closed_forms_of_energy_and_work(rotating):
    """V = alpha E_d per body to round-off; E_d per cycle = 4 f P delta_s, delta_s the
    centre pair's slip amplitude of the same rotating sliding run (measured 0.03 %)."""
    simulation, result = rotating
    final = result.final
    for body, law in LAWS.items():
        assert final.profile.volume(body) == pytest.approx(law.alpha / JOULE * final.energy,
                                                           rel=1e-12)  # fmt: skip
    assert final.energy / 400 == pytest.approx(4 * F * P * slip_amplitude(simulation), rel=2e-3)
    archard = {"upper": ArchardWear(1e-9), "lower": ArchardWear(3e-9)}
    worked = run_wear(WearSimulation(simulation, archard, 50, sliding=True)).final
    for body, law in archard.items():
        assert worked.profile.volume(body) == pytest.approx(law.k * worked.work, rel=1e-12)


def test_the_block_turns_in_the_cycles_as_in_the_sliding_run(rotating):
    """At N = 0 the cycle's M and tilt per step are the sliding run's within the
    re-pairing's resolution (the wear track re-pairs on its own grid of slides: measured
    6e-6); the unworn cylinder in gross slip has M = h Q / (1 + P R / k_r) (measured 1.6e-4
    of h f P on 21 pairs) and tilt = -M / k_r; the worn contact re-solved from pressing
    (``at``) turns the block as the cycles did (M within 8.9e-4, as its pressure within
    2 % of p0 with or without rotation: it re-registers the worn faces from the start)."""
    simulation, result = rotating
    first, last = result.snapshots[0], result.final
    steps = solve_sliding(simulation, say=lambda _: None).steps[1:]
    k_r = simulation.rig.rotational
    for k, step in enumerate(steps):
        assert first.moment[k] == pytest.approx(step.moment, rel=3e-5)
        assert first.tilt[k] == pytest.approx(step.tilt, rel=3e-5)
    for k, sign in enumerate((1.0, -1.0, 1.0)):
        expected = sign * H * F * P / (1 + P * 70.0 / k_r)
        assert abs(first.moment[k] - expected) < 4e-4 * H * F * P
    for snapshot in (first, last):
        assert np.allclose(snapshot.tilt, -snapshot.moment / k_r, rtol=1e-12, atol=0)
    again = result.at(last.cycles).steps[1:]
    for k, step in enumerate(again):
        assert step.moment == pytest.approx(last.moment[k], rel=2e-3)
        assert step.tilt == pytest.approx(-step.moment / k_r, rel=1e-12)


def test_a_stiff_spring_wears_as_a_block_that_does_not_turn():
    """k_r = 1e12: the tilt is ~1e-9 rad and the worn depths equal the non-rotating
    block's within 1e-6 of the largest (measured 2e-8)."""
    held = run_wear(WearSimulation(_scene(None), LAWS, 200, sliding=True)).final.profile
    stiff = run_wear(WearSimulation(_scene(1e12), LAWS, 200, sliding=True)).final.profile
    for body in ("upper", "lower"):
        a, b = held.depth(body), stiff.depth(body)
        assert np.max(np.abs(a - b)) < 1e-6 * np.max(np.abs(a))


def _arc(stiffness: float | None, cycles: int = 50):
    """examples/fretting_wear_sliding_arc.toml (the pad R 70 on the cylinder R 70, bem
    bodies) at 21 pairs, its block held by a rotational spring ``stiffness`` (None: held)."""
    data = tomllib.loads((ROOT / "examples" / "fretting_wear_sliding_arc.toml").read_text())
    data["contact"]["pairs"] = 21
    data.pop("wear")
    if stiffness is not None:
        data["rig"] = {"stiffness_rotation": stiffness}
    return build(scene_from_data(data))[0]


ARC_LAWS = {"upper": EnergyWear(1e-5), "lower": ArchardWear(3e-9)}


def test_along_an_arc_the_rotating_block_wears_by_the_closed_forms():
    """Along the arc (the pad turning with it, each pair in its own frame) with k_r = 1e6:
    V_pad = alpha E_d and V_specimen = k sum(p ds) to round-off, E_d a cycle 4 f P
    delta_s (+0.019 % measured, +0.0009 % with the held block or a 1e12 spring); the first
    cycle's M per step is the sliding run's within the arc's re-pairing resolution (4.5e-3
    measured; a 1e12 spring 3.1e-3: between re-pairings the pad translates, which moves
    its contact along the arc by half as much, and the wear track re-pairs on its own
    grid), and the tilt is -M / k_r."""
    simulation = _arc(1.0e6)
    result = run_wear(WearSimulation(simulation, ARC_LAWS, 50, sliding=True))
    final = result.final
    assert final.profile.volume("upper") == pytest.approx(1e-5 / JOULE * final.energy, rel=1e-12)
    assert final.profile.volume("lower") == pytest.approx(3e-9 * final.work, rel=1e-12)
    per_cycle = final.energy / 50 / (4 * F * P * slip_amplitude(simulation))
    assert per_cycle - 1.0 == pytest.approx(1.9e-4, abs=1e-4)
    first = result.snapshots[0]
    steps = solve_sliding(simulation, say=lambda _: None).steps[1:]
    for k, step in enumerate(steps):
        assert first.moment[k] == pytest.approx(step.moment, rel=6e-3)
        assert abs(first.moment[k]) > 0.9 * 16.25 * F * P  # h Q: the pivot on the pad's top
    for snapshot in (first, final):
        assert np.allclose(snapshot.tilt, -snapshot.moment / 1.0e6, rtol=1e-12, atol=0)


@pytest.mark.slow
def test_along_an_arc_a_stiff_spring_wears_as_a_block_that_does_not_turn():
    """k_r = 1e12 along the arc: the worn depths equal the held block's within 1e-6 of the
    largest (measured 1.3e-7)."""
    held = run_wear(WearSimulation(_arc(None), ARC_LAWS, 50, sliding=True)).final.profile
    stiff = run_wear(WearSimulation(_arc(1e12), ARC_LAWS, 50, sliding=True)).final.profile
    for body in ("upper", "lower"):
        a, b = held.depth(body), stiff.depth(body)
        assert np.max(np.abs(a - b)) < 1e-6 * np.max(np.abs(a))


def test_the_arc_wear_scene_with_a_spring_writes_the_blocks_turn(tmp_path):
    """examples/fretting_wear_sliding_arc.toml with [rig] stiffness_rotation through
    fretbem run (21 pairs, 20 cycles): wear.csv and wear_summary.csv carry M, theta and
    tilt, the tilt is -M / k_r at every N and step, the actuator held at 0, the volumes
    alpha E_d."""
    text = (ROOT / "examples" / "fretting_wear_sliding_arc.toml").read_text()
    text = text.replace("cycles = 400", "cycles = 20").replace("output = [100, 200]", "")
    text = text.replace("pairs = 41", "pairs = 21") + "\n[rig]\nstiffness_rotation = 1.0e6\n"
    (tmp_path / "scene.toml").write_text(text)
    out = tmp_path / "out"
    assert cli.main(["run", str(tmp_path / "scene.toml"), "--out", str(out), "--no-figures",
                     "--no-vtk", "--quiet"]) == 0  # fmt: skip
    with open(out / "wear.csv") as handle:
        wear = list(csv.DictReader(handle))
    with open(out / "wear_summary.csv") as handle:
        summary = list(csv.DictReader(handle))
    assert {"M", "theta", "tilt"} <= set(wear[0]) and "M_amplitude" in summary[0]
    for row in wear:
        assert float(row["theta"]) == pytest.approx(0.0, abs=1e-15)
        assert float(row["tilt"]) == pytest.approx(-float(row["M"]) / 1.0e6, rel=1e-9)
    assert max(abs(float(row["M"])) for row in wear) > 0.9 * 16.25 * F * P  # h Q, h = 16.25
    final = summary[-1]
    for body, alpha in (("pad", 1e-5), ("specimen", 2e-5)):
        assert float(final[f"volume_{body}"]) == pytest.approx(
            alpha / JOULE * float(final["energy"]), rel=1e-12
        )
