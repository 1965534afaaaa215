"""The specimen's side of a slide along an arc, before and after the tractions were carried
along each pair's own normal: tractions, stresses, wear and the moment balance.

Runs the same measurement in two trees (fresh processes, ``PYTHONPATH`` at each tree's
framework/ and plugins/) and prints, per arc (cylinder specimens of R = R_pad = 70, 35 and
17.5 mm at P = 100 N/mm, R = 70 mm at P = 160, a groove of 70 mm under a 40 mm pad; 31
pairs, examples/gross_sliding_arc.toml and gross_sliding_groove.toml slid and back in 12
increments each) and step: the largest change of the specimen's nodal tractions and of the
pair pressures over p0, of the specimen's stresses at 25 points under the contact (depths
0.05 to 0.8 mm, -a to a) over p0, and each tree's moment of the specimen's nodal tractions
plus the pad's less the gap's lever int g q ds, over P a, beside int g p phi ds (phi: each
pair's angle to the pad's axis). Then the wear along arcs of R_s = 70, 35 and 17.5 mm
(tests/validation/test_sliding_wear_arc.py's scene, 21 pairs, 100 cycles): each face's
deepest wear, profile, scar and volume, after against before.

    git archive 615b3c2 | tar -x -C /tmp/before   # the tangent mapping
    git archive HEAD | tar -x -C /tmp/after
    OPENBLAS_NUM_THREADS=1 python benchmarks/arc_transfer_before_after.py \\
        --before /tmp/before --after /tmp/after
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

MEASURE = r"""
import sys, tomllib
from pathlib import Path
import numpy as np
from fretbem.numerics.quadrature import QuadratureRule
from fretbem.scenes.builder import build
from fretbem.scenes.file import scene_from_data
from fretbem.sliding import solve_sliding
from fretbem.stress.evaluate import stresses
from fretbem.wear.law import EnergyWear
from fretbem.wear.profile import pair_weights
from fretbem.wear.run import WearSimulation, run_wear

ROOT, OUT = Path(sys.argv[1]), sys.argv[2]
RULE = QuadratureRule.gauss_legendre(8)


def integrals(field, values, shift):
    force, moment = np.zeros(2), 0.0
    for index, basis in enumerate(field.segments):
        b = np.unique(basis.element_bounds)
        lo, hi = b[:-1], b[1:]
        s = (lo[:, None] + 0.5 * (RULE.points[None, :] + 1.0) * (hi - lo)[:, None]).ravel()
        w = (0.5 * RULE.weights[None, :] * (hi - lo)[:, None]).ravel()
        points, derivatives = basis.curve.points_and_derivatives(s)
        ds = w * np.linalg.norm(derivatives, axis=1)
        t = field.interpolation(np.full(s.shape, index), s) @ values
        x = points + shift
        force += ds @ t
        moment += ds @ (x[:, 0] * t[:, 1] - x[:, 1] * t[:, 0])
    return force, moment


def slid(kind, radius, load):
    name = "gross_sliding_arc.toml" if kind == "cylinder" else "gross_sliding_groove.toml"
    data = tomllib.loads((ROOT / "examples" / name).read_text())
    data["pad"]["radius"] = radius
    if kind == "cylinder":
        data["specimen"]["radius"] = radius
    data["contact"]["pairs"] = 31
    data["contact"].pop("frame", None)
    data["load"].update(P=load, increments=[1, 12, 12])
    return build(scene_from_data(data))[0]


