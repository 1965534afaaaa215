"""The notebook tutorial runs: repr, to_xarray, netCDF round trip and the report page."""

import runpy
from pathlib import Path

import matplotlib
import pytest

matplotlib.use("Agg")
import matplotlib.pyplot as plt

SCRIPT = Path(__file__).resolve().parents[2] / "docs/tutorials/08_results/results_in_a_notebook.py"


def test_results_tutorial(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    try:
        ns = runpy.run_path(str(SCRIPT))
    finally:
        plt.close("all")
    assert len(repr(ns["result"])) < 400
    assert ns["LINE_X"] == pytest.approx(-ns["HERTZ_A"])  # "trailing-edge" is x = -a
    assert ns["back"].identical(ns["ds"])
    report = ns["REPORT"].read_text()
    assert report.startswith("<!DOCTYPE html>") and 'id="fatigue"' in report
