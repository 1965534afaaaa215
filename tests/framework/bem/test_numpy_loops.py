"""The numpy assembly loops' scratch arrays: per thread, reused, never shared."""

from __future__ import annotations

import threading

import numpy as np
import pytest

from fretbem.bem import assembly, numpy_loops
from fretbem.bem.integration import Assembler, IntegrationSettings
from fretbem.bem.kernels import KelvinKernel
from fretbem.scenes import cattaneo_mindlin


def _assemble(body):
    settings = IntegrationSettings(compiled=False)
    return Assembler(body.segments, KelvinKernel.of(body.material), settings).assemble()


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
def test_bodies_assembled_in_threads_equal_serial_ones(basis):
    """Two threads assembling different bodies at once (a sweep on threads) each write the
    kernel into their own scratch: H and G equal the serial assembly's to the bit."""
    simulation = cattaneo_mindlin(basis=basis, pairs=21)
    bodies = (simulation.pair.upper, simulation.pair.lower)
    assembly.BLOCKS.clear()
    serial = [_assemble(body) for body in bodies]
    results: dict[int, tuple] = {}
    start = threading.Barrier(2)

    def work(k: int) -> None:
        start.wait()
        for _ in range(5):  # a shared scratch fails this in most runs
            results[k] = _assemble(bodies[k])

    assembly.BLOCKS.clear()  # no reused blocks: both threads integrate
    threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    for k in range(2):
        assert np.array_equal(results[k][0], serial[k][0])
        assert np.array_equal(results[k][1], serial[k][1])


def test_scratch_views_are_disjoint_and_the_buffer_only_grows():
    a, b = numpy_loops._scratch((3, 4), (5,))
    assert a.shape == (3, 4) and b.shape == (5,)
    assert not np.shares_memory(a, b)
    buffer = numpy_loops._SCRATCH.buffer
    numpy_loops._scratch((2,))
    assert numpy_loops._SCRATCH.buffer is buffer  # smaller: the same buffer
    (big,) = numpy_loops._scratch((buffer.size + 1,))
    assert numpy_loops._SCRATCH.buffer.size == buffer.size + 1 and big.size == buffer.size + 1
