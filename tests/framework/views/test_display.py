"""Notebook display: one-line reprs and HTML tables of a scene, a run, a step, stresses,
a fatigue report and a sweep (the repr of a run was 59 kB)."""

from __future__ import annotations

import re
from html.parser import HTMLParser

import numpy as np

from fretbem.contact.zones import step_zones
from fretbem.testing.scenes import SMALL_SCENE, scene_data_with
from fretbem.views.display import MAX_ROWS

#: a repr is one readable line
SHORT = 400


class _Cells(HTMLParser):
    """The text of every table cell, and whether tags balance."""

    def __init__(self):
        super().__init__()
        self.cells, self.stack, self._text = [], [], None

    def handle_starttag(self, tag, attrs):
        self.stack.append(tag)
        if tag in ("td", "th"):
            self._text = ""

    def handle_endtag(self, tag):
        assert self.stack.pop() == tag, f"unbalanced </{tag}>"
        if tag in ("td", "th"):
            self.cells.append(self._text)
            self._text = None

    def handle_data(self, data):
        if self._text is not None:
            self._text += data


def _cells(markup: str) -> list[str]:
    parser = _Cells()
    parser.feed(markup)
    assert not parser.stack
    return parser.cells


def test_run_and_step_reprs_are_one_short_line(rig_run):
    result = rig_run.result
    for obj in (result, result["B"], rig_run):
        text = repr(obj)
        assert len(text) < SHORT and "\n" not in text, text
    text = repr(result)
    worst = max(s.errors["e_q_max"] for s in result.steps)
    assert f"max e_q {100 * worst:.3f} %" in text and "checks passed" in text
    assert "31 pairs" in text and "5 steps A..E" in text
    step = repr(result["B"])
    assert "Q=45" in step and "sigma_B=90" in step
    assert f"{result['B'].count('slip')} slip" in step


def test_run_html_is_a_table_of_steps_with_zones_beside_theory(rig_run):
    result = rig_run.result
    cells = _cells(result._repr_html_())
    summary = result.summary()
    for step in summary["steps"]:
        row = cells[cells.index(step["step"]) :][:11]
        assert row[1] == f"{step['P']:g}" and row[2] == f"{step['Q']:g}"
        assert row[3] == f"{step['sigma_B']:g}"
        assert row[5] == f"{100 * step['e_q_max']:.3f} / {100 * step['est_q_max']:.3f}"
        low, high = step["stick_zones"][0]
        assert row[6] == f"[{low:+.4f}, {high:+.4f}]"
        t_low, t_high = step["theory_stick_zone"]
        assert row[7] == f"[{t_low:+.4f}, {t_high:+.4f}]"
        assert row[10] == "passed"
    assert len(result._repr_html_()) < 10_000
    step_cells = _cells(result["B"]._repr_html_())
    zones = step_zones(result["B"])
    assert f"[{zones.contact[0]:+.4f}, {zones.contact[1]:+.4f}]" in step_cells


def test_a_long_history_shows_its_ends(rig_data):
    from fretbem.pipeline import run_scene
    from fretbem.scenes.file import scene_from_data

    n = 3 * MAX_ROWS
    q = [0.0, *(30.0 * np.sin(np.linspace(0.3, 6.0, n - 1)))]
    load = {"steps": [f"s{k}" for k in range(n)], "P": 200.0, "Q": q, "bulk": [2.0 * v for v in q]}
    result = run_scene(scene_from_data(rig_data(21, load=load))).result
    assert len(repr(result)) < SHORT
    markup = result._repr_html_()
    cells = _cells(markup)
    assert "s0" in cells and f"s{n - 1}" in cells and f"s{n // 2}" not in cells
    assert f"... {n - MAX_ROWS} steps not shown ..." in cells


def test_scene_display(rig_data):
    from fretbem.scenes.file import scene_from_data

    scene = scene_from_data(rig_data())
    text = repr(scene)
    assert len(text) < SHORT and "5 steps A..E" in text and "sigma_B -90..90" in text
    cells = _cells(scene._repr_html_())
    assert ["B", "200", "45", "90", "1"] == cells[cells.index("B") :][:5]


def test_stress_and_fatigue_display(rig_run):
    from fretbem.fatigue import CattaneoMindlinCycle, fatigue_request_from_dict, run_fatigue
    from fretbem.stress import evaluate_stress_request, stress_request_from_dict

    done = evaluate_stress_request(
        rig_run.result,
        stress_request_from_dict(
            {"steps": ["B"], "line": {"x": "trailing-edge", "depth": 0.3, "n": 6}}
        ),
    )
    text = repr(done)
    hot = done.hot_spot()["sigma_xx"]
    assert len(text) < SHORT and f"max sigma_xx {hot['value']:.4g} MPa at step B" in text
    assert f"{hot['value']:.4g} at step B" in " ".join(_cells(done._repr_html_()))
    cycle = CattaneoMindlinCycle(
        a=0.5, p0=300.0, f=0.6, tangential_ratio=0.5, sigma_bulk_max=80.0, nu=0.342
    )
    report = run_fatigue(
        cycle,
        fatigue_request_from_dict(
            {
                "material": "Ti-6Al-4V",
                "map_points": [11, 5],
                "methods": ["swt"],
                "critical_distance": 0.05,
            }
        ),
    )
    text = repr(report)
    swt = report.methods["swt"]
    assert len(text) < SHORT and f"swt {swt.at_hot_spot.value[0]:.4g} MPa" in text
    assert len(repr(swt)) < SHORT
    cells = _cells(report._repr_html_())
    assert cells[cells.index("swt") :][1] == f"{swt.hot_spot[0]:.4g}"
    assert re.fullmatch(r"[0-9.e+]+|run-out", cells[cells.index("swt") :][6])


def test_sweep_display(tmp_path):
    from fretbem.studies.sweep.run import sweep

    scene = scene_data_with(
        SMALL_SCENE, {"load__Q": [0.0, 18.0, 0.0], "load__steps": ["A", "B", "C"]}
    )
    result = sweep(
        scene,
        {"load.P": [80.0, 120.0], "contact.friction": [0.3, 0.5]},
        out=tmp_path / "s",
        serial=True,
        progress=False,
    )
    text = repr(result)
    assert len(text) < SHORT and "4/4 cases" in text and "load.P x contact.friction" in text
    cells = _cells(result._repr_html_())
    assert "load.P (N/mm)" in cells and "regime" in cells
    ds = result.to_xarray()
    assert ds["regime"].dims == ("load.P", "contact.friction")
