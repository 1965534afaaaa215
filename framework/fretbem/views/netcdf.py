"""netCDF files of labelled results, through xarray's scipy backend (netCDF-3: no library
beyond scipy, which fretbem already needs)."""

from __future__ import annotations

import os
from pathlib import Path

__all__ = ["ENGINE", "read_netcdf", "write_netcdf"]

ENGINE = "scipy"


def write_netcdf(dataset, path: str | os.PathLike) -> Path:
    """Write ``dataset`` to ``path`` (netCDF-3 64-bit offset); returns the path."""
    path = Path(path)
    dataset.to_netcdf(path, engine=ENGINE)
    return path


def read_netcdf(path: str | os.PathLike):
    """The Dataset in a netCDF file, loaded into memory (the file is closed on return)."""
    import xarray as xr

    with xr.open_dataset(path, engine=ENGINE) as dataset:
        return dataset.load()