out = {}
for kind, radius, load in (("cylinder", 70.0, 100.0), ("cylinder", 35.0, 100.0),
                           ("cylinder", 17.5, 100.0), ("cylinder", 70.0, 160.0),
                           ("groove", 40.0, 100.0)):
    result = solve_sliding(slid(kind, radius, load), say=lambda _: None)
    for step in result.steps[1:]:
        pair, pairing = step.pair, step.pair.pairing()
        frame = np.stack([-pairing.normals, pairing.tangents], axis=-1)
        traction = (frame @ np.stack([step.pressure, step.shear], -1)[..., None])[..., 0]
        lower, upper = pair._field("lower"), pair._field("upper")
        specimen = pairing.scatter("lower", traction, lower.n_nodes)
        force_s, moment_s = integrals(lower, specimen, np.zeros(2))
        force_p, moment_p = integrals(
            upper, pairing.scatter("upper", -traction, upper.n_nodes), pair.offset
        )
        weights = pair_weights(pair.condensed())
        normal, tangent = pairing.load_frame()
        phi = np.arcsin(normal[0] * pairing.normals[:, 1] - normal[1] * pairing.normals[:, 0])
        touching = step.pressure > 0
        a = 0.5 * np.ptp(pairing.points[touching] @ tangent)
        centre = step.pressure @ pairing.points / step.pressure.sum()
        points = np.array([centre - d * normal + x * a * tangent
                           for d in (0.05, 0.1, 0.2, 0.4, 0.8) for x in (-1, -0.5, 0, 0.5, 1)])
        key = f"{kind} {radius:g} mm, P {load:g}, {step.name}"
        out[key + "|specimen"] = specimen
        out[key + "|pressure"] = step.pressure
        out[key + "|stress"] = stresses(result, step.name, points, body="lower")[:, :3]
        out[key + "|meta"] = np.array([
            np.linalg.norm(force_s + force_p), moment_s + moment_p, weights @ step.pressure, a,
            step.pressure.max(), np.sum(weights * pairing.gap * step.shear),
            np.sum(weights * pairing.gap * step.pressure * phi),
        ])
        print(key, flush=True)

sys.path.insert(0, str(ROOT / "tests" / "validation"))
from test_sliding_wear_arc import CYCLES, LAWS, scene  # noqa: E402

for radius in (70.0, 35.0, 17.5):
    profile = run_wear(WearSimulation(scene(radius), LAWS, CYCLES, sliding=True)).final.profile
    for body in ("upper", "lower"):
        key = f"wear R_s {radius:g} mm|{body}"
        out[key + "|depth"] = profile.depth(body)
        out[key + "|measures"] = np.array(
            [profile.max_depth(body), profile.scar_width(body), profile.volume(body)]
        )
    print(f"wear R_s {radius:g}", flush=True)
np.savez(OUT, **out)
"""


def measure(tree: Path, out: Path) -> dict:
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1",
               PYTHONPATH=f"{tree / 'framework'}{os.pathsep}{tree / 'plugins'}")  # fmt: skip
    subprocess.run([sys.executable, "-c", MEASURE, str(tree), str(out)], env=env, check=True)
    return dict(np.load(out))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--before", type=Path, required=True)
    parser.add_argument("--after", type=Path, required=True)
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as scratch:
        before = measure(args.before, Path(scratch) / "before.npz")
        after = measure(args.after, Path(scratch) / "after.npz")
    print(f"load average {os.getloadavg()[0]:.2f}")
    print(
        "arc, step | specimen tractions, pair pressures, stresses (/p0) | moment less "
        "int g q ds before, after (/P a) | int g p phi ds (/P a) | force (/P) after"
    )
    for key in sorted(k.split("|")[0] for k in after if k.endswith("|meta")):
        old, new = before[key + "|meta"], after[key + "|meta"]
        p0, scale = new[4], new[2] * new[3]
        change = [np.abs(before[f"{key}|{n}"] - after[f"{key}|{n}"]).max() / p0
                  for n in ("specimen", "pressure", "stress")]  # fmt: skip
        print(f"{key:<32} {change[0]:.1e} {change[1]:.1e} {change[2]:.1e} | "
              f"{(old[1] - old[5]) / scale:+.2e} {(new[1] - new[5]) / scale:+.2e} | "
              f"{new[6] / scale:+.2e} | {new[0] / new[2]:.0e}")  # fmt: skip
    print("wear (after / before - 1) | deepest | profile (/deepest) | scar | volume")
    for key in sorted(k.rsplit("|", 1)[0] for k in after if k.endswith("|measures")):
        old, new = before[key + "|measures"], after[key + "|measures"]
        profile = np.abs(before[key + "|depth"] - after[key + "|depth"]).max() / old[0]
        print(f"{key:<24} {new[0] / old[0] - 1:+.1e} {profile:.1e} {new[1] / old[1] - 1:+.1e} "
              f"{new[2] / old[2] - 1:+.1e}")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
