"""Parameter sweeps: many cases of one scene, grouped for reuse, run here, on forked worker
processes or on Dask.

``sweep(scene, parameters, out=...)`` (or ``fretbem sweep SWEEP.toml``) expands the
parameters into cases, groups them by what changes the condensed problem, splits the groups
into batches, and solves the batches with one of the ``ENGINES``: in this process
("serial"), on worker processes forked from it that inherit its prepared groups
("processes", Linux), or as tasks of a Dask cluster ("dask": a ``LocalCluster``, any
scheduler address, or a ``Client`` passed in). The default, "auto", starts in this process
and forks the workers once the remaining work, estimated from the cases solved so far,
pays for them. Every finished batch is stored at once (see ``sweep_store``), so an
interrupted sweep re-run with the same description solves only the missing cases.
Dask, pandas and pyarrow are imported only here, when a sweep runs.
"""

from __future__ import annotations

import argparse
import concurrent.futures
import copy
import gc
import json
import logging
import math
import multiprocessing
import os
import statistics
import sys
import time
from collections import Counter
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any

import attrs

from fretbem.errors import ComputationError, FretbemError
from fretbem.output.staging import output_lock
from fretbem.pipeline import requests
from fretbem.scenes.file import scene_from_data
from fretbem.studies.sweep_options import ENGINES, add_arguments
from fretbem.validators import flag, whole_number

from . import cases as sweep_cases
from .cases import (
    CYCLE_COLUMNS,
    REGIMES,
    ROTATION_COLUMNS,
    ROTATION_CYCLE_COLUMNS,
    STEP_COLUMNS,
    TIMING_COLUMNS,
    batch_rows,
    case_loading,
    group_key,
    representative,
    run_batch,
)
from .labelled import sweep_dataset, sweep_html, sweep_repr
from .maps import check_maps, draw_maps
from .outputs import declared_columns, resolve_all
from .probe import PROBE_CASES, WorkProbe, queued_work
from .spec import SweepSpec, SweepSpecError, load_sweep, set_path
from .store import SweepStore, read_table

#: environment of the local cluster's workers: one BLAS thread per process
BLAS_ENV = {
    "OMP_NUM_THREADS": "1",
    "OPENBLAS_NUM_THREADS": "1",
    "MKL_NUM_THREADS": "1",
    "BLIS_NUM_THREADS": "1",
    "VECLIB_MAXIMUM_THREADS": "1",
    "NUMEXPR_NUM_THREADS": "1",
}

#: tables of a sweep file passed to the output functions (e.g. [fatigue]), not to the scene
POST_TABLES = ("fatigue", "stress")

#: most cases in one task (and one stored chunk)
MAX_BATCH = 250
#: CPU seconds a local cluster costs besides the solves: importing dask.distributed,
#: starting the scheduler and worker processes, their imports of fretbem and their own
#: assemblies (measured: a 1,444-case sweep took 13.6 s CPU serially and 25.1 s on a
#: 2-worker cluster, 2 cores at load 9; the start alone is 1.6-5 s of wall time)
CLUSTER_START_SECONDS = 8.0
#: the default engine starts a local cluster only when the sweep's remaining work, estimated
#: from the cases solved in this process so far, exceeds this many cluster starts: below
#: it the start and the workers' own assemblies cost more than the second core gives back
PARALLEL_MIN_STARTS = 3.0

#: default tasks per worker: small enough to balance the last round, large enough that the
#: per-task cost (scheduling, one Parquet chunk) stays below 1 % of the solves
TASKS_PER_WORKER = 8

#: serial CPU seconds of remaining work (whole cases: solve, columns, output functions)
#: above which the default engine hands the rest to a pool of forked processes. Forking
#: costs milliseconds (the workers inherit this process's prepared groups, nothing is
#: assembled or pickled again); forked after its first cases, the 144-case example map
#: (about 0.5 s of work left then) took 1.76 CPU s against 1.53 serially and no less
#: wall on two free cores, so it stays in this process (estimated at 0.6-0.8 s; 0.46 s on
#: the 2-core host of 2026-11), ten times it (estimated at 6.5-10.6 s; 4.25 s there) forks
POOL_MIN_SECONDS = 2.5


class SweepError(ComputationError):
    """A sweep that cannot run (no scheduler reachable, bad execution options)."""


def machine_cores() -> int:
    """Cores this process may use (affinity-aware)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not on Linux
        return os.cpu_count() or 1


@attrs.frozen
class Task:
    """A batch of cases of one group, solved on the group's representative scene."""

    scene: dict
    cases: tuple[tuple[int, dict, dict], ...]


def plan(spec: SweepSpec, done: set[int], workers: int, batch: int | None = None) -> list[Task]:
    """Batches of the cases not yet done: enough tasks to keep ``workers`` busy.

    The representative scene of a group is taken over all its cases (done or not), so a
    resumed sweep solves on exactly the bodies of an uninterrupted one.
    """
    groups = spec.groups()
    remaining = sum(1 for cases in groups.values() for c in cases if c.index not in done)
    if batch is None:
        per_worker = TASKS_PER_WORKER * max(1, workers)
        batch = max(1, min(MAX_BATCH, math.ceil(remaining / per_worker)))
    elif isinstance(batch, bool) or not isinstance(batch, int) or batch < 1:
        raise SweepError(f"batch size must be an integer >= 1, got {batch!r}")
    tasks = []
    for cases in groups.values():
        todo = [(c.index, c.values, c.scene) for c in cases if c.index not in done]
        if not todo:
            continue
        scene = representative([c.scene for c in cases])
        for k in range(0, len(todo), batch):
            tasks.append(Task(scene, tuple(todo[k : k + batch])))
    return tasks


