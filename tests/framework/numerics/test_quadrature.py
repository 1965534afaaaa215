"""Quadrature rules: Gauss-Legendre and the log-weighted Gauss rule used for singular G."""

from __future__ import annotations

import math

import attrs
import numpy as np
import pytest

from fretbem.numerics.quadrature import QuadratureRule


@pytest.mark.parametrize("n", [1, 2, 3, 5, 8, 16, 24])
def test_gauss_legendre_exact_to_degree_2n_minus_1(n):
    """n points integrate x^k on [-1, 1] exactly (2/(k+1) or 0) for every k <= 2n - 1."""
    rule = QuadratureRule.gauss_legendre(n)
    assert rule.interval == (-1.0, 1.0)
    assert rule.points.shape == rule.weights.shape == (n,)
    for k in range(2 * n):
        exact = 2.0 / (k + 1) if k % 2 == 0 else 0.0
        assert np.sum(rule.weights * rule.points**k) == pytest.approx(exact, rel=1e-14, abs=1e-14)


@pytest.mark.parametrize("n", [2, 4, 8])
def test_gauss_legendre_not_exact_at_degree_2n(n):
    """x^(2n) is the first monomial the rule misses (so the exactness test has teeth)."""
    rule = QuadratureRule.gauss_legendre(n)
    assert abs(np.sum(rule.weights * rule.points ** (2 * n)) - 2.0 / (2 * n + 1)) > 1e-6


def test_mapped_rule_integrates_on_any_interval():
    """A rule mapped onto [2, 5] integrates x^3 exactly: (5^4 - 2^4) / 4."""
    points, weights = QuadratureRule.gauss_legendre(3).mapped(2.0, 5.0)
    assert np.sum(weights * points**3) == pytest.approx((5**4 - 2**4) / 4, rel=1e-14)
    # broadcast over several intervals at once
    points, weights = QuadratureRule.gauss_legendre(2).mapped(np.array([0.0, 1.0]), [1.0, 3.0])
    assert points.shape == weights.shape == (2, 2)
    np.testing.assert_allclose(weights.sum(axis=1), [1.0, 2.0], rtol=1e-15)


@pytest.mark.parametrize("n", [1, 2, 3, 4, 6, 8, 12, 16])
def test_gauss_log_exact_for_log_weighted_polynomials(n):
    """n points integrate -ln(x) x^k on [0, 1] = 1/(k+1)^2 for k < 2n, to 1e-14 relative."""
    rule = QuadratureRule.gauss_log(n)
    assert rule.interval == (0.0, 1.0)
    assert np.all((rule.points > 0) & (rule.points < 1)) and np.all(rule.weights > 0)
    assert np.all(np.diff(rule.points) > 0)
    for k in range(2 * n):
        moment = np.sum(rule.weights * rule.points**k)
        assert moment == pytest.approx(1.0 / (k + 1) ** 2, rel=1e-14), f"k = {k}"


def test_gauss_log_two_points_match_published_table():
    """The 2-point rule matches the classical table (Stroud & Secrest 1966) to 1e-14."""
    rule = QuadratureRule.gauss_log(2)
    # closed form: the points are the roots of x^2 - (5/7) x + 17/252, the monic degree-2
    # polynomial orthogonal to 1 and x under the moments 1/(k+1)^2
    disc = math.sqrt((5 / 7) ** 2 - 4 * 17 / 252)
    points = np.array([(5 / 7 - disc) / 2, (5 / 7 + disc) / 2])
    np.testing.assert_allclose(rule.points, points, rtol=1e-14)
    np.testing.assert_allclose(rule.points, [0.112008806166976, 0.602276908118738], rtol=1e-13)
    np.testing.assert_allclose(rule.weights, [0.718539319030384, 0.281460680969616], rtol=1e-13)


def test_gauss_log_beats_gauss_legendre_on_log_singularity():
    """8-point log rule integrates -ln(x) cos(x) to 1e-14; 8-point Gauss-Legendre only ~1e-3."""
    # -int_0^1 ln(x) cos(x) dx = Si(1) = 0.946083070367183...
    exact = 0.9460830703671830
    log_rule = QuadratureRule.gauss_log(8)
    assert np.sum(log_rule.weights * np.cos(log_rule.points)) == pytest.approx(exact, rel=1e-14)
    points, weights = QuadratureRule.gauss_legendre(8).mapped(0.0, 1.0)
    assert abs(np.sum(-weights * np.log(points) * np.cos(points)) - exact) > 1e-4


def test_rules_are_frozen_and_cached():
    """Rules are immutable records with read-only arrays, built once per size."""
    rule = QuadratureRule.gauss_log(5)
    assert rule is QuadratureRule.gauss_log(5)
    with pytest.raises(attrs.exceptions.FrozenInstanceError):
        rule.points = np.zeros(5)
    with pytest.raises(ValueError, match="read-only"):
        rule.weights[0] = 1.0


def test_rule_validates_shape():
    """Points and weights must be 1-D."""
    with pytest.raises(ValueError, match=r"QuadratureRule\.points must have shape \(n\)"):
        QuadratureRule(np.zeros((2, 2)), np.zeros(2))
