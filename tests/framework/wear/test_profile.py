"""The worn profile as a gap offset: same condensation, shifted gap, the NURBS refit."""

import attrs
import numpy as np
import pytest

from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run
from fretbem.wear.profile import WornPair, WornProfile, pair_weights
from fretbem.wear.refit import refit_face


@pytest.fixture(scope="module")
def simulation():
    return cattaneo_mindlin(pairs=21)


def test_worn_pair_reuses_the_condensation_and_offsets_the_gap(simulation):
    base = simulation.pair.condensed()
    offset = np.linspace(0.0, 1e-4, base.n_pairs)
    worn = WornPair.of(simulation.pair, offset).condensed()
    assert worn.normal_map is base.normal_map and worn.tangential_map is base.tangential_map
    assert np.array_equal(worn.gap, base.gap + offset)
    # a worn pair of a worn pair offsets the unworn one, not twice
    again = WornPair.of(WornPair.of(simulation.pair, offset), offset).condensed()
    assert np.array_equal(again.gap, base.gap + offset)


def test_weights_integrate_the_load(simulation):
    result = run(simulation)
    w = pair_weights(simulation.prepare())
    for step in result.steps:  # the contact force the results report, and so about P
        assert w @ step.pressure == pytest.approx(step.resultant[0], rel=1e-12)
        assert w @ step.pressure == pytest.approx(step.normal, rel=1e-4)


@pytest.mark.parametrize(("depth", "touching"), [(2e-4, False), (4e-3, True)])
def test_uniform_wear_is_a_rigid_approach(simulation, depth, touching):
    """The same depth everywhere moves the pad down and changes no traction (a depth beyond
    the solver's reach from the unloaded bodies is taken up by ``touching``)."""
    base = run(simulation)
    n = simulation.pair.n_pairs
    pair = WornPair.of(simulation.pair, np.full(n, depth), touching=touching)
    if touching:
        assert pair.pairing().gap.min() == 0.0
    worn = run(attrs.evolve(simulation, pair=pair))
    for a, b in zip(base.steps, worn.steps, strict=True):
        p0 = np.max(a.pressure)
        assert np.max(np.abs(a.pressure - b.pressure)) < 1e-9 * p0
        assert np.max(np.abs(a.shear - b.shear)) < 1e-9 * p0


def test_profile_volume_depth_and_scar():
    x = np.linspace(-1.0, 1.0, 21)
    w = np.full(21, 0.1)
    depth = np.maximum(0.0, 1e-3 * (1 - (x / 0.5) ** 2))
    profile = WornProfile(x, w, np.zeros(21), np.zeros(21)).worn(10, 0.5 * depth, depth)
    assert profile.cycles == 10
    assert profile.volume("lower") == pytest.approx(0.1 * depth.sum(), rel=1e-14)
    assert profile.volume("upper") == pytest.approx(0.05 * depth.sum(), rel=1e-14)
    assert profile.max_depth("lower") == pytest.approx(1e-3)
    assert profile.scar_width("lower") == pytest.approx(0.8)  # |x| < 0.5, depth > 1 % of max
    assert np.array_equal(profile.offset, 1.5 * depth)
    assert WornProfile(x, w, np.zeros(21), np.zeros(21)).scar_width("upper") == 0.0


def test_refit_error_is_measured_against_the_worn_face(simulation):
    """A refit at the element breakpoints carries an error of about 1 % of a scar's depth
    (measured 0.95 % on a partial-slip scar, docs/explanation/wear.rst); a smooth dent it
    fits closely, a step it cannot."""
    pair = simulation.pair
    x = pair.pairing().points[:, 0]
    a = 0.5 * (x.max() - x.min()) / 1.5
    smooth = 1e-3 * np.maximum(0.0, 1 - (x / a) ** 2) ** 2
    fit = refit_face(pair.lower, pair.lower_tag, x, smooth)
    assert fit.depth == pytest.approx(smooth.max())
    assert fit.error < 0.05 * fit.depth
    step = np.where(np.abs(x) < 0.5 * a, 1e-3, 0.0)
    assert refit_face(pair.lower, pair.lower_tag, x, step).error > 0.02e-3  # measured 4.3 %
