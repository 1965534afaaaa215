"""Every body model, as pad and as specimen, through the whole ``fretbem run`` path.

Figures, VTK, a ``[stress]`` table, a ``[fatigue]`` table and the error estimate are all on;
outputs reach the bodies through the :class:`~fretbem.body.Body` contract only, so any
registered model must pass. What cannot apply to a model is said in one line, never a crash.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest

from fretbem.app import cli
from fretbem.scenes.spec import MODELS

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

RIG = Path(__file__).resolve().parents[3] / "examples" / "fretting_rig.toml"


def _toml(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, list):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return repr(value)


def _write(data: dict, path: Path) -> Path:
    lines = []

    def table(name, body):
        plain = {
            k: v
            for k, v in body.items()
            if not isinstance(v, (dict, list))
            or (isinstance(v, list) and not (v and isinstance(v[0], dict)))
        }
        lines.append(f"[{name}]")
        lines.extend(f"{k} = {_toml(v)}" for k, v in plain.items())
        for k, v in body.items():
            if isinstance(v, dict):
                table(f"{name}.{k}", v)
            elif isinstance(v, list) and v and isinstance(v[0], dict):
                for item in v:
                    lines.append(f"[[{name}.{k}]]")
                    lines.extend(f"{kk} = {_toml(vv)}" for kk, vv in item.items())

    for name, body in data.items():
        table(name, body)
    path.write_text("\n".join(lines) + "\n")
    return path


def _scene(pad: str, specimen: str) -> dict:
    data = tomllib.loads(RIG.read_text())
    data["pad"]["model"], data["specimen"]["model"] = pad, specimen
    data["contact"]["pairs"] = 31
    data["stress"]["line"][0]["n"] = 12
    return data


COMBINATIONS = [(pad, specimen) for pad in MODELS for specimen in MODELS]
#: the combinations whose pad block turns against a rotational rig spring (each pad model once)
ROTATING = {("bem", "half-plane"), ("half-plane", "bem")}


@pytest.mark.parametrize(("pad", "specimen"), COMBINATIONS)
def test_every_model_through_every_output(tmp_path, capsys, pad, specimen):
    """Two of the four combinations turn the pad's block (a rotational rig spring): M, theta
    and tilt then reach summary.json, loops.csv, the netCDF file and the report."""
    data = _scene(pad, specimen)
    rotating = (pad, specimen) in ROTATING
    if rotating:
        data["rig"] = {"stiffness_rotation": 2.0e5}
    scene = _write(data, tmp_path / "scene.toml")
    out = tmp_path / "out"
    argv = ["run", str(scene), "--out", str(out), "--report", "--netcdf"]
    assert cli.main(argv) == 0, capsys.readouterr().err
    printed = capsys.readouterr().out
    files = {p.name for p in out.iterdir()}
    assert {"results.csv", "summary.json", "units.json", "fatigue.json"} <= files
    assert {"results.nc", "report.html", "loops.csv"} <= files
    _rotation_reached_every_output(out, rotating)
    assert any(name.endswith(".png") for name in files)
    assert list((out / "vtk").glob("*.vtp")) and (out / "history.pvd").exists()
    assert any(name.startswith("stress_") for name in files)
    for path in out.rglob("*"):
        assert path.is_dir() or path.stat().st_size > 0, path
    summary = json.loads((out / "summary.json").read_text())
    assert summary["steps"][1]["est_q_max"] is not None  # the estimate reached every model
    # a half-plane has no far boundary: said once, in one line, for each such body
    for model, label in ((pad, "pad"), (specimen, "specimen")):
        line = f"VTK of the {model} body {label!r}: its face only (it has no far boundary)"
        assert printed.count(line) == (1 if model == "half-plane" else 0)


def _rotation_reached_every_output(out: Path, rotating: bool) -> None:
    """The block's tilt in summary.json, loops.csv, results.nc and the report: Q > 0 below
    the pivot tilts the pad clockwise, the spring holds M = -k_r tilt; a held block: 0."""
    from fretbem.views import read_netcdf

    steps = json.loads((out / "summary.json").read_text())["steps"]
    tilts = np.array([s["tilt"] for s in steps])
    loops = np.genfromtxt(out / "loops.csv", delimiter=",", names=True, dtype=None,
                          encoding="utf-8")  # fmt: skip
    dataset = read_netcdf(out / "results.nc")
    np.testing.assert_allclose(dataset["tilt"].values, tilts, rtol=1e-12, atol=0)
    np.testing.assert_allclose(dataset["M"].values, [s["M"] for s in steps], rtol=1e-12)
    report = (out / "report.html").read_text()
    if not rotating:
        assert not tilts.any() and "tilt (rad)" not in report
        return
    assert tilts[1] < 0 < tilts[3]  # Q = +45 then -45 N/mm
    for step in steps:
        assert step["M"] == pytest.approx(-2.0e5 * step["tilt"], rel=1e-9, abs=1e-9)
    assert np.ptp(loops["M"]) > 0 and "tilt (rad)" in report


def test_a_rounded_flat_half_plane_pad_through_every_output(tmp_path, capsys):
    """The rig with a rounded-flat pad (a face of three segments) as a half-plane: every
    output written; the error estimate, which needs a one-segment face, says so in the
    summary as for a BEM rounded-flat pad (on a BEM specimen: the shape-matrix test)."""
    data = _scene("half-plane", "half-plane")
    data["pad"] = {"shape": "rounded-flat", "flat": 0.3, "edge_radius": 20.0, "width": 10.0,
                   "height": 10.0, "model": "half-plane"}  # fmt: skip
    data["contact"].pop("zone")
    data["contact"].update(pairs=33, zone_width=1.0)
    data.pop("fatigue")
    scene = _write(data, tmp_path / "scene.toml")
    out = tmp_path / "out"
    assert cli.main(["run", str(scene), "--out", str(out)]) == 0, capsys.readouterr().err
    printed = capsys.readouterr().out
    files = {p.name for p in out.iterdir()}
    assert {"results.csv", "summary.json", "units.json"} <= files
    assert any(name.endswith(".png") for name in files)
    assert len(list((out / "vtk").glob("*.vtp"))) >= 5 and (out / "history.pvd").exists()
    assert any(name.startswith("stress_") for name in files)
    summary = json.loads((out / "summary.json").read_text())
    assert "need the contact face as one segment" in summary["accuracy"]["estimate_reason"]
    for step in summary["steps"]:
        assert step["integral_p"] == pytest.approx(data["load"]["P"], rel=1e-3)
    assert printed.count("VTK of the half-plane body 'pad': its face only") == 1


def test_surface_stress_of_the_models_agree(tmp_path):
    """sigma_xx at the specimen's surface under the trailing edge: the half-plane specimen and
    the BEM specimen (13 mm thick on rollers, bending under the bulk load) differ by the
    finite body: measured 5.7 % of p0 at most (31 pairs), asserted below 8 %."""
    from fretbem.scenes.builder import build
    from fretbem.scenes.file import load_scene
    from fretbem.simulation import run
    from fretbem.stress.evaluate import StressEvaluator

    values = {}
    for model in ("bem", "half-plane"):
        data = _scene("bem", model)
        data.pop("stress"), data.pop("fatigue")
        scene = load_scene(_write(data, tmp_path / f"{model}.toml"))
        simulation, _ = build(scene)
        result = run(simulation)
        x = np.array([-0.664, -0.3, 0.0, 0.3, 0.664])
        points = np.column_stack([x, np.full(x.size, -0.05)])  # 50 um below the surface
        values[model] = StressEvaluator(result, points, "lower").step("B")[:, 0]
    p0 = 2 * 200.0 / (np.pi * 0.664)
    assert np.max(np.abs(values["bem"] - values["half-plane"])) < 0.08 * p0
