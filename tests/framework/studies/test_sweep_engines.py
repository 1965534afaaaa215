"""The sweep engines: forked worker processes, the default's choice, prepared groups shared."""

from __future__ import annotations

import pickle

import numpy as np
import pytest
from test_sweep import CYCLE, SCENE, write_scene

from fretbem.errors import InputError
from fretbem.studies.sweep import cases as sweep_cases
from fretbem.studies.sweep import run as sweep_run
from fretbem.studies.sweep.cases import TIMING_COLUMNS, build_simulation, representative
from fretbem.studies.sweep.spec import SweepSpec

pd = pytest.importorskip("pandas")

#: two groups (radius), loads inside and beyond gross slip, two frictions
PARAMETERS = {
    "geometry.radius": [60.0, 70.0],
    "load.P": [80.0, 100.0],
    "load.Q": {"values": [0.0, 12.0, 40.0], "pattern": CYCLE},
    "contact.friction": [0.3, 0.5],
}

needs_fork = pytest.mark.skipif(not sweep_run.fork_available(), reason="forks on Linux only")


def _results(table):
    return table.drop(columns=[c for c in TIMING_COLUMNS if c in table])


@needs_fork
def test_forked_processes_equal_serial_and_resume(tmp_path):
    """Two forked workers (stopped after two tasks, then completed): the serial table."""
    serial = sweep_run.sweep(SCENE, PARAMETERS, out=tmp_path / "serial", serial=True)
    first = sweep_run.sweep(
        SCENE, PARAMETERS, out=tmp_path / "p", engine="processes", workers=2, batch=4, limit=2
    )
    assert first.summary.mode == "process" and first.summary.stopped
    rest = sweep_run.sweep(SCENE, PARAMETERS, out=tmp_path / "p", workers=2, batch=4)
    assert rest.summary.mode == "process" and rest.summary.workers == 2
    assert rest.summary.stored == 24 and rest.summary.skipped == first.summary.stored
    assert rest.table["worker"].nunique() >= 2  # solved in several processes
    pd.testing.assert_frame_equal(_results(rest.table), _results(serial.table))


@needs_fork
def test_default_engine_forks_once_the_work_pays_and_workers_do_not_assemble(tmp_path, monkeypatch):
    """With the pool's threshold at 0 s the default engine forks after its probe cases; the
    workers inherit the group this process prepared (no assembly of theirs) and the table
    is the serial one."""
    parameters = {"load.P": [80.0, 90.0, 100.0], "load.Q": {"values": [0.0, 6.0, 12.0, 18.0],
                  "pattern": CYCLE}}  # fmt: skip
    serial = sweep_run.sweep(SCENE, parameters, out=tmp_path / "serial", serial=True)
    monkeypatch.setattr(sweep_run, "POOL_MIN_SECONDS", 0.0)
    monkeypatch.setattr(sweep_run, "machine_cores", lambda: 2)
    sweep_cases._GROUPS.clear()
    auto = sweep_run.sweep(SCENE, parameters, out=tmp_path / "auto")
    assert auto.summary.mode == "process" and auto.summary.workers == 2
    assert "2 forked worker processes" in auto.summary.engine_note
    assert "passed 0 s (POOL_MIN_SECONDS)" in str(auto.summary)
    table = auto.table
    assert table["worker"].nunique() >= 2
    assert (table["assembly_seconds"] > 0).sum() == 1  # the one assembly of this process
    pd.testing.assert_frame_equal(_results(table), _results(serial.table))


