"""Hostile runs by class: a result edited after the solve is never written as checked, the
default solver succeeds where Newton alone fails, the advice near gross slip is what works,
closed forms are compared only inside their validity, and a run says when its accuracy is
poor (coarse mesh, no estimate, adaptive tolerance missed)."""

from __future__ import annotations

import attrs
import numpy as np
import pytest

from fretbem.app import cli
from fretbem.output.write import write_results
from fretbem.pipeline import run_scene
from fretbem.scenes.file import scene_from_dict
from fretbem.verification.checks import ConsistencyError

BASE = {
    "pad": {"shape": "cylinder", "radius": 70.0},
    "specimen": {"shape": "cylinder"},
    "contact": {"pairs": 11},
    "load": {"steps": ["A", "B"], "P": 100.0, "Q": [0.0, 18.0]},
}


def _scene(**tables):
    data = {k: dict(v) for k, v in BASE.items()}
    for name, table in tables.items():
        data[name] = {**data.get(name, {}), **table}
    return scene_from_dict(data)


@pytest.fixture(scope="module")
def result():
    return run_scene(_scene()).result


@pytest.mark.parametrize("field", ["pressure", "shear", "x", "states", "unknowns"])
def test_result_arrays_are_read_only(result, field):
    with pytest.raises(ValueError, match="read-only"):
        getattr(result.steps[1], field)[:1] *= 2


@pytest.mark.parametrize(
    ("field", "change"),
    [
        ("pressure", lambda s: 2 * s.pressure),
        ("shear", lambda s: s.shear + 1.0),
        ("resultant", lambda s: (2 * s.resultant[0], s.resultant[1])),
    ],
)
def test_the_writer_refuses_a_result_edited_after_the_solve(result, tmp_path, field, change):
    """Reproducer: a doubled pressure was written beside 'equilibrium passed'."""
    step = attrs.evolve(result.steps[1], **{field: change(result.steps[1])})
    edited = attrs.evolve(result, steps=(result.steps[0], step))
    with pytest.raises(ConsistencyError, match="edited after the solve"):
        write_results(edited, tmp_path / "out", figures=False, vtk=False)
    assert not (tmp_path / "out").exists()


RIG = {
    "pad": {"shape": "cylinder", "radius": 70.0, "width": 10.0, "height": 10.0},
    "specimen": {"shape": "flat", "length": 40.0, "thickness": 13.0},
    "material": {"E": 72000.0, "nu": 0.33},
    "contact": {"friction": 0.5, "pairs": 21},
    "load": {"steps": ["A", "B", "C"], "P": 200.0, "Q": [0.0, 45.0, -45.0],
             "bulk": [60.0, 90.0, -90.0]},
}  # fmt: skip


def test_bulk_stress_in_the_first_step_is_solved_by_the_default_solver():
    """Reproducer: Newton separated every pair in step A and advised sub-increments, which
    failed too; Lemke's method solves it, so the default falls back to it."""
    said = []
    done = run_scene(scene_from_dict(RIG), say=said.append)
    assert [s.name for s in done.result.steps] == ["A", "B", "C"]
    assert any("Lemke" in line for line in said)


def test_newton_advice_names_scene_keys():
    from fretbem.simulation import run

    scene = scene_from_dict({**RIG, "contact": {**RIG["contact"], "solver": "newton"}})
    from fretbem.scenes.builder import build

    simulation, _ = build(scene)
    with pytest.raises(Exception, match=r"\[contact\] solver = 'lemke'.*\[load\]") as info:
        run(simulation)
    assert "increments" in str(info.value)


def test_near_gross_slip_the_advice_says_how_many_pairs_it_would_take(tmp_path, capsys):
    data = {**BASE, "load": {**BASE["load"], "Q": [0.0, 29.99]}}
    path = tmp_path / "s.toml"
    path.write_text(_toml(data))
    assert cli.main(["run", str(path), "--out", str(tmp_path / "o"), "--no-figures",
                     "--no-vtk"]) == 1  # fmt: skip
    line = capsys.readouterr().err
    assert "times the pairs" in line and "keep |Q| / (f P) below about" in line


def _toml(data: dict) -> str:
    def value(v):
        if isinstance(v, str):
            return f'"{v}"'
        if isinstance(v, list):
            return "[" + ", ".join(value(x) for x in v) + "]"
        return repr(v)

    return "".join(
        f"[{t}]\n" + "".join(f"{k} = {value(v)}\n" for k, v in table.items())
        for t, table in data.items()
    )


def test_closed_forms_are_compared_only_for_small_contacts():
    """Reproducer: a / R of 0.3 reported 'errors' of 80-99 % against an estimate of 20 %."""
    big = {"radius": 2.0, "width": 3.0, "height": 3.0}
    scene = _scene(pad=big, specimen=big, load={"P": 3000.0, "Q": [0.0, 500.0]})
    done = run_scene(scene)
    assert done.result.steps[1].errors is None
    assert "a / R = 0.15 is outside half-plane theory's validity" in done.reason


def test_finite_bodies_report_the_difference_from_half_plane_theory(result):
    from fretbem.contact.zones import zone_table

    assert "difference from half-plane theory" in zone_table(result)


def test_half_plane_bodies_report_errors_against_theory():
    """The note is asked of the bodies (Body.finite), not read from a model's name."""
    from fretbem.contact.zones import zone_table

    half = {"model": "half-plane"}
    done = run_scene(_scene(pad=half, specimen={**half, "shape": "flat"}))
    table = zone_table(done.result)
    assert "errors against the closed form" in table
    assert "difference from half-plane theory" not in table


@pytest.mark.parametrize(
    ("contact", "words"),
    [
        ({"pairs": 5}, "give no estimate"),
        ({"pairs": 9}, "the contact mesh is coarse"),
        ({"mesh": "adaptive", "tolerance": 0.001, "budget": 21}, "above the tolerance"),
    ],
)
def test_poor_accuracy_is_said(contact, words):
    """Reproducer: 5 pairs gave e_p 25 % with exit 0 and no word; an adaptive run that
    missed its tolerance said nothing."""
    data = {k: dict(v) for k, v in BASE.items()}
    data["contact"] = contact
    result = run_scene(scene_from_dict(data)).result
    assert words in (result.accuracy.caution or "")
    assert words in result.table()


def test_the_reference_mesh_has_no_caution():
    result = run_scene(_scene(contact={"pairs": 61})).result
    assert result.accuracy.caution is None
    assert np.isfinite(result.steps[1].estimate.e_p_max)
