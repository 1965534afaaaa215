"""The ``netcdf`` writer: the run (results.nc), its stresses (stress.nc) and its fatigue
report (fatigue.nc) as labelled netCDF files (:mod:`fretbem.views`)."""

from __future__ import annotations

from pathlib import Path

from fretbem.stress.run import evaluate_stress_request
from fretbem.views.netcdf import write_netcdf

__all__ = ["evaluated_stress", "write_netcdf_files"]


def evaluated_stress(context):
    """The run's StressResult, evaluated once per write (writers share it)."""
    if context.stress is None:
        return None
    if "stress" not in context.cache:
        context.cache["stress"] = evaluate_stress_request(
            context.result, context.stress, progress=context.progress
        )
    return context.cache["stress"]


def write_netcdf_files(context, directory: Path) -> list[Path]:
    """results.nc, and stress.nc and fatigue.nc when the run carries them."""
    directory = Path(directory)
    paths = [write_netcdf(context.result.to_xarray(), directory / "results.nc")]
    stress = evaluated_stress(context)
    if stress is not None:
        paths.append(write_netcdf(stress.to_xarray(), directory / "stress.nc"))
    if context.fatigue is not None:
        paths.append(write_netcdf(context.fatigue.to_xarray(), directory / "fatigue.nc"))
    return paths
