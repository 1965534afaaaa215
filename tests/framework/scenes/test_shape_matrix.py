"""Every documented shape and support, for pad and specimen, built and run from a scene file.

The one scene builder builds the reference scene and any scene file alike; this matrix runs
cylinder, rounded-flat and nurbs pads on cylinder, flat and nurbs specimens, both supports,
through ``fretbem run``. A 'nurbs' body given the library shape's own segments must give the
library shape's answer, and the cylinder-on-flat case Hertz's half-width and peak pressure.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from fretbem.app import cli
from fretbem.geometry.shapes import CylinderPad, FlatSpecimen, RoundedFlatPad
from fretbem.scenes.file import load_scene
from fretbem.verification.closed_forms import HertzLineContact

E, NU, P, R = 73400.0, 0.33, 100.0, 70.0


def _segments_toml(table: str, segments) -> str:
    out = []
    for s in segments:
        c = s.curve
        points = ", ".join(f"[{float(x)!r}, {float(y)!r}]" for x, y in c.control_points)
        out.append(
            f"[[{table}.segments]]\ntag = {s.tag!r}\ndegree = {int(c.degree)}\n"
            f"knots = {[float(k) for k in c.knots]}\npoints = [{points}]\n"
            f"weights = {[float(w) for w in c.weights]}\n"
        )
    return "\n".join(out).replace("'", '"')


PADS = {
    "cylinder": f'shape = "cylinder"\nradius = {R}\nwidth = 6.5\nheight = 6.5\n',
    "rounded-flat": 'shape = "rounded-flat"\nflat = 0.3\nedge_radius = 20.0\nwidth = 6.5\n'
    "height = 6.5\n",
}
SPECIMENS = {
    "cylinder": f'shape = "cylinder"\nradius = {R}\nwidth = 6.5\nheight = 6.5\n',
    "flat-ends": 'shape = "flat"\nlength = 12.0\nthickness = 6.0\nsupport = "ends"\n',
    "flat-clamped": 'shape = "flat"\nlength = 12.0\nthickness = 6.0\nsupport = "clamped-bottom"\n',
}
ZONE = 0.6  # mm: inside every pad's face, wider than every contact here


def _scene(tmp_path: Path, pad: str, specimen: str, name: str, pairs: int = 33) -> Path:
    """33 pairs: a rounded-flat face's zone has 3 contact segments (11 pairs each)."""
    text = (
        f"[pad]\n{pad}\n[specimen]\n{specimen}\n[material]\nE = {E}\nnu = {NU}\n\n"
        f"[contact]\nfriction = 0.3\npairs = {pairs}\nzone_width = {ZONE}\n\n"
        f'[load]\nsteps = ["A", "B", "C"]\nP = {P}\nQ = [0.0, 15.0, 0.0]\n'
    )
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    return path


def _run(path: Path, out: Path) -> dict:
    assert cli.main(["run", str(path), "--out", str(out), "--no-figures", "--no-vtk"]) == 0
    return json.loads((out / "summary.json").read_text())


def _pressure(out: Path, step: str = "A"):
    rows = np.genfromtxt(out / "results.csv", delimiter=",", names=True, dtype=None,
                         encoding="utf-8")  # fmt: skip
    rows = rows[rows["step"] == step]
    return rows["x"], rows["p"]


@pytest.mark.parametrize("specimen", list(SPECIMENS))
@pytest.mark.parametrize("pad", list(PADS))
def test_library_shapes_build_and_run(tmp_path, capsys, pad, specimen):
    path = _scene(tmp_path, PADS[pad], SPECIMENS[specimen], "s")
    if (pad, specimen) == ("rounded-flat", "cylinder"):  # faces that do not match node to node
        assert cli.main(["run", str(path), "--out", str(tmp_path / "out")]) == 2
        err = capsys.readouterr().err
        assert "faces node to node only a cylinder pad of the same radius" in err
        return
    summary = _run(path, tmp_path / "out")
    for step in summary["steps"]:  # equilibrium is checked before writing; restated here
        assert step["integral_p"] == pytest.approx(P, rel=1e-3)
    _, p = _pressure(tmp_path / "out")
    assert p.max() > 0 and p[0] == 0 and p[-1] == 0  # the zone's edges are separated


