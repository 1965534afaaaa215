"""The ``fretbem sweep`` command line's options, apart from the sweep engine: the ``fretbem``
command builds its parser from them without loading the engine (its cases, store and maps:
~20 ms of every other command's start-up)."""

from __future__ import annotations

__all__ = ["ENGINES", "add_arguments"]

#: the engines of ``engine=`` / ``--engine`` (module docstring and docs/how-to/sweeps.rst)
ENGINES = ("auto", "serial", "processes", "dask")


def add_arguments(parser) -> None:
    """The sweep subcommand's arguments (for the fretbem CLI's subparser)."""
    parser.add_argument("sweep_file", metavar="SWEEP.toml", help="sweep description")
    parser.add_argument(
        "--scheduler", metavar="ADDRESS", help="Dask scheduler address, e.g. tcp://host:8786"
    )
    parser.add_argument(
        "--serial", action="store_true", help="solve in this process (--engine serial)"
    )
    parser.add_argument(
        "--engine",
        choices=ENGINES,
        help="auto (default: in this process, forked workers once the work pays for them), "
        "serial, processes (forked workers at once) or dask (a LocalCluster, or --scheduler)",
    )
    parser.add_argument(
        "--out", metavar="DIR", help="store directory (default: [sweep] out, or <name>-sweep)"
    )
    parser.add_argument(
        "--workers", type=int, metavar="N", help="worker processes (default: cores)"
    )
    parser.add_argument("--batch", type=int, metavar="N", help="cases per task (default: auto)")
    parser.add_argument(
        "--limit", type=int, metavar="N", help="stop after N tasks (re-run to complete)"
    )
    parser.add_argument("--no-figures", action="store_true", help="skip the fretting maps")
    parser.add_argument(
        "--maps-only",
        action="store_true",
        help="solve nothing: redraw the [[maps]] from the cases already in the store",
    )
    parser.add_argument(
        "--quiet", action="store_true", help="no progress bar (it shows only on a terminal)"
    )