class _Progress:
    """A one-line progress bar on a terminal (silent elsewhere until the summary)."""

    def __init__(self, tasks: int, cases: int, enabled: bool, stream=None) -> None:
        self.stream = stream or sys.stderr
        self.enabled = enabled and self.stream.isatty()
        self.tasks, self.cases = tasks, cases
        self.done_tasks = self.done_cases = 0
        self.start = time.perf_counter()
        self._draw()

    def update(self, cases: int) -> None:
        self.done_tasks += 1
        self.done_cases += cases
        self._draw()

    def _draw(self) -> None:
        if not self.enabled:
            return
        width = 30
        filled = int(width * self.done_cases / max(1, self.cases))
        bar = "#" * filled + "." * (width - filled)
        self.stream.write(
            f"\r[{bar}] {self.done_cases}/{self.cases} cases, {self.done_tasks} tasks, "
            f"{time.perf_counter() - self.start:.1f} s"
        )
        self.stream.flush()

    def close(self) -> None:
        if self.enabled:
            self.stream.write("\n")
            self.stream.flush()


@attrs.frozen
class SweepSummary:
    """What a sweep run did and what the store now holds."""

    directory: Path
    cases: int
    stored: int
    solved_now: int
    skipped: int
    groups: int
    tasks: int
    workers: int
    mode: str
    wall: float
    status: dict
    regimes: dict
    assembly_seconds: float | None
    solve_seconds: float | None
    stopped: bool
    lost: tuple[str, ...] = ()
    #: why the engine ran as it did (the default engine's choice), "" when it was asked for
    engine_note: str = ""

    def __str__(self) -> str:
        def fmt(value, unit=" s"):
            return "n/a" if value is None else f"{value:.4g}{unit}"

        if self.tasks:
            run = (
                f"  this run: {self.solved_now} cases in {self.tasks} tasks on {self.workers} "
                f"{self.mode} worker(s), {self.wall:.2f} s wall; {self.skipped} already stored"
            )
        else:
            run = f"  this run: nothing to solve, all {self.skipped} cases already stored"
        lines = [
            f"sweep: {self.cases} cases in {self.groups} condensation groups -> {self.directory}",
            run,
            *([f"  {self.engine_note}"] if self.engine_note else []),
            "  stored: "
            + ", ".join(f"{n} {k}" for k, n in sorted(self.status.items()))
            + f" ({self.stored}/{self.cases})",
            "  regimes: " + ", ".join(f"{n} {k}" for k, n in self.regimes.items() if n),
            f"  median assembly + condensation {fmt(self.assembly_seconds)} (per group and "
            f"worker), median solve {fmt(self.solve_seconds)} per case",
        ]
        if self.assembly_seconds and self.solve_seconds:
            ratio = self.assembly_seconds / self.solve_seconds
            lines[-1] += f": one assembly costs {ratio:.0f} case solves"
        if self.lost:
            lines.append(
                f"  {len(self.lost)} task(s) lost by the cluster (first: {self.lost[0]}); "
                "their cases are not stored: re-run the same command to complete the sweep"
            )
        if self.stopped:
            lines.append("  stopped early: re-run the same command to complete the sweep")
        elif self.status.get("error"):
            lines.append("  failed cases are in the table with their error (column 'error')")
        return "\n".join(lines)


@attrs.frozen(eq=False)
class SweepResult:
    """The store's table (pandas DataFrame, one row per case) and the run's summary."""

    table: Any
    summary: SweepSummary
    spec: SweepSpec

    def __repr__(self) -> str:
        return sweep_repr(self)

    def _repr_html_(self) -> str:
        return sweep_html(self)

    def to_xarray(self):
        """The table as an :class:`xarray.Dataset` indexed by the varied parameters (a grid
        in ``product`` mode), with units: :func:`.labelled.sweep_dataset`."""
        return sweep_dataset(self.table, self.spec.paths, self.spec.mode)


def _summarise(table, spec, directory, stats) -> SweepSummary:
    status = Counter(table["status"]) if "status" in table else Counter()
    regimes = Counter(table["regime"]) if "regime" in table else Counter()

    def median(column, positive=False):
        if column not in table:
            return None
        values = [float(v) for v in table[column].dropna() if not positive or v > 0]
        return statistics.median(values) if values else None

    return SweepSummary(
        directory=Path(directory),
        cases=len(spec.combinations()),
        stored=len(table),
        status=dict(status),
        regimes={k: regimes.get(k, 0) for k in REGIMES},
        groups=spec.group_count(),
        assembly_seconds=median("assembly_seconds", positive=True),
        solve_seconds=median("solve_seconds"),
        **stats,
    )


