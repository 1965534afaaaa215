"""Writing a run: staging and locks, the writers (CSV, JSON, figures, VTK).

The names of :mod:`.write` are re-exported here.
"""

from .write import (
    CSV_COLUMNS,
    MARKER,
    SPACE_MARGIN,
    STATE_NAMES,
    SUMMARY_KEYS,
    OutputError,
    OutputExistsError,
    OutputLockedError,
    Writer,
    check_free_space,
    csv_cell,
    output_lock,
    prepare_output,
    register_writer,
    staged_directory,
    write_csv,
    write_json,
    write_results,
    write_units,
)

__all__ = [
    "CSV_COLUMNS",
    "MARKER",
    "SPACE_MARGIN",
    "STATE_NAMES",
    "SUMMARY_KEYS",
    "OutputError",
    "OutputExistsError",
    "OutputLockedError",
    "Writer",
    "check_free_space",
    "csv_cell",
    "output_lock",
    "prepare_output",
    "register_writer",
    "staged_directory",
    "write_csv",
    "write_json",
    "write_results",
    "write_units",
]
