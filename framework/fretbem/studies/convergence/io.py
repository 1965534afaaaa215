"""Files of the convergence study: its CSV tables and the record of the machine.

Every table of the study (the fixed-pairs runs, the adaptive series, the sawtooth) is a CSV
rewritten after each run, so an interrupted study keeps what it measured.
"""

from __future__ import annotations

import csv
import math
import os
import platform
import re
from collections.abc import Sequence
from pathlib import Path

import numpy as np

STEPS = ("A", "B", "C", "D", "E")
#: steps whose errors are reported (A has no shear)
ERROR_STEPS = ("B", "C", "D", "E")
ERRORS = ("e_p_max", "e_q_max", "e_p_l2", "e_q_l2")
#: columns of convergence.csv, one row per fixed-pairs run
COLUMNS = (
    "family",
    "degree",
    "pairs",
    "bodies",
    "width",
    "height",
    "rest",
    "flank_elements",
    "side_elements",
    "top_elements",
    "dofs",
    *(f"{e}_{s}" for e in ERRORS for s in ERROR_STEPS),
    *ERRORS,
    *(f"iterations_{s}" for s in STEPS),
    "iterations",
    "assembly_s",
    "factorisation_s",
    "condensation_s",
    *(f"solve_{s}_s" for s in STEPS),
    "steps_s",
    "run_s",
    "wall_s",
    "peak_memory_mib",
    "repeats",
    "rest_change_p",
    "rest_change_q",
)
#: columns holding text; every other cell is a number
TEXT = frozenset({"family", "levels"})
_INTEGER = re.compile(r"-?\d+")


def write_csv(rows: Sequence[dict], path: str | Path, columns: Sequence[str] = COLUMNS) -> None:
    """Write ``rows`` with the given columns (missing cells and nan are empty)."""
    with open(path, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(columns), extrasaction="ignore")
        writer.writeheader()
        for row in rows:
            writer.writerow({k: _format(row.get(k)) for k in columns})


def _format(value) -> str:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return ""
    if isinstance(value, float):
        return repr(value)  # always with a '.' or an exponent: read back as a float
    return str(value)


def read_csv(path: str | Path) -> list[dict]:
    """Rows of a study CSV with numbers parsed: integers as int, empty cells as None."""
    rows = []
    with open(path, newline="") as handle:
        for raw in csv.DictReader(handle):
            row = {}
            for key, value in raw.items():
                if key in TEXT:
                    row[key] = value
                elif value in ("", None):
                    row[key] = None
                elif _INTEGER.fullmatch(value):
                    row[key] = int(value)
                else:
                    row[key] = float(value)
            rows.append(row)
    return rows


def machine() -> dict:
    """Cores, platform and versions, for the record."""
    import scipy

    threads = {
        k: os.environ[k]
        for k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")
        if k in os.environ
    }
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else None
    return {
        "cores": os.cpu_count(),
        "platform": platform.platform(),
        "processor": platform.processor() or platform.machine(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "blas_threads_env": threads,
        "load_average_1min": load,
    }


__all__ = ["COLUMNS", "ERRORS", "ERROR_STEPS", "STEPS", "machine", "read_csv", "write_csv"]
