"""Tests of the half-plane analytical solutions (Hertz, Mindlin–Deresiewicz) on the scene."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad

from fretbem.verification.closed_forms import (
    HertzLineContact,
    MindlinDeresiewicz,
    dundurs_beta,
    effective_modulus,
)

# The reference scene (shared/reference-scene.md): mm, N/mm, MPa.
E, NU, R, P, F, Q_MAX = 73_400.0, 0.33, 70.0, 100.0, 0.3, 18.0
CYCLE = [0.0, Q_MAX, 0.0, -Q_MAX, 0.0]  # steps A..E


def scene_hertz(radius_lower: float = R) -> HertzLineContact:
    """Hertz contact of the scene (arc on arc, or arc on flat with radius_lower = inf)."""
    return HertzLineContact.from_bodies(
        load=P, radius_upper=R, radius_lower=radius_lower,
        E_upper=E, nu_upper=NU, E_lower=E, nu_lower=NU,
    )  # fmt: skip


HERTZ = scene_hertz()
MD = MindlinDeresiewicz(hertz=HERTZ, friction=F)
A, P0 = HERTZ.half_width, HERTZ.peak_pressure
X = np.linspace(-1.2 * A, 1.2 * A, 4001)


def s(x: np.ndarray, c: float) -> np.ndarray:
    """Reference s_c(x) = sqrt(1 - x²/c²) inside |x| < c, 0 outside (written independently)."""
    return np.where(np.abs(x) < c, np.sqrt(np.abs(1.0 - (x / c) ** 2)), 0.0)


def breakpoints(md: MindlinDeresiewicz, history: list[float]) -> list[float]:
    """Every ±c met along the path plus ±a: where q may have a kink."""
    a = md.hertz.half_width
    pts = {-a, a}
    for i in range(len(history)):
        pts.update(md.stick_zone(history[: i + 1]))
    return sorted(pts)


def quad_shear(md: MindlinDeresiewicz, history: list[float]) -> float:
    """∫q dx by adaptive quadrature split at every stick-zone edge."""
    a = md.hertz.half_width
    value, _ = quad(
        lambda x: float(md.shear_traction(x, history)), -a, a,
        points=breakpoints(md, history), epsabs=1e-12, epsrel=1e-12, limit=200,
    )  # fmt: skip
    return value


def gauss_shear(md: MindlinDeresiewicz, history: list[float], n: int = 64) -> float:
    """∫q dx by Gauss–Legendre in θ, x = m + h sin θ, on each piece between stick-zone edges.

    The substitution turns the square-root edges of every piece into analytic behaviour, so a
    few dozen nodes per piece give round-off accuracy.
    """
    theta, weights = np.polynomial.legendre.leggauss(n)
    theta, weights = 0.5 * np.pi * theta, 0.5 * np.pi * weights
    pts = np.array(breakpoints(md, history))
    mid, half = 0.5 * (pts[1:] + pts[:-1]), 0.5 * (pts[1:] - pts[:-1])
    x = mid[:, None] + half[:, None] * np.sin(theta)
    jacobian = half[:, None] * np.cos(theta) * weights
    return float(np.sum(jacobian * md.shear_traction(x, history)))


# --------------------------------------------------------------------------- moduli


def test_scene_effective_modulus():
    """E* of two similar bodies in plane strain is E / (2 (1 - nu²)) = 41185 MPa."""
    expected = E / (2.0 * (1.0 - NU**2))
    assert effective_modulus(E, NU, E, NU) == pytest.approx(expected, rel=1e-14)
    assert expected == pytest.approx(41_185.05, abs=0.01)


def test_plane_stress_effective_modulus():
    """In plane stress 1/E* = 1/E1 + 1/E2, independent of Poisson's ratios."""
    assert effective_modulus(200.0, 0.3, 100.0, 0.1, plane_stress=True) == pytest.approx(200 / 3)


def test_dundurs_beta_zero_for_similar_bodies():
    """Similar bodies have beta = 0 in plane strain and plane stress: the problems uncouple."""
    assert dundurs_beta(E, NU, E, NU) == 0.0
    assert dundurs_beta(E, NU, E, NU, plane_stress=True) == 0.0


def test_dundurs_beta_nonzero_for_mismatched_moduli():
    """Moduli 1000x apart give a clearly nonzero beta, antisymmetric under swapping bodies."""
    beta = dundurs_beta(E, NU, E / 1000.0, NU)
    # Rigid-ish body 1 on soft body 2: beta -> -(1 - 2 nu) / (2 (1 - nu)).
    assert beta == pytest.approx(-(1 - 2 * NU) / (2 * (1 - NU)), rel=2e-3)
    assert dundurs_beta(E / 1000.0, NU, E, NU) == pytest.approx(-beta, rel=1e-14)


# --------------------------------------------------------------------------- Hertz


