"""Fretting fatigue from a computed stress cycle: critical planes, critical distances, life.

Typical use::

    from fretbem.fatigue import fatigue_request_from_dict, run_fatigue, write_fatigue

    request = fatigue_request_from_dict({"material": "Ti-6Al-4V", "critical_distance": 0.05})
    report = run_fatigue(provider, request)     # any StressHistoryProvider
    write_fatigue("out", report)

The building blocks take plain arrays: :func:`critical_plane_parameters` on a stress history
(n_steps, n_points, 4), :func:`ruiz_parameters`, :func:`critical_distance_values` with any
``parameter_at(points)`` callable, and :func:`estimate_life` (with the mean-stress corrections
of :mod:`.mean_stress` for the stress- and strain-life curves).
"""

from .critical_distance import (
    AREA_RADIUS_FACTOR,
    CriticalDistanceValues,
    critical_distance_from_threshold,
    critical_distance_values,
)
from .critical_plane import (
    DEFAULT_METHODS,
    METHODS,
    CriterionResult,
    PlaneSearch,
    critical_plane_parameters,
)
from .cycle import last_full_reversal, select_cycle, turning_points
from .errors import FatigueInputError, MissingFatigueDataError
from .life import LifeEstimate, estimate_life
from .material import FatigueMaterial, available_materials, load_material
from .mcc import minimum_circumscribed_circle
from .mean_stress import CORRECTIONS, MeanStressCorrection, mean_stress_correction
from .output import fatigue_summary, format_report, write_fatigue
from .providers import (
    CattaneoMindlinCycle,
    GridStressHistory,
    StressHistoryProvider,
    SurfaceHistory,
)
from .request import REQUEST_KEYS, FatigueRequest, fatigue_request_from_dict
from .ruiz import RuizParameters, ruiz_parameters
from .run import FatigueReport, MethodReport, run_fatigue

__all__ = [
    "AREA_RADIUS_FACTOR",
    "CORRECTIONS",
    "DEFAULT_METHODS",
    "METHODS",
    "REQUEST_KEYS",
    "CattaneoMindlinCycle",
    "CriterionResult",
    "CriticalDistanceValues",
    "FatigueInputError",
    "FatigueMaterial",
    "FatigueReport",
    "FatigueRequest",
    "GridStressHistory",
    "LifeEstimate",
    "MeanStressCorrection",
    "MethodReport",
    "MissingFatigueDataError",
    "PlaneSearch",
    "RuizParameters",
    "StressHistoryProvider",
    "SurfaceHistory",
    "available_materials",
    "critical_distance_from_threshold",
    "critical_distance_values",
    "critical_plane_parameters",
    "estimate_life",
    "fatigue_request_from_dict",
    "fatigue_summary",
    "format_report",
    "last_full_reversal",
    "load_material",
    "mean_stress_correction",
    "minimum_circumscribed_circle",
    "ruiz_parameters",
    "run_fatigue",
    "select_cycle",
    "turning_points",
    "write_fatigue",
]
