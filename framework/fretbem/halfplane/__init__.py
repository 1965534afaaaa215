"""The elastic half-plane: closed-form surface influence coefficients, no boundary to mesh."""

from .body import BULK, HalfPlaneBody, HalfPlaneSolution
from .influence import (
    FlamantCompliance,
    HalfPlaneFaceError,
    line_load_displacement,
    surface_integrals,
)
from .surface import HalfPlaneSurface

__all__ = [
    "BULK",
    "FlamantCompliance",
    "HalfPlaneBody",
    "HalfPlaneFaceError",
    "HalfPlaneSolution",
    "HalfPlaneSurface",
    "line_load_displacement",
    "surface_integrals",
]
