"""The ``fretbem`` command: its options, and each subcommand's function loaded when it runs
(:data:`COMMANDS`), so a command loads only what it uses."""

from __future__ import annotations

import argparse
import atexit
import gc
import importlib
import os
import signal
import sys
from importlib.metadata import PackageNotFoundError, version

from fretbem.app import lean_matplotlib
from fretbem.errors import FretbemError, ResultCheckError
from fretbem.studies.sweep_options import add_arguments as sweep_arguments

#: each subcommand's function as "module:function", loaded when it runs: ``fretbem bases``
#: does not load the solver, nor ``fretbem demo`` the sweep engine, and a command's imports
#: run after :func:`main` has chosen how the process collects its garbage
COMMANDS = {
    "bases": "fretbem.app.commands:list_bases",
    "plugins": "fretbem.app.commands:list_plugins",
    "run": "fretbem.app.commands:run_scene_file",
    "demo": "fretbem.app.commands:run_demo",
    "report": "fretbem.app.commands:write_report",
    "convergence": "fretbem.studies.convergence.study:run_command",
    "sweep": "fretbem.studies.sweep.run:run_command",
}


def command(name: str):
    """The function of the subcommand ``name`` (:data:`COMMANDS`), its module loaded now."""
    module, _, function = COMMANDS[name].partition(":")
    return getattr(importlib.import_module(module), function)


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 1, got {value}")
    return value


