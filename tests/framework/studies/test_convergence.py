"""The convergence study (issue 4): quick form end to end, its analysis helpers, slow checks."""

import csv
import importlib
import importlib.util
import itertools
import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

from fretbem.accuracy.adaptive import run_adaptive
from fretbem.app import cli
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.studies.convergence.adaptive import FULL_BUDGETS, placeable
from fretbem.studies.convergence.analysis import cheapest, settled_from
from fretbem.studies.convergence.study import (
    ADAPTIVE_COLUMNS,
    ADAPTIVE_NAME,
    COLUMNS,
    FAMILIES,
    LARGE,
    QUICK_PAIRS,
    SAWTOOTH_COLUMNS,
    SAWTOOTH_NAME,
    AdaptiveCase,
    Case,
    StudyPlan,
    crossings,
    first_crossing,
    fit_exponent,
    read_csv,
    run_study,
)

# the results page generator is documentation tooling (docs/sphinxext), not the package
sys.path.insert(0, str(Path(__file__).resolve().parents[3] / "docs" / "sphinxext"))
from results_page_text import results_page, write_results_page


@pytest.fixture(scope="module")
def quick_study(tmp_path_factory):
    """`fretbem convergence --quick` once for the module: its output folder and rows."""
    out = tmp_path_factory.mktemp("convergence")
    # the compiled assembly loops from the start when numba is there, so that the study and a
    # case re-run after it take the same loops (the ski rental of fretbem.bem.integration
    # switches part-way through the study otherwise, where its numpy work reaches the
    # threshold: the re-run's numbers then differ at round-off)
    if importlib.util.find_spec("numba") is not None:
        importlib.import_module("fretbem.bem.compiled_loops")
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


def _header(path: Path) -> tuple[str, ...]:
    with open(path, newline="") as handle:
        return tuple(next(csv.reader(handle)))


def test_quick_study_runs_the_adaptive_series(quick_study):
    """Per adaptive family and budget one row with the fixed runs' error keys (largest over
    steps B-E), the estimate beside them, DOFs of the finest level and time of all levels."""
    out, _ = quick_study
    plan = StudyPlan.quick()
    assert _header(out / ADAPTIVE_NAME) == ADAPTIVE_COLUMNS
    adaptive = read_csv(out / ADAPTIVE_NAME)
    expected = [(f, 2, b) for f, _ in plan.adaptive_families for b in plan.budgets]
    assert [(r["family"], r["degree"], r["budget"]) for r in adaptive] == expected
    for r in adaptive:
        assert r["pairs"] == r["budget"]  # the study's tolerance lets the budget end the run
        assert r["levels"].split("/")[-1] == str(r["pairs"])
        assert r["dofs"] > 2 * 2 * r["pairs"]
        for key in ("e_p_max", "e_q_max", "e_p_l2", "e_q_l2"):
            assert 0 < r[key] < 0.25 and 0 < r[f"estimate_{key}"] < 0.25
        assert r["e_q_l2"] <= r["e_q_max"] and r["e_p_l2"] <= r["e_p_max"]
        assert 0 < r["adaptive_s"] <= r["wall_s"]
        assert r["iterations"] >= 5 * len(r["levels"].split("/"))
        assert r["tolerance"] == plan.tolerance and r["repeats"] == plan.repeats
    # the row is the mode's own result: one case re-run directly
    first = adaptive[0]
    case = AdaptiveCase(first["family"], first["degree"], first["budget"])
    direct = run_adaptive(cattaneo_mindlin(case.scene()), case.settings(plan.tolerance))
    steps = [s for s in direct.result.steps if s.name in "BCDE"]
    assert first["e_q_max"] == max(s.errors["e_q_max"] for s in steps)
    assert first["estimate_e_q_l2"] == max(direct.estimate[s.name]["e_q_l2"] for s in steps)
    assert first["dofs"] == direct.result.describe()["dofs"]


def test_quick_study_runs_the_sawtooth(quick_study):
    """Every placeable pair count of the range, fixed and adaptive; they agree with the fixed
    run and the adaptive series at the same pair count."""
    out, rows = quick_study
    plan = StudyPlan.quick()
    assert _header(out / SAWTOOTH_NAME) == SAWTOOTH_COLUMNS
    tooth = read_csv(out / SAWTOOTH_NAME)
    first, last = plan.sawtooth
    expected = [
        (f, n) for f, d in plan.adaptive_families for n in range(first, last + 1)
        if placeable(f, d, n)
    ]  # fmt: skip
    assert [(r["family"], r["pairs"]) for r in tooth] == expected
    assert [n for f, n in expected if f == "lagrange2"] == list(range(first, last + 1, 2))
    adaptive = {(r["family"], r["budget"]): r for r in read_csv(out / ADAPTIVE_NAME)}
    main = [r for r in rows if r["bodies"] == 1 and r["rest"] == 1]
    fixed = {(r["family"], r["degree"], r["pairs"]): r for r in main}
    for r in tooth:
        twin = fixed.get((r["family"], r["degree"], r["pairs"]))
        if twin is not None:
            assert r["fixed_dofs"] == twin["dofs"]
            assert r["fixed_e_q_max"] == pytest.approx(twin["e_q_max"], rel=1e-9)
        series = adaptive.get((r["family"], r["pairs"]))
        if series is not None:
            assert r["adaptive_e_q_max"] == pytest.approx(series["e_q_max"], rel=1e-9)
        assert r["adaptive_pairs"] == r["pairs"]


