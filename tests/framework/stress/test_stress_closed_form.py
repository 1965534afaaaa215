"""Closed-form contact stresses: against direct Flamant integration, equilibrium, surface."""

import numpy as np
import pytest

from fretbem.stress import closed_form as cf
from fretbem.stress.errors import StressInputError


def _flamant_integral(x, z, a, density, centre=0.0, normal=True):
    """Integrate the Flamant line load over an elliptical density on |s - centre| < a
    (Gauss-Chebyshev of the second kind: the sqrt(1 - t^2) weight is exact)."""
    n = 20000
    k = np.arange(1, n + 1)
    t = np.cos(k * np.pi / (n + 1))
    weight = density * a * np.pi / (n + 1) * np.sin(k * np.pi / (n + 1)) ** 2
    load = {"normal": 1.0} if normal else {"tangential": 1.0}
    field = cf.flamant_stress(x - (centre + a * t), z, nu=0.3, **load)
    return np.einsum("k,k...->...", weight, field)


POINTS = [(0.3, 0.2), (-1.5, 0.1), (1.2, 0.05), (0.0, 2.0), (-0.9, 0.01), (2.5, 1.0)]


@pytest.mark.parametrize("x, z", POINTS)
def test_mcewen_and_smith_liu_equal_integrated_flamant(x, z):
    a, p0, q0 = 1.3, 2.0, 0.7
    ref_p = cf.elliptical_pressure_stress(x, z, a=a, p0=p0, centre=0.2, nu=0.3)
    ref_q = cf.elliptical_shear_stress(x, z, b=a, q0=q0, centre=0.2, nu=0.3)
    assert np.allclose(_flamant_integral(x, z, a, p0, 0.2), ref_p, atol=1e-11)
    assert np.allclose(_flamant_integral(x, z, a, q0, 0.2, normal=False), ref_q, atol=1e-11)


def test_flamant_cut_equilibrium_signs():
    """Slab between surface and a cut at depth d: int syy dx = -P and int sxy dx = +Q."""
    x = np.linspace(-4000.0, 4000.0, 800001)
    s = cf.flamant_stress(x, 1.0, normal=3.0, tangential=2.0, nu=0.3)
    integral = np.trapezoid(s, x, axis=0)
    assert integral[1] == pytest.approx(-3.0, rel=1e-3)
    assert integral[2] == pytest.approx(2.0, rel=1e-3)


def test_surface_values_and_trailing_edge_peak():
    a, p0, f, c = 0.33, 190.0, 0.3, 0.2
    x = np.array([-0.2, 0.0, 0.25])
    surface = cf.cattaneo_mindlin_stress(x, 0.0, a=a, p0=p0, f=f, c=c, nu=0.3)
    assert np.allclose(surface[:, 1], -p0 * np.sqrt(1 - x**2 / a**2), atol=1e-12)
    assert np.allclose(surface[:, 3], 0.3 * (surface[:, 0] + surface[:, 1]))
    # peak tension at x = -a for a shear in +x: 2 f p0 sqrt(1 - c^2 / a^2)
    peak = cf.surface_sigma_xx(-a, a=a, p0=p0, f=f, c=c)
    assert peak == pytest.approx(2 * f * p0 * np.sqrt(1 - c**2 / a**2), rel=1e-12)
    # bulk stress, stick zone moved away from the peak edge by e (Nowell-Hills peak)
    sb = 60.0
    e = a * sb / (4 * f * p0)
    peak = cf.surface_sigma_xx(-a, a=a, p0=p0, f=f, c=c, e=e, sigma_bulk=sb)
    assert peak == pytest.approx(sb / 2 + 2 * f * p0 * np.sqrt((1 + e / a) ** 2 - (c / a) ** 2))


def test_plane_stress_has_no_szz_and_bulk_enters_szz_in_plane_strain():
    kw = dict(a=1.0, p0=1.0, f=0.2, c=0.5, sigma_bulk=10.0, nu=0.25)
    assert np.all(cf.cattaneo_mindlin_stress(0.1, 0.5, plane_strain=False, **kw)[..., 3] == 0)
    s = cf.cattaneo_mindlin_stress(0.1, 0.5, **kw)
    assert s[3] == pytest.approx(0.25 * (s[0] + s[1]))


def test_bad_inputs_are_named():
    with pytest.raises(StressInputError, match="depth"):
        cf.elliptical_pressure_stress(0.0, -1.0, a=1.0, p0=1.0, nu=0.3)
    with pytest.raises(StressInputError, match="stick zone"):
        cf.cattaneo_mindlin_stress(0.0, 1.0, a=1.0, p0=1.0, f=0.3, c=0.8, e=0.3, nu=0.3)
    with pytest.raises(StressInputError, match="a must"):
        cf.elliptical_pressure_stress(0.0, 1.0, a=0.0, p0=1.0, nu=0.3)
