"""Labelled views of results: xarray Datasets with CF-style units, netCDF files, and the
short text and HTML display of results in a notebook.

xarray is imported only when a Dataset is made. The modules read results by duck typing
(a run's steps, a stress or fatigue record), so any layer above can use them.
"""

from .cf import VARIABLES, clean_attrs
from .netcdf import read_netcdf, write_netcdf
from .run import run_dataset

__all__ = ["VARIABLES", "clean_attrs", "read_netcdf", "run_dataset", "write_netcdf"]
