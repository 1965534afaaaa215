"""From a stress history to a fatigue report: map, hot spot, critical distances, lives, Ruiz.

:func:`run_fatigue` is the one call a script or the command line makes; it takes any
:class:`~fretbem.fatigue.providers.StressHistoryProvider` and a
:class:`~fretbem.fatigue.request.FatigueRequest`.
"""

from __future__ import annotations

import attrs
import numpy as np

from .critical_distance import CriticalDistanceValues, critical_distance_values
from .critical_plane import CriterionResult, critical_plane_parameters
from .cycle import select_cycle
from .errors import FatigueInputError, MissingFatigueDataError
from .labelled import fatigue_dataset, fatigue_html, fatigue_repr
from .life import LifeEstimate, estimate_life
from .mean_stress import CORRECTIONS_OF
from .providers import StressHistoryProvider
from .request import FatigueRequest
from .ruiz import RuizParameters, ruiz_parameters

__all__ = ["FatigueReport", "MethodReport", "run_fatigue"]

#: points of the fine surface scan for the hot spot
SURFACE_SCAN_POINTS = 401
#: points of the second, local surface scan around the best coarse point
FINE_SCAN_POINTS = 41
#: points of the depth profile below the hot spot
PROFILE_POINTS = 60


@attrs.frozen(eq=False)
class MethodReport:
    """One parameter: its map, hot spot, critical plane, critical-distance values and lives.

    Attributes
    ----------
    method : str
        Parameter name.
    map : CriterionResult
        The parameter on the map grid (flattened, depth-major: shape (ndepth * nx,)).
    hot_spot : tuple[float, float]
        [x, depth] of the hot spot, mm.
    at_hot_spot : CriterionResult
        The parameter and critical plane at the hot spot (one point).
    critical_distance : CriticalDistanceValues or None
        Point, line and area values (None without L).
    direction : tuple[float, float]
        Critical direction used, [x, depth].
    profile_distance, profile_value : ndarray
        Parameter along the critical direction from the hot spot.
    life_hot_spot, life_critical_distance : LifeEstimate or None
        Life from the hot-spot value and from the point-method value.
    life_message : str
        Why a life is missing, if it is.
    """

    method: str
    map: CriterionResult
    hot_spot: tuple[float, float]
    at_hot_spot: CriterionResult
    critical_distance: CriticalDistanceValues | None
    direction: tuple[float, float]
    profile_distance: np.ndarray
    profile_value: np.ndarray
    life_hot_spot: LifeEstimate | None
    life_critical_distance: LifeEstimate | None
    life_message: str = ""

    def __repr__(self) -> str:
        return (f"<MethodReport {self.method}: {float(self.at_hot_spot.value[0]):.4g} at hot "
                f"spot x={self.hot_spot[0]:.4g}, depth={self.hot_spot[1]:.4g}>")  # fmt: skip


@attrs.frozen(eq=False)
class FatigueReport:
    """Everything :func:`run_fatigue` found; written by :func:`fretbem.fatigue.write_fatigue`.

    Attributes
    ----------
    request : FatigueRequest
    cycle_steps : ndarray
        Step indices of the evaluated cycle.
    map_x, map_depth : ndarray
        Grid axes of the parameter maps, mm.
    methods : dict[str, MethodReport]
    ruiz : RuizParameters or None
    notes : tuple[str, ...]
    """

    request: FatigueRequest
    cycle_steps: np.ndarray
    map_x: np.ndarray
    map_depth: np.ndarray
    methods: dict[str, MethodReport]
    ruiz: RuizParameters | None
    notes: tuple[str, ...]

    def __repr__(self) -> str:
        return fatigue_repr(self)

    def _repr_html_(self) -> str:
        return fatigue_html(self)

    def to_xarray(self):
        """The report as an :class:`xarray.Dataset` (maps, profiles, Ruiz parameters; hot
        spots and lives as attributes): :func:`fretbem.fatigue.labelled.fatigue_dataset`."""
        return fatigue_dataset(self)


