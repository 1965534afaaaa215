"""A two-body contact scene as data: the records a scene file is read into, and its key table.

A scene is a pad (the upper body) on a specimen (the lower body), the contact between them
and a load history whose steps give the normal load P, the tangential load Q and the
specimen's bulk stress sigma_B. Every key of the file is one row of :data:`KEYS` (table,
key, unit, default, meaning); the reader, the error messages and the documentation's table
(docs/scene-format.md, checked against :func:`markdown_table` by the tests) all come from it,
and the Python records use the same names as the file's keys.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping
from typing import Any

import attrs
import numpy as np

from fretbem import registry
from fretbem.contact.control import STIFFNESS_UNITS, check_pivot_height, check_stiffness
from fretbem.contact.law import MAX_FRICTION
from fretbem.contact.node_to_segment import FRAMES
from fretbem.fretting.waveform import SHAPES, Waveform, WaveformError
from fretbem.geometry.boundary import Segment
from fretbem.geometry.nurbs import NurbsCurve
from fretbem.geometry.shapes import (
    CylinderPad,
    CylinderSpecimen,
    FlatSpecimen,
    GrooveSpecimen,
    NurbsShape,
    RoundedFlatPad,
)
from fretbem.material import Material
from fretbem.validators import WHOLE_MAX, file_string, shown
from fretbem.views.display import scene_html, scene_repr

from .errors import SceneFileError

__all__ = [
    "KEYS",
    "BodySpec",
    "ContactSpec",
    "LoadSpec",
    "MeshSpec",
    "Scene",
    "SceneFileError",
    "markdown_table",
    "scene_from_dict",
]


NUMBER = (int, float)


@attrs.frozen
class Key:
    """One documented key of the scene file."""

    table: str
    name: str
    kind: tuple[type, ...]
    unit: str
    default: Any
    meaning: str
    shapes: tuple[str, ...] = ()  # the body shapes the key belongs to (empty: all)


PAD_SHAPES = {"cylinder": CylinderPad, "rounded-flat": RoundedFlatPad, "nurbs": NurbsShape}
SPECIMEN_SHAPES = {
    "cylinder": CylinderSpecimen,
    "groove": GrooveSpecimen,
    "flat": FlatSpecimen,
    "nurbs": NurbsShape,
}
#: the built-in body models (any name registered in the ``fretbem.bodies`` group is accepted)
MODELS = ("bem", "half-plane")
SUPPORTS = ("clamped-bottom", "ends")


def _body_keys(role: str) -> tuple[Key, ...]:
    """The body-model and contact-face keys that [pad] and [specimen] share."""
    return (
        Key(role, "model", (str,), "", "bem", "`bem` (finite body), `half-plane` or a plugin's"),
        Key(
            role, "basis", (str,), "", None, "this body's basis family; omitted: `[contact] basis`"
        ),
        Key(role, "degree", (int,), "", None, "this body's basis degree (`[contact] degree`)"),
        Key(
            role,
            "pairs",
            (int,),
            "",
            None,
            "collocation points on this body's contact face in the zone (`fixed`); omitted: "
            '`[contact] pairs`; faces that differ need `pairing = "node-to-segment"`',
        ),
        Key(
            role,
            "elements",
            (int,),
            "",
            None,
            "elements on this body's contact face in the zone, instead of `pairs` (`fixed`)",
        ),
        Key(
            role,
            "segments",
            (list,),
            "",
            None,
            f"explicit NURBS segments (`[[{role}.segments]]`)",
            ("nurbs",),
        ),
    )


#: every key of the scene file, in the order of the documentation's table
KEYS: tuple[Key, ...] = (
    Key("pad", "shape", (str,), "", "cylinder", "`cylinder`, `rounded-flat` or `nurbs`"),
    Key("pad", "radius", NUMBER, "mm", 70.0, "radius R of the face", ("cylinder",)),
    Key("pad", "flat", NUMBER, "mm", None, "half-width b of the flat", ("rounded-flat",)),
    Key("pad", "edge_radius", NUMBER, "mm", None, "radius r of the fillets", ("rounded-flat",)),
    Key(
        "pad",
        "width",
        NUMBER,
        "mm",
        6.5,
        "width w (x from -w/2 to w/2)",
        ("cylinder", "rounded-flat"),
    ),
    Key(
        "pad",
        "height",
        NUMBER,
        "mm",
        16.25,
        "height h (loading block on the top edge)",
        ("cylinder", "rounded-flat"),
    ),
    *_body_keys("pad"),
    Key(
        "specimen",
        "shape",
        (str,),
        "",
        "cylinder",
        "`cylinder` (the pad's mirror image), `groove` (a concave arc), `flat` or `nurbs`",
    ),
    Key(
        "specimen",
        "radius",
        NUMBER,
        "mm",
        70.0,
        "radius of the face (`cylinder`: the pad's; `groove`: required, larger than the "
        "cylinder pad's)",
        ("cylinder", "groove"),
    ),
    Key("specimen", "width", NUMBER, "mm", 6.5, "width", ("cylinder", "groove")),
    Key(
        "specimen",
        "height",
        NUMBER,
        "mm",
        16.25,
        "height (clamped bottom at y = -h)",
        ("cylinder", "groove"),
    ),
    Key("specimen", "length", NUMBER, "mm", 40.0, "length L (x from -L/2 to L/2)", ("flat",)),
    Key("specimen", "thickness", NUMBER, "mm", 13.0, "thickness t (bottom at y = -t)", ("flat",)),
    Key(
        "specimen",
        "support",
        (str,),
        "",
        "see meaning",
        "`clamped-bottom` (default of `cylinder` and `groove`) or `ends` (default of `flat`: "
        "-x end held in x, bottom on rollers, bulk stress on the +x end)",
    ),
    *_body_keys("specimen"),
    Key("material", "E", NUMBER, "MPa", 73400.0, "Young's modulus of both bodies"),
    Key("material", "nu", NUMBER, "", 0.33, "Poisson's ratio of both bodies"),
    Key("material", "plane", (str,), "", "strain", "`strain` or `stress`"),
    Key("contact", "friction", NUMBER, "", 0.3, "Coulomb coefficient f"),
    Key("contact", "basis", (str,), "", "nurbs", "basis family (`fretbem bases`)"),
    Key("contact", "degree", (int,), "", None, "basis degree; omitted: the family's default"),
    Key("contact", "pairs", (int,), "", 61, "node pairs in the candidate contact zone (`fixed`)"),
    Key(
        "contact",
        "mesh",
        (str,),
        "",
        "fixed",
        "`fixed` (uniform, `pairs`) or `adaptive` (re-meshed on the contact edges and "
        "stick-slip boundaries until `tolerance` or `budget`)",
    ),
    Key(
        "contact",
        "tolerance",
        NUMBER,
        "",
        0.02,
        "`adaptive`: stop when the estimated max error is below this fraction of p0 and f p0",
    ),
    Key(
        "contact",
        "budget",
        (int,),
        "",
        61,
        "`adaptive`: most node pairs of the last level (at most 521: a larger budget is "
        "capped there, with a caution)",
    ),
    Key(
        "contact",
        "estimate",
        (bool,),
        "",
        True,
        "`fixed`: also solve about half the pairs and estimate each step's error from the "
        "two levels (`adaptive` always estimates)",
    ),
    Key(
        "contact", "zone", NUMBER, "", 1.5, "candidate zone half-width over the Hertz half-width a"
    ),
    Key(
        "contact",
        "zone_width",
        NUMBER,
        "mm",
        None,
        "candidate zone half-width in mm (instead of `zone`; required without a Hertz estimate)",
    ),
    Key(
        "contact",
        "pairing",
        (str,),
        "",
        "node-to-node",
        "`node-to-node` (faces discretised alike) or `node-to-segment` (faces may differ: "
        "nodes of one projected on the other's exact geometry)",
    ),
    Key(
        "contact",
        "sliding",
        (bool,),
        "",
        False,
        "finite sliding: the pairs are projected again as the pad slides (gross slip over "
        'several contact widths); needs `pairing = "node-to-segment"` and a flat specimen '
        "(either body model), or a cylinder or groove specimen (a convex or concave arc the "
        "pad turns along; `bem` bodies)",
    ),
    Key(
        "contact",
        "track_width",
        NUMBER,
        "mm",
        None,
        "`sliding`: half-width of the specimen's contact segment the pad slides along "
        "(default: the zone plus the largest delta of the history, in absolute value)",
    ),
    Key(
        "contact",
        "frame",
        (str,),
        "",
        "local",
        "`sliding` along an arc (a `cylinder` or `groove` specimen): the pair frame, `local` "
        "(each pair the arc's normal and tangent where it meets it, the gap along that normal) "
        "or `shared` (all pairs the pad's turned frame: the a/R simplification); refused on a "
        "flat specimen (its pairs share one frame either way) and without `sliding`",
    ),
    Key("contact", "solver", (str,), "", "newton", "contact solver (`fretbem plugins`)"),
    Key("contact", "law", (str,), "", "coulomb", "contact law (`fretbem plugins`)"),
    Key("mesh", "flank_elements", (int,), "", 16, "elements on each face part outside the zone"),
    Key(
        "mesh",
        "side_elements",
        (int,),
        "",
        12,
        "elements on each side or end, graded toward the corners",
    ),
    Key(
        "mesh",
        "top_elements",
        (int,),
        "",
        12,
        "elements on the pad's top and the specimen's bottom",
    ),
    Key("load", "steps", (list,), "", ["A", "B", "C", "D", "E"], "step names (unique)"),
    Key(
        "load",
        "P",
        (*NUMBER, list),
        "N/mm",
        100.0,
        "normal load at the end of each step (a number: constant)",
    ),
    Key(
        "load",
        "Q",
        (*NUMBER, list),
        "N/mm",
        [0.0, 18.0, 0.0, -18.0, 0.0],
        "tangential load on the pad, +x",
    ),
    Key(
        "load",
        "bulk",
        (*NUMBER, list),
        "MPa",
        0.0,
        "bulk stress sigma_B on the specimen's +x end, tension > 0",
    ),
    Key("load", "increments", (int, list), "", 1, "equal sub-increments per step"),
    Key(
        "load",
        "delta",
        (*NUMBER, list),
        "mm",
        None,
        "tangential displacement of the pad's loading block against the specimen's held end, "
        "+x, imposed instead of `Q` (displacement control; gross slip allowed)",
    ),
    Key(
        "load",
        "approach",
        (*NUMBER, list),
        "mm",
        None,
        "normal approach of the pad's loading block against the specimen's held end (> 0 "
        "presses), imposed instead of `P`; needs [contact] `zone_width`",
    ),
    Key(
        "load",
        "moment",
        (*NUMBER, list),
        "N mm/mm",
        None,
        "moment M the pad's loading block applies to the pad about the rig's pivot, "
        "counterclockwise (x right, y up) > 0: the block then rotates freely under it",
    ),
    Key(
        "load",
        "rotation",
        (*NUMBER, list),
        "rad",
        None,
        "rotation of the actuator holding the pad's block, counterclockwise > 0, imposed "
        "instead of `moment` (through [rig] `stiffness_rotation`); neither given: 0",
    ),
    Key(
        "load.cycle",
        "delta",
        NUMBER,
        "mm",
        None,
        "a cyclic history instead of named steps: the amplitude delta* of the pad block's "
        "displacement (displacement control; gross slip allowed); [load] then keeps only "
        "`P` and `bulk` (the means)",
    ),
    Key("load.cycle", "Q", NUMBER, "N/mm", None, "or the amplitude Q* (force control), < f P"),
    Key("load.cycle", "cycles", (int,), "", 1, "number of cycles"),
    Key(
        "load.cycle",
        "increments",
        (int,),
        "",
        40,
        "increments per cycle, a multiple of 4 (each is a step of the results)",
    ),
    Key("load.cycle", "shape", (str,), "", "sine", "`sine` or `triangle`"),
    Key(
        "load.cycle",
        "P_amplitude",
        NUMBER,
        "N/mm",
        0.0,
        "cyclic normal load: P(t) = P + P_amplitude w(t + P_phase / 360)",
    ),
    Key("load.cycle", "P_phase", NUMBER, "degrees", 0.0, "phase of P against the drive"),
    Key("load.cycle", "bulk_amplitude", NUMBER, "MPa", 0.0, "cyclic bulk stress amplitude"),
    Key("load.cycle", "bulk_phase", NUMBER, "degrees", 0.0, "phase of sigma_B against the drive"),
    Key(
        "load.cycle",
        "M_amplitude",
        NUMBER,
        "N mm/mm",
        0.0,
        "cyclic moment on the pad's block: M(t) = M + M_amplitude w(t + M_phase / 360), "
        "M the [load] `moment` (the mean)",
    ),
    Key("load.cycle", "M_phase", NUMBER, "degrees", 0.0, "phase of M against the drive"),
    Key(
        "rig",
        "stiffness_x",
        NUMBER,
        "MPa",
        None,
        "tangential stiffness of the rig between the actuator and the pad's block (N/mm per "
        "mm); `delta` is then the actuator's; omitted: rigid",
    ),
    Key(
        "rig",
        "stiffness_y",
        NUMBER,
        "MPa",
        None,
        "normal stiffness of the rig (N/mm per mm); `approach` is then the actuator's",
    ),
    Key(
        "rig",
        "stiffness_rotation",
        NUMBER,
        "N mm/mm per rad",
        None,
        "rotational stiffness of the rig about its pivot: the pad's block tilts by "
        "-M / k_r under the moment it carries (Q acts below the pivot; with [contact] "
        "`sliding` along an arc, from the pad's turned pose); omitted: the block does not "
        "rotate (unless [load] gives a moment or rotation)",
    ),
    Key(
        "rig",
        "pivot_height",
        NUMBER,
        "mm",
        None,
        "height of the pivot above the initial first-contact point, where the block's "
        "rotation and moment M are taken; omitted: the pad block's line (the pad's top; "
        "for a half-plane pad its datum depth, 10 mm); at most 1e4 mm from the contact",
    ),
)

#: the highest basis degree a scene may ask for (higher degrees are ill-conditioned)
MAX_DEGREE = 8

#: tables whose content another module reads (stress evaluation, fatigue)
EXTRA_TABLES = ("stress", "fatigue", "wear")
SEGMENT_KEYS = {"tag", "degree", "knots", "points", "weights"}


@attrs.frozen(eq=False)
class BodySpec:
    """One body: its shape, material and model (and the specimen's support).

    Attributes
    ----------
    shape : CylinderPad, RoundedFlatPad, CylinderSpecimen, FlatSpecimen or NurbsShape
    material : Material
    model : str
        ``"bem"`` or ``"half-plane"``.
    support : str
        Specimen only: ``"clamped-bottom"`` or ``"ends"``.
    basis, degree, pairs, elements : optional
        This body's contact-face discretisation (None: the ``[contact]`` value; ``elements``
        instead of ``pairs``). Faces that differ need ``[contact] pairing =
        "node-to-segment"``.
    """

    shape: Any
    material: Material
    model: str = "bem"
    support: str = attrs.field(default="clamped-bottom", validator=attrs.validators.in_(SUPPORTS))
    basis: str | None = None
    degree: int | None = None
    pairs: int | None = None
    elements: int | None = None


@attrs.frozen
class ContactSpec:
    """Friction, discretisation of the contact faces and the solver."""

    friction: float = 0.3
    basis: str = "nurbs"
    degree: int | None = None
    pairs: int = 61
    zone: float = 1.5
    zone_width: float | None = None
    solver: str = "newton"
    law: str = "coulomb"
    pairing: str = "node-to-node"
    sliding: bool = False
    track_width: float | None = None
    frame: str | None = None
    mesh: str = "fixed"
    tolerance: float = 0.02
    budget: int = 61
    estimate: bool = True

    def __attrs_post_init__(self) -> None:
        _check_numbers(self, "contact")

    @property
    def sliding_frame(self) -> str:
        """The pair frame of finite sliding along an arc: ``frame``, by default ``"local"``."""
        return self.frame or "local"


@attrs.frozen
class MeshSpec:
    """Element counts away from the contact zone."""

    flank_elements: int = 16
    side_elements: int = 12
    top_elements: int = 12

    def __attrs_post_init__(self) -> None:
        _check_numbers(self, "mesh")


#: the [load] entries that may be None in a step (P under an approach, a free rotation)
_OPTIONAL_LOADS = ("P", "delta", "approach", "moment", "rotation")


@attrs.frozen
class LoadSpec:
    """The load history: one entry per step in every tuple."""

    steps: tuple[str, ...]
    P: tuple[float | None, ...]
    Q: tuple[float, ...]
    bulk: tuple[float, ...]
    increments: tuple[int, ...]
    delta: tuple[float, ...] | None = None
    approach: tuple[float, ...] | None = None
    cycle: tuple[int, ...] | None = None
    waveform: Any = None
    moment: tuple[float, ...] | None = None
    rotation: tuple[float, ...] | None = None

    def __attrs_post_init__(self) -> None:
        n = len(self.steps)
        for name in (
            "P", "Q", "bulk", "increments", "delta", "approach", "cycle", "moment", "rotation"
        ):  # fmt: skip
            if getattr(self, name) is None:
                continue
            if len(getattr(self, name)) != n:
                raise SceneFileError(
                    f"[load] {name} has {len(getattr(self, name))} values for {n} steps; give "
                    "one value per step (or a single number for all)"
                )
        for name in ("P", "Q", "bulk", "delta", "approach", "moment", "rotation", "increments",
                     "cycle"):  # fmt: skip
            whole = name in ("increments", "cycle")
            plain = int if whole else float
            for k, value in enumerate(getattr(self, name) or ()):
                if type(value) is plain and (
                    abs(value) <= WHOLE_MAX if whole else value - value == 0
                ):
                    continue  # the common entry, without _check's isinstance chain
                if value is not None or name not in _OPTIONAL_LOADS:
                    _check(f"[load] {name}[{k}]", value, (int,) if whole else NUMBER)
        seen = set()
        for name in self.steps:
            if name in seen:
                raise SceneFileError(
                    f"[load] steps: the name {name!r} is used twice; names must be unique"
                )
            seen.add(name)


@attrs.frozen
class RigSpec:
    """Springs between the actuator and the pad's block (None: rigid)."""

    stiffness_x: float | None = None
    stiffness_y: float | None = None
    stiffness_rotation: float | None = None
    pivot_height: float | None = None


