"""Re-run of the hostile-input audit (issue 24's classes): each case is judged good or bad.

Classes, worst first: silent wrong result, data loss, traceback, misleading message or
missing limit, weak (silent coercion, missing note). A case is *good* when fretbem either
does the right thing or refuses with one line (exit 2, or 1 for a failed check) naming the
scene key; a traceback, a hang past the case's time limit, exit 0 on an input that must be
refused, or a message without the expected words is *bad*.

    python benchmarks/hostile_audit.py            # every class, a table and the counts
    python benchmarks/hostile_audit.py --only traceback --verbose
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import os
import signal
import sys
import tempfile
import textwrap
import time
import traceback
from collections import Counter
from pathlib import Path

import numpy as np

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

BASE = """
[pad]
shape = "cylinder"
radius = 70.0
[specimen]
shape = "cylinder"
[contact]
pairs = 11
[load]
steps = ["A", "B"]
P = 100.0
Q = [0.0, 18.0]
"""

RIG = """
[pad]
shape = "cylinder"
radius = 70.0
width = 10.0
height = 10.0
[specimen]
shape = "flat"
length = 40.0
thickness = 13.0
[material]
E = 72000.0
nu = 0.33
[contact]
friction = 0.5
pairs = 21
[load]
steps = ["A", "B", "C", "D", "E"]
P = 200.0
Q = [0.0, 45.0, 0.0, -45.0, 0.0]
bulk = [0.0, 90.0, 0.0, -90.0, 0.0]
"""

CASES: list = []


def case(klass: str, name: str, seconds: float = 60.0):
    """Register ``function() -> (good, detail)`` under ``klass``."""

    def register(function):
        CASES.append((klass, name, seconds, function))
        return function

    return register


class Timeout(Exception):
    pass


def _alarm(signum, frame):
    raise Timeout


def cli(*argv: str, seconds: float = 30.0) -> tuple[int | str, str]:
    """``fretbem argv`` in this process: (exit code or 'traceback'/'timeout', stderr+stdout)."""
    from fretbem.app.cli import main

    err, out = io.StringIO(), io.StringIO()
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
            code = main(list(argv))
    except Timeout:
        code = "timeout"
    except SystemExit as exit_:
        code = exit_.code
    except BaseException:
        code = "traceback"
        err.write(traceback.format_exc(limit=-2))
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)
    return code, err.getvalue() + out.getvalue()


WORK = Path(tempfile.mkdtemp(prefix="fretbem-audit-"))


def scene_file(text: str, name: str = "scene.toml", encoding: str | None = None) -> Path:
    path = WORK / f"{time.perf_counter_ns()}-{name}"
    path.write_bytes(text.encode(encoding) if encoding else text.encode())
    return path


def run_text(text: str, *extra: str, seconds: float = 30.0, encoding=None):
    path = scene_file(text, encoding=encoding)
    out = WORK / f"out-{time.perf_counter_ns()}"
    return cli("run", str(path), "--out", str(out), "--no-figures", "--no-vtk", *extra,
               seconds=seconds)  # fmt: skip


def refused(code, text, *words, exit_code=2) -> tuple[bool, str]:
    """Good if exit ``exit_code`` with one line holding every word (case-insensitive)."""
    line = text.strip().splitlines()[-1] if text.strip() else ""
    ok = code == exit_code and all(w.lower() in text.lower() for w in words)
    return ok, f"exit {code}: {line[:200]}"


def with_key(table: str, key: str, value: str, base: str = BASE) -> str:
    """``base`` with ``key = value`` set in ``[table]`` (added or replaced)."""
    lines, out, inside, done = base.strip().splitlines(), [], False, False
    for line in lines:
        if line.startswith("["):
            if inside and not done:
                out.append(f"{key} = {value}")
                done = True
            inside = line.strip() == f"[{table}]"
        elif inside and line.split("=")[0].strip() == key:
            out.append(f"{key} = {value}")
            done = True
            continue
        out.append(line)
    if not done:
        if not inside:
            out.append(f"[{table}]")
        out.append(f"{key} = {value}")
    return "\n".join(out) + "\n"


# ------------------------------------------------------------------ silent wrong results

SWEEP_FATIGUE = """
[sweep]
scene = "{scene}"
outputs = ["fretbem.studies.sweep.outputs:fatigue"]
[parameters]
"fatigue.constants.fatigue_strength_coefficient" = [1000.0, 2464.0]
[fatigue]
material = "Ti-6Al-4V"
methods = ["swt"]
critical_distance = 0.05
map_points = [9, 5]
"""


@case("silent-wrong", "sweep [fatigue] table vs swept fatigue.* parameter", 240)
def _sweep_fatigue():
    scene = scene_file(RIG.replace("pairs = 21", "pairs = 11"))
    sweep = scene_file(SWEEP_FATIGUE.format(scene=scene.name))
    out = WORK / "sweep-fatigue"
    code, text = cli("sweep", str(sweep), "--serial", "--out", str(out), "--no-figures",
                     seconds=240)  # fmt: skip
    if code != 0:
        return False, f"exit {code}: {text.strip()[-200:]}"
    import pandas as pd

    table = pd.concat(pd.read_parquet(p) for p in out.glob("cases-*.parquet"))
    lives = table.sort_values("case")["swt.life"].to_list()
    return bool(np.all(np.isfinite(lives))) and lives[0] != lives[1], f"swt.life {lives}"


@case("silent-wrong", "sweep of an adaptive-mesh scene", 240)
def _sweep_adaptive():
    scene = scene_file(
        BASE.replace("pairs = 11", 'mesh = "adaptive"\nbudget = 41\ntolerance = 0.05')
    )
    sweep = scene_file(
        f'[sweep]\nscene = "{scene.name}"\n[parameters]\n"contact.friction" = [0.3, 0.4]\n'
    )
    out = WORK / "sweep-adaptive"
    code, text = cli("sweep", str(sweep), "--serial", "--out", str(out), "--no-figures",
                     seconds=240)  # fmt: skip
    if code == 2 and "adaptive" in text:
        return True, f"refused: {text.strip()[-160:]}"
    if code != 0:
        return False, f"exit {code}: {text.strip()[-200:]}"
    import pandas as pd

    table = pd.concat(pd.read_parquet(p) for p in out.glob("cases-*.parquet"))
    if "pairs" not in table:
        return False, "no pairs column: which mesh was solved is not recorded"
    pairs = table["pairs"].to_list()
    return all(p != 61 for p in pairs) and set(table["status"]) == {"ok"}, f"pairs {pairs}"


FATIGUE_BAD = {
    "fatigue_strength_exponent": "0.5",
    "fatigue_ductility_exponent": "0.2",
    "fatigue_strength_coefficient": "-100.0",
    "fatigue_limit_range": "0.0",
    "threshold_sif_range": "-2.0",
    "findley_k": "-0.3",
    "yield_strength": "-5.0",
    "nu": "0.7",
    "E": "-1.0",
}


def _fatigue_scene(extra: str, **keys: str) -> str:
    table = {"material": '"Al 7050-T7451"', "methods": '["swt"]', "map_points": "[9, 5]", **keys}
    text = "".join(f"{k} = {v}\n" for k, v in table.items())
    return RIG.replace("pairs = 21", "pairs = 11") + "[fatigue]\n" + text + extra


for _key, _value in FATIGUE_BAD.items():

    @case("silent-wrong", f"unphysical [fatigue.constants] {_key} = {_value}")
    def _fatigue_constant(key=_key, value=_value):
        code, text = run_text(_fatigue_scene(f"[fatigue.constants]\n{key} = {value}\n"))
        return refused(code, text, key)


for _key, _value in {
    "area_radius_factor": "-1.0",
    "critical_distance": "-0.1",
    "runout_cycles": "-5.0",
    "map_depth": "-1.0",
}.items():

    @case("silent-wrong", f"unphysical [fatigue] {_key} = {_value}")
    def _fatigue_key(key=_key, value=_value):
        code, text = run_text(_fatigue_scene("").replace("[fatigue]\n", f"[fatigue]\n{key} = "
                                                                         f"{value}\n"))  # fmt: skip
        return refused(code, text, key)


def _result():
    from fretbem.scenes.reference import CattaneoMindlinScene, cattaneo_mindlin
    from fretbem.simulation import run

    return run(cattaneo_mindlin(CattaneoMindlinScene(pairs=21)))


for _field in (
    "pressure",
    "shear",
    "x",
    "normal_displacement",
    "tangential_displacement",
    "states",
    "unknowns",
):

    @case("silent-wrong", f"result array {_field} written in place")
    def _writable(field=_field):
        r = _result()
        array = getattr(r.steps[1], field)
        try:
            array[:1] = array[:1] * 2
        except (ValueError, TypeError) as err:
            return True, f"refused: {err}"
        return False, f"steps[1].{field} is writable"


@case("silent-wrong", "writer checks the tractions it writes (doubled pressure)")
def _writer_checks():
    import attrs

    from fretbem.output.write import write_results

    r = _result()
    step = r.steps[1]
    doubled = attrs.evolve(step, pressure=np.asarray(step.pressure) * 2)
    r2 = attrs.evolve(r, steps=(r.steps[0], doubled, *r.steps[2:]))
    try:
        write_results(r2, WORK / "doubled", figures=False, vtk=False)
    except Exception as err:
        return "edited" in str(err), f"{type(err).__name__}: {err}"[:200]
    summary = json.loads((WORK / "doubled" / "summary.json").read_text())
    passed = summary["steps"][1]["checks"]["equilibrium"]["passed"]
    return not passed, f"written, equilibrium passed = {passed}"


# ------------------------------------------------------------------ data loss


@case("data-loss", "glob characters in --out keep another run's staging")
def _glob_out():
    parent = WORK / "glob"
    parent.mkdir()
    other = parent / ".r1.tmp-abc"
    other.mkdir()
    (other / "results.csv").write_text("precious")
    for name in ("r*", "r[1]", "r?"):
        run_text(BASE, "--out", str(parent / name))
    return other.exists(), f"other staging {'kept' if other.exists() else 'deleted'}"


@case("data-loss", "a user's file inside a previous output is not deleted")
def _user_file():
    out = WORK / "userfile"
    run_text(BASE, "--out", str(out))
    (out / "notes.txt").write_text("mine")
    code, text = run_text(BASE, "--out", str(out))
    return (out / "notes.txt").exists() and code == 2, f"exit {code}: {text.strip()[-120:]}"


@case("data-loss", "a copied marker does not make a folder replaceable")
def _copied_marker():
    out = WORK / "marked"
    run_text(BASE, "--out", str(out))
    mine = WORK / "thesis"
    mine.mkdir()
    (mine / "chapter.tex").write_text("mine")
    (mine / ".fretbem-output").write_text((out / ".fretbem-output").read_text())
    code, text = run_text(BASE, "--out", str(mine))
    return (mine / "chapter.tex").exists(), f"exit {code}: {text.strip()[-120:]}"


# ------------------------------------------------------------------ tracebacks

NURBS_PAD = """
[[{body}.segments]]
tag = "{tag}"
degree = 1
knots = [0.0, 0.0, 1.0, 1.0]
points = [[-1.0, 0.0], [1.0, 0.0]]
"""

for _body in ("pad", "specimen"):
    for _tag in ("contact", "face"):

        @case("traceback", f"shape = 'nurbs' {_body} with a {_tag!r} segment")
        def _nurbs(body=_body, tag=_tag):
            text = with_key(body, "shape", '"nurbs"').replace("radius = 70.0\n", "")
            text += NURBS_PAD.format(body=body, tag=tag)
            code, out = run_text(text)
            return refused(code, out, body)


#: hostile values tried on every key of the scene file
HOSTILE_VALUES = [
    "9223372036854775807",
    "-9223372036854775808",
    "0",
    "-1",
    "1e308",
    "1e-308",
    '"x"',
    "true",
    "[]",
    "[1, 2]",
    "{ a = 1 }",
    "2.5",
]


def _keys():
    from fretbem.scenes.spec import KEYS

    skip = {"segments"}
    return [(k.table, k.name) for k in KEYS if k.name not in skip and not k.shapes]


for _table, _name in _keys():
    for _value in HOSTILE_VALUES:

        @case("traceback", f"[{_table}] {_name} = {_value}", 30)
        def _fuzz(table=_table, name=_name, value=_value):
            code, out = run_text(with_key(table, name, value), seconds=25)
            ok = code in (0, 1, 2) and "Traceback" not in out
            if code == 2:
                ok = name in out or "traceback" not in out.lower()
            return ok, f"exit {code}: {out.strip().splitlines()[-1][:160] if out.strip() else ''}"


# ------------------------------------------------------------------ misleading / limits


@case("misleading", "empty [load] steps")
def _empty_steps():
    return refused(*run_text(with_key("load", "steps", "[]").replace("Q = [0.0, 18.0]", "")),
                   "steps")  # fmt: skip


@case("misleading", "material error names a table the file has")
def _material_table():
    code, text = run_text(with_key("material", "plane", '"strainn"'))
    return refused(code, text, "[material]") if "[pad.material]" not in text else (False, text)


for _encoding in ("latin-1", "utf-16", "utf-8-sig"):

    @case("misleading", f"scene file in {_encoding}")
    def _encoded(encoding=_encoding):
        text = "# pad: Ø 70 mm, µ = 0.3\n" + BASE
        code, out = run_text(text, encoding=encoding)
        if code == 0:
            return True, "read"
        return refused(code, out, encoding.split("-")[0].replace("utf", "utf"))


@case("misleading", "a /dev/zero scene is refused by its size, not blamed on pairs", 30)
def _dev_zero():
    code, text = cli("run", "/dev/zero", "--out", str(WORK / "zero"), seconds=25)
    return refused(code, text, "larger than") if "pairs" not in text else (False, text)


@case("misleading", "--out name too long for the lock is refused before computing")
def _long_out():
    name = "r" * 250
    t = time.perf_counter()
    code, text = run_text(BASE.replace("pairs = 11", "pairs = 61"), "--out", str(WORK / name))
    seconds = time.perf_counter() - t
    return code == 2 and "long" in text and seconds < 3, f"exit {code} {seconds:.1f} s: " + \
        text.strip()[-120:]  # fmt: skip


@case("misleading", "increments = 1e9 refused up front with the estimate", 20)
def _increments():
    code, text = run_text(with_key("load", "increments", "1000000000"), seconds=15)
    return refused(code, text, "increments", "estimate")


@case("misleading", "an 11-million-entry Q list refused up front", 60)
def _long_q():
    n = 11_000_000
    text = BASE.replace('steps = ["A", "B"]\n', "").replace(
        "Q = [0.0, 18.0]", "Q = [0.0, " + ", ".join(["1.0"] * (n - 1)) + "]"
    )
    code, out = run_text(text, seconds=55)
    return refused(code, out, "MB", "split")


@case("misleading", "a 2000 x 2000 stress grid refused up front with its estimate", 30)
def _grid():
    text = BASE + "[stress]\nfigures = false\nvtk = false\n[stress.grid]\nx = [-1.0, 1.0]\n"
    text += "depth = 1.0\nnx = 2000\nny = 2000\n"
    code, out = run_text(text, seconds=25)
    return refused(code, out, "[stress.grid]", "estimate")


@case("misleading", "bulk stress in step A: the default solver succeeds or advises", 120)
def _bulk_in_a():
    text = RIG.replace(
        "bulk = [0.0, 90.0, 0.0, -90.0, 0.0]", "bulk = [60.0, 90.0, 0.0, -90.0, 0.0]"
    )
    code, out = run_text(text, seconds=110)
    return code == 0 or (code == 2 and "lemke" in out), f"exit {code}: {out.strip()[-200:]}"


@case("misleading", "near gross slip the advice is quantified (not just 'more pairs')", 120)
def _near_gross():
    text = BASE.replace("Q = [0.0, 18.0]", "Q = [0.0, 29.99]")
    code, out = run_text(text, seconds=110)
    # more pairs would not help at |Q| = 0.9997 f P: the advice says how many it would take
    good = code == 0 or (code in (1, 2) and "times the pairs" in out)
    return good, f"exit {code}: {out.strip()[-200:]}"


def _sweep(body: str, scene_text: str = BASE, *extra: str, seconds=120):
    scene = scene_file(scene_text)
    sweep = scene_file(f'[sweep]\nscene = "{scene.name}"\n' + body)
    out = WORK / f"sweep-{time.perf_counter_ns()}"
    t = time.perf_counter()
    code, text = cli("sweep", str(sweep), "--serial", "--out", str(out), *extra, seconds=seconds)
    return code, text, time.perf_counter() - t, out


@case("misleading", "sweep [[maps]] column typo refused before solving")
def _map_typo():
    code, text, seconds, _ = _sweep(
        '[parameters]\n"load.P" = [90.0, 100.0]\n"contact.friction" = [0.3, 0.4]\n'
        '[[maps]]\nx = "load.P"\ny = "contact.friction"\ncolumn = "stick_widht.B"\n'
    )
    return code == 2 and "stick_widht" in text and "solved" not in text, (
        f"exit {code} {seconds:.1f} s: {text.strip()[-160:]}"
    )


@case("misleading", "sweep map axis that is not a parameter refused before solving")
def _map_axis():
    code, text, seconds, _ = _sweep(
        '[parameters]\n"load.P" = [90.0, 100.0]\n"contact.friction" = [0.3, 0.4]\n'
        '[[maps]]\nx = "load.P"\ny = "load.Q"\n'
    )
    return code == 2 and "load.Q" in text and "solved" not in text, (
        f"exit {code} {seconds:.1f} s: {text.strip()[-160:]}"
    )


@case("misleading", "sweep outputs accept only registered outputs (os:getcwd)")
def _outputs():
    code, text, _, _ = _sweep('outputs = ["os:getcwd"]\n[parameters]\n"load.P" = [90.0]\n')
    return refused(code, text, "os:getcwd")


@case("misleading", "planning a 1e6-case sweep is refused or lazy", 30)
def _huge():
    body = '[parameters]\n"load.P" = { start = 50.0, stop = 150.0, num = 1000 }\n'
    body += '"contact.friction" = { start = 0.2, stop = 0.6, num = 1000 }\n'
    code, text, seconds, _ = _sweep(body, BASE, "--limit", "1", seconds=25)
    return code in (0, 2) and seconds < 20, f"exit {code} {seconds:.1f} s: {text.strip()[-160:]}"


def _chunk_case(spoil) -> tuple[bool, str]:
    scene = scene_file(BASE)
    sweep = scene_file(f'[sweep]\nscene = "{scene.name}"\n[parameters]\n"load.P" = [90.0, 100.0]\n')
    out = WORK / f"sweep-{time.perf_counter_ns()}"
    cli("sweep", str(sweep), "--serial", "--out", str(out), "--no-figures", seconds=60)
    chunk = sorted(out.glob("cases-*.parquet"))[0]
    spoil(chunk)
    code, text = cli("sweep", str(sweep), "--serial", "--out", str(out), "--no-figures")
    return refused(code, text, chunk.name)


def _rewrite(chunk):
    import pandas as pd

    frame = pd.read_parquet(chunk)
    frame["p_max.B"] = frame["p_max.B"] * 2
    frame.to_parquet(chunk)


@case("misleading", "a rewritten Parquet chunk in a store is refused naming the file")
def _rewritten_chunk():
    return _chunk_case(_rewrite)


@case("misleading", "a corrupt Parquet chunk's error names the file")
def _corrupt_chunk():
    return _chunk_case(lambda chunk: chunk.write_bytes(b"garbage"))


@case("misleading", "a foreign Parquet chunk (no checksum) is refused naming the file")
def _foreign_chunk():
    def spoil(chunk):
        foreign = chunk.with_name("cases-0000099-0000099-deadbeef.parquet")
        foreign.write_bytes(chunk.read_bytes())
        chunk.rename(foreign)  # keep only the copy, without its checksum file
        Path(str(chunk) + ".sha256").unlink()
        foreign.rename(chunk)

    return _chunk_case(spoil)


@case("misleading", "two sweeps into one store: the second is refused while the first runs")
def _store_lock():
    from fretbem.output.staging import output_lock

    scene = scene_file(BASE)
    sweep = scene_file(f'[sweep]\nscene = "{scene.name}"\n[parameters]\n"load.P" = [90.0]\n')
    out = WORK / f"sweep-{time.perf_counter_ns()}"
    with output_lock(out.resolve()):  # a first sweep holding the store
        code, text = cli("sweep", str(sweep), "--serial", "--out", str(out), "--no-figures")
    return refused(code, text, "another fretbem run")


@case("misleading", "a fixed [[maps]] entry is redrawn from the store, no new sweep")
def _redraw():
    scene = scene_file(BASE)
    body = '[parameters]\n"load.P" = [90.0, 100.0]\n"contact.friction" = [0.3, 0.4]\n'
    sweep = scene_file(f'[sweep]\nscene = "{scene.name}"\n{body}')
    out = WORK / f"sweep-{time.perf_counter_ns()}"
    cli("sweep", str(sweep), "--serial", "--out", str(out), "--no-figures")
    fixed = scene_file(sweep.read_text() + '[[maps]]\nx = "load.P"\ny = "contact.friction"\n'
                       'column = "stick_width.B"\n')  # fmt: skip
    code, text = cli("sweep", str(fixed), "--serial", "--out", str(out), "--maps-only")
    return code == 0 and "map-stick_width_B" in text, f"exit {code}: {text.strip()[-160:]}"


@case("misleading", "a one-parameter sweep draws a line plot")
def _line():
    scene = scene_file(BASE)
    sweep = scene_file(f'[sweep]\nscene = "{scene.name}"\n[parameters]\n"load.P" = [90.0, 100.0]\n')
    out = WORK / f"sweep-{time.perf_counter_ns()}"
    code, text = cli("sweep", str(sweep), "--serial", "--out", str(out))
    return code == 0 and "figure:" in text, f"exit {code}: {text.strip()[-160:]}"


# ------------------------------------------------------------------ weak

COERCION = [
    ("[fatigue] in_plane_only", "in_plane_only", '"false"'),
    ("[fatigue] cycle_steps", "cycle_steps", "[1.7, 2.2, 3.9]"),
    ("[fatigue] map_points", "map_points", "[9.5, 5]"),
    ("[fatigue] runout_cycles", "runout_cycles", "true"),
    ("[fatigue] critical_distance", "critical_distance", '"0.05"'),
    ("[fatigue] methods", "methods", "[1, 2]"),
    ("[fatigue] direction", "direction", "1"),
]
for _label, _key, _value in COERCION:

    @case("weak", f"{_label} = {_value}")
    def _coerce_fatigue(key=_key, value=_value):
        code, text = run_text(_fatigue_scene("", **{key: value}))
        return refused(code, text, key)


STRESS_COERCION = [
    ("line", "n", "2.7"),
    ("line", "n", "true"),
    ("line", "depth", '"1.0"'),
    ("line", "grading", "false"),
    ("line", "x", "true"),
    ("grid", "nx", "20.5"),
    ("grid", "depth", "true"),
]
for _where, _key, _value in STRESS_COERCION:

    @case("weak", f"[stress.{_where}] {_key} = {_value}")
    def _coerce_stress(where=_where, key=_key, value=_value):
        line = {"x": "0.0", "depth": "1.0", "n": "5", "grading": "2.0"}
        grid = {"x": "[-1.0, 1.0]", "depth": "1.0", "nx": "5", "ny": "5"}
        table = dict(line if where == "line" else grid)
        table[key] = value
        text = BASE + "[stress]\nfigures = false\nvtk = false\n"
        text += f"[stress.{where}]\n" + "".join(f"{k} = {v}\n" for k, v in table.items())
        code, out = run_text(text)
        return refused(code, out, key)


for _key, _value in (("degree", "2.5"), ("pairs", "11.0"), ("friction", "true"),
                     ("zone", "false"), ("estimate", "1")):  # fmt: skip

    @case("weak", f"[contact] {_key} = {_value}")
    def _coerce_contact(key=_key, value=_value):
        return refused(*run_text(with_key("contact", key, value)), key)


@case("weak", "zone and zone_width both given")
def _zone_both():
    text = with_key("contact", "zone", "1.5", with_key("contact", "zone_width", "0.8"))
    return refused(*run_text(text), "zone_width")


@case("weak", "sweep file pattern and values coerced")
def _sweep_bool():
    code, text, _, _ = _sweep('[parameters]\n"contact.pairs" = [true]\n', BASE, "--no-figures")
    return refused(code, text, "contact.pairs")


@case("weak", "5 pairs: a large estimated error is not reported silently", 60)
def _five_pairs():
    _code, text = run_text(BASE.replace("pairs = 11", "pairs = 5"))
    return "estimate" in text.lower() and ("coarse" in text or "not converged" in text or
                                           "exceeds" in text), text.strip()[-200:]  # fmt: skip


@case("weak", "closed form compared outside its validity (a/R large)", 60)
def _validity():
    text = BASE.replace("radius = 70.0", "radius = 2.0\nwidth = 3.0\nheight = 3.0")
    text = text.replace("[specimen]\n", "[specimen]\nradius = 2.0\nwidth = 3.0\nheight = 3.0\n")
    text = text.replace("P = 100.0", "P = 3000.0").replace("Q = [0.0, 18.0]", "Q = [0.0, 500.0]")
    code, out = run_text(text)
    return ("validity" in out or "a / R" in out) and code in (0, 2), out.strip()[-200:]


@case("weak", "finite bodies: the comparison is called the difference from theory", 60)
def _difference():
    code, out = run_text(BASE)
    return code == 0 and "difference from half-plane theory" in out, out.strip()[-200:]


@case("weak", "an adaptive run that misses its tolerance says so", 120)
def _adaptive_missed():
    text = BASE.replace("pairs = 11", 'mesh = "adaptive"\ntolerance = 0.001\nbudget = 21')
    code, out = run_text(text, seconds=110)
    return code == 0 and "above the tolerance" in out, out.strip()[-200:]


# ------------------------------------------------------------------ rotation and mean stress
# The pad block's rotation ([rig] stiffness_rotation, pivot_height, [load] moment, rotation,
# [load.cycle] M_amplitude, M_phase) and the mean-stress corrections ([fatigue] mean_stress):
# every key's hostile values, the keys against each other and against the other features,
# and sweeps over them (their values honoured or refused before solving).

#: half-plane bodies with the pivot at the contact: a moment there only shifts the contact
HP = (
    BASE.replace("radius = 70.0", 'radius = 70.0\nmodel = "half-plane"')
    .replace(
        '[specimen]\nshape = "cylinder"', '[specimen]\nshape = "cylinder"\nmodel = "half-plane"'
    )
    .replace("pairs = 11", "pairs = 21\nestimate = false")
    + "[rig]\npivot_height = 0.0\n"
)
#: a cyclic history with a moment on the half-plane bodies
CYCLE = HP.replace('steps = ["A", "B"]\n', "").replace(
    "Q = [0.0, 18.0]", "moment = 1.0\n[load.cycle]\nQ = 9.0\nincrements = 8"
)
ROTATION_VALUES = ["nan", "inf", "-inf", '"x"', "true", "[]", "[1.0, 2.0, 3.0]", "{ a = 1 }",
                   "0.0", "-1.0", "1e308", "-1e308", "1e-308"]  # fmt: skip
ROTATION_KEYS = [
    ("rig", "stiffness_rotation", BASE),
    ("rig", "pivot_height", HP),
    ("load", "moment", HP),
    ("load", "rotation", HP),
    ("load.cycle", "M_amplitude", CYCLE),
    ("load.cycle", "M_phase", CYCLE),
]


def _named(code, text, name) -> tuple[bool, str]:
    """Good: a run (0), a failed check (1) or a refusal (2) naming ``name``; no traceback."""
    line = text.strip().splitlines()[-1] if text.strip() else ""
    good = code in (0, 1, 2) and "Traceback" not in text
    if code in (1, 2):
        good = good and name in text
    return good, f"exit {code}: {line[:200]}"


for _table, _name, _base in ROTATION_KEYS:
    for _value in ROTATION_VALUES:

        @case("traceback", f"rotation key [{_table}] {_name} = {_value}", 60)
        def _rotation_value(table=_table, name=_name, value=_value, base=_base):
            if table == "load.cycle":
                text = base.replace("increments = 8", f"increments = 8\n{name} = {value}")
                if name == "M_phase":
                    text = text.replace("increments = 8", "increments = 8\nM_amplitude = 2.0")
            else:
                text = with_key(table, name, value, base)
            return _named(*run_text(text, seconds=55), name)


for _value in ('"goodmann"', "1.0", "true", '["goodman"]', '""', '"Goodman"'):

    @case("weak", f"[fatigue] mean_stress = {_value}")
    def _mean_stress_value(value=_value):
        text = _fatigue_scene("", methods='["stress_life"]', mean_stress=value)
        return refused(*run_text(text), "mean_stress")


for _methods, _correction, _words in (
    ('["swt"]', '"goodman"', ("mean_stress", "stress_life")),
    ('["strain_life"]', '"goodman"', ("mean_stress", "morrow")),
    ('["strain_life"]', '"gerber"', ("mean_stress", "morrow")),
    ('["stress_life", "strain_life"]', '"goodman"', ("mean_stress", "strain_life")),
    ('["findley", "stress_life"]', '"morrow_true_fracture"', ("true_fracture_strength",)),
):

    @case("misleading", f"[fatigue] mean_stress = {_correction} with methods = {_methods}")
    def _mean_stress_methods(methods=_methods, correction=_correction, words=_words):
        # (Al 7050-T7451 has no true fracture strength: morrow_true_fracture names it)
        text = _fatigue_scene("", methods=methods, mean_stress=correction)
        return refused(*run_text(text), *words)


for _methods, _correction in (('["stress_life"]', '"none"'), ('["stress_life"]', '"goodman"'),
                              ('["stress_life"]', '"gerber"'), ('["stress_life"]', '"morrow"'),
                              ('["strain_life"]', '"morrow"'),
                              ('["swt", "stress_life"]', '"goodman"')):  # fmt: skip

    @case("silent-wrong", f"mean_stress = {_correction}, methods = {_methods}: lives written", 120)
    def _mean_stress_runs(methods=_methods, correction=_correction):
        text = _fatigue_scene("", methods=methods, mean_stress=correction)
        text = text.replace('"Al 7050-T7451"', '"Ti-6Al-4V"')  # sigma_f' and sigma_u sourced
        out = WORK / f"ms-{time.perf_counter_ns()}"
        path = scene_file(text)
        code, said = cli("run", str(path), "--out", str(out), "--no-figures", "--no-vtk",
                         seconds=110)  # fmt: skip
        if code != 0:
            return False, f"exit {code}: {said.strip()[-200:]}"
        report = json.loads((out / "fatigue.json").read_text())
        entry = next(iter(report["methods"].values())) if "methods" in report else report
        text_ = json.dumps(report)
        named = correction.strip('"') in text_ or correction == '"none"'
        return named and bool(entry), f"fatigue.json names the correction: {named}"


def _tip_case(text, *words):
    code, out = run_text(text, seconds=55)
    return refused(code, out, *words)


@case("misleading", "a moment with Q below the pivot: the block tips, the keys named", 60)
def _tips():
    return _tip_case(with_key("load", "moment", "0.0"), "[load] moment", "pivot_height", "d =")


@case("misleading", "a near-zero rotational stiffness: the spring named", 60)
def _soft():
    return _tip_case(with_key("rig", "stiffness_rotation", "1e-12"), "stiffness_rotation")


@case("silent-wrong", "Lemke's method never solves a rotating block (fallback, moment 1e6)", 60)
def _no_lemke_fallback():
    code, out = run_text(with_key("load", "moment", "1e6"), seconds=55)
    return code == 2 and "Lemke" not in out and "moment" in out, f"exit {code}: " + \
        out.strip()[-200:]  # fmt: skip


@case("misleading", "a rotation the contact cannot follow: the zone check names it", 60)
def _zone_rotation():
    code, out = run_text(with_key("load", "rotation", "1.0"), seconds=55)
    tail = out.split("enlarge")[-1]  # the check's own advice names the zone: past it
    return code in (1, 2) and "rotation" in tail, f"exit {code}: {out.strip()[-200:]}"


for _solver in ("lemke",):
    for _key, _value in (("stiffness_rotation", "1e5"), ("moment", "[0.0, 1.0]")):

        @case("misleading", f"solver = {_solver!r} with {_key}: refused naming newton")
        def _lcp(solver=_solver, key=_key, value=_value):
            table = "rig" if key == "stiffness_rotation" else "load"
            text = with_key("contact", "solver", f'"{solver}"', with_key(table, key, value, HP))
            return refused(*run_text(text), "newton")


SLIDING = """
[pad]
model = "half-plane"
radius = 70.0
[specimen]
model = "half-plane"
shape = "flat"
length = 40.0
thickness = 13.0
[contact]
pairs = 21
pairing = "node-to-segment"
sliding = true
estimate = false
[load]
steps = ["A", "B"]
P = 100.0
delta = [0.0, 0.5]
"""


for _table, _key, _value in (("rig", "stiffness_rotation", "1e5"),
                             ("load", "rotation", "[0.0, 0.0001]")):  # fmt: skip

    @case("misleading", f"finite sliding on a flat with [{_table}] {_key}: the block turns")
    def _sliding(table=_table, key=_key, value=_value):
        code, text = run_text(with_key(table, key, value, SLIDING))
        return code == 0, f"exit {code}: {text.strip()[-160:]}"


@case("misleading", "finite sliding with a [load] moment the contact cannot balance: named")
def _sliding_moment():
    # M = 1 N mm/mm against h Q = 300: the contact leaves the zone, a failed check
    return refused(*run_text(with_key("load", "moment", "1.0", SLIDING)), "moment", exit_code=1)


@case("misleading", "finite sliding along an arc with a rotating block: the block turns")
def _sliding_arc_rotation():
    arc = SLIDING.replace('model = "half-plane"\n', "").replace(
        'shape = "flat"\nlength = 40.0\nthickness = 13.0',
        'shape = "cylinder"\nradius = 70.0\nwidth = 12.0\nheight = 10.0',
    )
    code, text = run_text(with_key("rig", "stiffness_rotation", "5e5", arc))
    return code == 0, f"exit {code}: {text.strip()[-160:]}"


for _label, _text in (
    (
        "moment with displacement control (delta)",
        with_key("load", "moment", "1.0", HP.replace("Q = [0.0, 18.0]", "delta = [0.0, 0.0005]")),
    ),
    (
        "rotation with displacement control (delta)",
        with_key(
            "load",
            "rotation",
            "[0.0, 0.0001]",
            HP.replace("Q = [0.0, 18.0]", "delta = [0.0, 0.0005]"),
        ),
    ),
    ("rotation spring on half-plane bodies", with_key("rig", "stiffness_rotation", "1e5", HP)),
    ("rotation spring on bem bodies", with_key("rig", "stiffness_rotation", "1e5")),
    ("moment on half-plane bodies", with_key("load", "moment", "[0.0, 2.0]", HP)),
    (
        "moment on a bem pad, pivot at the contact",
        with_key("rig", "pivot_height", "0.0", with_key("load", "moment", "[0.0, 2.0]")),
    ),
    (
        "cyclic moment (M_amplitude, M_phase)",
        CYCLE.replace("increments = 8", "increments = 8\nM_amplitude = 2.0\nM_phase = 90.0"),
    ),
    (
        "moment with node-to-segment pairing",
        with_key("contact", "pairing", '"node-to-segment"', with_key("load", "moment", "1.0", HP)),
    ),
    (
        "moment with the lagrange2 family",
        with_key("contact", "basis", '"lagrange2"', with_key("load", "moment", "1.0", HP)),
    ),
):

    @case("silent-wrong", f"{_label}: runs, M and tilt in summary.json", 120)
    def _combination(text=_text):
        out = WORK / f"rot-{time.perf_counter_ns()}"
        code, said = cli("run", str(scene_file(text)), "--out", str(out), "--no-figures",
                         "--no-vtk", seconds=110)  # fmt: skip
        if code != 0:
            return False, f"exit {code}: {said.strip()[-200:]}"
        steps = json.loads((out / "summary.json").read_text())["steps"]
        values = [(s["M"], s["tilt"]) for s in steps]
        good = all(m is not None and t is not None for m, t in values)
        return good and any(t != 0 for _, t in values), f"(M, tilt) {values[-1]}"


WEAR = """
[pad]
shape = "cylinder"
radius = 70.0
width = 10.0
height = 10.0
model = "half-plane"
[specimen]
shape = "flat"
length = 40.0
thickness = 13.0
support = "ends"
model = "half-plane"
[material]
E = 116000.0
nu = 0.342
[contact]
friction = 0.5
pairs = 21
zone = 3.0
estimate = false
[rig]
stiffness_rotation = 2.0e5
[load]
steps = ["A", "B", "C", "D", "E"]
P = 400.0
Q = [0.0, 90.0, 0.0, -90.0, 0.0]
[wear]
law = "energy"
pad = 1.8e-4
specimen = 1.8e-4
cycles = 10000
"""


@case("silent-wrong", "rotation with [wear]: worn and tilting, or refused by name", 240)
def _wear_rotation():
    out = WORK / f"wear-{time.perf_counter_ns()}"
    code, said = cli("run", str(scene_file(WEAR)), "--out", str(out), "--no-figures", "--no-vtk",
                     seconds=230)  # fmt: skip
    if code == 2 and "rotat" in said:
        return True, f"refused: {said.strip()[-160:]}"
    if code != 0:
        return False, f"exit {code}: {said.strip()[-200:]}"
    steps = json.loads((out / "summary.json").read_text())["steps"]
    worn = (out / "wear_summary.csv").exists()
    return worn and steps[1]["tilt"] < 0, f"worn {worn}, tilt B {steps[1]['tilt']:.3g}"


def _swept(parameters: str, scene_text: str):
    """The rows of a serial sweep of ``parameters`` over ``scene_text``, sorted by case."""
    import pandas as pd

    code, text, _, out = _sweep(f"[parameters]\n{parameters}\n", scene_text, "--no-figures",
                                seconds=230)  # fmt: skip
    if code != 0:
        raise RuntimeError(f"exit {code}: {text.strip()[-200:]}")
    table = pd.concat(pd.read_parquet(p) for p in out.glob("cases-*.parquet"))
    return table.sort_values("case")


#: half-plane pad on a flat specimen on its ends, a bulk stress for the fatigue columns
SWEEP_SCENE = HP.replace(
    '[specimen]\nshape = "cylinder"\nmodel = "half-plane"',
    '[specimen]\nshape = "flat"\nmodel = "half-plane"\nlength = 40.0\nthickness = 13.0\n'
    'support = "ends"',
).replace("Q = [0.0, 18.0]", "Q = [0.0, 18.0]\nbulk = [0.0, 40.0]")


def _check_swept(path: str, values: list, scene_text: str, column: str = "p_max.B"):
    """Every swept value honoured: each case's column equals a direct solve's."""
    from fretbem.scenes.builder import build
    from fretbem.scenes.spec import scene_from_dict
    from fretbem.simulation import run
    from fretbem.studies.sweep.cases import step_metrics
    from fretbem.studies.sweep.spec import set_path

    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover
        import tomli as tomllib
    table = _swept(f'"{path}" = {json.dumps(values)}', scene_text)
    got, want = [], []
    for value, (_, row) in zip(values, table.iterrows(), strict=True):
        data = tomllib.loads(scene_text)
        set_path(data, path, value)
        step = run(build(scene_from_dict(data))[0]).steps[1]
        got.append(float(row[column]))
        want.append(step_metrics(step)[column.split(".")[0]])
    good = set(table["status"]) == {"ok"} and np.allclose(got, want, rtol=1e-9, atol=0)
    return good, f"sweep {np.round(got, 6).tolist()} direct {np.round(want, 6).tolist()}"


@case("silent-wrong", "sweep over load.moment: every value honoured", 240)
def _sweep_moment():
    return _check_swept(
        "load.moment",
        [0.0, 3.0, -3.0],
        with_key("load", "moment", "0.0", SWEEP_SCENE),
        "stick_width.B",
    )


@case("silent-wrong", "sweep over rig.stiffness_rotation: every value honoured", 240)
def _sweep_stiffness():
    scene = with_key("rig", "stiffness_rotation", "1e5",
                     with_key("rig", "pivot_height", "3.0", SWEEP_SCENE))  # fmt: skip
    return _check_swept("rig.stiffness_rotation", [3e4, 1e5, 1e6], scene)


@case("silent-wrong", "sweep over rig.pivot_height: every value honoured", 240)
def _sweep_pivot():
    scene = with_key("rig", "stiffness_rotation", "1e5", SWEEP_SCENE)
    return _check_swept("rig.pivot_height", [0.0, 2.0, 4.0], scene)


@case("silent-wrong", "sweep over fatigue.mean_stress: every correction honoured", 240)
def _sweep_mean_stress():
    from fretbem.fatigue import fatigue_request_from_dict
    from fretbem.fatigue.from_simulation import SimulationStressHistory
    from fretbem.fatigue.run import run_fatigue
    from fretbem.scenes.builder import build
    from fretbem.scenes.spec import scene_from_dict
    from fretbem.simulation import run

    if sys.version_info >= (3, 11):
        import tomllib
    else:  # pragma: no cover
        import tomli as tomllib
    fatigue = {"material": "Ti-6Al-4V", "methods": ["stress_life"], "critical_distance": 0.05,
               "map_points": [9, 5]}  # fmt: skip
    corrections = ["none", "goodman", "gerber", "morrow"]
    body = 'outputs = ["fatigue"]\n[parameters]\n'
    body += f'"fatigue.mean_stress" = {json.dumps(corrections)}\n'
    body += "[fatigue]\n" + "".join(f"{k} = {json.dumps(v)}\n" for k, v in fatigue.items())
    code, text, _, out = _sweep(body, SWEEP_SCENE, "--no-figures", seconds=230)
    if code != 0:
        return False, f"exit {code}: {text.strip()[-200:]}"
    import pandas as pd

    table = pd.concat(pd.read_parquet(p) for p in out.glob("cases-*.parquet")).sort_values("case")
    result = run(build(scene_from_dict(tomllib.loads(SWEEP_SCENE)))[0])
    got, want = [], []
    for correction, (_, row) in zip(corrections, table.iterrows(), strict=True):
        report = run_fatigue(
            SimulationStressHistory(result),
            fatigue_request_from_dict({**fatigue, "mean_stress": correction}),
        )
        entry = report.methods["stress_life"]
        got.append(float(row["stress_life.parameter"]))
        want.append(float(entry.at_hot_spot.value[0]))
    good = np.allclose(got, want, rtol=1e-9) and len(set(np.round(got, 9))) == len(got)
    return good, f"sweep {np.round(got, 4).tolist()} direct {np.round(want, 4).tolist()}"


for _path, _values, _scene, _words in (
    ("fatigue.mean_stress", '["none", "goodmann"]', None, ("goodmann",)),
    ("rig.stiffness_rotation", "[1e5, -1.0]", None, ("stiffness_rotation",)),
    ("rig.pivot_height", "[0.0, 1e9]", None, ("pivot_height",)),
    ("load.moment", '["x"]', None, ("load.moment",)),
    ("load.moment", "[[1.0, 2.0, 3.0]]", None, ("moment",)),
    ("load.rotation", "[0.0, 0.001]", "moment", ("moment and rotation",)),
    ("load.cycle.M_amplitude", "[1.0, true]", "cycle", ("M_amplitude",)),
):

    @case("misleading", f"sweep {_path} = {_values}: refused before solving", 60)
    def _sweep_bad(path=_path, values=_values, scene=_scene, words=_words):
        base = {None: SWEEP_SCENE, "moment": with_key("load", "moment", "0.0", SWEEP_SCENE),
                "cycle": CYCLE}[scene]  # fmt: skip
        body = f'[parameters]\n"{path}" = {values}\n'
        if path.startswith("fatigue"):
            body = f'outputs = ["fatigue"]\n{body}[fatigue]\nmaterial = "Ti-6Al-4V"\n'
            body += 'methods = ["stress_life"]\ncritical_distance = 0.05\n'
        code, text, seconds, _ = _sweep(body, base, "--no-figures", seconds=55)
        good = code == 2 and all(w in text for w in words) and "solved" not in text
        return good, f"exit {code} {seconds:.1f} s: {text.strip()[-160:]}"


# ------------------------------------------------------------- Python records (no file)

#: the public records a script builds for a run, each with valid keyword arguments; every
#: numeric field is then given True, "3", nan, inf and None (where None means nothing)
PY_RECORDS = (
    ("fretbem:LoadStep", {"name": "A", "normal": 100.0, "tangential": 5.0, "increments": 2}),
    ("fretbem:LoadStep", {"name": "A", "normal": None, "approach": 1e-3, "delta": 1e-3,
                          "cycle": 1, "moment": 5.0}),
    ("fretbem:LoadStep", {"name": "A", "normal": 100.0, "rotation": 1e-4}),
    ("fretbem.fretting:Waveform", {
        "amplitude": 1e-3, "normal": 100.0, "cycles": 2, "increments": 8,
        "normal_amplitude": 10.0, "normal_phase": 90.0, "bulk": 50.0, "bulk_amplitude": 20.0,
        "bulk_phase": 0.0, "moment": 1.0, "moment_amplitude": 2.0, "moment_phase": 0.0}),
    ("fretbem:Material", {"E": 73400.0, "nu": 0.33}),
    ("fretbem:CoulombFriction", {"friction": 0.3}),
    ("fretbem.wear:ArchardWear", {"k": 1e-8}),
    ("fretbem.wear:EnergyWear", {"alpha": 2e-4}),
    ("fretbem.wear.jump:JumpControl", {"max_change": 1e-4, "relative_change": 0.05,
                                       "safety": 0.5, "max_jump": 100}),
    ("fretbem.contact.control:Rig", {"tangential": 1e4, "normal": 1e5, "rotational": 1e6,
                                     "pivot_height": 10.0}),
    ("fretbem.geometry.shapes:CylinderPad", {"radius": 70.0, "width": 6.5, "height": 16.25}),
    ("fretbem.geometry.shapes:RoundedFlatPad", {"flat": 2.0, "edge_radius": 5.0,
                                                "width": 10.0, "height": 10.0}),
    ("fretbem.geometry.shapes:FlatSpecimen", {"length": 40.0, "thickness": 13.0}),
    ("fretbem.geometry.shapes:CylinderSpecimen", {"radius": 70.0, "width": 6.5,
                                                  "height": 16.25}),
    ("fretbem.conditions:Displacement", {"tag": "bottom", "x": 0.0, "y": 1e-3}),
    ("fretbem.conditions:Traction", {"tag": "end", "x": 1.0, "y": 0.0, "load": "bulk"}),
    ("fretbem:Refinement", {"elements": 8, "degree": 2, "ratio": 4.0}),
)  # fmt: skip
#: (record, field) where None is a valid value with a meaning
PY_NONE = {("LoadStep", f) for f in ("normal", "approach", "delta", "moment", "rotation")} | {
    ("Rig", "pivot_height"), ("Waveform", "moment"), ("Refinement", "degree"),
    ("Displacement", "x"), ("Displacement", "y"), ("Traction", "x"), ("Traction", "y"),
    ("JumpControl", "max_change"), ("JumpControl", "max_jump"),
}  # fmt: skip
#: (record, field) where infinity is valid (a rigid rig)
PY_INF = {("Rig", "tangential"), ("Rig", "normal"), ("Rig", "rotational")}
PY_BAD = (("True", True), ("string", "3"), ("nan", float("nan")), ("inf", float("inf")),
          ("None", None))  # fmt: skip


def _python_record(path: str, valid: dict, field: str, bad) -> tuple[bool, str]:
    """Good if the record refuses ``bad`` with one InputError line naming the field."""
    import importlib

    from fretbem.errors import InputError

    module, name = path.split(":")
    record = getattr(importlib.import_module(module), name)
    try:
        built = record(**{**valid, field: bad})
    except InputError as err:
        text = str(err)
        return field in text and "\n" not in text, f"InputError: {text[:200]}"
    except BaseException as err:
        return False, f"{type(err).__name__} (not InputError): {str(err)[:160]}"
    return False, f"accepted: {field} = {getattr(built, field)!r}"


for _path, _valid in PY_RECORDS:
    _record = _path.split(":")[1]
    for _field, _value in _valid.items():
        if isinstance(_value, str) or _field == "name":
            continue
        for _label, _bad in PY_BAD:
            if _bad is None and (_record, _field) in PY_NONE:
                continue
            if _label == "inf" and (_record, _field) in PY_INF:
                continue

            @case("python", f"{_record}.{_field} = {_label} from Python", 10)
            def _python(path=_path, valid=_valid, field=_field, bad=_bad):
                return _python_record(path, valid, field, bad)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", help="run one class")
    parser.add_argument("--match", help="run cases whose name holds this text")
    parser.add_argument("--verbose", action="store_true", help="print every case")
    parser.add_argument("--json", help="write the rows here")
    args = parser.parse_args()
    counts: dict[str, Counter] = {}
    rows = []
    for klass, name, _seconds, function in CASES:
        if args.only and klass != args.only:
            continue
        if args.match and args.match not in name:
            continue
        t = time.perf_counter()
        try:
            good, detail = function()
        except BaseException as err:
            good, detail = (
                False,
                "audit crashed: "
                + "".join(traceback.format_exception_only(type(err), err)).strip(),
            )
        counts.setdefault(klass, Counter())["good" if good else "bad"] += 1
        rows.append({"class": klass, "case": name, "good": bool(good), "detail": detail,
                     "seconds": round(time.perf_counter() - t, 2)})  # fmt: skip
        if args.verbose or not good:
            mark = "good" if good else "BAD "
            print(f"{mark} [{klass}] {name}: {textwrap.shorten(str(detail), 220)}", flush=True)
    print("\nclass          good  bad")
    for klass, c in counts.items():
        print(f"{klass:<14} {c['good']:>4} {c['bad']:>4}")
    total = sum(counts.values(), Counter())
    print(f"{'total':<14} {total['good']:>4} {total['bad']:>4}")
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
