"""Critical-plane parameters against hand results, invariances and the circumscribed circle."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from fretbem.fatigue import (
    FatigueInputError,
    PlaneSearch,
    critical_plane_parameters,
    minimum_circumscribed_circle,
)
from fretbem.fatigue.critical_plane import plane_quantities
from fretbem.fatigue.mcc import circle_bounds
from fretbem.fatigue.planes import projection
from fretbem.testing.fatigue import in_plane_scan

E, NU = 70000.0, 0.3
G = E / (2 * (1 + NU))
K_F, K_FS, SY = 0.3, 0.5, 400.0
KW = {"E": E, "nu": NU, "findley_k": K_F, "fatemi_socie_k": K_FS, "yield_strength": SY}
#: measured: the refined search reaches the 1D hand maxima to 1.2e-6 relative at worst (the
#: uniaxial Fatemi-Socie maximum lies on a cone of planes, a ridge for the angle search)
HAND_RTOL = 5e-6


def cycle(n=25):
    return np.linspace(0.0, 2 * np.pi, n)


def history(**components):
    """Stress history (T, 1, 4) from component time series."""
    t = cycle()
    out = np.zeros((t.size, 1, 4))
    for i, name in enumerate(("sxx", "syy", "sxy", "szz")):
        if name in components:
            out[:, 0, i] = components[name](t)
    return out


def dense_max(f):
    """max over a 1D angle of f(phi): the hand result of an axisymmetric or in-plane case."""
    phi = np.linspace(0, np.pi, 2_000_001)
    return float(np.max(f(phi)))


# -- minimum circumscribed circle ------------------------------------------------------------


def brute_force_radius(p):
    best = np.inf
    for i, j in itertools.combinations(range(len(p)), 2):
        c = 0.5 * (p[i] + p[j])
        r = np.linalg.norm(p[i] - c)
        if np.all(np.linalg.norm(p - c, axis=1) <= r * (1 + 1e-9)):
            best = min(best, r)
    for i, j, k in itertools.combinations(range(len(p)), 3):
        a, b, c = p[i], p[j], p[k]
        d = 2 * (a[0] * (b[1] - c[1]) + b[0] * (c[1] - a[1]) + c[0] * (a[1] - b[1]))
        if abs(d) < 1e-14:
            continue
        ux = ((a @ a) * (b[1] - c[1]) + (b @ b) * (c[1] - a[1]) + (c @ c) * (a[1] - b[1])) / d
        uy = ((a @ a) * (c[0] - b[0]) + (b @ b) * (a[0] - c[0]) + (c @ c) * (b[0] - a[0])) / d
        centre = np.array([ux, uy])
        r = np.linalg.norm(a - centre)
        if np.all(np.linalg.norm(p - centre, axis=1) <= r * (1 + 1e-9)):
            best = min(best, r)
    return best


def test_mcc_matches_brute_force_on_random_paths():
    rng = np.random.default_rng(3)
    points = rng.normal(size=(200, 9, 2)) * rng.uniform(0.1, 10, size=(200, 1, 1))
    _, radius = minimum_circumscribed_circle(points)
    expected = np.array([brute_force_radius(p) for p in points])
    np.testing.assert_allclose(radius, expected, rtol=1e-12)
    lower, upper = circle_bounds(points)
    assert np.all(lower <= radius * (1 + 1e-12)) and np.all(upper >= radius * (1 - 1e-12))


def test_mcc_degenerate_sets():
    same = np.ones((1, 7, 2))
    line = np.stack([np.linspace(-2, 3, 7), 2 * np.linspace(-2, 3, 7)], axis=1)[None]
    _, r = minimum_circumscribed_circle(np.concatenate([same, line]))
    assert r[0] == 0.0
    assert r[1] == pytest.approx(0.5 * 5 * np.sqrt(5), rel=1e-14)


def test_triangle_path_uses_the_circumscribed_circle_not_half_the_chord():
    """Three shear states 120 degrees apart: amplitude R, while half the chord is R sqrt(3)/2."""
    A = 200.0
    t = np.deg2rad([0.0, 120.0, 240.0])
    # on the plane theta = 0, psi = 45 deg: tau_1 = (sxx - szz)/2, tau_2 = sxy / sqrt(2)
    stress = np.zeros((3, 1, 4))
    stress[:, 0, 0] = A * np.sin(t)
    stress[:, 0, 2] = A / np.sqrt(2) * np.cos(t)
    q = plane_quantities(stress, projection(np.array([0.0]), np.array([np.pi / 4])), E, NU)
    path = np.stack([q["path_x"][:, 0], q["path_y"][:, 0]], axis=1)[None]
    _, r = minimum_circumscribed_circle(path)
    assert r[0] == pytest.approx(A / 2, rel=1e-12)
    chord = max(np.linalg.norm(path[0, i] - path[0, j]) for i in range(3) for j in range(3))
    assert chord / 2 == pytest.approx(A / 2 * np.sqrt(3) / 2, rel=1e-12)


def test_ninety_degree_out_of_phase_tension_torsion():
    """sigma = 2 tau out of phase: every in-plane plane sees a shear amplitude tau (Mohr radius)."""
    tau = 150.0
    s = history(sxx=lambda t: 2 * tau * np.sin(t), sxy=lambda t: tau * np.cos(t))
    r = critical_plane_parameters(s, methods=("mwcm",), **KW)["mwcm"]
    assert r.shear_stress_amplitude[0] == pytest.approx(tau, rel=HAND_RTOL)
    # the tie between the equal-amplitude planes goes to the largest normal stress
    phi = np.linspace(0, np.pi, 200001)
    smax = np.max(np.sqrt((2 * tau * np.cos(phi) ** 2) ** 2 + (tau * np.sin(2 * phi)) ** 2))
    assert r.normal_stress_max[0] == pytest.approx(smax, rel=1e-5)


# -- hand results ------------------------------------------------------------------------------


def test_uniaxial_cycle_hand_results():
    sa, sm = 200.0, 50.0
    s = history(sxx=lambda t: sm + sa * np.sin(t))
    r = critical_plane_parameters(s, **KW)
    # SWT = sigma_max eps_a on the loading axis
    assert r["swt"].value[0] == pytest.approx((sm + sa) * sa / E, rel=HAND_RTOL)
    assert min(r["swt"].normal_angle_deg[0], 180 - r["swt"].normal_angle_deg[0]) < 0.5

    # axisymmetric about x: one angle phi between normal and x
    def tau_a(phi):
        return sa * np.abs(np.sin(phi) * np.cos(phi))

    def smax(phi):
        return (sm + sa) * np.cos(phi) ** 2

    assert r["findley"].value[0] == pytest.approx(
        dense_max(lambda p: tau_a(p) + K_F * smax(p)), rel=HAND_RTOL
    )
    assert r["fatemi_socie"].value[0] == pytest.approx(
        dense_max(lambda p: tau_a(p) / G * (1 + K_FS * smax(p) / SY)), rel=HAND_RTOL
    )
    assert r["mwcm"].shear_stress_amplitude[0] == pytest.approx(sa / 2, rel=HAND_RTOL)
    assert r["mwcm"].rho[0] == pytest.approx(1 + sm / sa, rel=1e-5)
    assert r["mwcm"].normal_strain_amplitude[0] > 0


def test_fully_reversed_uniaxial_findley_closed_form():
    sa = 180.0
    s = history(sxx=lambda t: sa * np.sin(t))
    r = critical_plane_parameters(s, methods=("findley",), **KW)["findley"]
    assert r.value[0] == pytest.approx(sa / 2 * (K_F + np.sqrt(1 + K_F**2)), rel=HAND_RTOL)


def test_pure_shear_cycle_hand_results():
    """Torsion: Findley = tau sqrt(1 + k^2) (the torsion-limit relation), SWT on 45 deg planes."""
    tau = 120.0
    s = history(sxy=lambda t: tau * np.sin(t))
    r = critical_plane_parameters(s, **KW)
    assert r["findley"].value[0] == pytest.approx(tau * np.sqrt(1 + K_F**2), rel=HAND_RTOL)
    assert r["swt"].value[0] == pytest.approx(tau * (1 + NU) * tau / E, rel=HAND_RTOL)
    assert r["swt"].normal_angle_deg[0] % 90 == pytest.approx(45.0, abs=0.3)
    expected_fs = dense_max(
        lambda p: tau * np.abs(np.cos(2 * p)) / G * (1 + K_FS * tau * np.abs(np.sin(2 * p)) / SY)
    )
    assert r["fatemi_socie"].value[0] == pytest.approx(expected_fs, rel=HAND_RTOL)
    assert r["mwcm"].value[0] == pytest.approx(tau, rel=HAND_RTOL)
    assert r["mwcm"].shear_strain_amplitude[0] == pytest.approx(tau / G, rel=HAND_RTOL)


def test_plane_strain_out_of_plane_planes_matter():
    """A state whose largest shear lies on planes tilted out of x-y: the 3D search finds it."""
    sa = 100.0
    # sxx = syy in phase, szz = 0: in-plane shear is zero, the shear acts on planes through z
    s = history(sxx=lambda t: sa * np.sin(t), syy=lambda t: sa * np.sin(t))
    full = critical_plane_parameters(s, methods=("mwcm",), **KW)["mwcm"]
    flat = critical_plane_parameters(
        s, methods=("mwcm",), search=PlaneSearch(in_plane_only=True), **KW
    )["mwcm"]
    assert full.value[0] == pytest.approx(sa / 2, rel=HAND_RTOL)
    assert abs(full.normal_tilt_deg[0]) == pytest.approx(45.0, abs=0.5)
    assert flat.value[0] == pytest.approx(0.0, abs=1e-9)


# -- invariance --------------------------------------------------------------------------------


def random_history(seed, n_points=30):
    rng = np.random.default_rng(seed)
    t = cycle(11)
    A = rng.normal(size=(n_points, 4)) * 100
    B = rng.normal(size=(n_points, 4)) * 40
    s = A[None] * np.sin(t)[:, None, None] + B[None] * np.cos(2 * t)[:, None, None]
    s += rng.normal(size=(1, n_points, 4)) * 30
    s[..., 3] = NU * (s[..., 0] + s[..., 1])
    return s


def rotate(s, alpha):
    c, si = np.cos(alpha), np.sin(alpha)
    sxx, syy, sxy = s[..., 0], s[..., 1], s[..., 2]
    out = s.copy()
    out[..., 0] = c * c * sxx + si * si * syy - 2 * c * si * sxy
    out[..., 1] = si * si * sxx + c * c * syy + 2 * c * si * sxy
    out[..., 2] = c * si * (sxx - syy) + (c * c - si * si) * sxy
    return out


#: measured over these histories: rotated and original maxima agree to 3e-5 of the largest
#: value (the grids differ relative to the material); the margin covers other seeds
INVARIANCE_RTOL = 5e-4


@pytest.mark.parametrize("alpha_deg", [17.0, 63.0, 131.0])
def test_rotation_leaves_parameters_unchanged_and_rotates_the_plane(alpha_deg):
    s = random_history(7)
    alpha = np.deg2rad(alpha_deg)
    a = critical_plane_parameters(s, **KW)
    b = critical_plane_parameters(rotate(s, alpha), **KW)
    for m in a:
        scale = np.abs(a[m].value).max()
        np.testing.assert_allclose(b[m].value, a[m].value, atol=INVARIANCE_RTOL * scale)
    # where the critical plane is in-plane and clearly unique, its angle turns by alpha
    r0, r1 = a["swt"], b["swt"]
    flat = (np.abs(r0.normal_tilt_deg) < 1) & (np.abs(r1.normal_tilt_deg) < 1)
    diff = (r1.normal_angle_deg[flat] - r0.normal_angle_deg[flat] - alpha_deg) % 180
    diff = np.minimum(diff, 180 - diff)
    assert flat.sum() >= 5
    assert np.median(diff) < 0.5


def test_scaling_the_amplitude():
    s = random_history(11)
    lam = 1.7
    a = critical_plane_parameters(s, methods=("swt", "findley", "mwcm"), **KW)
    b = critical_plane_parameters(lam * s, methods=("swt", "findley", "mwcm"), **KW)
    for m, power in (("swt", 2), ("findley", 1), ("mwcm", 1)):
        scale = np.abs(b[m].value).max()
        np.testing.assert_allclose(
            b[m].value, lam**power * a[m].value, atol=INVARIANCE_RTOL * scale
        )
    # Fatemi-Socie without the normal-stress term is a shear strain amplitude: linear too
    kw = dict(KW, fatemi_socie_k=0.0)
    fa = critical_plane_parameters(s, methods=("fatemi_socie",), **kw)["fatemi_socie"]
    fb = critical_plane_parameters(lam * s, methods=("fatemi_socie",), **kw)["fatemi_socie"]
    np.testing.assert_allclose(fb.value, lam * fa.value, rtol=INVARIANCE_RTOL)


def test_refined_search_reaches_a_dense_grid():
    """Default search vs a 1-degree grid: measured worst shortfall 1e-3 of the largest value."""
    s = random_history(5, n_points=40)
    a = critical_plane_parameters(s, **KW)
    dense = critical_plane_parameters(
        s, search=PlaneSearch(theta_step_deg=1.0, psi_step_deg=1.0, chunk_points=10), **KW
    )
    for m in a:
        scale = np.abs(dense[m].value).max()
        assert np.all(a[m].value <= dense[m].value + 1e-6 * scale)
        assert np.all(dense[m].value - a[m].value <= 2e-3 * scale)


def test_bad_inputs_are_named():
    with pytest.raises(FatigueInputError, match="n_steps >= 2"):
        critical_plane_parameters(np.zeros((5, 3)), **KW)
    with pytest.raises(FatigueInputError, match="NaN"):
        critical_plane_parameters(np.full((3, 2, 4), np.nan), **KW)
    with pytest.raises(FatigueInputError, match="findley_k"):
        critical_plane_parameters(np.zeros((3, 2, 4)), E=E, nu=NU, methods=("findley",))
    with pytest.raises(FatigueInputError, match="unknown fatigue method"):
        critical_plane_parameters(np.zeros((3, 2, 4)), E=E, nu=NU, methods=("dang_van",))


def plane_stresses_by_hand(stress, normal):
    """Normal stress and shear vector paths on the plane of unit ``normal`` (3,): traction
    sigma n, its normal part, the rest in a basis of the plane; (T,), (T, 2)."""
    sxx, syy, sxy, szz = np.moveaxis(stress, -1, 0)
    zero = np.zeros_like(sxx)
    tensor = np.stack(
        [np.stack([sxx, sxy, zero], -1), np.stack([sxy, syy, zero], -1),
         np.stack([zero, zero, szz], -1)], -2,
    )  # fmt: skip
    traction = tensor @ normal
    sigma_n = traction @ normal
    e1 = np.cross(normal, [0.0, 0.0, 1.0] if abs(normal[2]) < 0.9 else [1.0, 0.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(normal, e1)
    return sigma_n, np.stack([traction @ e1, traction @ e2], -1)


@pytest.mark.parametrize(
    "methods, in_plane",
    [(("swt",), False), (("swt", "findley"), False), (("swt", "mwcm"), True),
     (("stress_life", "strain_life"), False)],
)  # fmt: skip
def test_criteria_without_shear_report_their_planes_stresses(methods, in_plane):
    """SWT, stress and strain life search without the shear; their results still carry the
    critical plane's shear amplitude (minimum circle of the shear path) and normal stresses."""
    s = random_history(13, n_points=5)
    search = PlaneSearch(in_plane_only=in_plane)
    results = critical_plane_parameters(s, methods=methods, search=search, **KW)
    for name in methods:
        r = results[name]
        for p in range(s.shape[1]):
            sigma_n, shear = plane_stresses_by_hand(s[:, p], r.normal[p])
            tau = brute_force_radius(shear)
            assert tau > 0.1  # these histories shear the critical planes (0.48 to 69 MPa)
            assert r.shear_stress_amplitude[p] == pytest.approx(tau, rel=1e-9)
            assert r.shear_strain_amplitude[p] == pytest.approx(tau / G, rel=1e-9)
            assert r.normal_stress_max[p] == pytest.approx(sigma_n.max(), rel=1e-12, abs=1e-9)
            amplitude, mean = np.ptp(sigma_n) / 2, (sigma_n.max() + sigma_n.min()) / 2
            assert r.normal_stress_amplitude[p] == pytest.approx(amplitude, rel=1e-12)
            assert r.normal_stress_mean[p] == pytest.approx(mean, rel=1e-12, abs=1e-9)


