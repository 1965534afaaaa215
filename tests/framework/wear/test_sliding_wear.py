"""Wear with finite sliding: the pairing follows the pad, each face wears at its own points.

A cylinder (R = 70 mm) on a flat, both half-planes, P = 100 N/mm, f = 0.3, the pad's block
driven +-0.2 mm in gross slip (about four contact half-widths): the energy and Archard
volumes equal the summed work to round-off, the energy per cycle is 4 f P delta_s, the
specimen's scar spans the contact plus the stroke while the pad's is the contact's width,
and the worn contact carries P and Q = f P while sliding.
"""

import csv
import json
from pathlib import Path

import attrs
import numpy as np
import pytest

from fretbem.app import cli
from fretbem.scenes.builder import build
from fretbem.scenes.file import scene_from_data
from fretbem.scenes.spec import SceneFileError
from fretbem.sliding import SlidingError
from fretbem.testing.sliding import slip_amplitude
from fretbem.wear.jump import JumpControl
from fretbem.wear.law import JOULE, ArchardWear, EnergyWear, WearInputError
from fretbem.wear.run import WearSimulation, run_wear

P, F, DELTA = 100.0, 0.3, 0.2
ROOT = Path(__file__).resolve().parents[3]


def _scene(pairs=31, increments=6, models=("half-plane", "half-plane"), **contact):
    data = {
        "pad": {"shape": "cylinder", "radius": 70.0, "width": 6.5, "height": 16.25,
                "model": models[0]},
        "specimen": {"shape": "flat", "length": 20.0, "thickness": 10.0, "model": models[1]},
        "material": {"E": 73400.0, "nu": 0.33},
        "contact": {"friction": F, "pairs": pairs, "pairing": "node-to-segment",
                    "sliding": True, "zone": 2.0, **contact},
        "load": {"steps": ["press", "A", "B", "C"], "P": P, "delta": [0.0, DELTA, -DELTA, 0.0],
                 "increments": [1, increments, 2 * increments, increments]},
    }  # fmt: skip
    return build(scene_from_data(data))[0]


@pytest.fixture(scope="module")
def energy_run():
    laws = {"upper": EnergyWear(1e-5), "lower": EnergyWear(2e-5)}
    simulation = _scene()
    wear = WearSimulation(simulation, laws, 400, outputs=[100], sliding=True)
    return simulation, laws, run_wear(wear)


def test_energy_volume_is_alpha_times_the_dissipated_energy(energy_run):
    simulation, laws, result = energy_run
    final = result.final
    for body, law in laws.items():
        assert final.profile.volume(body) == pytest.approx(law.alpha / JOULE * final.energy,
                                                           rel=1e-12)  # fmt: skip
    # the energy is the friction work of gross sliding: 4 f P delta_s a cycle (0.07 %)
    per_cycle = final.energy / 400
    assert per_cycle == pytest.approx(4 * F * P * slip_amplitude(simulation), rel=2e-3)


def test_archard_volume_is_k_times_the_summed_p_ds():
    laws = {"upper": ArchardWear(1e-9), "lower": ArchardWear(3e-9)}
    result = run_wear(WearSimulation(_scene(pairs=21), laws, 100, sliding=True))
    final = result.final
    assert final.work > 0
    for body, law in laws.items():
        assert final.profile.volume(body) == pytest.approx(law.k * final.work, rel=1e-12)


