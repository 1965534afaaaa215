"""Life inversion, critical distances, Ruiz, cycle selection, material data and the request."""

from __future__ import annotations

import math
import sys
from importlib import resources

import numpy as np
import pytest

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

from fretbem.fatigue import (
    FatigueInputError,
    FatigueMaterial,
    MissingFatigueDataError,
    available_materials,
    critical_distance_from_threshold,
    critical_distance_values,
    estimate_life,
    fatigue_request_from_dict,
    last_full_reversal,
    load_material,
    ruiz_parameters,
    select_cycle,
    turning_points,
)

USER = FatigueMaterial(
    name="user",
    values={
        "E": 70000.0,
        "nu": 0.3,
        "fatigue_strength_coefficient": 1000.0,
        "fatigue_strength_exponent": -0.1,
        "fatigue_ductility_coefficient": 0.3,
        "fatigue_ductility_exponent": -0.6,
        "fatigue_limit_range": 400.0,
        "torsion_fatigue_limit_amplitude": 130.0,
        "findley_k": 0.3,
    },
    sources={},
)


# -- life ----------------------------------------------------------------------------------------


@pytest.mark.parametrize("cycles", [50.0, 3.0e3, 2.0e5, 5.0e6])
def test_swt_life_inverts_the_strain_life_curve(cycles):
    E, sf, b, ef, c = 70000.0, 1000.0, -0.1, 0.3, -0.6
    x = 2 * cycles
    swt = sf**2 / E * x ** (2 * b) + sf * ef * x ** (b + c)
    life = estimate_life("swt", swt, USER)
    assert not life.runout
    assert life.cycles == pytest.approx(cycles, rel=1e-9)


def test_fatemi_socie_life_uses_the_shear_curve_estimated_from_the_uniaxial_one():
    G = 70000.0 / 2.6
    tf, gf = 1000.0 / math.sqrt(3), 0.3 * math.sqrt(3)
    x = 2 * 1.0e4
    fs = tf / G * x**-0.1 + gf * x**-0.6
    assert estimate_life("fatemi_socie", fs, USER).cycles == pytest.approx(1.0e4, rel=1e-9)
    assert "shear_fatigue_strength_coefficient" in USER.derived


def test_findley_life_closed_form_and_its_fatigue_limit():
    scale = math.sqrt(1 + 0.3**2) * 1000.0 / math.sqrt(3)
    value = scale * (2 * 1.0e5) ** -0.1
    assert estimate_life("findley", value, USER).cycles == pytest.approx(1.0e5, rel=1e-9)
    limit = 130.0 * math.sqrt(1 + 0.3**2)
    below = estimate_life("findley", 0.99 * limit, USER)
    assert below.runout and math.isinf(below.cycles) and "fatigue limit" in below.message


def test_runout_is_reported_as_such_never_as_a_huge_number():
    life = estimate_life("swt", 1e-6, USER, runout_cycles=1e7)
    assert life.runout and math.isinf(life.cycles) and "run-out" in life.message
    assert estimate_life("swt", -0.3, USER).runout


def test_mwcm_life_on_the_modified_wohler_curves():
    # torsion (rho = 0) at the reference life: exactly the torsion limit gives run-out
    assert estimate_life("mwcm", 130.0, USER, rho=0.0).runout
    # uniaxial (rho = 1): tau_ref = sigma_A / 2 = 100 MPa, inverse slope k = -1/b = 10
    life = estimate_life("mwcm", 200.0, USER, rho=1.0, runout_cycles=2e6)
    assert life.cycles == pytest.approx(2e6 * 0.5**10, rel=1e-12)


def test_missing_constants_are_named():
    bare = FatigueMaterial(name="bare", values={"E": 1.0, "nu": 0.3}, sources={})
    with pytest.raises(MissingFatigueDataError, match="fatigue_strength_coefficient"):
        estimate_life("swt", 1.0, bare)
    with pytest.raises(MissingFatigueDataError, match="torsion_fatigue_limit_amplitude"):
        estimate_life("mwcm", 1.0, bare, rho=1.0)


def test_findley_k_from_two_fatigue_limits():
    """tau_-1 sqrt(1 + k^2) = (sigma_-1 / 2)(k + sqrt(1 + k^2)) defines k."""
    m = FatigueMaterial(
        name="limits",
        values={"fatigue_limit_range": 400.0, "torsion_fatigue_limit_amplitude": 130.0},
        sources={},
    )
    k = m.get("findley_k")
    assert 130.0 * math.sqrt(1 + k * k) == pytest.approx(100.0 * (k + math.sqrt(1 + k * k)))
    assert "findley_k" in m.derived


# -- critical distances -------------------------------------------------------------------------


def test_critical_distance_from_threshold():
    # Al 7050-T7451 (Pinto et al. 2022): Delta K_th 5.5 MPa sqrt(m), Delta sigma_0 292 MPa -> 113 um
    assert critical_distance_from_threshold(5.5, 292.0) == pytest.approx(0.1129, abs=5e-5)