def _grid(provider, request: FatigueRequest):
    a = getattr(provider, "contact_half_width", None)
    if (request.map_x is None or request.map_depth is None) and a is None:
        raise FatigueInputError(
            "the parameter map needs map_x and map_depth, or a provider with contact_half_width"
        )
    x0, x1 = request.map_x if request.map_x is not None else (-1.5 * a, 1.5 * a)
    depth = request.map_depth if request.map_depth is not None else a
    nx, nz = request.map_points
    return np.linspace(x0, x1, nx), np.linspace(request.surface_depth, depth, nz)


def _direction(request: FatigueRequest, hot: CriterionResult) -> np.ndarray:
    if request.direction == "depth":
        return np.array([0.0, 1.0])
    theta = np.deg2rad(hot.normal_angle_deg[0])
    # trace of the critical plane in the x-y plane, as [x, depth] (depth = -y), into the body
    d = np.array([-np.sin(theta), -np.cos(theta)])
    return -d if d[1] < 0 else d


def _life(method, result: CriterionResult, index, request) -> LifeEstimate:
    if method in CORRECTIONS_OF:  # the amplitude and mean on the critical plane, corrected
        amplitude = (
            result.normal_stress_amplitude if method == "stress_life"
            else result.normal_strain_amplitude
        )  # fmt: skip
        return estimate_life(
            method,
            float(amplitude[index]),
            request.material,
            mean_stress=float(result.normal_stress_mean[index]),
            correction=request.mean_stress,
            runout_cycles=request.runout_cycles,
        )
    value = float(result.value[index])
    rho = float(result.rho[index]) if method == "mwcm" else None
    return estimate_life(
        method, value, request.material, rho=rho, runout_cycles=request.runout_cycles
    )


#: the hot spot sits at a contact edge, where the tractions converge slowest: its parameter
#: and life carry no estimate of their own
MESH_NOTE = (
    "the hot-spot parameter and life are not convergence-checked: they sit at a contact edge, "
    "where the tractions converge slowest (examples/fretting_rig_ti64.toml, 61 -> 241 pairs: "
    "the SWT hot-spot life 1.69e4 -> 1.36e4 cycles, the critical-distance life 6.04e4 -> "
    "5.9e4); repeat with twice [contact] pairs and compare before relying on the hot-spot "
    "life, or use the critical-distance life"
)


#: the sign convention the hot spot's position depends on (docs/scene-format.md, "Signs")
SIGN_NOTE = (
    "signs: Q > 0 (on the pad, +x) drags the specimen's surface toward +x, so its trailing "
    "edge, where the surface tension peaks, is x = -a (x = +a for Q < 0); sigma_B > 0 in phase "
    "with Q > 0 is the single-actuator rig (the pulled specimen drags the pad)"
)