def test_the_specimen_scar_spans_the_contact_plus_the_stroke(energy_run):
    """Specimen: 2 a + 2 delta_s, between the unworn and the worn contact's width plus the
    stroke (measured 1.331 mm against 0.963 + 0.396 = 1.359 mm, 2 % under at the 1 %
    depth level); pad: its contact's width, to a pair spacing (0.898 against 0.963 mm);
    the peak pressure falls (136.8, 133.9, 126.3 MPa at N = 0, 100, 400)."""
    simulation, _, result = energy_run
    final, first = result.final, result.snapshots[0]
    amplitude = slip_amplitude(simulation)

    def width(snap, step=0):
        touching = snap.pair_x(step)[snap.pressure[step] > 0]
        return touching.max() - touching.min()

    scar = final.profile.scar_width("lower")
    assert width(first) + 2 * amplitude < scar
    assert scar == pytest.approx(width(final) + 2 * amplitude, rel=0.03)
    spacing = 1.2 * float(np.median(np.diff(final.profile.upper_x)))  # 0.064 mm
    assert abs(final.profile.scar_width("upper") - width(final)) < spacing
    peaks = [float(s.pressure.max()) for s in result.snapshots]
    assert np.all(np.diff(peaks) < 0)


def test_the_worn_contact_carries_p_and_f_p_while_sliding(energy_run):
    _, _, result = energy_run
    worn = result.at(400)
    for step in worn.steps:
        assert step.normal == pytest.approx(P, rel=1e-9)
    for name, sign in (("A", 1.0), ("B", -1.0)):
        step = next(s for s in worn.steps if s.name == name)
        assert step.tangential == pytest.approx(sign * F * P, rel=1e-9)


NODE_TO_NODE = {
    "pad": {"radius": 70.0, "model": "half-plane"},
    "specimen": {"shape": "flat", "model": "half-plane"},
    "material": {"E": 73400.0, "nu": 0.33},
    "contact": {"friction": F, "pairs": 21},
    "load": {"steps": ["press", "A"], "P": P, "Q": [0.0, 10.0]},
}


def test_wear_refuses_node_to_node_pairs_and_implicit_jumps():
    """Wear with sliding re-pairs by projection: node-to-node pairs are refused, and so are
    implicit jumps and pairs on specimen nodes the pad does not face; finite ``bem``
    bodies are taken (below)."""
    laws = {"upper": EnergyWear(1e-5), "lower": EnergyWear(1e-5)}
    nodes = build(scene_from_data(NODE_TO_NODE))[0]
    with pytest.raises(SlidingError, match="re-pairs the faces by projection"):
        run_wear(WearSimulation(nodes, laws, 10, sliding=True))
    implicit = JumpControl(scheme="implicit")
    with pytest.raises(WearInputError, match="'implicit' is not available with finite"):
        WearSimulation(_scene(pairs=21), laws, 10, sliding=True, control=implicit)
    # pairs on the specimen's nodes, most of them beyond the pad: refused, not NaN depths
    simulation = _scene(pairs=21, models=("bem", "bem"))
    pair = attrs.evolve(simulation.pair, slave="lower", uncovered="open")
    simulation = attrs.evolve(simulation, pair=pair)
    with pytest.raises(SlidingError, match=r"node of the specimen.*slave='upper'"):
        run_wear(WearSimulation(simulation, laws, 10, sliding=True))


FINITE = [
    (("bem", "bem"), "nurbs"),
    (("bem", "bem"), "lagrange2"),
    (("bem", "half-plane"), "nurbs"),
    (("half-plane", "bem"), "lagrange2"),
]


@pytest.mark.parametrize(("models", "basis"), FINITE)
def test_on_finite_bodies_the_volumes_are_the_closed_forms(models, basis):
    """``bem`` bodies (and one bem body on a half-plane), the pad wearing by the energy law
    and the specimen by Archard's: V_pad = alpha E_d and V_specimen = k sum(w p |ds|) to
    round-off; E_d a cycle is 4 f P delta_s with the bodies' own delta_s (a finite pad's
    block runs 0.026 mm ahead of its face under Q = f P; measured 0.022 to 0.057 %, both
    families)."""
    laws = {"upper": EnergyWear(1e-5), "lower": ArchardWear(3e-9)}
    simulation = _scene(pairs=21, models=models, basis=basis)
    final = run_wear(WearSimulation(simulation, laws, 100, sliding=True)).final
    assert final.work > 0
    assert final.profile.volume("upper") == pytest.approx(1e-5 / JOULE * final.energy, rel=1e-12)
    assert final.profile.volume("lower") == pytest.approx(3e-9 * final.work, rel=1e-12)
    per_cycle = final.energy / 100
    assert per_cycle == pytest.approx(4 * F * P * slip_amplitude(simulation), rel=2e-3)


