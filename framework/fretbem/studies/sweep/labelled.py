"""A sweep's table as an xarray Dataset indexed by its varied parameters.

In ``product`` mode every combination is one cell of a grid over the parameters (missing or
failed cases are NaN); in ``zip`` mode the cases lie along one ``case`` dimension with the
parameters as coordinates. Every variable carries its unit (:mod:`.units`).
"""

from __future__ import annotations

import html
from collections.abc import Sequence

from fretbem.views.cf import CONVENTIONS, clean_attrs
from fretbem.views.display import html_table

from .units import unit_of

__all__ = ["sweep_dataset", "sweep_html", "sweep_repr"]

#: table rows shown in a notebook
SHOWN_ROWS = 10


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
        clean_attrs(
            {
                "Conventions": CONVENTIONS,
                "title": "fretbem parameter sweep",
                "mode": mode,
                "parameters": " ".join(paths),
            }
        )
    )
    return dataset


def sweep_repr(result) -> str:
    """One line: cases stored of the total, statuses, regimes, the varied parameters."""
    summary = result.summary
    status = ", ".join(f"{n} {k}" for k, n in sorted(summary.status.items()))
    regimes = ", ".join(f"{n} {k}" for k, n in summary.regimes.items() if n)
    return (
        f"<SweepResult {summary.stored}/{summary.cases} cases ({status}); "
        f"parameters {' x '.join(result.spec.paths)}; regimes {regimes or 'none'}>"
    )


def sweep_html(result) -> str:
    """The summary lines and the first rows of the table (parameters, regime, status)."""
    table = result.table
    paths = [p for p in result.spec.paths if p in table]
    columns = [*paths, *(c for c in ("regime", "status", "P_max", "Q_peak") if c in table)]
    rows = [
        tuple(_cell(v) for v in row)
        for row in table[columns].head(SHOWN_ROWS).itertuples(index=False)
    ]
    if len(table) > SHOWN_ROWS:
        rows.append((f"... {len(table) - SHOWN_ROWS} more cases (result.table) ...",))
    head = "".join(f"<div>{html.escape(line)}</div>" for line in str(result.summary).splitlines())
    header = [f"{c} ({unit_of(c)})" if unit_of(c) not in (None, "1") else c for c in columns]
    return f"<div><b>SweepResult</b>{head}{html_table(header, rows)}</div>"


def _cell(value) -> str:
    if isinstance(value, float):
        return f"{value:.4g}"
    return str(value)
