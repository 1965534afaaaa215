"""Labelled results: a run, its stresses, a fatigue report and a sweep table as xarray
Datasets with CF units, written to netCDF by the command line and read back unchanged."""

from __future__ import annotations

import numpy as np
import pytest

xr = pytest.importorskip("xarray")

from fretbem.app import cli  # noqa: E402
from fretbem.views import read_netcdf, write_netcdf  # noqa: E402
from fretbem.views.cf import VARIABLES  # noqa: E402


def _same_run(dataset, result):
    """Every labelled number is the result's own."""
    assert list(dataset.step.values) == [s.name for s in result.steps]
    assert np.array_equal(dataset.x.values, result.steps[0].x)
    for k, step in enumerate(result.steps):
        fields = {
            "p": step.pressure,
            "q": step.shear,
            "un": step.normal_displacement,
            "ut": step.tangential_displacement,
            "state": step.states,
        }
        for name, values in fields.items():
            assert np.array_equal(dataset[name].values[k], values), name
        assert dataset.P.values[k] == step.normal and dataset.Q.values[k] == step.tangential
    ut = dataset.ut.values
    assert np.allclose(dataset.slip.values, np.diff(ut, axis=0, prepend=0 * ut[:1]), atol=0)


def test_run_dataset_is_the_result_with_units(rig_run):
    result = rig_run.result
    ds = result.to_xarray()
    _same_run(ds, result)
    assert ds.p.dims == ("step", "pair") and ds.sigma_B.values.tolist() == [0, 90, 0, -90, 0]
    for name in ds.variables:
        if name in VARIABLES:
            assert ds[name].attrs["units"] == VARIABLES[name][0], name
            assert ds[name].attrs["long_name"]
    assert ds.q.attrs["comment"].startswith("of the upper body on the lower, along +x")
    assert ds.state.attrs["flag_meanings"] == "separated stick slip"
    summary = result.summary()
    assert ds.attrs["hertz_a"] == summary["hertz"]["a"]
    assert ds.attrs["hertz_p0"] == summary["hertz"]["p0"]
    for k, step in enumerate(summary["steps"]):
        assert ds.contact.values[k].tolist() == step["contact"]
        assert ds.theory_stick_zone.values[k].tolist() == step["theory_stick_zone"]
        stick = ds.stick_zone.values[k]
        assert stick[~np.isnan(stick[:, 0])].tolist() == step["stick_zones"]
        assert ds.e_q_max.values[k] == step["e_q_max"]
        assert ds.est_q_max.values[k] == step["est_q_max"]
    passed = ds.check_passed.sel(step="B", check="equilibrium").item()
    assert passed == int(result["B"].checks["equilibrium"].passed) == 1
    assert ds.sel(step="B").q.max() > 0  # labelled selection works


def test_run_dataset_round_trips_through_netcdf(rig_run, tmp_path):
    ds = rig_run.result.to_xarray()
    back = read_netcdf(write_netcdf(ds, tmp_path / "results.nc"))
    xr.testing.assert_identical(ds, back)


@pytest.mark.parametrize(
    ("change", "theory"),
    [
        ({"specimen": "half-plane"}, True),
        ({"basis": "lagrange2"}, True),
        ({"pad": "half-plane", "pad_E": 110000.0}, False),
    ],
)
def test_every_body_model_and_family_labels(rig_data, change, theory, tmp_path):
    from fretbem.pipeline import run_scene
    from fretbem.scenes.file import scene_from_data

    data = rig_data(21)
    if "specimen" in change:
        data["specimen"]["model"] = change["specimen"]
    if "pad" in change:
        data["pad"]["model"] = change["pad"]
        data["pad"]["material"] = {"E": change["pad_E"], "nu": 0.33}
    if "basis" in change:
        data["contact"]["basis"] = change["basis"]
    result = run_scene(scene_from_data(data)).result
    ds = result.to_xarray()
    _same_run(ds, result)
    assert ("theory_stick_zone" in ds) is theory and ("hertz_a" in ds.attrs) is theory
    xr.testing.assert_identical(ds, read_netcdf(write_netcdf(ds, tmp_path / "r.nc")))


