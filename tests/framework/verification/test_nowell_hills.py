"""The Nowell-Hills closed form: reduces to Cattaneo-Mindlin, keeps equilibrium, moves c by e."""

import numpy as np
import pytest

from fretbem.verification.closed_forms import HertzLineContact, MindlinDeresiewicz
from fretbem.verification.nowell_hills import NotApplicableError, NowellHills

HERTZ = HertzLineContact(load=150.0, effective_radius=50.0, effective_modulus=40000.0)
F = 0.45
NH = NowellHills(HERTZ, F)
A, P0 = HERTZ.half_width, HERTZ.peak_pressure
X = np.linspace(-A, A, 20001)


def integral(q):
    return float(np.trapezoid(q, X))


def test_zero_bulk_is_cattaneo_mindlin():
    md = MindlinDeresiewicz(HERTZ, F)
    path = [0.0, 40.0, 10.0, -40.0, 5.0]
    for k in range(1, len(path) + 1):
        q_nh = NH.shear_traction(X, path[:k], [0.0] * k)
        np.testing.assert_allclose(q_nh, md.shear_traction(X, path[:k]), atol=1e-12 * P0)


def test_offset_and_width_at_first_loading():
    q, sigma = 30.0, 40.0
    lo, hi = NH.stick_zone([0.0, q], [0.0, sigma])
    c = A * np.sqrt(1 - q / (F * 150.0))
    e = A * sigma / (4 * F * P0)
    assert (lo, hi) == pytest.approx((e - c, e + c), rel=1e-12)
    # equilibrium: the shifted stick term integrates like the centred one
    assert integral(NH.shear_traction(X, [0.0, q], [0.0, sigma])) == pytest.approx(q, rel=1e-5)


def test_reversal_keeps_equilibrium_and_closes_the_cycle():
    k = 1.5  # sigma_B = k Q
    path = [0.0, 45.0, 0.0, -45.0, 0.0, 45.0]
    for n in range(2, len(path) + 1):
        q = NH.shear_traction(X, path[:n], [k * v for v in path[:n]])
        assert integral(q) == pytest.approx(path[n - 1], abs=2e-5 * F * 150.0)
    # fully reversed in-phase loading: -Q_max lies on the first-loading curve (Masing), so
    # reloading from it to 0 is unloading from +Q_max to 0 with every load negated
    down = NH.shear_traction(X, path[:3], [k * v for v in path[:3]])
    up = NH.shear_traction(X, path[:5], [k * v for v in path[:5]])
    np.testing.assert_allclose(up, -down, atol=1e-9 * P0)


def test_limit_and_refusals():
    q = 30.0
    limit = NH.limit(q)
    assert NH.applies([0.0, q], [0.0, 0.99 * limit]) is None
    assert "leaves the contact" in NH.applies([0.0, q], [0.0, 1.01 * limit])
    with pytest.raises(NotApplicableError, match="mean bulk stress"):
        NH.shear_traction(X, [0.0, q], [10.0, 20.0])
    with pytest.raises(NotApplicableError, match="in phase"):
        NH.shear_traction(X, [0.0, q, 2 * q], [0.0, 10.0, 30.0])
