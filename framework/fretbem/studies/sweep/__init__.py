"""Parameter sweeps and fretting maps on Dask, resumable from a Parquet store.

The names of :mod:`.run` are re-exported here.
"""

from .run import (
    BLAS_ENV,
    POST_TABLES,
    SweepError,
    SweepResult,
    SweepSummary,
    Task,
    add_arguments,
    machine_cores,
    plan,
    run_command,
    run_sweep,
    sweep,
    sweep_command,
)

__all__ = [
    "BLAS_ENV",
    "POST_TABLES",
    "SweepError",
    "SweepResult",
    "SweepSummary",
    "Task",
    "add_arguments",
    "machine_cores",
    "plan",
    "run_command",
    "run_sweep",
    "sweep",
    "sweep_command",
]
