"""A sweep's table as an xarray Dataset indexed by its varied parameters.

In ``product`` mode every combination is one cell of a grid over the parameters (missing or
failed cases are NaN); in ``zip`` mode the cases lie along one ``case`` dimension with the
parameters as coordinates. Every variable carries its unit (:mod:`.units`).
"""

from __future__ import annotations

from collections.abc import Sequence

from fretbem.views.cf import CONVENTIONS, clean_attrs

from .units import unit_of

__all__ = ["sweep_dataset"]


def _cf_unit(unit: str | None) -> dict:
    if unit is None:
        return {}
    return {"units": unit.replace("N/mm", "N mm-1")}


def sweep_dataset(table, paths: Sequence[str], mode: str = "product"):
    """The sweep's ``table`` (pandas, one row per case) as an :class:`xarray.Dataset`."""
    paths = [p for p in paths if p in table.columns]
    grid = mode == "product" and paths and not table.duplicated(paths).any()
    if grid:
        dataset = table.set_index(list(paths)).to_xarray()
    else:
        dataset = table.set_index("case").to_xarray() if "case" in table else table.to_xarray()
        dataset = dataset.set_coords([p for p in paths if p in dataset])
    for name in dataset.variables:
        dataset[name].attrs.update(_cf_unit(unit_of(str(name))))
        if name in paths:
            dataset[name].attrs["long_name"] = f"varied scene key {name}"
    dataset.attrs.update(
        clean_attrs({
            "Conventions": CONVENTIONS,
            "title": "fretbem parameter sweep",
            "mode": mode,
            "parameters": " ".join(paths),
        })
    )  # fmt: skip
    return dataset