def test_stress_result_dataset(rig_run, tmp_path):
    from fretbem.stress import evaluate_stress_request, stress_request_from_dict
    from fretbem.stress.output import von_mises

    request = stress_request_from_dict(
        {
            "steps": ["A", "B"],
            "points": [["trailing-edge", 0.0], [0.0, -0.1]],
            "line": {"x": "trailing-edge", "depth": 0.5, "n": 5},
            "grid": {"x": [-0.8, 0.8], "depth": 0.4, "nx": 5, "ny": 4},
        }
    )
    done = evaluate_stress_request(rig_run.result, request)
    ds = done.to_xarray()
    a = rig_run.result.hertz()["a"]
    assert ds.point_x.values[0] == pytest.approx(-a) and done.half_width == a
    assert np.array_equal(ds.line0_sigma_xx.values, done.lines[0].stress[..., 0])
    assert np.array_equal(ds.grid_von_mises.values, von_mises(done.grid_stress))
    assert ds.grid_sigma_xx.dims == ("step", "grid_depth", "grid_x")
    assert ds.grid_sigma_xx.attrs["units"] == "MPa" and ds.line0_depth.attrs["units"] == "mm"
    hot = done.hot_spot()
    assert hot["sigma_xx"]["value"] == pytest.approx(
        max(float(ds[v].max()) for v in ("point_sigma_xx", "line0_sigma_xx", "grid_sigma_xx"))
    )
    xr.testing.assert_identical(ds, read_netcdf(write_netcdf(ds, tmp_path / "s.nc")))


def test_fatigue_report_dataset(tmp_path):
    from fretbem.fatigue import CattaneoMindlinCycle, fatigue_request_from_dict, run_fatigue

    cycle = CattaneoMindlinCycle(
        a=0.5, p0=300.0, f=0.6, tangential_ratio=0.5, sigma_bulk_max=80.0, nu=0.342
    )
    request = fatigue_request_from_dict(
        {
            "material": "Ti-6Al-4V",
            "constants": {"findley_k": 0.3},
            "critical_distance": 0.05,
            "map_points": [11, 5],
            "methods": ["swt", "findley"],
        }
    )
    report = run_fatigue(cycle, request)
    ds = report.to_xarray()
    for method, rep in report.methods.items():
        assert ds[method].dims == ("depth", "x") and ds[method].attrs["units"] == "MPa"
        assert np.array_equal(ds[method].values.ravel(), rep.map.value)
        assert ds[method].attrs["hot_spot_x"] == rep.hot_spot[0]
        assert ds[method].attrs["life_at_hot_spot_cycles"] == pytest.approx(
            rep.life_hot_spot.cycles
        )
    assert ("ruiz_f2" in ds) is (report.ruiz is not None)
    xr.testing.assert_identical(ds, read_netcdf(write_netcdf(ds, tmp_path / "f.nc")))


def test_sweep_table_dataset_is_indexed_by_its_parameters():
    import pandas as pd

    from fretbem.studies.sweep.labelled import sweep_dataset

    P, Q = np.meshgrid([60.0, 100.0], [0.0, 10.0, 20.0], indexing="ij")
    table = pd.DataFrame(
        {
            "case": range(6),
            "load.P": P.ravel(),
            "load.Q": Q.ravel(),
            "stick_width.B": np.arange(6.0),
            "regime": ["partial slip"] * 6,
        }
    )
    ds = sweep_dataset(table.drop(index=3), ["load.P", "load.Q"])
    assert ds["stick_width.B"].dims == ("load.P", "load.Q")
    assert ds["stick_width.B"].sel({"load.P": 100.0, "load.Q": 20.0}).item() == 5.0
    assert np.isnan(ds["stick_width.B"].sel({"load.P": 100.0, "load.Q": 0.0}).item())
    assert ds["load.P"].attrs["units"] == "N mm-1" and ds["stick_width.B"].attrs["units"] == "mm"
    zipped = sweep_dataset(table, ["load.P", "load.Q"], mode="zip")
    assert zipped["stick_width.B"].dims == ("case",) and "load.P" in zipped.coords


def test_command_line_writes_netcdf_on_request(tmp_path):
    out = tmp_path / "out"
    code = cli.main(
        ["demo", "--pairs", "21", "--no-figures", "--no-vtk", "--netcdf", "--out", str(out)]
    )
    assert code == 0
    ds = read_netcdf(out / "results.nc")
    import csv

    rows = list(csv.DictReader((out / "results.csv").open()))
    assert len(rows) == ds.sizes["step"] * ds.sizes["pair"]
    assert float(rows[-1]["q"]) == ds.q.values[-1, -1]
    assert ds.attrs["hertz_a"] == pytest.approx(0.3289, abs=5e-5)
    code = cli.main(
        ["demo", "--pairs", "21", "--no-figures", "--no-vtk", "--out", str(tmp_path / "plain")]
    )
    assert code == 0 and not (tmp_path / "plain" / "results.nc").exists()
