"""The fretting rig: a cylindrical pad on a flat specimen under P, Q and a bulk stress.

Checked against Nowell-Hills (stick-zone offset e and width c, shear traction) on a
half-plane specimen and on a finite specimen 37 a deep; beyond the validity limit by
equilibrium, the Coulomb cone and refinement; along cycles by the consistency of the
friction memory; with P varying by Hertz at each P. Geometry and loads are our own:
R = 50 mm, E = 115 GPa, nu = 0.3, f = 0.6, P = 120 N/mm, Q = 0.4 f P.
"""

import numpy as np
import pytest

from fretbem.scenes.builder import build, hertz
from fretbem.scenes.spec import scene_from_dict
from fretbem.simulation import run
from fretbem.verification.nowell_hills import NowellHills

F, P, Q = 0.6, 120.0, 0.4 * 0.6 * 120.0
SOLVER = "newton"


def rig(pairs=61, pad="half-plane", specimen="half-plane", load=None, **specimen_keys):
    data = {
        "pad": {"radius": 50.0, "width": 10.0, "height": 10.0, "model": pad},
        "specimen": {"shape": "flat", "length": 40.0, "thickness": 13.0, "model": specimen,
                     **specimen_keys},
        "material": {"E": 115000.0, "nu": 0.3},
        "contact": {"friction": F, "pairs": pairs, "solver": SOLVER},
        "load": load or {"steps": ["A", "B"], "P": P, "Q": [0.0, Q], "bulk": 0.0},
    }  # fmt: skip
    return scene_from_dict(data)


CONTACT = hertz(rig())
A, P0 = CONTACT.half_width, CONTACT.peak_pressure
NH = NowellHills(CONTACT, F)
LIMIT = NH.limit(Q)


def stick_zone(step):
    x = step.x[step.states == 1]
    return x.min(), x.max()


def spacing(step):
    return float(np.max(np.diff(step.x)))


def first_loading(model, pairs=61, fraction=0.8):
    sigma = fraction * LIMIT
    scene = rig(pairs, "half-plane", model,
                {"steps": ["A", "B"], "P": P, "Q": [0.0, Q], "bulk": [0.0, sigma]})  # fmt: skip
    simulation, reason = build(scene)
    assert reason is None and simulation.reference is not None
    return run(simulation), sigma


@pytest.mark.parametrize(
    ("model", "e_q_max", "e_q_l2"),
    [("half-plane", 0.016, 0.0025), ("bem", 0.07, 0.015)],  # measured 1.34/0.18, 5.7/1.24 %
)
def test_nowell_hills_first_loading(model, e_q_max, e_q_l2):
    """Stick zone moved by e = a sigma_B / (4 f p0), width c, shear as the closed form."""
    result, sigma = first_loading(model)
    step = result["B"]
    lo, hi = NH.stick_zone([0.0, Q], [0.0, sigma])
    e, c = 0.5 * (lo + hi), 0.5 * (hi - lo)
    assert e == pytest.approx(A * sigma / (4 * F * P0))
    found_lo, found_hi = stick_zone(step)
    h = spacing(step)
    assert abs(0.5 * (found_lo + found_hi) - e) <= h  # measured 0.002 a / 0.023 a, h = 0.05 a
    assert abs(0.5 * (found_hi - found_lo) - c) <= h
    assert e > 2 * h  # the shift is resolved, not noise
    assert step.errors["e_q_max"] <= e_q_max
    assert step.errors["e_q_l2"] <= e_q_l2
    assert step.resultant == pytest.approx((P, Q), rel=2e-3)


def test_finite_specimen_approaches_the_half_plane():
    """q at first loading: the finite specimen's error falls as it grows (40x13 -> 160x52)."""
    errors = []
    for scale in (1, 2, 4):
        scene = rig(61, "half-plane", "bem",
                    {"steps": ["A", "B"], "P": P, "Q": [0.0, Q], "bulk": [0.0, 0.5 * LIMIT]},
                    length=40.0 * scale, thickness=13.0 * scale)  # fmt: skip
        errors.append(run(build(scene)[0])["B"].errors["e_q_l2"])
    assert errors[0] > errors[1] > errors[2]


def test_beyond_the_limit():
    """sigma_B past the limit: equilibrium, the cone, a reverse-slip zone, refinement."""
    sigma = 1.6 * LIMIT
    load = {"steps": ["A", "B"], "P": P, "Q": [0.0, Q], "bulk": [0.0, sigma]}
    simulation, reason = build(rig(61, load=load))
    assert simulation.reference is None and "leaves the contact" in reason
    fine = run(build(rig(121, load=load))[0])["B"]
    step = run(simulation)["B"]
    assert step.resultant == pytest.approx((P, Q), rel=2e-3)
    assert np.all(np.abs(step.shear) <= F * step.pressure + 1e-9 * F * P0)
    reverse = (step.states == 2) & (np.sign(step.shear) == -np.sign(Q))
    assert reverse.any()  # one edge slips backwards
    coarse = np.interp(fine.x, step.x, step.shear)
    assert np.sqrt(np.mean((coarse - fine.shear) ** 2)) < 0.03 * F * P0


def test_in_phase_cycle_memory():
    """Fully reversed in-phase cycle: -Q mirrors +Q; with a mean bulk stress the cycle shakes
    down (the second and third peaks agree)."""
    k = 0.8 * LIMIT / Q
    steps = ["A", "B", "C", "D", "E", "F", "G", "H"]
    qs = [0.0, Q, 0.0, -Q, 0.0, Q, -Q, Q]
    result = run(build(rig(61, load={"steps": steps, "P": P, "Q": qs,
                                     "bulk": [k * q for q in qs]}))[0])  # fmt: skip
    np.testing.assert_allclose(result["D"].shear, -result["B"].shear, atol=1e-6 * F * P0)
    np.testing.assert_allclose(result["H"].shear, result["F"].shear, atol=1e-6 * F * P0)
    mean = 0.3 * LIMIT
    result = run(build(rig(61, load={"steps": steps, "P": P, "Q": qs,
                                     "bulk": [mean + k * q for q in qs]}))[0])  # fmt: skip
    np.testing.assert_allclose(result["H"].shear, result["F"].shear, atol=1e-6 * F * P0)
    # stick pairs keep their relative tangential displacement between two steps
    both = (result["G"].states == 1) & (result["H"].states == 1)
    assert not both.any() or np.allclose(
        result["G"].tangential_displacement[both], result["H"].tangential_displacement[both]
    )


def test_normal_load_changes_between_steps():
    """Unload P with Q held, then reload: the contact width follows Hertz at each P."""
    loads = [P, P, 0.6 * P, P]
    result = run(build(rig(61, load={"steps": ["A", "B", "C", "D"], "P": loads,
                                     "Q": [0.0, 0.3 * Q, 0.3 * Q, 0.3 * Q]}))[0])  # fmt: skip
    for step, load in zip(result.steps, loads, strict=True):
        width = hertz(rig(), load).half_width
        touching = step.x[step.pressure > 0]
        assert abs(touching.max() - width) <= spacing(step)
        assert abs(-touching.min() - width) <= spacing(step)
        assert step.resultant[0] == pytest.approx(load, rel=2e-3)