def test_circle_of_nearly_equal_points_far_from_the_origin():
    """Two shear points 2.4e-9 MPa apart at 29 MPa (a plane whose shear barely moves): the
    distances' round-off (~1e-14 MPa) exceeds the circle's own slack, which once made the
    iteration run out of rounds ('did not converge'); the circle is the pair's half distance."""
    from fretbem.fatigue.mcc import minimum_circumscribed_circle_xy

    x = np.array([[-1.3554238596245625e-15], [1.0434966352127865e-15]])
    y = np.array([[-29.222977473699515], [-29.222977471320252]])
    _, _, radius = minimum_circumscribed_circle_xy(x, y)
    assert radius[0] == pytest.approx(0.5 * abs(y[1, 0] - y[0, 0]), rel=1e-6)


def tilted_history(n=40, seed=11):
    """Random non-proportional histories with an independent sigma_zz (planes tilted)."""
    rng = np.random.default_rng(seed)
    t = np.linspace(0.0, 2 * np.pi, 9)
    a, b = rng.normal(size=(n, 4)) * 100, rng.normal(size=(n, 4)) * 60
    s = a[None] * np.sin(t)[:, None, None] + b[None] * np.cos(3 * t)[:, None, None]
    return s + rng.normal(size=(1, n, 4)) * 50


