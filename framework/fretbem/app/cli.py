"""The ``fretbem`` command: list basis families, run a scene file, run the reference demo."""

from __future__ import annotations

import argparse
import gc
import importlib
import inspect
import json
import signal
import sys
import time
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

import attrs

from fretbem import pipeline
from fretbem import registry as bases
from fretbem.accuracy import modes as accuracy
from fretbem.accuracy.modes import Accuracy, mode_of
from fretbem.app.progress import Bars
from fretbem.bem.resources import check_resources
from fretbem.contact.zones import zone_table
from fretbem.errors import FretbemError, InputError, ResultCheckError
from fretbem.fretting import analyse as analyse_cycles
from fretbem.output import fretting as fretting_output
from fretbem.output.report import REPORT, build_report
from fretbem.output.staging import add_output_file
from fretbem.output.write import WriteContext, analyses, chosen_writers, prepare_output
from fretbem.scenes.builder import build
from fretbem.scenes.file import load_scene
from fretbem.scenes.reference import CattaneoMindlinScene, cattaneo_mindlin
from fretbem.studies.sweep_options import add_arguments as sweep_arguments
from fretbem.verification.checks import step_names


def _bases(args: argparse.Namespace) -> int:
    families = bases.describe()
    if not families:
        print("no basis family installed (pip install fretbem registers nurbs and lagrange2)")
        return 1
    width = max(len(name) for name in families)
    for name, description in families.items():
        print(f"{name:<{width}}  {description}")
    return 0


def _plugins(args: argparse.Namespace) -> int:
    """Every plugin group: name, distribution, version, object, and whether it loads."""
    for key, group in bases.GROUPS.items():
        rows = bases.entries(key)
        print(f"{group.entry_points} ({group.what}):")
        if not rows:
            print("  (none installed)")
        for row in rows:
            status = "" if row["status"] == "ok" else f"  [{row['status']}]"
            print(
                f"  {row['name']:<12} {row['distribution']} {row['version']:<8} "
                f"{row['object']}{status}"
            )
    return 0


#: --quiet: no status lines and no progress bars on stderr
QUIET = {"on": False}


def _progress(message: str) -> None:
    """A short status line on stderr (stdout keeps the table); nothing with --quiet."""
    if not QUIET["on"]:
        print(f"fretbem: {message}", file=sys.stderr, flush=True)


class StepProgress:
    """Prints "step k/n (name)" on stderr after each step, at most once a second (and last)."""

    def __init__(self, total: int, interval: float = 1.0) -> None:
        self.total, self.interval = total, interval
        self.start = self.last = time.perf_counter()

    def __call__(self, k: int, n: int, step) -> None:
        now = time.perf_counter()
        if now - self.last >= self.interval or k == n:
            self.last = now
            name = getattr(step, "name", "")
            _progress(f"step {k}/{n} ({name}) done, {now - self.start:.1f} s")


def _progress_option(run, simulation, estimate, bars: Bars | None = None) -> dict:
    """``progress=`` for run() when it takes the hook and the run is long (> 2 s or > 20
    steps): a bar over the steps on a terminal, else a status line at most once a second;
    nothing with --quiet."""

    long = estimate.seconds > 2.0 or len(simulation.steps) > 20
    if QUIET["on"] or not long or "progress" not in inspect.signature(run).parameters:
        return {}
    if bars is not None and bars.enabled:
        return {"progress": bars.steps(len(simulation.steps))}
    return {"progress": StepProgress(len(simulation.steps))}


def _check_compare(names) -> list[str]:
    """--compare names must be installed families (checked before the run)."""
    installed = bases.available()
    unknown = [name for name in names or [] if name not in installed]
    if unknown:
        raise CommandError(
            f"--compare: no basis family {unknown}; installed: {sorted(installed)} "
            "(`fretbem bases`)"
        )
    return list(names or [])


def _check_steps(simulation, steps) -> None:
    names = [step.name for step in simulation.steps]

    step_names(names)
    if steps:
        missing = [name for name in steps if name not in names]
        if missing:
            raise CommandError(f"--steps {missing} are not load steps; the steps are {names}")