@pytest.fixture(scope="module")
def bem_run():
    laws = {"upper": EnergyWear(1e-5), "lower": EnergyWear(2e-5)}
    simulation = _scene(models=("bem", "bem"))
    return simulation, run_wear(WearSimulation(simulation, laws, 400, sliding=True))


def test_the_worn_bem_contact_carries_p_and_f_p_while_sliding(bem_run):
    """The worn faces of finite bodies, slid again: P, q = f p at every pair in contact and
    Q = f P from the tractions to round-off, at the block within the BEM block's
    equilibrium (measured 0.99961)."""
    _, result = bem_run
    worn = result.at(400)
    assert np.ptp(result.final.profile.lower) > 0
    for step in worn.steps:
        assert step.normal == pytest.approx(P, rel=1e-9)
    for name, sign in (("A", 1.0), ("B", -1.0)):
        step = next(s for s in worn.steps if s.name == name)
        touching = step.pressure > 0
        assert np.max(np.abs(np.abs(step.shear[touching]) - F * step.pressure[touching])) < 1e-9
        assert step.resultant[1] == pytest.approx(sign * F * step.resultant[0], rel=1e-9)
        assert step.tangential == pytest.approx(sign * F * P, rel=5e-4)


def test_the_bem_pad_tilts_its_scars_wider(bem_run):
    """On the reference bodies the pad bends under Q and its tilted cylinder touches
    0.134 mm ahead of its face (tests/validation/test_sliding_bem.py), each way: the pad's
    scar is its contact's width plus about twice that (measured 1.155 mm against 1.231,
    to the pad's pair spacing, 0.064 mm; 0.898 mm on half-planes), and the specimen's the
    contact plus the stroke plus the same (1.523 against 1.579 mm; 1.331 mm on
    half-planes); the peak pressure falls as the faces wear."""
    simulation, result = bem_run
    final = result.final
    contact = 2 * 0.4815  # 2 a
    tilt = 0.134
    assert final.profile.scar_width("upper") == pytest.approx(contact + 2 * tilt, abs=0.1)
    stroke = 2 * slip_amplitude(simulation)
    assert final.profile.scar_width("lower") == pytest.approx(contact + stroke + 2 * tilt,
                                                              abs=0.1)  # fmt: skip
    peaks = [float(s.pressure.max()) for s in result.snapshots]
    assert peaks[-1] < peaks[0]


def _arc(example: str, pairs: int = 21, **contact) -> dict:
    """A sliding arc scene's data (a cylinder specimen, or a groove), the pad's block
    driven +-0.2 mm along the arc and back."""
    import tomllib

    data = tomllib.loads((ROOT / "examples" / example).read_text())
    data["contact"].update(pairs=pairs, zone=2.0, **contact)
    data["load"].update(steps=["press", "A", "B", "C"], delta=[0.0, DELTA, -DELTA, 0.0],
                        increments=[1, 6, 12, 6])  # fmt: skip
    return data


