"""Fretting cycles against the closed forms: slip, energy, gross slip, transition (issue 22).

Every tolerance is the largest value measured over the cases here (in the comments) with
a margin; the BEM bodies (6.5 mm wide, 16.25 mm high cylinders, clamped) differ from the
half-plane theory by their finite size (docs/explanation/fretting.rst).
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest

from fretbem.fretting import Waveform, analyse
from fretbem.fretting.cycles import onset_displacement
from fretbem.scenes.builder import build
from fretbem.scenes.spec import scene_from_dict
from fretbem.simulation import Simulation, run
from fretbem.verification import fretting as cf
from fretbem.verification.closed_forms import SlidingPath

F, P = 0.3, 100.0
CASES = [("half-plane", "nurbs", 61), ("half-plane", "lagrange2", 121), ("bem", "nurbs", 61),
         ("bem", "lagrange2", 121)]  # fmt: skip
#: measured maxima over CASES and loads (half-plane, BEM)
SLIP = {"half-plane": 0.01, "bem": 0.02}  # 0.0033, 0.0068 of the largest slip
ENERGY = {"half-plane": 0.015, "bem": 0.03}  # 0.0058, 0.0174 of W
LOOP = {"half-plane": 2e-3, "bem": 5e-3}  # 6.6e-4, 2.1e-3 of E_d
PLATEAU = {"half-plane": 1e-12, "bem": 1e-3}  # 7e-16, 4.4e-4 of f P


@functools.cache
def simulation(model: str, basis: str, pairs: int) -> Simulation:
    data = {
        "pad": {"model": model},
        "specimen": {"model": model},
        "contact": {"pairs": pairs, "basis": basis, "zone": 1.2, "friction": F},
        "load": {"steps": ["A", "B"], "P": P, "Q": [0.0, 18.0]},
    }
    sim, _ = build(scene_from_dict(data))
    sim.prepare()
    return sim


@functools.cache
def cycle(model, basis, pairs, amplitude, control, increments=40):
    """The second (stabilised) cycle of a fully reversed history, and its analysis."""
    base = simulation(model, basis, pairs)
    waveform = Waveform(amplitude, P, control=control, cycles=2, increments=increments)
    sim = Simulation(base.pair, waveform.steps(), law=base.law,
                     reference=SlidingPath(base.reference))  # fmt: skip
    result = run(sim)
    analysis = analyse(result)
    return result, analysis, analysis.cycles[-1]


def test_energy_integral_values_and_limits():
    """I(k) against the tabulated values (3 digits), I(0) = pi/16, W's small-load limit."""
    table = {0.1: 6.89e-5, 0.2: 5.83e-4, 0.3: 2.09e-3, 0.5: 1.116e-2, 0.7: 3.68e-2, 0.9: 1.04e-1}
    for ratio, value in table.items():
        assert cf.energy_integral(cf.stick_ratio(ratio)) == pytest.approx(value, rel=2e-3)
    assert cf.energy_integral(1e-9) == pytest.approx(math.pi / 16, rel=1e-6)
    hertz = simulation("half-plane", "nurbs", 61).reference.hertz
    for ratio in (1e-3, 1e-2):
        small = cf.small_load_energy(hertz, F, ratio * F * P)
        assert cf.cycle_energy(hertz, F, ratio * F * P) == pytest.approx(small, rel=ratio)
    assert cf.cycle_energy(hertz, F, F * P) == pytest.approx(cf.onset_energy(hertz, F))


@pytest.mark.parametrize(("model", "basis", "pairs"), CASES)
@pytest.mark.parametrize("ratio", [0.3, 0.6, 0.9])
def test_partial_slip_cycle_against_cattaneo_and_energy(model, basis, pairs, ratio):
    """Slip amplitude = Cattaneo's s(x), E_d = W(c/a), E_d = loop area = sum of densities."""
    _, _, c = cycle(model, basis, pairs, ratio * F * P, "force")
    hertz = simulation(model, basis, pairs).reference.hertz
    assert c.regime == "partial slip"
    assert c.tangential_amplitude == pytest.approx(ratio * F * P, rel=1e-12)
    exact = cf.cattaneo_slip(hertz, F, cf.stick_ratio(ratio) * hertz.half_width, c.x)
    inside = np.isfinite(exact)
    error = np.max(np.abs(c.slip_amplitude[inside] - exact[inside])) / np.max(exact[inside])
    assert error < SLIP[model]
    assert c.dissipated_energy == pytest.approx(cf.cycle_energy(hertz, F, ratio * F * P),
                                                rel=ENERGY[model])  # fmt: skip
    assert c.loop_area == pytest.approx(c.dissipated_energy, rel=LOOP[model])
    weights = analyse(cycle(model, basis, pairs, ratio * F * P, "force")[0]).weights
    assert weights @ c.energy_density == pytest.approx(c.dissipated_energy, rel=1e-12)
    assert np.all(c.energy_density >= -1e-12 * np.max(c.energy_density))
    assert 0 < c.energy_ratio < analyse(cycle(model, basis, pairs, ratio * F * P, "force")[0]
                                        ).transition_ratio  # fmt: skip


