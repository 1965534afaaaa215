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
import time

import attrs

from fretbem.errors import ResourceLimitError

from . import images
from .body import BemBody
from .image_matrices import KEEP_MAX_ROWS
from .integration import LOOP_CHOICE

#: peak bytes per dofs^2 above the interpreter's own (BEM bodies): H, G and the LU of one
#: body with its parameter block, the other body's response and the condensed maps (H and G
#: are released once a body's contact system is built). With BYTES_PER_DOF, BASE_BYTES and
#: COMPILED_BYTES fitted to the peak resident memory of the reference cycle, each run in a
#: fresh process (benchmarks/memory_estimate.py: 61-961 pairs, nurbs and lagrange2; and
#: benchmarks/large_problems.py at 3,841 pairs, 15,676 DOFs, 3,599 MiB with the freed arrays
#: kept on the heap, :mod:`fretbem.numerics.memory`): the estimate is 1.05-1.26x the peak
#: from 244 to 4,408 DOFs and 1.03x at 15,676 (it was 0.72x at 481 nurbs pairs while the
#: numba its assembly loaded went uncounted, and up to 1.49x for the small runs, whose
#: interpreter it counted as 100 MB).
BYTES_PER_DOF2 = 14
#: and while both bodies are small enough for the first one's H and G to be kept for its
#: point image (:data:`~fretbem.bem.image_matrices.KEEP_MAX_ROWS` rows each), those too:
#: 2 x 8 bytes x (dofs / 2)^2 once (at 241 pairs the estimate was 0.99-1.00x the peak
#: without); half that since a pad the mirror split solves keeps only its general parameter
#: columns for its image and the image forms its contact columns only when asked (the peaks
#: fell by 1.5-5 MiB at 241 pairs, 10-29 MiB at 481; with 4 the estimate read 1.37x the
#: peak at 481 lagrange2 pairs, with 2 and IMAGE_BYTES_PER_DOF2 16 it reads 1.05-1.26x)
KEPT_BYTES_PER_DOF2 = 2
#: less, per squared DOF of a body whose H and G are never formed (the point image of the
#: other, :func:`fretbem.bem.system._permuted_parameters`): its own H and G, 2 x 8 bytes
#: (12 while the image still formed its contact columns; benchmarks/memory_estimate.py,
#: both families)
IMAGE_BYTES_PER_DOF2 = 16
#: bytes per DOF: the assembly's and the steps' transients that grow with the boundary
BYTES_PER_DOF = 18_000
#: memory of the interpreter with numpy, scipy and fretbem imported: 63 MiB measured, with
#: 9 MiB of margin (the estimate of the small runs is 1.02-1.16x their peaks)
BASE_BYTES = 72 * 2**20
#: numba's compiled assembly loops in memory (:mod:`fretbem.bem.compiled_loops`): a run
#: whose assembly loads them peaks 99-133 MiB higher than with the numpy loops (numba and
#: llvmlite imported, 54 MiB, and the cached kernels; measured at 241, 481 and 961 pairs)
COMPILED_BYTES = 135 * 2**20
#: bytes per DOF and per DOF^2 of a half-plane body (:mod:`fretbem.halfplane`), which holds
#: no dense body matrices: its face's influence coefficients only. Fitted to the peaks of the
#: reference scene on half-planes, 61-1,921 pairs (a growth over the imports of 4-393 MiB;
#: the estimate 1.09-1.19x the peaks at 61-1,921 pairs; it was 1.55-2.37x at the BEM rates)
HALF_PLANE_BYTES_PER_DOF = 8_000
HALF_PLANE_BYTES_PER_DOF2 = 7
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
    """Bytes of memory available now: MemAvailable of /proc/meminfo (None where unreadable).

    Read as bytes in one system call (its third line): a text file's reader and line
    iteration cost 2-5x the read itself inside a run (40-100 us against 20 us). The reading
    is kept for :func:`_available_for`, through which a scene build's check and a run ask."""
    found = _read_available()
    _RECENT.update(time=time.monotonic(), available=found)
    return found


#: a reading of the available memory at most this old (s) serves again an estimate of at
#: most RECENT_SHARE of it: the scene build and its run each ask within milliseconds, and
#: the read costs 20-90 us of a 61-pair half-plane run (more than its step checks) when it
#: follows the build's allocations; a second does not take nine tenths of it unseen
RECENT_SECONDS = 1.0
RECENT_SHARE = 0.1
_RECENT: dict = {"time": -math.inf, "available": None}


def _available_for(memory: float) -> float | None:
    """The available memory to check an estimate of ``memory`` bytes against: the last
    reading if recent and ``memory`` small against it, else a new one."""
    last = _RECENT["available"]
    if (
        last is not None
        and memory <= RECENT_SHARE * last
        and time.monotonic() - _RECENT["time"] <= RECENT_SECONDS
    ):
        return last
    return available_memory()


