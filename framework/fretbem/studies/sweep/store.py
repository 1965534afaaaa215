"""The sweep's on-disk store: a manifest and one Parquet file per finished batch of cases.

Each batch is written to a temporary file in the store and renamed into place, so a chunk
is either whole or absent whatever interrupts the sweep; re-running the same sweep reads the
case numbers already stored and solves only the others. The manifest names the sweep by a
fingerprint of its scene, parameters and options, so a store is never completed with the
cases of a different sweep.
"""

from __future__ import annotations

import json
import os
import uuid
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from fretbem.errors import ComputationError

from .cases import TIMING_COLUMNS

FORMAT = "fretbem-sweep/1"
MANIFEST = "manifest.json"


class SweepStoreError(ComputationError):
    """A store that belongs to another sweep, or that cannot be read or written."""


def _atomic_write(path: Path, write) -> None:
    """Write through ``write(temp_path)`` then rename onto ``path`` (same directory)."""
    temp = path.with_name(f".{path.name}.{uuid.uuid4().hex}.tmp")
    try:
        write(temp)
        os.replace(temp, path)
    finally:
        if temp.exists():
            temp.unlink()


class SweepStore:
    """A directory holding one sweep's finished cases."""

    def __init__(self, directory: str | Path, manifest: dict[str, Any]) -> None:
        """Open (creating if needed) the store of the sweep described by ``manifest``.

        ``manifest`` must hold a ``fingerprint``; an existing store with another fingerprint
        is refused rather than mixed with this sweep's cases.
        """
        self.directory = Path(directory)
        path = self.directory / MANIFEST
        if self.directory.exists() and not path.exists():
            if not self.directory.is_dir() or any(self.directory.iterdir()):
                raise SweepStoreError(
                    f"{self.directory} exists and is not a sweep store (no {MANIFEST}); give a "
                    "new or empty output directory, so nothing else is mixed with the results"
                )
        self.directory.mkdir(parents=True, exist_ok=True)
        if path.exists():
            try:
                stored = json.loads(path.read_text())
            except (OSError, ValueError) as err:
                raise SweepStoreError(f"cannot read the sweep manifest {path}: {err}") from err
            if stored.get("fingerprint") != manifest["fingerprint"]:
                raise SweepStoreError(
                    f"{self.directory} holds the results of another sweep (fingerprint "
                    f"{stored.get('fingerprint')}, this sweep is {manifest['fingerprint']}); "
                    "choose another output directory or delete that one"
                )
            self.manifest = stored
        else:
            self.manifest = {"format": FORMAT, **manifest}
            text = json.dumps(self.manifest, indent=2, sort_keys=True, default=str)
            _atomic_write(path, lambda temp: temp.write_text(text))

    def chunks(self) -> list[Path]:
        """The finished chunk files, in name order."""
        return sorted(self.directory.glob("cases-*.parquet"))

    def done(self) -> set[int]:
        """Case numbers already stored."""
        import pyarrow.parquet as pq

        done: set[int] = set()
        for chunk in self.chunks():
            done.update(pq.read_table(chunk, columns=["case"]).column("case").to_pylist())
        return done

    def write(self, rows: Sequence[dict[str, Any]]) -> Path:
        """Store one batch of rows atomically; returns the chunk path."""
        import pandas as pd

        cases = sorted(int(r["case"]) for r in rows)
        path = (
            self.directory / f"cases-{cases[0]:07d}-{cases[-1]:07d}-{uuid.uuid4().hex[:8]}.parquet"
        )
        frame = pd.DataFrame(list(rows))
        _atomic_write(path, lambda temp: frame.to_parquet(temp, engine="pyarrow", index=False))
        return path

    def table(self):
        """Every stored case, one row each, sorted by case number (a pandas DataFrame)."""
        return read_table(self.directory)


def read_table(directory: str | Path):
    """The table of a sweep store (pandas DataFrame, one row per case, by case number)."""
    import pandas as pd

    directory = Path(directory)
    if not (directory / MANIFEST).exists():
        raise SweepStoreError(f"{directory} is not a sweep store (no {MANIFEST})")
    frames = [
        pd.read_parquet(c, engine="pyarrow") for c in sorted(directory.glob("cases-*.parquet"))
    ]
    frames = [f for f in frames if len(f)]
    if not frames:
        return pd.DataFrame({"case": pd.Series([], dtype="int64")})
    table = pd.concat(frames, ignore_index=True)
    table = table.drop_duplicates("case", keep="first").sort_values("case", kind="stable")
    table = table.reset_index(drop=True).infer_objects()
    manifest = json.loads((directory / MANIFEST).read_text())
    return table[_column_order(table.columns, manifest.get("paths", []))]


def _column_order(columns, paths: Sequence[str]) -> list[str]:
    """case, parameters, status and regime, outputs (sorted), then timings: run-independent."""
    front = ["case", *paths, "status", "error", "regime", "friction"]
    front = [c for c in dict.fromkeys(front) if c in columns]
    last = [c for c in TIMING_COLUMNS if c in columns]
    middle = sorted(c for c in columns if c not in front and c not in last)
    return front + middle + last


__all__ = ["MANIFEST", "SweepStore", "SweepStoreError", "read_table"]
