"""A tilted pad: the pad block's rotation and moment against the shifted closed forms.

Page: docs/verification/tilted_pad.py. A cylindrical pad (R = 70 mm) on a flat specimen,
similar aluminium bodies (E = 73.4 GPa, nu = 0.33), f = 0.3, the rig's pivot at the
first-contact point (``[rig] pivot_height = 0``). Tilting the pad's parabolic profile
x^2 / (2 R) by theta (counterclockwise) gives x^2 / (2 R) + theta x, the same parabola
centred at d = -theta R: under P and a moment M the pressure is Hertz's of the same a and p0
about d, with M = -P d (the block's moment balances the pressure's, P at d), so theta =
M / (P R); under P, M and Q the shear is Cattaneo-Mindlin's about d, and with a bulk stress
Nowell-Hills' about d. Half-planes meet them to the discretisation error (the same as the
centred contact's); finite BEM bodies within the finite-body difference, measured against
the same scene on bodies 4x larger.
"""

import numpy as np
import pytest

from fretbem.contact import control
from fretbem.scenes.builder import build
from fretbem.scenes.spec import scene_from_dict
from fretbem.simulation import run
from fretbem.verification.closed_forms import (
    HertzLineContact,
    MindlinDeresiewicz,
    effective_modulus,
)
from fretbem.verification.nowell_hills import NowellHills

E, NU, F, R = 73400.0, 0.33, 0.3, 70.0
E_STAR = effective_modulus(E, NU, E, NU)
PAGE = "tilted_pad"
#: the largest contact shift of the cases (mm): the candidate zone covers it
SHIFT = 0.25


def tilted_run(load, *, pairs=61, basis="nurbs", model="half-plane", size=1.0, rig=None,
               support="clamped-bottom", pairing="node-to-node"):  # fmt: skip
    """The pad on the flat specimen under ``load`` ([load] keys); returns (simulation, result)."""
    a = HertzLineContact(100.0, R, E_STAR).half_width
    data = {
        "pad": {"shape": "cylinder", "radius": R, "width": 6.5 * size, "height": 16.25 * size,
                "model": model},
        "specimen": {"shape": "flat", "length": 40.0 * size, "thickness": 13.0 * size,
                     "model": model, "support": support},
        "material": {"E": E, "nu": NU},
        "contact": {"friction": F, "pairs": pairs, "basis": basis, "estimate": False,
                    "pairing": pairing, "zone_width": SHIFT + 1.25 * a},
        "load": load,
        "rig": {"pivot_height": 0.0} if rig is None else rig,
    }  # fmt: skip
    simulation, _ = build(scene_from_dict(data))
    return simulation, run(simulation)


def measured(simulation, step) -> dict:
    problem = simulation.prepare()
    return control.measure(problem, step.unknowns, problem.amplitudes(step.loads), simulation.rig)


def balance(simulation, step) -> float:
    """The block's moment plus the contact tractions' moment on the pad (both about the pivot)."""
    rotation = simulation.prepare().rotation
    return rotation.moment(step.unknowns) + rotation.contact_moment(step.unknowns)


def rms(values) -> float:
    return float(np.sqrt(np.mean(np.square(values))))


def centroid(step) -> float:
    return float(np.trapezoid(step.pressure * step.x, step.x) / np.trapezoid(step.pressure, step.x))


#: half-planes, family: pairs and tolerances (p RMS / p0, q RMS / f p0, theta relative):
#: theta as the shift error over a; measured at P 50-100, M -25..10 N mm/mm, zone 0.83 mm:
#: p max 0.75 % nurbs, 0.62 % lagrange2 61, 1.3 % lagrange2 41 (P 50: 16 pairs in
#: contact); q 1.3 % nurbs, 1.7 % lagrange2 61, 2.1 % lagrange2 41 (back at Q = 0); theta
#: 5.7e-4 nurbs, 7.6e-4 lagrange2 61, 2.4e-3 lagrange2 41 (P 50)
HALF_PLANE = {
    ("nurbs", 41): (0.009, 0.016, 3e-3),
    ("nurbs", 61): (0.009, 0.016, 3e-3),
    ("lagrange2", 41): (0.016, 0.026, 3e-3),
    ("lagrange2", 61): (0.012, 0.02, 3e-3),
}
LOADS = [(100.0, 10.0), (100.0, -25.0), (50.0, 10.0)]


