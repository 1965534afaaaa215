"""The convergence study (issue 4): quick form end to end, its analysis helpers, slow checks."""

import csv
import itertools
import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

from fretbem import cli
from fretbem.studies.convergence import (
    COLUMNS,
    FAMILIES,
    LARGE,
    QUICK_PAIRS,
    Case,
    StudyPlan,
    crossings,
    first_crossing,
    fit_exponent,
    read_csv,
    run_study,
)

# the results page generator is documentation tooling (docs/sphinxext), not the package
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "docs" / "sphinxext"))
from results_page_text import results_page, write_results_page


@pytest.fixture(scope="module")
def quick_study(tmp_path_factory):
    """`fretbem convergence --quick` once for the module: its output folder and rows."""
    out = tmp_path_factory.mktemp("convergence")
    assert cli.main(["convergence", "--quick", "--out", str(out)]) == 0
    return out, read_csv(out / "convergence.csv")


def test_quick_study_writes_csv_with_every_column(quick_study):
    """One row per run, the documented columns, every family and quick level present."""
    out, rows = quick_study
    with open(out / "convergence.csv", newline="") as handle:
        header = next(csv.reader(handle))
    assert tuple(header) == COLUMNS
    assert len(rows) == len(StudyPlan.quick().cases())
    main = [r for r in rows if r["bodies"] == 1 and r["rest"] == 1]
    families = {(r["family"], r["degree"]) for r in main}
    assert families == {(f, 2 if d is None else d) for f, d in FAMILIES}
    assert sorted({r["pairs"] for r in main}) == list(QUICK_PAIRS)
    for r in main:
        assert r["dofs"] > 2 * 2 * r["pairs"]  # both bodies, two components, more than the zone
        for key in ("e_p_max", "e_q_max", "e_p_l2", "e_q_l2"):
            assert 0 < r[key] < 0.25
            assert r[key] == max(r[f"{key}_{s}"] for s in "BCDE")
            assert r[key.replace("max", "l2")] <= r[key.replace("l2", "max")] + 1e-12
        assert all(r[f"iterations_{s}"] >= 1 for s in "ABCDE")
        assert r["iterations"] == sum(r[f"iterations_{s}"] for s in "ABCDE")
        assert 0 < r["assembly_s"] < r["run_s"] <= r["wall_s"]
        assert r["factorisation_s"] <= r["condensation_s"]
        assert r["peak_memory_mib"] > 1
        assert r["rest_change_p"] is None


def test_quick_study_compares_finite_and_larger_bodies(quick_study):
    """The finest quick level also runs on bodies 4x larger, with the same contact pairs."""
    _, rows = quick_study
    large = [r for r in rows if r["bodies"] == LARGE]
    assert large and all(r["pairs"] == QUICK_PAIRS[-1] for r in large)
    for r in large:
        twin = next(
            s
            for s in rows
            if s["bodies"] == 1
            and s["rest"] == 1
            and (s["family"], s["degree"], s["pairs"]) == (r["family"], r["degree"], r["pairs"])
        )
        assert r["width"] == pytest.approx(LARGE * twin["width"])
        assert r["height"] == pytest.approx(LARGE * twin["height"])
        assert r["dofs"] == twin["dofs"]  # same discretisation, larger bodies
        assert r["e_q_max"] != twin["e_q_max"]


def test_quick_study_checks_refinement_of_the_rest(quick_study):
    """Refining flanks, sides and top barely changes the contact tractions."""
    _, rows = quick_study
    checks = [r for r in rows if r["rest"] != 1]
    assert checks
    for r in checks:
        assert r["flank_elements"] == round(16 * r["rest"])
        assert 0 <= r["rest_change_p"] < 0.005 and 0 <= r["rest_change_q"] < 0.005


