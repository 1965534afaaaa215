"""The demo's VTK files written by fretbem's own writer against pyvista's (issue 28 item 4).

fretbem writes the .vtp boundaries as VTK XML from Python (``fretbem.output.vtk.save_vtk``);
the maintained alternative is pyvista (``to_polydata(arrays).save(path)``, VTK's own XML
writer). Each round runs two fresh processes on the same solved reference cycle (nurbs, 61
pairs, five steps, both bodies, plain and deformed: 20 files) and times, in CPU seconds,
the import of the writer plus the writing of every file; the files of both writers are then
read back with pyvista and compared array by array (points, lines, point, cell and field
data). Prints one JSON document (medians of ``--rounds``, the load before and after).
Usage::

    OPENBLAS_NUM_THREADS=1 python benchmarks/vtk_writer.py --rounds 5
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

CHILD = r"""
import json, sys, time
from pathlib import Path
from fretbem.scenes.reference import cattaneo_mindlin
from fretbem.simulation import run
result = run(cattaneo_mindlin(basis="nurbs", pairs=61))
folder, writer = Path(sys.argv[1]), sys.argv[2]
folder.mkdir(parents=True, exist_ok=True)
start = time.process_time()
if writer == "fretbem":
    from fretbem.output.vtk import save_vtk
    files = [p for p in save_vtk(result, folder) if p.suffix == ".vtp"]
else:  # the same arrays through pyvista's PolyData and VTK's XML writer
    import pyvista
    from fretbem.output.vtk import deformation_scale, deformed, step_arrays, to_polydata
    steps = [step_arrays(result, s) for s in result.steps]
    scale = deformation_scale([m for meshes in steps for m in meshes.values()])
    files = []
    for step, meshes in zip(result.steps, steps):
        for label, mesh in meshes.items():
            for suffix, data in (("", mesh), ("_deformed", deformed(mesh, scale))):
                path = folder / "vtk" / f"{step.name}_{label}{suffix}.vtp"
                path.parent.mkdir(exist_ok=True)
                to_polydata(data).save(path)
                files.append(path)
print(json.dumps({"cpu": time.process_time() - start, "files": len(files)}))
"""

SAME = r"""
import json, sys
import numpy as np
import pyvista as pv
from pathlib import Path
a, b = Path(sys.argv[1]) / "vtk", Path(sys.argv[2]) / "vtk"
names = sorted(p.name for p in a.glob("*.vtp"))
assert names == sorted(p.name for p in b.glob("*.vtp")), "different files"
for name in names:
    x, y = pv.read(a / name), pv.read(b / name)
    assert np.array_equal(x.points, y.points), name
    assert np.array_equal(x.lines, y.lines), name
    for kind in ("point_data", "cell_data", "field_data"):
        p, q = getattr(x, kind), getattr(y, kind)
        assert set(p.keys()) == set(q.keys()), (name, kind)
        for key in p.keys():
            assert np.asarray(p[key]).tolist() == np.asarray(q[key]).tolist(), (name, kind, key)
print(json.dumps({"files": len(names), "identical": True}))
"""


def _child(code: str, *args: str) -> dict:
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1"}
    done = subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True,
                          env=env, check=False)  # fmt: skip
    if done.returncode:
        raise RuntimeError(done.stderr[-2000:])
    return json.loads(done.stdout.strip().splitlines()[-1])


def main(rounds: int) -> dict:
    load = [round(os.getloadavg()[0], 2)]
    times: dict[str, list[float]] = {"fretbem": [], "pyvista": []}
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(rounds):
            for writer in times:  # interleaved
                times[writer].append(_child(CHILD, f"{tmp}/{writer}{k}", writer)["cpu"])
        check = _child(SAME, f"{tmp}/fretbem0", f"{tmp}/pyvista0")
    load.append(round(os.getloadavg()[0], 2))
    medians = {w: statistics.median(t) for w, t in times.items()}
    out = {
        "import + write, CPU s (median)": {w: round(v, 4) for w, v in medians.items()},
        "pyvista / fretbem": round(medians["pyvista"] / medians["fretbem"], 2),
        "runs": {w: [round(v, 4) for v in t] for w, t in times.items()},
        "read back in pyvista": check,
        "load": load,
    }
    print(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=5)
    main(parser.parse_args().rounds)