#: the families run by default (the 41-pair ones in the slow tests)
FAMILIES = [
    family if family[1] == 61 else pytest.param(family, marks=pytest.mark.slow)
    for family in HALF_PLANE
]


@pytest.mark.parametrize("family", FAMILIES)
@pytest.mark.parametrize("load, moment", LOADS)
def test_moment_gives_hertz_about_the_shifted_centre(family, load, moment, record):
    """P and M on two half-planes: Hertz about d = -M / P, theta = M / (P R), and the
    block's moment equal and opposite to the contact tractions' (to round-off)."""
    basis, pairs = family
    p_tol, _, theta_tol = HALF_PLANE[family]
    simulation, result = tilted_run(
        {"steps": ["A"], "P": load, "Q": 0.0, "moment": moment}, pairs=pairs, basis=basis
    )
    step = result["A"]
    hertz = HertzLineContact(load, R, E_STAR)
    shift = -moment / load
    e_p = rms(step.pressure - hertz.pressure(step.x - shift)) / hertz.peak_pressure
    values = measured(simulation, step)
    e_theta = abs(values["tilt"] - moment / (load * R)) * R / hertz.half_width
    case = f"tilted pad, P {load:g}, M {moment:g} (half-planes, {basis} {pairs})"
    assert record(case, "p RMS error / p0 about d = -M/P", e_p, p_tol, page=PAGE)
    assert record(case, "abs(theta - M / (P R)) R / a", e_theta, theta_tol, page=PAGE)
    # the trapezoid rule over the pair values (not the model's own quadrature): 5e-3 a
    assert abs(centroid(step) - shift) < 1e-2 * hertz.half_width
    assert values["moment"] == pytest.approx(moment, abs=1e-12 * abs(moment))
    assert abs(balance(simulation, step)) < 1e-12 * load * hertz.half_width


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
def test_prescribed_rotation_shifts_the_contact_by_minus_theta_r(basis):
    """The sign: a counterclockwise rotation theta lowers the pad's left side, so the
    contact moves to d = -theta R and the block's moment is M = P theta R (> 0)."""
    theta = 2e-3
    simulation, result = tilted_run(
        {"steps": ["A"], "P": 100.0, "Q": 0.0, "rotation": theta}, basis=basis
    )
    step = result["A"]
    values = measured(simulation, step)
    assert values["tilt"] == pytest.approx(theta, rel=1e-12)
    assert centroid(step) == pytest.approx(-theta * R, rel=3e-3)
    assert values["moment"] == pytest.approx(100.0 * theta * R, rel=3e-3)


@pytest.mark.parametrize("family", FAMILIES)
@pytest.mark.parametrize("moment, ratio", [(10.0, 0.5), (-25.0, 0.8)])
def test_moment_and_shear_give_cattaneo_about_the_shifted_centre(family, moment, ratio, record):
    """P, M, then Q = ratio f P and back to 0: Cattaneo-Mindlin (and its unloading) about
    d = -M / P."""
    basis, pairs = family
    _, q_tol, _ = HALF_PLANE[family]
    load = 100.0
    q_peak = ratio * F * load
    history = [0.0, q_peak, 0.0]
    _, result = tilted_run(
        {"steps": ["A", "B", "C"], "P": load, "Q": history, "moment": moment},
        pairs=pairs,
        basis=basis,
    )
    hertz = HertzLineContact(load, R, E_STAR)
    theory = MindlinDeresiewicz(hertz, F)
    shift = -moment / load
    case = f"tilted pad, M {moment:g}, Q {ratio:g} f P (half-planes, {basis} {pairs})"
    for k, name in ((1, "B"), (2, "C")):
        step = result[name]
        exact = theory.shear_traction(step.x - shift, history[: k + 1])
        error = rms(step.shear - exact) / (F * hertz.peak_pressure)
        what = "at Q peak" if k == 1 else "back at Q = 0"
        assert record(case, f"q RMS error / f p0 about d, {what}", error, q_tol, page=PAGE)