def _local_cluster(workers: int):
    from dask.distributed import LocalCluster

    return LocalCluster(
        n_workers=workers,
        threads_per_worker=1,
        processes=True,
        env=dict(BLAS_ENV),
        dashboard_address=":0",
        silence_logs=logging.ERROR,
    )


def _connect(scheduler: str | None, workers: int):
    """(cluster or None, client): a new LocalCluster, or a client of ``scheduler``."""
    from dask.distributed import Client

    try:
        if scheduler is not None:
            return None, Client(scheduler, timeout="20s")
        cluster = _local_cluster(workers)
        return cluster, Client(cluster)
    except (OSError, TimeoutError) as err:
        raise SweepError(
            f"cannot reach the Dask scheduler {scheduler!r}: {err}; start one "
            "(`dask scheduler`, or dask-jobqueue on a cluster) or run with --serial"
        ) from err


def _cluster_threads(client) -> int:
    """Worker threads of a client's cluster now (0 without a client or workers)."""
    if client is None:
        return 0
    workers = client.scheduler_info().get("workers", {})
    return sum(int(w.get("nthreads", 1)) for w in workers.values())


def _split(queue: list[Task], workers: int) -> list[Task]:
    """The queued tasks cut to about ``TASKS_PER_WORKER`` tasks per worker (at most
    MAX_BATCH cases), the last ones smaller so the workers finish together: a task takes at
    most the cases left over twice the workers, down to an eighth of the first tasks' size
    (the workers take the tasks in this order)."""
    workers = max(1, workers)
    left = sum(len(t.cases) for t in queue)
    size = max(1, min(MAX_BATCH, math.ceil(left / (TASKS_PER_WORKER * workers))))
    smallest = math.ceil(size / 8)
    tasks = []
    for task in queue:
        k = 0
        while k < len(task.cases):
            n = max(smallest, min(size, math.ceil(left / (2 * workers))))
            tasks.append(Task(task.scene, task.cases[k : k + n]))
            k, left = k + n, left - min(n, len(task.cases) - k)
    return tasks


def _solve_here(queue, builder, outputs, extras, on_rows, stop, max_tasks) -> int:
    """Solve queued tasks in this process until ``stop(row, cases, groups, cpu)`` after a
    case (the cases and further groups left, this task's unsolved cases included; the CPU
    seconds since the previous case: the case's loading, solve and columns) or
    ``max_tasks`` tasks (None: no limit); returns the tasks finished. A task is one batch,
    its group looked up and its resource block entered once, as ``--serial`` does; a task
    cut short goes back to the front of the queue with its unsolved cases (and counts as
    finished)."""
    finished = 0
    while queue and (max_tasks is None or finished < max_tasks):
        task, rows, stopped = queue.pop(0), [], False
        cases, groups = queued_work(queue, task.scene)
        batch = batch_rows(task.scene, task.cases, builder, outputs, extras)
        cpu = time.process_time()
        try:
            for row in batch:
                rows.append(row)
                spent, cpu = time.process_time() - cpu, time.process_time()
                if stop(row, cases + len(task.cases) - len(rows), groups, spent):
                    stopped = True
                    break
        finally:
            batch.close()
        if len(rows) < len(task.cases):
            queue.insert(0, Task(task.scene, task.cases[len(rows) :]))
        on_rows(rows)
        finished += 1
        if stopped:
            break
    return finished


def fork_available() -> bool:
    """Whether worker processes can be forked from this one (Linux: they inherit its
    prepared groups; elsewhere forking a process with system frameworks loaded is unsafe)."""
    return sys.platform.startswith("linux") and "fork" in multiprocessing.get_all_start_methods()


def fork_safe_threads() -> None:
    """Have numba start its threads in a layer a forked worker may use (tbb or workqueue,
    ``"forksafe"``), unless the user chose one or they already run: GNU OpenMP, its default
    here, terminates a forked process that runs a parallel loop after its parent did (a
    worker building another group's stress operator: a sweep of several groups with a
    stress column stopped "interrupted"). The loops' results do not depend on the layer."""
    numba = sys.modules.get("numba")
    if numba is None:  # read when numba loads (a sweep without compiled loops never does)
        os.environ.setdefault("NUMBA_THREADING_LAYER", "forksafe")
    elif numba.config.THREADING_LAYER == "default":  # read when its threads start
        numba.config.THREADING_LAYER = "forksafe"


class _Collector:
    """The cyclic garbage collector's full passes kept off what the sweep has made so far.

    Its modules (numpy, scipy, numba, pandas: about 2 x 10^5 objects), its plan and its
    prepared groups live to the sweep's end and are not cyclic garbage, yet every full pass
    traversed them all: one while pandas loads, one when the table is concatenated (0.1 CPU s
    of the 1,440-case map's parent after its workers stop). ``settle()`` freezes what exists
    now (``gc.freeze``: the passes skip it, refcounting still frees it); ``release()`` at the
    sweep's end hands it back to the collector. A caller that froze objects itself keeps its
    own policy: nothing is frozen for it but what the forked workers inherit."""

    def __init__(self) -> None:
        self.owner = gc.isenabled() and gc.get_freeze_count() == 0

    def settle(self) -> None:
        if self.owner:
            gc.freeze()

    def release(self) -> None:
        if self.owner:
            gc.unfreeze()


