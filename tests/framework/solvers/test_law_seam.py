"""The law seam: a solver's fast path is reached through the law's interface.

A law that is Coulomb's cone without being CoulombFriction gets the reduced Newton step (and
the Lemke solver) by answering ``coulomb_form()``; a law that does not answer takes the
general Newton path. Unknowns and iterations are the same to round-off either way.
"""

from __future__ import annotations

import attrs
import numpy as np
import pytest

from fretbem.contact.law import ContactLaw, CoulombFriction
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run
from fretbem.solvers import LemkeSolver
from fretbem.solvers.newton import SemiSmoothNewton


@attrs.frozen
class WrappedCoulomb(ContactLaw):
    """Coulomb friction by delegation: the same functions, another class."""

    inner: CoulombFriction
    fast: bool = True

    @property
    def friction(self) -> float:
        return self.inner.friction

    def coulomb_form(self):
        return self.inner.friction if self.fast else None

    def evaluate(self, *args):
        return self.inner.evaluate(*args)

    def evaluate_on(self, *args):
        return self.inner.evaluate_on(*args)

    def jacobian_rows(self, *args):
        return self.inner.jacobian_rows(*args)

    def check_history(self, steps):
        return self.inner.check_history(steps)


def _solve(law, solver, pairs):
    simulation = attrs.evolve(cattaneo_mindlin(pairs=pairs), law=law, solver=solver)
    return run(simulation), simulation


@pytest.mark.parametrize("pairs", [31, 61])
@pytest.mark.parametrize("fast", [True, False])
def test_a_law_gets_the_fast_path_through_its_interface(pairs, fast):
    reference, _ = _solve(CoulombFriction(0.3), SemiSmoothNewton(), pairs)
    solver = SemiSmoothNewton()
    result, _ = _solve(WrappedCoulomb(CoulombFriction(0.3), fast), solver, pairs)
    assert (len(solver._linear) > 0) == fast  # the reduced Newton solver was kept, or not
    for ours, theirs in zip(result.steps, reference.steps, strict=True):
        scale = np.max(np.abs(theirs.unknowns))
        assert np.max(np.abs(ours.unknowns - theirs.unknowns)) <= 1e-10 * scale
        if fast:
            assert ours.iterations == theirs.iterations


def test_lemke_asks_the_law_for_its_coulomb_form():
    reference, _ = _solve(CoulombFriction(0.3), LemkeSolver(), 31)
    result, _ = _solve(WrappedCoulomb(CoulombFriction(0.3)), LemkeSolver(), 31)
    for ours, theirs in zip(result.steps, reference.steps, strict=True):
        assert np.allclose(ours.unknowns, theirs.unknowns, rtol=0, atol=1e-10)
    with pytest.raises(ValueError, match="coulomb_form"):
        _solve(WrappedCoulomb(CoulombFriction(0.3), fast=False), LemkeSolver(), 31)
