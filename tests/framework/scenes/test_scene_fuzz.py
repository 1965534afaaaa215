"""Fuzzing the scene-file reader through the command: every input either runs with passing
result checks or exits with one named error line; never a traceback, never a file outside
--out. The default run tries a few examples; ``-m slow`` tries many."""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from fretbem.app import cli

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

EXAMPLE = Path(__file__).parents[3] / "examples" / "cattaneo_mindlin.toml"
BASE = tomllib.loads(EXAMPLE.read_text())
SMALL_PAIRS = 15

_text = st.text(st.characters(blacklist_categories=("Cs",)), max_size=12)
_number = st.one_of(
    st.integers(-3, 60),
    st.sampled_from([0, 1, 2, 10**12, -(10**12)]),
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -0.0, 1e-300, 1e300, 0.5, 0.499999, 1e16, 1e-8]),
)
_scalar = st.one_of(_number, _text, st.booleans(), st.sampled_from(["nurbs", "lagrange2", "flat"]))
_value = st.one_of(_scalar, st.lists(_scalar, max_size=6), st.lists(_number, max_size=6))


def _toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return (
            "nan"
            if math.isnan(value)
            else ("inf" if value > 0 else "-inf")
            if math.isinf(value)
            else repr(value)
        )
    if isinstance(value, str):
        return json.dumps(value)  # JSON string escapes are valid TOML basic-string escapes
    return "[" + ", ".join(_toml_value(v) for v in value) + "]"


def to_toml(data: dict, prefix: str = "") -> str:
    """A small TOML writer for nested tables of scalars and arrays."""
    scalars = [f"{k} = {_toml_value(v)}" for k, v in data.items() if not isinstance(v, dict)]
    lines = ([f"[{prefix}]"] if prefix else []) + scalars
    for key, value in data.items():
        if isinstance(value, dict):
            lines.append(to_toml(value, f"{prefix}.{key}" if prefix else key))
    return "\n".join(lines) + "\n"


def _keys(data: dict, prefix=()) -> list[tuple[str, ...]]:
    out = []
    for key, value in data.items():
        out.append((*prefix, key))
        if isinstance(value, dict):
            out.extend(_keys(value, (*prefix, key)))
    return out


PATHS = [*_keys(BASE), ("scene", "typo"), ("bogus",), ("material", "upper", "E"), ("load", "x")]


@st.composite
def scenes(draw) -> dict:
    """The example scene with 1 to 4 keys replaced, deleted or added."""
    data = json.loads(json.dumps(BASE))
    data.setdefault("scene", {})["pairs"] = SMALL_PAIRS
    for _ in range(draw(st.integers(1, 4))):
        path = draw(st.sampled_from(PATHS))
        table = data
        for key in path[:-1]:
            if not isinstance(table.get(key), dict):
                table[key] = {}
            table = table[key]
        if draw(st.booleans()) and path[-1] in table:
            del table[path[-1]]
        elif path[-1] == "pairs":
            table["pairs"] = draw(st.one_of(st.integers(-2, 31), _scalar))
        else:
            table[path[-1]] = draw(_value)
    return data


def check_one(data: dict, root: Path) -> None:
    """Run the command on ``data``; assert the outcome is a clean success or one error line."""
    import contextlib
    import io

    root.mkdir()
    path = root / "scene.toml"
    path.write_text(to_toml(data))
    out = root / "out"
    err = io.StringIO()
    with (
        contextlib.chdir(root),  # relative paths written by mistake would land in root
        contextlib.redirect_stdout(io.StringIO()),
        contextlib.redirect_stderr(err),
    ):
        code = cli.main(["run", str(path), "--out", "out", "--no-figures", "--no-vtk"])
    lines = err.getvalue().strip().splitlines()
    event(f"exit code {code}")
    assert "Traceback" not in err.getvalue()
    assert {p.name for p in root.iterdir()} <= {"scene.toml", "out"}, "file outside --out"
    if code == 0:
        summary = json.loads((out / "summary.json").read_text())
        for step in summary["steps"]:
            assert all(c["passed"] for c in step["checks"].values())
    else:
        assert code in (1, 2), code
        failures = [line for line in lines if line.startswith("fretbem: ") and
                    ("error:" in line or "result check failed" in line)]  # fmt: skip
        assert len(failures) == 1, lines
        assert not out.exists()


def test_example_round_trips_through_the_toml_writer():
    """The fuzz writer reproduces the example scene exactly."""
    assert tomllib.loads(to_toml(BASE)) == BASE


_counter = iter(range(10**9))


@settings(
    max_examples=12, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(data=scenes())
def test_fuzzed_scene_files(data, tmp_path):
    check_one(data, tmp_path / f"case{next(_counter)}")


@pytest.mark.slow
@settings(
    max_examples=400, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(data=scenes())
def test_fuzzed_scene_files_many(data, tmp_path):
    check_one(data, tmp_path / f"case{next(_counter)}")
