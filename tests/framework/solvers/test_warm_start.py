"""Newton starts from a solved run on another contact mesh (the adaptive mode's levels)."""

from __future__ import annotations

import attrs
import numpy as np
import pytest

from fretbem.accuracy.remesh import remesh
from fretbem.scenes import cattaneo_mindlin
from fretbem.simulation import LoadStep, run
from fretbem.solvers.newton import SemiSmoothNewton, SolverConvergenceError
from fretbem.solvers.warm_start import WarmStart


@pytest.fixture(scope="module")
def coarse():
    return run(cattaneo_mindlin(pairs=31))


def _uniform(pairs: int, **overrides):
    return remesh(cattaneo_mindlin(pairs=31, **overrides), np.array([]), pairs, ratio=1.0)


def _same_solution(warm, cold, rel):
    for a, b in zip(warm.steps, cold.steps, strict=True):
        assert np.array_equal(a.states, b.states), a.name
        scale = np.abs(b.unknowns[: 2 * b.x.size]).max()
        assert np.abs(a.unknowns - b.unknowns).max() <= rel * scale, a.name


@pytest.mark.parametrize("pairs", [41, 61, 81])
def test_a_warm_start_reaches_the_cold_solution_in_fewer_iterations(coarse, pairs):
    cold = run(_uniform(pairs))
    warm = run(_uniform(pairs), warm=WarmStart.of(coarse))
    # measured: 7.6e-14 (41 pairs), 1.3e-13 (61), 6.8e-13 (81) of the largest traction (the
    # solver's tolerance is 1e-10 on the residual); 29 -> 10 iterations at 61 pairs
    _same_solution(warm, cold, 5e-12)
    assert sum(s.iterations for s in warm.steps) < sum(s.iterations for s in cold.steps)


def test_increments_and_the_other_family_start_warm_too():
    steps = tuple(
        LoadStep(s.name, s.normal, s.tangential, 2)
        for s in cattaneo_mindlin(pairs=31, basis="lagrange2").steps
    )
    coarse = run(attrs.evolve(_uniform(31, basis="lagrange2"), steps=steps))
    fine = attrs.evolve(_uniform(61, basis="lagrange2"), steps=steps)
    cold, warm = run(fine), run(fine, warm=WarmStart.of(coarse))
    _same_solution(warm, cold, 5e-12)  # measured 4.4e-13; 40 -> 11 iterations
    for a, b in zip(warm.steps, cold.steps, strict=True):
        assert len(a.increments) == len(b.increments) == 2
        for ra, rb in zip(a.increments, b.increments, strict=True):
            assert np.array_equal(ra.states, rb.states)
    assert sum(s.iterations for s in warm.steps) < sum(s.iterations for s in cold.steps)


def test_a_history_the_solved_run_does_not_have_starts_cold(coarse):
    fine = _uniform(61)
    other = attrs.evolve(fine, steps=tuple(attrs.evolve(s, name=s.name + "2") for s in fine.steps))
    warm = run(other, warm=WarmStart.of(coarse))
    cold = run(other)
    for a, b in zip(warm.steps, cold.steps, strict=True):
        assert a.iterations == b.iterations
        assert np.array_equal(a.unknowns, b.unknowns)


@attrs.frozen
class _RefusingWarmStarts(SemiSmoothNewton):
    """Newton that fails every increment started off the previous state (a warm start)."""

    def solve_increment(self, problem, law, *, forces, loads, previous, start):
        if start is not None and start is not previous:
            raise SolverConvergenceError("warm start refused", [1.0, 0.5])
        return super().solve_increment(
            problem, law, forces=forces, loads=loads, previous=previous, start=start
        )


def test_a_failed_warm_start_is_solved_again_from_the_usual_start(coarse):
    fine = _uniform(61)
    cold = run(fine)
    warm = run(attrs.evolve(fine, solver=_RefusingWarmStarts()), warm=WarmStart.of(coarse))
    for a, b in zip(warm.steps, cold.steps, strict=True):
        assert np.array_equal(a.unknowns, b.unknowns)
        # the refused attempt's two iterations are reported with the solve's
        assert a.iterations == b.iterations + 2
        assert a.residuals[:2] == (1.0, 0.5)
