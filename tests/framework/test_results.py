"""Step records: the errors against theory, computed when first read."""

from __future__ import annotations

import pickle

import attrs
import numpy as np

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
