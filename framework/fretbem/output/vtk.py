"""VTK export: each body's boundary per load step, and a ParaView time series.

Every step gives, per body, ``vtk/<step>_<body>.vtp`` (undeformed boundary with point data
"displacement", "traction", "traction_magnitude", "segment") and ``vtk/<step>_<body>_deformed.vtp``
(points moved by displacement x scale, the scale in field data). ``history.pvd`` lists the
undeformed files and ``history_deformed.pvd`` the deformed ones, one time step per load step.
``<step>`` is the step name made safe for a file name
(:func:`fretbem.verification.checks.safe_names`).

The .vtp files are written here as VTK XML with Python file I/O, so a full disk raises
OSError instead of crashing inside the VTK library, and the free space is checked before
writing. Numbers are inline binary (base64 of the little-endian doubles and integers: exact,
and encoded by numpy in one call per array); strings are ASCII. pyvista is imported only to
build meshes for rendering.
"""

from __future__ import annotations

import base64
from pathlib import Path
from typing import TYPE_CHECKING

import attrs
import numpy as np

from fretbem.bem.system import BodySolution
from fretbem.body import Body
from fretbem.results import SimulationResult, StepResult
from fretbem.sliding.result import step_solutions
from fretbem.verification.checks import safe_names
from fretbem.views.markup import quote_attribute

from .staging import check_free_space

if TYPE_CHECKING:  # pragma: no cover
    import pyvista as pv

POINTS_PER_ELEMENT = 8
#: the deformed files magnify displacements so the largest is this fraction of the body width
DEFORMED_FRACTION = 0.05


def _params(basis, points_per_element: int) -> np.ndarray:
    """Curve parameters sampling every element (shared element ends appear once)."""
    local = np.linspace(0.0, 1.0, points_per_element)
    lo, hi = basis.element_bounds.T
    params = (lo[:, None] + local[None, :] * (hi - lo)[:, None])[:, :-1].ravel()
    return np.append(params, hi[-1])


def _as_3d(values: np.ndarray) -> np.ndarray:
    return np.column_stack([values, np.zeros(len(values))])


@attrs.frozen(eq=False)
class BoundarySampling:
    """Where a body's boundary is drawn, the same at every step: each segment's curve
    parameters, its points there and its basis's evaluation matrix there."""

    body: Body
    params: tuple
    points: tuple
    matrices: tuple

    @classmethod
    def of(cls, body: Body, points_per_element: int = POINTS_PER_ELEMENT) -> BoundarySampling:
        params = tuple(_params(basis, points_per_element) for basis in body.segments)
        points = tuple(
            basis.geometry(*basis.to_local(p))[0]
            for basis, p in zip(body.segments, params, strict=True)
        )
        matrices = tuple(
            basis.evaluation_matrix(p) for basis, p in zip(body.segments, params, strict=True)
        )
        return cls(body, params, points, matrices)

    def fields(self, solution, k: int) -> tuple[np.ndarray, np.ndarray]:
        """Displacement and traction of ``solution`` on segment ``k``: a BEM body's
        coefficients through the kept matrix (the products ``BodySolution`` forms), any
        other solution (or another body's) asked at the parameters."""
        params = self.params[k]
        if not isinstance(solution, BodySolution) or solution.body is not self.body:
            return solution.displacement(k, params), solution.traction(k, params)
        part = solution.body.function_slice(k)
        return (
            self.matrices[k] @ solution.displacement_coefficients[part],
            self.matrices[k] @ solution.traction_coefficients[part],
        )


def boundary_arrays(
    body: Body,
    solution=None,
    points_per_element: int = POINTS_PER_ELEMENT,
    sampling: BoundarySampling | None = None,
) -> dict:
    """The discretised boundary as arrays: points (N, 3), lines (point index arrays, one per
    segment), point_data, cell_data and field_data dictionaries (the solution's fields).
    ``sampling`` (``BoundarySampling.of(body, points_per_element)``) serves every step."""
    if sampling is None:
        sampling = BoundarySampling.of(body, points_per_element)
    points, lines, segment, fields = [], [], [], {"displacement": [], "traction": []}
    start = 0
    for k, params in enumerate(sampling.params):
        points.append(sampling.points[k])
        lines.append(start + np.arange(len(params)))
        segment.append(np.full(len(params), k))
        start += len(params)
        if solution is not None:
            displacement, traction = sampling.fields(solution, k)
            fields["displacement"].append(displacement)
            fields["traction"].append(traction)
    point_data = {"segment": np.concatenate(segment)}
    field_data = {"tags": np.array(body.segment_tags), "body": np.array([body.name])}
    if solution is not None:
        for name, values in fields.items():
            point_data[name] = _as_3d(np.concatenate(values))
        point_data["traction_magnitude"] = np.linalg.norm(point_data["traction"], axis=1)
        field_data["block_displacement"] = np.asarray(solution.block_displacement, float)
    return {
        "points": _as_3d(np.concatenate(points)),
        "lines": lines,
        "point_data": point_data,
        "cell_data": {"segment": np.arange(len(body.segments))},
        "field_data": field_data,
    }


