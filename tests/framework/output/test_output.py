"""Output files of a run: CSV, JSON summary, figures, VTK boundaries and the ParaView series."""

from __future__ import annotations

import csv
import json
import xml.etree.ElementTree as ET

import matplotlib.image as mpimg
import numpy as np
import pytest

from fretbem.output.write import write_results
from fretbem.scenes.reference import REFERENCE_STEPS, cattaneo_mindlin
from fretbem.simulation import run

pv = pytest.importorskip("pyvista")

PAIRS = 31


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    """The reference scene (nurbs, 31 pairs) run once and saved."""
    result = run(cattaneo_mindlin(basis="nurbs", pairs=PAIRS))
    directory = write_results(result, tmp_path_factory.mktemp("output") / "out")
    return result, directory


def test_csv_has_one_row_per_pair_per_step(saved):
    """results.csv has the agreed header and 5 x 31 data rows."""
    _, directory = saved
    with open(directory / "results.csv", newline="") as handle:
        rows = list(csv.reader(handle))
    assert rows[0] == ["step", "x", "p", "q", "un", "ut", "state"]
    assert len(rows) - 1 == len(REFERENCE_STEPS) * PAIRS
    assert {row[0] for row in rows[1:]} == set(REFERENCE_STEPS)
    assert {row[6] for row in rows[1:]} <= {"separated", "stick", "slip"}


def test_summary_lists_every_step_with_errors(saved):
    """summary.json has the five steps, each with the four error norms."""
    _, directory = saved
    summary = json.loads((directory / "summary.json").read_text())
    assert [s["step"] for s in summary["steps"]] == list(REFERENCE_STEPS)
    for step in summary["steps"]:
        for key in ("e_p_max", "e_q_max", "e_p_l2", "e_q_l2"):
            assert key in step
    assert summary["scene"]["pairs"] == PAIRS


@pytest.mark.parametrize("name", ["tractions.png", "displacements.png", "states.png"])
def test_figures_are_nonblank_images(saved, name):
    """Each figure is a readable PNG of plausible size that is not a blank canvas."""
    _, directory = saved
    image = mpimg.imread(directory / name)
    height, width = image.shape[:2]
    assert height >= 300 and width >= 500
    assert image.shape[2] in (3, 4)
    assert np.std(image[..., :3]) > 0.05


def _bottom_points(mesh, body):
    return np.isin(mesh.point_data["segment"], body.boundary.indices("bottom"))


def test_vtp_files_carry_fields_and_boundary_conditions(saved):
    """Each step's .vtp boundaries read back with their arrays; fixed bottom, rigid top."""
    result, directory = saved
    pair = result.simulation.pair
    for step in result.steps:
        lower = pv.read(directory / "vtk" / f"{step.name}_lower.vtp")
        upper = pv.read(directory / "vtk" / f"{step.name}_upper.vtp")
        for mesh in (lower, upper):
            assert mesh.n_points > 0 and mesh.n_lines == 6
            for name in ("displacement", "traction"):
                assert mesh.point_data[name].shape == (mesh.n_points, 3)
            assert "segment" in mesh.point_data
        scale = np.abs(upper.point_data["displacement"]).max()
        bottom = lower.point_data["displacement"][_bottom_points(lower, pair.lower)]
        assert np.abs(bottom).max() <= 1e-9 * scale
        top = upper.point_data["displacement"][
            np.isin(upper.point_data["segment"], pair.upper.boundary.indices("top"))
        ]
        assert np.allclose(top, top[0], atol=1e-9 * scale)


def test_deformed_files_move_points_by_scaled_displacement(saved):
    """*_deformed.vtp holds the points moved by scale x displacement, the scale as field data."""
    _, directory = saved
    plain = pv.read(directory / "vtk" / "B_upper.vtp")
    warped = pv.read(directory / "vtk" / "B_upper_deformed.vtp")
    scale = float(warped.field_data["displacement_scale"][0])
    assert scale > 1.0
    expected = plain.points + scale * plain.point_data["displacement"]
    assert np.allclose(warped.points, expected)
    width = np.ptp(plain.points[:, 0])
    largest = np.linalg.norm(plain.point_data["displacement"], axis=1).max() * scale
    assert largest <= 0.05 * width * (1 + 1e-9)


def test_pvd_lists_every_step(saved):
    """history.pvd names one time step per load step, both bodies each, files that exist."""
    _, directory = saved
    datasets = ET.parse(directory / "history.pvd").getroot().findall("./Collection/DataSet")
    assert len({d.get("timestep") for d in datasets}) == len(REFERENCE_STEPS)
    assert len(datasets) == 2 * len(REFERENCE_STEPS)
    for d in datasets:
        assert (directory / d.get("file")).is_file()


