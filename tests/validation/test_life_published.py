"""The life solver against published worked examples, and the mean-stress corrections.

Page: docs/verification/life_published.py. SWT carries the mean stress through sigma_max,
checked against its closed form in the elastic range at several mean stresses; the
stress-life method with Gerber's and Morrow's corrections against FatPy's published test
cases, every correction against its closed form, and the strain-life Morrow correction
against its curve and, in the elastic range, against the stress-life Morrow correction.
"""

import math

import numpy as np
import pytest

from fretbem.fatigue import FatigueMaterial, critical_plane_parameters, estimate_life
from fretbem.fatigue.mean_stress import mean_stress_correction
from fretbem.verification.published_lives import (
    STRESS_LIFE_WORKED_CASES,
    SWT_WORKED_CASES,
    basquin_swt_cycles,
    swt_stress,
)

PAGE = "life_published"


@pytest.mark.parametrize("case", SWT_WORKED_CASES, ids=lambda c: c.name)
def test_swt_life_matches_published(case, record):
    """N = 278.02 cycles for the FatPy case (published 277 and 278): within half a cycle of
    the rounded value 278 (the two published values differ by their rounding)."""
    material = FatigueMaterial("worked", case.constants(), {})
    life = estimate_life("swt", case.parameter, material)
    p_swt = swt_stress(case.E, case.parameter)
    assert record("SWT worked example (FatPy)", "P_SWT - 810.0 MPa (MPa)",
                  abs(p_swt - case.published_swt_stress), 0.05, page=PAGE)  # fmt: skip
    assert record("SWT worked example (FatPy)", "|N - 278| (cycles)",
                  abs(life.cycles - max(case.published_cycles)), 0.5, page=PAGE)  # fmt: skip
    assert min(case.published_cycles) - 1 <= life.cycles <= max(case.published_cycles) + 1
    assert not life.runout


@pytest.mark.parametrize("case", SWT_WORKED_CASES, ids=lambda c: c.name)
def test_critical_plane_search_gives_the_uniaxial_swt(case, record):
    """The uniaxial cycle sigma_xx = sigma_m + sigma_a sin(t) through the 3D plane search.

    Strains come from Hooke's law there, so the modulus is taken as sigma_a / eps_a (the
    secant of the worked example's cycle): the search must find the plane normal to x and
    sigma_max eps_a = 300 x 0.0135 = 4.05 MPa.
    """
    t = np.linspace(0.0, 2 * math.pi, 73)
    stress = np.zeros((t.size, 1, 4))
    stress[:, 0, 0] = case.mean_stress + case.stress_amplitude * np.sin(t)
    secant = case.stress_amplitude / case.strain_amplitude
    result = critical_plane_parameters(stress, E=secant, nu=0.3, methods=["swt"])["swt"]
    relative = abs(result.value[0] - case.parameter) / case.parameter
    assert record("SWT worked example (FatPy)", "plane search: relative error of sigma_max eps_a",
                  relative, 1e-6, page=PAGE)  # fmt: skip
    assert (
        abs(result.normal_angle_deg[0]) < 1e-6 or abs(abs(result.normal_angle_deg[0]) - 180) < 1e-6
    )


@pytest.mark.parametrize("mean", [-100.0, 0.0, 50.0, 150.0])
def test_swt_mean_stress_correction_matches_its_closed_form(mean, record):
    """Elastic range (eps_f' = 1e-15, negligible; the library refuses 0):
    N = (1/2)(sqrt(sigma_max sigma_a)/sigma_f')^(1/b) for sigma_a = 180 MPa and sigma_m
    from -100 to 150 MPa (the worked example's Basquin constants); the root finder agrees
    to 1e-9 (relative)."""
    sf, b, E, amplitude = 475.4, -0.078, 162000.0, 180.0
    material = FatigueMaterial(
        "basquin",
        {"E": E, "fatigue_strength_coefficient": sf, "fatigue_strength_exponent": b,
         "fatigue_ductility_coefficient": 1e-15, "fatigue_ductility_exponent": -0.62},
        {},
    )  # fmt: skip
    stress_max = mean + amplitude
    life = estimate_life("swt", stress_max * amplitude / E, material, runout_cycles=1e12)
    exact = basquin_swt_cycles(sf, b, stress_max, amplitude)
    # floored at 1e-12 so the table does not show rounding noise (measured 1e-15)
    relative = max(abs(life.cycles - exact) / exact, 1e-12)
    quantity = f"relative error of N at sigma_m = {mean:g} MPa (floor 1e-12)"
    assert record("SWT mean-stress correction (Basquin range)", quantity, relative, 1e-9,
                  page=PAGE)  # fmt: skip
    if mean > 0:
        assert life.cycles < basquin_swt_cycles(sf, b, amplitude, amplitude)