def test_normal_amplitudes_are_largest_on_the_in_plane_row_or_normal_to_z():
    """sigma_n = szz + sin^2 psi (sigma_ee - szz) at every step: the normal stress and strain
    amplitudes are convex in sin^2 psi, largest at psi = 0 or 90 degrees in every column
    (why the strain-life and uncorrected stress-life searches skip the tilted planes)."""
    stress = tilted_history()
    theta, psi = np.meshgrid(np.deg2rad(np.arange(0.0, 180.0, 3.0)), np.deg2rad(np.arange(0, 91)))
    q = plane_quantities(stress, projection(theta.ravel(), psi.ravel()), E, NU)
    shape = (stress.shape[1], *psi.shape)  # (P, psi, theta)
    for amplitude in (
        0.5 * (q["normal_stress_max"] - q["normal_stress_min"]),
        q["normal_strain_amplitude"],
    ):
        a = amplitude.reshape(shape)
        ends = np.maximum(a[:, 0], a[:, -1])  # psi = 0 and 90 degrees
        assert np.all(a[:, 1:-1].max(axis=1) <= ends * (1.0 + 1e-12))
        assert np.any(a[:, 1:-1].max(axis=1) > 0.9 * ends)  # not trivially small inside


@pytest.mark.parametrize("compiled", [False, True], ids=["numpy", "compiled"])
def test_convex_criteria_take_their_3d_maximum_in_plane_or_normal_to_z(compiled):
    """strain_life and stress_life without a correction, searched in 3D: the best of the
    in-plane family (a 0.01 degree scan) and the plane normal to z, which the search reaches;
    the other criteria still find tilted planes on these histories."""
    if compiled:
        pytest.importorskip("numba")
    stress = tilted_history()
    kw = {"E": E, "nu": NU, "findley_k": 0.3, "fatemi_socie_k": 0.5, "yield_strength": 941.8}
    res = critical_plane_parameters(
        stress, methods=("strain_life", "stress_life", "findley"),
        search=PlaneSearch(compiled=compiled), **kw,
    )  # fmt: skip
    scan, _ = in_plane_scan(stress, step_deg=0.01, **kw)
    zz = stress[..., 3]
    tr = stress[..., 0] + stress[..., 1] + zz
    en = ((1.0 + NU) * zz - NU * tr) / E
    normal_to_z = {
        "stress_life": 0.5 * (zz.max(axis=0) - zz.min(axis=0)),
        "strain_life": 0.5 * (en.max(axis=0) - en.min(axis=0)),
    }
    for name, z_value in normal_to_z.items():
        best = np.maximum(scan[name], z_value)
        value = res[name].value
        # measured: 7.2e-4 short at one point (strain life: a second in-plane maximum of
        # nearly equal height, the search's documented limit), 1.4e-16 at the others; up to
        # 1.2e-8 above the scan, whose 0.01 degree steps miss the top of the maximum
        assert np.all(value <= best * (1.0 + 3e-8)), name
        assert np.all(value >= best * (1.0 - 1e-3)), name
        assert np.mean(value >= best * (1.0 - 1e-9)) >= 0.95, name
        tilt = res[name].normal_tilt_deg
        assert np.all(np.isclose(tilt, 0.0, atol=1e-9) | np.isclose(tilt, 90.0, atol=1e-9))
        assert np.any(z_value > scan[name]) and np.any(z_value < scan[name])
    assert np.any(np.abs(res["findley"].normal_tilt_deg) > 1.0)


