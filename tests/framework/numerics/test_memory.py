"""Inside ``kept_memory`` a large array lives on the heap and its memory stays there when it
is freed, and numpy asks for no huge pages; outside (after the block, and when not enabled)
an array is mapped by itself and the settings are back. Every run path (run, finite
sliding, wear, a sweep's batch, the run pipeline) solves inside the block
(``run_resources``), checked against the memory once."""

from __future__ import annotations

import copy
import ctypes

import numpy as np
import pytest

import fretbem.simulation as simulation_module
from fretbem.numerics import memory
from fretbem.pipeline import run_simulation
from fretbem.scenes import cattaneo_mindlin
from fretbem.scenes.builder import build
from fretbem.scenes.file import scene_from_data
from fretbem.simulation import run
from fretbem.sliding.slide import run_sliding
from fretbem.studies.sweep import cases as sweep_cases
from fretbem.testing.scenes import SMALL_SCENE
from fretbem.wear.law import ArchardWear
from fretbem.wear.run import WearSimulation, run_wear


class _MallInfo2(ctypes.Structure):
    _fields_ = [
        (name, ctypes.c_size_t)
        for name in ("arena ordblks smblks hblks hblkhd usmblks fsmblks uordblks fordblks "
                     "keepcost").split()
    ]  # fmt: skip


@pytest.fixture
def heap():
    """(heap bytes, separately mapped bytes) of the process (glibc >= 2.33)."""
    libc = memory._glibc()
    if not libc or not hasattr(libc, "mallinfo2"):
        pytest.skip("needs glibc's mallinfo2")
    libc.mallinfo2.restype = _MallInfo2

    def read() -> tuple[int, int]:
        info = libc.mallinfo2()
        return info.arena, info.hblkhd

    return read


SIZE = 64 * 2**20  # bytes: above glibc's largest mmap threshold (32 MB)


