"""Finite sliding with pad and specimen discretised apart (``[pad] pairs`` and
``[specimen] pairs``), in both orders of pair counts: the pairs stand on the pad's nodes
whichever face has fewer (they move with the pad and the long track faces them all the
way; the "coarser" rule would put them on the specimen's track, most of which faces no pad),
and ``[specimen] pairs`` counts the candidate zone, as on every scene, the track keeping
that density along the slide. Checked as tests/validation/test_sliding_scene.py checks the
matching faces: Q = +-f P, q = f p at every pair in contact, p against Hertz about where
the pad is (tolerances: measured plus a margin; the pad's own pair count sets the level:
node to node without sliding at 21 pairs 4.67 % of p0, at 41 pairs 6.88 %, at 31 and 61
0.12 and 0.08 %).
"""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import attrs
import numpy as np
import pytest
import tomllib

from fretbem.app.cli import main
from fretbem.contact.law import PairState
from fretbem.contact.node_to_segment import NodeToSegmentPair
from fretbem.pipeline import run_scene
from fretbem.scenes.builder import build, zone_half_width
from fretbem.scenes.file import scene_from_data
from fretbem.sliding import SlidingError, run_sliding
from fretbem.verification.closed_forms import HertzLineContact

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "examples" / "gross_sliding.toml"
P, F = 100.0, 0.3
HERTZ = HertzLineContact.from_bodies(
    load=P, radius_upper=70.0, radius_lower=math.inf,
    E_upper=73400.0, nu_upper=0.33, E_lower=73400.0, nu_lower=0.33,
)  # fmt: skip
P0 = HERTZ.peak_pressure


def _data(pad: int, specimen: int) -> dict:
    data = tomllib.loads(SCENE.read_text())
    data.pop("stress")
    data["pad"]["pairs"], data["specimen"]["pairs"] = pad, specimen
    return data


def _toml(data: dict) -> str:
    lines = []
    for table, keys in data.items():
        lines.append(f"[{table}]")
        lines += [f"{key} = {json.dumps(value)}" for key, value in keys.items()]
    return "\n".join(lines) + "\n"


def _check_steps(steps, pad_nodes: int, tolerance: float) -> None:
    """Every step on the pad's nodes, Coulomb in gross slip both ways, Hertz where the pad is."""
    for step in steps:
        assert step.pair.slave_side() == "upper" and step.x.size == pad_nodes
        offset = float(step.pair.offset[0])
        error = np.max(np.abs(step.pressure - HERTZ.pressure(step.x - offset))) / P0
        assert error < tolerance, (step.name, error)
        normal, tangential = step.resultant
        assert abs(normal - P) < 1e-4 * P
        if step.name == "press":
            continue
        sign = 1.0 if step.name == "slide" else -1.0
        touching = step.pressure > 0
        assert touching.sum() > 10 and set(step.states[touching].tolist()) == {PairState.SLIP}
        assert abs(step.tangential - sign * F * P) < 1e-9 * P
        assert abs(tangential - sign * F * P) < 1e-4 * P
        assert np.max(np.abs(sign * step.shear[touching] - F * step.pressure[touching])) < 1e-9 * P0


@pytest.mark.parametrize(
    ("pad", "specimen", "tolerance"),
    [
        (31, 21, 0.03),  # measured 2.41 % of p0 (press 2.25, slide 1.58, back 2.41)
        (21, 31, 0.055),  # measured 4.73 % (the pad's 21 pairs: 4.67 node to node)
        pytest.param(61, 41, 0.025, marks=pytest.mark.slow),  # measured 1.96 %
        pytest.param(41, 61, 0.075, marks=pytest.mark.slow),  # measured 6.85 % (6.88 n to n)
    ],
)  # fmt: skip
def test_a_scene_file_slides_with_either_face_coarser(tmp_path, pad, specimen, tolerance):
    """``fretbem run`` on examples/gross_sliding.toml with [pad] pairs and [specimen] pairs
    apart, either coarser: it runs (the "no point facing it" refusal is gone), and its
    Python route solves the same steps on the pad's nodes, checked against Coulomb and Hertz."""
    data = _data(pad, specimen)
    path = tmp_path / "faces.toml"
    path.write_text(_toml(data))
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--no-figures", "--no-vtk", "--quiet"]) == 0
    with open(out / "results.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    result = run_scene(scene_from_data(data), say=lambda message: None).result
    for step in result.steps:
        p = np.array([float(row["p"]) for row in rows if row["step"] == step.name])
        assert np.allclose(p, step.pressure, rtol=0, atol=1e-9 * P0)
    _check_steps(result.steps, pad, tolerance)


def test_the_track_keeps_the_zone_density_of_specimen_pairs():
    """[specimen] pairs = 21 counts the zone (19 quadratic elements over 2 zone): the track
    carries that density over (zone + 2.8 mm) either side, not 21 nodes spread over it all;
    the pad keeps its own 31."""
    scene = scene_from_data(_data(31, 21))
    zone = zone_half_width(scene)
    simulation, _ = build(scene)
    track = simulation.pair.lower.contact_face("contact").n_nodes
    assert track == math.ceil(19 * (zone + 2.8) / zone) + 2
    assert simulation.pair.upper.contact_face("contact").n_nodes == 31


def test_run_sliding_stands_the_default_rule_on_the_pad():
    """From Python: a NodeToSegmentPair with the default slave rule ("coarser") on a track
    with fewer nodes than the pad ([specimen] pairs = 11 in the zone: 48 track nodes against
    the pad's 61) slides on the pad's nodes, the same run as slave="upper" to round-off,
    Coulomb exact, Hertz within the coarse track's resolution (3 to 4 elements across the
    contact: measured 16.8 % of p0); a pair set on the specimen's nodes is refused with the
    fix."""
    simulation, _ = build(scene_from_data(_data(61, 11)))
    pair = NodeToSegmentPair(simulation.pair.upper, simulation.pair.lower)
    assert pair.slave_side() == "lower"  # the track is the coarser face
    sliding = run_sliding(attrs.evolve(simulation, pair=pair), note=None)
    _check_steps(sliding.steps, 61, 0.2)
    upper = run_sliding(attrs.evolve(simulation, pair=attrs.evolve(pair, slave="upper")), note=None)
    for one, other in zip(sliding.steps, upper.steps, strict=True):
        assert np.allclose(one.pressure, other.pressure, rtol=0, atol=1e-12 * P0)
        assert np.allclose(one.shear, other.shear, rtol=0, atol=1e-12 * P0)
    on_the_specimen = attrs.evolve(simulation, pair=attrs.evolve(pair, slave="lower"))
    with pytest.raises(SlidingError, match=r"pad's nodes.*slave='upper'"):
        run_sliding(on_the_specimen, note=None)
