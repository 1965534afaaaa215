"""Up-front memory and time estimates from the DOF count, checked against the machine.

The BEM matrices H and G are dense (dofs x dofs each), and the factorisation and the
condensation hold further dense copies, so the peak memory grows as dofs^2 and the time as
dofs^2 (assembly) plus dofs^3 (factorisation). The coefficients were measured with
``benchmarks/resources.py`` and ``benchmarks/large_problems.py`` (peak resident memory from
``resource.getrusage`` against the DOFs of the reference scene) and carry a margin; they
are estimates to refuse hopeless runs early, not predictions.
"""

from __future__ import annotations

import math
import os

import attrs

from fretbem.errors import ResourceLimitError

#: peak bytes per dofs^2 above the interpreter's own: two dense 8-byte arrays' worth. The
#: peak is H, G and the LU of one body with its parameter block, the other body's response
#: and the condensed maps (H and G are released once a body's contact system is built).
#: Fitted with BYTES_PER_DOF to the peak RSS of benchmarks/large_problems.py (the growth over
#: the imports: 174 MiB at 2236 DOFs, 340 at 4156, 1030 at 7996: 16.9 bytes per dofs^2 at
#: the largest); the estimate is within 0.9-1.15x of those peaks. At 15,676 DOFs (3,841
#: pairs) the peak is 3,335 MiB since the condensation stopped copying the face's response
#: (3,791 before): the estimate, 4,149 MiB, is 1.24x it, kept for its margin at small sizes.
#: Solving a symmetric body as two half systems (:mod:`fretbem.bem.mirror_split`) left the
#: peaks as they were (3,334 MiB at 3,841 pairs, 407 at 961): the peak is not reached while
#: a body's system is solved (at 961 pairs it comes in the Newton steps). A large run keeps
#: its freed arrays' memory on the heap for the next ones (:mod:`fretbem.numerics.memory`):
#: 3,599 MiB at 3,841 pairs, since a freed block does not always fit the next request.
BYTES_PER_DOF2 = 16
#: bytes per DOF: the assembly's and the steps' transients that grow with the boundary
BYTES_PER_DOF = 20_000
#: memory of the interpreter with numpy, scipy and fretbem imported (measured 60 MB)
BASE_BYTES = 100 * 2**20
#: seconds per dofs^2 (assembly, condensation, steps) and per dofs^3 (factorisations),
#: fitted to the CPU seconds of the whole cycle, 3.5 s at 4156 and 18 s at 7996 DOFs, on
#: one BLAS thread (a busy machine stretches the wall time)
SECONDS_PER_DOF2 = 1.2e-7
SECONDS_PER_DOF3 = 2.0e-11
#: refuse when the estimate exceeds this fraction of the available memory
MEMORY_FRACTION = 0.8


@attrs.frozen
class Estimate:
    """Estimated peak memory (bytes) and time (seconds) of a run with ``dofs`` unknowns."""

    dofs: int
    memory: float
    seconds: float
    available: float | None  # bytes the machine can give now (None if unknown)

    @property
    def fits(self) -> bool:
        """True unless the estimate exceeds MEMORY_FRACTION of the known available memory."""
        return self.available is None or self.memory <= MEMORY_FRACTION * self.available

    def describe(self) -> str:
        """One line: DOFs, estimated memory and time, available memory."""
        avail = "unknown" if self.available is None else _size(self.available)
        return (
            f"{self.dofs} boundary DOFs: about {_size(self.memory)} of memory and "
            f"{_duration(self.seconds)} (available memory: {avail})"
        )


def _size(n: float) -> str:
    for unit in ("B", "KB", "MB", "GB", "TB"):
        if n < 1024 or unit == "TB":
            return f"{n:.3g} {unit}"
        n /= 1024
    return f"{n:.3g} TB"  # pragma: no cover


def _duration(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.2g} s"
    if seconds < 7200:
        return f"{seconds / 60:.2g} min"
    return f"{seconds / 3600:.3g} h"


def available_memory() -> float | None:
    """Bytes of memory available now: MemAvailable of /proc/meminfo (None where unreadable)."""
    try:
        with open("/proc/meminfo") as handle:
            for line in handle:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024
    except OSError:
        pass
    try:  # other POSIX systems: free pages (an underestimate of what could be freed)
        return float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return None


def estimate_resources(dofs: int, *, available: float | None = math.nan) -> Estimate:
    """Peak memory and time of a dense BEM run with ``dofs`` boundary unknowns (both bodies).

    ``available`` overrides the machine's free memory (bytes; None for unknown).
    """
    n = float(dofs)
    if available is not None and math.isnan(available):
        available = available_memory()
    return Estimate(
        dofs=int(dofs),
        memory=BASE_BYTES + BYTES_PER_DOF * n + BYTES_PER_DOF2 * n * n,
        seconds=SECONDS_PER_DOF2 * n * n + SECONDS_PER_DOF3 * n**3,
        available=available,
    )


def check_resources(dofs: int, *, available: float | None = math.nan) -> Estimate:
    """The estimate, or ResourceLimitError when it cannot fit in the available memory."""
    estimate = estimate_resources(dofs, available=available)
    if not estimate.fits:
        raise ResourceLimitError(
            f"refusing to start: {estimate.describe()}; the dense BEM matrices grow as "
            "DOFs^2: use fewer pairs (a coarser contact zone) or a machine with more memory"
        )
    return estimate
