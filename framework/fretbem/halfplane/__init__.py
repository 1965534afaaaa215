"""The elastic half-plane: closed-form surface influence coefficients, no boundary to mesh."""

from .influence import (
    FlamantCompliance,
    HalfPlaneFaceError,
    line_load_displacement,
    surface_integrals,
)
from .surface import HalfPlaneSurface

__all__ = [
    "FlamantCompliance",
    "HalfPlaneFaceError",
    "HalfPlaneSurface",
    "line_load_displacement",
    "surface_integrals",
]
