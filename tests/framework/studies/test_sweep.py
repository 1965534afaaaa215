"""Parameter sweeps: description, reuse of the condensed problem, store, resume, Dask."""

from __future__ import annotations

import copy
import json
import math

import numpy as np
import pytest

from fretbem.studies.sweep.cases import (
    TIMING_COLUMNS,
    build_simulation,
    case_loading,
    representative,
    run_batch,
    step_metrics,
)
from fretbem.studies.sweep.spec import (
    Parameter,
    SweepSpec,
    SweepSpecError,
    changes_condensation,
    copy_tree,
    load_sweep,
    set_path,
    split_path,
)
from fretbem.testing.scenes import SMALL_SCENE

pd = pytest.importorskip("pandas")

#: a small reference-type scene (coarse mesh, 21 pairs): fast to assemble
SCENE = SMALL_SCENE
CYCLE = [0.0, 1.0, 0.0, -1.0, 0.0]


def write_scene(path):
    """SCENE as a scene file at ``path``."""
    path.write_text(
        "\n".join(
            f"[{table}]\n" + "\n".join(f"{k} = {json.dumps(v)}" for k, v in keys.items())
            for table, keys in SCENE.items()
        )
    )


def _results(table):
    """The table without the columns that differ from run to run."""
    return table.drop(columns=[c for c in TIMING_COLUMNS if c in table])


