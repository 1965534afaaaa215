"""Solving a batch of sweep cases that share one condensed contact problem.

The group's bodies are built once from a *representative* scene: the first case's scene
with the largest normal load of the group (the candidate contact zone is sized from the Hertz
half-width of that load, so every case's contact lies inside it), zero tangential load and a
bulk load column if any case loads one. Each case then only swaps the load steps, the
friction and the analytical reference on the same contact pair, so its cost is the Newton
solve alone. Workers keep the last groups they built, so batches of one group that land on
the same worker assemble once.
"""

from __future__ import annotations

import contextlib
import copy
import json
import os
import socket
import time
from collections import OrderedDict
from collections.abc import Callable, Iterator, Mapping, Sequence
from typing import Any

import attrs
import numpy as np

from fretbem.accuracy.modes import Accuracy, mode_of
from fretbem.contact.law import CoulombFriction
from fretbem.contact.pairs import SEPARATED, SLIP, STICK
from fretbem.errors import ComputationError
from fretbem.fretting import analyse
from fretbem.pipeline import run_scene, run_simulation
from fretbem.scenes import builder as scene_build
from fretbem.scenes.file import scene_from_data
from fretbem.scenes.reference import CattaneoMindlinScene, cattaneo_mindlin
from fretbem.simulation import LoadStep, run_resources
from fretbem.solvers.step_memo import StepMemo
from fretbem.studies.sweep.outputs import resolve_all

#: worst first: the regime of a cycle is the worst regime of its steps
REGIMES = ("full stick", "partial slip", "gross slip")

#: per-step output columns, named ``<quantity>.<step>``
STEP_COLUMNS = ("regime", "stick_width", "contact_width", "p_max", "q_max", "iterations")

#: columns that differ from run to run (timings, worker names): not part of the result
TIMING_COLUMNS = ("solve_seconds", "solve_cpu_seconds", "assembly_seconds", "worker")


class GroupBuildError(ComputationError):
    """The bodies of a condensation group could not be built or condensed."""


@attrs.frozen
class Loading:
    """What a case changes on a shared problem: steps, friction, reference, solver."""

    steps: tuple
    friction: float
    reference: Any = None
    solver: Any = None  #: None keeps the group's solver


def parse_scene(scene: Mapping):
    """The scene record of a scene dict (the round-1 format translated by the file reader)."""

    return scene_from_data(dict(scene))


def _round_one(record) -> bool:
    return isinstance(record, CattaneoMindlinScene)


def build_simulation(scene: Mapping):
    """The Simulation a scene dict describes (round-1 format or the two-body format)."""
    record = parse_scene(scene)
    if _round_one(record):
        return cattaneo_mindlin(record)

    simulation, _ = scene_build.build(record)
    return simulation


def case_loading(scene: Mapping) -> Loading:
    """The load steps, friction, reference and solver of a scene dict, without bodies."""

    record = parse_scene(scene)
    if _round_one(record):
        steps = tuple(
            LoadStep(name, record.normal, q, record.increments)
            for name, q in zip(record.names, record.tangential, strict=True)
        )
        return Loading(steps, float(record.friction), record.reference())

    steps = scene_build.load_steps(record.load)
    return Loading(
        steps,
        float(record.contact.friction),
        scene_build.reference(record)[0],
        scene_build.solver(record.contact.solver),
    )


def representative(scenes: Sequence[Mapping]) -> dict:
    """The scene a group's bodies are built from (see the module docstring).

    Computed from the whole group before it is split into batches, so every batch of a
    group solves on the same discretisation.
    """
    scene = copy.deepcopy(dict(scenes[0]))
    loads = [s.get("load", {}) for s in scenes]
    normal = [abs(float(v)) for ld in loads for v in np.ravel(ld.get("P", []))]
    load = scene.setdefault("load", {})
    if normal:
        load["P"] = max(normal)

    def zeros(value, fill):
        return [fill] * len(value) if isinstance(value, list) else fill

    if "Q" in load:
        load["Q"] = zeros(load["Q"], 0.0)
    if any("bulk" in ld for ld in loads):
        loaded = any(float(v) != 0 for ld in loads for v in np.ravel(ld.get("bulk", 0.0)))
        load["bulk"] = zeros(load.get("bulk", 0.0), 1.0 if loaded else 0.0)
    scene.setdefault("contact", {})["friction"] = 1.0
    return scene


def _has_law(simulation) -> bool:
    return "law" in attrs.fields_dict(type(simulation))


