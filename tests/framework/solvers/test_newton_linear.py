"""The reduced Newton step equals the full dense Jacobian solve (solver.py's system)."""

import numpy as np
import pytest

from fretbem.solvers import newton_linear
from fretbem.solvers.newton_linear import NewtonLinear, reduced_newton_step

SEPARATED, STICK, SLIP = 0, 1, 2


def full_jacobian(normal_map, tangential_map, resultant_map, states, direction, f, r_n, r_t):
    """The generalised Jacobian exactly as the semi-smooth Newton solver builds it."""
    n, n_x = normal_map.shape
    jac = np.zeros((n_x, n_x))
    rows = np.arange(n)
    separated, stick, slip = (states == s for s in (SEPARATED, STICK, SLIP))
    contact = ~separated
    jac[rows[separated], rows[separated]] = 1.0
    jac[rows[contact]] = r_n * normal_map[contact]
    jac[n + rows[separated], n + rows[separated]] = 1.0
    jac[n + rows[stick]] = -r_t * tangential_map[stick]
    slip_rows = n + rows[slip]
    coeff = (f * direction[slip])[:, None]
    jac[slip_rows] = coeff * r_n * normal_map[slip]
    jac[slip_rows, rows[slip]] -= coeff[:, 0]
    jac[slip_rows, slip_rows] += 1.0
    jac[2 * n :] = resultant_map
    return jac


def problem(rng, n, m, states):
    """Maps like a condensed contact: dominant diagonals, dense coupling, m block columns."""
    n_x = 2 * n + m
    normal = 0.05 * rng.standard_normal((n, n_x))
    tangential = 0.05 * rng.standard_normal((n, n_x))
    normal[:, :n] += np.eye(n)
    tangential[:, n : 2 * n] += np.eye(n)
    normal[:, 2 * n :] += 1.0
    tangential[:, 2 * n :] += rng.standard_normal(m)
    resultant = np.zeros((m, n_x))
    resultant[:, :n] = rng.uniform(0.5, 1.5, (m, n))
    resultant[:, n : 2 * n] = rng.uniform(0.5, 1.5, (m, n))
    resultant[:, 2 * n :] = rng.standard_normal((m, m))
    direction = rng.choice([-1.0, 1.0], n)
    residual = rng.standard_normal(n_x)
    return normal, tangential, resultant, states, direction, residual


