"""The contact-side surface level where stress lines start (Body.surface_level)."""

from __future__ import annotations

import numpy as np
import pytest

from fretbem.scenes import cattaneo_mindlin


def _dense_level(body, x, side):
    """The same level from a dense sampling of every segment (brute force)."""
    best = np.full(x.shape, -np.inf if side == "lower" else np.inf)
    t = np.linspace(0.0, 1.0, 100_001)
    for basis in body.segments:
        pts = basis.curve.points(t)
        for k in range(len(x)):
            cross = np.flatnonzero(np.diff(np.sign(pts[:, 0] - x[k])) != 0)
            for c in cross:
                (x0, y0), (x1, y1) = pts[c], pts[c + 1]
                y = y0 + (y1 - y0) * (x[k] - x0) / (x1 - x0)
                best[k] = max(best[k], y) if side == "lower" else min(best[k], y)
    return best


@pytest.mark.parametrize("side", ["lower", "upper"])
def test_surface_level_matches_a_dense_sampling_of_the_curves(side):
    """Batched bisection on the exact curves: the highest (lower body) or lowest (upper body)
    boundary crossing of each vertical line, to 1e-9 mm; +-inf off the body."""
    body = cattaneo_mindlin(pairs=21).pair.side(side)[0]
    x = np.array([-3.0, -1.1, -0.2, 0.0, 0.37, 2.9])
    level = body.surface_level(x, side)
    assert np.allclose(level, _dense_level(body, x, side), rtol=0, atol=1e-9)
    # the faces are cylinders of radius 70 touching at y = 0: y = +-(R - sqrt(R^2 - x^2))
    sign = -1.0 if side == "lower" else 1.0
    assert np.allclose(level, sign * (70.0 - np.sqrt(70.0**2 - x**2)), rtol=0, atol=1e-9)
    far = body.surface_level(np.array([[100.0, 0.0]]), side)  # any shape; off the body
    assert far.shape == (1, 2) and far[0, 0] == (-np.inf if side == "lower" else np.inf)


def test_a_repeated_abscissa_is_found_once_with_the_same_level():
    """A map's grid repeats each x for every depth: the level is found per distinct x and
    equals the level of that x asked alone, bit for bit, in the grid's shape."""
    body = cattaneo_mindlin(pairs=21).pair.side("lower")[0]
    xs = np.array([-1.1, 0.0, 0.37, 100.0])
    grid = np.tile(xs, (5, 1))  # (depth, x)
    level = body.surface_level(grid, "lower")
    alone = np.array([body.surface_level(np.array([x]), "lower")[0] for x in xs])
    assert level.shape == grid.shape and np.array_equal(level, np.tile(alone, (5, 1)))