def _dofs(pair) -> int:
    """Boundary unknowns of both bodies (bodies without a ``dofs`` count, e.g. half-planes,
    hold no dense BEM matrices and count 0)."""
    return sum(int(getattr(body, "dofs", 0) or 0) for body in (pair.upper, pair.lower))


def _prepare(make, args: argparse.Namespace):
    """Everything checkable before computing: output directory, options, size, step names."""

    prepare_output(args.out, overwrite=args.overwrite)
    compare = _check_compare(args.compare) if not args.no_figures else []
    simulation, reason = make(None)
    _check_steps(simulation, args.steps)
    pair = simulation.pair
    estimate = check_resources(int(pair.upper.dofs + pair.lower.dofs))
    if estimate.seconds > 2.0:
        _progress(f"running, estimated {estimate.describe()}")
    return simulation, reason, compare, estimate


def _mode(args: argparse.Namespace, base):
    """The accuracy mode: the scene's (``base``) with the command's options over it."""

    mesh = args.mesh or base.mesh
    if mesh != "adaptive":
        given = [f"--{n}" for n in ("tolerance", "budget") if getattr(args, n) is not None]
        if given:
            raise CommandError(
                f"{' and '.join(given)} apply to the adaptive mesh; add --mesh adaptive "
                "(or set [contact] mesh = 'adaptive' in the scene)"
            )
    elif args.pairs is not None:
        raise CommandError(
            "--pairs sets the fixed mesh's pairs; an adaptive run takes --budget (most pairs) "
            "or --tolerance, or add --mesh fixed"
        )
    elif args.no_estimate:
        raise CommandError(
            "--no-estimate applies to the fixed mesh; the adaptive mode's levels always give "
            "the estimate"
        )
    return Accuracy(
        mesh=mesh,
        estimate=mesh == "adaptive" or (base.estimate and not args.no_estimate),
        tolerance=base.tolerance if args.tolerance is None else args.tolerance,
        budget=base.budget if args.budget is None else args.budget,
    )


def _simulate(
    make, args: argparse.Namespace, extras=None, mode=None, companion=None, sliding=False
) -> int:
    """Solve in ``mode`` (``companion(pairs)``: the fixed mode's coarser level) through the
    run pipeline, print the tables with the estimate, and write the output."""
    start = time.perf_counter()
    QUIET["on"] = bool(getattr(args, "quiet", False))
    bars = Bars(quiet=QUIET["on"])
    simulation, reason, compare, estimate = _prepare(make, args)
    built = time.perf_counter() - start
    if sliding:
        reason = "finite sliding: no closed form follows the pad along the track"
    stress, fatigue = pipeline.requests(extras)  # bad tables are refused before solving
    wear = pipeline.wear_request(extras)
    done = pipeline.run_simulation(
        simulation,
        mode=mode or accuracy.Accuracy(),
        extras=extras,
        reason=reason,
        companion=companion,
        compare=[make(name)[0] for name in compare],
        progress=_progress_option(accuracy.solve, simulation, estimate, bars).get("progress"),
        say=_progress,
        bars=bars,
        phases={"build": built},
        sliding=sliding,
    )
    result = done.result
    info = result.describe()
    faces = info["faces"]
    if faces["upper"] == faces["lower"]:
        print(
            f"{info['basis']} (degree {info['degree']}), {info['pairs']} node pairs, "
            f"{info['dofs']} boundary DOFs"
        )
    else:  # faces discretised independently (node-to-segment pairing)
        shown = {
            k: f"{f['basis']} (degree {f['degree']}, {f['nodes']} nodes)" for k, f in faces.items()
        }
        print(
            f"pad face {shown['upper']}, specimen face {shown['lower']}: {info['pairs']} pairs "
            f"({info['pairing']}), {info['dofs']} boundary DOFs"
        )
    print(result.table())
    print(zone_table(result, reason))
    cyclic = fretting_output.has_cycles(result)
    if cyclic:
        print(analyse_cycles(result).table())
    if done.fatigue is not None:
        print(analyses().format_report(done.fatigue))
    if done.wear is not None:
        print(analyses().format_wear(done.wear))
    if stress is not None:
        _progress("evaluating the stresses")
    if not args.no_figures or not args.no_vtk:
        _progress("writing figures and files")
    out = done.write(
        args.out, overwrite=args.overwrite, steps=args.steps,
        figures=not args.no_figures, vtk=not args.no_vtk, writers=_writer_names(args, done),
        progress=bars,
    )  # fmt: skip
    asked = (("stress", stress), ("fatigue", fatigue), ("wear", wear))
    kinds = [k for k, v in asked if v is not None]
    kinds += [k for k, flag in (("netCDF", "netcdf"), ("report.html", "report"))
              if getattr(args, flag, False)]  # fmt: skip
    print(
        f"wrote {out}/ (results.csv, summary.json, units.json, loops.csv"
        f"{', slip.csv' if cyclic else ''}"
        f"{', VTK' if not args.no_vtk else ''}{', figures' if not args.no_figures else ''}"
        f"{''.join(', ' + kind for kind in kinds)}) "
        f"in {time.perf_counter() - start:.2f} s; all result checks passed"
    )
    phases = _phases(out)
    if phases:
        print("time by phase: " + ", ".join(f"{k} {v:.2f} s" for k, v in phases.items()))
    return 0


