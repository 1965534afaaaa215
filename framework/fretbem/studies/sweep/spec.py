"""What a sweep varies: parameter paths into a scene dict, their values, and the case list.

A scene is a nested dict (a parsed scene file); a parameter path is a TOML key path such as
``load.Q``, ``contact.friction`` or ``geometry.radius``, with an optional list index
(``load.Q[1]``). Values are lists, linspace ranges or explicit value tables, combined as a
product (every combination) or zipped (element by element). Paths under the loads, the
friction law, the solver and post-processing do not change the condensed contact problem;
every other path does, and the cases are grouped by those values so that each group is
assembled and condensed once.
"""

from __future__ import annotations

import copy
import functools
import hashlib
import itertools
import json
import math
import re
from collections.abc import Collection, Mapping
from pathlib import Path
from typing import Any

import attrs
import numpy as np

from fretbem.errors import InputError
from fretbem.scenes.text import read_toml


class SweepSpecError(InputError):
    """A sweep description with a bad parameter path, value range or combination mode."""


#: key paths that change only the loads, the contact law, the solver or post-processing:
#: cases differing only there share one assembled and condensed problem
LOADING_PREFIXES = (
    "load",
    "contact.friction",
    "contact.solver",
    "scene.increments",
    "stress",
    "fatigue",
)

_PART = re.compile(r"^([A-Za-z_][A-Za-z0-9_-]*)((?:\[\d+\])*)$")


def split_path(path: str) -> list[str | int]:
    """``"load.Q[1]"`` -> ``["load", "Q", 1]``; refuses empty parts and bad indices."""
    if not isinstance(path, str) or not path:
        raise SweepSpecError(f"a parameter path must be a non-empty string, got {path!r}")
    return list(_parts(path))


@functools.lru_cache(maxsize=256)
def _parts(path: str) -> tuple[str | int, ...]:
    """:func:`split_path` of a string, parsed once per path (planning sets two paths a case
    and reads each twice: 6,000 parses of four strings in a 1,440-case sweep)."""
    parts: list[str | int] = []
    for piece in path.split("."):
        match = _PART.match(piece)
        if match is None:
            raise SweepSpecError(
                f"parameter path {path!r}: {piece!r} is not a key (letters, digits, _ or -) "
                "optionally followed by [index]; write e.g. 'load.Q' or 'load.Q[1]'"
            )
        parts.append(match.group(1))
        parts += [int(k) for k in re.findall(r"\[(\d+)\]", match.group(2))]
    return tuple(parts)


def changes_condensation(path: str) -> bool:
    """True if the path can change the condensed problem (geometry, materials, mesh...)."""
    keys = ".".join(p for p in split_path(path) if isinstance(p, str))
    return not any(keys == p or keys.startswith(p + ".") for p in LOADING_PREFIXES)


def get_path(scene: Mapping, path: str) -> Any:
    """The value at ``path`` in ``scene`` (KeyError naming the missing part if absent)."""
    node: Any = scene
    for part in split_path(path):
        try:
            node = node[part]
        except (KeyError, IndexError, TypeError):
            raise KeyError(f"{path!r}: no {part!r} in the scene") from None
    return node


def set_path(scene: dict, path: str, value: Any) -> None:
    """Set ``path`` in ``scene`` in place, creating missing tables (not missing list items)."""
    parts = split_path(path)
    node: Any = scene
    for k, part in enumerate(parts[:-1]):
        if isinstance(part, int):
            if not isinstance(node, list) or part >= len(node):
                raise SweepSpecError(
                    f"parameter path {path!r}: the scene has no item [{part}] there; index "
                    "only into lists the scene already gives"
                )
            node = node[part]
            continue
        if not isinstance(node, dict):
            raise SweepSpecError(f"parameter path {path!r}: {parts[k - 1]!r} is not a table")
        nxt = parts[k + 1]
        if part not in node:
            if isinstance(nxt, int):
                raise SweepSpecError(f"parameter path {path!r}: the scene has no list {part!r}")
            node[part] = {}
        node = node[part]
    last = parts[-1]
    if isinstance(last, int):
        if not isinstance(node, list) or last >= len(node):
            raise SweepSpecError(
                f"parameter path {path!r}: the scene has no item [{last}] to replace; index only "
                "into lists the scene already gives"
            )
        node[last] = value
    elif not isinstance(node, dict):
        raise SweepSpecError(f"parameter path {path!r}: its parent is not a table")
    else:
        node[last] = value