@attrs.frozen(eq=False)
class Scene:
    """A two-body fretting scene: pad, specimen, contact, mesh and load history.

    ``extras`` keeps the raw ``[stress]``, ``[fatigue]`` and ``[wear]`` tables for the
    modules that read them; ``legacy`` is True for a file in the round-1 format (translated
    on reading).
    """

    pad: BodySpec
    specimen: BodySpec
    contact: ContactSpec = attrs.field(factory=ContactSpec)
    mesh: MeshSpec = attrs.field(factory=MeshSpec)
    load: LoadSpec | None = None
    extras: Mapping[str, Any] = attrs.field(factory=dict)
    legacy: bool = False
    rig: RigSpec = attrs.field(factory=RigSpec)

    @property
    def block_rotates(self) -> bool:
        """Whether the scene turns the pad's block (a moment, a rotation or a rotational
        spring)."""
        load = self.load
        turns = load is not None and (load.moment is not None or any(load.rotation or ()))
        return turns or self.rig.stiffness_rotation is not None

    def __repr__(self) -> str:
        return scene_repr(self)

    def _repr_html_(self) -> str:
        return scene_html(self)


# --------------------------------------------------------------------------- reading


def _type_name(kind) -> str:
    names = {
        int: "an integer",
        float: "a number",
        str: "a string",
        list: "a list",
        bool: "true or false",
    }
    return " or ".join(dict.fromkeys(names[k] for k in kind))


