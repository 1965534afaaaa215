"""The quadrature reference for tilted contacts against the closed forms it must reproduce."""

import numpy as np
import pytest

from fretbem.verification.closed_forms import HertzLineContact, effective_modulus
from fretbem.verification.rounded_flat import RoundedFlatPunch
from fretbem.verification.tilted_contact import TiltedContact

E_STAR = effective_modulus(73400.0, 0.33, 73400.0, 0.33)


def test_tilted_cylinder_is_hertz_about_minus_theta_r():
    """The circular profile tilted by theta: Hertz about d = -theta R (to the circle's
    departure from the parabola, 1.4e-4 of p0), M = P theta R."""
    radius, load, theta = 70.0, 100.0, 2e-3
    contact = TiltedContact(lambda x: x / np.sqrt(radius**2 - x**2), E_STAR)
    hertz = HertzLineContact(load, radius, E_STAR)
    x = np.linspace(-0.8, 0.8, 161)
    p = contact.pressure(x, load, theta, (-0.6, 0.3))
    assert np.abs(p - hertz.pressure(x + theta * radius)).max() < 3e-4 * hertz.peak_pressure
    e1, e2 = contact.edges(load, theta, (-0.6, 0.3))
    assert 0.5 * (e1 + e2) == pytest.approx(-theta * radius, abs=1e-4)
    assert contact.moment(load, theta, (e1, e2)) == pytest.approx(load * theta * radius, rel=1e-4)


def test_untilted_rounded_flat_is_the_closed_form():
    """b/a = 0.5: pressure and Ciavarella-Jager shear equal the closed form's (1.6e-4, the
    exact fillet circles against the closed form's parabolas)."""
    flat, edge, friction = 0.3, 20.0, 0.3
    punch = RoundedFlatPunch(flat, edge, E_STAR, friction)

    def slope(x):
        beyond = np.maximum(np.abs(x) - flat, 0.0)
        return np.sign(x) * beyond / np.sqrt(edge**2 - beyond**2)

    contact = TiltedContact(slope, E_STAR, friction)
    load = punch.load(0.6)
    x = np.linspace(-0.7, 0.7, 141)
    peak = punch.pressure(x, 0.6).max()
    assert np.abs(contact.pressure(x, load, 0.0, (-0.6, 0.6)) - punch.pressure(x, 0.6)).max() < (
        3e-4 * peak
    )
    q = contact.shear(x, load, 0.5 * friction * load, 0.0, (-0.6, 0.6))
    assert np.abs(q - punch.shear(x, load, 0.5 * friction * load)).max() < 3e-4 * friction * peak
