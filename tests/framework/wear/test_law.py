"""Wear laws: the two built-in laws, their registration and the conformance check."""

import numpy as np
import pytest

from fretbem import registry
from fretbem.testing import check_wear_law
from fretbem.wear.law import JOULE, ArchardWear, EnergyWear, WearInputError, WearLaw


@pytest.mark.parametrize("law", [ArchardWear(1e-8), EnergyWear(3.55e-4), ArchardWear(0.0)])
def test_built_in_laws_conform(law):
    check_wear_law(law)


def test_laws_are_registered_by_name():
    laws = registry.available("wear_laws")
    assert laws["archard"] is ArchardWear and laws["energy"] is EnergyWear
    assert registry.get("energy", "wear_laws") is EnergyWear


def test_depths_in_stated_units():
    p, q, ds = np.array([100.0, 0.0]), np.array([50.0, 0.0]), np.array([-2e-3, 1e-3])
    # Archard: k [1/MPa] * p [MPa] * |ds| [mm] = mm
    assert np.allclose(ArchardWear(1e-7).depth(p, q, ds), [1e-7 * 100 * 2e-3, 0.0], rtol=1e-15)
    # energy: alpha [mm^3/J] = alpha / 1000 [mm^3/(N mm)]
    assert JOULE == 1000.0
    assert np.allclose(EnergyWear(2e-4).depth(p, q, ds), [2e-7 * 50 * 2e-3, 0.0], rtol=1e-15)


@pytest.mark.parametrize("bad", [-1e-8, float("nan"), float("inf"), True])
def test_bad_coefficients_are_named(bad):
    with pytest.raises(WearInputError, match="coefficient k must be a finite number >= 0"):
        ArchardWear(bad)


def test_check_names_a_broken_law():
    class Negative(WearLaw):
        coefficient_name = "c"
        c = 1.0

        def depth(self, p, q, slip):
            return -np.abs(slip)

    with pytest.raises(AssertionError, match="Negative: depths are >= 0"):
        check_wear_law(Negative())

    class StickWears(WearLaw):
        coefficient_name = "c"
        c = 1.0

        def depth(self, p, q, slip):
            return 1e-9 * np.maximum(p, 0) + np.abs(slip)

    with pytest.raises(AssertionError, match="no wear without slip"):
        check_wear_law(StickWears())
