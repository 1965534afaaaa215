"""The fatigue functions called from Python refuse a bad number with one FatigueInputError
naming the argument: no TypeError from a comparison, no OverflowError, no NaN reaching a root
finder, no string read as an index."""

from __future__ import annotations

import math

import numpy as np
import pytest

from fretbem.fatigue import (
    critical_distance_from_threshold,
    critical_plane_parameters,
    estimate_life,
    load_material,
    select_cycle,
    turning_points,
)
from fretbem.fatigue.critical_distance import critical_distance_values
from fretbem.fatigue.errors import FatigueInputError

TI = load_material("Ti-6Al-4V")
#: a small stress history (5 steps, 10 points): sxx cycling
STRESS = np.zeros((5, 10, 4))
STRESS[:, :, 0] = np.linspace(-100.0, 100.0, 5)[:, None]


@pytest.mark.parametrize(
    ("call", "message"),
    [
        (lambda: critical_distance_from_threshold(10**400, 100.0), r"threshold_sif.*10\^400"),
        (lambda: critical_distance_from_threshold("5", 100.0), r"threshold_sif_range must be"),
        (lambda: critical_distance_from_threshold(5.0, True), r"fatigue_limit_range must be a num"),
        (lambda: critical_distance_values(None, (0.0, 0.0), "0.1"), r"critical_distance must be a"),
        (lambda: estimate_life("swt", "1.0", TI), r"estimate_life parameter must be a number"),
        (lambda: estimate_life("swt", True, TI), r"estimate_life parameter must be a number"),
        (lambda: estimate_life("swt", math.nan, TI), r"the swt life needs a finite parameter"),
        (lambda: estimate_life("swt", 10**400, TI), r"the swt life needs a finite parameter"),
        (lambda: estimate_life("stress_life", 10**400, TI), r"needs a finite amplitude"),
        (lambda: estimate_life("swt", 1.0, TI, runout_cycles="1e7"), r"runout_cycles must be a"),
        (lambda: estimate_life("stress_life", 1.0, TI, mean_stress="5"), r"mean_stress must be a"),
        (lambda: select_cycle(10**400), r"n_steps must be below 2\^63"),
        (lambda: select_cycle("5"), r"n_steps must be a whole number"),
        (lambda: select_cycle(4, steps=["1", "2"]), r"cycle steps\[0\] must be a whole number"),
        (lambda: select_cycle(4, steps=[1.5, 2]), r"cycle steps\[0\] must be a whole number"),
        (lambda: select_cycle(4, steps="12"), r"cycle steps must list step indices"),
        (lambda: turning_points(["a", "b"]), r"cycle driver must be a 1D load history of numbers"),
        (lambda: critical_plane_parameters(STRESS, E=10**400, nu=0.3), r"E must be a finite"),
        (lambda: critical_plane_parameters(STRESS, E="7e4", nu=0.3), r"E must be a number"),
        (lambda: critical_plane_parameters(STRESS, E=7e4, nu=True), r"nu must be a number"),
        (lambda: critical_plane_parameters(STRESS, E=7e4, nu=0.3, methods=("findley",),
                                           findley_k="0.3"), r"findley_k must be a number"),
        (lambda: critical_plane_parameters(STRESS, E=7e4, nu=0.3, methods="swt"),
         r"methods must be a list of method names, got the string 'swt'"),
        (lambda: critical_plane_parameters(STRESS, E=7e4, nu=0.3, search={"compiled": True}),
         r"search must be a PlaneSearch or None"),
        (lambda: turning_points([0.0, math.nan, 1.0]), r"cycle driver has NaN or infinite"),
    ],
)  # fmt: skip
def test_a_bad_argument_is_named(call, message):
    with pytest.raises(FatigueInputError, match=message) as error:
        call()
    assert "\n" not in str(error.value)


def test_valid_arguments_still_work():
    assert select_cycle(4, steps=[0, 2]).tolist() == [0, 2]
    assert select_cycle(5, driver=[0, 1, 0, -1, 0]).tolist() == [1, 2, 3, 4]
    assert critical_distance_from_threshold(5, 100) == pytest.approx(1000 / math.pi * 0.05**2)
    assert estimate_life("stress_life", 100, TI).cycles > 0