#: what the forked workers of the running pool solve: set before the fork, read by them
_POOL: dict[str, Any] = {}


def _pool_task(index: int) -> list[dict]:
    """Task ``index`` of the running pool, solved in a forked worker."""
    tasks, builder, outputs, extras = _POOL["work"]
    task = tasks[index]
    return run_batch(task.scene, task.cases, builder, outputs, extras)


def _run_pool(queue, workers, builder, outputs, extras, on_rows, limit, on_start=None,
              collector=None):  # fmt: skip
    """Solve the queued tasks on ``workers`` forked processes, storing each as it returns.

    Returns (stopped early, errors of tasks lost with a worker). The workers
    inherit this process's memory: the groups it prepared (``cases._GROUPS``), the builder
    and the output functions are theirs without pickling; each task sends back its rows.
    ``on_start()`` runs once every task is submitted (the workers forked). ``collector``:
    the sweep's :class:`_Collector`, which releases the objects frozen here when the sweep
    ends (without it they are released when the pool stops).
    """
    finished, lost, stopped = 0, [], False
    _POOL["work"] = (list(queue), builder, outputs, extras)
    # the inherited objects out of the workers' garbage collector: its passes would write
    # to every page holding one and copy it (copy-on-write), for nothing
    gc.freeze()
    pool = concurrent.futures.ProcessPoolExecutor(
        workers, mp_context=multiprocessing.get_context("fork")
    )
    try:
        futures = [pool.submit(_pool_task, k) for k in range(len(queue))]
        if on_start is not None:
            on_start()
        for future in concurrent.futures.as_completed(futures):
            try:
                rows = future.result()
            except Exception as err:  # a worker that died (killed, out of memory)
                lost.append(f"{type(err).__name__}: {err}")
                continue
            on_rows(rows)
            finished += 1
            if limit is not None and finished >= limit and finished < len(futures):
                stopped = True
                break
    finally:
        pool.shutdown(wait=True, cancel_futures=True)
        if collector is None:
            gc.unfreeze()
        _POOL.clear()
    return stopped, lost


def _run_engine(
    tasks,
    client,
    scheduler,
    workers,
    builder,
    outputs,
    on_rows,
    limit,
    extras=None,
    engine="dask",
    resplit=False,
    collector=None,
):
    """Run the tasks on ``engine`` ("auto", "processes" or "dask"), storing each batch as it
    completes.

    Returns (workers, stopped early, errors of tasks lost with a worker, mode, note): a lost
    task's cases stay unstored, for the next run; the note says why the default engine ran
    as it did ("" for an engine asked for).

    "auto" (the default engine) solves in this process until the remaining work, estimated
    from the cases solved so far, is worth a parallel start: ``POOL_MIN_SECONDS`` for a pool
    of forked processes (Linux), ``PARALLEL_MIN_STARTS`` cluster starts for a Dask
    LocalCluster (elsewhere); a smaller sweep ends in this process (mode "serial").
    "processes" forks the pool at once, after this process has prepared the first group.
    "dask": without a client, the cluster starts (or the scheduler is reached) in a thread
    while this process solves the first tasks itself. ``resplit`` cuts the remaining
    batches for the workers. ``collector``: the sweep's :class:`_Collector` (the pool's).
    """
    queue = list(tasks)
    finished = 0
    lost: list[str] = []
    cluster = own_client = None

    def budget():
        return None if limit is None else limit - finished

    forked = engine == "processes" or (engine == "auto" and fork_available() and workers > 1)
    note = ""
    # the rows of the task solved here last before forking: stored once the workers run
    # (the store's first write imports pandas, 0.3-0.5 CPU s the workers need not wait for)
    held: list[list[dict]] = []

    def store_held():
        while held:
            on_rows(held.pop(0))

    def store_or_hold(rows):
        if forked and queue and chose:
            held.append(rows)
        else:
            on_rows(rows)

    chose = engine == "processes"
    if engine == "auto":
        probe, threshold = WorkProbe(), auto_threshold(workers, forked)

        def worth_it(row, cases, groups, cpu):
            nonlocal chose
            probe.add(row, cpu)
            remaining = probe.remaining(cases, groups)
            chose = remaining is not None and remaining > threshold
            return chose

        def never(row, cases, groups, cpu):  # one core: the serial engine, no estimate
            return False

        stop = never if math.isinf(threshold) else worth_it
        try:
            finished += _solve_here(queue, builder, outputs, extras, store_or_hold, stop, budget())
        except BaseException:  # interrupted: what was solved is stored
            store_held()
            raise
        if not queue or (limit is not None and finished >= limit):
            store_held()
            note = auto_note(probe, threshold, workers, forked, limited=bool(queue))
            return 1, bool(queue), lost, "serial", note
        note = auto_note(probe, threshold, workers, forked, chose=True)
    elif forked:  # the first case here: the workers inherit its group, prepared
        finished += _solve_here(queue, builder, outputs, extras, store_or_hold, _always, 1)
        if not queue or (limit is not None and finished >= limit):
            store_held()
            return workers, bool(queue), lost, "process", note
    if resplit and engine == "auto":  # the batches were sized for one worker
        queue = _split(queue, workers)
    if forked:
        try:
            stopped, lost = _run_pool(
                queue, workers, builder, outputs, extras, on_rows, budget(), store_held, collector
            )
        finally:
            store_held()
        return workers, stopped, lost, "process", note
    try:
        from dask.distributed import as_completed
    except ImportError as err:  # pragma: no cover - dask is a dependency
        raise SweepError("the Dask mode needs dask[distributed]; use serial=True") from err
    if client is None:
        with concurrent.futures.ThreadPoolExecutor(1) as pool:
            starting = pool.submit(_connect, scheduler, workers)

            def started(row, cases, groups, cpu):
                return starting.done()

            # case by case, so the cluster never waits for this process to finish a task
            while queue and not starting.done() and (limit is None or finished < limit):
                finished += _solve_here(queue, builder, outputs, extras, on_rows, started, budget())
            cluster, own_client = starting.result()
        client = own_client
    stopped = False
    try:
        n_workers = len(client.scheduler_info().get("workers", {})) or workers
        if limit is not None and finished >= limit:
            return n_workers, bool(queue), lost, "dask", note
        total = finished + len(queue)
        shared = _share_prepared(client, queue, builder)
        futures = [
            client.submit(
                run_batch,
                t.scene,
                t.cases,
                builder,
                outputs,
                extras,
                shared.get(group_key(t.scene)),
                pure=False,
            )
            for t in queue
        ]
        for future in as_completed(futures):
            try:
                rows = future.result()
            except Exception as err:  # a lost worker or a cancelled task, not a failing case
                lost.append(f"{type(err).__name__}: {err}")
                continue
            on_rows(rows)
            finished += 1
            if limit is not None and finished >= limit and finished < total:
                stopped = True
                client.cancel(futures)
                break
    finally:
        if own_client is not None:
            own_client.close()
        if cluster is not None:
            cluster.close()
    return n_workers, stopped, lost, "dask", note