def test_the_collector_is_handed_back_when_a_sweep_ends(tmp_path, monkeypatch):
    """The sweep freezes its long-lived objects out of the collector's passes while it runs
    (after planning, after its first chunk) and releases them at its end, forked or not, or
    when it fails; a caller's own frozen objects stay frozen."""
    import gc

    seen = []
    real = sweep_run.run_batch

    def batch(*args, **kwargs):
        seen.append(gc.get_freeze_count())
        return real(*args, **kwargs)

    monkeypatch.setattr(sweep_run, "run_batch", batch)
    parameters = {"load.Q": {"values": [0.0, 6.0, 12.0, 18.0], "pattern": CYCLE}}
    assert gc.get_freeze_count() == 0
    sweep_run.sweep(SCENE, parameters, out=tmp_path / "serial", serial=True, batch=2)
    assert seen and min(seen) > 0 and gc.get_freeze_count() == 0
    if sweep_run.fork_available():
        sweep_run.sweep(SCENE, parameters, out=tmp_path / "p", engine="processes", workers=2)
        assert gc.get_freeze_count() == 0

    def failing(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(sweep_run, "run_batch", failing)
    with pytest.raises(KeyboardInterrupt):
        sweep_run.sweep(SCENE, parameters, out=tmp_path / "stopped", serial=True)
    assert gc.get_freeze_count() == 0
    monkeypatch.setattr(sweep_run, "run_batch", real)
    gc.freeze()
    try:
        frozen = gc.get_freeze_count()
        sweep_run.sweep(SCENE, parameters, out=tmp_path / "theirs", serial=True)
        assert gc.get_freeze_count() > frozen // 2  # not unfrozen (refcounting frees some)
    finally:
        gc.unfreeze()


@needs_fork
def test_forked_workers_build_other_groups_stress_operators(tmp_path):
    """Workers forked after this process ran numba's parallel stress loop run it again for
    their own groups (a fork-safe threading layer; GNU OpenMP terminated them): the table
    is the serial one. In a fresh process, as `fretbem sweep` runs: numba's threads start
    once per process."""
    import subprocess
    import sys

    write_scene(tmp_path / "scene.toml")
    sweep_file = tmp_path / "s.toml"
    sweep_file.write_text(
        '[sweep]\nscene = "scene.toml"\n'
        'outputs = ["fretbem.studies.sweep.outputs:surface_stress"]\n[parameters]\n'
        '"geometry.radius" = [60.0, 70.0, 80.0]\n'
        '"load.Q" = {values = [0.0, 10.0], pattern = [0, 1, 0, -1, 0]}\n'
    )
    tables = {}
    for name, flags in (("serial", ["--serial"]), ("forked", ["--engine", "processes",
                                                                "--workers", "2"])):  # fmt: skip
        command = [sys.executable, "-m", "fretbem.app.cli", "sweep", str(sweep_file), "--out",
                   str(tmp_path / name), "--no-figures", "--quiet", *flags]  # fmt: skip
        done = subprocess.run(command, capture_output=True, text=True, cwd=tmp_path)
        assert done.returncode == 0, done.stderr
        assert "OpenMP" not in done.stderr
        tables[name] = sweep_run.read_table(tmp_path / name)
    assert (tables["forked"]["status"] == "ok").all()
    assert tables["forked"]["sxx_max"].notna().all()
    pd.testing.assert_frame_equal(_results(tables["forked"]), _results(tables["serial"]))


def test_default_engine_on_one_core_stays_in_this_process(tmp_path, monkeypatch):
    monkeypatch.setattr(sweep_run, "POOL_MIN_SECONDS", 0.0)
    monkeypatch.setattr(sweep_run, "machine_cores", lambda: 1)
    parameters = {"load.Q": {"values": [0.0, 6.0, 12.0, 18.0], "pattern": CYCLE}}
    auto = sweep_run.sweep(SCENE, parameters, out=tmp_path / "auto")
    assert auto.summary.mode == "serial" and auto.summary.workers == 1
    assert "one core" in auto.summary.engine_note


def test_default_engine_in_this_process_solves_batches_as_serial_does(tmp_path, monkeypatch):
    """Staying in its process, the default engine takes each task as one batch (the group
    looked up and its resource block entered once per task, as --serial), not case by case."""
    parameters = {"load.P": [80.0, 100.0], "load.Q": {"values": [0.0, 6.0, 12.0, 18.0],
                  "pattern": CYCLE}}  # fmt: skip
    monkeypatch.setattr(sweep_run, "POOL_MIN_SECONDS", 1e6)
    monkeypatch.setattr(sweep_run, "machine_cores", lambda: 2)
    entered = []
    real = sweep_cases.run_resources

    def counted(simulation):
        entered.append(1)
        return real(simulation)

    monkeypatch.setattr(sweep_cases, "run_resources", counted)
    serial = sweep_run.sweep(SCENE, parameters, out=tmp_path / "serial", serial=True, batch=3)
    blocks, entered[:] = len(entered), []
    auto = sweep_run.sweep(SCENE, parameters, out=tmp_path / "auto", batch=3)
    assert auto.summary.mode == "serial" and "stayed under the 1e+06 s" in str(auto.summary)
    assert len(entered) == blocks == serial.summary.tasks == auto.summary.tasks == 3
    pd.testing.assert_frame_equal(_results(auto.table), _results(serial.table))


def test_engine_options_that_clash_are_refused_naming_the_fix():
    choose = sweep_run.choose_engine
    assert choose(None, False, None, None, None) == "auto"
    assert choose(None, True, None, None, None) == "serial"
    assert choose(None, False, None, "tcp://h:8786", None) == "dask"
    assert choose("dask", False, None, None, 3) == "dask"
    expected = "processes" if sweep_run.fork_available() else "dask"
    assert choose(None, False, None, None, 2) == expected
    with pytest.raises(sweep_run.SweepError, match="one of auto, serial, processes, dask"):
        choose("threads", False, None, None, None)
    with pytest.raises(sweep_run.SweepError, match="clash"):
        choose("processes", True, None, None, None)
    with pytest.raises(sweep_run.SweepError, match="drop the client/scheduler"):
        choose("processes", False, None, "tcp://h:8786", None)
    with pytest.raises(sweep_run.SweepError, match="drop the client/scheduler"):
        choose(None, True, None, "tcp://h:8786", None)


@pytest.mark.parametrize(
    ("options", "message"),
    [
        ({"workers": 0}, r"workers must be a whole number >= 1, got 0"),
        ({"workers": "2"}, r'workers must be a whole number >= 1, got the string "2"'),
        ({"workers": True}, r"workers must be a whole number >= 1, got True"),
        ({"workers": 10**400}, r"workers must be below 2\^63"),
        ({"workers": 5000}, r"workers = 5000 would start that many processes .* give at most"),
        ({"limit": "3"}, r"limit \(tasks to run before stopping\) must be a whole number"),
        ({"batch": 2.5}, r"batch size must be a whole number >= 1, got 2.5"),
        ({"serial": "no"}, r"serial must be True or False"),
        ({"progress": "no"}, r"progress must be True or False"),
    ],
)
def test_bad_run_options_are_refused_before_anything_starts(tmp_path, options, message):
    """5,000 forked workers once stalled a 2-core machine; "no" was a true serial."""
    spec = SweepSpec.from_mapping(SCENE, {"load.P": [90.0, 110.0]})
    with pytest.raises((sweep_run.SweepError, InputError), match=message):
        sweep_run.run_sweep(spec, tmp_path / "store", **options)
    assert not (tmp_path / "store").exists()


def test_the_command_takes_an_engine(tmp_path, capsys):
    write_scene(tmp_path / "scene.toml")
    sweep_file = tmp_path / "s.toml"
    sweep_file.write_text(
        '[sweep]\nscene = "scene.toml"\n[parameters]\n"load.P" = [90.0, 110.0]\n'
        '"load.Q" = {values = [10.0], pattern = [0, 1, 0, -1, 0]}\n'
    )
    out = str(tmp_path / "out")
    args = [str(sweep_file), "--out", out, "--no-figures", "--quiet"]
    assert sweep_run.sweep_command([*args, "--engine", "serial"]) == 0
    printed = capsys.readouterr().out
    assert "on 1 serial worker" in printed and "engine auto" not in printed
    assert sweep_run.sweep_command([*args[:2], str(tmp_path / "auto"), *args[3:]]) == 0
    assert "\n  engine auto: solved in this process" in capsys.readouterr().out  # and why
    assert sweep_run.sweep_command([*args, "--engine", "serial", "--scheduler", "x:1"]) == 2
    assert "drop the client/scheduler" in capsys.readouterr().err


def test_a_prepared_group_pickles_and_is_taken_instead_of_assembling():
    """The prepared simulation (condensed pair, solver without its kept LUs) pickles; a
    process given it solves the group's cases without assembling, with the same numbers."""
    spec = SweepSpec.from_mapping(SCENE, {"load.Q": {"values": [6.0, 12.0], "pattern": CYCLE}})
    cases = [(c.index, c.values, c.scene) for c in spec.cases()]
    scene = representative([c[2] for c in cases])
    simulation = build_simulation(scene)
    simulation.prepare()
    copy = pickle.loads(pickle.dumps(simulation))
    assert copy.solver == simulation.solver
    sweep_cases._GROUPS.clear()
    shipped = sweep_cases.run_batch(scene, cases, prepared=copy)
    assert [r["assembly_seconds"] for r in shipped] == [0.0, 0.0]
    sweep_cases._GROUPS.clear()
    built = sweep_cases.run_batch(scene, cases)
    assert built[0]["assembly_seconds"] > 0
    for a, b in zip(shipped, built, strict=True):
        for key, value in b.items():
            if key not in TIMING_COLUMNS:
                assert a[key] == pytest.approx(value, rel=1e-12, abs=1e-12), key
    sweep_cases._GROUPS.clear()


def test_pool_errors_of_a_lost_worker_leave_its_cases_for_the_next_run(tmp_path, monkeypatch):
    """A worker that dies loses its task's cases (reported), the others are stored."""
    if not sweep_run.fork_available():
        pytest.skip("forks on Linux only")
    import os

    real = sweep_run.run_batch

    def dying(scene, cases, *args):
        if any(values["load.Q"] == 12.0 for _, values, _ in cases):
            os._exit(3)
        return real(scene, cases, *args)

    monkeypatch.setattr(sweep_run, "run_batch", dying)
    parameters = {"load.Q": {"values": [0.0, 6.0, 12.0, 18.0], "pattern": CYCLE}}
    first = sweep_run.sweep(
        SCENE, parameters, out=tmp_path / "p", engine="processes", workers=2, batch=1
    )
    assert first.summary.lost and "lost" in str(first.summary)
    assert 12.0 not in set(first.table["load.Q"])
    monkeypatch.setattr(sweep_run, "run_batch", real)
    rest = sweep_run.sweep(SCENE, parameters, out=tmp_path / "p", serial=True)
    assert rest.summary.stored == 4
    assert np.all(rest.table["status"] == "ok")


def test_dask_workers_take_the_groups_this_process_prepared(tmp_path):
    """A group this process has prepared is sent to the Dask workers: none assembles it."""
    pytest.importorskip("distributed")
    from dask.distributed import Client

    parameters = {"load.P": [80.0, 100.0], "load.Q": {"values": [6.0, 12.0], "pattern": CYCLE}}
    sweep_cases._GROUPS.clear()
    serial = sweep_run.sweep(SCENE, parameters, out=tmp_path / "serial", serial=True)
    assert (serial.table["assembly_seconds"] > 0).sum() == 1  # prepared here, kept
    with sweep_run._local_cluster(2) as cluster, Client(cluster) as client:
        shared = sweep_run.sweep(SCENE, parameters, out=tmp_path / "dask", client=client, batch=1)
    assert shared.summary.mode == "dask"
    assert (shared.table["assembly_seconds"] == 0).all()
    assert not set(shared.table["worker"]) & set(serial.table["worker"])  # solved remotely
    pd.testing.assert_frame_equal(_results(shared.table), _results(serial.table))
    sweep_cases._GROUPS.clear()


def test_default_engine_without_fork_starts_a_local_cluster_and_says_why(tmp_path, monkeypatch):
    """Where processes cannot be forked, the default engine's parallel start is a Dask
    LocalCluster, once the estimate passes its threshold; the summary names it and why."""
    pytest.importorskip("distributed")
    # more cases than the estimate needs (PROBE_CASES), one left to hand over
    values = [3.0 * k for k in range(sweep_run.PROBE_CASES + 1)]
    parameters = {"load.Q": {"values": values, "pattern": CYCLE}}
    serial = sweep_run.sweep(SCENE, parameters, out=tmp_path / "serial", serial=True)
    monkeypatch.setattr(sweep_run, "fork_available", lambda: False)
    monkeypatch.setattr(sweep_run, "machine_cores", lambda: 2)
    monkeypatch.setattr(sweep_run, "CLUSTER_START_SECONDS", 0.0)
    auto = sweep_run.sweep(SCENE, parameters, out=tmp_path / "auto")
    note = auto.summary.engine_note
    assert note.startswith("engine auto: a Dask LocalCluster: the work left, estimated at")
    assert "(PARALLEL_MIN_STARTS x CLUSTER_START_SECONDS)" in note
    assert auto.summary.mode == "dask" and auto.summary.stored == len(values)
    pd.testing.assert_frame_equal(_results(auto.table), _results(serial.table))
    sweep_cases._GROUPS.clear()