@pytest.mark.parametrize(("model", "basis", "pairs"), CASES)
def test_gross_slip_plateau_and_energy(model, basis, pairs):
    """Beyond the onset delta_t: Q = +-f P plateaus; E_d = 4 f P delta_s + W(0), delta_s the
    sliding amplitude (half the slip per stroke at the centre). Measured (E_d - 4 f P
    delta_s) / W(0): 0.995, 0.973 (half-plane), 0.960, 0.930 (BEM) at 1.02 and 2 delta_t."""
    base = simulation(model, basis, pairs)
    result, _, _ = cycle(model, basis, pairs, 0.5 * F * P, "force")
    onset = onset_displacement(base.prepare(), result.steps[0], F)
    hertz = base.reference.hertz
    for factor in (1.02, 2.0):
        result, analysis, c = cycle(model, basis, pairs, factor * onset, "displacement")
        assert c.regime == "gross slip"
        sliding = [i for s in result.steps for i in s.increments if not np.any(i.states == 1)]
        assert sliding
        for inc in sliding:
            assert abs(inc.tangential) == pytest.approx(F * inc.normal, rel=PLATEAU[model])
        assert c.tangential_amplitude == pytest.approx(F * P, rel=PLATEAU[model])
        centre = int(np.argmin(np.abs(c.x)))
        sliding_part = 4 * F * P * c.slip_amplitude[centre]
        transition = (c.dissipated_energy - sliding_part) / cf.onset_energy(hertz, F)
        assert transition == pytest.approx(1.0, abs=0.05 if model == "half-plane" else 0.1)
        assert c.loop_area == pytest.approx(c.dissipated_energy, rel=LOOP[model])
        assert c.energy_ratio > analysis.transition_ratio


@pytest.mark.parametrize(("model", "basis", "pairs"), CASES)
def test_transition_same_under_force_and_displacement(model, basis, pairs):
    """Displacement control: partial slip at 0.98 delta_t, gross slip at 1.02 delta_t, the
    energy ratio A crossing the transition value between them; force control at Q* = 0.999
    f P: partial slip with delta* just below delta_t (measured 0.9982-0.9994)."""
    base = simulation(model, basis, pairs)
    result, analysis, forced = cycle(model, basis, pairs, 0.999 * F * P, "force")
    onset = onset_displacement(base.prepare(), result.steps[0], F)
    assert forced.regime == "partial slip"
    assert 0.99 < forced.delta_amplitude / onset < 1.0
    _, _, below = cycle(model, basis, pairs, 0.98 * onset, "displacement")
    _, _, above = cycle(model, basis, pairs, 1.02 * onset, "displacement")
    assert below.regime == "partial slip" and above.regime == "gross slip"
    assert below.tangential_amplitude < F * P * (1 - 1e-3)
    assert below.energy_ratio < analysis.transition_ratio < above.energy_ratio


def test_half_plane_transition_ratio_closed_form():
    """Two half-planes with datum depth d0: A_t = 1 / (4 ln(2 d0 / a) + 2) (measured 4e-6)."""
    for basis, pairs in (("nurbs", 61), ("lagrange2", 121)):
        _, analysis, _ = cycle("half-plane", basis, pairs, 0.5 * F * P, "force")
        base = simulation("half-plane", basis, pairs)
        expected = cf.half_plane_transition_ratio(base.reference.hertz, base.pair.upper.datum)
        assert analysis.transition_ratio == pytest.approx(expected, rel=1e-4)


def test_rig_springs_move_the_transition_by_their_travel():
    """With a tangential rig stiffness k_t, gross slip starts at the actuator displacement
    delta_t + f P / k_t, and the springs change the loop's shape, not its area."""
    from fretbem.contact.control import Rig

    base = simulation("half-plane", "nurbs", 61)
    result, _, _ = cycle("half-plane", "nurbs", 61, 0.6 * F * P, "force")
    k_t = 2.0e4
    onset = onset_displacement(base.prepare(), result.steps[0], F) + F * P / k_t
    found = {}
    for factor in (0.98, 1.02):
        waveform = Waveform(factor * onset, P, cycles=2, increments=40)
        sim = Simulation(base.pair, waveform.steps(), law=base.law, rig=Rig(tangential=k_t),
                         reference=SlidingPath(base.reference))  # fmt: skip
        found[factor] = analyse(run(sim))
    assert found[0.98].cycles[-1].regime == "partial slip"
    assert found[1.02].cycles[-1].regime == "gross slip"
    assert found[0.98].cycles[-1].energy_ratio < found[0.98].transition_ratio
    assert found[1.02].cycles[-1].energy_ratio > found[1.02].transition_ratio
    # the same Q* through springs: the same dissipated energy (measured 3e-5 relative)
    q_star = found[0.98].cycles[-1].tangential_amplitude
    _, _, forced = cycle("half-plane", "nurbs", 61, q_star, "force")
    assert found[0.98].cycles[-1].dissipated_energy == pytest.approx(
        forced.dissipated_energy, rel=1e-3
    )
    assert found[0.98].cycles[-1].loop_area == pytest.approx(forced.loop_area, rel=1e-3)