def _check(where: str, value: Any, kind: tuple[type, ...]) -> Any:
    if (isinstance(value, bool) and bool not in kind) or not isinstance(value, kind):
        raise SceneFileError(f"{where} must be {_type_name(kind)}, got {shown(value)}")
    if isinstance(value, float) and not math.isfinite(value):
        raise SceneFileError(f"{where} must be a finite number, got {value!r}")
    if type(value) is int and abs(value) > WHOLE_MAX:  # (only from Python: TOML's are 64-bit)
        raise SceneFileError(f"{where} must fit a 64-bit integer, got {shown(value)}")
    return value


def _check_range(where: str, name: str, value: Any) -> None:
    """The range of a [contact] or [mesh] number whose type :func:`_check` accepted."""
    if name in ("pairs", "flank_elements", "side_elements", "top_elements") and value < 1:
        raise SceneFileError(f"{where} must be >= 1, got {value}")
    if name in ("zone", "zone_width", "track_width") and not value > 0:
        raise SceneFileError(f"{where} must be > 0, got {value}")
    if name == "friction" and value > MAX_FRICTION:
        raise SceneFileError(
            f"{where} is a Coulomb coefficient, 0 < f <= {MAX_FRICTION:g} (metals "
            f"in fretting: about 0.3 to 1.5), got {value}"
        )
    if name == "friction" and not value > 0:
        raise SceneFileError(
            f"{where} must be > 0 (a frictionless contact cannot hold the pad "
            f"under a tangential force), got {value}"
        )
    if name == "degree" and not 1 <= value <= MAX_DEGREE:
        raise SceneFileError(f"{where} must be between 1 and {MAX_DEGREE}, got {value}")
    if name == "tolerance" and not 0.0 < value < 1.0:
        raise SceneFileError(
            f"{where} is a fraction of p0 and f p0, 0 < tolerance < 1; got "
            f"{value!r} (e.g. 0.02 for 2 %)"
        )
    if name == "budget" and value < 5:
        raise SceneFileError(f"{where} must be >= 5 pairs, got {value}")