@pytest.mark.parametrize("basis", ["nurbs", "lagrange2"])
def test_moment_with_bulk_stress_gives_nowell_hills_about_the_shifted_centre(basis, record):
    """P, M = 10 N mm/mm, then Q = 0.4 f P with sigma_B = 0.6 x the Nowell-Hills limit:
    Nowell-Hills about d (measured 0.66 % nurbs, 0.50 % lagrange2)."""
    load, moment, q_peak = 100.0, 10.0, 0.4 * F * 100.0
    hertz = HertzLineContact(load, R, E_STAR)
    theory = NowellHills(hertz, F, shift=1.0)
    bulk = 0.6 * theory.limit(q_peak)
    _, result = tilted_run(
        {"steps": ["A", "B"], "P": load, "Q": [0.0, q_peak], "moment": moment,
         "bulk": [0.0, bulk]},
        basis=basis, support="ends",
    )  # fmt: skip
    step = result["B"]
    exact = theory.shear_traction(step.x + moment / load, [0.0, q_peak], [0.0, bulk])
    error = rms(step.shear - exact) / (F * hertz.peak_pressure)
    case = f"tilted pad, M 10, Q 0.4 f P, sigma_B 0.6 x limit (half-planes, {basis} 61)"
    assert record(case, "q RMS error / f p0 about d (Nowell-Hills)", error, 0.012, page=PAGE)


def test_node_to_segment_pairing_tilts_alike():
    """The projection pairing (faces discretised differently) gives the same shift."""
    simulation, result = tilted_run(
        {"steps": ["A"], "P": 100.0, "Q": 0.0, "moment": 10.0},
        pairing="node-to-segment",
    )
    hertz = HertzLineContact(100.0, R, E_STAR)
    step = result["A"]
    assert rms(step.pressure - hertz.pressure(step.x + 0.1)) / hertz.peak_pressure < 0.009
    assert measured(simulation, step)["tilt"] == pytest.approx(10.0 / (100.0 * R), rel=3e-3)


@pytest.mark.parametrize("stiffness", [1e5, pytest.param(1e6, marks=pytest.mark.slow)])
@pytest.mark.parametrize("height", [5.0, 16.25])
def test_rotational_rig_spring_tilts_the_pad_under_q(stiffness, height, record):
    """Q acts at the contact, a height h below the pivot: the block carries M = h Q - d P
    about the pivot, the spring turns it by theta = -M / k_r, and the tilt shifts the
    contact by d = -theta R, so theta = -h Q / (k_r + R P) (half-planes, exact): moment
    balance to round-off, the shift and the rotation against the closed form (measured
    4.2e-5 to 3.4e-4)."""
    load, q = 100.0, 0.5 * F * 100.0
    simulation, result = tilted_run(
        {"steps": ["A", "B"], "P": load, "Q": [0.0, q]},
        rig={"stiffness_rotation": stiffness, "pivot_height": height},
    )
    step = result["B"]
    values = measured(simulation, step)
    theta = -height * q / (stiffness + R * load)
    case = f"rig k_r {stiffness:g}, pivot h {height:g} (half-planes, nurbs 61)"
    assert abs(balance(simulation, step)) < 1e-12 * load * height
    assert values["moment"] == pytest.approx(-stiffness * values["tilt"], rel=1e-12)
    assert values["rotation"] == pytest.approx(0.0, abs=1e-15)
    assert record(case, "theta / (-h Q / (k_r + R P)) - 1", abs(values["tilt"] / theta - 1),
                  3e-3, page=PAGE)  # fmt: skip
    a = HertzLineContact(load, R, E_STAR).half_width
    assert abs(centroid(step) + theta * R) < 2e-3 * a
    assert result["A"].iterations > 0 and abs(measured(simulation, result["A"])["tilt"]) < 1e-9


#: BEM bodies, family: (p RMS, q RMS, theta) at 1x and 4x, and the centred contact's
#: (M = 0) q error that the shifted one must match; measured at 61 pairs, M 10 and -25:
#: p <= 0.64 %, q 3.0-5.6 % (centred 2.9-5.1 %: the flat specimen's finite-body
#: difference), theta 4.4-4.7 % at 1x (the finite pad's own tilt), 0.16-0.40 % at 4x
BEM = {"nurbs": (0.008, 0.065, 0.006), "lagrange2": (0.012, 0.045, 0.006)}


