"""The lean iteration of small uncoupled problems (fretbem.solvers.newton_uncoupled) against
the general path (NewtonLinear and the law's evaluation): the same unknowns to round-off
and the same iterations, in every kind of step; coupled, larger or other-law problems keep
the general path."""

from __future__ import annotations

import copy
from pathlib import Path

import attrs
import numpy as np
import pytest

from fretbem.contact.law import CoulombFriction
from fretbem.scenes.builder import build
from fretbem.scenes.file import load_scene
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import LoadStep, run
from fretbem.solvers import newton_linear, newton_uncoupled
from fretbem.solvers.newton import NewtonConvergenceError, SemiSmoothNewton
from fretbem.solvers.newton_linear import NewtonLinear
from fretbem.solvers.newton_uncoupled import UncoupledIncrement, UncoupledSteps

EXAMPLES = Path(__file__).resolve().parents[3] / "examples"
HALF_PLANES = {"upper": "half-plane", "lower": "half-plane"}
#: measured: 4e-14 of p_max at most (21-61 pairs, both families, the cases below)
ROUND_OFF = 1e-12


def _both(simulation, monkeypatch):
    """The run through the lean iteration and through the general path (fresh solvers),
    with the kinds of Newton linear solver each kept."""
    runs = []
    for lean in (True, False):
        if not lean:
            monkeypatch.setattr(newton_uncoupled, "LEAN_BELOW", 0)
        solver = copy.copy(simulation.solver)  # its settings, none of its kept solvers
        result = run(attrs.evolve(simulation, solver=solver))
        runs.append((result, {type(linear) for linear in solver._linear.values()}))
        monkeypatch.undo()
    return runs


def _same(simulation, monkeypatch, stalls: bool = False):
    """Lean and general runs agree to round-off, in as many iterations (fewer where an
    iteration ``stalls``: the lean one guards reversals from the first stalled residual)."""
    (lean, kinds), (general, general_kinds) = _both(simulation, monkeypatch)
    assert kinds == {UncoupledSteps} and general_kinds == {NewtonLinear}
    for ours, theirs in zip(lean.steps, general.steps, strict=True):
        if stalls:
            assert ours.iterations <= theirs.iterations
        else:
            assert ours.iterations == theirs.iterations
        assert len(ours.increments) == len(theirs.increments)
        scale = np.abs(theirs.pressure).max()
        assert np.abs(ours.unknowns - theirs.unknowns).max() <= ROUND_OFF * scale
        assert np.array_equal(ours.states, theirs.states)
    return lean, general


def _displaced(simulation, delta: float, increments: int = 1):
    """The simulation's cycle driven by the pad's tangential displacement."""
    steps = [LoadStep("A", normal=100.0)]
    for name, sign in zip("BCDE", (1.0, 0.0, -1.0, 0.0), strict=True):
        steps.append(LoadStep(name, normal=100.0, delta=sign * delta, increments=increments))
    return attrs.evolve(simulation, steps=tuple(steps))


