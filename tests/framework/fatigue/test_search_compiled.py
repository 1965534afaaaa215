"""The compiled (numba) critical-plane search against the numpy search it replaces.

Both run the same algorithm (coarse grid, pruned exact circles, pattern search or in-plane
golden-section search, parabolic step), so they must agree on every criterion's plane and value
to round-off: measured 6e-16 relative on the values and 6e-11 degrees on the planes over the
histories below.
"""

from __future__ import annotations

import importlib.util

import numpy as np
import pytest

from fretbem.fatigue import (
    FatigueInputError,
    PlaneSearch,
    critical_plane_parameters,
)
from fretbem.fatigue import critical_plane as cp
from fretbem.fatigue.mean_stress import MeanStressCorrection
from fretbem.testing.fatigue import contact_stress_history, random_stress_history

pytest.importorskip("numba")

E, NU = 116000.0, 0.342
KW = {
    "methods": cp.METHODS,
    "E": E,
    "nu": NU,
    "findley_k": 0.3,
    "fatemi_socie_k": 0.5,
    "yield_strength": 941.8,
}
FIELDS = (
    "value",
    "shear_stress_amplitude",
    "normal_stress_max",
    "normal_stress_amplitude",
    "normal_stress_mean",
    "normal_strain_amplitude",
    "shear_strain_amplitude",
)


def cattaneo_mindlin(n=120, seed=3):
    """The benchmark's Cattaneo-Mindlin / Nowell-Hills cycle at points below the contact."""
    return contact_stress_history(n, seed, depth=0.5, steps_per_branch=2, nu=NU)


def plane_strain_history(n=50, seed=5):
    """Random non-proportional histories with sigma_zz = nu (sxx + syy)."""
    return random_stress_history(n, seed, nu=NU)


