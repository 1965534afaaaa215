"""Half-plane surface influence coefficients against the Flamant closed forms and Hertz."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fretbem import registry as bases
from fretbem.basis import Refinement
from fretbem.geometry.nurbs import NurbsCurve
from fretbem.halfplane import (
    FlamantCompliance,
    HalfPlaneFaceError,
    HalfPlaneSurface,
    line_load_displacement,
    surface_integrals,
)
from fretbem.material import Material
from fretbem.verification.closed_forms import HertzLineContact, effective_modulus

STEEL = Material(210000.0, 0.3)


def _face(family="nurbs", elements=10, start=(-1.0, 0.0), end=(1.0, 0.0), curve=None):
    curve = curve or NurbsCurve.line(start, end)
    return bases.get(family).discretise(curve, Refinement(elements=elements))


# -- the closed form ------------------------------------------------------------------------


def test_line_load_matches_johnson_plane_strain():
    """Johnson (1985) eqs. 2.19-2.20 for a lower half-plane, z = -y into the body."""
    E, nu = STEEL.E, STEEL.nu
    x = np.array([-2.0, -0.5, 0.3, 4.0])
    kernel = line_load_displacement(STEEL, "lower", x, 0.0, datum=1.0)
    # normal load P pressing into the body is F_y = -P: u_z = -2(1-nu^2)/(pi E) P ln|x|
    # (u_y = -u_z) and u_x = -(1-2nu)(1+nu)/(2E) P sign(x) (toward the load)
    P = 1.0
    u_z = -2 * (1 - nu**2) / (math.pi * E) * P * np.log(np.abs(x))
    u_x = -(1 - 2 * nu) * (1 + nu) / (2 * E) * P * np.sign(x)
    np.testing.assert_allclose(kernel[:, 1, 1] * -P, -u_z, rtol=1e-14)
    np.testing.assert_allclose(kernel[:, 0, 1] * -P, u_x, rtol=1e-14)
    # tangential load Q in +x: u_x = -2(1-nu^2)/(pi E) Q ln|x|, u_z = +(1-2nu)(1+nu)/(2E) Q sign
    np.testing.assert_allclose(kernel[:, 0, 0], u_z, rtol=1e-14)
    u_z_q = (1 - 2 * nu) * (1 + nu) / (2 * E) * np.sign(x)
    np.testing.assert_allclose(kernel[:, 1, 0], -u_z_q, rtol=1e-14)


def test_line_load_reciprocity_and_mirror():
    """Betti: u_i(x; unit j at s) = u_j(s; unit i at x); the upper body mirrors the lower."""
    x, s = 0.7, -0.4
    for side in ("lower", "upper"):
        forward = line_load_displacement(STEEL, side, np.array([x]), s)[0]
        back = line_load_displacement(STEEL, side, np.array([s]), x)[0]
        np.testing.assert_allclose(forward, back.T, rtol=1e-14)
    lower = line_load_displacement(STEEL, "lower", np.array([x]), s)[0]
    upper = line_load_displacement(STEEL, "upper", np.array([x]), s)[0]
    mirror = np.diag([1.0, -1.0])
    np.testing.assert_allclose(upper, mirror @ lower @ mirror, rtol=1e-14)


def test_plane_stress_constants():
    stress = Material(STEEL.E, STEEL.nu, plane_stress=True)
    c = FlamantCompliance.of(stress)
    assert c.log == pytest.approx(2.0 / (math.pi * STEEL.E), rel=1e-14)
    assert c.jump == pytest.approx((1 - STEEL.nu) / (2 * STEEL.E), rel=1e-14)
    assert c.bulk_strain(stress) == pytest.approx(1.0 / STEEL.E)
    assert FlamantCompliance.of(STEEL).bulk_strain(STEEL) == pytest.approx(
        (1 - STEEL.nu**2) / STEEL.E
    )


# -- the integrals --------------------------------------------------------------------------


def _x_log_x(z):
    return np.where(z == 0, 0.0, z * np.log(np.abs(np.where(z == 0, 1.0, z))))


def _z2_log(z):
    return np.where(z == 0, 0.0, z**2 / 2 * np.log(np.abs(np.where(z == 0, 1.0, z)))) - z**2 / 4


@pytest.mark.parametrize("family", ["nurbs", "lagrange2"])
@pytest.mark.parametrize("direction", [1, -1])
def test_integrals_of_constant_and_linear_traction(family, direction):
    """int ln(|x - s|/d0) {1, s} ds and int sign(x - s) ds over [-1, 1], at nodes and beyond."""
    ends = ((-1.0, 0.0), (1.0, 0.0))[::direction]
    face = _face(family, 7, *ends)
    elements, local = face.collocation()
    nodes = face.map(elements, local).points[:, 0]
    element_ends = face.map(np.arange(7), -np.ones(7)).points[:, 0]
    x = np.concatenate([nodes, element_ends, [-3.0, -1.0 - 1e-7, 1.0, 1.0 + 1e-9, 0.123, 5.0]])
    datum = 0.37
    integrals = surface_integrals(face, x, datum)
    constant = _x_log_x(x + 1) - _x_log_x(x - 1) - 2 - 2 * math.log(datum)
    np.testing.assert_allclose(integrals.log.sum(axis=1), constant, atol=2e-14)
    np.testing.assert_allclose(integrals.sign.sum(axis=1), 2 * np.clip(x, -1, 1), atol=2e-14)
    # the geometry coefficients reproduce s itself (both families reproduce linears)
    s_coeff = face.geometry_coefficients[:, 0]
    linear = x * (_x_log_x(x + 1) - (x + 1) - _x_log_x(x - 1) + (x - 1)) - (
        _z2_log(x + 1) - _z2_log(x - 1)
    )
    np.testing.assert_allclose(integrals.log @ s_coeff, linear, atol=2e-14)


def test_integrals_on_a_rational_parametrisation():
    """A flattened NURBS arc (rational x(xi)) integrates the same polynomials of s."""
    radius = 3.0
    up = math.pi / 2
    phi = math.asin(1.0 / radius)
    curve = NurbsCurve.arc([0.0, -radius], radius, up - phi, up + phi).flattened(0.0)
    face = bases.get("nurbs").discretise(curve, Refinement(elements=9))
    x = np.linspace(-1.4, 1.4, 23)
    integrals = surface_integrals(face, x, 1.0)
    constant = _x_log_x(x + 1) - _x_log_x(x - 1) - 2
    # shape functions of a rational curve reproduce constants but not s: check constants
    np.testing.assert_allclose(integrals.log.sum(axis=1), constant, atol=1e-13)
    np.testing.assert_allclose(integrals.sign.sum(axis=1), 2 * np.clip(x, -1, 1), atol=1e-13)


def test_uniform_pressure_displacement_at_the_nodes():
    """Uniform pressure p on |x| < b: u_y, u_x of the lower half-plane in closed form."""
    b, p = 0.5, 3.0
    surface = HalfPlaneSurface(_face("lagrange2", 6, (-b, 0), (b, 0)), STEEL, "lower", datum=2.0)
    n = len(surface.points)
    t = np.zeros((n, 2))
    t[:, 1] = -p  # pressure on a lower body: traction -p n with n = +y
    u = surface.traction_map.reshape(n, 2, n, 2).reshape(2 * n, 2 * n) @ t.ravel()
    u = u.reshape(n, 2)
    c = FlamantCompliance.of(STEEL)
    x = surface.points[:, 0]
    log_integral = _x_log_x(x + b) - _x_log_x(x - b) - 2 * b - 2 * b * math.log(2.0)
    np.testing.assert_allclose(u[:, 1], c.log * p * log_integral, rtol=1e-12)
    np.testing.assert_allclose(u[:, 0], -c.jump * p * 2 * x, atol=1e-12 * c.jump * p)
    force = surface.contact_force() @ t.ravel()
    np.testing.assert_allclose(force, [0.0, -2 * b * p], atol=1e-13)


def test_bulk_displacement():
    surface = HalfPlaneSurface(_face(), STEEL, "lower", bulk_origin=0.25)
    x = np.array([-1.0, 0.25, 2.0])
    u = surface.bulk_displacement(x)
    np.testing.assert_allclose(u[:, 0], (1 - 0.3**2) / STEEL.E * (x - 0.25), rtol=1e-14)
    np.testing.assert_array_equal(u[:, 1], 0.0)


# -- Hertz ----------------------------------------------------------------------------------


def _frictionless(upper: HalfPlaneSurface, lower: HalfPlaneSurface, profile, load):
    """Normal contact by an active-set loop: g = profile - d + C p >= 0, p >= 0, sum w p = P."""
    n = len(lower.points)
    # relative normal displacement (upper minus lower, along +y) per unit pressure: the
    # lower body carries (0, -p), the upper (0, +p)
    compliance = upper.traction_map[:, 1, 1::2] + lower.traction_map[:, 1, 1::2]
    weights = lower.contact_force()[1, 1::2]
    active = np.ones(n, bool)
    for _ in range(50):
        idx = np.flatnonzero(active)
        system = np.zeros((idx.size + 1, idx.size + 1))
        system[:-1, :-1] = compliance[np.ix_(idx, idx)]
        system[:-1, -1] = -1.0
        system[-1, :-1] = weights[idx]
        solution = np.linalg.solve(system, np.concatenate([-profile[idx], [load]]))
        p = np.zeros(n)
        p[idx] = solution[:-1]
        gap = profile - solution[-1] + compliance @ p
        new = np.where(active, p > 0, gap < 0)
        if np.array_equal(new, active):
            return p, solution[-1]
        active = new
    raise AssertionError("active set did not settle")


@pytest.mark.parametrize(
    ("family", "elements", "tolerance"),
    [("nurbs", 59, 1.2e-3), ("lagrange2", 30, 4e-2)],
)
@pytest.mark.parametrize("plane_stress", [False, True])
def test_two_half_planes_reproduce_hertz(family, elements, tolerance, plane_stress):
    """Two similar cylinders R = 70 mm as half-planes: a and p0 of Hertz (plane strain/stress)."""
    material = Material(73400.0, 0.33, plane_stress=plane_stress)
    radius, load = 70.0, 100.0
    modulus = effective_modulus(
        material.E, material.nu, material.E, material.nu, plane_stress=plane_stress
    )
    hertz = HertzLineContact(load, radius / 2, modulus)
    a = hertz.half_width
    face = _face(family, elements, (-1.5 * a, 0.0), (1.5 * a, 0.0))
    upper = HalfPlaneSurface(face, material, "upper")
    lower = HalfPlaneSurface(face, material, "lower")
    x = lower.points[:, 0]
    p, _ = _frictionless(upper, lower, x**2 / radius, load)
    error = np.abs(p - hertz.pressure(x)).max() / hertz.peak_pressure
    assert error < tolerance
    assert p.max() == pytest.approx(hertz.peak_pressure, rel=tolerance)
    # contact half-width within a node spacing
    spacing = np.diff(x).max()
    assert abs(x[p > 0].max() - a) < spacing


def test_hertz_converges_with_refinement():
    """L2 pressure error falls at least like h (measured rate ~1.1-1.4 at 61/121/241 nodes)."""
    material = Material(73400.0, 0.33)
    hertz = HertzLineContact(100.0, 35.0, effective_modulus(73400.0, 0.33, 73400.0, 0.33))
    a = hertz.half_width
    errors = []
    for nodes in (61, 121, 241):
        face = _face("nurbs", nodes - 2, (-1.5 * a, 0.0), (1.5 * a, 0.0))
        upper = HalfPlaneSurface(face, material, "upper")
        lower = HalfPlaneSurface(face, material, "lower")
        x = lower.points[:, 0]
        p, _ = _frictionless(upper, lower, x**2 / 70.0, 100.0)
        errors.append(np.sqrt(np.mean((p - hertz.pressure(x)) ** 2)) / hertz.peak_pressure)
    rates = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert errors[-1] < 3e-4
    assert np.all(rates > 0.5), (errors, rates)


def test_datum_shifts_the_body_not_the_pressure():
    """d0 moves each body rigidly by A ln(d0'/d0) P; the pressure does not change."""
    material = Material(73400.0, 0.33)
    face = _face("nurbs", 39, (-0.5, 0.0), (0.5, 0.0))
    results = {}
    for datum in (0.01, 1.0, 300.0):
        upper = HalfPlaneSurface(face, material, "upper", datum=datum)
        lower = HalfPlaneSurface(face, material, "lower", datum=datum)
        results[datum] = _frictionless(upper, lower, lower.points[:, 0] ** 2 / 70.0, 100.0)
    p_ref, approach_ref = results[1.0]
    c = FlamantCompliance.of(material)
    for datum, (p, approach) in results.items():
        np.testing.assert_allclose(p, p_ref, atol=1e-10 * p_ref.max())
        # u = -A ln(r / d0) F: a larger d0 moves each body by A ln(d0'/d0) P away from the
        # other, which the approach of the far fields takes up
        expected = approach_ref + 2 * c.log * math.log(datum / 1.0) * 100.0
        assert approach == pytest.approx(expected, rel=1e-10, abs=1e-14)


# -- bad input ------------------------------------------------------------------------------


def test_face_must_be_monotone_in_x():
    bent = NurbsCurve.arc([0.0, 0.0], 1.0, 0.0, 1.5 * math.pi)
    with pytest.raises(HalfPlaneFaceError, match="monotonically in x"):
        HalfPlaneSurface(bases.get("nurbs").discretise(bent, Refinement(elements=8)), STEEL)


def test_side_is_checked():
    with pytest.raises(HalfPlaneFaceError, match=r"'lower'.*'upper'"):
        HalfPlaneSurface(_face(), STEEL, "left")


# -- against the Kelvin BEM -----------------------------------------------------------------


def _bem_block(half_width: float, patch: float, material: Material):
    """A BEM block 2L wide and 2L deep, clamped at the bottom, its top loaded by a uniform
    pressure of 1 on |x| < patch: a finite stand-in for the half-plane."""
    from fretbem.bem.body import BemBody
    from fretbem.conditions import Displacement, Traction
    from fretbem.geometry.boundary import Boundary, Segment

    L, b = half_width, patch
    boundary = Boundary(
        [
            Segment("bottom", NurbsCurve.line([-L, -2 * L], [L, -2 * L])),
            Segment("right", NurbsCurve.line([L, -2 * L], [L, 0])),
            Segment("top_right", NurbsCurve.line([L, 0], [b, 0])),
            Segment("patch", NurbsCurve.line([b, 0], [-b, 0])),
            Segment("top_left", NurbsCurve.line([-b, 0], [-L, 0])),
            Segment("left", NurbsCurve.line([-L, 0], [-L, -2 * L])),
        ]
    )
    refinement = {
        "patch": Refinement(elements=8),
        "top_right": Refinement.graded(40, 1.0, 200.0),
        "top_left": Refinement.graded(40, 0.0, 200.0),
        "left": Refinement.graded(16, 0.0, 20.0),
        "right": Refinement.graded(16, 1.0, 20.0),
        "bottom": Refinement(elements=16),
    }
    conditions = [Displacement("bottom"), Traction("patch", x=0.0, y=-1.0)]
    return BemBody(boundary, material, conditions, basis="nurbs", refinement=refinement)


def test_influence_agrees_with_a_wide_bem_block():
    """Both Flamant terms, sign and size, against the Kelvin-kernel BEM: a pressure patch
    |x| < 1 on a block 2L wide and deep. Datum-free differences at x = 2, 3 (and -x):
    u_x(x) - u_x(-x) (the sign term, 2 B) and u_y(x) - u_y(5) (the ln term, A). Measured
    relative errors (worst of x = 2, 3) 13 % / 1.5 % at L = 25 and 3.2 % / 0.09 % at
    L = 100: they fall like 1/L, the finite block's own correction."""
    material = Material(100000.0, 0.3)
    x = np.array([2.0, 3.0, 5.0])
    face = bases.get("nurbs").discretise(NurbsCurve.line([-1, 0], [1, 0]), Refinement(elements=8))
    surface = HalfPlaneSurface(face, material, "lower")
    t = np.tile([0.0, -1.0], len(surface.points))
    half_plane = {side: surface.node_map(side * x) @ t for side in (1.0, -1.0)}
    hp_jump = half_plane[1.0][:2, 0] - half_plane[-1.0][:2, 0]
    hp_log = half_plane[1.0][:2, 1] - half_plane[1.0][2, 1]
    errors = []
    for L in (25.0, 100.0):
        solution = _bem_block(L, 1.0, material).solve()
        right = solution.displacement(2, (L - x) / (L - 1.0))  # top_right runs L -> 1
        left = solution.displacement(4, (x - 1.0) / (L - 1.0))  # top_left runs -1 -> -L
        bem_jump = right[:2, 0] - left[:2, 0]
        bem_log = right[:2, 1] - right[2, 1]
        errors.append(
            (
                np.abs(bem_jump / hp_jump - 1).max(),
                np.abs(bem_log / hp_log - 1).max(),
            )
        )
    (jump_25, log_25), (jump_100, log_100) = errors
    assert jump_100 < 0.04 and log_100 < 1.2e-3
    assert jump_100 < 0.3 * jump_25 and log_100 < 0.3 * log_25  # ~1/L