@pytest.mark.parametrize("basis", ["nurbs", pytest.param("lagrange2", marks=pytest.mark.slow)])
@pytest.mark.parametrize("moment", [10.0, pytest.param(-25.0, marks=pytest.mark.slow)])
def test_bem_bodies_within_the_finite_body_difference(basis, moment, record):
    """Finite BEM bodies under P, M and Q = 0.5 f P: the shifted closed forms hold as well
    as the centred ones do (the q error within 1 % of f p0 of the centred run's); theta
    falls from ~4.5 % off at the rig's size to < 0.6 % on bodies 4x larger."""
    p_tol, q_tol, theta_tol = BEM[basis]
    load, q = 100.0, 0.5 * F * 100.0
    hertz = HertzLineContact(load, R, E_STAR)
    theory = MindlinDeresiewicz(hertz, F)
    errors = {}
    for size in (1.0, 4.0):
        for m in (moment, 0.0):
            simulation, result = tilted_run(
                {"steps": ["A", "B"], "P": load, "Q": [0.0, q], "moment": m},
                basis=basis, model="bem", size=size,
            )  # fmt: skip
            shift = -m / load
            A, B = result["A"], result["B"]
            tilt = measured(simulation, A)["tilt"]
            errors[size, m] = (
                rms(A.pressure - hertz.pressure(A.x - shift)) / hertz.peak_pressure,
                rms(B.shear - theory.shear_traction(B.x - shift, [0.0, q]))
                / (F * hertz.peak_pressure),
                abs(tilt / (m / (load * R)) - 1.0) if m else abs(tilt),
            )
    e_p, e_q, e_theta = errors[4.0, moment]
    case = f"tilted pad, M {moment:g}, Q 0.5 f P (BEM, 4x bodies, {basis} 61)"
    assert record(case, "p RMS error / p0 about d", e_p, p_tol, page=PAGE)
    assert record(case, "q RMS error / f p0 about d", e_q, q_tol, page=PAGE)
    assert record(case, "theta / (M / (P R)) - 1", e_theta, theta_tol, page=PAGE)
    assert abs(errors[4.0, moment][1] - errors[4.0, 0.0][1]) < 0.01
    assert errors[1.0, moment][2] > 5 * errors[4.0, moment][2]
    assert errors[4.0, 0.0][2] < 1e-12


#: rounded-flat pad (flat b = 0.3 mm, fillets R = 20 mm) under P for b/a = 0.5 and a moment
#: that makes the contact unsymmetric: family: (pairs, p, q tolerances) against the same
#: half-plane problem at 480 nurbs pairs (an independent converged computation: measured
#: at most p 0.51 %, q 1.5 % back at Q = 0 for nurbs 60; lagrange2 63: 1.0 % and 1.8 %)
ROUNDED_FLAT = {"nurbs": (60, 0.007, 0.02), "lagrange2": (63, 0.013, 0.024)}
FLAT, EDGE = 0.3, 20.0


def rounded_flat_load():
    """The rounded flat's load P for a = 2 b (half-plane theory) and that a."""
    from fretbem.verification.rounded_flat import RoundedFlatPunch

    a = FLAT / 0.5
    return RoundedFlatPunch(FLAT, EDGE, E_STAR, F).load(a), a


def rounded_flat_scene(pairs, basis, a, load_table):
    """The rounded flat on half-planes, pivot at the first-contact point, ``load_table``
    its [load]."""
    return {
        "pad": {"shape": "rounded-flat", "flat": FLAT, "edge_radius": EDGE, "width": 10.0,
                "height": 10.0, "model": "half-plane"},
        "specimen": {"shape": "flat", "length": 40.0, "thickness": 13.0,
                     "model": "half-plane"},
        "material": {"E": E, "nu": NU},
        "contact": {"friction": F, "pairs": pairs, "basis": basis, "zone_width": 1.5 * a,
                    "estimate": False},
        "load": load_table,
        "rig": {"pivot_height": 0.0},
    }  # fmt: skip


