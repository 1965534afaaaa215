"""Inside ``kept_memory`` a large array lives on the heap and its memory stays there when it
is freed, and numpy asks for no huge pages; outside (after the block, and when not enabled)
an array is mapped by itself and the settings are back."""

from __future__ import annotations

import ctypes

import numpy as np
import pytest

import fretbem.simulation as simulation_module
from fretbem.numerics import memory
from fretbem.scenes import cattaneo_mindlin
from fretbem.simulation import run


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