def _mapped_alone(heap) -> bool:
    """Whether a fresh 64 MB array is mapped by itself (not on the heap)."""
    before = heap()[1]
    array = np.empty(SIZE // 8)
    alone = heap()[1] - before >= SIZE
    del array
    return alone


def test_large_arrays_stay_on_the_heap_inside_the_block(heap):
    assert _mapped_alone(heap)
    with memory.kept_memory():
        arena = heap()[0]
        assert not _mapped_alone(heap)
        grown = heap()[0]
        assert grown >= arena + SIZE // 2  # freed, but kept for the next one
        assert not _mapped_alone(heap)
        assert heap()[0] == grown  # which takes it
        with memory.kept_memory():  # nested: still kept after the inner block
            pass
        assert not _mapped_alone(heap)
    assert _mapped_alone(heap)
    assert heap()[0] < arena + SIZE // 2  # given back at the end


def test_not_enabled_does_nothing(heap):
    with memory.kept_memory(enabled=False):
        assert _mapped_alone(heap)


def test_a_run_restores_the_allocator(heap, monkeypatch):
    seen = []
    monkeypatch.setattr(simulation_module, "KEPT_MEMORY_DOFS", 0)
    simulation = cattaneo_mindlin(pairs=21, models={})
    run(simulation, progress=lambda *args: seen.append(_mapped_alone(heap)))
    assert seen and not any(seen)  # kept during the run's steps
    assert _mapped_alone(heap)  # and restored after it


def test_no_huge_pages_inside_the_block():
    multiarray = np._core.multiarray
    before = multiarray._get_madvise_hugepage()
    with memory.kept_memory():
        assert not multiarray._get_madvise_hugepage()
    assert multiarray._get_madvise_hugepage() == before


HALF_PLANES = {"upper": "half-plane", "lower": "half-plane"}


@pytest.fixture
def kept_from_zero(monkeypatch):
    """Every run keeps its memory (the threshold at 0 DOFs)."""
    monkeypatch.setattr(simulation_module, "KEPT_MEMORY_DOFS", 0)


def _sliding_scene(pairs=21):
    data = {
        "pad": {"shape": "cylinder", "radius": 70.0, "width": 6.5, "height": 16.25,
                "model": "half-plane"},
        "specimen": {"shape": "flat", "length": 20.0, "thickness": 10.0, "model": "half-plane"},
        "material": {"E": 73400.0, "nu": 0.33},
        "contact": {"friction": 0.3, "pairs": pairs, "pairing": "node-to-segment",
                    "sliding": True, "zone": 2.0},
        "load": {"steps": ["press", "A", "B"], "P": 100.0, "delta": [0.0, 0.2, -0.2],
                 "increments": [1, 3, 3]},
    }  # fmt: skip
    return build(scene_from_data(data))[0]


def test_finite_sliding_runs_in_the_block(heap, kept_from_zero):
    seen = []
    run_sliding(_sliding_scene(), note=None, progress=lambda *a: seen.append(_mapped_alone(heap)))
    assert len(seen) == 3 and not any(seen)
    assert _mapped_alone(heap)


@pytest.mark.parametrize("sliding", [False, True])
def test_a_wear_history_runs_in_the_block(heap, kept_from_zero, sliding):
    if sliding:
        simulation, k, cycles = _sliding_scene(), 1e-9, 100
    else:
        simulation = cattaneo_mindlin(pairs=21, increments=3, lower="flat", models=HALF_PLANES)
        k, cycles = 1e-7, 1000
    laws = {"upper": ArchardWear(k), "lower": ArchardWear(k)}
    seen = []
    wear = WearSimulation(simulation, laws, cycles, sliding=sliding)
    run_wear(wear, progress=lambda *a: seen.append(_mapped_alone(heap)))
    assert seen and not any(seen)  # after every jump
    assert _mapped_alone(heap)


#: a small sweep group, two loads
SWEEP_SCENE = SMALL_SCENE


def test_a_sweep_batch_runs_in_one_block_from_its_assembly(heap, kept_from_zero, monkeypatch):
    """The group's bodies are assembled and every case solved in one block."""
    seen, solve = [], sweep_cases.solve_case
    prepare = simulation_module.Simulation.prepare

    def solve_case(*args, **kwargs):
        seen.append(("case", _mapped_alone(heap)))
        return solve(*args, **kwargs)

    def prepared(simulation):
        seen.append(("assembly", _mapped_alone(heap)))
        return prepare(simulation)

    monkeypatch.setattr(sweep_cases, "solve_case", solve_case)
    monkeypatch.setattr(simulation_module.Simulation, "prepare", prepared)
    second = copy.deepcopy(SWEEP_SCENE)
    second["load"]["Q"] = [0.0, 12.0, 0.0, -12.0, 0.0]
    sweep_cases._GROUPS.clear()
    rows = sweep_cases.run_batch(SWEEP_SCENE, [(0, {}, SWEEP_SCENE), (1, {}, second)])
    assert [row["status"] for row in rows] == ["ok", "ok"], rows
    assert seen[0] == ("assembly", False) and ("case", False) in seen
    assert not any(alone for _, alone in seen)
    assert _mapped_alone(heap)


def test_the_pipeline_checks_once_and_holds_the_block_over_its_phases(
    heap, kept_from_zero, monkeypatch
):
    """The solve, its companion level and a comparison family run in the pipeline's block,
    whose check is the only one (the runs inside read no memory again)."""
    checked, said = [], []
    monkeypatch.setattr(
        simulation_module, "check_resources", lambda dofs, **size: checked.append(dofs)
    )
    simulation = cattaneo_mindlin(pairs=21, models={})
    other = cattaneo_mindlin(pairs=21, models={}, basis="lagrange2")
    run_simulation(
        simulation, companion=lambda pairs: cattaneo_mindlin(pairs=pairs, models={}),
        compare=[other], say=lambda line: said.append(_mapped_alone(heap)),
    )  # fmt: skip
    dofs = simulation.pair.upper.dofs + simulation.pair.lower.dofs
    larger = other.pair.upper.dofs + other.pair.lower.dofs
    assert checked == [dofs, larger]  # the family with more DOFs is checked for them
    assert said and not any(said)
    assert _mapped_alone(heap)
