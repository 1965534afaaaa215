"""Result checks, input checks, safe file names and resource estimates
(fretbem.verification.checks)."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from fretbem.bem.resources import (
    BYTES_PER_DOF,
    BYTES_PER_DOF2,
    KEPT_BYTES_PER_DOF2,
    check_resources,
    estimate_resources,
)
from fretbem.errors import ResourceLimitError
from fretbem.geometry.boundary import Boundary, BoundaryError
from fretbem.scenes.reference import CattaneoMindlinScene, cattaneo_mindlin
from fretbem.simulation import run
from fretbem.verification import checks


@pytest.fixture(scope="module")
def reference():
    """The reference cycle with 31 nurbs pairs."""
    return run(cattaneo_mindlin(CattaneoMindlinScene(pairs=31)))


def test_a_fresh_result_keeps_the_checks_of_its_run_and_an_edited_one_is_checked(reference):
    """``fresh=True`` (the pipeline, straight after the solve) takes the records run() made
    as it solved each step; a result with a step run() did not check is checked whole."""
    import attrs

    records = checks.check_steps(reference, fresh=True)
    assert [r is s.checks for r, s in zip(records, reference.steps, strict=True)] == [True] * 5
    step = attrs.evolve(reference.steps[1], pressure=2 * reference.steps[1].pressure, checks=None)
    edited = attrs.evolve(reference, steps=(reference.steps[0], step))
    with pytest.raises(checks.ConsistencyError, match="edited after the solve"):
        checks.check_steps(edited, fresh=True)


def test_reference_passes_every_check_with_small_residuals(reference):
    """Measured: equilibrium residual 5e-5 (p) / 7e-5 (q) x P, end pairs separated."""
    for records in checks.check_steps(reference):
        assert all(r.passed for r in records.values())
        assert records["equilibrium"].residual < 2e-4
        assert records["zone_edge"].residual == 0
        assert records["tangential_hold"].residual < 1.0


def test_unbalanced_tractions_are_an_equilibrium_error():
    """1 % missing from the integral of p (10 x the tolerance) is refused with the fix."""
    with pytest.raises(checks.EquilibriumError, match="refine the contact zone") as info:
        checks.equilibrium(99.0, 18.0, 100.0, 18.0, step="B")
    assert info.value.residual == pytest.approx(0.01)
    assert info.value.check == "equilibrium"
    assert not checks.equilibrium(np.nan, 0, 100, 0, raise_error=False).passed
    assert checks.equilibrium(100.00001, 0.0, 100.0, 0.0).passed


def test_body_balance():
    """Each body's net force must vanish relative to the load."""
    assert checks.resultant_balance([[1e-6, -1e-6], [0.0, 0.0]], 100.0).passed
    with pytest.raises(checks.EquilibriumError, match="body 1"):
        checks.resultant_balance([[0.0, 0.0], [0.0, 5.0]], 100.0)


def test_too_small_zone_is_refused_naming_zone():
    """Reproducer: zone = 0.5 put the end pairs in contact (1820 MPa at the edge), exit 0.
    run() itself refuses at the first step; check_steps refuses the same result."""
    simulation = cattaneo_mindlin(CattaneoMindlinScene(pairs=21, zone=0.5))
    with pytest.raises(checks.ContactZoneError, match=r"step 'A'.*`zone`"):
        run(simulation)
    result = run(simulation, check=False)
    with pytest.raises(checks.ContactZoneError, match="`zone`"):
        checks.check_steps(result)
    records = checks.check_steps(result, raise_error=False)
    assert all(r["zone_edge"].residual == 2 for r in records)


def test_too_small_zone_is_refused_for_dissimilar_bodies_without_theory():
    """Reproducer: with dissimilar bodies (no analytical reference, no error column) a zone
    of 0.5 gave 1241 MPa at its edge pairs and nothing flagged it."""
    scene = CattaneoMindlinScene(pairs=21, zone=0.5, E_lower=210000.0, nu_lower=0.3)
    with pytest.raises(checks.ContactZoneError):
        run(cattaneo_mindlin(scene))
    result = run(cattaneo_mindlin(scene), check=False)
    assert result.simulation.reference is None
    with pytest.raises(checks.ContactZoneError, match="enlarge the scene's `zone`"):
        checks.check_steps(result)