def _phases(out: Path) -> dict:
    """The phases' seconds summary.json recorded ({} without it)."""
    try:
        return json.loads((Path(out) / "summary.json").read_text()).get("phases", {})
    except (OSError, ValueError):
        return {}


def _writer_names(args: argparse.Namespace, done) -> list[str] | None:
    """The default writers plus those the options ask for (--netcdf, --report); None when
    no option adds one (write_results then runs its defaults)."""
    extra = [name for name, flag in (("netcdf", "netcdf"), ("report", "report"))
             if getattr(args, flag, False)]  # fmt: skip
    if not extra:
        return None
    context = WriteContext(done.result, stress=done.stress, fatigue=done.fatigue, wear=done.wear)
    return [w.name for w in chosen_writers(None, context)] + extra


def _run(args: argparse.Namespace) -> int:
    scene_path, out = Path(args.scene).resolve(), Path(args.out).resolve()
    if scene_path.is_relative_to(out):
        raise CommandError(
            f"--out {out} contains the scene file {args.scene}; replacing it would delete the "
            "scene: choose another --out"
        )
    scene = load_scene(args.scene, basis=args.basis, pairs=args.pairs)
    if scene.legacy:
        _progress(
            f"{args.scene} is in the round-1 scene format; it was translated (see "
            "docs/scene-format.md, 'Round-1 files', for the current keys)"
        )
    mode = _mode(args, mode_of(scene))
    return _simulate(
        lambda basis: build(scene, basis=basis),
        args,
        scene.extras,
        mode,
        lambda pairs: build(scene, pairs=pairs)[0],
        sliding=scene.contact.sliding,
    )


def _demo(args: argparse.Namespace) -> int:
    mode = _mode(args, Accuracy())
    scene = CattaneoMindlinScene(basis=args.basis, pairs=args.pairs or 61)
    if args.compare is None and not args.no_figures:
        args.compare = []
        for name, family in bases.available().items():
            if name == args.basis:
                continue
            try:
                scene.zone_elements(family)
            except ValueError as err:  # e.g. a cubic family needs pairs = 3 k + 1
                print(f"fretbem: not comparing with {name}: {err}", file=sys.stderr)
                continue
            args.compare.append(name)

    def make(basis):
        return cattaneo_mindlin(attrs.evolve(scene, basis=basis or scene.basis)), None

    def companion(pairs):
        return cattaneo_mindlin(attrs.evolve(scene, pairs=pairs))

    return _simulate(make, args, None, mode, companion)


def _report(args: argparse.Namespace) -> int:
    """report.html of a finished output folder (read-only apart from the page itself)."""
    page = build_report(args.out)
    path = add_output_file(args.out, REPORT, page)
    print(f"wrote {path} ({len(page) / 1024:.0f} kB, figures embedded)")
    return 0


