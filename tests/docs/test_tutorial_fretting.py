"""The fretting tutorial runs and its key numbers hold."""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import runpy

import matplotlib.pyplot as plt

SCRIPT = (
    Path(__file__).resolve().parents[2] / "docs/tutorials/09_fretting/fretting_loops_and_regimes.py"
)


def test_fretting_tutorial(tmp_path, monkeypatch):
    """61 half-plane pairs: measured slip amplitude 0.03 % off Cattaneo, E_d -0.44 % off W,
    loop area = E_d to 2e-9, (E_d - 4 f P delta_s) / W(0) = 0.971, A_t = 0.0543."""
    monkeypatch.chdir(tmp_path)
    try:
        ns = runpy.run_path(str(SCRIPT))
    finally:
        plt.close("all")
    assert ns["PARTIAL"].regime == "partial slip" and ns["GROSS"].regime == "gross slip"
    assert ns["SLIP_ERROR"] < 0.005
    assert abs(ns["ENERGY_ERROR"]) < 0.01
    assert abs(ns["LOOP_ERROR"]) < 1e-4
    assert abs(ns["TRANSITION_PART"] - 1) < 0.05
    assert ns["PARTIAL"].energy_ratio < ns["TRANSITION"] < ns["GROSS"].energy_ratio
    assert abs(ns["GROSS"].tangential_amplitude - 30.0) < 1e-9