def test_no_stick_pair_is_refused_with_widths():
    """Near gross sliding: all pairs slip; the message gives stick width against spacing."""
    x = np.linspace(-1, 1, 21)
    states = np.full(21, checks.SLIP)
    states[[0, -1]] = checks.SEPARATED
    with pytest.raises(checks.TangentialIndeterminacyError) as info:
        checks.tangential_hold(x, states, 100.0, 29.997, 0.3, step="B")
    message = str(info.value)
    assert "no pair sticks" in message and "0.9999" in message
    assert "pair spacing of 0.1 mm" in message
    # the advice is quantified: more pairs would not help at 0.9999 (about 170 times), a
    # lower |Q| / (f P) would (the stick zone then spans three pairs)
    assert "times the pairs" in message and "below about 0.97" in message


def test_runaway_block_displacement_is_refused():
    """Reproducer: Newton returned a 1e9 mm block displacement and the run exited 0."""
    x = np.linspace(-1, 1, 21)
    states = np.full(21, checks.STICK)
    with pytest.raises(checks.TangentialIndeterminacyError, match="block moved 1e\\+09 mm"):
        checks.tangential_hold(x, states, 100.0, 29.0, 0.3, block_displacement=1e9)
    with pytest.raises(checks.TangentialIndeterminacyError, match="singular"):
        checks.tangential_hold(x, states, 100.0, 29.0, 0.3, condition=1e17)
    assert checks.tangential_hold(x, states, 100.0, 29.0, 0.3, block_displacement=0.01).passed


@pytest.mark.parametrize(
    ("tolerance", "iterations", "substeps"),
    [(0.5, 50, 4), (0.0, 50, 4), (-1e-10, 50, 4), (math.nan, 50, 4), ("x", 50, 4),
     (1e-10, 0, 4), (1e-10, 2.5, 4), (1e-10, True, 4), (1e-10, 50, -1)],
)  # fmt: skip
def test_solver_settings_are_validated(tolerance, iterations, substeps):
    """Reproducer: Solver(tolerance=0.5) returned e_q 90 %; bad counts were accepted."""
    with pytest.raises(checks.SolverSettingsError):
        checks.solver_settings(tolerance, iterations, substeps)


def test_good_solver_settings_pass():
    checks.solver_settings(1e-10, 50, 4)
    checks.solver_settings(1e-3, 1, 0)


def test_duplicate_or_empty_step_names_are_refused():
    """Step names key results and files: duplicates, empty names and NUL are refused."""
    with pytest.raises(checks.StepNameError, match=r"repeated: \['B'\]"):
        checks.step_names(["A", "B", "B"])
    for bad in ("", "  ", "a\0b", 3):
        with pytest.raises(checks.StepNameError):
            checks.step_names(["A", bad])
    assert checks.step_names(("A", "B")) == ("A", "B")


def test_hostile_step_names_become_safe_unique_file_names():
    """Reproducers: ../../x, /abs/path, B/1, 300 characters, NUL, duplicates after cleaning."""
    names = ["../../x", "/abs/path", "B/1", "y" * 300, "a\0b", "B_1", "..", "b_1"]
    safe = checks.safe_names(names)
    assert safe[:3] == ["x", "abs_path", "B_1"]
    assert len(safe[3]) <= checks.MAX_NAME
    assert len({s.lower() for s in safe}) == len(safe)
    assert all(re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9._-]*", s) for s in safe)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.text(max_size=80), max_size=12))
def test_any_names_give_safe_unique_stems(names):
    """Property: every stem is a plain file name (no separator, no leading dot), unique."""
    safe = checks.safe_names(names)
    assert len(safe) == len(names)
    assert len({s.lower() for s in safe}) == len(safe)
    for stem in safe:
        assert re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9._-]{0,63}", stem), stem
        assert ".." not in stem


def test_resource_estimate_grows_as_dofs_squared_and_refuses_what_cannot_fit():
    """Reproducer: --pairs 20001 (80316 DOFs) needs ~190 GB: refused up front with the
    estimate and the machine's free memory."""
    small, large = estimate_resources(1000, available=None), estimate_resources(2000)
    per_dof2 = BYTES_PER_DOF2 + KEPT_BYTES_PER_DOF2  # bodies small enough to keep H and G
    growth = per_dof2 * (2000**2 - 1000**2) + BYTES_PER_DOF * 1000
    assert large.memory - small.memory == pytest.approx(growth)
    assert BYTES_PER_DOF2 * 80316**2 > 10 * BYTES_PER_DOF * 80316  # the square dominates
    assert large.seconds > 4 * small.seconds
    with pytest.raises(ResourceLimitError, match=r"80316 boundary DOFs.*GB.*available"):
        check_resources(80316, available=16 * 2**30)
    assert check_resources(556, available=16 * 2**30).fits