def _check_numbers(spec: Any, table: str) -> None:
    """A spec record built from Python: its numbers and flags as the scene reader checks them
    (type, finite, range; a key's consistency with the others is the reader's and the
    builder's), so ``ContactSpec(pairs="61")`` is refused as ``[contact] pairs = "61"`` is."""
    for name, kind, default in _numeric_fields(type(spec), table):
        value = getattr(spec, name)
        if value is default or (type(value) is type(default) and value == default):
            continue  # the default (valid), without the checks' cost (a scene build makes several)
        if value is None and default is None:
            continue
        where = f"[{table}] {name}"
        if isinstance(value, np.generic) and not isinstance(value, np.bool_):
            value = value.item()  # a numpy scalar from Python: stored as its number
            object.__setattr__(spec, name, value)
        _check(where, value, kind)
        if bool not in kind:
            _check_range(where, name, value)


@functools.cache
def _numeric_fields(cls: type, table: str) -> tuple[tuple[str, tuple[type, ...], Any], ...]:
    """(name, kinds, default) of the number and flag fields of a spec record (not strings)."""
    keys = _keys(table)
    return tuple(
        (field.name, keys[field.name].kind, field.default)
        for field in attrs.fields(cls)
        if field.name in keys and str not in keys[field.name].kind
    )


def _unknown(where: str, keys, known) -> None:
    extra = sorted(set(keys) - set(known))
    if extra:
        raise SceneFileError(
            f"unknown key{'s' if len(extra) > 1 else ''} {extra} in {where}; the keys there are "
            f"{sorted(known)} (docs/scene-format.md lists them all)"
        )