def _always(row, cases, groups, cpu) -> bool:
    return True


def auto_threshold(workers: int, forked: bool) -> float:
    """Serial CPU seconds of work left above which the default engine goes parallel:
    ``POOL_MIN_SECONDS`` for forked workers, ``PARALLEL_MIN_STARTS`` cluster starts for a
    Dask LocalCluster, never on one core."""
    if workers <= 1:
        return math.inf
    return POOL_MIN_SECONDS if forked else PARALLEL_MIN_STARTS * CLUSTER_START_SECONDS


def auto_note(probe: WorkProbe, threshold: float, workers: int, forked: bool,
              chose: bool = False, limited: bool = False) -> str:  # fmt: skip
    """What the default engine chose and why, for the summary: ``chose`` when it hands the
    rest to a parallel engine, else it stayed in this process (``limited``: the task limit
    came first)."""
    if limited:
        return "engine auto: solved in this process until the task limit (--limit, limit=)"
    if math.isinf(threshold):
        return "engine auto: solved in this process (one core: no parallel engine can pay)"
    if forked:
        engine, limit = f"{workers} forked worker processes", "POOL_MIN_SECONDS"
    else:
        engine, limit = "a Dask LocalCluster", "PARALLEL_MIN_STARTS x CLUSTER_START_SECONDS"
    if probe.peak is None:
        return (
            f"engine auto: solved in this process (fewer than {PROBE_CASES} cases solved, "
            "too few to estimate the work)"
        )
    seconds, cases = probe.peak
    estimate = f"the work left, estimated at {seconds:.3g} CPU s after {cases} case(s)"
    if chose:
        return f"engine auto: {engine}: {estimate}, passed {threshold:.3g} s ({limit})"
    if seconds > threshold:  # on the last case: nothing left to hand over
        return (
            f"engine auto: solved in this process: {estimate}, passed {threshold:.3g} s only "
            "on the last case"
        )
    return (
        f"engine auto: solved in this process: {estimate}, stayed under the {threshold:.3g} s "
        f"that pay for {engine} ({limit})"
    )


def _share_prepared(client, queue: list[Task], builder) -> dict:
    """The groups this process has prepared that queued tasks need, sent once to every
    worker (futures by group key): the workers take them instead of assembling again."""
    if builder is not None:
        return {}
    keys = {group_key(t.scene) for t in queue}
    return {
        key: client.scatter(sweep_cases._GROUPS[key][0], broadcast=True, hash=False)
        for key in keys
        if key in sweep_cases._GROUPS
    }


#: most cases of one sweep: planning holds every case's scene in memory (about 20 kB each
#: with its copies) and a store of more is better split into several sweeps
MAX_CASES = 100_000
#: planning cost per case measured on the reference scene (deep copy, group key), seconds
PLAN_SECONDS_PER_CASE = 1e-4