@pytest.mark.parametrize("seed", range(8))
@pytest.mark.parametrize("m", [0, 2])
def test_reduced_step_equals_full_solve(seed, m):
    rng = np.random.default_rng(seed)
    n = 40
    states = rng.choice([SEPARATED, STICK, SLIP], n)
    if m == 0:  # without a block the stick pairs alone must make the system regular
        states[: n // 2] = STICK
    normal, tangential, resultant, states, direction, residual = problem(rng, n, m, states)
    f, r_n, r_t = 0.3, 1.7, 0.8
    jac = full_jacobian(normal, tangential, resultant, states, direction, f, r_n, r_t)
    expected = np.linalg.solve(jac, -residual)
    step = reduced_newton_step(
        normal, tangential, resultant, residual, states, direction, f, r_n, r_t
    )
    assert np.max(np.abs(step - expected)) <= 1e-12 * np.max(np.abs(expected))
    # and it solves the full system
    assert np.max(np.abs(jac @ step + residual)) <= 1e-12 * np.max(np.abs(jac) @ np.abs(step))


@pytest.mark.parametrize("kind", [SEPARATED, STICK, SLIP])
def test_single_state_patterns(kind):
    rng = np.random.default_rng(3)
    n, m = 12, 2
    states = np.full(n, kind)
    normal, tangential, resultant, states, direction, residual = problem(rng, n, m, states)
    if kind == SEPARATED:  # no pair touches: only the blocks' own stiffness is left
        resultant[:, 2 * n :] = np.array([[2.0, 0.3], [0.1, 1.5]])
    jac = full_jacobian(normal, tangential, resultant, states, direction, 0.4, 1.0, 1.0)
    expected = np.linalg.solve(jac, -residual)
    step = reduced_newton_step(
        normal, tangential, resultant, residual, states, direction, 0.4, 1.0, 1.0
    )
    assert np.max(np.abs(step - expected)) <= 1e-12 * np.max(np.abs(expected))


def test_singular_reduced_system_raises():
    n = 4
    normal = np.zeros((n, 2 * n))
    tangential = np.zeros((n, 2 * n))
    states = np.full(n, STICK)
    with pytest.raises(np.linalg.LinAlgError):
        reduced_newton_step(
            normal, tangential, np.zeros((0, 2 * n)), np.ones(2 * n), states, np.ones(n),
            0.3, 1.0, 1.0,
        )  # fmt: skip


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("m", [0, 2])
@pytest.mark.parametrize("direct", [False, True])
def test_successive_patterns_through_one_factorisation(seed, m, direct, monkeypatch):
    """A pattern a few pairs away is solved through the kept LU, bordered by the rows that
    differ, and still equals the full dense solve; a far pattern refactorises. A system
    smaller than DIRECT_BELOW is factorised afresh every step whose pattern changed (an
    unchanged pattern reuses its LU), with the same steps."""
    monkeypatch.setattr(newton_linear, "DIRECT_BELOW", 10**9 if direct else 0)
    rng = np.random.default_rng(100 + seed)
    n = 60
    states = rng.choice([SEPARATED, STICK, SLIP], n)
    states[: n // 2] = STICK
    normal, tangential, resultant, states, direction, residual = problem(rng, n, m, states)
    f, r_n, r_t = 0.3, 1.7, 0.8
    linear = NewtonLinear(normal, tangential, resultant, f, r_n, r_t)
    changed, last = 0, None
    for change in (0, 1, 2, 3, 1, 25):  # pairs changed from the previous pattern
        states = states.copy()
        moved = rng.choice(np.arange(n // 2, n), change, replace=False)
        states[moved] = rng.choice([SEPARATED, STICK, SLIP], change)
        direction = np.where(rng.random(n) < 0.1, -direction, direction)
        pattern = (states.tolist(), np.where(states == SLIP, direction, 0.0).tolist())
        changed += pattern != last
        last = pattern
        residual = rng.standard_normal(2 * n + m)
        jac = full_jacobian(normal, tangential, resultant, states, direction, f, r_n, r_t)
        expected = np.linalg.solve(jac, -residual)
        step = linear.step(residual, states, direction)
        assert np.max(np.abs(step - expected)) <= 1e-12 * np.max(np.abs(expected))
        # a separated pair's step is exactly -F (its p lands on exactly 0), as in the
        # reduced solve: results count pairs with p > 0
        separated = np.flatnonzero(states == SEPARATED)
        assert np.array_equal(step[separated], -residual[separated])
        assert np.array_equal(step[n + separated], -residual[n + separated])
    # the near patterns went through the border, unless every step factorises
    assert linear.factorisations == changed if direct else linear.factorisations <= 2


@pytest.mark.parametrize("m", [0, 2])
def test_unchanged_pattern_reuses_its_factorisation(m):
    """A small system whose pattern did not change since the last step (the last
    iterations of an increment) is solved through the kept LU: one factorisation, and
    steps bit-identical to those of a fresh solver."""
    rng = np.random.default_rng(7)
    n = 40
    states = rng.choice([SEPARATED, STICK, SLIP], n)
    states[: n // 2] = STICK
    normal, tangential, resultant, states, direction, _ = problem(rng, n, m, states)
    linear = NewtonLinear(normal, tangential, resultant, 0.3, 1.7, 0.8)
    for _ in range(3):
        residual = rng.standard_normal(2 * n + m)
        fresh = NewtonLinear(normal, tangential, resultant, 0.3, 1.7, 0.8)
        expected = fresh.step(residual, states, direction)
        assert np.array_equal(linear.step(residual, states, direction), expected)
    assert linear.factorisations == 1


def uncoupled_problem(rng, n, states):
    """Maps of identical bodies: the gap and the normal block resultant (block column and row
    1) do not depend on the shear or the tangential block component (column and row 0)."""
    normal, tangential, resultant, states, direction, residual = problem(rng, n, 2, states)
    normal[:, n : 2 * n] = 0.0
    normal[:, 2 * n] = 0.0
    tangential[:, :n] = 0.0
    tangential[:, 2 * n + 1] = 0.0
    resultant[0, :n] = resultant[1, n:] = 0.0
    resultant[0, 2 * n] = 0.0  # the block rows carry no stiffness of their own
    return normal, tangential, resultant, states, direction, residual


def test_small_systems_split_the_factor_but_not_the_products():
    """Under SPLIT_FROM unknowns the factor splits (its tangential LU is a fraction of the
    coupled one) while the products stay whole (numpy's cost per call outweighs the
    skipped ranges there); the steps still equal the full solve's."""
    rng = np.random.default_rng(12)
    n = 10
    states = np.full(n, STICK)
    states[7:] = SLIP
    normal, tangential, resultant, states, direction, _ = uncoupled_problem(rng, n, states)
    f, r_n, r_t = 0.3, 1.7, 0.8
    linear = NewtonLinear(normal, tangential, resultant, f, r_n, r_t)
    assert 2 * n + 2 < newton_linear.SPLIT_FROM
    maps = linear.maps
    assert maps.normal_part is not None
    assert maps.normal_ranges is maps.tangential_ranges is maps.mirrored is None
    residual = rng.standard_normal(2 * n + 2)
    jac = full_jacobian(normal, tangential, resultant, states, direction, f, r_n, r_t)
    expected = np.linalg.solve(jac, -residual)
    step = linear.step(residual, states, direction)
    assert linear.factor.split is not None
    assert np.max(np.abs(step - expected)) <= 1e-12 * np.max(np.abs(expected))


def test_normal_part_only_when_the_coupling_is_exactly_zero():
    rng = np.random.default_rng(11)
    n = 10
    normal, tangential, resultant, *_ = uncoupled_problem(rng, n, np.full(n, STICK))
    part = newton_linear.normal_part(normal, tangential, resultant)
    assert part.tolist() == [True] * n + [False] * n + [False, True]
    for coupling in ((normal, 3, n + 4), (normal, 0, 2 * n), (resultant, 1, n + 2)):
        target, row, column = coupling
        kept = target[row, column]
        target[row, column] = 1e-300  # round-off is a coupling too
        assert newton_linear.normal_part(normal, tangential, resultant) is None
        target[row, column] = kept
    coupled = problem(rng, n, 2, np.full(n, STICK))
    assert newton_linear.normal_part(*coupled[:3]) is None


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("direct", [False, True])
def test_uncoupled_steps_equal_the_full_solve(seed, direct, monkeypatch):
    """Identical bodies: the normal block and then the tangential one, through two LUs of
    half the order (bordered or refactorised), give the full dense solve's step."""
    monkeypatch.setattr(newton_linear, "DIRECT_BELOW", 10**9 if direct else 0)
    monkeypatch.setattr(newton_linear, "SPLIT_FROM", 0)
    rng = np.random.default_rng(200 + seed)
    n = 60
    states = rng.choice([SEPARATED, STICK, SLIP], n)
    states[: n // 2] = STICK
    normal, tangential, resultant, states, direction, residual = uncoupled_problem(rng, n, states)
    f, r_n, r_t = 0.3, 1.7, 0.8
    linear = NewtonLinear(normal, tangential, resultant, f, r_n, r_t)
    assert linear.maps.normal_part is not None
    for change in (0, 1, 3, 25):
        states = states.copy()
        moved = rng.choice(np.arange(n // 2, n), change, replace=False)
        states[moved] = rng.choice([SEPARATED, STICK, SLIP], change)
        residual = rng.standard_normal(2 * n + 2)
        jac = full_jacobian(normal, tangential, resultant, states, direction, f, r_n, r_t)
        expected = np.linalg.solve(jac, -residual)
        step = linear.step(residual, states, direction)
        assert np.max(np.abs(step - expected)) <= 1e-12 * np.max(np.abs(expected))
        assert linear.factor.split is not None


@pytest.mark.parametrize("direct", [False, True])
def test_mirrored_maps_share_one_product(direct, monkeypatch):
    """Identical bodies (T's shear block minus N's pressure block, bit for bit): N x and T x
    from one product over the block equal the two products, for vectors and matrices, and
    the Newton steps still equal the full solve's; any other map keeps the two products."""
    monkeypatch.setattr(newton_linear, "DIRECT_BELOW", 10**9 if direct else 0)
    monkeypatch.setattr(newton_linear, "SPLIT_FROM", 0)
    rng = np.random.default_rng(31)
    n = 40
    states = rng.choice([SEPARATED, STICK, SLIP], n)
    states[: n // 2] = STICK
    normal, tangential, resultant, states, direction, residual = uncoupled_problem(rng, n, states)
    tangential[:, n : 2 * n] = -normal[:, :n]
    f, r_n, r_t = 0.3, 1.7, 0.8
    linear = NewtonLinear(normal, tangential, resultant, f, r_n, r_t)
    maps = linear.maps
    assert maps.mirrored is not None
    for x in (rng.standard_normal(2 * n + 2), rng.standard_normal((2 * n + 2, 3))):
        got_n, got_t = maps.both_times(x)
        scale = np.abs(normal).max() * np.abs(x).max() * n
        assert np.max(np.abs(got_n - normal @ x)) <= 1e-14 * scale
        assert np.max(np.abs(got_t - tangential @ x)) <= 1e-14 * scale
    jac = full_jacobian(normal, tangential, resultant, states, direction, f, r_n, r_t)
    expected = np.linalg.solve(jac, -residual)
    step = linear.step(residual, states, direction)
    assert np.max(np.abs(step - expected)) <= 1e-12 * np.max(np.abs(expected))
    tangential[3, n + 5] *= 1.0 + 1e-15  # no longer mirrored exactly: two products
    assert NewtonLinear(normal, tangential, resultant, f, r_n, r_t).maps.mirrored is None


@pytest.mark.parametrize("n", [30, 80])
@pytest.mark.parametrize("uncoupled", [False, True])
@pytest.mark.parametrize("direct", [False, True])
def test_a_small_pattern_keeps_the_large_factor_aside(n, uncoupled, direct, monkeypatch):
    """Every pair in contact, then a few (the start of a cycle), then every pair again: the
    small pattern's LU is made with the large one kept aside, which the third step takes
    back, bit for bit what a fresh solver gives; a pattern a few pairs from it borders it
    (a small system factorises it); a large new pattern drops the spare. Every step equals
    the full dense solve's."""
    monkeypatch.setattr(newton_linear, "DIRECT_BELOW", 10**9 if direct else 0)
    if uncoupled:
        monkeypatch.setattr(newton_linear, "SPLIT_FROM", 0)
    rng = np.random.default_rng(300 + n)
    make = uncoupled_problem if uncoupled else (lambda r, k, s: problem(r, k, 2, s))
    everywhere = np.full(n, STICK)
    normal, tangential, resultant, _, direction, _ = make(rng, n, everywhere)
    few = np.full(n, SEPARATED)
    few[n // 2 - 3 : n // 2 + 3] = STICK
    near = everywhere.copy()
    near[[1, n - 2]] = SLIP
    far = np.repeat([SEPARATED, SLIP, STICK], [n // 3, n // 3, n - 2 * (n // 3)])
    f, r_n, r_t = 0.3, 1.7, 0.8
    linear = NewtonLinear(normal, tangential, resultant, f, r_n, r_t)
    for states, factorisations, spare in ((everywhere, 1, False), (few, 2, True),
                                          (everywhere, 2, True), (near, 2 + direct, not direct),
                                          (far, 3 + direct, False)):  # fmt: skip
        residual = rng.standard_normal(2 * n + 2)
        jac = full_jacobian(normal, tangential, resultant, states, direction, f, r_n, r_t)
        expected = np.linalg.solve(jac, -residual)
        step = linear.step(residual, states, direction)
        assert np.max(np.abs(step - expected)) <= 1e-12 * np.max(np.abs(expected))
        if states is everywhere:
            fresh = NewtonLinear(normal, tangential, resultant, f, r_n, r_t)
            assert np.array_equal(step, fresh.step(residual, states, direction))
        assert linear.factorisations == factorisations
        assert (linear.spare is not None) == spare


def test_a_whole_axis_is_copied_not_gathered_and_only_in_order():
    """``_taken`` skips the gather of an axis taken whole in order, always returns a new
    array, and gathers an index of the axis's length that is not 0, 1, ... (a concatenation
    of column sets with repeats)."""
    from fretbem.solvers.newton_linear import _taken

    matrix = np.arange(20.0).reshape(4, 5)
    rows, columns = np.arange(4), np.arange(5)
    for r, c in ((rows, columns), (rows, columns[::-1]), (rows[[0, 2, 2, 3]], columns),
                 (rows[[1, 3]], np.array([0, 1, 1, 4, 2]))):  # fmt: skip
        out = _taken(matrix, r, c)
        assert np.array_equal(out, matrix[np.ix_(r, c)])
        assert not np.shares_memory(out, matrix)