def _table(data: Mapping, name: str) -> dict:
    section = data.get(name, {})
    if not isinstance(section, dict):
        raise SceneFileError(f"[{name}] must be a table, got {section!r}")
    return section


def _keys(table: str) -> dict[str, Key]:
    return {k.name: k for k in KEYS if k.table == table}


def _plugin(where: str, name: str, group: str) -> str:
    """``name`` if the registry has it in ``group``, else the error listing what is installed."""
    _check(where, name, (str,))
    try:
        registry.get(name, group)
    except registry.UnknownPluginError as err:
        raise SceneFileError(f"{where}: {err}") from None
    return name


def _segments(where: str, items: Any) -> tuple[Segment, ...]:
    if not isinstance(items, list) or not items:
        raise SceneFileError(f"{where} must be a non-empty list of segment tables")
    out = []
    for i, item in enumerate(items):
        here = f"{where}[{i}]"
        if not isinstance(item, dict):
            raise SceneFileError(f"{here} must be a table with {sorted(SEGMENT_KEYS)}")
        _unknown(here, item, SEGMENT_KEYS)
        missing = sorted({"tag", "degree", "knots", "points"} - set(item))
        if missing:
            raise SceneFileError(f"{here} needs {missing}")
        _check(f"{here} tag", item["tag"], (str,))
        _check(f"{here} degree", item["degree"], (int,))
        for key in ("knots", "weights"):
            for j, v in enumerate(item.get(key, [])):
                _check(f"{here} {key}[{j}]", v, NUMBER)
        points = item["points"]
        if not isinstance(points, list) or not all(
            isinstance(p, list) and len(p) == 2 for p in points
        ):
            raise SceneFileError(f"{here} points must be a list of [x, y] pairs")
        for j, p in enumerate(points):
            for v in p:
                _check(f"{here} points[{j}]", v, NUMBER)
        weights = item.get("weights", [1.0] * len(points))
        try:
            curve = NurbsCurve(item["degree"], item["knots"], points, weights)
        except (TypeError, ValueError) as err:
            raise SceneFileError(f"{here}: {err}") from None
        out.append(Segment(item["tag"], curve))
    return tuple(out)


def _material(data: Mapping, body: str) -> Material:
    shared = _table(data, "material")
    own = _table(_table(data, body), "material") if isinstance(data.get(body), dict) else {}
    keys = _keys("material")
    _unknown("[material]", shared, keys)
    _unknown(f"[{body}.material]", own, keys)
    values = {k.name: k.default for k in keys.values()}
    origin = dict.fromkeys(values, "[material]")  # where each value was given (for messages)
    for source, where in ((shared, "[material]"), (own, f"[{body}.material]")):
        for name, value in source.items():
            values[name] = _check(f"{where} {name}", value, keys[name].kind)
            origin[name] = where
    if values["plane"] not in ("strain", "stress"):
        raise SceneFileError(
            f"{origin['plane']} plane must be 'strain' or 'stress', got {values['plane']!r}"
        )
    if not values["E"] > 0:
        raise SceneFileError(f"{origin['E']} E must be > 0 MPa, got {values['E']!r}")
    if not -1.0 < values["nu"] < 0.5:
        raise SceneFileError(
            f"{origin['nu']} nu (Poisson's ratio) must lie in (-1, 0.5) for a stable "
            f"isotropic material, got {values['nu']!r}"
        )
    try:
        return Material(values["E"], values["nu"], plane_stress=values["plane"] == "stress")
    except ValueError as err:
        raise SceneFileError(f"{origin['E']}: {err}") from None


def _body(data: Mapping, body: str, library: Mapping[str, type]) -> BodySpec:
    section = _table(data, body)
    keys = _keys(body)
    _unknown(f"[{body}]", set(section) - {"material"}, keys)
    for name, value in section.items():
        if name != "material":
            _check(f"[{body}] {name}", value, keys[name].kind)
    shape_name = section.get("shape", keys["shape"].default)
    if shape_name not in library:
        raise SceneFileError(f"[{body}] shape must be one of {sorted(library)}, got {shape_name!r}")
    for name in section:
        key = keys.get(name)
        if key is not None and key.shapes and shape_name not in key.shapes:
            raise SceneFileError(
                f"[{body}] {name} does not apply to a {shape_name!r} {body} (it is a key of "
                f"{', '.join(repr(s) for s in key.shapes)}); remove it"
            )
    model = _plugin(f"[{body}] model", section.get("model", "bem"), "bodies")
    if shape_name == "nurbs":
        if "segments" not in section:
            raise SceneFileError(f"[{body}] shape = 'nurbs' needs [[{body}.segments]]")
        shape = NurbsShape(_segments(f"[[{body}.segments]]", section["segments"]))
    elif shape_name == "groove" and "radius" not in section:
        raise SceneFileError(
            "[specimen] a 'groove' specimen needs 'radius' (its concave face's, larger than "
            "the cylinder pad's [pad] radius); give [specimen] radius in mm"
        )
    else:
        fields = {}
        for key in keys.values():
            if key.shapes and shape_name in key.shapes and key.name != "segments":
                value = section.get(key.name, key.default)
                if value is None:
                    raise SceneFileError(f"[{body}] a {shape_name!r} {body} needs {key.name!r}")
                fields[key.name] = float(value)
        if shape_name == "flat":
            fields = {"length": fields["length"], "thickness": fields["thickness"]}
        try:
            shape = library[shape_name](**fields)
        except ValueError as err:
            raise SceneFileError(f"[{body}]: {err}") from None
    extra = {}
    if body == "specimen":
        support = section.get("support", "ends" if shape_name == "flat" else "clamped-bottom")
        if support not in SUPPORTS:
            raise SceneFileError(
                f"[specimen] support must be one of {list(SUPPORTS)}, got {support!r}"
            )
        if support == "ends" and shape_name in ("cylinder", "groove"):
            raise SceneFileError(
                f"[specimen] support = 'ends' holds and pulls a flat specimen at its ends, but "
                f"a {shape_name!r} specimen has sides, not ends; use support = "
                "'clamped-bottom' (its default) or a flat specimen"
            )
        extra["support"] = support
    extra.update(_face_keys(section, body))
    return BodySpec(shape, _material(data, body), model, **extra)


