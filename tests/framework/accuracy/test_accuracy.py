"""The accuracy a user asks for (fixed pairs or a tolerance and a budget) and the error
estimate every run reports, tested against the closed form of the reference scene."""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

import numpy as np
import pytest

from fretbem import simulation
from fretbem.accuracy import modes as accuracy
from fretbem.app import cli
from fretbem.bem.integration import LOOP_CHOICE
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.scenes.spec import SceneFileError, scene_from_dict
from fretbem.testing.caches import forget_assembled

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

ROOT = Path(__file__).parents[3]
EXAMPLES = ROOT / "examples"
FAST = ["--no-figures", "--no-vtk"]
KEYS = ("e_p_max", "e_q_max", "e_p_l2", "e_q_l2")


def ratios(result) -> dict[str, float]:
    """Largest estimate over the steps divided by the largest true error, per key."""
    return {
        k: max(s.estimate[k] for s in result.steps) / max(s.errors[k] for s in result.steps)
        for k in KEYS
    }


def example(name: str, **contact) -> dict:
    data = tomllib.loads((EXAMPLES / name).read_text())
    data["contact"].update(contact)
    return data


def write_scene(tmp_path: Path, data: dict, drop=()) -> str:
    """A scene file from parsed data (tables of scalars and lists), without ``drop`` tables."""

    def value(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return json.dumps(v)
        if isinstance(v, list):
            return "[" + ", ".join(value(x) for x in v) + "]"
        return repr(v)

    lines = []
    for table, keys in data.items():
        if table in drop:
            continue
        lines.append(f"[{table}]")
        lines += [f"{k} = {value(v)}" for k, v in keys.items() if not isinstance(v, dict)]
    path = tmp_path / "scene.toml"
    path.write_text("\n".join(lines) + "\n")
    return str(path)


# -- the scene file ------------------------------------------------------------------------
def test_adaptive_example_reads_into_the_mode():
    scene = scene_from_dict(
        tomllib.loads((EXAMPLES / "cattaneo_mindlin_adaptive.toml").read_text())
    )
    assert accuracy.mode_of(scene) == accuracy.Accuracy(mesh="adaptive", tolerance=0.02, budget=61)
    old = scene_from_dict(tomllib.loads((EXAMPLES / "cattaneo_mindlin.toml").read_text()))
    assert accuracy.mode_of(old) == accuracy.Accuracy()  # fixed, with the estimate
    off = scene_from_dict(example("cattaneo_mindlin.toml", estimate=False))
    assert accuracy.mode_of(off) == accuracy.Accuracy(estimate=False)


@pytest.mark.parametrize(
    ("contact", "message"),
    [
        ({"mesh": "smart"}, r"\[contact\] mesh must be 'fixed' \(pairs\) or 'adaptive'"),
        ({"mesh": "adaptive", "tolerance": 0.0}, r"\[contact\] tolerance is a fraction"),
        ({"mesh": "adaptive", "tolerance": 2.0}, r"0 < tolerance < 1; got 2.0 \(e.g. 0.02"),
        ({"mesh": "adaptive", "tolerance": True}, r"\[contact\] tolerance must be an integer or"),
        ({"mesh": "adaptive", "budget": 3}, r"\[contact\] budget must be >= 5"),
        ({"mesh": "adaptive", "budget": 40.5}, r"\[contact\] budget must be an integer"),
        ({"estimate": "yes"}, r"\[contact\] estimate must be true or false"),
        ({"mesh": "adaptive", "pairs": 61}, r"pairs does not apply to mesh = 'adaptive'.*remove"),
        ({"budget": 81}, r"budget does not apply to mesh = 'fixed'.*set mesh = 'adaptive'"),
        ({"tolerance": 0.01}, r"tolerance does not apply to mesh = 'fixed'"),
        ({"mesh": "adaptive", "estimate": False}, r"estimate does not apply to mesh = 'adaptive'"),
    ],
)
def test_bad_accuracy_keys(contact, message):
    data = example("cattaneo_mindlin_adaptive.toml")
    data["contact"] = {"friction": 0.3, **contact}
    with pytest.raises(SceneFileError, match=message):
        scene_from_dict(data)


@pytest.mark.parametrize(
    ("fields", "message"),
    [
        ({"mesh": "auto"}, "mesh must be one of"),
        ({"tolerance": 1.0}, "0 < tolerance < 1"),
        ({"budget": 2}, "whole number >= 5"),
        ({"mesh": "adaptive", "estimate": False}, "always estimates"),
    ],
)
def test_bad_modes_from_python(fields, message):
    with pytest.raises(accuracy.AccuracyError, match=message):
        accuracy.Accuracy(**fields)


# -- the estimate against the closed form ----------------------------------------------------
def test_fixed_mode_keeps_the_unknowns_and_adds_the_estimate():
    """The estimate solves a second, coarser level; the answer is run()'s, bit for bit.

    Both from cold and under one choice of assembly loops: the numpy and compiled loops
    agree to round-off only (3.3e-11 in these unknowns, measured), as do a point image's
    permuted H and its own assembly (5.5e-11), and which of them serves a run depends on
    what the process assembled and kept before (after tests/framework/scenes both did)."""
    LOOP_CHOICE.reset()
    forget_assembled()
    plain = simulation.run(cattaneo_mindlin(pairs=41))
    forget_assembled()
    result = accuracy.solve(cattaneo_mindlin(pairs=41))
    for a, b in zip(plain.steps, result.steps, strict=True):
        assert np.array_equal(a.unknowns, b.unknowns) and a.iterations == b.iterations
        assert set(b.estimate.as_dict()) == set(KEYS)
    assert result.accuracy.levels == (21, 41) and result.accuracy.estimate_reason is None
    assert plain.steps[1].estimate is None and "no estimate: one level" in plain.table()


#: est / true error (max over the steps) of the fixed mode, pairs 31 to 81 (odd), measured:
#: e_p_max 0.84 to 39.5, e_q_max 0.73 to 7.2, e_p_l2 1.43 to 31.6, e_q_l2 1.06 to 9.6 (the
#: uniform error is a sawtooth in the pair count; docs/how-to/accuracy.rst). Bands with margin:
FIXED_BANDS = {"e_p_max": (0.6, 48.0), "e_q_max": (0.6, 9.0), "e_p_l2": (1.1, 38.0),
               "e_q_l2": (0.85, 12.0)}  # fmt: skip


@pytest.mark.parametrize("pairs", [41, 61, 81])
def test_fixed_estimate_against_the_closed_form(pairs):
    result = accuracy.solve(cattaneo_mindlin(pairs=pairs))
    for key, ratio in ratios(result).items():
        low, high = FIXED_BANDS[key]
        assert low <= ratio <= high, (pairs, key, ratio)


@pytest.mark.slow
@pytest.mark.parametrize("pairs", range(31, 82, 2))
def test_fixed_estimate_against_the_closed_form_every_count(pairs):
    test_fixed_estimate_against_the_closed_form(pairs)


def test_adaptive_estimate_against_the_closed_form():
    """Budget 61: the adaptive levels' estimate reaches the user's result. Measured est / true
    error (max over steps, p and q; the closed form holds the finite-body difference too):
    0.71 to 1.11 before commit d648f6d, 0.28 to 0.53 after it (the estimator of
    fretbem.accuracy.estimate is tested in tests/validation/test_adaptive.py); band with margin."""
    result = accuracy.solve(cattaneo_mindlin(), accuracy.Accuracy(mesh="adaptive", budget=61))
    record = result.accuracy
    assert record["mesh"] == "adaptive" and max(record["levels"]) <= 61
    assert record["levels"][-1] == result.steps[0].x.size and record["seconds"] > 0
    for key, ratio in ratios(result).items():
        assert 0.2 <= ratio <= 2.0, (key, ratio)
    summary = result.summary()
    assert summary["accuracy"]["levels"] == record["levels"]
    assert summary["steps"][2]["est_q_max"] == result.steps[2].estimate["e_q_max"]


# -- no estimate: the reason, never a failure --------------------------------------------------
def test_a_failed_companion_level_is_a_reason():
    def broken(pairs):
        raise ValueError(f"cannot build {pairs} pairs")

    result = accuracy.solve(cattaneo_mindlin(pairs=31), coarse=broken)
    reason = result.accuracy["estimate_reason"]
    assert reason == "the companion level of 16 pairs failed: cannot build 16 pairs"
    assert all(s.estimate is None for s in result.steps)
    assert result.summary()["steps"][1]["est_q_max"] is None
    assert f"no estimate: {reason}" in result.table()


@pytest.mark.parametrize("models", [("bem", "half-plane"), ("half-plane", "half-plane")])
def test_half_plane_bodies_get_the_estimate_and_the_adaptive_mode(tmp_path, capsys, models):
    """The estimate and the adaptive re-mesh reach a body through the Body contract only, so a
    half-plane pad or specimen gets them as a BEM body does (it once had "no estimate")."""
    data = example("cattaneo_mindlin.toml", pairs=61)
    data["pad"]["model"], data["specimen"]["model"] = models
    path = write_scene(tmp_path, data)
    assert cli.main(["run", path, "--out", str(tmp_path / "out"), *FAST]) == 0
    assert "est from the companion level of 31 pairs" in capsys.readouterr().out
    steps = json.loads((tmp_path / "out" / "summary.json").read_text())["steps"]
    exact_model = models == ("half-plane", "half-plane")  # the closed form's own model
    for step in steps[1:]:
        assert step["est_q_max"] > 0
        if exact_model:  # the fixed-mode estimate is a rarely-low bound (measured 2.3-2.6x)
            assert step["est_q_max"] >= 0.5 * step["e_q_max"]
    if not exact_model:
        return  # adaptive on a BEM pad over a half-plane: the open issue on non-matching faces
    data["contact"] = {"friction": 0.3, "mesh": "adaptive", "budget": 41}
    path = write_scene(tmp_path, data)
    assert cli.main(["run", path, "--out", str(tmp_path / "out2"), *FAST]) == 0
    steps = json.loads((tmp_path / "out2" / "summary.json").read_text())["steps"]
    for step in steps[1:]:  # measured 0.46 % against an estimate of 0.31 %
        assert step["e_q_max"] < 0.01
        assert 0.3 * step["e_q_max"] <= step["est_q_max"] <= 3.0 * step["e_q_max"]


def test_rig_scene_reports_the_estimate(tmp_path, capsys):
    """The fretting rig (flat specimen on ends, bulk stress) without its stress and fatigue."""
    path = write_scene(tmp_path, example("fretting_rig.toml"), drop=("stress", "fatigue"))
    assert cli.main(["run", path, "--out", str(tmp_path / "out"), *FAST]) == 0
    assert "est from the companion level of 31 pairs" in capsys.readouterr().out
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["accuracy"]["levels"] == [31, 61]
    assert all(0 < step["est_q_l2"] < 1 for step in summary["steps"][1:])


@pytest.mark.slow
@pytest.mark.parametrize(
    "name", ["fretting_rig.toml", "fretting_rig_ti64.toml", "cattaneo_mindlin.toml"]
)
def test_examples_end_to_end_with_the_estimate(name, tmp_path, capsys):
    out = tmp_path / "out"
    assert cli.main(["run", str(EXAMPLES / name), "--out", str(out), *FAST]) == 0
    assert "est from the companion level of 31 pairs" in capsys.readouterr().out
    summary = json.loads((out / "summary.json").read_text())
    assert all(step["est_p_max"] is not None for step in summary["steps"])


# -- the command -----------------------------------------------------------------------------
def test_run_adaptive_scene_file(tmp_path, capsys):
    out = tmp_path / "out"
    path = str(EXAMPLES / "cattaneo_mindlin_adaptive.toml")
    assert cli.main(["run", path, "--out", str(out), *FAST]) == 0
    printed = capsys.readouterr().out
    assert re.search(r"adaptive mesh, levels 31(, \d+)* pairs; all levels", printed)
    assert "e_q max%     est" in printed
    summary = json.loads((out / "summary.json").read_text())
    assert summary["accuracy"]["mesh"] == "adaptive" and summary["accuracy"]["budget"] == 61
    assert summary["scene"]["pairs"] == summary["accuracy"]["levels"][-1] <= 61
    for step in summary["steps"]:
        assert {f"est{k[1:]}" for k in KEYS} <= set(step)
        assert step["est_q_max"] is not None
    units = json.loads((out / "units.json").read_text())["summary.json"]
    assert units["est_p_max, est_p_l2"]["unit"] == "fraction of p0"
    assert units["est_q_max, est_q_l2"]["unit"] == "fraction of f p0"
    assert "accuracy" in units


def test_run_options_override_the_scene(tmp_path, capsys):
    """--mesh fixed --pairs 31 on the adaptive file; --no-estimate skips the second level."""
    path = str(EXAMPLES / "cattaneo_mindlin_adaptive.toml")
    args = ["run", path, "--mesh", "fixed", "--pairs", "31", "--no-estimate", *FAST]
    assert cli.main([*args, "--out", str(tmp_path / "out")]) == 0
    assert "fixed mesh, levels 31 pairs" in capsys.readouterr().out
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["accuracy"]["estimate_reason"] == "not asked (estimate = false)"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--budget", "41"], "--budget apply to the adaptive mesh; add --mesh adaptive"),
        (["--tolerance", "0.01"], "--tolerance apply to the adaptive mesh"),
        (["--mesh", "adaptive", "--pairs", "41"], "an adaptive run takes --budget"),
        (["--mesh", "adaptive", "--no-estimate"], "--no-estimate applies to the fixed mesh"),
    ],
)
def test_conflicting_options_are_refused_before_running(
    patch_run, args, message, tmp_path, monkeypatch, capsys
):
    def forbidden(*a, **k):
        raise AssertionError("the run started before the bad option was refused")

    patch_run(forbidden)
    path = str(EXAMPLES / "cattaneo_mindlin.toml")
    assert cli.main(["run", path, *args, "--out", str(tmp_path / "o"), *FAST]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and message in err[0], err


def test_bad_tolerance_option(capsys):
    with pytest.raises(SystemExit) as info:
        cli.main(["demo", "--mesh", "adaptive", "--tolerance", "5"])
    assert info.value.code == 2
    assert "0 < tolerance < 1" in capsys.readouterr().err


def test_solve_scene_from_python():
    scene = scene_from_dict(example("cattaneo_mindlin.toml", pairs=31))
    result, reason = accuracy.solve_scene(scene)
    assert reason is None and result.accuracy["levels"] == [16, 31]
    assert result.steps[2].estimate["e_q_max"] > 0


def test_adaptive_levels_past_61_pairs_need_no_caution():
    """Budget 81 with a tolerance no estimate meets goes past 61 pairs; the error against a
    converged BEM falls there (tests/validation/test_adaptive.py), so no caution is shown."""
    result = accuracy.solve(
        cattaneo_mindlin(pairs=31), accuracy.Accuracy(mesh="adaptive", tolerance=1e-6, budget=81)
    )
    assert max(result.accuracy["levels"]) == 81
    # no caution about the levels past 61 pairs; the missed tolerance is said (issue 24)
    caution = result.accuracy.caution
    assert "61" not in caution and "verified" not in caution
    assert caution.startswith("the adaptive mesh stopped at 81 pairs (its budget)")
    assert "above the tolerance of 0.0001 %" in result.table()


def test_settling_measure_leaves_out_a_knot_crowded_against_its_neighbour():
    """A knot whose move passes the middle of the gap to its neighbour cannot settle on its
    level: the measure that picks the kept re-solve leaves it out, the caution's does not."""
    from fretbem.accuracy.adaptive import _residual

    positions = np.array([-0.3, -0.2, -0.199, 0.3])
    scale = np.full(4, 0.01)
    # the knot at -0.2 wants 0.05 toward -0.199 (past the middle at -0.1995): crowded
    moves = np.array([0.0005, 0.05, 0.0, -0.001])
    # the largest free move: 0.001 over a spacing of 0.01
    assert _residual(positions, moves, scale) == pytest.approx(0.1)
    assert _residual(positions, moves, scale, crowded=True) == pytest.approx(5.0)
    # a move short of the middle counts as before
    free = np.array([0.0005, 0.0004, 0.0, -0.001])
    assert _residual(positions, free, scale) == pytest.approx(0.1)
    assert _residual(positions, free, scale, crowded=True) == pytest.approx(0.1)
    assert _residual(np.zeros(0), np.zeros(0), np.zeros(0)) == 0.0