@pytest.mark.parametrize(
    ("example", "basis", "measured"),
    [("gross_sliding_arc.toml", "nurbs", 1.9e-4), ("gross_sliding_arc.toml", "lagrange2", 5.8e-4),
     ("gross_sliding_groove.toml", "nurbs", -1.04e-3),
     ("gross_sliding_groove.toml", "lagrange2", -1.73e-3)],
)  # fmt: skip
def test_along_an_arc_the_volumes_are_the_closed_forms(example, basis, measured):
    """Wear along a convex cylinder specimen (R 70 under the R 70 pad) and in a concave
    groove (R 70 under an R 40 pad), bem bodies, each pair in the arc's own frame: the pad
    by the energy law, the specimen by Archard's, V_pad = alpha E_d and V_specimen =
    k sum(w p |ds|) to round-off; E_d a cycle is 4 f P delta_s with the bodies' own
    delta_s (the centre pair's slide; measured 0.019 / 0.058 % on the cylinder, nurbs /
    lagrange2, -0.10 / -0.17 % in the conforming groove, whose contact is wider: the local
    normals tilt part of the pressure off P); the specimen's scar wider than the pad's by
    about the stroke (0.19 to 0.36 mm against 0.34: the pad's is counted on its 21 nodes)."""
    laws = {"upper": EnergyWear(1e-5), "lower": ArchardWear(3e-9)}
    simulation = build(scene_from_data(_arc(example, basis=basis)))[0]
    final = run_wear(WearSimulation(simulation, laws, 50, sliding=True)).final
    assert final.work > 0
    assert final.profile.volume("upper") == pytest.approx(1e-5 / JOULE * final.energy, rel=1e-12)
    assert final.profile.volume("lower") == pytest.approx(3e-9 * final.work, rel=1e-12)
    per_cycle = final.energy / 50 / (4 * F * P * slip_amplitude(simulation))
    assert per_cycle - 1.0 == pytest.approx(measured, abs=2e-4)
    stroke = 2 * slip_amplitude(simulation)
    scars = final.profile.scar_width("lower") - final.profile.scar_width("upper")
    assert 0.5 * stroke < scars < 1.2 * stroke


def test_wear_along_an_arc_refuses_half_plane_bodies_when_the_scene_is_read():
    """[wear] on a sliding arc: the arc refuses a half-plane body (its surface cannot turn
    with the pad) naming the key and the fix, before any run."""
    data = _arc("gross_sliding_arc.toml")
    data["pad"]["model"] = "half-plane"
    data["wear"] = {"law": "energy", "pad": 1e-5, "specimen": 1e-5, "cycles": 10}
    with pytest.raises(SceneFileError, match=r"\[pad\] model = 'half-plane'.*model = 'bem'"):
        build(scene_from_data(data))


def test_the_arc_example_scene_runs_and_writes_the_wear_files(tmp_path):
    """examples/fretting_wear_sliding_arc.toml through ``fretbem run`` (fewer cycles and
    pairs): the volumes alpha E_d, the specimen's grid in arc length over the track, p where
    the pad stands at the cycle's first step's end (the block at +0.2 mm)."""
    text = (ROOT / "examples" / "fretting_wear_sliding_arc.toml").read_text()
    text = text.replace("cycles = 400", "cycles = 20").replace("output = [100, 200]", "")
    text = text.replace("pairs = 41", "pairs = 21")
    (tmp_path / "scene.toml").write_text(text)
    out = tmp_path / "out"
    assert cli.main(["run", str(tmp_path / "scene.toml"), "--out", str(out), "--quiet"]) == 0
    rows = list(csv.DictReader(open(out / "wear_summary.csv")))
    assert [int(r["N"]) for r in rows] == [0, 20]
    final = rows[-1]
    for body, alpha in (("pad", 1e-5), ("specimen", 2e-5)):
        assert float(final[f"volume_{body}"]) == pytest.approx(
            alpha / JOULE * float(final["energy"]), rel=1e-12
        )
    assert float(final["scar_width_specimen"]) > float(final["scar_width_pad"]) + 0.1
    wear = list(csv.DictReader(open(out / "wear.csv")))
    x = np.array([float(r["x"]) for r in wear if r["N"] == "20" and r["step"] == "A"])
    p = np.array([float(r["p"]) for r in wear if r["N"] == "20" and r["step"] == "A"])
    assert x.min() < -0.8 and x.max() > 0.8  # the track, +-0.85 mm of arc
    assert np.allclose(np.diff(x), x[1] - x[0], rtol=1e-9, atol=0)  # uniform in arc length
    assert p[x < -0.3].max() == 0.0 and p.max() > 150  # the pad ahead: p there only
    face = (out / "vtk" / "wear_N20_specimen.vtp").read_text()
    assert "wear_depth" in face and 'Name="p"' in face