@pytest.mark.parametrize(
    "kwargs",
    [dict(pairs=61), dict(pairs=61, basis="lagrange2"), dict(pairs=21),
     dict(pairs=41, basis="lagrange2", normal=200.0, tangential=(0.0, 50.0, 0.0, -50.0, 0.0)),
     dict(pairs=61, increments=3, normal=50.0, tangential=(0.0, 13.5, 0.0, -13.5, 0.0)),
     dict(pairs=41, increments=3, tangential=(0.0, 25.0, -25.0, 29.0), names=tuple("ABCD")),
     dict(pairs=61, lower="flat")],
)  # fmt: skip
def test_force_controlled_cycles_match_the_general_path(kwargs, monkeypatch):
    """Reference cycles at several loads and sizes, sub-increments, near gross slip, a flat
    specimen; and their errors against Cattaneo-Mindlin are the same."""
    lean, general = _same(cattaneo_mindlin(models=HALF_PLANES, **kwargs), monkeypatch)
    for ours, theirs in zip(lean.steps, general.steps, strict=True):
        if theirs.errors is not None:
            for key, value in theirs.errors.items():
                assert abs(ours.errors[key] - value) <= 1e-12, key


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
@pytest.mark.parametrize(("delta", "increments"), [(0.0015, 1), (0.004, 3)])
def test_displacement_controlled_cycles_match_the_general_path(basis, delta, increments,
                                                               monkeypatch):  # fmt: skip
    """The pad driven by delta: partial slip; and gross slip over 3 increments, whose
    unloading increments start on an all-slip pattern that keeps its residual (0.6 four
    or five times over): the general path guards reversals once round-off reads a
    residual an ulp larger, the lean one from the first equal value, so the lean path
    never takes more iterations. How many fewer depends on the CPU's round-off: at 61
    pairs 53 general against 49 lean (nurbs), 53 and 50 (lagrange2) on the host it was written on;
    49 and 49, 50 and 50 on an AMD EPYC host, where no residual reads an ulp larger."""
    simulation = cattaneo_mindlin(pairs=61, basis=basis, models=HALF_PLANES)
    lean, general = _same(_displaced(simulation, delta, increments), monkeypatch,
                          stalls=increments > 1)  # fmt: skip
    total = sum(s.iterations for s in lean.steps)
    assert total <= sum(s.iterations for s in general.steps)


@pytest.mark.parametrize(
    ("friction", "steps"),
    [(0.3, (LoadStep("A", normal=100.0),
            LoadStep("B", normal=150.0, tangential=20.0, increments=3),
            LoadStep("C", normal=60.0, tangential=-10.0, increments=2))),
     (0.3, (LoadStep("A", normal=100.0), LoadStep("B", normal=100.0, tangential=29.0, increments=4),
            LoadStep("C", normal=100.0, tangential=-29.5, increments=6))),
     (0.0, (LoadStep("A", normal=100.0, delta=0.0), LoadStep("B", normal=100.0, delta=0.002))),
     (1.2, (LoadStep("A", normal=100.0, delta=0.0), LoadStep("B", normal=100.0, delta=0.002),
            LoadStep("C", normal=100.0, delta=-0.002)))],
)  # fmt: skip
def test_histories_that_move_both_parts_match_the_general_path(friction, steps, monkeypatch):
    """P and Q changed in one step (the normal part iterates beside the tangential one),
    Q to near gross slip and back, a frictionless and a high-friction delta history."""
    simulation = cattaneo_mindlin(pairs=41, models=HALF_PLANES)
    _same(attrs.evolve(simulation, steps=steps, law=CoulombFriction(friction)), monkeypatch)


def test_approach_controlled_steps_match_the_general_path(monkeypatch):
    """The normal approach imposed instead of P (its block row a displacement row)."""
    simulation = cattaneo_mindlin(pairs=41, models=HALF_PLANES)
    steps = (LoadStep("A", normal=None, approach=0.004),
             LoadStep("B", normal=None, approach=0.004, tangential=10.0),
             LoadStep("C", normal=None, approach=0.004, delta=-0.001))  # fmt: skip
    _same(attrs.evolve(simulation, steps=steps), monkeypatch)


def test_a_scene_file_takes_the_lean_iteration(monkeypatch):
    """The rounded-flat example (two half-planes of one material on differently meshed
    faces, whose gap sees the shears at 1e-16 of the map) from its TOML file."""
    simulation, _ = build(load_scene(EXAMPLES / "rounded_flat_half_plane.toml"))
    problem = simulation.prepare()
    maps = problem.normal_map, problem.tangential_map, problem.resultant_map
    assert newton_linear.normal_part(*maps) is None  # exactly: a round-off coupling
    _same(simulation, monkeypatch)