def _contact_cycle(tangential_ratio, bulk, n, seed):
    from fretbem.fatigue import CattaneoMindlinCycle, last_full_reversal

    cm = CattaneoMindlinCycle(a=0.5, p0=300.0, f=0.6, tangential_ratio=tangential_ratio,
                              sigma_bulk_max=bulk, nu=0.342, steps_per_branch=2)  # fmt: skip
    rng = np.random.default_rng(seed)
    points = np.stack([rng.uniform(-0.75, 0.75, n), rng.uniform(0.0, 0.5, n)], axis=1)
    return cm.stress_at(points)[last_full_reversal(cm.driver)]


@pytest.mark.parametrize(
    ("tangential_ratio", "bulk", "n"), [(0.3, 0.0, 40), (0.5, 80.0, 25), (0.8, 150.0, 40)]
)
def test_default_3d_grid_against_a_dense_search(tangential_ratio, bulk, n):
    """The default 3D search (psi rows 90 and 45 degrees, three levels) against a search ten
    times finer (0.5 x 1 degree, ten levels) on fretting-contact cycles at three loads: each
    point's value at most 1e-4 of the largest value further below than the former 5 x 10
    degree, five-level search's (both up to 8e-4 below for Findley, where they refine a
    second local maximum; the three levels leave it up to 3.2e-5 further, SWT 7e-10, MWCM
    7e-15), the hot spot's within 1e-6 (measured 3.1e-7, Fatemi-Socie)."""
    stress = _contact_cycle(tangential_ratio, bulk, n, 11)
    kw = {**KW, "E": 116000.0, "nu": 0.342, "yield_strength": 941.8}
    dense = PlaneSearch(theta_step_deg=0.5, psi_step_deg=1.0, refine_levels=10, compiled=True)
    former = PlaneSearch(psi_step_deg=10.0, refine_levels=5, compiled=True)
    ref = critical_plane_parameters(stress, search=dense, **kw)
    old = critical_plane_parameters(stress, search=former, **kw)
    new = critical_plane_parameters(stress, search=PlaneSearch(compiled=True), **kw)
    for method, r in ref.items():
        scale = np.abs(r.value).max()
        short_new = (r.value - new[method].value) / scale
        short_old = (r.value - old[method].value) / scale
        assert np.all(short_new <= np.maximum(short_old, 0.0) + 1e-4), method
        assert (r.value.max() - new[method].value.max()) / scale <= 1e-6, method