def _fraction(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not 0.0 < value < 1.0:
        raise argparse.ArgumentTypeError(
            f"expected a fraction of p0, 0 < tolerance < 1 (0.02 is 2 %), got {text}"
        )
    return value


def _accuracy_options(parser: argparse.ArgumentParser, where: str) -> None:
    parser.add_argument(
        "--mesh",
        choices=("fixed", "adaptive"),
        help=f"contact mesh: fixed pairs, or adaptive to a tolerance or budget ({where})",
    )
    parser.add_argument(
        "--tolerance",
        type=_fraction,
        help="adaptive: stop when the estimated max error is below this fraction (0.02 = 2 %%)",
    )
    parser.add_argument(
        "--budget", type=_positive_int, help="adaptive: most node pairs of the last level"
    )
    parser.add_argument(
        "--no-estimate",
        action="store_true",
        help="fixed: skip the companion level of half the pairs (no error estimate; the "
        "level costs about half the main solve)",
    )


def _output_options(parser: argparse.ArgumentParser, default_out: str) -> None:
    parser.add_argument("--out", default=default_out, help="output directory")
    parser.add_argument(
        "--overwrite",
        action="store_true",
        help="replace --out even if it is a non-empty directory that fretbem did not write",
    )
    parser.add_argument("--no-figures", action="store_true", help="skip the matplotlib figures")
    parser.add_argument("--no-vtk", action="store_true", help="skip the VTK files")
    parser.add_argument(
        "--quiet",
        action="store_true",
        help="no status lines and no progress bars on stderr (the tables still print)",
    )
    parser.add_argument(
        "--report",
        action="store_true",
        help="also write report.html: the run on one self-contained page (fretbem report OUT "
        "makes it for a finished run)",
    )
    parser.add_argument(
        "--netcdf",
        action="store_true",
        help="also write results.nc (and stress.nc, fatigue.nc): labelled netCDF for xarray",
    )
    parser.add_argument(
        "--compare",
        nargs="*",
        metavar="NAME",
        help="also run these families and draw them in the figures",
    )
    parser.add_argument(
        "--steps",
        nargs="+",
        metavar="STEP",
        help="load steps drawn as figure panels (default: all, or 6 spread over a long "
        "history, the first included)",
    )


def parser() -> argparse.ArgumentParser:
    """The argument parser of the ``fretbem`` command."""
    main = argparse.ArgumentParser(
        prog="fretbem",
        description="2D frictional contact (fretting) by the boundary element method",
    )
    main.add_argument("--version", action=_VersionAction)
    sub = main.add_subparsers(dest="command")
    sub.add_parser("bases", help="list the installed basis families")
    sub.add_parser(
        "plugins",
        help="list every plugin group (bases, body models, solvers, laws) with its packages",
    )
    run_ = sub.add_parser("run", help="run a scene file (TOML)")
    run_.add_argument("scene", help="scene file, e.g. examples/cattaneo_mindlin.toml")
    run_.add_argument("--basis", help="basis family (overrides the file)")
    run_.add_argument(
        "--pairs", type=_positive_int, help="node pairs in the contact zone (overrides)"
    )
    _accuracy_options(run_, "overrides [contact] mesh")
    _output_options(run_, "out")
    demo = sub.add_parser("demo", help="run the reference Cattaneo-Mindlin fretting cycle")
    demo.add_argument("--basis", default="nurbs", help="basis family (default nurbs)")
    demo.add_argument("--pairs", type=_positive_int, help="node pairs (default 61)")
    _accuracy_options(demo, "default fixed, 61 pairs")
    _output_options(demo, "demo-out")
    report = sub.add_parser(
        "report", help="write report.html for a finished run: one self-contained page"
    )
    report.add_argument("out", help="the output folder of fretbem run or demo (--out)")
    convergence = sub.add_parser(
        "convergence", help="speed against error: the convergence study of the reference scene"
    )
    convergence.add_argument(
        "--quick", action="store_true", help="a few small levels (CI) instead of the full study"
    )
    convergence.add_argument("--out", default="convergence-out", help="output directory")

    sweep = sub.add_parser(
        "sweep", help="parameter sweep and fretting maps from a sweep file (TOML), on Dask"
    )
    sweep_arguments(sweep)
    return main


class _VersionAction(argparse.Action):
    """``--version``: argparse's version action, with the installed version read from the
    package metadata only when asked for (every other command skips that file read)."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS,
                 help="show program's version number and exit"):  # fmt: skip
        super().__init__(option_strings, dest, nargs=0, default=default, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        parser._print_message(f"{parser.prog} {_version()}\n", sys.stdout)
        parser.exit()


def _version() -> str:
    try:
        return version("fretbem")
    except PackageNotFoundError:  # pragma: no cover - not installed
        return "unknown"


def _one_line(err: BaseException) -> str:
    if isinstance(err, KeyError) and err.args:
        return str(err.args[0])
    if isinstance(err, MemoryError):
        return (
            "out of memory; use fewer pairs (a coarser contact zone) or a machine with more memory"
        )
    if isinstance(err, OSError):
        where = f": {err.filename}" if err.filename else ""
        return f"{err.strerror or err}{where}"
    return " ".join(str(err).split("\n"))


#: commands run by the console script with the cyclic garbage collector off, and whose
#: process ends without the interpreter's teardown (:func:`_end_process`): the demo is a
#: fixed small computation (its allocations are bounded) whose ~100 collections traversed
#: the ~3 x 10^5 objects of numpy, scipy, matplotlib and fretbem to free almost nothing
#: (~90 ms of the demo's ~1.5 s CPU: the imports' ~40, the one after the figures ~40)
UNCOLLECTED = frozenset({"demo"})

#: exit code when the reader of stdout closed it, as a shell reports a process ended by SIGPIPE
SIGPIPE_EXIT = 128 + 13


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``fretbem`` console script; returns the exit code.

    Exit codes: 0 success, 1 a result check failed (nothing written), 2 bad input or an
    output/system error (one line on stderr), 130 interrupted.
    """

    main_parser = parser()
    args = main_parser.parse_args(argv)
    if args.command is None:
        main_parser.print_help()
        return 0
    previous = _terminate_as_interrupt()
    if argv is None:  # the console script: no docstring is read in this process
        lean_matplotlib.install()
    ending = argv is None and args.command in UNCOLLECTED
    if ending:
        gc.disable()  # the process ends with the command: its garbage goes with it
    try:
        code = command(args.command)(args)
    except ResultCheckError as err:
        print(f"fretbem: result check failed ({err.check}): {_one_line(err)}", file=sys.stderr)
        code = 1
    except BrokenPipeError:  # the reader stopped reading (`fretbem plugins | head`)
        _silence_stdout()
        code = SIGPIPE_EXIT
    except (FretbemError, ValueError, KeyError, RuntimeError, OSError, MemoryError) as err:
        print(f"fretbem: error: {_one_line(err)}", file=sys.stderr)
        code = 2
    except KeyboardInterrupt:
        print("fretbem: interrupted; the output directory was left as it was", file=sys.stderr)
        code = 130
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
        if argv is None:  # the console script: the process ends now
            gc.freeze()  # exit then skips the collector's passes over every object made
    if ending:
        _end_process(code)
    return code


def _end_process(code: int) -> None:
    """End the process now with ``code``: the exit handlers run and the output is flushed,
    but the interpreter does not tear its ~3 x 10^5 objects and ~800 modules down one by one
    (~20 ms of a demo's CPU); the kernel frees the memory whole. Only the console script's
    fixed-size commands (:data:`UNCOLLECTED`), whose files are all closed, end this way; an
    interpreter without ``atexit._run_exitfuncs`` returns and exits as usual."""
    run_exit_handlers = getattr(atexit, "_run_exitfuncs", None)
    if run_exit_handlers is None:  # pragma: no cover - not CPython
        return
    run_exit_handlers()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe: what is lost is lost either way
            pass
    os._exit(code)


def _silence_stdout() -> None:
    """Point stdout at the null device, so that the interpreter's final flush of the closed
    pipe does not print a second error."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):  # pragma: no cover - no stdout descriptor
        pass


def _interrupt(signum, frame) -> None:
    raise KeyboardInterrupt


def _terminate_as_interrupt():
    """SIGTERM (kill, a batch system's time limit) cleans up like Ctrl-C; returns the old
    handler (None where signals cannot be set, e.g. outside the main thread)."""
    try:
        return signal.signal(signal.SIGTERM, _interrupt)
    except ValueError:
        return None


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
