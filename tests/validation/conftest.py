"""The validation table: tests record (case, quantity, tolerance, measured, pass) rows.

``record(case, quantity, measured, tolerance, page=...)`` returns whether measured <=
tolerance, so a test asserts exactly what its row says. Rows are written only when the
environment variable FRETBEM_VALIDATION_TABLE names a JSON file (set by
``python tests/validation/make_table.py``, which renders docs/validation-table.md); an
ordinary test run writes nothing.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

import pytest

TABLE_ENV = "FRETBEM_VALIDATION_TABLE"
_ROWS: dict[tuple[str, str], dict] = {}


def _significant(value: float, digits: int = 2) -> float:
    """Round to ``digits`` significant figures (the table must not change with the machine)."""
    if value == 0 or not math.isfinite(value):
        return value
    return round(value, digits - 1 - math.floor(math.log10(abs(value))))


@pytest.fixture
def record():
    """Record one row of the validation table; returns measured <= tolerance."""

    def add(case: str, quantity: str, measured: float, tolerance: float, *, page: str) -> bool:
        measured, tolerance = float(measured), float(tolerance)
        passed = bool(measured <= tolerance)
        _ROWS[(case, quantity)] = {
            "case": case,
            "quantity": quantity,
            "tolerance": _significant(tolerance),
            "measured": _significant(measured),
            "pass": passed,
            "page": page,
        }
        return passed

    return add


def pytest_sessionfinish(session, exitstatus):
    target = os.environ.get(TABLE_ENV)
    if not target or not _ROWS:
        return
    path = Path(target)
    rows = json.loads(path.read_text()) if path.exists() else []
    merged = {(r["case"], r["quantity"]): r for r in rows}
    merged.update(_ROWS)
    ordered = [merged[k] for k in sorted(merged)]
    path.write_text(json.dumps(ordered, indent=1, sort_keys=True) + "\n")
