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

_state: dict = {"controller": None, "scipy": False}


def one_blas_thread():
    """Context manager limiting every loaded BLAS to one thread (restored on exit); nothing
    to do when each runs one already (``OPENBLAS_NUM_THREADS=1``): asking each library its
    count costs ~1 us, the limit's own bookkeeping ~50 us."""
    scipy_loaded = "scipy.linalg" in sys.modules
    if _state["controller"] is None or (scipy_loaded and not _state["scipy"]):
        _state["controller"] = ThreadpoolController()
        _state["scipy"] = scipy_loaded
    controller = _state["controller"]
    blas = [lib for lib in controller.lib_controllers if lib.user_api == "blas"]
    if all(lib.num_threads == 1 for lib in blas):
        return contextlib.nullcontext()
    return controller.limit(limits=1, user_api="blas")
