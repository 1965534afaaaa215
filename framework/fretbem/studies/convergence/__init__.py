"""The convergence study: speed against error for both families and the adaptive mode.

The names of :mod:`.study` are re-exported here.
"""

from .study import (
    COLUMNS,
    FAMILIES,
    AdaptiveCase,
    Case,
    StudyPlan,
    measure,
    read_csv,
    run_study,
    traction_change,
    write_csv,
)

__all__ = [
    "COLUMNS",
    "FAMILIES",
    "AdaptiveCase",
    "Case",
    "StudyPlan",
    "measure",
    "read_csv",
    "run_study",
    "traction_change",
    "write_csv",
]
