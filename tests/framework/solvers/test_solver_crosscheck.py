"""The pivoting (Lemke) solver against semi-smooth Newton: the same answers, independently."""

from __future__ import annotations

import functools

import numpy as np
import pytest

from fretbem.contact.law import ContactLaw, CoulombFriction
from fretbem.scenes import reference as scenes
from fretbem.simulation import Simulation, run
from fretbem.solvers import LemkeSolver, PivotingError, UnsupportedLawError
from fretbem.solvers.newton import SemiSmoothNewton, SolverSettingsError

#: agreement required of the two solvers, in units of f p0 (issue 9); measured ~1e-12
AGREEMENT = 1e-8

# the half-plane through the scene factory's body-model hook (kept if already registered)


@functools.cache
def _pair(**fields):
    simulation = scenes.cattaneo_mindlin(**fields)
    simulation.prepare()
    return simulation


def _rerun(base: Simulation, solver) -> object:
    return run(Simulation(base.pair, base.steps, solver, law=base.law, reference=base.reference))


def _difference(a, b) -> float:
    """Largest pressure or shear difference over every step, in units of f p0."""
    fp0 = a.simulation.law.friction * max(s.pressure.max() for s in a.steps)
    return max(
        max(np.abs(x.pressure - y.pressure).max(), np.abs(x.shear - y.shear).max()) / fp0
        for x, y in zip(a.steps, b.steps, strict=True)
    )


@pytest.mark.parametrize(
    "models",
    [{}, {"lower": "half-plane"}, {"upper": "half-plane", "lower": "half-plane"}],
    ids=["bem-bem", "bem-halfplane", "halfplane-halfplane"],
)
def test_reference_cycle_agrees_with_newton(models):
    """All five steps of the reference scene at 61 pairs, for each body model pairing."""
    base = _pair(pairs=61, models=tuple(models.items()))
    newton = _rerun(base, SemiSmoothNewton())
    lemke = _rerun(base, LemkeSolver())
    assert _difference(newton, lemke) < AGREEMENT
    for x, y in zip(newton.steps, lemke.steps, strict=True):
        np.testing.assert_array_equal(x.states, y.states)
        # the block displacements too (relative to f p0 times the pair compliance scale)
        blocks = np.abs(x.unknowns[2 * len(x.x) :] - y.unknowns[2 * len(x.x) :])
        assert np.all(blocks <= 1e-9 * np.abs(x.unknowns[2 * len(x.x) :]).max())
        assert y.iterations > 0  # pivots are reported as iterations


def test_lemke_handles_coulomb_friction_only():
    class Frictionless(ContactLaw):
        def evaluate(self, *args):  # pragma: no cover - never reached
            raise NotImplementedError

        def jacobian_rows(self, *args):  # pragma: no cover - never reached
            raise NotImplementedError

    base = _pair(pairs=31)
    simulation = Simulation(base.pair, base.steps, LemkeSolver(), law=Frictionless())
    with pytest.raises(UnsupportedLawError, match="CoulombFriction"):
        run(simulation)


def test_pivot_limit_is_a_convergence_failure():
    """Too few pivots: a SolverConvergenceError the Simulation may sub-step on."""
    base = _pair(pairs=31)
    simulation = Simulation(
        base.pair, base.steps, LemkeSolver(max_pivots=3), law=CoulombFriction(0.3)
    )
    with pytest.raises(PivotingError, match="did not finish in 3 pivots"):
        run(simulation)


@pytest.mark.parametrize(
    ("field", "value"), [("max_pivots", 0), ("max_pivots", 2.5), ("max_substeps", -1)]
)
def test_bad_settings_are_refused(field, value):
    with pytest.raises(SolverSettingsError, match=field):
        LemkeSolver(**{field: value})


@pytest.mark.parametrize(
    "models", [{}, {"upper": "half-plane", "lower": "half-plane"}], ids=["bem", "half-plane"]
)
def test_lemke_passes_the_solver_conformance_checks(models):
    from fretbem.testing.conformance import check_solver

    check_solver(LemkeSolver(), simulation=scenes.cattaneo_mindlin(pairs=21, models=models))
