"""The ``netcdf`` writer: the run (results.nc), its stresses (stress.nc) and its fatigue
report (fatigue.nc) as labelled netCDF files (:mod:`fretbem.views`)."""

from __future__ import annotations

from pathlib import Path

from fretbem.views.netcdf import write_netcdf

__all__ = ["write_netcdf_files"]


def write_netcdf_files(context, directory: Path, stress=None) -> list[Path]:
    """results.nc, and stress.nc (``stress``: the run's evaluated StressResult) and
    fatigue.nc when the run carries them."""
    directory = Path(directory)
    paths = [write_netcdf(context.result.to_xarray(), directory / "results.nc")]
    if stress is not None:
        paths.append(write_netcdf(stress.to_xarray(), directory / "stress.nc"))
    if context.fatigue is not None:
        paths.append(write_netcdf(context.fatigue.to_xarray(), directory / "fatigue.nc"))
    return paths