#: per-body contact-face keys ([pad] and [specimen]; [contact] gives their defaults)
FACE_KEYS = ("basis", "degree", "pairs", "elements")


def _face_keys(section: Mapping, body: str) -> dict:
    """The body's own contact-face discretisation keys, checked."""
    out = {name: section[name] for name in FACE_KEYS if name in section}
    if "basis" in out:
        _plugin(f"[{body}] basis", out["basis"], "bases")
    if "pairs" in out and "elements" in out:
        raise SceneFileError(
            f"[{body}] gives both pairs and elements; give one (pairs: collocation points on "
            "the face in the zone, elements: elements there)"
        )
    for name in ("pairs", "elements", "degree"):
        if name in out and out[name] < 1:
            raise SceneFileError(f"[{body}] {name} must be >= 1, got {out[name]}")
    return out


def _per_step(name: str, value: Any, n: int | None, item: tuple[type, ...]) -> list:
    if isinstance(value, list):
        for i, v in enumerate(value):
            _check(f"[load] {name}[{i}]", v, item)
        return list(value)
    _check(f"[load] {name}", value, item)
    return [value] * (n if n is not None else 1)


def _cycle_load(section: dict) -> LoadSpec:
    """[load] with a [load.cycle] table: the waveform expanded into one step per increment."""
    cycle = section["cycle"]
    if not isinstance(cycle, dict):
        raise SceneFileError(f"[load.cycle] must be a table, got {cycle!r}")
    keys = _keys("load.cycle")
    _unknown("[load.cycle]", cycle, keys)
    for name, value in cycle.items():
        _check(f"[load.cycle] {name}", value, keys[name].kind)
    other = sorted(set(section) - {"cycle", "P", "bulk", "moment"})
    if other:
        raise SceneFileError(
            f"[load] {other} do not go with [load.cycle] (the waveform makes the steps); "
            "keep only P, bulk and moment (the mean values) in [load], or drop [load.cycle]"
        )
    for name in ("P", "bulk", "moment"):
        if name in section and not isinstance(section[name], list):
            _check(f"[load] {name}", section[name], NUMBER)
        if isinstance(section.get(name), list):
            raise SceneFileError(
                f"[load] {name} must be one number (the mean) with [load.cycle], got a list"
            )
    if ("delta" in cycle) == ("Q" in cycle):
        raise SceneFileError(
            "[load.cycle] needs exactly one amplitude: delta (mm, the pad block's displacement "
            "amplitude, displacement control) or Q (N/mm, force control)"
        )
    values = {k.name: cycle.get(k.name, k.default) for k in keys.values()}
    if values["shape"] not in SHAPES:
        raise SceneFileError(
            f"[load.cycle] shape must be one of {list(SHAPES)}, got {values['shape']!r}"
        )
    try:
        waveform = Waveform(
            amplitude=values["delta"] if "delta" in cycle else values["Q"],
            normal=section.get("P", _keys("load")["P"].default),
            control="displacement" if "delta" in cycle else "force",
            cycles=values["cycles"],
            increments=values["increments"],
            shape=values["shape"],
            normal_amplitude=values["P_amplitude"],
            normal_phase=values["P_phase"],
            bulk=section.get("bulk", 0.0),
            bulk_amplitude=values["bulk_amplitude"],
            bulk_phase=values["bulk_phase"],
            moment=section.get("moment"),
            moment_amplitude=values["M_amplitude"],
            moment_phase=values["M_phase"],
        )
    except (WaveformError, ValueError) as err:
        name = "delta" if "delta" in cycle else "Q"
        message = str(err).replace("Waveform.normal_amplitude", "P_amplitude")
        message = message.replace("Waveform.normal", "[load] P").replace("Waveform.amplitude", name)
        message = message.replace("Waveform.moment_amplitude", "M_amplitude")
        message = message.replace("Waveform.moment_phase", "M_phase")
        message = message.replace("Waveform.moment", "[load] moment")
        message = message.replace("Waveform.", "")
        raise SceneFileError(f"[load.cycle]: {message}") from None
    steps = waveform.steps()
    displacement = waveform.control == "displacement"
    return LoadSpec(
        steps=tuple(s.name for s in steps),
        P=tuple(s.normal for s in steps),
        Q=tuple(s.tangential for s in steps),
        bulk=tuple(s.loads.get("bulk", 0.0) for s in steps),
        increments=(1,) * len(steps),
        delta=tuple(s.delta for s in steps) if displacement else None,
        cycle=tuple(s.cycle for s in steps),
        waveform=waveform,
        moment=tuple(s.moment for s in steps) if waveform.has_moment else None,
    )


