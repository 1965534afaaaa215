"""A face symmetric about its middle computes half its node integrals and mirrors the rest.

Checked against the full computation (the mirrored rows agree to the round-off of the
face's own symmetry, the computed ones bit for bit), on symmetric faces of both families
(an arc, a line; odd and even node counts), and refused on faces that are not symmetric:
graded to one side, an arc off-centre in parameter, a control point moved by 1e-9.
"""

from __future__ import annotations

import math

import attrs
import numpy as np
import pytest

from fretbem import registry as bases
from fretbem.basis import Refinement
from fretbem.geometry.nurbs import NurbsCurve
from fretbem.halfplane import HalfPlaneSurface, symmetry
from fretbem.material import Material

STEEL = Material(210000.0, 0.3)


def _arc(family: str, elements: int, half_angle: float = 0.3) -> object:
    radius, up = 5.0, math.pi / 2
    curve = NurbsCurve.arc([0.0, -radius], radius, up + half_angle, up - half_angle)
    return bases.get(family).discretise(curve, Refinement(elements=elements))


def _line(family: str, elements: int, reverse: bool = False) -> object:
    ends = ([1.5, 0.2], [-1.0, 0.2]) if reverse else ([-1.0, 0.2], [1.5, 0.2])
    return bases.get(family).discretise(NurbsCurve.line(*ends), Refinement(elements=elements))


def _full(surface: HalfPlaneSurface) -> np.ndarray:
    """The node integrals of every row (no mirroring)."""
    return surface._node_integrals(surface.points[:, 0], surface.face.collocation())


SYMMETRIC = {
    "nurbs arc 9": lambda: _arc("nurbs", 9),
    "nurbs arc 20": lambda: _arc("nurbs", 20),
    "nurbs line 6": lambda: _line("nurbs", 6),
    "nurbs line 8 reversed": lambda: _line("nurbs", 8, reverse=True),
    "lagrange2 arc 10": lambda: _arc("lagrange2", 10),
    "lagrange2 line 7": lambda: _line("lagrange2", 7),
}


@pytest.mark.parametrize("name", SYMMETRIC)
@pytest.mark.parametrize("side", ["lower", "upper"])
def test_symmetric_face_mirrors_half_its_rows(name, side):
    surface = HalfPlaneSurface(SYMMETRIC[name](), STEEL, side, datum=3.0)
    x = surface.points[:, 0]
    n = x.size
    half = symmetry.mirrored_rows(surface.face, x, surface._rule_map)
    assert half == (n + 1) // 2
    full = _full(surface)
    for got, want in zip(surface.traction_blocks, surface._blocks(full[:n], full[n:]),
                         strict=True):  # fmt: skip
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-13 * np.abs(want).max())
    # the first half is the full computation's, bit for bit; the second its mirror
    both = symmetry.mirrored(
        surface._node_integrals(x[:half], tuple(v[:half] for v in surface.face.collocation())), n
    )
    assert np.array_equal(both[:half], full[:half])
    assert np.array_equal(both[n : n + half], full[n : n + half])
    assert np.array_equal(both[half:n], both[: n - half][::-1, ::-1])
    assert np.array_equal(both[n + half :], -both[n : 2 * n - half][::-1, ::-1])


def _moved(basis, by: float):
    """``basis`` with one geometry coefficient moved by ``by`` along x (its curve too)."""
    points = np.array(basis.geometry_coefficients)
    points[1, 0] += by
    return attrs.evolve(basis, geometry_coefficients=points)


ASYMMETRIC = {
    "graded to one end": lambda: bases.get("nurbs").discretise(
        NurbsCurve.line([-1.0, 0.0], [1.0, 0.0]), Refinement.graded(12, 0.0, 3.0)
    ),
    "arc off-centre": lambda: bases.get("nurbs").discretise(
        NurbsCurve.arc([0.4, -5.0], 5.0, math.pi / 2 + 0.3, math.pi / 2 - 0.1),
        Refinement(elements=11),
    ),
    "moved by 1e-9": lambda: _moved(_arc("nurbs", 9), 1e-9),
    "lagrange2 moved by 1e-9": lambda: _moved(_arc("lagrange2", 10), 1e-9),
}


@pytest.mark.parametrize("name", ASYMMETRIC)
def test_asymmetric_face_computes_every_row(name):
    surface = HalfPlaneSurface(ASYMMETRIC[name](), STEEL, "lower", datum=3.0)
    x = surface.points[:, 0]
    assert symmetry.mirrored_rows(surface.face, x, surface._rule_map) is None
    n = x.size
    full = _full(surface)
    for got, want in zip(surface.traction_blocks, surface._blocks(full[:n], full[n:]),
                         strict=True):  # fmt: skip
        assert np.array_equal(got, want)
