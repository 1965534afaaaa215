"""one_blas_thread limits every loaded BLAS, scipy's included, and restores it."""

import numpy as np
import scipy.linalg  # noqa: F401 - its BLAS must be covered too
from threadpoolctl import threadpool_info

from fretbem.numerics.blas import one_blas_thread


def _blas_threads():
    return [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"]


def test_one_thread_inside_and_restored_after():
    before = _blas_threads()
    assert before
    with one_blas_thread():
        assert set(_blas_threads()) == {1}
        np.linalg.solve(np.eye(3) * 2.0, np.ones(3))
    assert _blas_threads() == before
    with one_blas_thread():  # reused controller
        assert set(_blas_threads()) == {1}


def test_limits_a_blas_running_more_threads_and_restores_it():
    """Under OPENBLAS_NUM_THREADS=1 the limit has nothing to do; with two threads it acts."""
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=2, user_api="blas"):
        before = _blas_threads()
        with one_blas_thread():
            assert set(_blas_threads()) == {1}
        assert _blas_threads() == before