def test_quick_study_figures_and_page(quick_study, tmp_path):
    """Two PNG figures from the study; the docs tool turns its CSV into a results page with
    the table, the comparison and the answer."""
    out, rows = quick_study
    for name in ("error_vs_dofs.png", "error_vs_time.png"):
        data = (out / name).read_bytes()
        assert data.startswith(b"\x89PNG") and len(data) > 10_000
    assert not (out / "results.md").exists()  # the package writes no docs page
    page_path = write_results_page(out / "convergence.csv", tmp_path / "results.md")
    page = page_path.read_text()
    for heading in (
        "## Which family is fastest to 1 %",
        "## All runs on the scene's bodies",
        "## Finite bodies against half-plane theory",
        "## Refinement of the rest of the bodies",
        "## Fitted exponents",
    ):
        assert heading in page
    assert "| nurbs | 2 | 31 |" in page and "| lagrange2 | 2 | 15 |" in page
    meta = json.loads((out / "study.json").read_text())
    figures = {"dofs": "results/error_vs_dofs.png", "time": "results/error_vs_time.png"}
    assert page == results_page(rows, meta=meta, figures=figures)  # a function of the CSV


def test_first_crossing_interpolates_in_log_log():
    """Between (100, 2 %) and (400, 0.5 %) the 1 % level is crossed at 200 in log-log."""
    assert first_crossing([100, 400], [0.02, 0.005]) == pytest.approx(200.0)
    assert first_crossing([100, 400], [0.005, 0.001]) == 100.0
    assert first_crossing([100, 400, 800], [0.03, 0.02, 0.015]) is None
    # a max error that dips below and comes back: the first crossing counts
    assert first_crossing([1, 10, 100], [0.02, 0.002, 0.03]) == pytest.approx(
        10 ** (math.log(0.5) / math.log(0.1))
    )


def test_fit_exponent_recovers_a_power_law():
    x = [10, 20, 40, 80]
    assert fit_exponent(x, [3 * v**-2.0 for v in x]) == pytest.approx(-2.0)
    assert math.isnan(fit_exponent([10], [1.0]))


def test_crossings_by_family():
    """crossings() answers per family in DOFs and in wall time, None when never reached."""
    rows = [
        {"family": "a", "degree": 2, "pairs": p, "dofs": d, "wall_s": t, "e_q_max": e}
        | {"rest": 1.0, "bodies": 1.0}
        for p, d, t, e in ((15, 100, 0.1, 0.04), (31, 400, 0.4, 0.0025))
    ] + [
        {"family": "b", "degree": 2, "pairs": 15, "dofs": 100, "wall_s": 0.1, "e_q_max": 0.05}
        | {"rest": 1.0, "bodies": 1.0}
    ]
    out = crossings(rows, "e_q_max")
    assert out[("a", 2)] == (pytest.approx(200.0), pytest.approx(0.2))
    assert out[("b", 2)] == (None, None)


def test_case_scales_bodies_and_rest():
    scene = Case("nurbs", 3, 61, bodies=4.0, rest=2.0).scene()
    assert (scene.width, scene.height) == (26.0, 65.0)
    assert (scene.flank_elements, scene.side_elements, scene.top_elements) == (32, 24, 24)
    assert scene.degree == 3 and scene.pairs == 61


def test_importing_the_study_defers_matplotlib():
    """matplotlib is imported only when figures are drawn."""
    code = "import sys, fretbem.studies.convergence; print('matplotlib' in sys.modules)"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.stdout.strip() == "False", done.stderr


@pytest.mark.slow
def test_l2_error_falls_on_larger_bodies(tmp_path):
    """On bodies 4x larger (no finite-body floor) the L2 errors fall at every level."""
    plan = StudyPlan(
        families=(("nurbs", 2), ("lagrange2", None)),
        pairs=(),
        large_pairs=(31, 61, 121, 241),
        rest_pairs=(),
        repeats=1,
        memory=False,
    )
    rows = run_study(plan, tmp_path, figures=False, progress=None)
    for family in ("nurbs", "lagrange2"):
        runs = sorted((r for r in rows if r["family"] == family), key=lambda r: r["pairs"])
        for key in ("e_p_l2", "e_q_l2"):
            values = [r[key] for r in runs]
            assert all(b < a for a, b in itertools.pairwise(values)), (key, values)