def free_history(n=80, seed=7):
    """Random histories with an independent sigma_zz: critical planes tilted out of plane."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 2 * np.pi, 9)
    a, b = rng.normal(size=(n, 4)) * 100, rng.normal(size=(n, 4)) * 60
    s = a[None] * np.sin(t)[:, None, None] + b[None] * np.cos(3 * t)[:, None, None]
    return s + rng.normal(size=(1, n, 4)) * 50


HISTORIES = {"cattaneo_mindlin": cattaneo_mindlin, "plane_strain": plane_strain_history,
             "free_szz": free_history}  # fmt: skip


def both(stress, search=None, **kw):
    search = search or PlaneSearch()
    options = {**KW, **kw}
    numpy_path = critical_plane_parameters(
        stress, search=PlaneSearch(**{**_fields(search), "compiled": False}), **options
    )
    compiled = critical_plane_parameters(
        stress, search=PlaneSearch(**{**_fields(search), "compiled": True}), **options
    )
    return numpy_path, compiled


def _fields(search):
    return {
        "in_plane_only": search.in_plane_only,
        "theta_step_deg": search.theta_step_deg,
        "psi_step_deg": search.psi_step_deg,
        "refine_levels": search.refine_levels,
    }


def _largest(a, names) -> float:
    return max(np.abs(v[np.isfinite(v)]).max(initial=0.0) for v in map(a.__getattribute__, names))


def assert_same(numpy_path, compiled, rtol=1e-9, deg=1e-7):
    """Every field to ``rtol`` of the largest of its kind (the value; the plane's stresses; its
    strains: a plane turned by round-off moves each of its stresses by up to the largest times
    the turn, so a near-zero shear amplitude is compared on the plane's stress scale); planes to
    ``deg`` degrees."""
    assert numpy_path.keys() == compiled.keys()
    for method, a in numpy_path.items():
        b = compiled[method]
        kinds = {"value": ("value",), "strain": tuple(n for n in FIELDS if "strain" in n)}
        kinds["stress"] = tuple(n for n in FIELDS if n not in kinds["strain"] + ("value",))
        for name in FIELDS:
            x, y = getattr(a, name), getattr(b, name)
            finite = np.isfinite(x)
            np.testing.assert_array_equal(finite, np.isfinite(y), err_msg=f"{method} {name}")
            kind = next(k for k, names in kinds.items() if name in names)
            scale = max(_largest(a, kinds[kind]), 1e-300)
            assert np.abs(x[finite] - y[finite]).max(initial=0.0) <= rtol * scale, (method, name)
        turn = (a.normal_angle_deg - b.normal_angle_deg + 90.0) % 180.0 - 90.0
        assert np.abs(turn).max() <= deg, method
        assert np.abs(a.normal_tilt_deg - b.normal_tilt_deg).max() <= deg, method
        assert np.all((b.normal_angle_deg >= 0.0) & (b.normal_angle_deg < 180.0))


@pytest.mark.parametrize("in_plane", [True, False], ids=["in_plane", "3d"])
@pytest.mark.parametrize("name", sorted(HISTORIES))
def test_compiled_search_finds_the_numpy_planes_and_values(name, in_plane):
    stress = HISTORIES[name]()
    assert_same(*both(stress, PlaneSearch(in_plane_only=in_plane)))


@pytest.mark.parametrize("correction", [("goodman", 900.0), ("gerber", 500.0), ("morrow", 60.0)])
def test_compiled_stress_life_with_mean_stress_corrections(correction):
    """Morrow at a 60 MPa limit: many planes are a static failure (inf), on both paths."""
    stress = free_history(n=40)
    numpy_path, compiled = both(
        stress, mean_stress=MeanStressCorrection(*correction), methods=("stress_life",)
    )
    assert_same(numpy_path, compiled)
    if correction[0] == "morrow":
        assert np.isinf(compiled["stress_life"].value).any()


@pytest.mark.parametrize(
    "search",
    [
        PlaneSearch(refine_levels=0),
        PlaneSearch(refine_levels=2, theta_step_deg=30.0, psi_step_deg=30.0),
        PlaneSearch(in_plane_only=True, theta_step_deg=12.0, refine_levels=7),
        PlaneSearch(psi_step_deg=45.0),
    ],
    ids=["no_refinement", "coarse_30deg", "in_plane_12deg", "psi_45deg"],
)
def test_compiled_search_follows_the_search_settings(search):
    assert_same(*both(plane_strain_history(n=30), search))


@pytest.mark.parametrize(
    "methods",
    [("swt",), ("mwcm", "swt"), ("strain_life", "findley"), ("stress_life", "strain_life")],
)
def test_compiled_search_with_any_subset_of_criteria(methods):
    """The criteria share one pass: a subset, in any order, finds the same planes."""
    stress = free_history(n=30)
    numpy_path, compiled = both(stress, methods=methods)
    assert list(compiled) == list(methods)
    assert_same(numpy_path, compiled)


def test_compiled_search_edge_histories():
    """One point, two steps; a point without stress; a proportional (straight) path; more
    points than a block of the refinement."""
    rng = np.random.default_rng(2)
    two_steps = rng.normal(size=(2, 1, 4)) * 100
    assert_same(*both(two_steps))
    calm = np.zeros((5, 3, 4))
    calm[:, 1] = np.linspace(-1.0, 1.0, 5)[:, None] * [100.0, -30.0, 40.0, 20.0]
    numpy_path, compiled = both(calm)
    assert_same(numpy_path, compiled)
    np.testing.assert_array_equal(compiled["findley"].value[[0, 2]], 0.0)
    many = cattaneo_mindlin(n=150)  # blocks of 64 points: 64 + 64 + 22
    assert_same(*both(many, PlaneSearch(in_plane_only=True)))


def test_compiled_search_on_the_boundaries_of_the_planes():
    """Critical planes on psi = 90 degrees (in-plane) and psi = 0 (normal z), where the
    compiled refinement takes the neighbours that are the plane itself unevaluated: the numpy
    search's planes and values, and the hand values of a uniaxial cycle along z (SWT
    sigma_max sigma_a / E on the plane normal to z) and along x (in-plane, normal x).

    On the 5 x 10 degree grid the two searches start from the same planes; on the default
    grid (psi rows 90 and 45 degrees) they start from different planes of the cones of
    maxima around the load axis of the second point (ties that single-precision rounding
    breaks differently): SWT and MWCM take the same values, and the three levels of the
    pattern search end within 7.2e-6 of the Fatemi-Socie and Findley cones' values
    (measured against a 0.5 x 1 degree grid with ten levels): both within 1e-5 there."""
    t = np.linspace(0.0, 2.0 * np.pi, 9)[:, None]
    stress = np.zeros((9, 2, 4))
    stress[:, 0, 3] = 100.0 + 200.0 * np.sin(t[:, 0])  # szz alone: the plane normal to z
    stress[:, 1, 0] = 100.0 + 200.0 * np.sin(t[:, 0])  # sxx alone: the in-plane normal x
    assert_same(*both(stress, PlaneSearch(psi_step_deg=10.0, refine_levels=5)))
    numpy_path, compiled = both(stress)
    for method, rtol in (
        ("swt", 1e-12),
        ("mwcm", 1e-12),
        ("findley", 1e-5),
        ("fatemi_socie", 1e-5),
    ):
        np.testing.assert_allclose(compiled[method].value, numpy_path[method].value, rtol=rtol)
    swt = compiled["swt"]
    assert swt.value == pytest.approx(300.0 * 200.0 / E, rel=1e-12)
    np.testing.assert_allclose(swt.normal_tilt_deg, [90.0, 0.0], atol=1e-12)
    # Findley and MWCM: tau_a of a uniaxial cycle, 100 MPa, on planes at 45 degrees to the load
    assert compiled["mwcm"].shear_stress_amplitude == pytest.approx(100.0, rel=1e-9)
    assert_same(*both(plane_strain_history(n=30), PlaneSearch(refine_levels=1)))


def test_the_default_choice_is_by_the_search_size_alone():
    """Compiled from COMPILED_MIN_EVALUATIONS on, whatever ran before in the process: a
    20,000-point 3D search is compiled; the benchmark's 10,000-point 3D search (73 grid
    planes, where both paths take ~0.4 s in a fresh process), its in-plane search and small
    ones numpy."""
    search, in_plane = PlaneSearch(), PlaneSearch(in_plane_only=True)
    assert cp.search_evaluations(search, 9, 10_000, 4) == 9 * 10_000 * (73 + 240)
    assert cp.use_compiled(search, 9, 20_000, 4)
    assert not cp.use_compiled(search, 9, 10_000, 4)
    assert not cp.use_compiled(in_plane, 9, 10_000, 4)
    assert not cp.use_compiled(search, 5, 100, 2)
    assert cp.use_compiled(PlaneSearch(compiled=True), 5, 100, 2)
    assert not cp.use_compiled(PlaneSearch(compiled=False), 9, 10_000, 4)


def test_the_same_search_twice_gives_the_same_bits():
    """A search repeated after compiled ones (numba loaded) takes the same path again."""
    stress = plane_strain_history(n=20)
    first = critical_plane_parameters(stress, **KW)
    both(stress)
    again = critical_plane_parameters(stress, **KW)
    for method in first:
        np.testing.assert_array_equal(first[method].value, again[method].value)
        np.testing.assert_array_equal(
            first[method].normal_angle_deg, again[method].normal_angle_deg
        )


def test_without_numba_the_search_stays_in_numpy(monkeypatch):
    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name, *a: None if name == "numba" else real(name, *a)
    )
    assert not cp.use_compiled(PlaneSearch(), 9, 10**6, 4)
    with pytest.raises(FatigueInputError, match=r"PlaneSearch\(compiled=True\) needs numba"):
        critical_plane_parameters(
            plane_strain_history(n=2), search=PlaneSearch(compiled=True), **KW
        )


def test_plane_search_refuses_a_non_boolean_choice():
    with pytest.raises(TypeError, match="compiled"):
        PlaneSearch(compiled="yes")


def test_compiled_circle_of_nearly_equal_points_far_from_the_origin():
    """The compiled circle of two shear points 2.4e-9 MPa apart at 29 MPa: the distances'
    round-off exceeds the tiny circle's own slack, which sent the iteration to a circle
    through collinear points and returned an infinite radius; it is the half distance."""
    from fretbem.fatigue import compiled_search

    x = np.array([-1.3554238596245625e-15, 1.0434966352127865e-15])
    y = np.array([-29.222977473699515, -29.222977471320252])
    radius = compiled_search._circle(x, y, np.array([-1, -1, -1]))
    assert radius == pytest.approx(0.5 * abs(y[1] - y[0]), rel=1e-6)
