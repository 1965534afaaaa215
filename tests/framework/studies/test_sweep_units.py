"""Units on every sweep map axis and colour bar."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from fretbem.studies.sweep.maps import column_map, regime_map
from fretbem.studies.sweep.units import axis_label, unit_of


@pytest.mark.parametrize(
    ("name", "unit"),
    [
        ("load.P", "N/mm"), ("load.Q", "N/mm"), ("load.Q[1]", "N/mm"), ("load.bulk", "MPa"),
        ("contact.friction", "1"), ("pad.radius", "mm"), ("material.E", "MPa"),
        ("stick_width.B", "mm"), ("sxx_max", "MPa"), ("sxx_max.B", "MPa"),
        ("e_q_max.D", "fraction of f p0"), ("swt.parameter", "MPa"), ("swt.life", "cycles"),
        ("fatemi_socie.parameter", "1"), ("mwcm.depth", "mm"), ("Q_peak", "N/mm"),
        ("M.B", "N mm/mm"), ("theta.B", "rad"), ("tilt.C", "rad"), ("tilt_amplitude", "rad"),
        ("M_amplitude", "N mm/mm"), ("theta_amplitude", "rad"), ("load.moment", "N mm/mm"),
        ("load.moment[1]", "N mm/mm"), ("load.rotation", "rad"),
        ("load.cycle.M_amplitude", "N mm/mm"), ("load.cycle.M_phase", "degrees"),
        ("rig.stiffness_rotation", "N mm/mm per rad"), ("rig.pivot_height", "mm"),
    ],
)  # fmt: skip
def test_units_of_parameters_and_outputs(name, unit):
    assert unit_of(name) == unit


def test_unknown_names_get_no_unit_rather_than_a_wrong_one():
    assert unit_of("my.output") is None
    assert axis_label("my.output") == "my.output"
    assert axis_label("contact.friction") == "contact.friction (-)"


def _table():
    P, Q = np.meshgrid([60.0, 100.0, 140.0], [0.0, 20.0, 40.0])
    P, Q = P.ravel(), Q.ravel()
    regime = np.where(Q == 0, "full stick", np.where(Q < 0.3 * P, "partial slip", "gross slip"))
    return pd.DataFrame(
        {"load.P": P, "load.Q": Q, "regime": regime, "friction": 0.3, "P_max": P,
         "Q_peak": Q, "stick_width.B": 0.1 * P / (1 + Q)}
    )  # fmt: skip


def test_every_map_axis_and_colour_bar_has_its_unit():
    ax = regime_map(_table(), "load.P", "load.Q")
    assert ax.get_xlabel() == "load.P (N/mm)" and ax.get_ylabel() == "load.Q (N/mm)"
    assert all(t.get_fontsize() >= 9 for t in ax.get_legend().get_texts())
    ax = column_map(_table(), "stick_width.B", "load.P", "load.Q")
    assert ax.get_xlabel() == "load.P (N/mm)"
    colour_bar = ax.figure.axes[-1]
    assert colour_bar.get_ylabel() == "stick_width.B (mm)"
