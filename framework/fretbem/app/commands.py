"""The ``fretbem`` command's subcommands that list plugins, solve, write and report: the
functions :data:`fretbem.app.cli.COMMANDS` names, loaded when one of them runs."""

from __future__ import annotations

import argparse
import inspect
import json
import sys
import time
from pathlib import Path

import attrs

from fretbem import pipeline
from fretbem import registry as bases
from fretbem.accuracy import modes as accuracy
from fretbem.accuracy.modes import Accuracy, mode_of
from fretbem.app.progress import Bars
from fretbem.bem.resources import check_resources, run_size
from fretbem.contact.zones import zone_table
from fretbem.errors import InputError
from fretbem.fretting import analyse as analyse_cycles
from fretbem.output import fretting as fretting_output
from fretbem.output.report import REPORT, build_report
from fretbem.output.staging import add_output_file
from fretbem.output.write import WriteContext, analyses, chosen_writers, prepare_output
from fretbem.scenes.builder import build
from fretbem.scenes.file import load_scene
from fretbem.scenes.reference import CattaneoMindlinScene, cattaneo_mindlin
from fretbem.verification.checks import step_names

__all__ = [
    "CommandError",
    "list_bases",
    "list_plugins",
    "run_demo",
    "run_scene_file",
    "write_report",
]


class CommandError(InputError):
    """A command-line option that cannot work (checked before any computation)."""


def list_bases(args: argparse.Namespace) -> int:
    """``fretbem bases``: every installed basis family with its description."""
    families = bases.describe()
    if not families:
        print("no basis family installed (pip install fretbem registers nurbs and lagrange2)")
        return 1
    width = max(len(name) for name in families)
    for name, description in families.items():
        print(f"{name:<{width}}  {description}")
    return 0


def list_plugins(args: argparse.Namespace) -> int:
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
    estimate = check_resources(**run_size(simulation.pair))
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
    make, args: argparse.Namespace, extras=None, mode=None, companion=None, sliding=False,
    frame="local",
) -> int:  # fmt: skip
    """Solve in ``mode`` (``companion(pairs)``: the fixed mode's coarser level) through the
    run pipeline, print the tables with the estimate, and write the output (``sliding``,
    ``frame``: finite sliding and its pair frame along an arc)."""
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
        frame=frame,
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


def run_scene_file(args: argparse.Namespace) -> int:
    """``fretbem run SCENE``: the scene file solved, its tables printed and its files written."""
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
        frame=scene.contact.sliding_frame,
    )


def run_demo(args: argparse.Namespace) -> int:
    """``fretbem demo``: the reference Cattaneo-Mindlin cycle, with the other installed
    families drawn beside it unless ``--compare`` names them or figures are off."""
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


def write_report(args: argparse.Namespace) -> int:
    """report.html of a finished output folder (read-only apart from the page itself)."""
    page = build_report(args.out)
    path = add_output_file(args.out, REPORT, page)
    print(f"wrote {path} ({len(page) / 1024:.0f} kB, figures embedded)")
    return 0