def check_size(spec: SweepSpec) -> None:
    """Refuse a sweep too large to plan, with its case count and the estimate."""
    count = spec.count()
    if count > MAX_CASES:
        shape = " x ".join(str(len(p.values)) for p in spec.parameters)
        raise SweepError(
            f"[parameters]: {shape} = {count} cases, more than {MAX_CASES} (planning alone "
            f"would hold about {count * 20 / 2**20 * 1024:.3g} MB and take about "
            f"{count * PLAN_SECONDS_PER_CASE:.3g} s before the first solve); split the sweep "
            "into several files over ranges of one parameter, or use fewer values (num)"
        )


def check_values(spec: SweepSpec, builder=None) -> None:
    """Every value of every parameter read as the scene file reader reads it, before any
    case is solved: a value the reader refuses (``contact.pairs = true``, a negative
    friction, an unphysical fatigue constant) is refused here naming the parameter.

    Each value is tried with the other parameters at their first value (values valid
    only in some combinations still fail their own cases, with the message).
    """
    if builder is not None:
        return  # a custom builder reads its own scenes

    for parameter in spec.parameters:
        for value in {_hashable(v): v for v in parameter.values}.values():
            scene = copy.deepcopy(spec.scene)
            for other in spec.parameters:
                chosen = value if other is parameter else other.values[0]
                set_path(scene, other.path, other.scene_value(_plain(chosen)))
            try:
                record = scene_from_data(scene)
                if hasattr(record, "extras"):
                    requests(record.extras)
            except FretbemError as err:
                raise SweepSpecError(
                    f"[parameters] {parameter.path!r} = {_plain(value)!r}: {err}"
                ) from None


def _hashable(value):
    """A dict key per distinct value and type: ``true`` is not ``1``, nor ``2.0`` ``2``
    (the reader takes one and refuses the other, so each is checked on its own)."""
    if isinstance(value, (list, dict)):
        return json.dumps(value, sort_keys=True)
    return (type(value).__name__, value)


def _plain(value):
    if isinstance(value, str) and value[:1] in "[{":
        try:
            return json.loads(value)
        except ValueError:
            return value
    return value


def sweep_columns(spec: SweepSpec, outputs: Sequence[str]) -> set[str] | None:
    """The columns the sweep will write (None when an output does not declare its own)."""
    scene = copy.deepcopy(spec.scene)
    for parameter in spec.parameters:
        set_path(scene, parameter.path, parameter.scene_value(parameter.values[0]))
    try:
        loading = case_loading(scene).steps
    except Exception:
        loading = []
    steps = [step.name for step in loading]
    declared = declared_columns(outputs, steps, spec.scene)
    if declared is None:
        return None
    base = {"case", "status", "error", "regime", "friction", "P_max", "Q_peak", "pairs",
            "transition_ratio", "cycles", *CYCLE_COLUMNS, *TIMING_COLUMNS}  # fmt: skip
    turning = sweep_cases.scene_rotates(scene, loading)  # the block's M, theta and tilt too
    per_step = {f"{c}.{s}" for c in STEP_COLUMNS for s in steps}
    per_step |= {f"{c}.{s}" for c in ROTATION_COLUMNS for s in steps if turning}
    if any(getattr(step, "cycle", 0) for step in loading):  # a cyclic case: its last cycle
        per_step = {*CYCLE_COLUMNS, "transition_ratio", "cycles"}
        per_step |= set(ROTATION_CYCLE_COLUMNS) if turning else set()
    return base | per_step | set(spec.paths) | declared


#: local worker processes a sweep may start per core (CPU-bound cases: past the cores a worker
#: only waits, and each is a process of its own: 5,000 forked workers stalled the machine)
MAX_WORKERS_PER_CORE = 4


def _count(where: str, value: Any, fix: str) -> int:
    """A whole number >= 1 of the sweep's options (True, "2", 2.5 and 10**400 refused)."""
    return whole_number(where, value, low=1, fix=fix, error=SweepError)


def _check_local_workers(workers: int | None) -> None:
    """Refuse more local workers than :data:`MAX_WORKERS_PER_CORE` per core."""
    cores = machine_cores()
    if workers is not None and workers > MAX_WORKERS_PER_CORE * cores:
        raise SweepError(
            f"workers = {workers} would start that many processes on this machine's {cores} "
            f"cores (the cases are CPU-bound: past the cores a worker only waits); give at "
            f"most {MAX_WORKERS_PER_CORE * cores} (leave it out for one per core), or run on a "
            "Dask cluster (--scheduler)"
        )


def choose_engine(engine, serial, client, scheduler, workers) -> str:
    """The engine of a sweep's options, or a SweepError naming the clash and the fix.

    ``serial=True`` is ``engine="serial"``; a client or scheduler means "dask"; a worker
    count without an engine asks for that many local processes ("processes" where they can
    be forked, else a Dask LocalCluster); otherwise "auto".
    """
    if engine is not None and engine not in ENGINES:
        raise SweepError(f"engine must be one of {', '.join(ENGINES)}, got {engine!r}")
    remote = client is not None or scheduler is not None
    if serial:
        if engine not in (None, "serial"):
            raise SweepError(f"serial=True (--serial) and engine {engine!r} clash: keep one")
        engine = "serial"
    if remote:
        if engine not in (None, "dask"):
            raise SweepError(
                f"a Dask client or scheduler runs the sweep on Dask, not engine {engine!r}: "
                "drop the client/scheduler (--scheduler) or the engine"
            )
        engine = "dask"
    if engine is None:
        engine = "auto" if workers is None else ("processes" if fork_available() else "dask")
    if engine == "processes" and not fork_available():
        raise SweepError(
            "engine 'processes' forks worker processes, which needs Linux; use engine 'dask' "
            "(--engine dask: a Dask LocalCluster) or 'serial'"
        )
    return engine