def to_polydata(arrays: dict) -> pv.PolyData:
    """A pyvista PolyData of ``boundary_arrays`` output."""
    import pyvista as pv

    cells = np.concatenate([np.concatenate([[len(line)], line]) for line in arrays["lines"]])
    mesh = pv.PolyData(arrays["points"], lines=cells)
    for kind in ("point_data", "cell_data", "field_data"):
        for name, values in arrays[kind].items():
            getattr(mesh, kind)[name] = values
    return mesh


def boundary_mesh(
    body: Body, solution=None, points_per_element: int = POINTS_PER_ELEMENT
) -> pv.PolyData:
    """The discretised boundary as pyvista polylines (one per segment), with the fields."""
    return to_polydata(boundary_arrays(body, solution, points_per_element))


#: VTK type and the little-endian numpy type written for each numpy kind
_VTK_TYPES = {"f": ("Float64", "<f8"), "i": ("Int64", "<i8"), "u": ("Int64", "<i8"),
              "b": ("Int64", "<i8")}  # fmt: skip


def _binary(values: np.ndarray, dtype: str) -> str:
    """VTK inline binary (header_type UInt64, no compression): base64 of the byte count, then
    base64 of the bytes, each encoded on its own as VTK reads them."""
    data = np.ascontiguousarray(values, dtype=dtype).tobytes()
    header = np.array([len(data)], dtype="<u8").tobytes()
    return (base64.b64encode(header) + base64.b64encode(data)).decode("ascii")


def _data_array(name: str | None, values: np.ndarray) -> str:
    values = np.asarray(values)
    named = f' Name="{name}"' if name else ""
    if values.dtype.kind in "US":  # strings: char codes, each string ended by 0 (VTK ASCII)
        codes = [str(c) for v in values.ravel() for c in [*str(v).encode(), 0]]
        return (
            f'<Array type="String"{named} NumberOfTuples="{values.size}" format="ascii">'
            + " ".join(codes)
            + "</Array>"
        )
    kind, dtype = _VTK_TYPES[values.dtype.kind]
    components = values.shape[1] if values.ndim == 2 else 1
    return (
        f'<DataArray type="{kind}"{named} NumberOfComponents="{components}" '
        f'NumberOfTuples="{len(values)}" format="binary">{_binary(values, dtype)}</DataArray>'
    )


def write_vtp(path: str | Path, arrays: dict) -> Path:
    """Write ``boundary_arrays`` output as a VTK XML PolyData file (polylines), one string."""
    points, lines = arrays["points"], arrays["lines"]
    field = "".join(
        _data_array(k, np.atleast_1d(v).ravel() if np.asarray(v).dtype.kind not in "US" else v)
        for k, v in arrays["field_data"].items()
    )
    point = "".join(_data_array(k, v) for k, v in arrays["point_data"].items())
    cell = "".join(_data_array(k, v) for k, v in arrays["cell_data"].items())
    offsets = np.cumsum([len(line) for line in lines])
    connectivity = np.concatenate(lines)
    text = (
        '<?xml version="1.0"?>\n'
        '<VTKFile type="PolyData" version="1.0" byte_order="LittleEndian" '
        'header_type="UInt64">\n<PolyData>\n'
        f"<FieldData>{field}</FieldData>\n"
        f'<Piece NumberOfPoints="{len(points)}" NumberOfVerts="0" NumberOfLines="{len(lines)}" '
        'NumberOfStrips="0" NumberOfPolys="0">\n'
        f"<PointData>{point}</PointData>\n<CellData>{cell}</CellData>\n"
        f"<Points>{_data_array(None, points)}</Points>\n"
        f"<Lines>{_data_array('connectivity', connectivity)}"
        f"{_data_array('offsets', offsets)}</Lines>\n"
        "</Piece>\n</PolyData>\n</VTKFile>\n"
    )
    path = Path(path)
    with open(path, "w") as handle:
        handle.write(text)
    return path


def body_solutions(result: SimulationResult, step: StepResult) -> dict:
    """Each body's full boundary solution at ``step`` ("upper" and "lower"); a step of a
    sliding run on its own pairing, the pad's slide added to its block's displacement."""
    if step.pair is None:
        return result.simulation.prepare().solutions(step.unknowns, step.loads)
    return step_solutions(result, step)