def _load(data: Mapping) -> LoadSpec:
    section = _table(data, "load")
    if "cycle" in section:
        return _cycle_load(section)
    keys = _keys("load")
    _unknown("[load]", section, keys)
    for name, value in section.items():
        _check(f"[load] {name}", value, keys[name].kind)
    for force, motion, direction in (("Q", "delta", "tangential"), ("P", "approach", "normal")):
        if force in section and motion in section:
            raise SceneFileError(
                f"[load] gives both {force} and {motion}: the {direction} direction is driven "
                f"by force ({force}) or by displacement ({motion}); keep one of them"
            )
    if "moment" in section and "rotation" in section:
        raise SceneFileError(
            "[load] gives both moment and rotation: the pad block's rotation is driven by "
            "the moment on it (moment, N mm/mm) or by the actuator's rotation (rotation, rad); "
            "keep one of them"
        )
    lists = {
        k: section[k]
        for k in (
            "steps",
            "P",
            "Q",
            "bulk",
            "increments",
            "delta",
            "approach",
            "moment",
            "rotation",
        )
        if isinstance(section.get(k), list)
    }
    for name, value in lists.items():
        if not value:
            raise SceneFileError(
                f"[load] {name} is an empty list; a load history needs at least one step "
                '(e.g. steps = ["A"], P = 100.0)'
            )
    if "steps" in section:
        n = len(section["steps"])
    elif lists:
        n = max(len(v) for v in lists.values())
    else:
        n = len(keys["steps"].default)
    values = {}
    for name in ("P", "Q", "bulk"):
        default = keys[name].default
        raw = section.get(name, default if name != "Q" or n == len(default) else 0.0)
        values[name] = tuple(float(v) for v in _per_step(name, raw, n, NUMBER))
    for name in ("delta", "approach", "moment", "rotation"):
        if name in section:
            values[name] = tuple(float(v) for v in _per_step(name, section[name], n, NUMBER))
    if "delta" in section:
        values["Q"] = (0.0,) * n
    if "approach" in section:
        values["P"] = (None,) * n
    values["increments"] = tuple(_per_step("increments", section.get("increments", 1), n, (int,)))
    if any(k < 1 for k in values["increments"]):
        raise SceneFileError(f"[load] increments must be >= 1, got {list(values['increments'])}")
    if "steps" in section:
        steps = tuple(_per_step("steps", section["steps"], n, (str,)))
    elif n == len(keys["steps"].default):
        steps = tuple(keys["steps"].default)
    else:
        steps = tuple(f"step{k + 1}" for k in range(n))
    return LoadSpec(steps, **values)


#: [contact] keys that belong to one mesh mode only
MODE_KEYS = {"pairs": "fixed", "tolerance": "adaptive", "budget": "adaptive", "estimate": "fixed"}


def _mesh_mode(contact: dict) -> None:
    """[contact] mesh and the keys of its mode: a key of the other mode is refused."""
    mode = contact.get("mesh", "fixed")
    if mode not in ("fixed", "adaptive"):
        raise SceneFileError(
            f"[contact] mesh must be 'fixed' (pairs) or 'adaptive' (tolerance, budget), got "
            f"{mode!r}"
        )
    for name, owner in MODE_KEYS.items():
        if name in contact and owner != mode:
            raise SceneFileError(
                f"[contact] {name} does not apply to mesh = {mode!r} (it is a key of "
                f"mesh = {owner!r}); remove it or set mesh = {owner!r}"
            )
    if "tolerance" in contact and not 0.0 < contact["tolerance"] < 1.0:
        raise SceneFileError(
            f"[contact] tolerance is a fraction of p0 and f p0, 0 < tolerance < 1; got "
            f"{contact['tolerance']!r} (e.g. 0.02 for 2 %)"
        )
    if "budget" in contact and contact["budget"] < 5:
        raise SceneFileError(f"[contact] budget must be >= 5 pairs, got {contact['budget']}")
    if "tolerance" in contact:
        contact["tolerance"] = float(contact["tolerance"])


def _sliding(contact: dict) -> None:
    """[contact] sliding and track_width: finite sliding needs the projection pairing and
    the fixed mesh; a track without sliding is refused."""
    if "track_width" in contact and not contact.get("sliding", False):
        raise SceneFileError(
            "[contact] track_width sets the track of finite sliding, but sliding is off; "
            "set [contact] sliding = true or remove track_width"
        )
    if "track_width" in contact and not contact["track_width"] > 0:
        raise SceneFileError(f"[contact] track_width must be > 0, got {contact['track_width']}")
    if not contact.get("sliding", False):
        return
    if contact.get("pairing", "node-to-node") != "node-to-segment":
        raise SceneFileError(
            "[contact] sliding = true re-pairs the faces by projection as the pad slides, "
            f"but [contact] pairing = {contact.get('pairing', 'node-to-node')!r}; set "
            "[contact] pairing = 'node-to-segment'"
        )
    if contact.get("mesh", "fixed") != "fixed":
        raise SceneFileError(
            "[contact] sliding = true needs mesh = 'fixed' (the adaptive mode refines the "
            "faces about a contact that does not move); set [contact] mesh = 'fixed'"
        )


def check_frame(frame: Any, sliding: bool, specimen: Any) -> str | None:
    """[contact] frame: ``"local"`` or ``"shared"``, and only where it means something,
    finite sliding along an arc (a cylinder or groove specimen). Returns the frame (None:
    not given). Called when a scene file is read and when a scene is built (a Scene made in
    Python)."""
    if frame is None:
        return None
    where = "[contact] frame"
    file_string(where, frame, error=SceneFileError)
    if frame not in FRAMES:
        raise SceneFileError(
            f"{where} must be 'local' (each pair its own frame: the arc's normal and tangent "
            f"where it meets it) or 'shared' (all pairs the pad's turned frame), got {frame!r}"
        )
    if not sliding:
        raise SceneFileError(
            f"{where} = {frame!r} chooses the pair frame of finite sliding along an arc, but "
            "[contact] sliding is off (the pairs stay where they are, in the frame of the "
            "faces as drawn); set [contact] sliding = true or remove frame"
        )
    kind = getattr(specimen, "kind", type(specimen).__name__)
    if kind == "flat":  # a shape other than flat, cylinder or groove is refused when built
        raise SceneFileError(
            f"{where} = {frame!r} has no meaning on a {kind!r} specimen: the pad slides along a "
            "straight track, so all its pairs share one frame whichever is chosen; remove "
            "frame (it applies to a 'cylinder' or 'groove' specimen, whose track is an arc)"
        )
    return frame