#: the commands whose code the others do not need, as "module:function", loaded when one
#: runs: the sweep engine and the convergence study (~20 ms of every other start-up)
COMMANDS = {
    "sweep": "fretbem.studies.sweep.run:run_command",
    "convergence": "fretbem.studies.convergence.study:main",
}


def _command(name: str):
    """The function of ``COMMANDS[name]``, its module loaded now."""
    module, _, function = COMMANDS[name].partition(":")
    return getattr(importlib.import_module(module), function)


def _convergence(args: argparse.Namespace) -> int:
    return _command("convergence")(quick=args.quick, out=args.out)


def _sweep(args: argparse.Namespace) -> int:
    return _command("sweep")(args)


class CommandError(InputError):
    """A command-line option that cannot work (checked before any computation)."""


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
    main.add_argument("--version", action="version", version=f"%(prog)s {_version()}")
    sub = main.add_subparsers(dest="command")
    sub.add_parser("bases", help="list the installed basis families").set_defaults(func=_bases)
    sub.add_parser(
        "plugins",
        help="list every plugin group (bases, body models, solvers, laws) with its packages",
    ).set_defaults(func=_plugins)
    run_ = sub.add_parser("run", help="run a scene file (TOML)")
    run_.add_argument("scene", help="scene file, e.g. examples/cattaneo_mindlin.toml")
    run_.add_argument("--basis", help="basis family (overrides the file)")
    run_.add_argument(
        "--pairs", type=_positive_int, help="node pairs in the contact zone (overrides)"
    )
    _accuracy_options(run_, "overrides [contact] mesh")
    _output_options(run_, "out")
    run_.set_defaults(func=_run)
    demo = sub.add_parser("demo", help="run the reference Cattaneo-Mindlin fretting cycle")
    demo.add_argument("--basis", default="nurbs", help="basis family (default nurbs)")
    demo.add_argument("--pairs", type=_positive_int, help="node pairs (default 61)")
    _accuracy_options(demo, "default fixed, 61 pairs")
    _output_options(demo, "demo-out")
    demo.set_defaults(func=_demo)
    report = sub.add_parser(
        "report", help="write report.html for a finished run: one self-contained page"
    )
    report.add_argument("out", help="the output folder of fretbem run or demo (--out)")
    report.set_defaults(func=_report)
    convergence = sub.add_parser(
        "convergence", help="speed against error: the convergence study of the reference scene"
    )
    convergence.add_argument(
        "--quick", action="store_true", help="a few small levels (CI) instead of the full study"
    )
    convergence.add_argument("--out", default="convergence-out", help="output directory")
    convergence.set_defaults(func=_convergence)

    sweep = sub.add_parser(
        "sweep", help="parameter sweep and fretting maps from a sweep file (TOML), on Dask"
    )
    sweep_arguments(sweep)
    sweep.set_defaults(func=_sweep)
    return main


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


#: commands run by the console script with the cyclic garbage collector off: the demo is a
#: fixed small computation (its allocations are bounded) whose ~100 collections traversed
#: the ~3 x 10^5 objects of numpy, scipy, matplotlib and fretbem to free almost nothing
#: (~50 ms of the demo's ~1.5 s CPU; the one after the figures alone ~40 ms)
UNCOLLECTED = frozenset({"demo"})


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
    if argv is None and args.command in UNCOLLECTED:
        gc.disable()  # the process ends with the command: its garbage goes with it
    try:
        return args.func(args)
    except ResultCheckError as err:
        print(f"fretbem: result check failed ({err.check}): {_one_line(err)}", file=sys.stderr)
        return 1
    except (FretbemError, ValueError, KeyError, RuntimeError, OSError, MemoryError) as err:
        print(f"fretbem: error: {_one_line(err)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("fretbem: interrupted; the output directory was left as it was", file=sys.stderr)
        return 130
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
        if argv is None:  # the console script: the process ends now
            gc.freeze()  # exit then skips the collector's passes over every object made


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