@pytest.mark.parametrize("example", ["fretting_wear_sliding", "fretting_wear_sliding_bem"])
def test_the_example_scene_runs_with_sliding_and_writes_the_wear_files(tmp_path, example):
    """examples/fretting_wear_sliding.toml (half-planes) and its bem twin through ``fretbem
    run`` (fewer cycles): the files on the track grid, the volumes alpha E_d, the
    specimen's scar the wider."""
    text = (ROOT / "examples" / f"{example}.toml").read_text()
    text = text.replace("cycles = 2000", "cycles = 20").replace("output = [500, 1000]", "")
    text = text.replace("pairs = 61", "pairs = 31").replace("[1, 10, 20]", "[1, 5, 10]")
    (tmp_path / "scene.toml").write_text(text)
    out = tmp_path / "out"
    assert cli.main(["run", str(tmp_path / "scene.toml"), "--out", str(out)]) == 0
    rows = list(csv.DictReader(open(out / "wear_summary.csv")))
    assert [int(r["N"]) for r in rows] == [0, 20]
    final = rows[-1]
    for body in ("pad", "specimen"):
        assert float(final[f"volume_{body}"]) == pytest.approx(
            1.775e-4 / JOULE * float(final["energy"]), rel=1e-12
        )
    assert float(final["scar_width_specimen"]) > float(final["scar_width_pad"]) + 0.1
    wear = list(csv.DictReader(open(out / "wear.csv")))
    x = np.array([float(r["x"]) for r in wear if r["N"] == "20" and r["step"] == "B"])
    p = np.array([float(r["p"]) for r in wear if r["N"] == "20" and r["step"] == "B"])
    assert x.min() < -1.0 and x.max() > 1.0  # the track grid, not the pad's pairs
    assert p[x > 0.8].max() == 0.0 and p.max() > 300  # the pad at +0.1 mm: p there only
    assert json.loads((out / "wear.json").read_text())["settings"]["sliding"] is True
    for name in ("wear_profiles.png", "wear_pressure.png", "wear_evolution.png", "wear.pvd"):
        assert (out / name).exists()
    face = (out / "vtk" / "wear_N20_specimen.vtp").read_text()
    assert "wear_depth" in face and 'Name="p"' in face


def test_the_worn_bem_faces_are_assessed_from_the_scene_file(tmp_path):
    """[wear] assess with sliding on bem bodies: the stresses re-run with sliding on the
    worn faces at each assessed N, written under wear_N<N>/; the worn line differs."""
    text = (ROOT / "examples" / "fretting_wear_sliding_bem.toml").read_text()
    text = text.replace("cycles = 2000", "cycles = 20").replace("output = [500, 1000]", "")
    text = text.replace("pairs = 61", "pairs = 21").replace("[1, 10, 20]", "[1, 4, 8]")
    text += '\nassess = [0, 20]\n\n[stress]\nbody = "lower"\n\n[[stress.line]]\nx = -0.3\n'
    text += "depth = 0.5\n"
    (tmp_path / "scene.toml").write_text(text)
    out = tmp_path / "out"
    args = ["run", str(tmp_path / "scene.toml"), "--out", str(out), "--no-figures", "--no-vtk"]
    assert cli.main([*args, "--quiet"]) == 0
    lines = [np.loadtxt(out / f"wear_N{n}" / "stress_line_0.csv", delimiter=",", skiprows=1,
                        usecols=range(4, 9)) for n in (0, 20)]  # fmt: skip
    assert lines[0].shape == lines[1].shape
    assert 0 < np.max(np.abs(lines[1] - lines[0])) < 0.5 * np.max(np.abs(lines[0]))