def drawable_bodies(result: SimulationResult, say=print) -> list[str]:
    """Labels of the bodies with a boundary to draw; one line said for each that has less."""
    pair = result.simulation.pair
    out = []
    for label, body in (("upper", pair.upper), ("lower", pair.lower)):
        model = body.describe().get("model", type(body).__name__)
        if not body.segments:
            say(f"skipped: VTK of the {model} body {body.name!r}: it has no boundary segments")
            continue
        if not body.outline_complete:
            say(f"VTK of the {model} body {body.name!r}: its face only (it has no far boundary)")
        out.append(label)
    return out


def step_arrays(
    result: SimulationResult,
    step: StepResult,
    points_per_element: int = POINTS_PER_ELEMENT,
    samplings: dict | None = None,
) -> dict[str, dict]:
    """``boundary_arrays`` of both bodies at ``step``, with the step's name and loads;
    ``samplings`` (a dict) keeps each body's BoundarySampling for the next steps."""
    pair = result.simulation.pair
    bodies = {"upper": pair.upper, "lower": pair.lower}
    samplings = {} if samplings is None else samplings
    out = {}
    for label, solution in body_solutions(result, step).items():
        body = bodies[label]
        if not body.segments:  # nothing to draw (said once by drawable_bodies)
            continue
        if label not in samplings:
            samplings[label] = BoundarySampling.of(body, points_per_element)
        arrays = boundary_arrays(body, solution, points_per_element, samplings[label])
        arrays["field_data"]["step"] = np.array([step.name])
        arrays["field_data"]["loads"] = np.array([step.normal, step.tangential])
        out[label] = arrays
    return out


def step_meshes(
    result: SimulationResult, step: StepResult, points_per_element: int = POINTS_PER_ELEMENT
) -> dict[str, pv.PolyData]:
    """Undeformed boundary meshes of both bodies at ``step``, with step facts as field data."""
    return {k: to_polydata(v) for k, v in step_arrays(result, step, points_per_element).items()}


def _points_and_displacement(mesh) -> tuple[np.ndarray, np.ndarray]:
    if isinstance(mesh, dict):
        return mesh["points"], mesh["point_data"]["displacement"]
    return np.asarray(mesh.points), np.asarray(mesh.point_data["displacement"])


def deformation_scale(meshes: list, fraction: float = DEFORMED_FRACTION) -> float:
    """Magnification making the largest displacement ``fraction`` of the widest body."""
    pairs = [_points_and_displacement(m) for m in meshes]
    width = max(float(np.ptp(points[:, 0])) for points, _ in pairs)
    largest = max(float(np.linalg.norm(u, axis=1).max()) for _, u in pairs)
    return fraction * width / largest if largest > 0 and np.isfinite(largest) else 1.0


def deformed(mesh, scale: float):
    """A copy of ``mesh`` (PolyData or arrays) with its points moved by scale x displacement."""
    if isinstance(mesh, dict):
        out = {**mesh, "field_data": dict(mesh["field_data"])}
        out["points"] = mesh["points"] + scale * mesh["point_data"]["displacement"]
        out["field_data"]["displacement_scale"] = np.array([scale])
        return out
    out = mesh.copy()
    out.points = mesh.points + scale * mesh.point_data["displacement"]
    out.field_data["displacement_scale"] = np.array([scale])
    return out


def write_pvd(path: Path, entries: list[tuple[int, int, str, Path]]) -> Path:
    """A ParaView collection: (timestep, part, name, file) per dataset, files relative to path."""
    lines = [
        '<?xml version="1.0"?>',
        '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
        "  <Collection>",
    ]
    for timestep, part, name, file in entries:
        relative = Path(file).relative_to(path.parent).as_posix()
        lines.append(
            f'    <DataSet timestep="{timestep}" group="" part="{part}" '
            f"name={quote_attribute(name)} file={quote_attribute(relative)}/>"
        )
    lines += ["  </Collection>", "</VTKFile>", ""]
    path.write_text("\n".join(lines))
    return path


def _size_estimate(arrays: dict) -> int:
    """Bytes of a .vtp file: 8-byte numbers in base64 are under 11 characters each."""
    numbers = arrays["points"].size + sum(np.size(v) for v in arrays["point_data"].values())
    return 11 * (numbers + 2 * sum(len(line) for line in arrays["lines"])) + 4096


def save_vtk(
    result: SimulationResult, directory: str | Path, points_per_element: int = POINTS_PER_ELEMENT
) -> list[Path]:
    """Write every step's boundary meshes (undeformed and deformed) and two .pvd series.

    Checks the free disk space for all files first (OutputError if short).
    """
    directory = Path(directory)
    folder = directory / "vtk"
    folder.mkdir(parents=True, exist_ok=True)
    stems = safe_names([s.name for s in result.steps])
    if not drawable_bodies(result):
        return []
    samplings: dict = {}  # each body's sampling, evaluated once for every step
    steps = [step_arrays(result, s, points_per_element, samplings) for s in result.steps]
    every = [m for meshes in steps for m in meshes.values()]
    check_free_space(folder, 2 * sum(_size_estimate(m) for m in every), "VTK files")
    scale = deformation_scale(every)
    written, plain, warped = [], [], []
    for timestep, (stem, meshes) in enumerate(zip(stems, steps, strict=True)):
        for part, (label, mesh) in enumerate(meshes.items()):
            versions = (("", mesh, plain), ("_deformed", deformed(mesh, scale), warped))
            for suffix, data, series in versions:
                path = write_vtp(folder / f"{stem}_{label}{suffix}.vtp", data)
                series.append((timestep, part, label, path))
                written.append(path)
    written.append(write_pvd(directory / "history.pvd", plain))
    written.append(write_pvd(directory / "history_deformed.pvd", warped))
    return written


