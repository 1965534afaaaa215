"""Up-front memory and time estimates of stress evaluations, refused with the estimate.

A body's stress operator at m points holds about 3 x 2 x DOFs numbers per point (three
stress components from the boundary displacements and tractions), and building it costs
about 1.6e-7 s per point and DOF (measured on the reference scene's 556 DOFs, 1600 points:
27 bytes and 1.6e-7 s per point and DOF; the memory below is the array's 48 bytes). A
request (``[stress]`` points, lines and grid, or the ``[fatigue]`` map) whose operator
cannot fit in memory is refused before the contact problem is solved.
"""

from __future__ import annotations

import math

from fretbem.bem import resources
from fretbem.bem.resources import MEMORY_FRACTION, _duration, _size
from fretbem.errors import ResourceLimitError

__all__ = ["BYTES_PER_POINT_DOF", "check_points", "request_points"]

#: bytes of the stress operator per evaluation point and boundary DOF
BYTES_PER_POINT_DOF = 48
#: seconds to build the operator per point and DOF (one BLAS thread)
SECONDS_PER_POINT_DOF = 1.6e-7


def request_points(request) -> int:
    """Evaluation points of a StressRequest (points, lines, grid)."""
    if request is None:
        return 0
    count = 0 if request.points is None else len(request.points)
    count += sum(line.n for line in request.lines)
    if request.grid is not None:
        count += request.grid.nx * request.grid.ny
    return count


def check_points(points: int, dofs: int, where: str, *, available: float | None = math.nan):
    """Refuse ``points`` evaluation points on a body of ``dofs`` when they cannot fit."""
    if available is not None and math.isnan(available):
        available = resources.available_memory()
    memory = float(points) * max(int(dofs), 1) * BYTES_PER_POINT_DOF
    seconds = float(points) * max(int(dofs), 1) * SECONDS_PER_POINT_DOF
    if available is not None and memory > MEMORY_FRACTION * available:
        raise ResourceLimitError(
            f"refusing to start: {where} asks for {points} stress points on a body of {dofs} "
            f"boundary DOFs, estimated {_size(memory)} of memory and {_duration(seconds)} for "
            f"the stress operator (available memory: {_size(available)}); ask for fewer "
            "points (a coarser grid, or a line where a profile is enough)"
        )
    return memory, seconds