@pytest.mark.parametrize("case", STRESS_LIFE_WORKED_CASES, ids=lambda c: c.name)
def test_stress_life_matches_published(case, record):
    """FatPy's Gerber (N = 98104) and Morrow (N = 21475) cases: sigma_ar within half the
    published 0.1 MPa step (plus 0.001 MPa: Gerber's 183.75 is an exact tie, published as
    183.8) and N within half a cycle of the published whole number."""
    material = FatigueMaterial("worked", case.constants(), {})
    life = estimate_life(
        "stress_life", case.stress_amplitude, material, mean_stress=case.mean_stress,
        correction=case.correction, runout_cycles=1e9,
    )  # fmt: skip
    label = f"stress life, {case.correction} (FatPy)"
    assert record(label, "|sigma_ar - published| (MPa)",
                  abs(life.parameter - case.published_equivalent_amplitude), 0.051,
                  page=PAGE)  # fmt: skip
    assert record(label, "|N - published| (cycles)", abs(life.cycles - case.published_cycles),
                  0.5, page=PAGE)  # fmt: skip


#: the limit stresses of the closed-form sweep: sigma_u, sigma_f' and sigma~_fB
CLOSED_FORM = {
    "E": 162000.0, "fatigue_strength_coefficient": 475.4, "fatigue_strength_exponent": -0.078,
    "ultimate_strength": 700.0, "true_fracture_strength": 770.0,
}  # fmt: skip


@pytest.mark.parametrize("correction", ["goodman", "gerber", "morrow", "morrow_true_fracture"])
def test_mean_stress_correction_matches_its_closed_form(correction, record):
    """sigma_ar = sigma_a / (1 - sigma_m/L) (Gerber: 1 - (sigma_m/L)^2), N = (1/2)
    (sigma_ar/sigma_f')^(1/b) for sigma_a = 180 MPa and sigma_m from -200 to 200 MPa (below
    the mean at which Morrow's sigma_ar reaches sigma_f' = 475.4 MPa, where N is capped at one
    reversal): the worst relative error of N (floored at 1e-12; measured ~1e-16)."""
    material = FatigueMaterial("closed form", CLOSED_FORM, {})
    limit = mean_stress_correction(correction, material).limit
    worst = 0.0
    for mean in np.linspace(-200.0, 200.0, 9):
        ratio = mean / limit
        factor = 1 - ratio**2 if correction == "gerber" else 1 - ratio
        exact = 0.5 * (180.0 / factor / 475.4) ** (1 / -0.078)
        life = estimate_life("stress_life", 180.0, material, mean_stress=mean,
                             correction=correction, runout_cycles=1e15)  # fmt: skip
        worst = max(worst, abs(life.cycles - exact) / exact)
    assert record(f"stress life, {correction} (closed form)",
                  "relative error of N, sigma_m -200..200 MPa (floor 1e-12)",
                  max(worst, 1e-12), 1e-9, page=PAGE)  # fmt: skip


def test_strain_life_morrow_matches_its_curve_and_the_stress_life_morrow(record):
    """The strain-life curve eps_a = (sigma_f' - sigma_m)/E (2N)^b + eps_f' (2N)^c inverted at
    N from 10 to 1e6 and sigma_m from -100 to 200 MPa (the FatPy SWT case's constants); and,
    with eps_f' = 1e-15 (elastic range), the same life as the stress-life Morrow correction
    at sigma_a = E eps_a: both relative errors <= 1e-9 (the root finder's tolerance)."""
    constants = {"E": 162000.0, "fatigue_strength_coefficient": 475.4,
                 "fatigue_strength_exponent": -0.078, "fatigue_ductility_coefficient": 0.612,
                 "fatigue_ductility_exponent": -0.62}  # fmt: skip
    material = FatigueMaterial("strain life", constants, {})
    elastic = material.with_values({"fatigue_ductility_coefficient": 1e-15})
    worst_curve = worst_stress = 0.0
    for mean in (-100.0, 0.0, 200.0):
        for cycles in (10.0, 1e3, 1e5, 1e6):
            x = 2 * cycles
            eps_a = (475.4 - mean) / 162000.0 * x**-0.078 + 0.612 * x**-0.62
            life = estimate_life("strain_life", eps_a, material, mean_stress=mean,
                                 correction="morrow")  # fmt: skip
            worst_curve = max(worst_curve, abs(life.cycles - cycles) / cycles)
        eps_a = 180.0 / 162000.0
        strain = estimate_life("strain_life", eps_a, elastic, mean_stress=mean,
                               correction="morrow", runout_cycles=1e15)  # fmt: skip
        stress = estimate_life("stress_life", 180.0, elastic, mean_stress=mean,
                               correction="morrow", runout_cycles=1e15)  # fmt: skip
        worst_stress = max(worst_stress, abs(strain.cycles - stress.cycles) / stress.cycles)
    assert record("strain life, Morrow", "relative error of N on its curve (floor 1e-12)",
                  max(worst_curve, 1e-12), 1e-9, page=PAGE)  # fmt: skip
    assert record("strain life, Morrow", "relative difference from stress-life Morrow, "
                  "elastic range (floor 1e-12)", max(worst_stress, 1e-12), 1e-9,
                  page=PAGE)  # fmt: skip