def test_render_step_writes_png(saved, tmp_path):
    """render_step draws step B off screen into a non-empty PNG."""
    from fretbem.output.vtk import render_step

    result, _ = saved
    path = render_step(result, "B", tmp_path / "step_B.png", window_size=(800, 400))
    image = mpimg.imread(path)
    assert image.shape[:2] == (400, 800)
    assert np.std(image[..., :3]) > 0.01


def test_draw_dispatches_on_geometry_types(saved):
    """draw() draws a contact pair and rejects types nobody registered."""
    import matplotlib.pyplot as plt

    from fretbem.output.figures import draw

    result, _ = saved
    ax = draw(result.simulation.pair)
    assert len(ax.lines) > 0
    plt.close(ax.figure)
    with pytest.raises(TypeError, match="cannot draw"):
        draw(object())


def test_vtp_arrays_read_back_bit_for_bit(saved, tmp_path):
    """The inline-binary .vtp files read back in VTK equal the arrays written, bit for bit:
    points, lines, point, cell and field data (strings too), plain and deformed."""
    from fretbem.output.vtk import deformed, step_arrays, write_vtp

    result, _ = saved
    for label, arrays in step_arrays(result, result["B"]).items():
        for suffix, data in (("", arrays), ("_deformed", deformed(arrays, 3.0))):
            mesh = pv.read(write_vtp(tmp_path / f"{label}{suffix}.vtp", data))
            assert np.array_equal(mesh.points, data["points"])
            cells = np.concatenate([[len(line), *line] for line in data["lines"]])
            assert np.array_equal(mesh.lines, cells)
            for kind in ("point_data", "cell_data", "field_data"):
                stored = getattr(mesh, kind)
                assert set(stored.keys()) == set(data[kind]), kind
                for name, values in data[kind].items():
                    got, want = np.asarray(stored[name]).ravel(), np.asarray(values).ravel()
                    assert got.tolist() == want.tolist(), (kind, name)


def test_writing_figures_and_vtk_imports_neither_pyplot_nor_pyvista(tmp_path):
    """The files of a run (figures and VTK included) are written without pyplot (plain
    figures on an Agg canvas) and without pyvista (the .vtp files are written by Python)."""
    import subprocess
    import sys

    code = (
        "import sys\n"
        "from fretbem.output import write_results\n"
        "from fretbem.scenes import cattaneo_mindlin\n"
        "from fretbem.simulation import run\n"
        "write_results(run(cattaneo_mindlin(pairs=11)), sys.argv[1])\n"
        "heavy = ('matplotlib.pyplot', 'pyvista', 'vtk', 'vtkmodules')\n"
        "print([m for m in heavy if m in sys.modules], 'matplotlib.figure' in sys.modules)\n"
    )
    out = tmp_path / "out"
    done = subprocess.run(
        [sys.executable, "-c", code, str(out)], capture_output=True, text=True, check=False
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.split("\n")[-2] == "[] True"
    assert (out / "tractions.png").is_file() and (out / "vtk" / "B_upper.vtp").is_file()


def test_figures_join_pyplot_when_it_is_in_use(saved, tmp_path):
    """With pyplot imported (notebooks, the docs gallery) a figure is pyplot's, so it shows
    and is collected there; save_figures closes the ones it draws."""
    import matplotlib.pyplot as plt

    from fretbem.output import figures as plot

    result, _ = saved
    fig = plot.traction_figure(result, ["B"])
    try:
        assert fig.number in plt.get_fignums()
    finally:
        plt.close(fig)
    before = set(plt.get_fignums())
    plot.save_figures(result, tmp_path)
    assert set(plt.get_fignums()) == before


def test_displacement_figure_draws_every_step_in_two_panels(saved):
    """displacements.png: u_n (with the closed gap) above u_t, every step's curve of every
    result in them (the same data as one panel per step, in 2 axes instead of 2 per step),
    and a legend entry per step and per result."""
    from fretbem.output.figures import displacement_figure

    result, _ = saved
    other = run(cattaneo_mindlin(basis="lagrange2", pairs=PAIRS))
    fig = displacement_figure([result, other])
    top, bottom = fig.axes
    scale = result.simulation.reference.hertz.half_width
    for ax, field in ((top, "normal_displacement"), (bottom, "tangential_displacement")):
        drawn = [(line.get_xdata(), line.get_ydata()) for line in ax.get_lines()]
        for r in (result, other):
            for step in r.steps:
                expected = (step.x / scale, 1e3 * getattr(step, field))
                assert any(
                    np.array_equal(x, expected[0]) and np.array_equal(y, expected[1])
                    for x, y in drawn
                ), (field, step.name)
    gap = -1e3 * result.simulation.pair.pairing().gap
    assert any(np.array_equal(line.get_ydata(), gap) for line in top.get_lines())
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert len(labels) == len(result.steps) + 2 + 1
    assert all(any(f"step {s.name}:" in label for label in labels) for s in result.steps)
