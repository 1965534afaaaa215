"""Fatigue constants of a material, each with its source, and the library of named materials.

The library is the data file ``materials.toml`` next to this module; no constant enters it
without a published source. Constants a method needs but no source gives are supplied by the
user (inline in the ``[fatigue]`` table or as keyword arguments), and are then marked as user
input. Estimates derived from other constants (shear strain-life from the uniaxial one, the
Findley factor from two fatigue limits) say so in :attr:`FatigueMaterial.derived`.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Mapping
from importlib import resources
from typing import Any

import attrs

from .errors import FatigueInputError, MissingFatigueDataError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

__all__ = ["CONSTANTS", "FatigueMaterial", "available_materials", "load_material"]

#: every constant a material may carry, with its meaning (units MPa unless said)
CONSTANTS: dict[str, str] = {
    "E": "Young's modulus",
    "nu": "Poisson's ratio",
    "yield_strength": "(cyclic) yield strength, used by Fatemi-Socie",
    "ultimate_strength": "ultimate tensile strength sigma_u, used by the Goodman and Gerber "
    "mean-stress corrections",
    "true_fracture_strength": "sigma~_fB, true fracture strength, used by the Morrow correction "
    "morrow_true_fracture",
    "fatigue_strength_coefficient": "sigma_f', Basquin coefficient (stress amplitude at 2N = 1)",
    "fatigue_strength_exponent": "b, Basquin exponent (< 0)",
    "fatigue_ductility_coefficient": "eps_f', Coffin-Manson coefficient",
    "fatigue_ductility_exponent": "c, Coffin-Manson exponent (< 0)",
    "shear_fatigue_strength_coefficient": "tau_f', shear Basquin coefficient",
    "shear_fatigue_strength_exponent": "b0, shear Basquin exponent (< 0)",
    "shear_fatigue_ductility_coefficient": "gamma_f', shear Coffin-Manson coefficient",
    "shear_fatigue_ductility_exponent": "c0, shear Coffin-Manson exponent (< 0)",
    "fatigue_limit_range": "Delta sigma_0, plain fatigue limit as a RANGE, fully reversed (R = -1)",
    "torsion_fatigue_limit_amplitude": "tau_-1, fully reversed torsion fatigue limit, AMPLITUDE",
    "threshold_sif_range": "Delta K_th, threshold stress-intensity RANGE, MPa sqrt(m)",
    "findley_k": "Findley normal-stress factor k",
    "fatemi_socie_k": "Fatemi-Socie normal-stress factor k",
}

#: physical range of each constant: (low, high, open ends); every material is checked against it
_NEGATIVE_EXPONENT = (-1.5, 0.0, True)
RANGES: dict[str, tuple[float | None, float | None, bool]] = {
    "E": (0.0, None, True),
    "nu": (-1.0, 0.5, True),
    "yield_strength": (0.0, None, True),
    "ultimate_strength": (0.0, None, True),
    "true_fracture_strength": (0.0, None, True),
    "fatigue_strength_coefficient": (0.0, None, True),
    "fatigue_strength_exponent": _NEGATIVE_EXPONENT,
    "fatigue_ductility_coefficient": (0.0, None, False),  # 0: elastic (Basquin) term only
    "fatigue_ductility_exponent": _NEGATIVE_EXPONENT,
    "shear_fatigue_strength_coefficient": (0.0, None, True),
    "shear_fatigue_strength_exponent": _NEGATIVE_EXPONENT,
    "shear_fatigue_ductility_coefficient": (0.0, None, False),
    "shear_fatigue_ductility_exponent": _NEGATIVE_EXPONENT,
    "fatigue_limit_range": (0.0, None, True),
    "torsion_fatigue_limit_amplitude": (0.0, None, True),
    "threshold_sif_range": (0.0, None, True),
    "findley_k": (0.0, 5.0, False),
    "fatemi_socie_k": (0.0, 5.0, False),
}


def _check_range(material: str, key: str, value: float) -> None:
    low, high, open_ = RANGES[key]
    bad = (low is not None and (value <= low if open_ else value < low)) or (
        high is not None and (value >= high if open_ else value > high)
    )
    if bad:
        span = " and ".join(
            f"{op} {bound:g}"
            for op, bound in (
                (">" if open_ else ">=", low),
                ("<" if open_ else "<=", high),
            )
            if bound is not None
        )
        raise FatigueInputError(
            f"[fatigue] constant {key} = {value:g} of material {material!r} is outside its "
            f"physical range: {CONSTANTS[key]} must be {span}; check its sign and units "
            "(stresses in MPa, Delta K_th in MPa sqrt(m))"
        )


_SOCIE = (
    "estimated from the uniaxial constants "
    "(von Mises: Socie and Marquis, Multiaxial Fatigue, SAE 2000)"
)


@attrs.frozen
class FatigueMaterial:
    """Named fatigue constants with their sources.

    Attributes
    ----------
    name : str
        Library name or "user".
    values : Mapping[str, float]
        Constants by the names of :data:`CONSTANTS`.
    sources : Mapping[str, str]
        Source of each constant ("user input" for inline values).
    """

    name: str
    values: Mapping[str, float] = attrs.field(converter=dict)
    sources: Mapping[str, str] = attrs.field(converter=dict)

    def __attrs_post_init__(self) -> None:
        unknown = sorted(set(self.values) - set(CONSTANTS))
        if unknown:
            raise FatigueInputError(
                f"unknown fatigue constant(s) {unknown} for {self.name!r}; "
                f"known: {sorted(CONSTANTS)}"
            )
        for key, value in self.values.items():
            if not math.isfinite(value):
                raise FatigueInputError(f"fatigue constant {key} of {self.name!r} must be finite")
            _check_range(self.name, key, value)

    def with_values(
        self, values: Mapping[str, float], source: str = "user input"
    ) -> FatigueMaterial:
        """A copy with ``values`` added or replaced, their source recorded as ``source``."""
        new_values = {**self.values, **{k: float(v) for k, v in values.items()}}
        new_sources = {**self.sources, **{k: source for k in values}}
        return FatigueMaterial(name=self.name, values=new_values, sources=new_sources)

    def has(self, key: str) -> bool:
        """Whether the constant (or its documented estimate) is available."""
        try:
            self.get(key)
        except MissingFatigueDataError:
            return False
        return True

    def require(self, keys: tuple[str, ...], purpose: str) -> dict[str, float]:
        """The constants ``keys`` (derived where documented); one error naming all missing."""
        found, missing = {}, []
        for key in keys:
            try:
                found[key] = self.get(key)
            except MissingFatigueDataError:
                missing.append(key)
        if missing:
            raise MissingFatigueDataError(
                f"{purpose} needs {missing} for material {self.name!r}, which has no sourced "
                "value for them: give them in the [fatigue.constants] table (e.g. "
                f"{missing[0]} = ...)"
            )
        return found

    @property
    def derived(self) -> dict[str, str]:
        """Constants that are estimates, with how they were estimated."""
        out = {}
        for key in (
            "shear_fatigue_strength_coefficient",
            "shear_fatigue_strength_exponent",
            "shear_fatigue_ductility_coefficient",
            "shear_fatigue_ductility_exponent",
            "findley_k",
        ):
            if key not in self.values and self.has(key):
                out[key] = (
                    "from the bending and torsion fatigue limits: 2 tau_-1 / sigma_-1 = "
                    "1 + k / sqrt(1 + k^2)"
                    if key == "findley_k"
                    else _SOCIE
                )
        return out

    def get(self, key: str) -> float:
        """A constant, or its documented estimate; :class:`MissingFatigueDataError` if neither."""
        v = self.values
        if key in v:
            return v[key]
        uni = {
            "shear_fatigue_strength_coefficient": (
                "fatigue_strength_coefficient",
                1 / math.sqrt(3),
            ),
            "shear_fatigue_strength_exponent": ("fatigue_strength_exponent", 1.0),
            "shear_fatigue_ductility_coefficient": ("fatigue_ductility_coefficient", math.sqrt(3)),
            "shear_fatigue_ductility_exponent": ("fatigue_ductility_exponent", 1.0),
        }
        if key in uni and uni[key][0] in v:
            return v[uni[key][0]] * uni[key][1]
        if key == "findley_k" and {"fatigue_limit_range", "torsion_fatigue_limit_amplitude"} <= set(
            v
        ):
            r = 2.0 * v["torsion_fatigue_limit_amplitude"] / (0.5 * v["fatigue_limit_range"])
            if not 1.0 < r < 2.0:
                raise FatigueInputError(
                    f"Findley k from the fatigue limits needs sigma_-1/2 < tau_-1 < sigma_-1, got "
                    f"tau_-1 / sigma_-1 = {r / 2:.3f}; give findley_k directly"
                )
            return (r - 1.0) / math.sqrt(1.0 - (r - 1.0) ** 2)
        raise MissingFatigueDataError(f"material {self.name!r} has no {key}")

    @classmethod
    def from_table(cls, name: str, table: Mapping[str, Any]) -> FatigueMaterial:
        """From a TOML table whose constants are ``{value, source}`` tables or plain numbers."""
        values, sources = {}, {}
        for key, entry in table.items():
            if key == "description":
                continue
            if isinstance(entry, Mapping):
                if "value" not in entry or not entry.get("source"):
                    raise FatigueInputError(
                        f'constant {key} of {name!r} must be {{ value = ..., source = "..." }}'
                    )
                values[key], sources[key] = float(entry["value"]), str(entry["source"])
            elif isinstance(entry, (int, float)) and not isinstance(entry, bool):
                values[key], sources[key] = float(entry), "user input"
            else:
                raise FatigueInputError(
                    f"constant {key} of {name!r} must be a number, got {entry!r}"
                )
        return cls(name=name, values=values, sources=sources)


def _library() -> dict[str, Any]:
    text = resources.files(__package__).joinpath("materials.toml").read_text(encoding="utf-8")
    return tomllib.loads(text)["materials"]


def available_materials() -> tuple[str, ...]:
    """Names of the materials in the library."""
    return tuple(_library())


def load_material(name: str) -> FatigueMaterial:
    """A library material by name; an unknown name lists the available ones."""
    library = _library()
    if name not in library:
        raise FatigueInputError(
            f"unknown fatigue material {name!r}; the library has {sorted(library)} "
            "(or give the constants inline)"
        )
    return FatigueMaterial.from_table(name, library[name])
