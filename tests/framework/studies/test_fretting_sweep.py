"""Running-condition maps of cyclic, displacement-driven sweeps (issue 22)."""

from __future__ import annotations

import numpy as np
import pytest

from fretbem.fretting.cycles import onset_displacement
from fretbem.scenes.builder import build
from fretbem.scenes.spec import scene_from_dict
from fretbem.simulation import run
from fretbem.studies.sweep.cases import case_loading, refused_steps

pytest.importorskip("pandas")

SCENE = {
    "pad": {"model": "half-plane"},
    "specimen": {"model": "half-plane"},
    "contact": {"pairs": 31},
    "load": {"P": 100.0, "cycle": {"delta": 0.002, "cycles": 2, "increments": 16}},
}


def test_regime_and_energy_maps_against_p_and_delta(tmp_path):
    """The map's regimes follow the model's own onset displacement at each P, and the
    energy and slip-amplitude maps are drawn with the A = A_t line."""
    from fretbem.studies.sweep.maps import draw_maps
    from fretbem.studies.sweep.run import sweep

    loads, deltas = [60.0, 100.0, 140.0], [0.001, 0.002, 0.003]
    axes = {"x": "load.P", "y": "load.cycle.delta"}
    columns = ("regime", "dissipated_energy", "slip_amplitude_max")
    options = {"maps": [{**axes, "column": column} for column in columns]}
    result = sweep(SCENE, {"load.P": loads, "load.cycle.delta": deltas}, out=tmp_path / "s",
                   serial=True, progress=False, options=options)  # fmt: skip
    table = result.table
    assert set(table["status"]) == {"ok"}
    assert "regime.c1.01" not in table.columns  # one row per case, not per increment
    for P in loads:
        scene = {**SCENE, "load": {"P": P, "cycle": {"delta": 0.001, "cycles": 1,
                                                       "increments": 4}}}  # fmt: skip
        sim, _ = build(scene_from_dict(scene))
        onset = onset_displacement(sim.prepare(), run(sim).steps[0], 0.3)
        for delta in deltas:
            row = table[
                np.isclose(table["load.P"], P) & np.isclose(table["load.cycle.delta"], delta)
            ]
            expected = "gross slip" if delta > onset else "partial slip"
            assert row["regime"].item() == expected, (P, delta, onset)
            gross = row["energy_ratio"].item() > row["transition_ratio"].item()
            assert gross == (expected == "gross slip")
            assert row["Q_peak"].item() <= 0.3 * P * (1 + 1e-12)
    names = {p.name for p in draw_maps(table, result.spec, tmp_path)}
    assert names == {"map-regime-load_P-load_cycle_delta.png",
                     "map-dissipated_energy-load_P-load_cycle_delta.png",
                     "map-slip_amplitude_max-load_P-load_cycle_delta.png"}  # fmt: skip


def test_displacement_steps_are_not_refused():
    loading = case_loading({**SCENE, "load": {"steps": ["A", "B"], "P": 100.0,
                                              "delta": [0.0, 1.0]}})  # fmt: skip
    assert refused_steps(loading) == []