def check_groove(pad: Any, groove: GrooveSpecimen, pairing: str) -> None:
    """A groove takes a pad that fits in it (a cylinder of a smaller radius, or a drawn
    face, checked when the scene is built) and pairs with it by projection. Called when a
    scene file is read and when a scene is built (a Scene made in Python)."""
    if isinstance(pad, RoundedFlatPad):
        raise SceneFileError(
            "[specimen] shape = 'groove': a rounded-flat pad's flat cannot sit in a concave "
            "groove (its ends would cut into the groove's face, which rises from its lowest "
            "point); use [pad] shape = 'cylinder' with a radius smaller than the groove's, or "
            "a flat specimen"
        )
    if isinstance(pad, CylinderPad) and not pad.radius < groove.radius:
        raise SceneFileError(
            f"[specimen] radius = {groove.radius:g} mm: a groove must be wider than the "
            f"cylinder pad in it ([pad] radius = {pad.radius:g} mm), or the pad touches it at "
            "its edges instead of its lowest point (conforming contact needs 1/R* = 1/R_pad - "
            "1/R_groove > 0); make [specimen] radius larger than [pad] radius"
        )
    if pairing != "node-to-segment":
        raise SceneFileError(
            "[specimen] shape = 'groove': the groove's concave face does not mirror the pad's "
            "node to node, so its points are paired by projection, but [contact] pairing = "
            f"{pairing!r}; set [contact] pairing = 'node-to-segment'"
        )


def is_legacy(data: Mapping) -> bool:
    """True for a scene table in the round-1 format ([scene], [geometry], upper/lower materials)."""
    return bool({"scene", "geometry"} & set(data)) or bool(
        "material" in data
        and isinstance(data["material"], Mapping)
        and {"upper", "lower"} & set(data["material"])
    )


def scene_from_dict(data: Mapping) -> Scene:
    """Validate a parsed scene file (new format, or the round-1 format translated)."""
    if not isinstance(data, Mapping):
        raise SceneFileError("a scene file must be a TOML table")
    if is_legacy(data):
        raise SceneFileError(
            "this table is in the round-1 format ([scene], [geometry]); read it with"
            " fretbem.scenes.file.load_scene or scene_from_data, which translate it"
        )
    _unknown(
        "the scene file",
        data,
        {"pad", "specimen", "material", "contact", "mesh", "load", "rig", *EXTRA_TABLES},
    )
    rig_section = _table(data, "rig")
    _unknown("[rig]", rig_section, _keys("rig"))
    for name, value in rig_section.items():
        _check(f"[rig] {name}", value, _keys("rig")[name].kind)
        where = f"[rig] {name}"
        if name == "pivot_height":  # above or below the contact, within a rig's reach
            check_pivot_height(where, value, omit="leave it out", error=SceneFileError)
            continue
        unit = STIFFNESS_UNITS["rotational" if name == "stiffness_rotation" else "normal"]
        check_stiffness(
            where, value, unit, rigid="leave it out for a rigid rig", error=SceneFileError
        )
    contact_section = _table(data, "contact")
    _unknown("[contact]", contact_section, _keys("contact"))
    contact = {}
    for name, value in contact_section.items():
        key = _keys("contact")[name]
        contact[name] = _check(f"[contact] {name}", value, key.kind)
    _mesh_mode(contact)
    for body in ("pad", "specimen"):
        section = data.get(body, {})
        mode = contact.get("mesh", "fixed")
        for name in ("pairs", "elements"):
            if isinstance(section, dict) and name in section and mode != "fixed":
                raise SceneFileError(
                    f"[{body}] {name} does not apply to mesh = {mode!r} (it sets the fixed "
                    "mesh of the face); remove it or set [contact] mesh = 'fixed'"
                )
    for name, group in (("solver", "solvers"), ("law", "laws"), ("pairing", "pairings")):
        if name in contact:
            _plugin(f"[contact] {name}", contact[name], group)
    _sliding(contact)
    mesh_section = _table(data, "mesh")
    _unknown("[mesh]", mesh_section, _keys("mesh"))
    mesh = {n: _check(f"[mesh] {n}", v, _keys("mesh")[n].kind) for n, v in mesh_section.items()}
    if "zone" in contact and "zone_width" in contact:
        raise SceneFileError(
            "[contact] zone and zone_width both set the candidate zone (zone in Hertz "
            "half-widths, zone_width in mm); keep one of them"
        )
    for name, value in {**contact, **mesh}.items():
        if name in ("pairs", "flank_elements", "side_elements", "top_elements", "zone",
                    "zone_width", "friction", "degree"):  # fmt: skip
            _check_range(f"{'[contact]' if name in contact else '[mesh]'} {name}", name, value)
    extras = {name: data[name] for name in EXTRA_TABLES if name in data}
    pad, specimen = _body(data, "pad", PAD_SHAPES), _body(data, "specimen", SPECIMEN_SHAPES)
    if isinstance(specimen.shape, GrooveSpecimen):
        check_groove(pad.shape, specimen.shape, contact.get("pairing", "node-to-node"))
    check_frame(contact.get("frame"), contact.get("sliding", False), specimen.shape)
    return Scene(
        pad=pad,
        specimen=specimen,
        contact=ContactSpec(**contact),
        mesh=MeshSpec(**mesh),
        load=_load(data),
        extras=extras,
        rig=RigSpec(**{k: float(v) for k, v in rig_section.items()}),
    )


def markdown_table() -> str:
    """The documentation's key table (docs/scene-format.md), generated from :data:`KEYS`."""

    def show(value: Any) -> str:
        if value is None:
            return "—"
        if isinstance(value, str) and value != "see meaning":
            return f'`"{value}"`'
        if isinstance(value, list):
            return (
                "`[" + ", ".join(f'"{v}"' if isinstance(v, str) else f"{v:g}" for v in value) + "]`"
            )
        if isinstance(value, bool):
            return f"`{str(value).lower()}`"
        if isinstance(value, float):
            return f"`{value:g}`"
        return f"`{value}`" if value != "see meaning" else "see meaning"

    rows = ["| table | key | unit | default | meaning |", "|---|---|---|---|---|"]
    for key in KEYS:
        table = (
            "[material], [pad.material], [specimen.material]"
            if key.table == "material"
            else f"[{key.table}]"
        )
        meaning = key.meaning + (f" (shape {', '.join(key.shapes)})" if key.shapes else "")
        rows.append(
            f"| `{table}` | `{key.name}` | {key.unit or '—'} | {show(key.default)} | {meaning} |"
        )
    return "\n".join(rows)