def run_sweep(
    spec: SweepSpec,
    out: str | Path,
    *,
    client=None,
    scheduler: str | None = None,
    serial: bool = False,
    engine: str | None = None,
    workers: int | None = None,
    batch: int | None = None,
    limit: int | None = None,
    progress: bool = True,
    builder: Callable[[Mapping], Any] | None = None,
) -> SweepResult:
    """Run (or complete) ``spec`` into the store at ``out``; see ``sweep`` for the options."""
    serial, progress = flag("serial", serial, error=SweepError), flag("progress", progress)
    if workers is not None:
        workers = _count("workers", workers, "give the worker processes, e.g. 2")
    engine = choose_engine(engine, serial, client, scheduler, workers)
    if client is None and scheduler is None:  # (a cluster's workers are its own)
        _check_local_workers(workers)
    if limit is not None:
        limit = _count("limit (tasks to run before stopping)", limit, "give e.g. 10")
    if batch is not None:
        batch = _count("batch size", batch, "give the cases per task, or leave it out")
    outputs = spec.options.get("outputs", ())
    outputs = (outputs,) if isinstance(outputs, str) else tuple(outputs)
    resolve_all(outputs)  # a bad name fails here, not on every case
    sweep_cases.forget_outputs()  # the batches resolve them once, afresh
    check_size(spec)
    check_values(spec, builder)  # a bad value fails here, naming its parameter, not as error rows
    check_maps(spec, sweep_columns(spec, outputs))  # a map typo fails before any solve
    #: post-processing tables of the sweep file, handed to the output functions with the scene
    extras = {k: v for k, v in spec.options.items() if k in POST_TABLES}
    if engine in ("auto", "processes") and fork_available():
        fork_safe_threads()  # before this process runs a case's parallel loops
    start = time.perf_counter()
    collector = _Collector()
    try:
        with output_lock(Path(out).expanduser().resolve()):  # two sweeps never share a store
            return _run_locked(spec, out, outputs, extras, start, client=client,
                               scheduler=scheduler, engine=engine, workers=workers,
                               batch=batch, limit=limit, progress=progress, builder=builder,
                               collector=collector)  # fmt: skip
    finally:
        collector.release()


def _run_locked(spec, out, outputs, extras, start, *, client, scheduler, engine, workers,
                batch, limit, progress, builder, collector) -> SweepResult:  # fmt: skip
    """run_sweep with the store locked."""
    Path(out).parent.mkdir(parents=True, exist_ok=True)
    store = SweepStore(
        out,
        {
            "fingerprint": spec.fingerprint(),
            "paths": list(spec.paths),
            "patterns": {p.path: p.pattern for p in spec.parameters if p.pattern},
            "mode": spec.mode,
            "cases": len(spec.combinations()),
            "scene": spec.scene,
            "options": spec.options,
        },
    )
    done = store.done()
    connected = None
    if engine == "dask" and client is None and scheduler is not None:
        _, connected = _connect(scheduler, 0)  # first, so the batches fit its workers
        client = connected
    serial = engine == "serial"
    n_workers = 1 if serial else (workers or _cluster_threads(client) or machine_cores())
    # the default engine starts as a serial run: batches sized for one worker (fewer chunks)
    tasks = plan(spec, done, 1 if engine == "auto" else n_workers, batch)
    collector.settle()  # the modules and the plan
    bar = _Progress(len(tasks), sum(len(t.cases) for t in tasks), progress)
    solved = ran = 0

    def on_rows(rows):
        nonlocal solved, ran
        store.write(rows)
        if not ran:  # the store's first chunk loaded pandas and pyarrow
            collector.settle()
        solved += len(rows)
        ran += 1
        bar.update(len(rows))

    stopped, lost, note = False, [], ""
    try:
        if not tasks:
            mode = "none"
        elif serial:
            mode = "serial"
            for k, task in enumerate(tasks):
                if limit is not None and k >= limit:
                    stopped = True
                    break
                on_rows(run_batch(task.scene, task.cases, builder, outputs, extras))
        else:
            n_workers, stopped, lost, mode, note = _run_engine(
                tasks,
                client,
                scheduler,
                n_workers,
                builder,
                outputs,
                on_rows,
                limit,
                extras,
                engine,
                resplit=batch is None,
                collector=collector,
            )
    finally:
        bar.close()
        if connected is not None:
            connected.close()
    table = store.table()
    stats = {
        "solved_now": solved,
        "skipped": len(done),
        "tasks": ran + len(lost),  # the default engine re-cuts its batches when it forks
        "workers": n_workers,
        "mode": mode,
        "wall": time.perf_counter() - start,
        "stopped": stopped,
        "lost": tuple(lost),
        "engine_note": note,
    }
    return SweepResult(table, _summarise(table, spec, store.directory, stats), spec)


