"""Knot moves of the adaptive mode where a knot's point has no transition next to it."""

from __future__ import annotations

import numpy as np
import pytest

from fretbem.accuracy import knots
from fretbem.contact.pairs import SLIP, STICK

X = np.linspace(0.0, 1.0, 11)  # points 0.1 apart


def states(*runs):
    """States of the 11 points from (state, count) runs."""
    out = np.concatenate([np.full(n, s) for s, n in runs])
    assert out.size == X.size
    return out


def test_a_knot_with_a_change_beside_it_moves_to_the_change():
    # stick up to x = 0.5, slip from 0.6: the change lies between them (0.55)
    level = [states((STICK, 6), (SLIP, 5))]
    move = knots._fallback(X, level, 0.4, 4, 0.1, knots.FALLBACK_REACH, SLIP, (STICK,))
    assert np.isclose(move, 0.15)


def test_a_knot_far_from_every_change_stays():
    """The nearest stick-slip change is 3.5 spacings off: another knot's (the rig's step E
    knot walked onto step A's boundary, docs/explanation/adaptive.rst, "Limits")."""
    level = [states((STICK, 9), (SLIP, 2))]
    assert knots._fallback(X, level, 0.5, 5, 0.1, knots.FALLBACK_REACH, SLIP, (STICK,)) == 0.0


def test_a_knot_without_a_point_always_moves_to_the_nearest_change():
    level = [states((STICK, 9), (SLIP, 2))]
    move = knots._fallback(X, level, 0.52, None, 0.1, knots.FALLBACK_REACH, SLIP, (STICK,))
    assert np.isclose(move, 0.85 - 0.52)


def test_no_change_at_all_leaves_the_knot():
    level = [states((STICK, 11))]
    assert knots._fallback(X, level, 0.52, None, 0.1, knots.FALLBACK_REACH, SLIP, (STICK,)) == 0.0


def test_without_a_reach_a_knot_moves_to_any_nearest_change():
    """Knots handed on by a coarse level (fewer points than the uniform first level, or
    faces paired by projection) lie farther off: they keep the unbounded move."""
    level = [states((STICK, 9), (SLIP, 2))]
    assert np.isclose(knots._fallback(X, level, 0.5, 5, 0.1, None, SLIP, (STICK,)), 0.35)


def test_a_hertzian_edge_is_found_exactly():
    """p^2 of a Hertzian pressure is quadratic in x: the fit's zero is the edge itself."""
    for a, n in ((1.0, 4), (0.37, 9), (2.5e-3, 15)):
        x = np.linspace(0.2 * a, 0.9 * a, n)
        p = 3.0 * np.sqrt(1.0 - (x / a) ** 2)
        assert abs(knots._root_of_square(x, p, x[-1]) - a) < 1e-12 * a
        assert abs(knots._root_of_square(-x[::-1], p[::-1], -x[-1]) + a) < 1e-12 * a


def test_a_square_root_fall_on_two_or_three_points_is_a_line_in_the_square():
    for n in (2, 3):
        x = 0.4 - 0.1 * np.arange(n)[::-1]  # ends at 0.4, the zero at 0.5
        values = 2.0 * np.sqrt(0.5 - x)
        assert abs(knots._root_of_square(x, values, x[-1]) - 0.5) < 1e-14
    assert knots._root_of_square(np.array([0.1]), np.array([1.0]), 0.1) is None


def test_the_fits_are_numpys_bit_for_bit():
    """The knots' own polyfit and roots give np.polyfit's and np.roots's numbers exactly
    (the adaptive levels depend on the knots to the last bit), 2 to 19 points, with and
    without noise, real and complex roots."""
    rng = np.random.default_rng(3)
    for _ in range(400):
        n = int(rng.integers(2, 20))
        x = np.sort(rng.uniform(-1e-3, 1e-3, n)) + rng.uniform(-1e-2, 1e-2)
        centre, width = rng.uniform(-1e-3, 1e-3), rng.uniform(1e-3, 2e-3)
        noise = rng.choice([0.0, 1e-3, 1.0])
        y = np.maximum(width**2 - (x - centre) ** 2, 0.0) * 1e6 + rng.normal(0.0, noise, n)
        for degree in (1, 2)[: n - 1]:
            fitted = knots._polyfit(x, y, degree)
            assert np.array_equal(fitted, np.polyfit(x, y, degree))
            roots, expected = knots._polyroots(fitted), np.roots(fitted)
            assert roots.dtype == expected.dtype and np.array_equal(roots, expected)


def test_a_level_is_sorted_along_the_face_once():
    """A solved level's pairs in face order, kept per result and read-only: the positions,
    the smallest spacing and every step's states, p, q, slip, slip increment (from the step
    before, the first from 0) and gap, as the knots' functions took them one by one."""
    from fretbem.accuracy import estimate
    from fretbem.scenes import cattaneo_mindlin
    from fretbem.simulation import run

    result = run(cattaneo_mindlin(pairs=21))
    level = knots._level(result)
    assert knots._level(result) is level
    order = np.argsort(estimate.positions(result))
    assert np.array_equal(level.x, estimate.positions(result)[order])
    assert level.spacing == float(np.min(np.diff(level.x)))
    gap = np.asarray(result.simulation.pair.pairing().gap, float)
    previous = np.zeros(order.size)
    for step, kept in zip(result.steps, level.steps, strict=True):
        slip = step.tangential_displacement[order]
        assert np.array_equal(kept.states, step.states[order])
        assert np.array_equal(kept.pressure, step.pressure[order])
        assert np.array_equal(kept.shear, step.shear[order])
        assert np.array_equal(kept.increment, np.abs(slip - previous))
        assert np.array_equal(kept.gap, gap[order] + step.normal_displacement[order])
        assert not kept.pressure.flags.writeable and not kept.gap.flags.writeable
        previous = slip
    assert not level.x.flags.writeable


def test_the_fits_without_numpys_gufuncs_and_on_non_finite_data(monkeypatch):
    """Non-finite data take the public functions (np.polyfit's NaN coefficients, np.roots's
    error), and so does a numpy without the gufuncs: the same numbers."""
    x = np.linspace(0.2, 0.33, 6)
    y = np.maximum(0.33**2 - x**2, 0.0)
    nan = np.array([1.0, np.nan, 2.0, 3.0])
    assert np.isnan(knots._polyfit(np.arange(4.0), nan, 2)).all()
    with pytest.raises(np.linalg.LinAlgError):
        knots._polyroots(np.array([1.0, np.nan, 2.0]))
    fitted = knots._polyfit(x, y, 2)
    roots = knots._polyroots(fitted)
    monkeypatch.setattr(knots, "_LSTSQ", None)
    monkeypatch.setattr(knots, "_EIGVALS", None)
    assert np.array_equal(knots._polyfit(x, y, 2), fitted)
    assert np.array_equal(knots._polyroots(fitted), roots)
