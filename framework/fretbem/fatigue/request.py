"""What a fatigue evaluation is asked to do: the record and the ``[fatigue]`` table parser.

A scene file's ``[fatigue]`` table (or a plain dict) becomes a :class:`FatigueRequest` through
:func:`fatigue_request_from_dict`; every key is listed in :data:`REQUEST_KEYS` with its
meaning, and an unknown key is refused by name.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import attrs

from fretbem.validators import file_bool, file_integer, file_list, file_number, file_string

from .critical_distance import AREA_RADIUS_FACTOR, critical_distance_from_threshold
from .critical_plane import DEFAULT_METHODS, METHODS, PlaneSearch
from .errors import FatigueInputError, MissingFatigueDataError
from .material import CONSTANTS, FatigueMaterial, load_material
from .mean_stress import CORRECTIONS, CORRECTIONS_OF, MeanStressCorrection, mean_stress_correction

__all__ = ["REQUEST_KEYS", "FatigueRequest", "fatigue_request_from_dict"]

#: the keys of the ``[fatigue]`` table and their meaning
REQUEST_KEYS: dict[str, str] = {
    "material": 'library name (e.g. "Ti-6Al-4V") or an inline table of constants',
    "constants": "table of extra or overriding constants (user input), names as the library's",
    "methods": "list of parameters: swt, findley, fatemi_socie, mwcm, stress_life, strain_life "
    "(default: the first four that the material's constants allow)",
    "mean_stress": 'mean-stress correction of stress_life / strain_life: "none" (default), '
    '"goodman", "gerber", "morrow", "morrow_true_fracture" (stress_life only)',
    "critical_distance": "L in mm (else from threshold_sif_range and fatigue_limit_range)",
    "cycle_steps": "list of step indices forming the cycle (default: last full reversal)",
    "hot_spot": '"surface" (largest parameter on the surface) or [x, depth] in mm',
    "direction": 'critical direction from the hot spot: "depth" or "critical_plane"',
    "in_plane_only": "search only planes containing z (the 2D restriction); default false",
    "runout_cycles": "lives beyond this are run-outs (default 1e7)",
    "map_x": "[x_min, x_max] of the parameter map, mm (default +-1.5 a)",
    "map_depth": "depth of the parameter map, mm (default a)",
    "map_points": "[nx, ndepth] of the parameter map (default [61, 31])",
    "surface_depth": "depth of the surface scan for the hot spot, mm (default 0)",
    "area_radius_factor": "area-method radius in units of L (default 1.32, Taylor)",
}


@attrs.frozen
class FatigueRequest:
    """A fatigue evaluation: material, methods, cycle, critical distance, map and search.

    Attributes are those of :data:`REQUEST_KEYS`; ``material`` is a
    :class:`~fretbem.fatigue.material.FatigueMaterial` and ``search`` a
    :class:`~fretbem.fatigue.critical_plane.PlaneSearch`.
    """

    material: FatigueMaterial
    methods: tuple[str, ...] = DEFAULT_METHODS
    mean_stress: str = "none"
    critical_distance: float | None = None
    cycle_steps: tuple[int, ...] | None = None
    hot_spot: str | tuple[float, float] = "surface"
    direction: str = "depth"
    search: PlaneSearch = attrs.field(factory=PlaneSearch)
    runout_cycles: float = 1e7
    map_x: tuple[float, float] | None = None
    map_depth: float | None = None
    map_points: tuple[int, int] = (61, 31)
    surface_depth: float = 0.0
    area_radius_factor: float = AREA_RADIUS_FACTOR
    notes: tuple[str, ...] = ()

    def __attrs_post_init__(self) -> None:
        for m in self.methods:
            if m not in METHODS:
                raise FatigueInputError(f"unknown fatigue method {m!r}; choose from {METHODS}")
        if self.direction not in ("depth", "critical_plane"):
            raise FatigueInputError(
                f'direction must be "depth" or "critical_plane", got {self.direction!r}'
            )
        if isinstance(self.hot_spot, str) and self.hot_spot != "surface":
            raise FatigueInputError(
                f'hot_spot must be "surface" or [x, depth], got {self.hot_spot!r}'
            )
        if self.critical_distance is not None and not self.critical_distance > 0:
            raise FatigueInputError(
                f"critical_distance must be > 0 mm, got {self.critical_distance}"
            )
        if min(self.map_points) < 2:
            raise FatigueInputError(f"map_points must be >= 2 each, got {self.map_points}")
        self._check_mean_stress()

    def _check_mean_stress(self) -> None:
        """The correction is known, fits every listed life method, and has its constant."""
        name = self.mean_stress
        if name not in CORRECTIONS:
            raise FatigueInputError(
                f"[fatigue] mean_stress must be one of {sorted(CORRECTIONS)}, got {name!r}"
            )
        if name == "none":
            return
        takers = [m for m in self.methods if m in CORRECTIONS_OF]
        if not takers:
            raise FatigueInputError(
                f'[fatigue] mean_stress = "{name}" corrects the stress_life and strain_life '
                f"methods, and methods = {list(self.methods)} has neither (SWT, Findley, "
                "Fatemi-Socie and MWCM carry the mean stress themselves): add "
                '"stress_life" (or "strain_life" for morrow) to methods, or remove mean_stress'
            )
        for m in takers:
            if name not in CORRECTIONS_OF[m]:
                raise FatigueInputError(
                    f'[fatigue] mean_stress = "{name}" does not apply to {m}, which takes '
                    f"{list(CORRECTIONS_OF[m])}: the strain-life curve is corrected by Morrow "
                    "(sigma_f' - sigma_m); use a separate run for the other method"
                )
        try:
            mean_stress_correction(name, self.material)
        except MissingFatigueDataError as exc:
            raise FatigueInputError(f"[fatigue] mean_stress: {exc}") from exc

    @property
    def mean_stress_correction(self) -> MeanStressCorrection:
        """The mean-stress correction with its limit stress from the material."""
        return mean_stress_correction(self.mean_stress, self.material)

    @property
    def method_constants(self) -> dict[str, Any]:
        """Findley k, Fatemi-Socie k and yield strength, where the material has them, and the
        mean-stress correction of stress_life."""
        m = self.material
        return {
            "findley_k": m.get("findley_k") if m.has("findley_k") else None,
            "fatemi_socie_k": m.get("fatemi_socie_k") if m.has("fatemi_socie_k") else None,
            "yield_strength": m.get("yield_strength") if m.has("yield_strength") else None,
            "mean_stress": self.mean_stress_correction,
        }


def _material(table: Mapping[str, Any]) -> FatigueMaterial:
    spec = table.get("material")
    if spec is None:
        raise FatigueInputError(
            '[fatigue] needs material = "<library name>" or an inline table of constants'
        )
    if isinstance(spec, str):
        material = load_material(spec)
    elif isinstance(spec, Mapping):
        material = FatigueMaterial.from_table("user", spec)
    else:
        raise FatigueInputError(f"[fatigue] material must be a name or a table, got {spec!r}")
    extra = table.get("constants", {})
    if not isinstance(extra, Mapping):
        raise FatigueInputError("[fatigue] constants must be a table of numbers")
    bad = sorted(set(extra) - set(CONSTANTS))
    if bad:
        raise FatigueInputError(f"[fatigue.constants] unknown {bad}; known: {sorted(CONSTANTS)}")
    extra = {k: file_number(f"[fatigue.constants] {k}", v, error=FatigueInputError)
             for k, v in extra.items()}  # fmt: skip
    return material.with_values(extra) if extra else material


def _available(material: FatigueMaterial) -> tuple[tuple[str, ...], tuple[str, ...]]:
    methods, notes = [], []
    for m in DEFAULT_METHODS:
        need = {
            "findley": ("findley_k",),
            "fatemi_socie": ("fatemi_socie_k", "yield_strength"),
        }.get(m, ())
        missing = [k for k in need if not material.has(k)]
        if missing:
            notes.append(f"{m} left out: the material has no {missing}")
        else:
            methods.append(m)
    return tuple(methods), tuple(notes)


def _pair_of(table: Mapping[str, Any], key: str, item) -> tuple:
    return tuple(file_list(f"[fatigue] {key}", table[key], item, length=2, error=FatigueInputError))


def _number(**limits):
    return lambda where, v: file_number(where, v, error=FatigueInputError, **limits)


def _values(table: Mapping[str, Any]) -> dict[str, Any]:
    """Every key of the table checked for its type and range (the key named in the message)."""
    out: dict[str, Any] = {}
    if "methods" in table:
        methods = table["methods"]
        methods = [methods] if isinstance(methods, str) else methods
        out["methods"] = tuple(
            file_list(
                "[fatigue] methods",
                methods,
                lambda w, v: file_string(w, v, METHODS, error=FatigueInputError),
                min_length=1,
                error=FatigueInputError,
            )
        )
    if "mean_stress" in table:
        out["mean_stress"] = file_string(
            "[fatigue] mean_stress", table["mean_stress"], tuple(CORRECTIONS),
            error=FatigueInputError,
        )  # fmt: skip
    if "critical_distance" in table:
        out["critical_distance"] = _number(low=0.0, low_open=True, why="L in mm")(
            "[fatigue] critical_distance", table["critical_distance"]
        )
    if "cycle_steps" in table:
        integer = lambda w, v: file_integer(w, v, low=0, error=FatigueInputError)  # noqa: E731
        out["cycle_steps"] = tuple(
            file_list("[fatigue] cycle_steps", table["cycle_steps"], integer, min_length=2,
                      error=FatigueInputError)
        )  # fmt: skip
    if "hot_spot" in table:
        hot = table["hot_spot"]
        if isinstance(hot, str):
            out["hot_spot"] = file_string("[fatigue] hot_spot", hot, ("surface",),
                                          error=FatigueInputError)  # fmt: skip
        else:
            x, depth = _pair_of(table, "hot_spot", _number())
            file_number("[fatigue] hot_spot depth", depth, low=0.0, error=FatigueInputError)
            out["hot_spot"] = (x, depth)
    if "direction" in table:
        out["direction"] = file_string(
            "[fatigue] direction", table["direction"], ("depth", "critical_plane"),
            error=FatigueInputError,
        )  # fmt: skip
    if "in_plane_only" in table:
        out["in_plane_only"] = file_bool(
            "[fatigue] in_plane_only", table["in_plane_only"], error=FatigueInputError
        )
    if "runout_cycles" in table:
        out["runout_cycles"] = _number(low=1.0, low_open=True, why="cycles")(
            "[fatigue] runout_cycles", table["runout_cycles"]
        )
    if "map_x" in table:
        out["map_x"] = _pair_of(table, "map_x", _number())
        if not out["map_x"][0] < out["map_x"][1]:
            raise FatigueInputError(
                f"[fatigue] map_x must be [x_min, x_max] with x_min < x_max, got {table['map_x']}"
            )
    if "map_depth" in table:
        out["map_depth"] = _number(low=0.0, low_open=True, why="mm below the surface")(
            "[fatigue] map_depth", table["map_depth"]
        )
    if "map_points" in table:
        count = lambda w, v: file_integer(w, v, low=2, error=FatigueInputError)  # noqa: E731
        out["map_points"] = _pair_of(table, "map_points", count)
    if "surface_depth" in table:
        out["surface_depth"] = _number(low=0.0, why="mm below the surface")(
            "[fatigue] surface_depth", table["surface_depth"]
        )
    if "area_radius_factor" in table:
        out["area_radius_factor"] = _number(
            low=0.0, high=10.0, low_open=True,
            why="the area-method radius in units of L; Taylor's value is 1.32",
        )("[fatigue] area_radius_factor", table["area_radius_factor"])  # fmt: skip
    return out


def fatigue_request_from_dict(table: Mapping[str, Any]) -> FatigueRequest:
    """A :class:`FatigueRequest` from a ``[fatigue]`` table (keys: :data:`REQUEST_KEYS`).

    Every value is checked for its type and range, without coercion (``2.7`` is not a
    count, ``"false"`` is not a boolean); the message names the key.
    """
    if not isinstance(table, Mapping):
        raise FatigueInputError(f"[fatigue] must be a table, got {type(table).__name__}")
    unknown = sorted(set(table) - set(REQUEST_KEYS))
    if unknown:
        raise FatigueInputError(
            f"[fatigue] unknown key(s) {unknown}; known: {sorted(REQUEST_KEYS)}"
        )
    values = _values(table)
    material = _material(table)
    notes: tuple[str, ...] = ()
    if "methods" in values:
        methods = values["methods"]
    else:
        methods, notes = _available(material)
    L = values.get("critical_distance")
    if L is None and material.has("threshold_sif_range") and material.has("fatigue_limit_range"):
        L = critical_distance_from_threshold(
            material.get("threshold_sif_range"), material.get("fatigue_limit_range")
        )
        notes += (f"L = {L:.4g} mm from Delta K_th and the plain fatigue limit range",)
    elif L is None:
        notes += ("no critical distance: give critical_distance or Delta K_th and Delta sigma_0",)
    try:
        return FatigueRequest(
            material=material,
            methods=methods,
            mean_stress=values.get("mean_stress", "none"),
            critical_distance=None if L is None else float(L),
            cycle_steps=values.get("cycle_steps"),
            hot_spot=values.get("hot_spot", "surface"),
            direction=values.get("direction", "depth"),
            search=PlaneSearch(in_plane_only=values.get("in_plane_only", False)),
            runout_cycles=values.get("runout_cycles", 1e7),
            map_x=values.get("map_x"),
            map_depth=values.get("map_depth"),
            map_points=values.get("map_points", (61, 31)),
            surface_depth=values.get("surface_depth", 0.0),
            area_radius_factor=values.get("area_radius_factor", AREA_RADIUS_FACTOR),
            notes=notes,
        )
    except (TypeError, MissingFatigueDataError) as exc:
        raise FatigueInputError(f"[fatigue] {exc}") from exc