def sweep(
    scene: Mapping,
    parameters: Mapping[str, Any],
    *,
    out: str | Path,
    mode: str = "product",
    client=None,
    scheduler: str | None = None,
    serial: bool = False,
    engine: str | None = None,
    workers: int | None = None,
    batch: int | None = None,
    limit: int | None = None,
    progress: bool = True,
    builder: Callable[[Mapping], Any] | None = None,
    outputs: Sequence[str] = (),
    options: Mapping[str, Any] | None = None,
) -> SweepResult:
    """Solve ``scene`` for every combination of ``parameters`` and store one row per case.

    Parameters
    ----------
    scene : mapping
        A scene as a nested dict (a parsed scene file).
    parameters : mapping
        Key path (``"load.Q"``, ``"contact.friction"``, ``"geometry.radius"``...) to a list of
        values, a range ``{"start", "stop", "num"}`` or ``{"values": [...]}``; either may
        carry a ``"pattern"`` the value scales (e.g. a load history).
    out : path
        The store directory; re-running into it completes an interrupted sweep.
    mode : "product" or "zip"
    client : dask.distributed.Client, optional
        Run on this client's cluster.
    scheduler : str, optional
        Address of a running scheduler (``tcp://host:8786``); else a LocalCluster.
    serial : bool
        Solve in this process (``engine="serial"``).
    engine : {"auto", "serial", "processes", "dask"}, optional
        "auto" (the default) solves here and forks worker processes once the estimated
        remaining work pays for them; "processes" forks them at once (Linux); "dask" runs
        on a Dask LocalCluster, or on ``scheduler`` / ``client``.
    workers : int, optional
        Worker processes (default: the machine's cores); alone, it asks for "processes"
        (a Dask LocalCluster where processes cannot be forked).
    batch : int, optional
        Cases per task (default: ``TASKS_PER_WORKER`` tasks per worker, at most ``MAX_BATCH``
        cases each).
    limit : int, optional
        Stop after this many tasks (the store keeps them; re-run to complete).
    progress : bool
        Progress bar on a terminal.
    builder : callable, optional
        Scene dict -> Simulation (default: the scene-file reader of the scene's format).
    outputs : sequence of str
        Extra column functions, ``"package.module:function"`` (see ``sweep_outputs``).
    options : mapping, optional
        Extra settings stored with the sweep (part of its identity).
    """
    options = dict(options or {})
    if outputs:
        options["outputs"] = [outputs] if isinstance(outputs, str) else list(outputs)
    spec = SweepSpec.from_mapping(scene, parameters, mode=mode, **options)
    return run_sweep(
        spec,
        out,
        client=client,
        scheduler=scheduler,
        serial=serial,
        engine=engine,
        workers=workers,
        batch=batch,
        limit=limit,
        progress=progress,
        builder=builder,
    )


def sweep_command(argv: Sequence[str] | None = None) -> int:
    """``fretbem sweep SWEEP.toml [--engine E] [--scheduler ADDRESS] [--serial] [--out DIR]
    [--workers N]``."""
    parser = argparse.ArgumentParser(
        prog="fretbem sweep",
        description="Run a parameter sweep (fretting map) described in a sweep TOML file.",
    )
    add_arguments(parser)
    return run_command(parser.parse_args(argv))


def run_command(args) -> int:
    """Run a parsed ``fretbem sweep`` command line; returns the exit status."""
    try:
        spec = load_sweep(args.sweep_file)
        path = Path(args.sweep_file)
        out = args.out or spec.options.get("out")
        out = Path(out) if out else Path(f"{path.stem}-sweep")
        if args.maps_only:
            return _redraw(spec, out)
        result = run_sweep(
            spec,
            out,
            scheduler=args.scheduler,
            serial=args.serial,
            engine=getattr(args, "engine", None),
            workers=args.workers,
            batch=args.batch,
            limit=args.limit,
            progress=not getattr(args, "quiet", False),
        )
        print(result.summary)
        if not args.no_figures and not result.summary.stopped:
            for figure in draw_maps(result.table, spec, out):
                print(f"  figure: {figure}")
    except (FretbemError, ValueError, OSError) as err:
        print(f"fretbem sweep: error: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(
            "fretbem sweep: interrupted; the finished batches are stored, re-run the same "
            "command to complete the sweep",
            file=sys.stderr,
        )
        return 130
    return 0


def _redraw(spec: SweepSpec, out: Path) -> int:
    """``--maps-only``: the maps of a finished store, its fingerprint checked."""
    SweepStore.open_existing(out, spec.fingerprint())
    table = read_table(out)
    check_maps(spec, set(table.columns))
    for figure in draw_maps(table, spec, out):
        print(f"  figure: {figure}")
    return 0


__all__ = [
    "BLAS_ENV",
    "ENGINES",
    "MAX_CASES",
    "POST_TABLES",
    "SweepError",
    "SweepResult",
    "SweepSummary",
    "Task",
    "add_arguments",
    "check_size",
    "choose_engine",
    "fork_available",
    "fork_safe_threads",
    "machine_cores",
    "plan",
    "run_command",
    "run_sweep",
    "sweep",
    "sweep_columns",
    "sweep_command",
]