def test_coupled_and_large_problems_keep_the_general_path(monkeypatch):
    """Dissimilar half-planes (beta != 0), 241 pairs (a bordered solve's size) and BEM
    bodies take NewtonLinear, bit for bit as with the lean iteration switched off."""
    for simulation in (
        cattaneo_mindlin(pairs=41, models=HALF_PLANES, E_lower=200000.0, nu_lower=0.3),
        cattaneo_mindlin(pairs=241, models=HALF_PLANES),
        cattaneo_mindlin(pairs=21),
    ):
        (first, kinds), (second, _) = _both(simulation, monkeypatch)
        assert kinds == {NewtonLinear}
        for ours, theirs in zip(first.steps, second.steps, strict=True):
            assert np.array_equal(ours.unknowns, theirs.unknowns)


def test_lean_part_reads_round_off_as_zero():
    """Entries at 1e-16 of a map are round-off of one material; a coupling of 1e-6 (faces
    paired by interpolation, dissimilar materials) is not."""
    problem = cattaneo_mindlin(pairs=21, models=HALF_PLANES).prepare()
    normal, tangential = problem.normal_map, problem.tangential_map
    resultant = problem.resultant_map
    n = problem.n_pairs
    assert newton_uncoupled.lean_part(normal, tangential, resultant) is not None
    for size, lean in ((1e-16, True), (1e-6, False)):
        coupled = normal.copy()
        coupled[:, n : 2 * n] = size * np.abs(normal).max()
        assert newton_linear.normal_part(coupled, tangential, resultant) is None
        assert (newton_uncoupled.lean_part(coupled, tangential, resultant) is not None) == lean


def test_a_law_that_changes_the_functions_takes_the_general_path():
    """A subclass of CoulombFriction with its own evaluate keeps the general path (the lean
    iteration writes CoulombFriction's arithmetic out)."""

    @attrs.frozen
    class Custom(CoulombFriction):
        def evaluate(self, *args):
            return super().evaluate(*args)

    solver = SemiSmoothNewton()
    simulation = cattaneo_mindlin(pairs=21, models=HALF_PLANES, solver=solver)
    run(attrs.evolve(simulation, law=Custom(0.3)))
    assert {type(linear) for linear in solver._linear.values()} == {NewtonLinear}


def test_a_singular_step_falls_back_to_the_dense_solve(monkeypatch):
    """A reduced matrix that does not factorise gives the dense Jacobian's step: with every
    step taken that way the run still matches, in as many iterations."""

    def singular(self):
        raise np.linalg.LinAlgError("singular")

    simulation = cattaneo_mindlin(pairs=21, models=HALF_PLANES)
    reference = run(simulation)
    monkeypatch.setattr(UncoupledIncrement, "step", singular)
    solver = SemiSmoothNewton()
    result = run(attrs.evolve(simulation, solver=solver))
    assert {type(linear) for linear in solver._linear.values()} == {UncoupledSteps}
    for ours, theirs in zip(result.steps, reference.steps, strict=True):
        assert ours.iterations == theirs.iterations
        scale = np.abs(theirs.pressure).max()
        assert np.abs(ours.unknowns - theirs.unknowns).max() <= ROUND_OFF * scale


def test_an_increment_out_of_iterations_fails_as_the_general_path(monkeypatch):
    """Too few iterations: the same error, naming the same pairs, through both paths."""
    simulation = cattaneo_mindlin(pairs=21, models=HALF_PLANES)
    messages = []
    for lean in (True, False):
        if not lean:
            monkeypatch.setattr(newton_uncoupled, "LEAN_BELOW", 0)
        solver = SemiSmoothNewton(max_iterations=2, max_substeps=0)
        with pytest.raises(NewtonConvergenceError) as failure:
            run(attrs.evolve(simulation, solver=solver))
        error = failure.value
        text = str(error).split("(last residual")[0]
        messages.append((text, error.changing_pairs.tolist(), len(error.residuals)))
        monkeypatch.undo()
    assert messages[0] == messages[1]


