"""Step records: the errors against theory, computed when first read."""

from __future__ import annotations

import pickle

import attrs
import numpy as np
import pytest

from fretbem.results import _Deferred
from fretbem.scenes import reference as scenes
from fretbem.simulation import run
from fretbem.verification.errors import errors_against_theory


def test_errors_are_computed_when_read_with_the_numbers_of_the_step():
    """The deferred errors and exact tractions are errors_against_theory's of the step's own
    x, p, q and tangential history, also after pickling and for an edited copy read first."""
    simulation = scenes.cattaneo_mindlin(pairs=21, models={"upper": "half-plane",
                                                           "lower": "half-plane"})  # fmt: skip
    result = run(simulation)
    history = []
    for step in result.steps:
        history.append(step.tangential)
        assert isinstance(step._errors, _Deferred) and step._errors.value is None
        edited = attrs.evolve(step, pressure=2 * step.pressure)
        copied = pickle.loads(pickle.dumps(step))
        errors, exact = errors_against_theory(
            simulation.reference, step.x, step.pressure, step.shear, history
        )
        for record in (edited, step, copied):  # the edited copy reads first
            assert record.errors == errors
            assert all(np.array_equal(a, b) for a, b in zip(record.exact, exact, strict=True))
    assert result.steps[1].errors["e_q_max"] < 0.1  # a Mindlin-Deresiewicz error, not a stub


def test_no_reference_no_errors():
    """A simulation without a closed form records None, as before."""
    simulation = attrs.evolve(scenes.cattaneo_mindlin(pairs=21), reference=None)
    step = run(simulation).steps[0]
    assert step.errors is None and step.exact is None


def test_a_step_built_from_its_last_increment_is_the_step_built_afresh():
    """StepResult.build with the last increment's record (and the run's positions, as run()
    gives them) has the fields it has without: the record's tractions, slip and states are
    the state's; frozen arrays are shared, never copied, and every array stays read-only."""
    from fretbem.results import IncrementRecord, StepResult, _frozen, pair_x

    simulation = scenes.cattaneo_mindlin(pairs=21, models={"upper": "half-plane",
                                                           "lower": "half-plane"})  # fmt: skip
    result = run(simulation)
    problem = simulation.prepare()
    for load, step in zip(simulation.steps, result.steps, strict=True):
        state = attrs.evolve(simulation_state(step), normal=step.normal, tangential=step.tangential)
        last = IncrementRecord.of(problem, state, simulation.rig)
        args = (simulation, problem, load, state, step.iterations, step.residuals, 0.0, (0.0,))
        shared = StepResult.build(*args, last=last, x=pair_x(problem))
        fresh = StepResult.build(*args)
        for name in ("x", "pressure", "shear", "normal_displacement",
                     "tangential_displacement", "states", "unknowns"):  # fmt: skip
            ours, theirs = getattr(shared, name), getattr(fresh, name)
            assert np.array_equal(ours, theirs) and ours.dtype == theirs.dtype
            assert not ours.flags.writeable and not theirs.flags.writeable
        assert shared.pressure is last.pressure and shared.states is last.states
        assert (shared.approach, shared.delta, shared.moment) == (fresh.approach, fresh.delta,
                                                                   fresh.moment)  # fmt: skip
    frozen = _frozen([1.0, 2.0])
    assert _frozen(frozen) is frozen
    writable = np.array([1.0, 2.0])
    assert _frozen(writable) is not writable and not _frozen(writable).flags.writeable
    view = frozen[:1]  # a view of a frozen array's numbers, which nothing can write: taken
    assert _frozen(view) is view and _frozen(frozen.astype(np.float32)).dtype == float
    shared = writable[:1]  # read-only, but its numbers are a writable array's: copied
    shared.setflags(write=False)
    assert _frozen(shared) is not shared and not _frozen(shared).flags.writeable
    buffered = np.frombuffer(bytearray(16))  # numbers owned by a writable buffer: copied
    assert _frozen(buffered) is not buffered


def test_run_records_share_the_solver_arrays_frozen_and_nothing_writes_them():
    """The arrays of every step and increment record (the solver's own unknowns, states
    and slip, taken uncopied) cannot be written by the user, nor made writable again from
    the records' views, and keep the numbers they had when their step was reported."""
    simulation = scenes.cattaneo_mindlin(pairs=21, increments=2, models={
        "upper": "half-plane", "lower": "half-plane"})  # fmt: skip
    names = ("x", "pressure", "shear", "normal_displacement", "tangential_displacement",
             "states", "unknowns")  # fmt: skip
    seen = []

    def arrays(step):
        out = [getattr(step, name) for name in names]
        for record in step.increments:
            out += [record.slip, record.pressure, record.shear, record.states]
        return out

    def keep(k, n, step):
        seen.append([(a, a.copy()) for a in arrays(step)])

    result = run(simulation, progress=keep)
    assert result.steps[-1].pressure.base is result.steps[-1].unknowns  # shared, not copied
    for step, kept in zip(result.steps, seen, strict=True):
        for array, (same, numbers) in zip(arrays(step), kept, strict=True):
            assert array is same and np.array_equal(array, numbers)
            assert not array.flags.writeable
            with pytest.raises(ValueError):
                array[0] = 1.0
            if array.base is not None:
                with pytest.raises(ValueError):
                    array.setflags(write=True)


def simulation_state(step):
    """The ContactState a step ended in (its unknowns, states and slip)."""
    from fretbem.contact.law import ContactState

    return ContactState(np.array(step.unknowns), np.array(step.states),
                        np.array(step.tangential_displacement), loads=dict(step.loads),
                        virgin=False)  # fmt: skip