def test_scene_half_width_and_peak_pressure():
    """The scene's a = 0.3289 mm and p0 = 193.5 MPa, to 4 digits."""
    assert HERTZ.effective_radius == pytest.approx(35.0)
    assert round(A, 4) == 0.3289
    assert round(P0, 1) == 193.5


def test_pressure_integrates_to_load():
    """∫p dx = P to 1e-10 relative, and p vanishes outside |x| < a."""
    total, _ = quad(lambda x: float(HERTZ.pressure(x)), -A, A, epsabs=0, epsrel=1e-12)
    assert total == pytest.approx(P, rel=1e-10)
    assert np.all(HERTZ.pressure([-1.01 * A, 1.01 * A, 5.0]) == 0.0)
    assert float(HERTZ.pressure(0.0)) == pytest.approx(P0)


def test_flat_variant_uses_full_radius():
    """Pad on flat: R_eff = R, so a grows by sqrt(2) and p0 falls by sqrt(2)."""
    flat = scene_hertz(radius_lower=math.inf)
    assert flat.effective_radius == pytest.approx(R)
    assert flat.half_width == pytest.approx(math.sqrt(2.0) * A, rel=1e-14)
    assert flat.peak_pressure == pytest.approx(P0 / math.sqrt(2.0), rel=1e-14)
    md = MindlinDeresiewicz(hertz=flat, friction=F)
    for i in range(1, len(CYCLE) + 1):
        assert quad_shear(md, CYCLE[:i]) == pytest.approx(CYCLE[i - 1], abs=1e-6 * F * P)


# --------------------------------------------------------------------------- Mindlin–Deresiewicz


@pytest.mark.parametrize("q_load", [-25.0, -Q_MAX, -3.0, 0.0, 1e-6, 7.5, Q_MAX, 29.9])
def test_first_loading_matches_cattaneo_mindlin(q_load):
    """Monotonic loading 0 -> Q gives sign(Q) f p0 [s_a - (c/a) s_c] and ∫q dx = Q."""
    ratio = math.sqrt(1.0 - abs(q_load) / (F * P))
    expected = math.copysign(1.0, q_load) * F * P0 * (s(X, A) - ratio * s(X, ratio * A))
    np.testing.assert_allclose(MD.shear_traction(X, [q_load]), expected, atol=1e-12 * P0)
    assert quad_shear(MD, [q_load]) == pytest.approx(q_load, rel=1e-6, abs=1e-6 * F * P)
    assert MD.stick_zone([q_load]) == pytest.approx((-ratio * A, ratio * A))


@pytest.mark.parametrize("step", range(len(CYCLE)), ids=list("ABCDE"))
def test_cycle_integral_identities(step):
    """Every step A–E of the cycle has ∫q dx = Q to 1e-6 of f P."""
    history = CYCLE[: step + 1]
    assert quad_shear(MD, history) == pytest.approx(CYCLE[step], rel=1e-6, abs=1e-6 * F * P)


def test_cycle_matches_scene_formulas():
    """Steps B and C equal the scene's explicit formulas; D = -B and E = -C."""
    q_a, q_b, q_c, q_d, q_e = MD.shear_history(X, CYCLE)
    c_b = A * math.sqrt(1.0 - Q_MAX / (F * P))
    c_c = A * math.sqrt(1.0 - (Q_MAX - 0.0) / (2.0 * F * P))
    exact_b = F * P0 * (s(X, A) - (c_b / A) * s(X, c_b))
    exact_c = F * P0 * (-s(X, A) + 2.0 * (c_c / A) * s(X, c_c) - (c_b / A) * s(X, c_b))
    tol = 1e-12 * P0
    np.testing.assert_allclose(q_a, 0.0, atol=tol)
    np.testing.assert_allclose(q_b, exact_b, atol=tol)
    np.testing.assert_allclose(q_c, exact_c, atol=tol)
    np.testing.assert_allclose(q_d, -q_b, atol=tol)
    np.testing.assert_allclose(q_e, -q_c, atol=tol)
    assert c_b / A == pytest.approx(math.sqrt(0.4))
    assert MD.stick_zone(CYCLE[:2]) == pytest.approx((-c_b, c_b))
    assert MD.stick_zone(CYCLE[:3]) == pytest.approx((-c_c, c_c))
    assert MD.stick_zone(CYCLE[:4]) == pytest.approx((-c_b, c_b))


def test_slip_zones_are_at_the_friction_limit():
    """At step C, |q| = f p in c < |x| < a and |q| < f p inside the stick zone."""
    q = MD.shear_traction(X, CYCLE[:3])
    limit = F * HERTZ.pressure(X)
    _, c = MD.stick_zone(CYCLE[:3])
    inside, slip = np.abs(X) < 0.999 * c, (np.abs(X) > c) & (np.abs(X) < A)
    np.testing.assert_allclose(np.abs(q[slip]), limit[slip], atol=1e-12 * P0)
    assert np.all(np.abs(q[inside]) < limit[inside])