def test_point_line_area_methods_on_a_linear_field():
    c0, c1, L = 3.0, -2.0, 0.2

    def field(points):
        return c0 + c1 * points[:, 1]

    t = critical_distance_values(field, (0.4, 0.0), L)
    assert t.point_value == pytest.approx(c0 + c1 * L / 2, rel=1e-14)
    assert t.line_value == pytest.approx(c0 + c1 * L, rel=1e-14)
    R = 1.32 * L
    assert t.area_value == pytest.approx(c0 + c1 * 4 * R / (3 * np.pi), rel=1e-12)


def test_critical_direction_along_a_slanted_line():
    d = np.array([1.0, 1.0]) / np.sqrt(2)

    def field(points):
        return points[:, 0] + points[:, 1]

    t = critical_distance_values(field, (0.0, 0.0), 1.0, direction=d)
    assert t.point_value == pytest.approx(np.sqrt(2) * 0.5, rel=1e-14)
    with pytest.raises(FatigueInputError, match="into the body"):
        critical_distance_values(field, (0.0, 0.0), 1.0, direction=(0.0, -1.0))


# -- Ruiz -------------------------------------------------------------------------------------


def test_ruiz_hand_result():
    x = np.array([0.0, 1.0, 2.0])
    q = np.array([[10.0, -20.0, 5.0], [-30.0, 10.0, 0.0]])
    sxx = np.array([[100.0, -50.0, 20.0], [50.0, -10.0, 40.0]])
    slip = np.array([[0.0, 1e-3, 0.0], [2e-3, -1e-3, 0.0]])
    r = ruiz_parameters(x, q, sxx, slip)
    np.testing.assert_allclose(r.slip_amplitude, [1e-3, 1e-3, 0.0])
    np.testing.assert_allclose(r.f1, [30e-3, 20e-3, 0.0])
    np.testing.assert_allclose(r.f2, [100 * 30e-3, 0.0, 0.0])  # compression gives no F2
    assert r.f2_max_location == 0.0
    with pytest.raises(FatigueInputError, match="shape"):
        ruiz_parameters(x, q[:, :2], sxx, slip)


# -- cycle --------------------------------------------------------------------------------------


def test_cycle_is_the_last_full_reversal():
    q = np.array([0.0, 0.5, 1.0, 0.0, -1.0, 0.0, 1.0])  # A..: load, unload, reload
    assert turning_points(q).tolist() == [0, 2, 4, 6]
    assert last_full_reversal(q).tolist() == [2, 3, 4, 5, 6]
    assert select_cycle(7, driver=q, steps=[0, 6]).tolist() == [0, 6]
    assert select_cycle(7).tolist() == list(range(7))
    with pytest.raises(FatigueInputError, match="never changes"):
        last_full_reversal(np.zeros(4))
    with pytest.raises(FatigueInputError, match="outside"):
        select_cycle(3, steps=[0, 5])


# -- materials and request ----------------------------------------------------------------------


def test_every_library_constant_has_a_source():
    text = resources.files("fretbem.fatigue").joinpath("materials.toml").read_text()
    library = tomllib.loads(text)["materials"]
    assert set(library) == {"Al 7050-T7451", "Ti-6Al-4V"} == set(available_materials())
    for name, table in library.items():
        for key, entry in table.items():
            if key == "description":
                continue
            assert isinstance(entry, dict) and entry["source"].strip(), (name, key)
        material = load_material(name)
        assert set(material.sources) == set(material.values)


def test_request_from_a_scene_table():
    req = fatigue_request_from_dict(
        {
            "material": "Al 7050-T7451",
            "constants": {"findley_k": 0.3},
            "methods": ["swt", "findley"],
            "cycle_steps": [2, 3, 4],
            "hot_spot": [0.1, 0.0],
            "map_points": [11, 5],
        }
    )
    assert req.methods == ("swt", "findley")
    assert req.critical_distance == pytest.approx(0.1129, abs=5e-5)  # from Delta K_th
    assert req.material.sources["findley_k"] == "user input"
    assert req.hot_spot == (0.1, 0.0)
    inline = fatigue_request_from_dict(
        {"material": {"E": 2e5, "nu": 0.3}, "critical_distance": 0.05}
    )
    assert inline.methods == ("swt", "mwcm")  # findley and fatemi_socie lack their k
    assert any("findley left out" in n for n in inline.notes)


@pytest.mark.parametrize(
    ("table", "match"),
    [
        ({"material": "Ti-6Al-4V", "colour": 1}, "unknown key"),
        ({"material": "Unobtainium"}, "unknown fatigue material"),
        ({}, "needs material"),
        ({"material": "Ti-6Al-4V", "methods": ["dang_van"]}, r"methods\[0\] must be one of"),
        ({"material": "Ti-6Al-4V", "constants": {"colour": 1.0}}, "unknown"),
        ({"material": "Ti-6Al-4V", "critical_distance": -1.0}, "critical_distance"),
        ({"material": "Ti-6Al-4V", "direction": "sideways"}, "direction"),
        ({"material": "Ti-6Al-4V", "map_x": [1.0]}, "map_x"),
        ({"material": {"E": {"value": 1.0}}}, "source"),
    ],
)
def test_bad_requests_are_named(table, match):
    with pytest.raises(FatigueInputError, match=match):
        fatigue_request_from_dict(table)