def test_cheapest_and_settled_from():
    """cheapest(): per series the fewest DOFs and the least time at or below a level;
    settled_from(): the pair count from which a column stays at or below it."""
    base = {"rest": 1.0, "bodies": 1.0, "family": "a", "degree": 2}
    rows = [
        base | {"pairs": 15, "dofs": 100, "wall_s": 0.1, "e_q_max": 0.03},
        base | {"pairs": 31, "dofs": 200, "wall_s": 0.3, "e_q_max": 0.01},
        base | {"pairs": 61, "dofs": 400, "wall_s": 0.2, "e_q_max": 0.005},
    ]
    adaptive = [{"family": "a", "degree": 2, "budget": 31, "dofs": 300, "wall_s": 1.0}]
    adaptive[0]["e_q_max"] = 0.02
    found = cheapest(rows, adaptive, "e_q_max", 0.01)
    assert found[("a", 2, "fixed")] == (rows[1], rows[2])
    assert found[("a", 2, "adaptive")] == (None, None)
    tooth = [
        {"pairs": n, "x": x} for n, x in ((31, 0.01), (32, 0.03), (33, 0.01), (34, 0.02))
    ]  # fmt: skip
    assert settled_from(tooth, "x", 0.02) == 33
    assert settled_from(tooth, "x", 0.03) == 31
    assert settled_from(tooth, "x", 0.015) is None


def test_quick_study_figures_and_page(quick_study, tmp_path):
    """Three PNG figures from the study; the docs tool turns its CSVs into a results page
    with the tables, the comparison, the adaptive section and the answers."""
    out, rows = quick_study
    for name in ("error_vs_dofs.png", "error_vs_time.png", "adaptive_study_sawtooth.png"):
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
        "## The adaptive mode",
        "### Which family is cheaper for a given error",
        "### Error against pair count: the sawtooth",
    ):
        assert heading in page
    assert "| nurbs | 2 | 31 |" in page and "| lagrange2 | 2 | 15 |" in page
    assert "| nurbs p=2 | 31 | 31/" in page and "| lagrange2 | 41 | 31/" in page
    assert "![e_q max against pair count, fixed and adaptive](results/adaptive_study_" in page
    meta = json.loads((out / "study.json").read_text())
    figures = {
        k: f"results/{v}"
        for k, v in (
            ("dofs", "error_vs_dofs.png"),
            ("time", "error_vs_time.png"),
            ("sawtooth", "adaptive_study_sawtooth.png"),
        )
    }
    adaptive, tooth = read_csv(out / ADAPTIVE_NAME), read_csv(out / SAWTOOTH_NAME)
    # a function of the CSVs
    assert page == results_page(rows, meta=meta, figures=figures, adaptive=adaptive, sawtooth=tooth)


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


@pytest.mark.slow
def test_adaptive_series_at_full_budgets(tmp_path):
    """The study's adaptive series (both families, budgets 31 to 121): every budget is
    spent, the DOFs grow with it, and at equal pairs the adaptive mode's L2 shear error is
    below the fixed mode's."""
    plan = StudyPlan(
        pairs=(61, 121), large_pairs=(), rest_pairs=(), families=StudyPlan().adaptive_families,
        budgets=FULL_BUDGETS, sawtooth=(), repeats=1, memory=False,
    )  # fmt: skip
    rows = run_study(plan, tmp_path, figures=False, progress=None)
    adaptive = read_csv(tmp_path / ADAPTIVE_NAME)
    for family, _ in plan.adaptive_families:
        runs = [r for r in adaptive if r["family"] == family]
        assert [r["budget"] for r in runs] == list(FULL_BUDGETS)
        assert all(r["pairs"] == r["budget"] for r in runs)
        assert all(b["dofs"] > a["dofs"] for a, b in itertools.pairwise(runs))
        for fixed in (r for r in rows if r["family"] == family):
            twin = next(r for r in runs if r["budget"] == fixed["pairs"])
            assert twin["dofs"] == fixed["dofs"]
            assert twin["e_q_l2"] < fixed["e_q_l2"], (family, fixed["pairs"])