def run_fatigue(
    provider: StressHistoryProvider, request: FatigueRequest, *, progress=None
) -> FatigueReport:
    """Evaluate ``request`` on the stress history of ``provider``; ``progress(description,
    total)`` (optional) returns a bar advanced after the map and after each method."""
    for member in ("n_steps", "stress_at"):
        if not hasattr(provider, member):
            raise FatigueInputError(f"the stress provider has no {member!r}")
    steps = select_cycle(
        provider.n_steps, driver=getattr(provider, "driver", None), steps=request.cycle_steps
    )
    material = request.material
    notes = list(request.notes)
    body_elastic = getattr(provider, "elastic_constants", None)
    if body_elastic is not None and not (material.has("E") and material.has("nu")):
        material = material.with_values(
            {"E": body_elastic[0], "nu": body_elastic[1]}, source="the stressed body's material"
        )
        request = attrs.evolve(request, material=material)
    elif body_elastic is not None:
        if not np.allclose((material.get("E"), material.get("nu")), body_elastic, rtol=1e-9):
            notes.append(
                f"the fatigue material's E, nu ({material.get('E'):g}, {material.get('nu'):g}) "
                f"differ from the stressed body's {tuple(float(v) for v in body_elastic)}: "
                "strains use the fatigue material's"
            )
    E, nu = material.require(("E", "nu"), "the strains (Hooke's law)").values()
    consts = request.method_constants

    def parameters(points, methods):
        stress = provider.stress_at(np.asarray(points, dtype=float))[steps]
        return critical_plane_parameters(
            stress, E=E, nu=nu, methods=methods, search=request.search, **consts
        )

    xs, zs = _grid(provider, request)
    a = getattr(provider, "contact_half_width", None)
    X, Z = np.meshgrid(xs, zs)
    grid = np.stack([X.ravel(), Z.ravel()], axis=1)
    bar = progress("fatigue", 1 + len(request.methods)) if progress is not None else None
    maps = parameters(grid, request.methods)
    if bar is not None:
        bar.update(1)
    reports = {}
    scan_x = np.linspace(xs[0], xs[-1], SURFACE_SCAN_POINTS)
    if a is not None:  # the contact edges, where closed-form surface peaks sit, exactly
        edges = np.array([-a, a])
        scan_x = np.unique(np.concatenate([scan_x, edges[(edges > xs[0]) & (edges < xs[-1])]]))
    scan = np.stack([scan_x, np.full_like(scan_x, request.surface_depth)], axis=1)
    scan_values = parameters(scan, request.methods) if request.hot_spot == "surface" else None
    for m in request.methods:
        if scan_values is not None:
            i = int(np.argmax(scan_values[m].value))
            lo, hi = scan_x[max(i - 1, 0)], scan_x[min(i + 1, scan_x.size - 1)]
            fine_x = np.unique(np.append(np.linspace(lo, hi, FINE_SCAN_POINTS), scan_x[i]))
            fine = np.stack([fine_x, np.full(fine_x.size, request.surface_depth)], axis=1)
            hot = tuple(fine[int(np.argmax(parameters(fine, (m,))[m].value))])
        else:
            hot = tuple(float(v) for v in request.hot_spot)
        at_hot = parameters(np.array([hot]), (m,))[m]
        direction = _direction(request, at_hot)

        def parameter_at(points, m=m):
            return parameters(points, (m,))[m].value

        L = request.critical_distance
        tcd = None
        if L is not None:
            tcd = critical_distance_values(
                parameter_at,
                hot,
                L,
                direction=direction,
                area_radius_factor=request.area_radius_factor,
            )
        reach = max(4.0 * L if L else 0.0, zs[-1] - hot[1])
        dist = reach * np.linspace(0.0, 1.0, PROFILE_POINTS) ** 2  # finer near the surface
        profile = parameter_at(np.asarray(hot) + dist[:, None] * direction)
        life_hot = life_tcd = None
        message = ""
        try:
            life_hot = _life(m, at_hot, 0, request)
            if tcd is not None:
                at_point = parameters(np.array([tcd.point]), (m,))[m]
                life_tcd = _life(m, at_point, 0, request)
        except MissingFatigueDataError as exc:
            message = f"no life: {exc}"
            notes.append(f"{m}: {message}")
        reports[m] = MethodReport(
            method=m,
            map=maps[m],
            hot_spot=(float(hot[0]), float(hot[1])),
            at_hot_spot=at_hot,
            critical_distance=tcd,
            direction=(float(direction[0]), float(direction[1])),
            profile_distance=dist,
            profile_value=profile,
            life_hot_spot=life_hot,
            life_critical_distance=life_tcd,
            life_message=message,
        )
        if bar is not None:
            bar.update(1)
    ruiz = None
    surface = getattr(provider, "surface_history", None)
    if surface is not None:
        try:
            hist = surface(scan_x)
        except FatigueInputError as exc:
            notes.append(f"Ruiz parameters not computed: {exc}")
        else:
            ruiz = ruiz_parameters(
                hist.x, hist.shear_traction[steps], hist.surface_stress_xx[steps], hist.slip[steps]
            )
    if bar is not None:
        bar.close()
    notes.extend((MESH_NOTE, SIGN_NOTE))
    return FatigueReport(
        request=request,
        cycle_steps=steps,
        map_x=xs,
        map_depth=zs,
        methods=reports,
        ruiz=ruiz,
        notes=tuple(notes),
    )
