"""Bulk stress beyond the Nowell-Hills limit: fretbem against the independent half-plane reference.

Page: docs/verification/bulk_beyond_limit.py. Past sigma_B = 4 f p0 (1 - sqrt(1 - Q/(f P)))
the slip at one edge of the contact reverses and no closed form exists (Andresen, Hills,
Barber and Vazquez 2019, arXiv 1908.07939; Andresen et al. 2021, arXiv 2103.15647: explicit
solutions stop there). The reference :class:`fretbem.verification.dissimilar.DissimilarCylinders`
(its own discretisation and solver) is first checked against Nowell-Hills inside the limit,
then fretbem's half-plane rig against it beyond. fretbem's loading block is rigid and does
not rotate, so the moment / tilted-pad cases of those papers are not covered.

Rig (as tests/validation/test_rig.py): R = 50 mm, E = 115 GPa, nu = 0.3, f = 0.6,
P = 120 N/mm, Q = 0.4 f P with sigma_B in 32 increments, then -Q, -sigma_B in 32.
"""

import functools

import numpy as np
import pytest

from fretbem.scenes.builder import build
from fretbem.scenes.spec import scene_from_dict
from fretbem.simulation import run
from fretbem.verification.dissimilar import DissimilarCylinders
from fretbem.verification.nowell_hills import NowellHills

F, P, E, NU, R = 0.6, 120.0, 115000.0, 0.3, 50.0
Q = 0.4 * F * P
MODEL = DissimilarCylinders(R, E, NU, E, NU, F)
HERTZ = MODEL.hertz(P)
A, P0 = HERTZ.half_width, HERTZ.peak_pressure
LIMIT = NowellHills(HERTZ, F).limit(Q)
PAGE = "bulk_beyond_limit"


@functools.cache
def reference(fraction: float, cells: int = 400):
    sigma = fraction * LIMIT
    history = [(P, 0.0, 0.0), (P, Q, sigma), (P, -Q, -sigma)]
    return MODEL.solve(history, cells=cells, increments=[1, 32, 32])


def rig(fraction: float, pairs: int = 61):
    sigma = fraction * LIMIT
    data = {
        "pad": {"radius": R, "width": 10.0, "height": 10.0, "model": "half-plane"},
        "specimen": {"shape": "flat", "length": 40.0, "thickness": 13.0, "model": "half-plane"},
        "material": {"E": E, "nu": NU},
        "contact": {"friction": F, "pairs": pairs, "estimate": False},
        "load": {"steps": ["A", "B", "C"], "P": P, "Q": [0.0, Q, -Q],
                 "bulk": [0.0, sigma, -sigma], "increments": [1, 32, 32]},
    }  # fmt: skip
    simulation, _ = build(scene_from_dict(data))
    return run(simulation)


def rms_inside(x, values) -> float:
    inside = np.abs(x) < A
    return float(np.sqrt(np.mean(values[inside] ** 2)))


@pytest.mark.parametrize("fraction", [0.5, 0.8])
def test_reference_reproduces_nowell_hills(fraction, record):
    """Inside the limit the reference gives the Nowell-Hills shear at Q (measured RMS 0.11 %
    of f p0 at 0.8 of the limit, 400 cells) and its stick zone moves the closed form's way."""
    state = reference(fraction)[1]
    closed = NowellHills(HERTZ, F).shear_traction(state.x, [0.0, Q], [0.0, fraction * LIMIT])
    error = rms_inside(state.x, state.shear - closed) / (F * P0)
    assert record(f"bulk stress {fraction:g} x Nowell-Hills limit: reference vs closed form",
                  "q RMS difference / f p0", error, 0.005, page=PAGE)  # fmt: skip


def _reversed(step) -> bool:
    """Whether the slip zones carry shear of both signs (slip reversed at one edge)."""
    slip = step.states == 2
    return bool(np.any(step.shear[slip] > 0) and np.any(step.shear[slip] < 0))


@pytest.mark.parametrize("fraction", [0.8, 1.5, 2.5])
def test_rig_matches_reference_beyond_the_limit(fraction, record):
    """fretbem (half-plane bodies, nurbs, 61 pairs) against the reference (400 cells) at
    (Q, sigma_B) and (-Q, -sigma_B): measured q RMS 0.23, 0.43, 0.39 % of f p0 at B; slip
    reverses at one edge beyond the limit in both, never inside it."""
    result = rig(fraction)
    states = reference(fraction)
    case = f"bulk stress {fraction:g} x Nowell-Hills limit (half-plane nurbs 61)"
    for step, ref in zip(result.steps[1:], states[1:], strict=True):
        q = np.interp(step.x, ref.x, ref.shear)
        error = rms_inside(step.x, step.shear - q) / (F * P0)
        assert record(case, f"q RMS difference / f p0 at step {step.name}", error, 0.007,
                      page=PAGE)  # fmt: skip
        stick, ref_stick = step.x[step.states == 1], ref.x[ref.states == 1]
        edges = max(abs(stick.min() - ref_stick.min()), abs(stick.max() - ref_stick.max())) / A
        assert record(case, f"stick-zone edge difference / a at step {step.name}", edges, 0.05,
                      page=PAGE)  # fmt: skip
        assert _reversed(step) == (fraction > 1.0) == _reversed(ref), step.name