def test_shear_history_rows_equal_path_prefixes():
    """shear_history row i equals shear_traction on the first i+1 values of the path."""
    path = [5.0, -12.0, 3.0, 3.0, -20.0, 10.0]
    rows = MD.shear_history(X, path)
    assert rows.shape == (len(path), X.size)
    for i, row in enumerate(rows):
        np.testing.assert_array_equal(row, MD.shear_traction(X, path[: i + 1]))


@pytest.mark.parametrize(
    ("path", "equivalent"),
    [
        ([10.0, 2.0, 12.0], [12.0]),  # reloading past Q1 wipes the 10 -> 2 reversal
        ([18.0, 0.0, -18.0], [-18.0]),  # reaching -Q1 rejoins the first-loading curve
        ([10.0, -5.0, 3.0, -8.0], [10.0, -8.0]),  # passing -5 closes the -5 -> 3 loop
        ([10.0, -5.0, 3.0, -8.0, 15.0], [15.0]),
        ([4.0, 8.0, 12.0], [12.0]),  # no reversal: intermediate values do not matter
    ],
)
def test_memory_rule(path, equivalent):
    """Masing memory rule: a load passing an earlier turning point erases the closed loops."""
    np.testing.assert_allclose(
        MD.shear_traction(X, path), MD.shear_traction(X, equivalent), atol=1e-12 * P0
    )
    assert MD.stick_zone(path) == pytest.approx(MD.stick_zone(equivalent))


def test_empty_path_is_unloaded():
    """An empty path is the Q = 0 state: no shear, stick over the whole contact."""
    np.testing.assert_array_equal(MD.shear_traction(X, []), 0.0)
    assert MD.shear_history(X, []).shape == (0, X.size)
    assert MD.stick_zone([]) == pytest.approx((-A, A))


@pytest.mark.parametrize("path", [[30.0], [18.0, -30.0], [10.0, 31.0, 0.0]])
def test_gross_sliding_raises(path):
    """|Q| >= f P anywhere on the path raises a ValueError naming the cause and value."""
    with pytest.raises(ValueError, match=r"gross sliding: \|Q\| = 3\d >= f P = 30"):
        MD.shear_traction(X, path)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"load": 0.0}, "load"),
        ({"load": -1.0}, "load"),
        ({"load": math.nan}, "load"),
        ({"radius_upper": 0.0}, "radius_upper"),
        ({"radius_lower": -5.0}, "radius_lower"),
        ({"E_upper": 0.0}, "E1"),
        ({"E_lower": math.inf}, "E2"),
        ({"nu_upper": 0.5}, "nu1"),
        ({"nu_lower": -1.0}, "nu2"),
    ],
)
def test_invalid_body_arguments_raise(kwargs, name):
    """Non-physical or non-finite body data raise ValueError naming the argument."""
    args = {
        "load": P, "radius_upper": R, "radius_lower": R,
        "E_upper": E, "nu_upper": NU, "E_lower": E, "nu_lower": NU,
    } | kwargs  # fmt: skip
    with pytest.raises(ValueError, match=name):
        HertzLineContact.from_bodies(**args)


@pytest.mark.parametrize("friction", [0.0, -0.1, math.inf])
def test_invalid_friction_raises(friction):
    """Friction must be finite and > 0."""
    with pytest.raises(ValueError, match="friction"):
        MindlinDeresiewicz(hertz=HERTZ, friction=friction)


def test_invalid_history_raises():
    """Non-finite loads in the path raise ValueError naming the history."""
    with pytest.raises(ValueError, match="history"):
        MD.shear_traction(X, [1.0, math.nan])


# --------------------------------------------------------------------------- random paths

paths = st.lists(
    st.floats(min_value=-0.99 * F * P, max_value=0.99 * F * P, allow_nan=False),
    min_size=1,
    max_size=7,
)


@settings(max_examples=40, deadline=None)
@given(path=paths)
def test_random_paths_respect_friction_and_equilibrium(path):
    """Any partial-slip path keeps |q| <= f p everywhere and ∫q dx = Q after every value."""
    bound = F * HERTZ.pressure(X) + 1e-9 * P0
    for i, q in enumerate(MD.shear_history(X, path)):
        assert np.all(np.abs(q) <= bound)
        total = gauss_shear(MD, path[: i + 1])
        assert total == pytest.approx(path[i], rel=1e-6, abs=1e-6 * F * P)


@settings(max_examples=40, deadline=None)
@given(path=paths, fraction=st.floats(min_value=0.01, max_value=0.99), positive=st.booleans())
def test_random_paths_forget_everything_beyond_their_extremes(path, fraction, positive):
    """Going past every earlier turning point gives the monotonic first-loading state."""
    largest = max(abs(v) for v in path)
    final = math.copysign(largest + fraction * (0.99 * F * P - largest), 1.0 if positive else -1.0)
    np.testing.assert_allclose(
        MD.shear_traction(X, [*path, final]), MD.shear_traction(X, [final]), atol=1e-12 * P0
    )