def _number(path: str, key: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise SweepSpecError(f"parameter {path!r}: {key} must be a finite number, got {value!r}")
    return value


def _plain(value: Any) -> Any:
    """Numpy scalars to Python numbers (values must survive TOML, JSON and Parquet)."""
    return value.item() if isinstance(value, np.generic) else value


@attrs.frozen
class Parameter:
    """One varied key path: its values and, optionally, a pattern they scale.

    Attributes
    ----------
    path : str
        TOML key path into the scene, e.g. ``load.Q``.
    values : tuple
        The values taken (the table column).
    pattern : tuple of float or None
        If given, the scene receives ``value * pattern`` (e.g. a load history
        ``[0, 1, 0, -1, 0]`` scaled by an amplitude) while the table keeps the value.
    """

    path: str
    values: tuple = attrs.field(converter=tuple)
    pattern: tuple[float, ...] | None = None

    def __attrs_post_init__(self) -> None:
        split_path(self.path)
        if not self.values:
            raise SweepSpecError(f"parameter {self.path!r} has no values; give at least one")

    def scene_value(self, value: Any) -> Any:
        """What goes into the scene for a table value."""
        if self.pattern is None:
            return value
        return [float(value) * w for w in self.pattern]

    @classmethod
    def parse(cls, path: str, spec: Any) -> Parameter:
        """From a TOML value: a list, ``{start, stop, num}`` or ``{values}``, with ``pattern``."""
        if isinstance(spec, list):
            return cls(path, [_plain(v) for v in spec])
        if not isinstance(spec, Mapping):
            raise SweepSpecError(
                f"parameter {path!r}: give a list of values, a range {{start, stop, num}} or "
                f"{{values = [...]}}, got {spec!r}"
            )
        keys = set(spec)
        pattern = spec.get("pattern")
        if pattern is not None:
            if not isinstance(pattern, list) or not pattern:
                raise SweepSpecError(f"parameter {path!r}: pattern must be a non-empty list")
            pattern = tuple(float(_number(path, "pattern item", w)) for w in pattern)
        if "values" in keys:
            extra = keys - {"values", "pattern"}
            if extra or not isinstance(spec["values"], list):
                raise SweepSpecError(
                    f"parameter {path!r}: {{values = [...]}} takes only values (a list) and "
                    f"pattern; unexpected {sorted(extra)}"
                )
            return cls(path, [_plain(v) for v in spec["values"]], pattern)
        if {"start", "stop", "num"} <= keys and not keys - {"start", "stop", "num", "pattern"}:
            start = _number(path, "start", spec["start"])
            stop = _number(path, "stop", spec["stop"])
            num = spec["num"]
            if isinstance(num, bool) or not isinstance(num, int) or num < 1:
                raise SweepSpecError(f"parameter {path!r}: num must be an integer >= 1")
            values = [float(v) for v in np.linspace(start, stop, num)]
            return cls(path, values, pattern)
        raise SweepSpecError(
            f"parameter {path!r}: a table must be {{start, stop, num}} (linspace) or "
            f"{{values = [...]}} (optionally with pattern), got keys {sorted(keys)}"
        )


@attrs.frozen
class Case:
    """One combination of parameter values and the scene dict it gives."""

    index: int
    values: dict
    scene: dict
    group: str


def _group_key(values: Mapping[str, Any], condensing: Collection[str] | None = None) -> str:
    """The condensation group of a case's parameter values: those of the paths that change
    the condensed problem (``condensing``: those paths, when the caller knows them)."""
    if condensing is None:
        condensing = [k for k in values if changes_condensation(k)]
    return json.dumps({k: v for k, v in sorted(values.items()) if k in condensing},
                      sort_keys=True)  # fmt: skip


def copy_tree(node: Any) -> Any:
    """A deep copy of a scene: its tables and lists new, its strings, numbers and booleans
    shared (immutable), anything else deep-copied. About four times faster than
    ``copy.deepcopy`` on a parsed scene file, which plans a copy per case."""
    kind = type(node)
    if kind is dict:
        return {key: copy_tree(value) for key, value in node.items()}
    if kind is list:
        return [copy_tree(value) for value in node]
    if kind in _IMMUTABLE:
        return node
    return copy.deepcopy(node)


_IMMUTABLE = frozenset({str, int, float, bool, type(None)})


@attrs.frozen
class SweepSpec:
    """A base scene, the parameters varied and how they combine.

    Attributes
    ----------
    scene : dict
        The base scene (a parsed scene file).
    parameters : tuple of Parameter
    mode : str
        "product" (every combination, first parameter slowest) or "zip".
    options : dict
        Free settings recorded with the sweep (e.g. fatigue, maps); part of its identity.
    """

    scene: dict
    parameters: tuple[Parameter, ...] = attrs.field(converter=tuple)
    mode: str = "product"
    options: dict = attrs.field(factory=dict)

    def __attrs_post_init__(self) -> None:
        if self.mode not in ("product", "zip"):
            raise SweepSpecError(f"mode must be 'product' or 'zip', got {self.mode!r}")
        paths = [p.path for p in self.parameters]
        if len(set(paths)) != len(paths):
            raise SweepSpecError(f"a parameter path is given twice in {paths}")
        if self.mode == "zip" and len({len(p.values) for p in self.parameters}) > 1:
            counts = {p.path: len(p.values) for p in self.parameters}
            raise SweepSpecError(
                f"mode = 'zip' pairs values element by element, so every parameter needs the "
                f"same number of values; got {counts}"
            )

    @property
    def paths(self) -> tuple[str, ...]:
        """The varied key paths, in order (the table's parameter columns)."""
        return tuple(p.path for p in self.parameters)

    def combinations(self) -> list[tuple]:
        """Value tuples in case order."""
        columns = [p.values for p in self.parameters]
        if not columns:
            return [()]
        if self.mode == "zip":
            return list(zip(*columns, strict=True))
        return list(itertools.product(*columns))

    def cases(self) -> list[Case]:
        """Every case with its scene dict and its condensation group key."""
        cases = []
        paths = self.paths
        condensing = {path for path in paths if changes_condensation(path)}
        for index, combo in enumerate(self.combinations()):
            scene = copy_tree(self.scene)
            for parameter, value in zip(self.parameters, combo, strict=True):
                set_path(scene, parameter.path, parameter.scene_value(value))
            values = dict(zip(paths, combo, strict=True))
            cases.append(Case(index, values, scene, _group_key(values, condensing)))
        return cases

    def groups(self) -> dict[str, list[Case]]:
        """Cases by condensation group, groups in order of first appearance."""
        groups: dict[str, list[Case]] = {}
        for case in self.cases():
            groups.setdefault(case.group, []).append(case)
        return groups

    def group_count(self) -> int:
        """Number of condensation groups, without building the cases' scenes."""
        return len({_group_key(dict(zip(self.paths, combo, strict=True)))
                    for combo in self.combinations()})  # fmt: skip

    def count(self) -> int:
        """Number of cases, without expanding them."""
        if not self.parameters:
            return 1
        if self.mode == "zip":
            return len(self.parameters[0].values)
        return math.prod(len(p.values) for p in self.parameters)

    def fingerprint(self) -> str:
        """Hash of everything that defines the results (scene, parameters, mode, options).

        The figures (``maps``) and the store's place (``out``) are not part of it: a map can
        be fixed and redrawn from a finished store."""
        data = {
            "scene": self.scene,
            "parameters": [[p.path, list(p.values), p.pattern] for p in self.parameters],
            "mode": self.mode,
            "options": {k: v for k, v in self.options.items() if k not in NOT_IDENTITY},
        }
        text = json.dumps(data, sort_keys=True, default=str)
        return hashlib.sha256(text.encode()).hexdigest()[:16]

    @classmethod
    def from_mapping(
        cls, scene: Mapping, parameters: Mapping[str, Any], *, mode: str = "product", **options
    ) -> SweepSpec:
        """From a scene dict and ``{path: values}`` (lists, ranges or value tables)."""
        if not isinstance(parameters, Mapping):
            raise SweepSpecError("parameters must map key paths to values")
        parsed = [Parameter.parse(path, spec) for path, spec in parameters.items()]
        scene = copy.deepcopy(dict(scene))
        for name in POST_TABLES:  # the sweep file's table over the scene's; swept keys win
            if isinstance(options.get(name), Mapping):
                scene[name] = _merged(scene.get(name), options[name])
        return cls(scene, parsed, mode, dict(options))


def _merged(base: Any, over: Mapping) -> dict:
    """``over`` deep-merged onto the table ``base`` (a new dict)."""
    out = copy.deepcopy(dict(base)) if isinstance(base, Mapping) else {}
    for key, value in over.items():
        if isinstance(value, Mapping) and isinstance(out.get(key), Mapping):
            out[key] = _merged(out[key], value)
        else:
            out[key] = copy.deepcopy(value)
    return out


def _read_toml(path: Path, what: str) -> dict:
    return read_toml(path, what.removeprefix("the "), SweepSpecError)


SWEEP_KEYS = {"scene", "mode", "out", "outputs"}
#: options that do not change the results: not part of the fingerprint
NOT_IDENTITY = ("maps", "out")
#: tables of a sweep file for the outputs; merged into the scene under the swept parameters
POST_TABLES = ("fatigue", "stress")
#: the tables of a sweep file ([fatigue] and [stress] go to the output functions)
TOP_TABLES = {"sweep", "parameters", "maps", "fatigue", "stress"}


def load_sweep(path: str | Path) -> SweepSpec:
    """Read a sweep file: ``[sweep]`` (scene file or inline ``[sweep.scene]``), ``[parameters]``.

    Other top-level tables (e.g. ``[[maps]]``, ``[fatigue]``) are kept in ``options``.
    """
    path = Path(path)
    data = _read_toml(path, "the sweep file")
    table = data.get("sweep")
    if not isinstance(table, dict):
        raise SweepSpecError(f"{path}: a sweep file needs a [sweep] table with its scene")
    extra = set(table) - SWEEP_KEYS
    if extra:
        raise SweepSpecError(
            f"{path}: unknown keys {sorted(extra)} in [sweep]; the keys there are "
            f"{sorted(SWEEP_KEYS)}"
        )
    scene = table.get("scene")
    if isinstance(scene, str):
        scene_path = (path.parent / scene).resolve()
        scene = _read_toml(scene_path, "the scene file")
    elif not isinstance(scene, dict):
        raise SweepSpecError(
            f"{path}: [sweep] scene must be a scene file path (relative to the sweep file) or "
            "an inline [sweep.scene] table"
        )
    parameters = data.get("parameters")
    if not isinstance(parameters, dict) or not parameters:
        raise SweepSpecError(f"{path}: give the varied key paths in a [parameters] table")
    unknown = sorted(set(data) - TOP_TABLES)
    if unknown:
        raise SweepSpecError(
            f"{path}: unknown table{'s' if len(unknown) > 1 else ''} {unknown}; a sweep file has "
            f"{sorted(TOP_TABLES)}"
        )
    options = {k: v for k, v in data.items() if k not in ("sweep", "parameters")}
    if "out" in table:
        options["out"] = str(table["out"])
    if "outputs" in table:
        outputs = table["outputs"]
        if not isinstance(outputs, list) or not all(isinstance(o, str) for o in outputs):
            raise SweepSpecError(f"{path}: [sweep] outputs must be a list of 'module:function'")
        options["outputs"] = outputs
    flat = _flatten(parameters)
    return SweepSpec.from_mapping(scene, flat, mode=table.get("mode", "product"), **options)


def _flatten(parameters: Mapping, prefix: str = "") -> dict[str, Any]:
    """``{"load": {"Q": [...]}}`` (TOML dotted keys) -> ``{"load.Q": [...]}``."""
    flat: dict[str, Any] = {}
    value_keys = {"start", "stop", "num", "values", "pattern"}
    for key, value in parameters.items():
        path = f"{prefix}{key}"
        if isinstance(value, Mapping) and not set(value) & value_keys:
            flat.update(_flatten(value, path + "."))
        else:
            flat[path] = value
    return flat


__all__ = [
    "LOADING_PREFIXES",
    "Case",
    "Parameter",
    "SweepSpec",
    "SweepSpecError",
    "changes_condensation",
    "get_path",
    "load_sweep",
    "set_path",
    "split_path",
]