def test_importing_the_sweep_does_not_import_dask_or_pandas():
    import subprocess
    import sys

    code = (
        "import sys, fretbem, fretbem.studies.sweep, fretbem.studies.sweep.maps\n"
        "heavy = [m for m in ('dask', 'distributed', 'pandas', 'pyarrow', 'xarray') "
        "if m in sys.modules]\n"
        "assert not heavy, heavy\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True)


# --- description ----------------------------------------------------------------------------


def test_paths_split_set_and_classify():
    assert split_path("load.Q[1]") == ["load", "Q", 1]
    scene = copy.deepcopy(SCENE)
    set_path(scene, "load.Q[1]", 5.0)
    set_path(scene, "contact.solver.tolerance", 1e-9)  # missing tables are created
    assert scene["load"]["Q"] == [0.0, 5.0, 0.0, -18.0, 0.0]
    assert scene["contact"]["solver"] == {"tolerance": 1e-9}
    for path in ("load.Q", "load.P", "load.Q[3]", "contact.friction", "load.bulk"):
        assert not changes_condensation(path), path
    for path in ("geometry.radius", "material.E", "scene.pairs", "pad.radius", "contact.basis"):
        assert changes_condensation(path), path
    for bad in ("", "load..Q", "load.Q[x]", "1load"):
        with pytest.raises(SweepSpecError):
            split_path(bad)
    with pytest.raises(SweepSpecError, match="no item"):
        set_path(scene, "load.Q[9]", 1.0)


def test_case_scenes_are_independent_copies_of_the_scene():
    """Planning copies the scene as a tree: each case's tables and lists its own (what
    copy.deepcopy gave), anything but plain TOML values deep-copied; a parsed path is the
    caller's to change."""
    spec = SweepSpec.from_mapping(SCENE, {"load.Q": {"values": [5.0, 6.0], "pattern": CYCLE}})
    first, second = (case.scene for case in spec.cases())
    assert first == {
        **copy.deepcopy(SCENE),
        "load": {**SCENE["load"], "Q": [5.0 * w for w in CYCLE]},
    }
    first["material"]["E"] = -1.0
    first["load"]["P"] = -1.0
    assert second["material"] == SCENE["material"] and second["load"]["P"] == SCENE["load"]["P"]
    assert spec.scene == SCENE
    odd = {"points": (np.array([1.0, 2.0]), [1, {"a": "b"}]), "flag": None, "n": 3, "on": True}
    copied = copy_tree(odd)
    assert copied["points"][0] is not odd["points"][0] and copied["points"][1] == [1, {"a": "b"}]
    assert copied["points"][1] is not odd["points"][1] and copied["flag"] is None
    parts = split_path("load.Q[1]")
    parts.append("x")
    assert split_path("load.Q[1]") == ["load", "Q", 1]


def test_values_ranges_patterns_product_and_zip():
    spec = SweepSpec.from_mapping(
        SCENE,
        {
            "load.Q": {"start": 0.0, "stop": 20.0, "num": 3, "pattern": CYCLE},
            "contact.friction": [0.3, 0.5],
            "geometry.radius": {"values": [50.0, 70.0]},
        },
    )
    cases = spec.cases()
    assert len(cases) == 12
    assert cases[1].values == {"load.Q": 0.0, "contact.friction": 0.3, "geometry.radius": 70.0}
    assert cases[-1].scene["load"]["Q"] == [0.0, 20.0, 0.0, -20.0, 0.0]
    assert cases[-1].scene["geometry"]["radius"] == 70.0
    assert SCENE["load"]["Q"][1] == 18.0  # the base scene is untouched
    # only the radius changes the condensed problem: 2 groups of 6 cases
    assert [len(g) for g in spec.groups().values()] == [6, 6]
    zipped = SweepSpec.from_mapping(SCENE, {"load.P": [90, 100], "load.Q[1]": [5, 6]}, mode="zip")
    assert [c.values for c in zipped.cases()] == [
        {"load.P": 90, "load.Q[1]": 5},
        {"load.P": 100, "load.Q[1]": 6},
    ]
    with pytest.raises(SweepSpecError, match="same number"):
        SweepSpec.from_mapping(SCENE, {"load.P": [1, 2], "load.Q[1]": [1]}, mode="zip")
    with pytest.raises(SweepSpecError, match="start, stop, num"):
        Parameter.parse("load.P", {"start": 1, "stop": 2})
    with pytest.raises(SweepSpecError, match="num"):
        Parameter.parse("load.P", {"start": 1, "stop": 2, "num": 0})
    with pytest.raises(SweepSpecError, match="no values"):
        Parameter.parse("load.P", [])
    with pytest.raises(SweepSpecError, match="mode"):
        SweepSpec.from_mapping(SCENE, {"load.P": [1]}, mode="cartesian")


def test_sweep_file_with_scene_file_and_inline_scene(tmp_path):
    import tomllib

    (tmp_path / "scene.toml").write_text("[contact]\nfriction = 0.4\n[load]\nP = 80.0\n")
    (tmp_path / "a.toml").write_text(
        '[sweep]\nscene = "scene.toml"\nmode = "zip"\n'
        '[parameters]\nload.P = [70.0, 90.0]\n"contact.friction" = {values = [0.3, 0.4]}\n'
        '[[maps]]\nx = "load.P"\ny = "contact.friction"\n'
    )
    spec = load_sweep(tmp_path / "a.toml")
    assert spec.paths == ("load.P", "contact.friction")
    assert spec.scene == tomllib.loads((tmp_path / "scene.toml").read_text())
    assert spec.options["maps"] == [{"x": "load.P", "y": "contact.friction"}]
    (tmp_path / "b.toml").write_text(
        '[sweep.scene.load]\nP = 80.0\n[parameters]\n"load.P" = [1.0]\n'
    )
    assert load_sweep(tmp_path / "b.toml").scene == {"load": {"P": 80.0}}
    (tmp_path / "c.toml").write_text('[sweep]\nscene = "scene.toml"\nsceen = 1\n')
    with pytest.raises(SweepSpecError, match="sceen"):
        load_sweep(tmp_path / "c.toml")
    (tmp_path / "e.toml").write_text(
        '[sweep]\nscene = "scene.toml"\n[parameters]\n"load.P" = [1.0]\n[fatige]\nx = 1\n'
    )
    with pytest.raises(SweepSpecError, match="fatige"):
        load_sweep(tmp_path / "e.toml")
    (tmp_path / "d.toml").write_text('[sweep]\nscene = "scene.toml"\n')
    with pytest.raises(SweepSpecError, match=r"\[parameters\]"):
        load_sweep(tmp_path / "d.toml")


def test_the_fretting_map_example_parses():
    from pathlib import Path

    from fretbem.studies.sweep.outputs import resolve_all

    spec = load_sweep(Path(__file__).parents[3] / "examples" / "fretting_map.toml")
    assert spec.paths == ("load.P", "load.Q") and len(spec.cases()) == 144
    assert len(spec.groups()) == 1  # loads only: one assembly
    assert [m.get("column", "regime") for m in spec.options["maps"]] == [
        "regime",
        "stick_width.B",
        "sxx_max",
    ]
    resolve_all(spec.options["outputs"])
    case_loading(spec.cases()[-1].scene)  # the scene file reads each case


# --- reuse ------------------------------------------------------------------------------------


def test_reused_problem_gives_the_fresh_solution_and_theory():
    """Cases solved on one condensed problem equal case-by-case runs; stick width vs theory."""
    from fretbem.simulation import run

    spec = SweepSpec.from_mapping(
        SCENE,
        {"load.Q": {"values": [9.0, 24.0], "pattern": CYCLE}, "contact.friction": [0.3, 0.45]},
    )
    cases = spec.cases()
    rows = run_batch(
        representative([c.scene for c in cases]), [(c.index, c.values, c.scene) for c in cases]
    )
    assert [r["status"] for r in rows] == ["ok", "ok", "ok", "ok"]
    assert rows[0]["assembly_seconds"] > 0 and rows[1]["assembly_seconds"] == 0
    for case, row in zip(cases, rows, strict=True):
        fresh = run(build_simulation(case.scene))
        for step in fresh.steps:
            for key, value in step_metrics(step).items():
                got = row[f"{key}.{step.name}"]
                if isinstance(value, float):
                    assert got == pytest.approx(value, rel=1e-9, abs=1e-12), (key, step.name)
                else:
                    assert got == value, (key, step.name)
        # Cattaneo-Mindlin: stick zone 2c = 2a sqrt(1 - Q / (f P)) at the first peak
        loading = case_loading(case.scene)
        a = loading.reference.hertz.half_width
        q, f = case.values["load.Q"], case.values["contact.friction"]
        # the extent of the stick nodes misses at most one pair spacing h at each edge
        # (measured: up to 1.4 h at 21 and 61 pairs)
        x = fresh.steps[0].x
        h = abs(x[-1] - x[0]) / (len(x) - 1)
        assert row["stick_width.B"] == pytest.approx(
            2 * a * math.sqrt(1 - q / (f * 100.0)), abs=2.0 * h
        )


def test_two_body_scene_with_bulk_load_reuses_the_problem():
    """The two-body format: Q and sigma_B cases on one problem equal case-by-case runs."""
    pytest.importorskip("fretbem.contact.law")
    from pathlib import Path

    import tomllib

    from fretbem.simulation import run

    rig = Path(__file__).parents[3] / "examples" / "fretting_rig.toml"
    scene = tomllib.loads(rig.read_text())
    scene["contact"]["pairs"] = 21
    spec = SweepSpec.from_mapping(
        scene,
        {
            "load.Q": {"values": [20.0, 45.0], "pattern": CYCLE},
            "load.bulk": {"values": [0.0, 10.0], "pattern": CYCLE},
        },
    )
    cases = spec.cases()
    assert len(spec.groups()) == 1
    rep = representative([c.scene for c in cases])
    assert rep["load"]["bulk"] == [1.0] * 5  # a bulk column for the loaded cases
    rows = run_batch(rep, [(c.index, c.values, c.scene) for c in cases])
    lemke = copy.deepcopy(cases[3].scene)
    lemke["contact"]["solver"] = "lemke"  # the solver is per case too
    assert type(case_loading(lemke).solver).__name__ == "LemkeSolver"
    (row,) = run_batch(rep, [(3, cases[3].values, lemke)])
    for key in ("p_max.B", "q_max.D", "stick_width.B"):
        assert row[key] == pytest.approx(rows[3][key], rel=1e-6, abs=1e-9)
    for case, row in zip(cases, rows, strict=True):
        assert row["status"] == "ok", row["error"]
        for step in run(build_simulation(case.scene)).steps:
            for key, value in step_metrics(step).items():
                got = row[f"{key}.{step.name}"]
                assert got == (pytest.approx(value, abs=1e-9) if key != "regime" else value)


def test_gross_slip_refused_and_failing_case_recorded():
    spec = SweepSpec.from_mapping(SCENE, {"load.Q": {"values": [10.0, 30.0], "pattern": CYCLE}})
    cases = spec.cases()
    rows = run_batch(
        representative([c.scene for c in cases]), [(c.index, c.values, c.scene) for c in cases]
    )
    assert rows[0]["regime"] == "partial slip" and rows[0]["regime.A"] == "full stick"
    assert rows[1]["status"] == "refused" and rows[1]["regime"] == "gross slip"
    assert rows[1]["regime.B"] == "gross slip" and rows[1]["regime.A"] == "not run"
    bad = copy.deepcopy(SCENE)
    bad["geometry"]["radius"] = -5.0
    rows = run_batch(representative([bad]), [(0, {"geometry.radius": -5.0}, bad)])
    assert rows[0]["status"] == "error" and "radius" in rows[0]["error"]


def test_output_functions_add_columns():
    from fretbem.studies.sweep.run import sweep

    spec = SweepSpec.from_mapping(SCENE, {"load.Q": {"values": [9.0], "pattern": CYCLE}})
    (case,) = spec.cases()
    name = "fretbem.studies.sweep.outputs:reference_errors"
    (row,) = run_batch(representative([case.scene]), [(0, case.values, case.scene)], None, [name])
    assert row["status"] == "ok"
    # 21 pairs, measured: e_p 5.1 % of p0 (zone edges), e_q 5.1 % at B, 11.0 % at C of f p0
    assert row["e_q_max.A"] < 1e-10  # no tangential load yet: q = 0 exactly
    assert row["e_p_max.B"] == pytest.approx(0.051, abs=0.005)
    assert row["e_q_max.C"] == pytest.approx(0.110, abs=0.01)
    # only registered outputs: a sweep file cannot call any installed function
    for name in ("nope", "fretbem:nope", "os:getcwd", "builtins:exit"):
        with pytest.raises(SweepSpecError, match="not a registered sweep output"):
            sweep(SCENE, {"load.P": [90.0]}, out="unused", serial=True, outputs=[name])


def test_surface_stress_output_reuses_the_evaluator():
    """sxx_max per step equals a fresh evaluation of each case; near the closed form."""
    pytest.importorskip("fretbem.contact.law")  # the stress evaluator needs the issue-9 contact API
    evaluate = pytest.importorskip("fretbem.stress.evaluate")
    from fretbem.simulation import run
    from fretbem.stress.closed_form import surface_sigma_xx

    spec = SweepSpec.from_mapping(SCENE, {"load.Q": {"values": [9.0, 18.0], "pattern": CYCLE}})
    cases = spec.cases()
    name = "fretbem.studies.sweep.outputs:surface_stress"
    rows = run_batch(
        representative([c.scene for c in cases]),
        [(c.index, c.values, c.scene) for c in cases],
        None,
        [name],
    )
    for case, row in zip(cases, rows, strict=True):
        fresh = run(build_simulation(case.scene))
        points = fresh.simulation.pair.pairing().points
        sxx = evaluate.StressEvaluator(fresh, points).steps()[:, :, 0]
        for step, values in zip(fresh.steps, sxx, strict=True):
            assert row[f"sxx_max.{step.name}"] == pytest.approx(values.max(), rel=1e-9, abs=1e-9)
        # Cattaneo-Mindlin surface sigma_xx at the same points (half-plane closed form):
        # measured differences 0.16-0.17 f p0 at 21 pairs (the shear error near the edges)
        hertz = case_loading(case.scene).reference.hertz
        a, p0, f, q = hertz.half_width, hertz.peak_pressure, 0.3, case.values["load.Q"]
        exact = surface_sigma_xx(
            fresh.steps[1].x, a=a, p0=p0, f=f, c=a * math.sqrt(1 - q / (f * 100.0))
        )
        assert row["sxx_max.B"] == pytest.approx(exact.max(), abs=0.2 * f * p0)
        assert row["sxx_max"] >= row["sxx_max.B"]


@pytest.mark.slow
def test_fatigue_output_columns():
    """Hot spot at the trailing contact edge; the SWT parameter grows with Q."""
    pytest.importorskip("fretbem.contact.law")
    pytest.importorskip("fretbem.fatigue.from_simulation")
    spec = SweepSpec.from_mapping(SCENE, {"load.Q": {"values": [9.0, 18.0], "pattern": CYCLE}})
    cases = spec.cases()
    extras = {"fatigue": {"material": "Al 7050-T7451", "methods": ["swt"], "in_plane_only": True}}
    rows = run_batch(
        representative([c.scene for c in cases]),
        [(c.index, c.values, c.scene) for c in cases],
        None,
        ["fretbem.studies.sweep.outputs:fatigue"],
        extras,
    )
    assert [r["status"] for r in rows] == ["ok", "ok"], [r["error"] for r in rows]
    a = case_loading(cases[0].scene).reference.hertz.half_width
    for row in rows:
        assert abs(row["swt.x"]) == pytest.approx(a, rel=0.05) and row["swt.depth"] == 0.0
    assert rows[1]["swt.parameter"] > rows[0]["swt.parameter"] > 0


# --- store, resume, Dask ----------------------------------------------------------------------

PARAMETERS = {
    "geometry.radius": [60.0, 70.0, -1.0],  # the last radius fails: recorded, not fatal
    "load.Q": {"values": [0.0, 12.0, 40.0], "pattern": CYCLE},
    "contact.friction": [0.3, 0.5],
}


def _check_table(table):
    assert len(table) == 18 and list(table["case"]) == list(range(18))
    status = table.set_index("case")["status"]
    assert set(status[table["geometry.radius"] == -1.0]) == {"error"}
    built = table[table["geometry.radius"] > 0]
    refused = built[(built["load.Q"] == 40.0) & (built["contact.friction"] == 0.3)]
    assert set(refused["status"]) == {"refused"} and set(refused["regime"]) == {"gross slip"}
    full = table[(table["load.Q"] == 0.0) & (table["status"] == "ok")]
    assert set(full["regime"]) == {"full stick"}


def test_serial_sweep_store_and_resume(tmp_path):
    from fretbem.studies.sweep.cases import build_simulation
    from fretbem.studies.sweep.run import sweep
    from fretbem.studies.sweep.store import SweepStoreError

    # read by the scene reader first, a bad value is refused before any solve, by name
    with pytest.raises(SweepSpecError, match=r"'geometry.radius' = -1.0: .*radius must be > 0"):
        sweep(SCENE, PARAMETERS, out=tmp_path / "refused", serial=True)
    assert not (tmp_path / "refused").exists()
    # a group whose bodies fail to build (here: a builder that reads no value first) fails
    # its cases as rows, not the sweep
    whole = sweep(SCENE, PARAMETERS, out=tmp_path / "whole", serial=True, batch=4,
                  builder=build_simulation)  # fmt: skip
    _check_table(whole.table)
    assert whole.summary.stored == 18 and whole.summary.groups == 3
    assert "6 error" in str(whole.summary) and "gross slip" in str(whole.summary)
    # interrupted after 2 tasks, then completed: the same table
    part = sweep(SCENE, PARAMETERS, out=tmp_path / "part", serial=True, batch=4, limit=2,
                 builder=build_simulation)  # fmt: skip
    assert part.summary.stopped and part.summary.stored == 6  # batches of 4 + 2 in group 1
    (tmp_path / "part" / ".cases-junk.parquet.tmp").write_bytes(b"half a file")  # killed write
    rest = sweep(SCENE, PARAMETERS, out=tmp_path / "part", serial=True, batch=5,
                 builder=build_simulation)  # fmt: skip
    assert rest.summary.skipped == 6 and rest.summary.solved_now == 12
    pd.testing.assert_frame_equal(_results(rest.table), _results(whole.table))
    again = sweep(SCENE, PARAMETERS, out=tmp_path / "part", serial=True, builder=build_simulation)
    assert again.summary.solved_now == 0 and again.summary.tasks == 0
    (tmp_path / "notes").mkdir()
    (tmp_path / "notes" / "thesis.tex").write_text("precious")
    with pytest.raises(SweepStoreError, match="not a sweep store"):
        sweep(SCENE, PARAMETERS, out=tmp_path / "notes", serial=True, builder=build_simulation)
    assert (tmp_path / "notes" / "thesis.tex").read_text() == "precious"
    with pytest.raises(SweepStoreError, match="another sweep"):
        sweep(SCENE, {"load.P": [90.0]}, out=tmp_path / "part", serial=True)
    manifest = json.loads((tmp_path / "part" / "manifest.json").read_text())
    assert manifest["paths"] == list(PARAMETERS)


def test_store_frames_equal_the_chunks_read_again(tmp_path):
    """The table made from the frames kept at writing equals the one read from the files
    (values and dtypes), for the kinds of value a row holds: numbers, whole numbers with a
    gap, text with a gap, an all-empty column, flags, numpy scalars and lists."""
    from fretbem.studies.sweep.store import SweepStore, read_table

    store = SweepStore(tmp_path / "s", {"fingerprint": "f", "paths": ["load.Q"]})
    chunks = [
        [{"case": 0, "load.Q": 1.0, "status": "ok", "error": None, "n": 3, "flag": True,
          "x": np.float32(0.5), "u": np.int64(7), "v": [1.0, 2.0]},
         {"case": 1, "load.Q": float("nan"), "status": "error", "error": "diverged",
          "n": None, "flag": False, "x": np.float32(1.5), "u": np.int64(8), "v": []}],
        [{"case": 2, "load.Q": 2.0, "status": "ok", "error": None, "n": 4, "flag": True,
          "x": np.float32(2.5), "u": np.int64(9), "v": [3.0]}],
    ]  # fmt: skip
    for rows in chunks:
        store.write(rows)
    kept, read = store.table(), read_table(tmp_path / "s")
    pd.testing.assert_frame_equal(kept, read, check_exact=True)
    assert list(kept["case"]) == [0, 1, 2] and kept["n"].isna().tolist() == [False, True, False]


def test_resume_after_the_process_is_killed(tmp_path):
    """SIGKILL a running sweep after two stored chunks; the re-run completes the same table."""
    import os
    import signal
    import subprocess
    import sys
    import time

    from fretbem.studies.sweep.run import sweep

    parameters = {
        "load.Q": {"start": 0.0, "stop": 27.0, "num": 30, "pattern": CYCLE},
        "contact.friction": [0.3, 0.5],
    }
    out = tmp_path / "killed"
    script = (
        "import json, sys\n"
        "from fretbem.studies.sweep import sweep\n"
        "scene, parameters, out = json.loads(sys.argv[1])\n"
        "sweep(scene, parameters, out=out, serial=True, batch=1, progress=False)\n"
    )
    argument = json.dumps([SCENE, parameters, str(out)])
    process = subprocess.Popen([sys.executable, "-c", script, argument])
    try:
        deadline = time.monotonic() + 60
        while len(list(out.glob("cases-*.parquet"))) < 2 and time.monotonic() < deadline:
            assert process.poll() is None, "the sweep ended before it could be killed"
            time.sleep(0.005)
        os.kill(process.pid, signal.SIGKILL)
    finally:
        process.wait()
    assert process.returncode == -signal.SIGKILL
    stored = len(list(out.glob("cases-*.parquet")))
    assert 2 <= stored < 60
    rest = sweep(SCENE, parameters, out=out, serial=True, batch=7)
    assert rest.summary.skipped == stored and rest.summary.stored == 60
    whole = sweep(SCENE, parameters, out=tmp_path / "whole", serial=True)
    pd.testing.assert_frame_equal(_results(rest.table), _results(whole.table))


def test_local_cluster_equals_serial_and_resumes(tmp_path):
    """Two process workers; stopped after one task and re-run: same table as serial."""
    pytest.importorskip("distributed")
    from dask.distributed import Client

    from fretbem.studies.sweep.cases import build_simulation
    from fretbem.studies.sweep.run import _local_cluster, sweep

    serial = sweep(SCENE, PARAMETERS, out=tmp_path / "serial", serial=True,
                   builder=build_simulation)  # fmt: skip
    with _local_cluster(2) as cluster:  # a running scheduler, named by its address
        first = sweep(
            SCENE,
            PARAMETERS,
            out=tmp_path / "dask",
            scheduler=cluster.scheduler_address,
            batch=3,
            limit=2,
            builder=build_simulation,
        )
        assert first.summary.mode == "dask" and first.summary.stopped
        assert first.summary.stored == 6  # two tasks of 3 cases
        with Client(cluster) as client:
            assert len(client.scheduler_info()["workers"]) == 2  # still up: not ours to close
    # completed on a cluster of its own (started while this process solves the first tasks)
    rest = sweep(SCENE, PARAMETERS, out=tmp_path / "dask", engine="dask", workers=2, batch=3,
                 builder=build_simulation)  # fmt: skip
    assert rest.summary.stored == 18 and rest.summary.skipped == 6
    assert rest.summary.workers == 2 and rest.summary.mode == "dask"
    assert rest.table["worker"].nunique() >= 2  # cases solved in several processes
    _check_table(rest.table)
    pd.testing.assert_frame_equal(_results(rest.table), _results(serial.table))


def _killing_builder(scene):
    """Builds like the default, but a Dask worker building the radius-60 group dies."""
    import os

    from distributed import get_worker

    try:
        get_worker()
    except ValueError:  # not on a worker
        pass
    else:
        if scene["geometry"]["radius"] == 60.0:
            os._exit(1)
    return build_simulation(scene)


@pytest.mark.slow
def test_tasks_lost_with_their_workers_are_left_for_the_next_run(tmp_path):
    import sys

    import cloudpickle
    import dask
    from dask.distributed import Client

    from fretbem.studies.sweep.run import _local_cluster, sweep

    cloudpickle.register_pickle_by_value(sys.modules[__name__])
    with dask.config.set({"distributed.scheduler.allowed-failures": 0}):
        with _local_cluster(2) as cluster, Client(cluster) as client:
            first = sweep(
                SCENE, PARAMETERS, out=tmp_path, client=client, batch=3, builder=_killing_builder
            )
    assert first.summary.lost and "KilledWorker" in first.summary.lost[0]
    assert "lost by the cluster" in str(first.summary)
    assert set(first.table["geometry.radius"]) <= {70.0, -1.0}  # nothing of radius 60 stored
    # the default builder, named: the up-front value check would refuse the failing radius
    rest = sweep(SCENE, PARAMETERS, out=tmp_path, serial=True, batch=3, builder=build_simulation)
    whole = sweep(
        SCENE, PARAMETERS, out=tmp_path.parent / "whole-lost", serial=True, builder=build_simulation
    )
    pd.testing.assert_frame_equal(_results(rest.table), _results(whole.table))


def test_maps_are_drawn(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    from fretbem.studies.sweep.maps import column_map, draw_maps, regime_map
    from fretbem.studies.sweep.run import sweep

    result = sweep(
        SCENE,
        {"load.P": [80.0, 120.0], "load.Q": {"values": [0.0, 20.0, 30.0], "pattern": CYCLE}},
        out=tmp_path / "map",
        serial=True,
    )
    ax = regime_map(result.table, "load.P", "load.Q")
    assert any(line.get_label() == "|Q| = f P" for line in ax.get_lines())
    mesh = ax.collections[0].get_array()
    # rows Q = 0, 20, 30; columns P = 80, 120: gross slip where Q >= 0.3 P
    assert np.array_equal(np.asarray(mesh).reshape(3, 2), [[0, 0], [1, 1], [2, 1]])
    column_map(result.table, "stick_width.B", "load.P", "load.Q")
    with pytest.raises(SweepSpecError, match="no output column"):
        column_map(result.table, "life", "load.P", "load.Q")
    files = draw_maps(result.table, result.spec, tmp_path / "map")
    assert [f.name for f in files] == ["map-regime-load_P-load_Q.png"]
    assert files[0].stat().st_size > 10_000


def test_maps_select_with_where_and_draw_the_boundary_on_any_axes():
    from fretbem.studies.sweep.maps import regime_map

    rows = []
    for f in (0.3, 0.5):
        for q in (10.0, 20.0, 40.0):
            for p in (50.0, 100.0):
                regime = "gross slip" if q >= f * p else "partial slip"
                rows.append(
                    {
                        "load.P": p,
                        "load.Q": q,
                        "contact.friction": f,
                        "regime": regime,
                        "P_max": p,
                        "Q_peak": q,
                        "friction": f,
                    }
                )
    table = pd.DataFrame(rows)
    with pytest.raises(SweepSpecError, match="where"):
        regime_map(table, "load.P", "load.Q")
    ax = regime_map(table, "load.P", "load.Q", where={"contact.friction": 0.5})
    codes = np.asarray(ax.collections[0].get_array()).reshape(3, 2)
    assert np.array_equal(codes, [[1, 1], [1, 1], [2, 1]])  # Q = 40 >= 0.5 P = 25: gross slip
    # friction against Q at P = 100: the boundary Q = f P is a line there too
    ax = regime_map(table, "contact.friction", "load.Q", where={"load.P": 100.0})
    assert any(line.get_label() == "|Q| = f P" for line in ax.get_lines())
    with pytest.raises(SweepSpecError, match="no column"):
        regime_map(table, "load.P", "geometry.radius")


def test_sweep_command(tmp_path, capsys):
    from fretbem.studies.sweep.run import sweep_command

    write_scene(tmp_path / "scene.toml")
    sweep_file = tmp_path / "s.toml"
    sweep_file.write_text(
        '[sweep]\nscene = "scene.toml"\n[parameters]\n"load.P" = [90.0, 110.0]\n'
        '"load.Q" = {values = [10.0, 40.0], pattern = [0, 1, 0, -1, 0]}\n'
    )
    out = tmp_path / "out"
    assert sweep_command([str(sweep_file), "--serial", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "4 cases in 1 condensation groups" in text and "2 refused" in text
    assert (out / "map-regime-load_P-load_Q.png").exists()
    assert sweep_command([str(tmp_path / "missing.toml"), "--serial"]) == 2
    assert "cannot read" in capsys.readouterr().err


def test_default_engine_stays_serial_when_the_work_is_small_next_to_a_parallel_start(
    tmp_path, monkeypatch
):
    """A sweep whose estimated work is below the parallel engine's threshold (forked
    processes: POOL_MIN_SECONDS; a Dask cluster: PARALLEL_MIN_STARTS cluster starts) never
    starts one: the default engine solves it in this process (the same table)."""
    pd = pytest.importorskip("pandas")
    from fretbem.studies.sweep import run as sweep_run
    from fretbem.studies.sweep.cases import build_simulation
    from fretbem.studies.sweep.probe import PROBE_CASES, WorkProbe, queued_work
    from fretbem.studies.sweep.run import sweep

    # above this sweep's work on any machine, however loaded (it is about 1 s)
    monkeypatch.setattr(sweep_run, "POOL_MIN_SECONDS", 1e6)
    monkeypatch.setattr(sweep_run, "CLUSTER_START_SECONDS", 1e6)

    # the builder keeps the failing radius a failing group (rows), as in the tests above
    serial = sweep(
        SCENE, PARAMETERS, out=tmp_path / "serial", serial=True, builder=build_simulation
    )
    auto = sweep(SCENE, PARAMETERS, out=tmp_path / "auto", builder=build_simulation)
    assert auto.summary.mode == "serial" and auto.summary.workers == 1
    assert auto.summary.tasks == serial.summary.tasks  # batches sized for one worker
    pd.testing.assert_frame_equal(_results(auto.table), _results(serial.table))
    assert "stayed under the" in auto.summary.engine_note  # the choice, explained
    assert auto.summary.engine_note in str(auto.summary)
    assert serial.summary.engine_note == ""  # asked for: nothing to explain
    # the estimate: median solve x queued cases + one assembly per further queued group
    rows = [{"solve_seconds": 0.01, "assembly_seconds": a}
            for a in (2.0, *[0.0] * (PROBE_CASES - 1))]  # fmt: skip
    first = sweep_run.Task({"a": 1}, ((0, {}, {}),) * 100)
    queue = [first, sweep_run.Task({"b": 2}, ((1, {}, {}),)), sweep_run.Task(first.scene, ())]
    assert queued_work(queue, first.scene) == (101, 1)
    assert queued_work(queue) == (101, 2)
    probe = WorkProbe()
    for row in rows[:-1]:
        probe.add(row)
    assert probe.remaining(101, 1) is None  # too few cases yet
    probe.add(rows[-1])
    assert probe.remaining(101, 1) == pytest.approx(0.01 * 101 + 2.0)
    assert probe.peak == (pytest.approx(3.01), PROBE_CASES)
    probe.add({"status": "refused"})  # no solve: no change
    assert probe.remaining(50, 0) == pytest.approx(0.5) and probe.peak[0] == pytest.approx(3.01)
    # the whole case's CPU where measured (its columns and outputs), less its assembly
    whole = WorkProbe()
    for row in rows:
        whole.add(row, cpu=2.03 if row["assembly_seconds"] else 0.03)
    assert whole.remaining(10, 0) == pytest.approx(0.3)
    whole.add({"solve_seconds": 0.01, "solve_cpu_seconds": 0.02}, cpu=0.001)  # never below
    assert list(whole.solves)[-1] == 0.02
    split = sweep_run._split(queue, workers=2)
    assert sum(len(t.cases) for t in split) == 101 and len(split) >= 2 * sweep_run.TASKS_PER_WORKER
    sizes = [len(t.cases) for t in split]  # the last tasks smaller: the workers end together
    assert sizes == sorted(sizes, reverse=True) and sizes[0] == 7 and sizes[-3:] == [1, 1, 1]