def test_softened_augmentation_restarts_from_the_same_point():
    """After r_n is softened (a repeated pattern), F at x is the fresh evaluation's with the
    new parameters, and the normal part is no longer taken as solved."""
    simulation = cattaneo_mindlin(pairs=21, models=HALF_PLANES)
    problem = simulation.prepare()
    maps = problem.normal_map, problem.tangential_map, problem.resultant_map
    part = newton_uncoupled.lean_part(*maps)
    steps = UncoupledSteps(*maps, part, 0.3, 2.0, 3.0)
    forces = simulation.forces(100.0, 0.0)
    increment = steps.increment(problem.bases(()), forces, np.zeros(problem.n_pairs))
    increment.begin(np.zeros(problem.layout.size), problem.gap)
    for _ in range(6):
        increment.advance(increment.step(), 100.0)
    assert increment.frozen
    softer = UncoupledSteps(*maps, part, 0.3, 0.2, 3.0)
    increment.thaw(softer)
    fresh = softer.increment(problem.bases(()), forces, np.zeros(problem.n_pairs))
    fresh.begin(increment.x.copy(), problem.gap)
    fresh.evaluate()
    assert not increment.frozen
    assert np.array_equal(increment.residual, fresh.residual)
    assert np.array_equal(increment.states, fresh.states)


def test_begin_on_a_pattern_is_the_evaluation_continued_on_it():
    """begin(x, gap, states) gives F, states and directions bit for bit as evaluating F at x
    and continuing it on the pattern (the directions of the shears at x, else of the trial
    tractions); the pattern's key is newton._seen_before's."""
    from fretbem.solvers.newton import _seen_before

    simulation = cattaneo_mindlin(pairs=21, models=HALF_PLANES)
    problem = simulation.prepare()
    maps = problem.normal_map, problem.tangential_map, problem.resultant_map
    steps = UncoupledSteps(*maps, newton_linear_part(maps), 0.3, 2.0, 3.0)
    end = run(simulation).steps[1]
    forces = simulation.forces(end.normal, end.tangential)
    rng = np.random.default_rng(3)
    for x in (np.array(end.unknowns), np.zeros(problem.layout.size)):
        states = rng.integers(0, 3, problem.n_pairs)
        bases = problem.bases(problem.amplitudes(end.loads))
        ours = steps.increment(bases, forces, np.array(end.tangential_displacement))
        ours.begin(x.copy(), problem.gap, states)
        theirs = steps.increment(bases, forces, np.array(end.tangential_displacement))
        theirs.begin(x.copy(), problem.gap)  # F at x, then continued on the pattern
        q = x[problem.n_pairs : 2 * problem.n_pairs]
        direction = np.where(q != 0.0, np.sign(q), theirs.direction)
        theirs._continue_on(states, direction, theirs.residual[2 * problem.n_pairs :])
        assert ours.residual.tobytes() == theirs.residual.tobytes()
        assert ours.direction.tobytes() == theirs.direction.tobytes()
        assert np.array_equal(ours.states, theirs.states)
        seen = set()
        _seen_before(seen, ours.states, ours.direction)
        assert seen == {ours.pattern()}


def newton_linear_part(maps):
    """The lean iteration's blocks of ``maps`` (a problem it takes)."""
    part = newton_uncoupled.lean_part(*maps)
    assert part is not None
    return part


def test_largest_of_each_is_the_largest_of_both_parts():
    """One reduction over a split gives _largest of each part (NaN, zeros, an empty part)."""
    from fretbem.solvers.newton_uncoupled import _largest, _largest_of_each

    rng = np.random.default_rng(4)
    for size in (1, 2, 7, 40):
        values = np.abs(rng.standard_normal(size))
        for cut in range(size + 1):
            if cut == 0:
                continue
            cuts = np.array([0, cut] if cut < size else [0])
            expected = (_largest(values[:cut]), _largest(values[cut:]))
            assert tuple(_largest_of_each(values, cuts)) == expected
        values[-1] = np.nan
        both = _largest_of_each(values, np.array([0, size // 2] if size > 1 else [0]))
        assert np.isnan(both[1] if size > 1 else both[0])
    assert tuple(_largest_of_each(np.zeros(3), np.array([0, 1]))) == (0.0, 0.0)