@pytest.mark.parametrize("body", ["pad", "specimen"])
def test_a_nurbs_body_given_the_library_segments_gives_the_library_answer(tmp_path, body):
    zone = ZONE
    if body == "pad":
        segments = CylinderPad(R, 6.5, 6.5).boundary(zone).segments
        pad, specimen = 'shape = "nurbs"\n\n' + _segments_toml("pad", segments), SPECIMENS[
            "flat-clamped"]  # fmt: skip
        library = (PADS["cylinder"], SPECIMENS["flat-clamped"])
    else:
        face = CylinderPad(R, 6.5, 6.5).face(zone)
        segments = FlatSpecimen(12.0, 6.0).boundary(face, zone).segments
        pad = PADS["cylinder"]
        specimen = 'shape = "nurbs"\nsupport = "clamped-bottom"\n\n' + _segments_toml(
            "specimen", segments
        )
        library = (PADS["cylinder"], SPECIMENS["flat-clamped"])
    nurbs = _run(_scene(tmp_path, pad, specimen, "nurbs"), tmp_path / "n")
    shape = _run(_scene(tmp_path, *library, "lib"), tmp_path / "l")
    for a, b in zip(nurbs["steps"], shape["steps"], strict=True):
        assert a["integral_q"] == pytest.approx(b["integral_q"], abs=1e-9 * P)
    (xn, pn), (xl, pl) = _pressure(tmp_path / "n", "B"), _pressure(tmp_path / "l", "B")
    assert np.allclose(xn, xl, atol=1e-12) and np.allclose(pn, pl, rtol=0, atol=1e-9 * pl.max())


HALF_PLANE_PADS = {
    **PADS,
    "nurbs rounded-flat": 'shape = "nurbs"\n\n'
    + _segments_toml("pad", RoundedFlatPad(0.3, 20.0, 6.5, 6.5).boundary(ZONE).segments),
}


@pytest.mark.parametrize("specimen", ["half-plane", "bem"])
@pytest.mark.parametrize("pad", list(HALF_PLANE_PADS))
def test_library_pads_as_half_planes_build_and_run(tmp_path, pad, specimen):
    """Every pad shape as a half-plane (the rounded flat's three-segment face joined), on a
    flat specimen of either model; the nurbs pad given the rounded flat's own segments gives
    the rounded-flat answer."""
    model = f'model = "half-plane"\n{HALF_PLANE_PADS[pad]}'
    flat = f'{SPECIMENS["flat-clamped"]}model = "{specimen}"\n'
    summary = _run(_scene(tmp_path, model, flat, "s"), tmp_path / "out")
    for step in summary["steps"]:
        assert step["integral_p"] == pytest.approx(P, rel=1e-3)
    x, p = _pressure(tmp_path / "out")
    assert p.max() > 0 and p[0] == 0 and p[-1] == 0
    if pad == "nurbs rounded-flat":
        library = f'model = "half-plane"\n{PADS["rounded-flat"]}'
        _run(_scene(tmp_path, library, flat, "lib"), tmp_path / "lib")
        xl, pl = _pressure(tmp_path / "lib")
        assert np.allclose(x, xl, atol=1e-12) and np.allclose(p, pl, atol=1e-9 * pl.max())


@pytest.mark.parametrize("specimen", ["cylinder", "flat-ends", "nurbs"])
def test_library_specimens_as_half_planes_build_and_run(tmp_path, specimen):
    """Every specimen shape as a half-plane under a half-plane cylinder pad (the nurbs
    specimen given the flat specimen's own segments)."""
    if specimen == "nurbs":
        face = CylinderPad(R, 6.5, 6.5).face(ZONE)
        segments = FlatSpecimen(12.0, 6.0).boundary(face, ZONE).segments
        text = 'shape = "nurbs"\nsupport = "clamped-bottom"\n\n' + _segments_toml(
            "specimen", segments
        )
    else:
        text = SPECIMENS[specimen]
    pad = f'model = "half-plane"\n{PADS["cylinder"]}'
    summary = _run(_scene(tmp_path, pad, f'model = "half-plane"\n{text}', "s"), tmp_path / "o")
    for step in summary["steps"]:
        assert step["integral_p"] == pytest.approx(P, rel=1e-3)
    _, p = _pressure(tmp_path / "o")
    assert p.max() > 0 and p[0] == 0 and p[-1] == 0


