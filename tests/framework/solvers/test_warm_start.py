"""Newton starts from a solved run on another contact mesh (the adaptive mode's levels)."""

from __future__ import annotations

from types import SimpleNamespace

import attrs
import numpy as np
import pytest

from fretbem.accuracy import estimate
from fretbem.accuracy.adaptive import AdaptiveSettings, run_adaptive
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


# -- the pattern's change at a knot on a solved pair ------------------------------------------
def _mapper(knots, new=(0.5, 1.0, 1.3, 1.8, 2.5), states=(0, 0, 1, 1)):
    """A mapper from a solved run of pairs at x = 0..3 (``states``) to pairs at ``new``."""
    old = np.array([[x, 0.0] for x in range(len(states))])
    steps = (("A", ((np.array(states), np.zeros(len(states)), np.zeros(len(states))),)),)
    warm = WarmStart(points=old, steps=steps, knots=np.array([[k, 0.0] for k in knots]))
    n = len(new)
    problem = SimpleNamespace(
        pairing=SimpleNamespace(
            points=np.array([[x, 0.0] for x in new]), tangents=np.tile([1.0, 0.0], (n, 1))
        ),
        layout=SimpleNamespace(pressure=np.arange(n), shear=n + np.arange(n)),
    )
    return warm.mapper(problem)


def _pattern(mapper):
    n = mapper.new.size
    state = SimpleNamespace(x=np.zeros(2 * n), slip=np.zeros(n))
    return mapper.start("A", 1, 1, state).states.tolist()


def test_the_pattern_changes_at_a_knot_on_a_solved_pair():
    # nearest solved pair: the change halfway between x = 1 and 2
    assert _pattern(_mapper([])) == [0, 0, 0, 1, 1]
    # a knot on the solved pair at x = 1: the new pairs past it take the next pair's state,
    # the pair on the knot keeps its own
    assert _pattern(_mapper([1.0])) == [0, 0, 1, 1, 1]
    # the same from the other side: a knot on the pair at x = 2
    assert _pattern(_mapper([2.0], new=(1.2, 1.7, 2.0, 2.5))) == [0, 0, 1, 1]
    # a knot between solved pairs, or where the pairs around it agree: the nearest pair's
    assert _pattern(_mapper([1.5])) == [0, 0, 0, 1, 1]
    assert _pattern(_mapper([1.0], states=(0, 0, 0, 1))) == [0, 0, 0, 0, 0]


def test_knots_handed_on_start_the_finer_level_on_its_own_pattern():
    """The reference scene at budget 61: the first 61-pair level starts on the settled
    31-pair level, its knots on that level's knot points. Told the knots, its start's
    pattern is its own converged one (1 iteration a step; 3 without); the solution is the
    same to the solver's tolerance (measured 2.1e-12 of the largest traction)."""
    out = run_adaptive(cattaneo_mindlin(pairs=61), AdaptiveSettings(budget=61, first=31))
    settled, level = out.levels[2], out.levels[3]
    knots = out.transitions[2].all
    tangent = estimate.pair_frame(level.simulation.pair)[1][0]
    told = run(level.simulation, warm=WarmStart.of(settled, np.outer(knots, tangent)))
    untold = run(level.simulation, warm=WarmStart.of(settled))
    cold = run(level.simulation)
    _same_solution(told, cold, 5e-12)
    _same_solution(untold, cold, 5e-12)
    assert [s.iterations for s in told.steps] == [1] * 5
    # the adaptive mode tells its levels their knots (fretbem.accuracy.adaptive.settle)
    assert [s.iterations for s in level.steps] == [1] * 5
    assert sum(s.iterations for s in untold.steps) == 15