def _read_available() -> float | None:
    """:func:`available_memory`'s reading."""
    try:
        handle = os.open("/proc/meminfo", os.O_RDONLY)
        try:
            found = mem_available(os.read(handle, 8192))
        finally:
            os.close(handle)
        if found is not None:
            return found
    except OSError:
        pass
    try:  # other POSIX systems: free pages (an underestimate of what could be freed)
        return float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return None


def mem_available(meminfo: bytes) -> float | None:
    """Bytes of the MemAvailable line of /proc/meminfo's text (kB), None without one."""
    data = b"\n" + meminfo
    start = data.find(b"\nMemAvailable:")
    if start < 0:
        return None
    try:
        return float(data[start + 1 :].split(maxsplit=2)[1]) * 1024
    except (ValueError, IndexError):
        return None


def estimate_resources(
    dofs: int,
    *,
    available: float | None = math.nan,
    half_plane_dofs: int = 0,
    compiled: bool = False,
    image_dofs: int = 0,
) -> Estimate:
    """Peak memory (of the process) and time of a run with ``dofs`` boundary unknowns (both
    bodies), dense BEM bodies unless ``half_plane_dofs`` of them are half-plane bodies';
    ``compiled``: the run's assembly loads numba's compiled loops; ``image_dofs``: those of
    a body whose H and G are never formed (:func:`run_size`).

    ``available`` overrides the machine's free memory (bytes; None for unknown), else read
    (:func:`available_memory`; a reading of the last second serves an estimate of at most
    a tenth of it, :data:`RECENT_SECONDS`).
    """
    n, face = float(dofs - half_plane_dofs), float(half_plane_dofs)
    per_dof2 = BYTES_PER_DOF2 + (KEPT_BYTES_PER_DOF2 if n <= 2 * KEEP_MAX_ROWS else 0)
    memory = BASE_BYTES + BYTES_PER_DOF * n + per_dof2 * n * n
    memory -= IMAGE_BYTES_PER_DOF2 * float(image_dofs) ** 2
    memory += HALF_PLANE_BYTES_PER_DOF * face + HALF_PLANE_BYTES_PER_DOF2 * face * face
    memory += COMPILED_BYTES if compiled else 0
    if available is not None and math.isnan(available):
        available = _available_for(memory)
    n = float(dofs)
    return Estimate(
        dofs=int(dofs),
        memory=memory,
        seconds=SECONDS_PER_DOF2 * n * n + SECONDS_PER_DOF3 * n**3,
        available=available,
    )


def run_size(pair) -> dict:
    """The keywords of :func:`estimate_resources` for a run on ``pair``: its DOFs, those of
    half-plane bodies (those whose segments cover their face alone: ``outline_complete``
    False), and whether its BEM bodies' assembly will load the compiled loops (the process's
    choice, :data:`~fretbem.bem.integration.LOOP_CHOICE`), and the DOFs of a body whose H and
    G are the other's permuted, never formed. Any other body counts as a dense BEM body."""
    dofs = half_plane = work = image = 0
    forced = False
    for body, other in ((pair.upper, None), (pair.lower, pair.upper)):
        count = int(body.dofs)
        dofs += count
        if isinstance(body, BemBody):
            choice = body.integration.compiled  # True, False or None: the process's choice
            forced |= choice is True
            derived = _derived(body, other)
            image += count if derived else 0
            if choice is None and not derived:
                work += body.n_functions * sum(basis.n_elements for basis in body.segments)
        elif not body.outline_complete:  # unknowns on its face alone (a half-plane body)
            half_plane += count
    compiled = forced or (work > 0 and LOOP_CHOICE.compiled(work))
    return {"dofs": dofs, "half_plane_dofs": half_plane, "compiled": compiled,
            "image_dofs": image}  # fmt: skip


def _derived(body: BemBody, other) -> bool:
    """Whether ``body``'s H and G will be permuted from ``other``'s, not assembled (every
    segment discretised as the point image of one of ``other``'s, the same material and
    integration: :mod:`fretbem.bem.image_matrices`): its assembly adds no work toward the
    compiled loops."""
    sources = {id(basis) for basis in getattr(other, "segments", ())}
    return (
        isinstance(other, BemBody)
        and body.dofs <= KEEP_MAX_ROWS
        and body.material == other.material
        and body.integration == other.integration
        and all(id(images.source(basis)) in sources for basis in body.segments)
    )


def check_resources(
    dofs: int,
    *,
    available: float | None = math.nan,
    half_plane_dofs: int = 0,
    compiled: bool = False,
    image_dofs: int = 0,
) -> Estimate:
    """The estimate, or ResourceLimitError when it cannot fit in the available memory."""
    estimate = estimate_resources(
        dofs, available=available, half_plane_dofs=half_plane_dofs, compiled=compiled,
        image_dofs=image_dofs,
    )  # fmt: skip
    if not estimate.fits:
        raise ResourceLimitError(
            f"refusing to start: {estimate.describe()}; the dense BEM matrices grow as "
            "DOFs^2: use fewer pairs (a coarser contact zone) or a machine with more memory"
        )
    return estimate