def with_loading(simulation, loading: Loading):
    """``simulation`` on the same (already condensed) pair with another loading."""
    if _has_law(simulation):
        return attrs.evolve(
            simulation,
            steps=loading.steps,
            law=CoulombFriction(loading.friction),
            reference=loading.reference,
            solver=simulation.solver if loading.solver is None else loading.solver,
        )
    # round-1 API: the friction sits on the pair; share its cached condensation
    pair = simulation.pair
    if pair.friction != loading.friction:
        shared = pair
        pair = attrs.evolve(shared, friction=loading.friction)
        pair._cache.update(shared._cache)
    return attrs.evolve(simulation, pair=pair, steps=loading.steps, reference=loading.reference)


def refused_steps(loading: Loading) -> list[str]:
    """Steps with ``|Q| >= f P`` under force control: gross slip, refused there (a step that
    imposes delta or the approach is solved: its Q or P is an output)."""
    return [
        s.name
        for s in loading.steps
        if getattr(s, "delta", None) is None
        and s.normal is not None
        and abs(s.tangential) >= loading.friction * s.normal
    ]


#: fretting columns of a cyclic case (its last cycle; fretbem.fretting)
CYCLE_COLUMNS = ("dissipated_energy", "delta_amplitude", "Q_amplitude", "energy_ratio",
                 "slip_amplitude_max")  # fmt: skip
#: the fretting regimes as the sweep names them
CYCLE_REGIMES = {"stick": "full stick", "partial slip": "partial slip", "gross slip": "gross slip"}


#: the pad block's rotation in a case whose block rotates, as the run's summary.json names
#: them: per step (``M.B``) ...
ROTATION_COLUMNS = ("M", "theta", "tilt")
#: ... or, in a cyclic case, half their ranges over the last cycle
ROTATION_CYCLE_COLUMNS = tuple(f"{name}_amplitude" for name in ROTATION_COLUMNS)


def rotates(simulation) -> bool:
    """Whether the pad block of ``simulation`` rotates (its rotation is an unknown)."""
    return bool(getattr(simulation, "rotates", False))


def scene_rotates(scene: Mapping, steps: Sequence) -> bool:
    """Whether a scene dict with load ``steps`` turns the pad's block, as the Simulation it
    builds would (:attr:`fretbem.simulation.Simulation.rotates`): a rotational rig spring,
    or a step that gives a moment or a rotation."""
    rig = scene.get("rig")
    spring = isinstance(rig, Mapping) and rig.get("stiffness_rotation") is not None
    return spring or any(getattr(step, "turns", False) for step in steps)


def cycle_metrics(result) -> dict[str, Any] | None:
    """Regime and fretting columns of the last load cycle of ``result`` (None: no cycles);
    with a rotating pad block, the amplitudes of its M, theta and tilt over that cycle."""
    if not any(getattr(s, "cycle", 0) for s in result.simulation.steps):
        return None
    analysis = analyse(result)
    last = analysis.cycles[-1].as_dict()
    row = {name: last[name] for name in CYCLE_COLUMNS}
    row["transition_ratio"] = analysis.transition_ratio
    row["regime"] = CYCLE_REGIMES[last["regime"]]
    row["cycles"] = len(analysis.cycles)
    if rotates(result.simulation):
        records = [record for step in result.steps for record in step.increments]
        loop = [records[k - 1] for k in analysis.cycles[-1].increments]
        for column, name in zip(ROTATION_CYCLE_COLUMNS, ("moment", "rotation", "tilt"),
                                strict=True):  # fmt: skip
            row[column] = 0.5 * float(np.ptp([getattr(r, name) for r in loop]))
    return row


def _extent(x: np.ndarray, mask: np.ndarray) -> float:
    return float(x[mask].max() - x[mask].min()) if mask.any() else 0.0


def step_metrics(step) -> dict[str, Any]:
    """Regime, stick and contact widths, peak p and ``|q|``, iterations of one solved step."""
    states = np.asarray(step.states)
    stick, slip = states == STICK, states == SLIP
    if not slip.any():
        regime = "full stick"
    elif stick.any():
        regime = "partial slip"
    else:
        regime = "gross slip"
    return {
        "regime": regime,
        "stick_width": _extent(step.x, stick),
        "contact_width": _extent(step.x, states != SEPARATED),
        "p_max": float(np.max(step.pressure)),
        "q_max": float(np.max(np.abs(step.shear))),
        "iterations": int(step.iterations),
    }


