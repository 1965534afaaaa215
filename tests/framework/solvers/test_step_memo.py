"""Step prefixes reused between histories on one condensed problem (a sweep's cases)."""

from __future__ import annotations

import attrs
import numpy as np
import pytest

from fretbem.contact.law import CoulombFriction
from fretbem.simulation import LoadStep, run
from fretbem.solvers.newton import SemiSmoothNewton
from fretbem.solvers.step_memo import StepMemo
from fretbem.studies.sweep.cases import build_simulation
from fretbem.testing.scenes import SMALL_SCENE

SCENE = SMALL_SCENE


@pytest.fixture(scope="module")
def prepared():
    simulation = build_simulation(SCENE)
    simulation.prepare()
    return simulation


def _history(p: float, q: float, increments: int = 1):
    return tuple(
        LoadStep(name, p, sign * q, increments)
        for name, sign in zip("ABCDE", (0.0, 1.0, 0.0, -1.0, 0.0), strict=True)
    )


def _case(simulation, p, q, friction=0.3, increments=1):
    # a fresh solver per case, as a sweep case reads it from its scene
    return attrs.evolve(
        simulation,
        steps=_history(p, q, increments),
        law=CoulombFriction(friction),
        solver=SemiSmoothNewton(),
    )


def _equal(a, b, rel):
    assert [s.name for s in a.steps] == [s.name for s in b.steps]
    for sa, sb in zip(a.steps, b.steps, strict=True):
        scale = np.max(np.abs(sb.unknowns))
        assert np.max(np.abs(sa.unknowns - sb.unknowns)) <= rel * scale, sa.name
        assert sa.iterations == sb.iterations, sa.name
        assert np.array_equal(sa.states, sb.states), sa.name
        assert len(sa.increments) == len(sb.increments)


@pytest.mark.parametrize("increments", [1, 2])
def test_cases_sharing_their_first_step_equal_their_standalone_runs(prepared, increments):
    """A P x Q map: every case after the first of its P takes step A from the memo. Each
    case equals its own standalone run: the reused step bit for bit (the same solve with a
    fresh solver), the later ones to round-off (measured 6e-13 relative; their Newton
    starts on the same state and pattern, only the LU kept from the last pattern differs),
    with the same iterations and states."""
    memo = StepMemo()
    for p in (80.0, 120.0):
        for q in (0.0, 6.0, 12.0, 20.0):
            case = _case(prepared, p, q, increments=increments)
            shared = run(case, memo=memo)
            alone = run(_case(prepared, p, q, increments=increments))
            _equal(shared, alone, 1e-10)
            assert np.array_equal(shared.steps[0].unknowns, alone.steps[0].unknowns)
    assert memo.hits == 2 * 3  # step A of the last three Q values of each P


def test_a_different_prefix_friction_or_solver_is_not_reused(prepared):
    memo = StepMemo()
    run(_case(prepared, 100.0, 10.0), memo=memo)
    run(_case(prepared, 90.0, 10.0), memo=memo)  # another P: step A differs
    assert memo.hits == 0
    run(_case(prepared, 100.0, 10.0, friction=0.5), memo=memo)  # another law: memo restarts
    assert memo.hits == 0
    run(_case(prepared, 100.0, 12.0, friction=0.5), memo=memo)
    assert memo.hits == 1
    tighter = attrs.evolve(_case(prepared, 100.0, 12.0, friction=0.5),
                           solver=SemiSmoothNewton(tolerance=1e-11))  # fmt: skip
    run(tighter, memo=memo)
    assert memo.hits == 1
    # the same history twice: every step but the last is taken, and the result is the same
    memo = StepMemo()
    first = run(_case(prepared, 100.0, 10.0), memo=memo)
    again = run(_case(prepared, 100.0, 10.0), memo=memo)
    assert memo.hits == 4
    _equal(again, first, 1e-10)


def test_a_full_memo_starts_again_empty(prepared):
    memo = StepMemo(capacity=1)  # smaller than one step: nothing is kept
    run(_case(prepared, 100.0, 10.0), memo=memo)
    run(_case(prepared, 100.0, 12.0), memo=memo)
    assert memo.hits == 0 and memo.nbytes == 0
    memo = StepMemo()
    run(_case(prepared, 100.0, 10.0), memo=memo)
    kept = memo.nbytes
    assert kept > 0
    memo.capacity = kept  # room for exactly what one history keeps
    run(_case(prepared, 90.0, 10.0), memo=memo)  # overflows: emptied, then nothing kept
    run(_case(prepared, 90.0, 12.0), memo=memo)
    assert memo.hits == 0 and memo.nbytes <= kept