def test_cylinder_on_flat_meets_hertz(tmp_path):
    """A large flat specimen: a and p0 of Hertz line contact within the node spacing."""
    specimen = 'shape = "flat"\nlength = 40.0\nthickness = 20.0\nsupport = "clamped-bottom"\n'
    _run(_scene(tmp_path, PADS["cylinder"], specimen, "h", pairs=61), tmp_path / "out")
    hertz = HertzLineContact.from_bodies(
        load=P, radius_upper=R, radius_lower=np.inf, E_upper=E, nu_upper=NU, E_lower=E, nu_lower=NU
    )
    x, p = _pressure(tmp_path / "out")
    spacing = np.diff(x).max()
    assert abs(x[p > 0].max() - hertz.half_width) < spacing
    assert p.max() == pytest.approx(hertz.peak_pressure, rel=0.03)


def test_a_nurbs_body_without_a_contact_tag_is_refused(tmp_path, capsys):
    segments = CylinderPad(R, 6.5, 6.5).boundary(ZONE).segments
    text = _segments_toml("pad", segments).replace('tag = "contact"', 'tag = "face"')
    path = _scene(tmp_path, 'shape = "nurbs"\n\n' + text, SPECIMENS["flat-clamped"], "bad")
    assert cli.main(["run", str(path), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "needs a segment tagged 'contact'" in err and "Traceback" not in err
    assert load_scene is not None


def _nurbs_pad(shape) -> str:
    return 'shape = "nurbs"\n\n' + _segments_toml("pad", shape.boundary(ZONE).segments)


#: every pad shape, a nurbs pad drawing either library shape
TURNING_PADS = {
    **PADS,
    "nurbs cylinder": _nurbs_pad(CylinderPad(R, 6.5, 6.5)),
    "nurbs rounded-flat": _nurbs_pad(RoundedFlatPad(0.3, 20.0, 6.5, 6.5)),
}
#: a default set in which every body model, basis family and pad shape turns once; the
#: other twelve of the 16 combinations are in the slow set
TURNING_DEFAULT = {
    ("half-plane", "nurbs", "cylinder"),
    ("half-plane", "lagrange2", "nurbs rounded-flat"),
    ("bem", "nurbs", "rounded-flat"),
    ("bem", "lagrange2", "nurbs cylinder"),
}
K_R, PIVOT = 1.0e5, 5.0  # N mm/mm per rad; mm above the first contact


@pytest.mark.parametrize(
    ("model", "basis", "pad"),
    [
        pytest.param(*c, marks=() if c in TURNING_DEFAULT else pytest.mark.slow)
        for c in ((m, b, p) for m in ("half-plane", "bem") for b in ("nurbs", "lagrange2")
                  for p in TURNING_PADS)
    ],
)  # fmt: skip
def test_a_rotating_block_on_every_pad_shape_family_and_model(tmp_path, model, basis, pad):
    """The pad's block turns against a rotational rig spring ([rig] stiffness_rotation,
    pivot_height) for every pad shape, body model and basis family, through ``fretbem run``:
    summary.json holds M = -k_r tilt, Q > 0 below the pivot tilts the pad clockwise, and the
    written tractions balance the moment about the pivot, M = h Q - d P (d the pressure's
    centre in results.csv): measured within 0.54 % of h Q (21 pairs, the trapezoid rule and
    the shear's arm over the curved face), asserted within 1 %."""
    rig = f"[rig]\nstiffness_rotation = {K_R}\npivot_height = {PIVOT}\n"
    pad_table = f'model = "{model}"\n{TURNING_PADS[pad]}'
    specimen = f'{SPECIMENS["flat-clamped"]}model = "{model}"\n'
    path = _scene(tmp_path, pad_table, specimen, "turning", pairs=21)
    text = path.read_text().replace("[contact]\n", f'{rig}[contact]\nbasis = "{basis}"\n')
    path.write_text(text.replace("Q = [0.0, 15.0, 0.0]", "Q = [0.0, 15.0, -15.0]"))
    out = tmp_path / "out"
    steps = _run(path, out)["steps"]
    assert steps[1]["tilt"] < 0 < steps[2]["tilt"]
    for step in steps:
        assert step["M"] == pytest.approx(-K_R * step["tilt"], rel=1e-9, abs=1e-9)
    for step in steps[1:]:
        x, p = _pressure(out, step["step"])
        centre = np.trapezoid(p * x, x) / np.trapezoid(p, x)
        balance = PIVOT * step["Q"] - centre * step["P"]
        assert abs(step["M"] - balance) < 0.01 * PIVOT * abs(step["Q"])
    loops = np.genfromtxt(out / "loops.csv", delimiter=",", names=True, dtype=None,
                          encoding="utf-8")  # fmt: skip
    np.testing.assert_allclose(loops["M"][-1], steps[-1]["M"], rtol=1e-9)