def rounded_flat_run(moment, pairs, basis="nurbs"):
    load, a = rounded_flat_load()
    table = {"steps": ["A", "B", "C"], "P": load, "Q": [0.0, 0.5 * F * load, 0.0],
             "moment": moment * load * a}  # fmt: skip
    simulation, _ = build(scene_from_dict(rounded_flat_scene(pairs, basis, a, table)))
    return run(simulation), load, a


def rounded_flat_errors(result, reference) -> dict:
    peak = reference["A"].pressure.max()
    out = {}
    for name in "ABC":
        step, ref = result[name], reference[name]
        p = np.interp(step.x, ref.x, ref.pressure)
        q = np.interp(step.x, ref.x, ref.shear)
        out[name] = (rms(step.pressure - p) / peak, rms(step.shear - q) / (F * peak))
    return out


@pytest.mark.parametrize(
    "family, moment",
    [
        ("nurbs", 0.1),
        pytest.param("nurbs", -0.2, marks=pytest.mark.slow),
        pytest.param("lagrange2", 0.1, marks=pytest.mark.slow),
        pytest.param("lagrange2", -0.2, marks=pytest.mark.slow),
    ],
)
def test_rounded_flat_under_a_moment_against_a_converged_run(family, moment, record):
    """A rounded-flat pad under P (b/a = 0.5), M = 0.1 or -0.2 P a about the contact point,
    then Q = 0.5 f P and back: the unsymmetric contact (its edges at -0.62 / +0.55 a for
    M = 0.1 P a) against the same half-plane problem at 480 pairs; the pressure's centroid
    is at -M / P."""
    pairs, p_tol, q_tol = ROUNDED_FLAT[family]
    reference, _, a = rounded_flat_run(moment, 480)
    result, _, _ = rounded_flat_run(moment, pairs, family)
    errors = rounded_flat_errors(result, reference)
    case = f"rounded-flat pad, b/a 0.5, M {moment:g} P a (half-planes, {family} {pairs})"
    assert record(case, "p RMS / p_peak vs 480 pairs", errors["A"][0], p_tol, page=PAGE)
    assert record(case, "q RMS / f p_peak vs 480 pairs, at 0.5 f P", errors["B"][1], q_tol,
                  page=PAGE)  # fmt: skip
    assert record(case, "q RMS / f p_peak vs 480 pairs, back at 0", errors["C"][1], q_tol,
                  page=PAGE)  # fmt: skip
    step = reference["A"]
    assert abs(centroid(step) + moment * a) < 1e-3 * a
    inside = step.x[step.pressure > 0]
    assert inside.min() < -FLAT and inside.max() > FLAT  # both fillets in contact
    assert abs(inside.min() + inside.max()) > 0.05 * a  # unsymmetric


@pytest.mark.slow
def test_rounded_flat_under_a_moment_converges():
    """The difference to the 480-pair run falls with the pairs (measured p 0.49 % at 60,
    0.25 % at 120, 0.17 % at 240)."""
    reference, _, _ = rounded_flat_run(0.1, 480)
    errors = [rounded_flat_errors(rounded_flat_run(0.1, n)[0], reference)["A"][0]
              for n in (60, 120, 240)]  # fmt: skip
    assert errors[1] < 0.7 * errors[0] and errors[2] < errors[1]


#: family: (pairs, p, q, M tolerances) against the independent quadrature solution
#: (TiltedContact); measured over theta = 1e-3, -2e-3, 4e-3: nurbs 60 p 0.72 %, q 0.89 %,
#: M 1.7e-3 (at 120 pairs p 0.27 %); lagrange2 63 p 1.8 %, q 1.8 %, M 2.7e-4
QUADRATURE = {"nurbs": (60, 0.009, 0.012, 3e-3), "lagrange2": (63, 0.025, 0.025, 3e-3)}


