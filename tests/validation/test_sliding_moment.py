"""The pad block's moment M while the pad slides, on a flat track and along an arc.

M is the moment the loading block applies to the pad about the pivot: the point on the
block's line (the pad's top edge; a half-plane pad's datum line) above the pad's
first-contact point, both in the pad's own axes, so the pivot moves and turns with the pad
(counterclockwise positive; a moment about a point of the pad is the same in its axes as
in the global frame). The pad carries nothing else, so M balances the moment of the
contact tractions on it about the same point: checked here against that moment integrated
independently over the pad's face (the node tractions interpolated by the face's own basis,
Gauss quadrature on the exact curve), at every position along the track, and against the
lever arms of a symmetric pad in full sliding (M = h Q - e P: h the pivot's height above
the contact, e the pressure's centre ahead of the pad's axis). Tolerances: measured values
(in the comments) plus a margin.
"""

from __future__ import annotations

import copy
import math
from pathlib import Path

import numpy as np
import pytest
import tomllib

from fretbem.contact import rotation as pad_rotation
from fretbem.scenes.builder import build
from fretbem.scenes.file import scene_from_data
from fretbem.sliding import run_sliding
from fretbem.testing.sliding import traction_moment

ROOT = Path(__file__).resolve().parents[2]


def slide(example: str, pairs: int, a: float, **tables) -> tuple:
    """``examples/<example>`` at ``pairs`` pairs (``tables`` update its tables), pressed,
    slid to 3 a and 6 a and back; the sliding result and its pairs."""
    data = tomllib.loads((ROOT / "examples" / example).read_text())
    for table, values in tables.items():
        data[table].update(values)
    data["contact"]["pairs"] = pairs
    data["load"].update(
        steps=["press", "half", "slide", "back"],
        delta=[0.0, 3 * a, 6 * a, 0.0],
        increments=[1, 6, 6, 12],
    )
    simulation, _ = build(scene_from_data(copy.deepcopy(data)))
    return run_sliding(simulation, note=None)


def rows_of(sliding) -> list[dict]:
    """Per step: M, the tractions' moment, the pivot's height above the contact and the
    pressure's centre ahead of the pad's axis (pad axes), P and Q."""
    out = []
    for step, pair in zip(sliding.steps, sliding.pairs, strict=True):
        moment, force = traction_moment(step, pair)
        problem = pair.condensed()
        points = pad_rotation.in_pad_axes(pair, pair.pairing().points)
        p = step.pressure
        out.append({
            "M": step.moment,
            "tractions": moment,
            "force": force,
            "P": step.normal,
            "Q": step.tangential,
            "h": pad_rotation.pivot(problem)[1] - float(np.sum(points[:, 1] * p) / np.sum(p)),
            "e": float(np.sum(points[:, 0] * p) / np.sum(p)),
            "turn": pair.turn,
        })  # fmt: skip
    return out


def check(rows, *, tractions: float, levers: float, along: float = 1e-3) -> None:
    """M against the tractions' moment within ``tractions`` of h Q, and against h Q - e P
    within ``levers`` of h Q, at every position; equal and opposite slid forth and back,
    the same at 3 a and 6 a within ``along`` of h Q (the pad's axes follow it)."""
    scale = rows[1]["h"] * abs(rows[1]["Q"])
    for row in rows:
        assert math.isfinite(row["M"])
        assert abs(row["M"] - row["tractions"]) < tractions * scale
        assert abs(row["M"] - (row["h"] * row["Q"] - row["e"] * row["P"])) < levers * scale
    assert abs(rows[1]["M"] - rows[2]["M"]) < along * scale
    assert abs(rows[2]["M"] + rows[3]["M"]) < along * scale


#: (example, pairs, Hertz half-width a (mm), table updates): the reference pad on a
#: cylinder and in a groove, a pad 26 mm wide on large bodies, a flat specimen with BEM
#: and with half-plane bodies
LARGE = {"pad": {"width": 26.0}, "specimen": {"width": 40.0, "height": 20.0}}
CASES = {
    "arc": ("gross_sliding_arc.toml", 41, 0.329, {}),
    "arc-large": ("gross_sliding_arc.toml", 31, 0.329, LARGE),
    "groove-large": ("gross_sliding_groove.toml", 31, 0.537, LARGE),
    "flat-bem": ("gross_sliding_bem.toml", 41, 0.465, {}),
    "flat-half-plane": ("gross_sliding.toml", 41, 0.465, {}),
    "arc-lagrange2": ("gross_sliding_arc.toml", 41, 0.329, {"contact": {"basis": "lagrange2"}}),
    "groove": ("gross_sliding_groove.toml", 41, 0.537, {}),
}


@pytest.mark.parametrize(
    ("case", "tractions", "levers"),
    [
        ("arc", 0.003, 0.0025),  # measured 2.2e-3, 1.8e-3
        ("arc-large", 3e-4, 3e-4),  # 1.3e-4, 1.0e-4
        ("groove-large", 3e-4, 3e-4),  # 1.5e-4, 1.3e-4
        ("flat-half-plane", 2e-5, 1e-4),  # 5.5e-6, 3.9e-5
    ],
)
def test_the_blocks_moment_balances_the_contact_tractions(case, tractions, levers):
    """At every position (pressed, slid 3 a and 6 a, back) M about the pad's pivot is minus
    the moment of the contact tractions on the pad, integrated over its face; for the
    symmetric pad in full sliding M = h Q - e P (h = 16.25 mm on BEM pads, the datum's 10 mm
    on a half-plane pad), the same forth and back. The narrow BEM pads differ by 0.22 % of
    h Q: the pad's own equilibrium between its block and its face (0.013 % on a pad four
    times as wide). On a flat track M was off by the slide times P before the pivot moved
    with the pad (580 against -300 N mm/mm slid 2.8 mm and back, half-plane bodies)."""
    example, pairs, a, tables = CASES[case]
    check(rows_of(slide(example, pairs, a, **tables)), tractions=tractions, levers=levers)


@pytest.mark.slow
@pytest.mark.parametrize(
    ("case", "tractions", "levers", "along"),
    [
        ("flat-bem", 0.003, 0.0025, 1e-3),  # measured 2.2e-3, 1.9e-3, 1.5e-4
        ("arc-lagrange2", 0.0015, 0.0018, 1e-3),  # 9.6e-4, 1.2e-3, 3.3e-4
        ("groove", 0.003, 0.0025, 4e-3),  # 2.1e-3, 1.8e-3, 3.1e-3
    ],
)
def test_the_blocks_moment_in_other_families_and_in_a_groove(case, tractions, levers, along):
    """As above; the reference pad in the 14 mm wide groove: M changes by 0.22 % of h Q
    between 3 a and 6 a along it and differs by 0.31 % from minus M back at the start (its
    pressure's centre 0.168, 0.157 and -0.172 mm ahead: the finite groove's compliance
    changes along the track)."""
    example, pairs, a, tables = CASES[case]
    rows = rows_of(slide(example, pairs, a, **tables))
    check(rows, tractions=tractions, levers=levers, along=along)
