"""The ``[wear]`` table of a scene file: which laws, how many cycles, how to jump, what to
keep. Every key is one row of :data:`WEAR_KEYS` (the documentation's table is checked
against it); an unknown key, a wrong type or a bad value is refused by name.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import attrs

from fretbem import registry

from .jump import JumpControl
from .law import WearInputError, WearLaw
from .run import WearSimulation

__all__ = ["WEAR_KEYS", "WearRequest", "wear_markdown_table", "wear_request_from_dict"]

#: key -> (unit, default, meaning) of the ``[wear]`` table
WEAR_KEYS: dict[str, tuple[str, str, str]] = {
    "law": ("", '"energy"', 'wear law of both bodies (`"energy"`, `"archard"` or a plugin\'s), '
            "or a table `{pad = ..., specimen = ...}`"),
    "pad": ("law's", "—", "the pad's coefficient: alpha in mm^3/J (energy) or k in 1/MPa "
            "(archard); 0: the pad does not wear"),
    "specimen": ("law's", "—", "the specimen's coefficient, as `pad`"),
    "cycles": ("", "—", "number of load cycles N (>= 1)"),
    "cycle": ("", "every step after the first", "names of the [load] steps forming one cycle "
              "(a [load.cycle] waveform: its first cycle)"),
    "increments": ("", "the [load] increments", "increments of each cycle step"),
    "max_change": ("mm", "—", "largest change of either face's depth per cycle jump (default: "
                   "`relative_change` of the contact's relief)"),
    "relative_change": ("", "0.02", "the profile limit as a fraction of the unworn contact's "
                        "relief (the initial gap's spread over the contact, a^2/2R)"),
    "scheme": ("", '"explicit"', '`"explicit"` (limited by stability too) or `"implicit"` '
               "(linearly implicit, stable for any jump; not with [contact] sliding)"),
    "safety": ("", "0.5", "Delta N lambda allowed per jump (stability limit, < 2)"),
    "max_jump": ("cycles", "—", "upper bound on a jump"),
    "output": ("cycles", "[0, cycles]", "N at which profiles, p and q are kept (0 and cycles "
               "always)"),
    "assess": ("cycles", "[0, cycles]", "N at which the [stress] and [fatigue] requests are "
               "evaluated on the worn contact (added to `output`)"),
}  # fmt: skip


@attrs.frozen
class WearRequest:
    """A parsed ``[wear]`` table: the laws per body and the history's settings."""

    laws: Mapping[str, WearLaw]
    cycles: int
    cycle: tuple[str, ...] = ()
    increments: int | None = None
    control: JumpControl = attrs.field(factory=JumpControl)
    outputs: tuple[int, ...] = ()
    assess: tuple[int, ...] = ()

    def simulation(self, simulation, sliding: bool = False, frame: str = "local") -> WearSimulation:
        """The wear history of ``simulation`` (the scene's), cycle increments applied;
        ``sliding``: with finite sliding (``[contact] sliding = true``), ``frame`` its pair
        frame along an arc (``[contact] frame``)."""
        if self.increments is not None:
            steps = tuple(attrs.evolve(s, increments=self.increments) for s in simulation.steps)
            simulation = attrs.evolve(simulation, steps=steps)
        return WearSimulation(
            simulation, self.laws, self.cycles, self.cycle, self.control,
            tuple(sorted({*self.outputs, *self.assess})), sliding, frame,
        )  # fmt: skip


def _number(table, key, default=None, *, whole=False, minimum=None):
    if key not in table:
        return default
    value = table[key]
    kinds = (int,) if whole else (int, float)
    if isinstance(value, bool) or not isinstance(value, kinds):
        what = "a whole number" if whole else "a number"
        raise WearInputError(f"[wear] {key} must be {what}, got {value!r}")
    if minimum is not None and value < minimum:
        raise WearInputError(f"[wear] {key} must be >= {minimum}, got {value!r}")
    return value


