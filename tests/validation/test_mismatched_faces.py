"""Pad and specimen discretised independently, against Mindlin-Deresiewicz.

The reference scene from a scene table with per-face keys ([pad], [specimen] over
[contact]) and node-to-segment pairing: 97 against 61 pairs either way round, and mixed
families. Each run's max errors (e_p, e_q over the cycle) must lie within the fixed mode's
errors of the two faces' own discretisations (node-to-node runs of each face's family and
count), with a margin of 10 %: the largest ratio measured is 1.064 (e_p, lagrange2 97 on
nurbs 61 at P = 160), every other below 1.0 (tables in docs/explanation/pairing.rst).
"""

from __future__ import annotations

import functools

import pytest

from fretbem.scenes.builder import build
from fretbem.scenes.file import scene_from_data
from fretbem.simulation import run

MARGIN = 1.10
LOADS = {100.0: 18.0, 60.0: 11.0, 160.0: 30.0}


def _data(P: float, pad: tuple[str, int], specimen: tuple[str, int], pairing: str) -> dict:
    Q = LOADS[P]
    return {
        "pad": {"shape": "cylinder", "basis": pad[0], "pairs": pad[1]},
        "specimen": {"shape": "cylinder", "basis": specimen[0], "pairs": specimen[1]},
        "contact": {"pairing": pairing},
        "load": {"P": P, "Q": [0.0, Q, 0.0, -Q, 0.0]},
    }


@functools.cache
def errors(P: float, pad: tuple[str, int], specimen: tuple[str, int], pairing: str) -> tuple:
    """(e_p max, e_q max) over the cycle of the scene."""
    simulation, _ = build(scene_from_data(_data(P, pad, specimen, pairing)))
    result = run(simulation)
    return tuple(max(s.errors[k] for s in result.steps) for k in ("e_p_max", "e_q_max"))


def fixed_mode_bound(P: float, pad, specimen) -> tuple[float, float]:
    """The larger of the two faces' own node-to-node errors, each component."""
    own = [errors(P, face, face, "node-to-node") for face in (pad, specimen)]
    return tuple(max(o[k] for o in own) for k in range(2))


CASES = [
    (("nurbs", 97), ("nurbs", 61)),
    (("nurbs", 61), ("nurbs", 97)),
    (("lagrange2", 61), ("nurbs", 61)),
    (("nurbs", 61), ("lagrange2", 61)),
    (("lagrange2", 97), ("nurbs", 61)),
]


def _check(P, pad, specimen):
    e_p, e_q = errors(P, pad, specimen, "node-to-segment")
    b_p, b_q = fixed_mode_bound(P, pad, specimen)
    assert e_p <= MARGIN * b_p, (e_p, b_p)
    assert e_q <= MARGIN * b_q, (e_q, b_q)


@pytest.mark.parametrize("P", sorted(LOADS))
@pytest.mark.parametrize(("pad", "specimen"), CASES)
def test_every_case_and_load_within_the_fixed_mode(P, pad, specimen):
    """Every pair of faces at P = 60, 100, 160 N/mm (at P = 100: 97 on 61 nurbs e_p 0.64 %,
    e_q 3.97 % against 0.92 / 4.00 %; a lagrange2 pad on a nurbs specimen 0.99 / 3.24 %
    against 2.20 / 7.23 %)."""
    _check(P, pad, specimen)
