"""One BLAS thread around dense factorisations and solves, cheaply.

On a machine shared with other work, OpenBLAS's default of one thread per core made a
278 x 278 LU 60x slower (threads waiting for busy cores); the dense problems here are small
enough that one thread loses little when the machine is idle. ``threadpool_limits`` rescans
the loaded libraries on every entry (0.5-4 ms); a ThreadpoolController kept between calls
does not, and is rebuilt only when scipy.linalg, which brings its own BLAS, has been
imported since.
"""

from __future__ import annotations

import contextlib
import sys

from threadpoolctl import ThreadpoolController

_state: dict = {"controller": None, "blas": (), "scipy": False}


def one_blas_thread():
    """Context manager limiting every loaded BLAS to one thread (restored on exit); nothing
    to do when each already runs one (``OPENBLAS_NUM_THREADS=1``, or inside another such
    block): asking each library its count costs ~1 us where a limit's entry and exit, which
    read every library's whole description, cost ~30 us (six per reference cycle)."""
    scipy_loaded = "scipy.linalg" in sys.modules
    if _state["controller"] is None or (scipy_loaded and not _state["scipy"]):
        _state["controller"] = ThreadpoolController()
        _state["blas"] = tuple(_state["controller"].select(user_api="blas").lib_controllers)
        _state["scipy"] = scipy_loaded
    if all(library.num_threads == 1 for library in _state["blas"]):
        return contextlib.nullcontext()
    return _state["controller"].limit(limits=1, user_api="blas")
