"""Large arrays' memory kept by the allocator for the next one during a large run.

glibc's malloc maps every block above 32 MB afresh (mmap) and unmaps it when freed, so
each large array's pages are faulted in and zeroed by the kernel again; on a virtual
machine that hands freed memory back to its host they are faulted on the host too (0.5-1.1
s of system time per 480 MB array measured here). The 3,841-pair reference cycle allocates
and frees dense arrays of 120-490 MB dozens of times: 15.7 s of its 69 s CPU were system
time. Inside :func:`kept_memory` large blocks come from the heap and a freed one stays
there for the next allocation, and numpy does not ask for transparent huge pages (whose
faults cost more system time here): 3.4 s of system time and 54 s CPU in all, unknowns
bit-identical (one run each, load 5-8). The peak grows, 3,335 -> 3,599 MiB, since a freed
block does not always fit the next request. The memory goes back to the system and the
settings to their defaults when the block ends. Only glibc has these settings; elsewhere
the heap part does nothing.
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import threading

import numpy as np

#: mallopt parameters (glibc malloc.h)
_M_TRIM_THRESHOLD, _M_MMAP_MAX = -1, -4
#: glibc's defaults, restored when the last block ends
_DEFAULT_TRIM_THRESHOLD, _DEFAULT_MMAP_MAX = 128 * 1024, 65536
#: free memory at the top of the heap kept for reuse inside a block (2 GiB - 1: mallopt takes
#: an int)
_KEPT_TRIM_THRESHOLD = 2**31 - 1

#: runs of at least this many boundary DOFs keep their memory (:func:`kept_memory`): their
#: dense (dofs x dofs) arrays of 8-byte numbers exceed glibc's largest mmap threshold, 32 MB
KEPT_MEMORY_DOFS = 2048

_lock = threading.Lock()
_state: dict = {"libc": None, "depth": 0, "huge pages": None}


def _glibc():
    """glibc's handle with mallopt and malloc_trim, or False where there is none."""
    if _state["libc"] is None:
        _state["libc"] = False
        try:
            libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
            libc.gnu_get_libc_version  # noqa: B018 - glibc only
            libc.mallopt.argtypes = (ctypes.c_int, ctypes.c_int)
            libc.malloc_trim.argtypes = (ctypes.c_size_t,)
            _state["libc"] = libc
        except (OSError, AttributeError):
            pass
    return _state["libc"]


@contextlib.contextmanager
def kept_memory(enabled: bool = True):
    """Within the block, large arrays are allocated on the heap and their memory is kept
    for the next ones when freed; returned to the system when the outermost block ends
    (nested and concurrent blocks share one setting). ``enabled`` False (a small run:
    its arrays are below glibc's mmap threshold anyway) does nothing."""
    libc = _glibc() if enabled else False
    if not libc:
        yield
        return
    with _lock:
        if _state["depth"] == 0:
            libc.mallopt(_M_MMAP_MAX, 0)
            libc.mallopt(_M_TRIM_THRESHOLD, _KEPT_TRIM_THRESHOLD)
            _state["huge pages"] = _huge_pages(False)
        _state["depth"] += 1
    try:
        yield
    finally:
        with _lock:
            _state["depth"] -= 1
            if _state["depth"] == 0:
                libc.mallopt(_M_MMAP_MAX, _DEFAULT_MMAP_MAX)
                libc.mallopt(_M_TRIM_THRESHOLD, _DEFAULT_TRIM_THRESHOLD)
                _huge_pages(_state["huge pages"])
                libc.malloc_trim(0)


def _huge_pages(enabled: bool | None) -> bool | None:
    """Set whether numpy asks for transparent huge pages on large arrays (its
    ``_set_madvise_hugepage``, numpy >= 1.20); the previous setting, None where numpy has
    no such switch (then nothing is set)."""
    core = getattr(np, "_core", None) or np.core
    switch = getattr(getattr(core, "multiarray", None), "_set_madvise_hugepage", None)
    if switch is None or enabled is None:
        return None
    return bool(switch(enabled))