def rotation_metrics(step) -> dict[str, float]:
    """M, theta and tilt of one solved step (a case whose pad block rotates)."""
    return dict(zip(ROTATION_COLUMNS, (step.moment, step.rotation, step.tilt), strict=True))


def worst(regimes: Sequence[str]) -> str:
    """The most severe regime of a cycle (gross slip > partial slip > full stick)."""
    return max(regimes, key=REGIMES.index)


#: the groups this process built last: (simulation, its StepMemo) by representative scene
_GROUPS: OrderedDict[str, tuple[Any, StepMemo]] = OrderedDict()
_KEEP = 2


def group_key(scene: Mapping) -> str:
    """The key of a group's representative scene in this process's cache."""
    return json.dumps(scene, sort_keys=True)


def _group_simulation(key: str, scene: dict, held: contextlib.ExitStack) -> tuple:
    """The group's condensed simulation and step memo, built here or taken from this
    process's cache (seconds spent building: 0 when cached), its run's resource block
    entered on ``held`` before it is assembled."""
    if key in _GROUPS:
        _GROUPS.move_to_end(key)
        held.enter_context(run_resources(_GROUPS[key][0]))
        return (*_GROUPS[key], 0.0)
    start = time.perf_counter()
    simulation = build_simulation(scene)
    held.enter_context(run_resources(simulation))
    simulation.prepare()
    seconds = time.perf_counter() - start
    keep_group(key, simulation)
    return (*_GROUPS[key], seconds)


def keep_group(key: str, simulation) -> None:
    """Keep a prepared group simulation in this process's cache (e.g. one sent by the
    process that built it), with a new step memo."""
    _GROUPS[key] = (simulation, StepMemo())
    _GROUPS.move_to_end(key)
    while len(_GROUPS) > _KEEP:
        _GROUPS.popitem(last=False)


#: a case is one fixed-mesh level on the group's shared assembly (no companion estimate)
FIXED = Accuracy(mesh="fixed", estimate=False)


def _error(err: BaseException) -> str:
    return f"{type(err).__name__}: {err}"


def _adaptive(scene: Mapping | None) -> bool:
    contact = (scene or {}).get("contact")
    return isinstance(contact, Mapping) and contact.get("mesh") == "adaptive"


def solve_case(simulation, loading: Loading, outputs=(), scene=None, memo=None) -> dict[str, Any]:
    """Solve one case on the group's problem; returns its output columns.

    ``outputs`` are extra column functions (see ``sweep_outputs``) called with the result
    and the case's ``scene`` dict; ``memo`` (a StepMemo of the group) lends the load steps
    an earlier case of the group solved (e.g. the same normal load).
    """

    row: dict[str, Any] = {
        "friction": loading.friction,
        "P_max": max((abs(s.normal) for s in loading.steps if s.normal is not None),
                     default=float("nan")),
        "Q_peak": max(abs(s.tangential) for s in loading.steps),
    }  # fmt: skip
    refused = refused_steps(loading)
    if refused:
        row.update(status="refused", error=f"|Q| >= f P in steps {refused}")
        row["regime"] = "gross slip"
        for step in loading.steps:
            row[f"regime.{step.name}"] = "gross slip" if step.name in refused else "not run"
        return row
    tic, cpu = time.perf_counter(), time.process_time()
    if _adaptive(scene):
        # an adaptive scene re-meshes per case: solved whole, as `fretbem run` solves it
        record = parse_scene(scene)
        result = run_scene(record, mode=mode_of(record)).result
    else:
        result = run_simulation(with_loading(simulation, loading), mode=FIXED, memo=memo).result
    row["pairs"] = int(result.simulation.pair.n_pairs)
    row["solve_seconds"] = time.perf_counter() - tic
    row["solve_cpu_seconds"] = time.process_time() - cpu
    if any(not s.controls.by_force for s in getattr(result.simulation, "steps", ())):
        row["P_max"] = max(abs(i.normal) for s in result.steps for i in s.increments)
        row["Q_peak"] = max(abs(i.tangential) for s in result.steps for i in s.increments)
    cyclic = cycle_metrics(result)
    if cyclic is not None:  # one row per case: the last cycle, not hundreds of step columns
        regime = cyclic.pop("regime")
        row.update(cyclic)
    else:
        regimes = []
        turning = rotates(result.simulation)
        for step in result.steps:
            metrics = step_metrics(step)
            if turning:
                metrics.update(rotation_metrics(step))
            for key, value in metrics.items():
                row[f"{key}.{step.name}"] = value
            regimes.append(row[f"regime.{step.name}"])
        regime = worst(regimes)
    for function in outputs:
        row.update(function(result, scene))
    row.update(status="ok", error="", regime=regime)
    return row