def _cycles_list(table, key, cycles) -> tuple[int, ...]:
    value = table.get(key, [])
    if not isinstance(value, list) or any(
        isinstance(n, bool) or not isinstance(n, int) for n in value
    ):
        raise WearInputError(f"[wear] {key} must be a list of whole cycle numbers, got {value!r}")
    bad = [n for n in value if not 0 <= n <= cycles]
    if bad:
        raise WearInputError(
            f"[wear] {key} asks for N = {bad[0]}, outside 0..cycles = {cycles}; "
            "list cycle numbers between 0 and [wear] cycles"
        )
    return tuple(sorted({0, cycles, *value}))


def _law(name: Any, coefficient: Any, body: str) -> WearLaw:
    if not isinstance(name, str):
        raise WearInputError(f"[wear] law of the {body} must be a law name, got {name!r}")
    cls = registry.get(name, "wear_laws")
    if coefficient is None:
        raise WearInputError(
            f"[wear] {body} is missing: give the {body}'s {name} wear coefficient "
            f"({getattr(cls, 'coefficient_name', 'coefficient')}; 0 if it does not wear)"
        )
    if isinstance(coefficient, bool) or not isinstance(coefficient, (int, float)):
        raise WearInputError(f"[wear] {body} must be a number, got {coefficient!r}")
    try:
        return cls(coefficient)
    except WearInputError as error:
        raise WearInputError(f"[wear] {body}: {error}") from None


def wear_request_from_dict(table: Mapping[str, Any]) -> WearRequest:
    """A :class:`WearRequest` from a ``[wear]`` table (keys: :data:`WEAR_KEYS`)."""
    if not isinstance(table, Mapping):
        raise WearInputError(f"[wear] must be a table, got {type(table).__name__}")
    unknown = sorted(set(table) - set(WEAR_KEYS))
    if unknown:
        raise WearInputError(f"[wear] unknown key(s) {unknown}; the keys are {list(WEAR_KEYS)}")
    if "cycles" not in table:
        raise WearInputError("[wear] cycles is missing: give the number of load cycles N")
    cycles = _number(table, "cycles", whole=True, minimum=1)
    law = table.get("law", "energy")
    names = dict(law) if isinstance(law, Mapping) else {"pad": law, "specimen": law}
    if set(names) != {"pad", "specimen"}:
        raise WearInputError(
            f"[wear] law as a table must name the pad and the specimen, got {sorted(names)}"
        )
    laws = {
        "upper": _law(names["pad"], table.get("pad"), "pad"),
        "lower": _law(names["specimen"], table.get("specimen"), "specimen"),
    }
    cycle = table.get("cycle", [])
    if not isinstance(cycle, list) or not all(isinstance(c, str) for c in cycle):
        raise WearInputError(f"[wear] cycle must be a list of step names, got {cycle!r}")
    scheme = table.get("scheme", "explicit")
    control = JumpControl(
        max_change=_number(table, "max_change"),
        relative_change=_number(table, "relative_change", 0.02),
        safety=_number(table, "safety", 0.5),
        max_jump=_number(table, "max_jump", whole=True, minimum=1),
        scheme=scheme,
    )
    return WearRequest(
        laws, cycles, tuple(cycle), _number(table, "increments", whole=True, minimum=1), control,
        _cycles_list(table, "output", cycles), _cycles_list(table, "assess", cycles),
    )  # fmt: skip


def wear_markdown_table() -> str:
    """The documentation's ``[wear]`` key table (docs/scene-format.md), from :data:`WEAR_KEYS`."""
    rows = ["| key | unit | default | meaning |", "|---|---|---|---|"]
    for key, (unit, default, meaning) in WEAR_KEYS.items():
        shown = default if default == "—" or default[:1].isalpha() else f"`{default}`"
        rows.append(f"| `{key}` | {unit or '—'} | {shown} | {meaning} |")
    return "\n".join(rows)