def test_boundary_touching_itself_at_a_vertex_is_refused():
    """Reproducer: a bow-tie boundary pinched at one vertex solved to |u| = 2e10."""
    with pytest.raises(BoundaryError, match="touches itself"):
        Boundary.polygon([(0, 0), (2, 0), (1, 1), (2, 2), (0, 2), (1, 1)], list("abcdef"))
    # a vertex lying on a non-adjacent side (T-touch) is refused too
    notch = [(0, 0), (4, 0), (4, 1), (2, 1), (2, 0.0), (1, 2), (0, 2)]
    with pytest.raises(BoundaryError, match="touches itself"):
        Boundary.polygon(notch, list("abcdefg"))
    notch[4] = (2, 0.01)  # a narrow gap is a valid body
    Boundary.polygon(notch, list("abcdefg"))


def test_refining_to_twenty_thousand_control_points_stays_sparse():
    """Reproducer: --pairs 20001 spent minutes in a dense (n x n) knot-insertion solve.
    The banded sparse solve refines an arc to 20 002 control points exactly (memory O(n p))."""
    from fretbem.geometry.nurbs import NurbsCurve

    arc = NurbsCurve.arc([0, 0], 70.0, -1.6, -1.5)
    new = np.linspace(0.0, 1.0, 20_001)[1:-1]
    refined, transform = arc.reparametrised().insert_knots(new)
    assert refined.n_control_points == arc.n_control_points + new.size
    assert transform.shape == (refined.n_control_points, arc.n_control_points)
    xi = np.linspace(0.0, 1.0, 997)
    assert np.abs(refined.points(xi) - arc.reparametrised().points(xi)).max() < 1e-9


@pytest.mark.parametrize(
    "settings",
    [
        {"tolerance": 0.5},
        {"tolerance": 0.0},
        {"max_iterations": 0},
        {"max_substeps": -1},
        {"max_iterations": 2.5},
        {"max_substeps": True},
    ],
)
def test_newton_refuses_meaningless_settings(settings):
    """Reproducer: SemiSmoothNewton(tolerance=0.5) ran and returned e_q = 90 %."""
    from fretbem.solvers.newton import SemiSmoothNewton

    with pytest.raises(ValueError, match="must"):
        SemiSmoothNewton(**settings)


def test_spacing_is_numpy_s_median_of_the_neighbour_distances():
    """_spacing gives np.median(np.diff(np.sort(x))) bit for bit (odd and even counts,
    ties, any scale) and NaN for fewer than two pairs."""
    from fretbem.verification.checks import _spacing

    rng = np.random.default_rng(5)
    for k in range(2000):
        x = rng.standard_normal(rng.integers(2, 40)) * 10 ** rng.uniform(-5, 5)
        if k % 3 == 0:
            x = np.round(x, 2)
        assert _spacing(x) == float(np.median(np.diff(np.sort(x))))
    assert math.isnan(_spacing(np.array([1.0])))


def test_checks_with_the_run_s_pair_positions_are_the_checks_without(reference):
    """check_step with :func:`checks.pair_positions` taken once (as run() does) gives the
    records it gives without them, for every step and for steps whose states would fail
    the zone-edge and hold checks; the block displacements read from the layout's slice
    are those pair_unknowns names."""
    import attrs

    positions = checks.pair_positions(reference.steps[0].x)
    assert positions.spacing == checks._spacing(reference.steps[0].x)
    assert positions.ends.tolist() == np.argsort(reference.steps[0].x)[[0, -1]].tolist()
    for step in reference.steps:
        assert checks.check_step(step, 0.3, positions=positions) == checks.check_step(step, 0.3)
        named = np.concatenate(list(step.pair_unknowns.blocks.values()))
        assert np.array_equal(checks._block_displacements(step), named)
        touching = np.ones_like(step.states)  # every pair sticking: the zone's ends too
        slipping = np.where(step.states == 0, 0, 2)  # no pair sticking
        for states in (touching, slipping):
            edited = attrs.evolve(step, states=states)
            both = [checks.check_step(edited, 0.3, raise_error=False, positions=given)
                    for given in (positions, None)]  # fmt: skip
            assert both[0] == both[1] and not all(r.passed for r in both[0].values())
    with pytest.raises(checks.ContactZoneError, match="outermost pair"):
        checks.zone_edge(step.x, touching, positions=positions)
    assert checks.pair_positions(np.zeros(0)).ends.size == 0