def _contact_centre(mesh: pv.PolyData, shape: pv.PolyData, zone: float) -> np.ndarray:
    """Mean deformed position of the points of ``mesh`` within ``zone`` of the origin."""
    near = np.linalg.norm(mesh.points[:, :2], axis=1) <= zone
    return shape.points[near].mean(axis=0)


def _add_boundaries(plotter, shapes, clim, scalar_bar: bool) -> None:
    bar = {"title": "traction magnitude (MPa)", "position_x": 0.3, "width": 0.4}
    for shape in shapes:
        plotter.add_mesh(
            shape, scalars="traction_magnitude", cmap="viridis", clim=clim, line_width=5,
            render_lines_as_tubes=True, show_scalar_bar=scalar_bar, scalar_bar_args=bar,
        )  # fmt: skip


def _add_traction_arrows(plotter, mesh, shape, segments, length: float, count: int = 21) -> None:
    """About ``count`` arrows of the traction on ``mesh`` along ``segments``."""
    on = np.flatnonzero(np.isin(mesh.point_data["segment"], segments))
    on = on[np.linspace(0, len(on) - 1, count).round().astype(int)]
    vectors = mesh.point_data["traction"][on]
    largest = np.linalg.norm(vectors, axis=1).max()
    if largest == 0:
        return
    import pyvista as pv

    cloud = pv.PolyData(shape.points[on])
    cloud.point_data["traction"] = vectors / largest
    arrow = pv.Arrow(tip_length=0.15, tip_radius=0.03, shaft_radius=0.008)
    glyphs = cloud.glyph(orient="traction", scale="traction", factor=length, geom=arrow)
    plotter.add_mesh(glyphs, color="black")


def render_step(
    result: SimulationResult,
    step_name: str,
    path: str | Path,
    *,
    window_size: tuple[int, int] = (1600, 800),
) -> Path:
    """Off-screen picture of the deformed boundaries at a step, coloured by |traction|.

    Left: both bodies, displacements magnified; right: the contact zone at true scale, with
    arrows of the traction the upper body exerts on the lower one.
    """
    import pyvista as pv

    step = result[step_name]
    pair = result.simulation.pair
    by_label = step_meshes(result, step)
    meshes = list(by_label.values())
    scale = deformation_scale(meshes)
    shapes = [deformed(m, scale) for m in meshes]
    zone = float(np.abs(step.x).max())
    clim = (0.0, 1.05 * float(np.max(np.hypot(step.pressure, step.shear))))
    weights = (1.0, 3.0)
    plotter = pv.Plotter(
        off_screen=True, shape=(1, 2), col_weights=weights, window_size=window_size, border=True
    )
    label = f"step {step.name}: P = {step.normal:g}, Q = {step.tangential:g} N/mm"
    plotter.subplot(0, 0)
    _add_boundaries(plotter, shapes, clim, scalar_bar=False)
    plotter.add_text(f"{label}\ndisplacement x {scale:.3g}", font_size=8)
    plotter.view_xy()
    plotter.subplot(0, 1)
    true_shapes = [deformed(m, 1.0) for m in meshes]
    _add_boundaries(plotter, true_shapes, clim, scalar_bar=True)
    lower = list(by_label).index("lower") if "lower" in by_label else len(meshes) - 1
    segments = [k for k, tag in enumerate(pair.lower.segment_tags) if tag == pair.lower_tag]
    _add_traction_arrows(plotter, meshes[lower], true_shapes[lower], segments, 0.5 * zone)
    plotter.add_text("contact zone, true scale; arrows: traction on the lower body", font_size=8)
    plotter.view_xy()
    centre = _contact_centre(meshes[lower], true_shapes[lower], zone)
    aspect = window_size[0] * weights[1] / sum(weights) / window_size[1]
    camera = plotter.camera
    camera.parallel_projection = True
    camera.focal_point = centre
    camera.position = centre + np.array([0.0, 0.0, 10.0])
    camera.up = (0.0, 1.0, 0.0)
    camera.parallel_scale = 1.6 * zone / aspect
    path = Path(path)
    plotter.screenshot(path)
    plotter.close()
    return path
