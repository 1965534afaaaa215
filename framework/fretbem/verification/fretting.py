"""Closed forms of fretting slip and dissipated energy for elastically similar cylinders (2D).

Under Cattaneo loading to Q (|Q| < f P) the stick zone is |x| < c, c = a sqrt(1 - Q / (f P)),
and the slip in c < |x| < a is the Hertz gap function of half-width c times f::

    s(x) = (f / (2 R')) [|x| sqrt(x^2 - c^2) - c^2 ln((|x| + sqrt(x^2 - c^2)) / c)]

(R' the effective radius, a^2 = 4 P R' / (pi E*)). Under fully reversed +-Q* the slip range
is 2 s(x), so the slip amplitude is s(x), and the energy dissipated per cycle (per unit
thickness) is W = 4 f integral p s dx = (32 f^2 P^2 / (pi^2 E*)) I(c / a) with

    I(k) = integral_k^1 sqrt(1 - t^2) [t sqrt(t^2 - k^2) - k^2 ln((t + sqrt(t^2 - k^2)) / k)] dt,

I(0) = pi / 16, so W -> 2 f^2 P^2 / (pi E*) at the onset of gross slip, and for small loads
W ~ 2 Q*^3 / (3 pi f P E*). docs/explanation/fretting.rst derives them.
"""

from __future__ import annotations

import math

import numpy as np

from .closed_forms import HertzLineContact


def stick_ratio(load_ratio: float) -> float:
    """c / a = sqrt(1 - Q* / (f P)) for 0 <= Q* / (f P) <= 1."""
    if not 0.0 <= load_ratio <= 1.0:
        raise ValueError(f"Q* / (f P) must lie in [0, 1], got {load_ratio!r}")
    return math.sqrt(1.0 - load_ratio)


def cattaneo_slip(hertz: HertzLineContact, friction: float, stick: float, x) -> np.ndarray:
    """Slip s(x) of the Cattaneo solution with stick half-width ``stick`` (= c), 0 inside the
    stick zone and NaN outside the contact (|x| > a)."""
    x = np.abs(np.asarray(x, dtype=float))
    a, c = hertz.half_width, float(stick)
    out = np.zeros_like(x)
    slip = (x > c) & (x <= a)
    xs = x[slip]
    root = np.sqrt(xs**2 - c**2)
    if c > 0:
        out[slip] = xs * root - c**2 * np.log((xs + root) / c)
    else:
        out[slip] = xs**2
    out *= friction / (2.0 * hertz.effective_radius)
    out[x > a] = np.nan
    return out


def energy_integral(k: float) -> float:
    """I(k) of the module docstring (adaptive quadrature; I(0) = pi / 16)."""
    from scipy.integrate import quad

    if not 0.0 <= k <= 1.0:
        raise ValueError(f"k = c / a must lie in [0, 1], got {k!r}")
    if k == 0.0:
        return math.pi / 16.0

    def integrand(t: float) -> float:
        root = math.sqrt(max(t * t - k * k, 0.0))
        return math.sqrt(max(1.0 - t * t, 0.0)) * (t * root - k * k * math.log((t + root) / k))

    return float(quad(integrand, k, 1.0, limit=200, epsabs=0.0, epsrel=1e-12)[0])


def cycle_energy(hertz: HertzLineContact, friction: float, amplitude: float) -> float:
    """W: energy dissipated per cycle of fully reversed +-Q* (= ``amplitude``), partial slip."""
    load = hertz.load
    k = stick_ratio(abs(amplitude) / (friction * load))
    return (
        32.0 * friction**2 * load**2 / (math.pi**2 * hertz.effective_modulus) * energy_integral(k)
    )


def small_load_energy(hertz: HertzLineContact, friction: float, amplitude: float) -> float:
    """The small-load limit of W: 2 Q*^3 / (3 pi f P E*)."""
    return (
        2.0
        * abs(amplitude) ** 3
        / (3.0 * math.pi * friction * hertz.load * hertz.effective_modulus)
    )


def onset_energy(hertz: HertzLineContact, friction: float) -> float:
    """W at the onset of gross slip (c = 0): 2 f^2 P^2 / (pi E*)."""
    return 2.0 * friction**2 * hertz.load**2 / (math.pi * hertz.effective_modulus)


def half_plane_transition_ratio(hertz: HertzLineContact, datum: float) -> float:
    """The energy ratio A at the partial / gross slip transition of two half-planes whose
    displacements are measured against points at depth ``datum``: 1 / (4 ln(2 d0 / a) + 2).

    delta at the onset (q = f p everywhere) is 2 f P (ln(2 d0 / a) + 1/2) / (pi E*), the
    mean of ln|x| over the Hertz (semicircle) distribution being ln(a / 2) - 1/2."""
    return 1.0 / (4.0 * math.log(2.0 * datum / hertz.half_width) + 2.0)
