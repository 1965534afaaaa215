"""The ``fretbem`` command: list basis families, run a scene file, run the reference demo."""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from . import bases


def _bases(args: argparse.Namespace) -> int:
    families = bases.describe()
    if not families:
        print("no basis family installed (pip install fretbem registers nurbs and lagrange2)")
        return 1
    width = max(len(name) for name in families)
    for name, description in families.items():
        print(f"{name:<{width}}  {description}")
    return 0


def _simulate(scene, args: argparse.Namespace) -> int:
    from .scenes import cattaneo_mindlin
    from .simulation import run

    start = time.perf_counter()
    result = run(cattaneo_mindlin(scene))
    info = result.describe()
    print(
        f"{info['basis']} (degree {info['degree']}), {info['pairs']} node pairs, "
        f"{info['dofs']} boundary DOFs"
    )
    print(result.table())
    if result.simulation.reference is None:
        print("errors: n/a (no analytical reference for this scene, e.g. dissimilar materials)")
    results = [result]
    if not args.no_figures:
        for name in args.compare or []:
            import attrs

            results.append(run(cattaneo_mindlin(attrs.evolve(scene, basis=name))))
    out = Path(args.out)
    result.save(out, figures=False, vtk=not args.no_vtk)
    if not args.no_figures:
        from . import plot

        plot.save_figures(results, out)
    print(
        f"wrote {out}/ (results.csv, summary.json"
        f"{', VTK' if not args.no_vtk else ''}{', figures' if not args.no_figures else ''}) "
        f"in {time.perf_counter() - start:.2f} s"
    )
    return 0


def _run(args: argparse.Namespace) -> int:
    from .scene_file import load_scene

    scene = load_scene(args.scene, basis=args.basis, pairs=args.pairs)
    return _simulate(scene, args)


def _demo(args: argparse.Namespace) -> int:
    from .scenes import CattaneoMindlinScene

    scene = CattaneoMindlinScene(basis=args.basis, pairs=args.pairs)
    if args.compare is None:
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
    return _simulate(scene, args)


def _convergence(args: argparse.Namespace) -> int:
    from .convergence import main as study

    return study(quick=args.quick, out=args.out)


def _output_options(parser: argparse.ArgumentParser, default_out: str) -> None:
    parser.add_argument("--out", default=default_out, help="output directory")
    parser.add_argument("--no-figures", action="store_true", help="skip the matplotlib figures")
    parser.add_argument("--no-vtk", action="store_true", help="skip the VTK files")
    parser.add_argument(
        "--compare",
        nargs="*",
        metavar="NAME",
        help="also run these families and draw them in the figures",
    )


def parser() -> argparse.ArgumentParser:
    """The argument parser of the ``fretbem`` command."""
    main = argparse.ArgumentParser(
        prog="fretbem",
        description="2D frictional contact (fretting) by the boundary element method",
    )
    sub = main.add_subparsers(dest="command", required=True)
    sub.add_parser("bases", help="list the installed basis families").set_defaults(func=_bases)
    run_ = sub.add_parser("run", help="run a scene file (TOML)")
    run_.add_argument("scene", help="scene file, e.g. examples/cattaneo_mindlin.toml")
    run_.add_argument("--basis", help="basis family (overrides the file)")
    run_.add_argument("--pairs", type=int, help="node pairs in the contact zone (overrides)")
    _output_options(run_, "out")
    run_.set_defaults(func=_run)
    demo = sub.add_parser("demo", help="run the reference Cattaneo-Mindlin fretting cycle")
    demo.add_argument("--basis", default="nurbs", help="basis family (default nurbs)")
    demo.add_argument("--pairs", type=int, default=61, help="node pairs (default 61)")
    _output_options(demo, "demo-out")
    demo.set_defaults(func=_demo)
    convergence = sub.add_parser(
        "convergence", help="speed against error: the convergence study of the reference scene"
    )
    convergence.add_argument(
        "--quick", action="store_true", help="a few small levels (CI) instead of the full study"
    )
    convergence.add_argument("--out", default="convergence-out", help="output directory")
    convergence.set_defaults(func=_convergence)
    return main


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``fretbem`` console script; returns the exit code."""
    args = parser().parse_args(argv)
    try:
        return args.func(args)
    except (ValueError, KeyError, RuntimeError) as err:
        message = err.args[0] if isinstance(err, KeyError) and err.args else err
        print(f"fretbem: error: {message}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