@pytest.mark.parametrize("family", ["nurbs", pytest.param("lagrange2", marks=pytest.mark.slow)])
@pytest.mark.parametrize("theta", [1e-3, -2e-3, 4e-3])
def test_tilted_rounded_flat_against_the_quadrature_solution(family, theta, record):
    """A rounded-flat pad (b/a = 0.5 untilted) turned by theta (``[load] rotation``), P, then
    Q = 0.5 f P: p, q (Ciavarella-Jager) and the block's moment against half-plane theory's
    integral solution for the tilted profile, evaluated by Gauss-Chebyshev quadrature
    (:class:`fretbem.verification.tilted_contact.TiltedContact`, checked against Hertz and
    the untilted closed form in tests/framework/verification)."""
    from fretbem.verification.tilted_contact import TiltedContact

    pairs, p_tol, q_tol, m_tol = QUADRATURE[family]
    load, a = rounded_flat_load()
    table = {"steps": ["A", "B"], "P": load, "Q": [0.0, 0.5 * F * load], "rotation": theta}
    simulation, _ = build(scene_from_dict(rounded_flat_scene(pairs, family, a, table)))
    result = run(simulation)
    theory = TiltedContact(rounded_flat_slope, E_STAR, F)
    edges = theory.edges(load, theta, (-a, a))
    A, B = result["A"], result["B"]
    exact_p = theory.pressure(A.x, load, theta, edges)
    peak = exact_p.max()
    e_p = rms(A.pressure - exact_p) / peak
    e_q = rms(B.shear - theory.shear(B.x, load, 0.5 * F * load, theta, edges)) / (F * peak)
    e_m = abs(A.moment / theory.moment(load, theta, edges) - 1.0)
    case = f"rounded-flat pad tilted {theta:g} rad (half-planes, {family} {pairs})"
    page = PAGE
    assert record(case, "p RMS / p_peak vs the quadrature solution", e_p, p_tol, page=page)
    assert record(case, "q RMS / f p_peak at 0.5 f P vs Ciavarella-Jager", e_q, q_tol, page=page)
    assert record(case, "M / M_quadrature - 1", e_m, m_tol, page=page)
    assert edges[0] < -FLAT and edges[1] > FLAT and abs(edges[0] + edges[1]) > 0.05 * a


def rounded_flat_slope(x):
    """f'(x) of the rounded flat: 0 on the flat, the circular fillets' slope beyond."""
    x = np.asarray(x, float)
    beyond = np.maximum(np.abs(x) - FLAT, 0.0)
    return np.sign(x) * beyond / np.sqrt(EDGE**2 - beyond**2)


@pytest.mark.parametrize("basis", ["nurbs", pytest.param("lagrange2", marks=pytest.mark.slow)])
def test_bem_rig_spring_within_the_finite_body_difference(basis, record):
    """The rotational rig spring on finite BEM bodies, pivot on the pad's top (h = 16.25 mm,
    65 mm at 4x), k_r = 1e6, Q = 0.5 f P: theta against -h Q / (k_r + R P) is 2.8 % off at
    the rig's size (the pad bends under Q) and 0.26-0.35 % off on bodies 4x larger; the
    spring holds M = -k_r theta to round-off; the block's moment (its traction unknowns)
    balances the contact tractions' to the discretisation (measured 2.2e-3 of M nurbs,
    9e-4 lagrange2, as the force balances)."""
    load, q, stiffness = 100.0, 15.0, 1e6
    errors = {}
    for size in (1.0, 4.0):
        simulation, result = tilted_run(
            {"steps": ["A", "B"], "P": load, "Q": [0.0, q]},
            basis=basis, model="bem", size=size, rig={"stiffness_rotation": stiffness},
        )  # fmt: skip
        step = result["B"]
        values = measured(simulation, step)
        theta = -16.25 * size * q / (stiffness + R * load)
        errors[size] = abs(values["tilt"] / theta - 1.0)
        assert values["moment"] == pytest.approx(-stiffness * values["tilt"], rel=1e-12)
        assert abs(balance(simulation, step)) < 5e-3 * abs(values["moment"])
    case = f"rig k_r 1e6, pivot on the pad's top (BEM, 4x bodies, {basis} 61)"
    assert record(case, "theta / (-h Q / (k_r + R P)) - 1", errors[4.0], 0.006, page=PAGE)
    assert errors[1.0] > 5 * errors[4.0]
