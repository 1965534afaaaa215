"""What a fatigue evaluation is asked to do: the record and the ``[fatigue]`` table parser.

A scene file's ``[fatigue]`` table (or a plain dict) becomes a :class:`FatigueRequest` through
:func:`fatigue_request_from_dict`; every key is listed in :data:`REQUEST_KEYS` with its
meaning, and an unknown key is refused by name.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import attrs

from .critical_distance import AREA_RADIUS_FACTOR, critical_distance_from_threshold
from .critical_plane import METHODS, PlaneSearch
from .errors import FatigueInputError, MissingFatigueDataError
from .material import CONSTANTS, FatigueMaterial, load_material

__all__ = ["REQUEST_KEYS", "FatigueRequest", "fatigue_request_from_dict"]

#: the keys of the ``[fatigue]`` table and their meaning
REQUEST_KEYS: dict[str, str] = {
    "material": 'library name (e.g. "Ti-6Al-4V") or an inline table of constants',
    "constants": "table of extra or overriding constants (user input), names as the library's",
    "methods": "list of parameters: swt, findley, fatemi_socie, mwcm (default: all available)",
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


def _pair(value, name, kind=float):
    if not isinstance(value, (list, tuple)) or len(value) != 2:
        raise FatigueInputError(f"[fatigue] {name} must be a list of two numbers, got {value!r}")
    return tuple(kind(v) for v in value)


@attrs.frozen
class FatigueRequest:
    """A fatigue evaluation: material, methods, cycle, critical distance, map and search.

    Attributes are those of :data:`REQUEST_KEYS`; ``material`` is a
    :class:`~fretbem.fatigue.material.FatigueMaterial` and ``search`` a
    :class:`~fretbem.fatigue.critical_plane.PlaneSearch`.
    """

    material: FatigueMaterial
    methods: tuple[str, ...] = METHODS
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

    @property
    def method_constants(self) -> dict[str, float | None]:
        """Findley k, Fatemi-Socie k and yield strength, where the material has them."""
        m = self.material
        return {
            "findley_k": m.get("findley_k") if m.has("findley_k") else None,
            "fatemi_socie_k": m.get("fatemi_socie_k") if m.has("fatemi_socie_k") else None,
            "yield_strength": m.get("yield_strength") if m.has("yield_strength") else None,
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
    return material.with_values(extra) if extra else material


def _available(material: FatigueMaterial) -> tuple[tuple[str, ...], tuple[str, ...]]:
    methods, notes = [], []
    for m in METHODS:
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


def fatigue_request_from_dict(table: Mapping[str, Any]) -> FatigueRequest:
    """A :class:`FatigueRequest` from a ``[fatigue]`` table (keys: :data:`REQUEST_KEYS`)."""
    if not isinstance(table, Mapping):
        raise FatigueInputError(f"[fatigue] must be a table, got {type(table).__name__}")
    unknown = sorted(set(table) - set(REQUEST_KEYS))
    if unknown:
        raise FatigueInputError(
            f"[fatigue] unknown key(s) {unknown}; known: {sorted(REQUEST_KEYS)}"
        )
    material = _material(table)
    notes: tuple[str, ...] = ()
    if "methods" in table:
        methods = table["methods"]
        if isinstance(methods, str):
            methods = [methods]
        methods = tuple(str(m) for m in methods)
    else:
        methods, notes = _available(material)
    L = table.get("critical_distance")
    if L is None and material.has("threshold_sif_range") and material.has("fatigue_limit_range"):
        L = critical_distance_from_threshold(
            material.get("threshold_sif_range"), material.get("fatigue_limit_range")
        )
        notes += (f"L = {L:.4g} mm from Delta K_th and the plain fatigue limit range",)
    elif L is None:
        notes += ("no critical distance: give critical_distance or Delta K_th and Delta sigma_0",)
    hot = table.get("hot_spot", "surface")
    if not isinstance(hot, str):
        hot = _pair(hot, "hot_spot")
    steps = table.get("cycle_steps")
    try:
        return FatigueRequest(
            material=material,
            methods=methods,
            critical_distance=None if L is None else float(L),
            cycle_steps=None if steps is None else tuple(int(s) for s in steps),
            hot_spot=hot,
            direction=str(table.get("direction", "depth")),
            search=PlaneSearch(in_plane_only=bool(table.get("in_plane_only", False))),
            runout_cycles=float(table.get("runout_cycles", 1e7)),
            map_x=_pair(table["map_x"], "map_x") if "map_x" in table else None,
            map_depth=float(table["map_depth"]) if "map_depth" in table else None,
            map_points=_pair(table.get("map_points", (61, 31)), "map_points", int),
            surface_depth=float(table.get("surface_depth", 0.0)),
            area_radius_factor=float(table.get("area_radius_factor", AREA_RADIUS_FACTOR)),
            notes=notes,
        )
    except (TypeError, MissingFatigueDataError) as exc:
        raise FatigueInputError(f"[fatigue] {exc}") from exc