#: output functions of the running sweep by their names: resolving them scans the installed
#: entry points (about 5 ms, half a case), and the default engine solves its first cases one
#: call each; emptied when a sweep starts (:func:`forget_outputs`)
_OUTPUTS: dict[tuple[str, ...], tuple] = {}


def _output_functions(outputs: Sequence[str]) -> tuple:
    key = (outputs,) if isinstance(outputs, str) else tuple(outputs)
    if key not in _OUTPUTS:
        _OUTPUTS[key] = resolve_all(key)
    return _OUTPUTS[key]


def forget_outputs() -> None:
    """Resolve the output functions again on the next batch (a new sweep starts)."""
    _OUTPUTS.clear()


def run_batch(
    scene: dict,
    cases: Sequence[tuple[int, dict, dict]],
    builder: Callable[[Mapping], Any] | None = None,
    outputs: Sequence[str] = (),
    extras: Mapping[str, Any] | None = None,
    prepared=None,
) -> list[dict[str, Any]]:
    """Solve ``cases`` (index, parameter values, scene dict) on the bodies of ``scene``.

    ``scene`` is the group's representative scene; ``outputs`` names extra column functions
    ("module:function"), called with the result and the case's scene plus ``extras`` (tables
    of the sweep file such as ``fatigue``). Never raises for a case: a failing case becomes a
    row with status "error" and the message; a group whose bodies cannot be built fails every
    one of its cases that way. ``prepared``: the group's simulation as another process
    prepared it (pickled to this one), taken instead of assembling it here.
    """

    return list(batch_rows(scene, cases, builder, outputs, extras, prepared))


def batch_rows(scene: dict, cases: Sequence[tuple[int, dict, dict]], builder=None,
               outputs: Sequence[str] = (), extras=None, prepared=None,
               ) -> Iterator[dict[str, Any]]:  # fmt: skip
    """The rows of :func:`run_batch` (same arguments), each as soon as its case is solved:
    a caller that decides between cases (the default engine's estimate) stops by closing
    the iterator, the group looked up and its resource block entered once, as for a batch."""
    with contextlib.ExitStack() as held:  # the group's run block: its assembly to its last case
        yield from _batch(scene, cases, builder, outputs, extras, prepared, held)


def _batch(scene, cases, builder, outputs, extras, prepared, held) -> Iterator[dict[str, Any]]:
    """:func:`batch_rows` with its group's resource block entered on ``held``."""
    worker = f"{socket.gethostname()}:{os.getpid()}"
    simulation, memo, assembly, failure = None, None, 0.0, None
    try:
        functions = _output_functions(outputs)
        if builder is None:
            key = group_key(scene)
            if prepared is not None and key not in _GROUPS:
                keep_group(key, prepared)
            simulation, memo, assembly = _group_simulation(key, scene, held)
        else:
            tic = time.perf_counter()
            simulation = builder(scene)
            held.enter_context(run_resources(simulation))
            simulation.prepare()
            memo = StepMemo()
            assembly = time.perf_counter() - tic
    except Exception as err:  # recorded on every case of the group, not fatal
        failure = _error(err)
    for index, values, case_scene in cases:
        row: dict[str, Any] = {"case": index, **values, "worker": worker}
        try:
            loading = case_loading(case_scene)
            if failure is not None:
                raise GroupBuildError(f"the group's bodies could not be built: {failure}")
            context = {**(extras or {}), **case_scene}  # swept [fatigue] keys win
            row.update(solve_case(simulation, loading, functions, context, memo))
        except Exception as err:
            row.update(status="error", error=_error(err), regime="")
        row["assembly_seconds"] = assembly
        assembly = 0.0  # paid once per batch: charged to its first case
        yield row


__all__ = [
    "REGIMES",
    "STEP_COLUMNS",
    "TIMING_COLUMNS",
    "GroupBuildError",
    "Loading",
    "batch_rows",
    "build_simulation",
    "case_loading",
    "forget_outputs",
    "group_key",
    "keep_group",
    "parse_scene",
    "refused_steps",
    "representative",
    "run_batch",
    "solve_case",
    "step_metrics",
    "with_loading",
    "worst",
]
