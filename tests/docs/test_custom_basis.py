"""The example plugin package (examples/custom_basis): installed, discovered, conforming,
converging — what the element-type tutorial promises."""

from __future__ import annotations

import itertools
import math
import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

from fretbem import registry as bases
from fretbem.basis import Refinement
from fretbem.bem.body import BemBody
from fretbem.conditions import Displacement, Traction
from fretbem.geometry.boundary import Boundary, Segment
from fretbem.geometry.nurbs import NurbsCurve
from fretbem.material import Material
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run
from fretbem.testing.conformance import check_basis


def test_registry_discovers_it(cubic_plugin):
    """bases.available() lists lagrange3 beside the built-in families, from the entry point."""
    families = bases.available()
    assert {"nurbs", "lagrange2", "lagrange3"} <= set(families)
    assert families["lagrange3"] is cubic_plugin
    assert cubic_plugin.__name__ == "CubicLagrangeBasis"
    assert cubic_plugin.__module__.startswith("fretbem_cubic")
    assert "cubic" in bases.describe()["lagrange3"]


@pytest.mark.parametrize("command", ["module", "script"])
def test_fretbem_bases_prints_it(cubic_plugin, command):
    """`fretbem bases` in a fresh process lists lagrange3 with its description."""
    if command == "script":
        script = shutil.which("fretbem")
        if script is None:
            pytest.skip("the fretbem console script is not on PATH")
        argv = [script, "bases"]
    else:
        argv = [sys.executable, "-m", "fretbem.app.cli", "bases"]
    # the plugin sits in a temporary target on this process's sys.path, not installed
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in sys.path if p)}
    done = subprocess.run(argv, capture_output=True, text=True, check=False, timeout=60, env=env)
    assert done.returncode == 0, done.stderr
    lines = {line.split()[0]: line for line in done.stdout.splitlines() if line.strip()}
    assert "lagrange3" in lines and "cubic" in lines["lagrange3"]
    assert {"nurbs", "lagrange2"} <= set(lines)


def test_conformance(cubic_plugin):
    """The same conformance suite the built-in families pass."""
    check_basis(cubic_plugin)


def _lame_error(family, elements: int) -> float:
    """Largest relative error of the radial displacement on the Lamé cylinder's outer arc."""
    a, b, p, E, nu = 1.0, 2.0, 10.0, 1000.0, 0.3
    boundary = Boundary(
        [
            Segment("bottom", NurbsCurve.line([a, 0], [b, 0])),
            Segment("outer", NurbsCurve.arc([0, 0], b, 0, math.pi / 2)),
            Segment("left", NurbsCurve.line([0, b], [0, a])),
            Segment("inner", NurbsCurve.arc([0, 0], a, math.pi / 2, 0)),
        ]
    )

    def radial(k):
        return lambda x: p * x[:, k] / np.linalg.norm(x, axis=1)

    body = BemBody(
        boundary,
        Material(E, nu),
        [
            Displacement("bottom", x=None, y=0.0),
            Displacement("left", x=0.0, y=None),
            Traction("inner", x=radial(0), y=radial(1)),
        ],
        basis=family,
        refinement={tag: Refinement(elements) for tag in boundary.tags},
    )
    solution = body.solve()
    s = np.linspace(0.0, 1.0, 201)
    points = solution.points(1, s)
    radius = np.linalg.norm(points, axis=1)
    u_r = np.sum(solution.displacement(1, s) * points / radius[:, None], axis=1)
    exact = (1 + nu) / E * a**2 * p / (b**2 - a**2) * ((1 - 2 * nu) * b + b)
    return float(np.abs(u_r - exact).max() / exact)


def test_lame_converges(cubic_plugin):
    """By name, on the Lamé cylinder: the error falls at a cubic family's rate (measured
    about 5: 5.9e-3, 1.4e-4, 6.3e-6 at 2, 4, 8 elements per segment)."""
    levels = (2, 4, 8)
    errors = [_lame_error("lagrange3", n) for n in levels]
    assert all(fine < coarse for coarse, fine in itertools.pairwise(errors))
    rate = -np.polyfit(np.log(levels), np.log(errors), 1)[0]
    assert rate > 3.5, (errors, rate)
    assert errors[-1] < 1e-4


def test_reference_scene_converges(cubic_plugin):
    """On the reference scene (pairs = 3 k + 1) the step-C errors fall with refinement
    (measured: e_q L2 3.2 % -> 1.4 %, e_p L2 2.4 % -> 1.1 % from 31 to 61 pairs)."""
    coarse, fine = (run(cattaneo_mindlin(basis="lagrange3", pairs=n))["C"].errors for n in (31, 61))
    assert fine["e_q_l2"] < coarse["e_q_l2"] < 0.05
    assert fine["e_p_l2"] < coarse["e_p_l2"]
    assert fine["e_q_l2"] < 0.02
