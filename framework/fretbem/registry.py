"""Registry of basis families, discovered from the ``fretbem.bases`` entry-point group.

Built-in families (``nurbs``, ``lagrange2``) are declared in fretbem's own ``pyproject.toml``
exactly as a third-party package declares its own, so there is one registration path.
Discovery is lazy: nothing is imported until :func:`available`, :func:`describe` or :func:`get`
is first called, and the result is cached until :func:`refresh`.
"""

from __future__ import annotations

import functools
import importlib.metadata
import re
import warnings
from collections.abc import Iterable
from typing import Any, Protocol

from fretbem.errors import ComputationError, InputError

from .basis import Basis

__all__ = [
    "GROUP",
    "KNOWN_FAMILIES",
    "BasisRegistrationError",
    "UnknownBasisError",
    "available",
    "describe",
    "families_from_entry_points",
    "get",
    "refresh",
]

GROUP = "fretbem.bases"
BUILTIN_DISTRIBUTION = "fretbem"
BUILTIN_FAMILIES: frozenset[str] = frozenset({"lagrange2", "nurbs"})

KNOWN_FAMILIES: dict[str, str] = {name: BUILTIN_DISTRIBUTION for name in sorted(BUILTIN_FAMILIES)}
"""Family name -> pip package that provides it, used to say what to install."""


class UnknownBasisError(InputError):
    """A basis family name that no installed distribution registers."""


class BasisRegistrationError(ComputationError):
    """Conflicting entry points: a duplicate name, or a built-in name claimed by another package."""


class _EntryPointLike(Protocol):
    """What the registry uses of :class:`importlib.metadata.EntryPoint`."""

    name: str
    value: str
    group: str

    def load(self) -> Any: ...


def _normalize(distribution: str) -> str:
    """Normalize a distribution name as PEP 503 does (``Fretbem_X`` -> ``fretbem-x``)."""
    return re.sub(r"[-_.]+", "-", distribution).lower()


def _distribution_of(entry_point: _EntryPointLike) -> str | None:
    """Return the normalized name of the distribution declaring ``entry_point``, if known."""
    dist = getattr(entry_point, "dist", None)
    return None if dist is None else _normalize(dist.name)


def _label(entry_point: _EntryPointLike) -> str:
    """Return ``'name = module:attr' (from dist)`` for messages."""
    dist = _distribution_of(entry_point) or "an unknown distribution"
    return f"'{entry_point.name} = {entry_point.value}' (from {dist})"


def _install_hint(family: str) -> str:
    """Return what to install for a family in :data:`KNOWN_FAMILIES`, else ``""``."""
    package = KNOWN_FAMILIES.get(family)
    if package is None:
        return ""
    if _normalize(package) == BUILTIN_DISTRIBUTION:
        return (
            f" {family!r} is built into fretbem: install it (pip install fretbem, or"
            " pip install -e . in a checkout; PYTHONPATH alone registers no entry points)."
        )
    return f" {family!r} is provided by the {package!r} package (pip install {package})."


def _load_failure_hint(family: str) -> str:
    """Return advice for a family in :data:`KNOWN_FAMILIES` whose plugin fails to import."""
    package = KNOWN_FAMILIES.get(family)
    if package is None:
        return ""
    if _normalize(package) == BUILTIN_DISTRIBUTION:
        return " The fretbem installation looks incomplete: reinstall fretbem."
    return f" Check that {package!r} and its dependencies are installed (pip install {package})."


def _unique_entry_points(entry_points: Iterable[_EntryPointLike]) -> list[_EntryPointLike]:
    """Return one entry point per name, sorted by name, raising on conflicts.

    The same (distribution, value) seen twice is collapsed; anything else sharing a name is a
    duplicate, and a built-in name declared by another distribution shadows a built-in.
    """
    by_name: dict[str, dict[tuple[str | None, str], _EntryPointLike]] = {}
    for ep in entry_points:
        if ep.name in BUILTIN_FAMILIES and _distribution_of(ep) != BUILTIN_DISTRIBUTION:
            raise BasisRegistrationError(
                f"entry point {_label(ep)} in group {GROUP!r} shadows the built-in basis family"
                f" {ep.name!r}, which only the {BUILTIN_DISTRIBUTION!r} distribution may"
                " register; rename the family in that package's entry points"
            )
        by_name.setdefault(ep.name, {}).setdefault((_distribution_of(ep), ep.value), ep)
    unique = []
    for name in sorted(by_name):
        matches = list(by_name[name].values())
        if len(matches) > 1:
            declared = "; ".join(_label(ep) for ep in matches)
            raise BasisRegistrationError(
                f"basis family {name!r} is registered more than once in group {GROUP!r}:"
                f" {declared}; uninstall or rename all but one"
            )
        unique.append(matches[0])
    return unique


def families_from_entry_points(
    entry_points: Iterable[_EntryPointLike],
) -> dict[str, type[Basis]]:
    """Load ``entry_points`` into a name -> class dict sorted by name (no caching, no discovery).

    A plugin that fails to import, or that does not load to a :class:`Basis` subclass, gives a
    ``RuntimeWarning`` and is skipped; conflicts raise :class:`BasisRegistrationError`.
    """
    families: dict[str, type[Basis]] = {}
    for ep in _unique_entry_points(entry_points):
        try:
            obj = ep.load()
        except Exception as exc:
            hint = _load_failure_hint(ep.name) if isinstance(exc, ImportError) else ""
            warnings.warn(
                f"basis family entry point {_label(ep)} failed to load and is skipped:"
                f" {type(exc).__name__}: {exc}.{hint}",
                RuntimeWarning,
                stacklevel=2,
            )
            continue
        if not (isinstance(obj, type) and issubclass(obj, Basis)) or obj is Basis:
            warnings.warn(
                f"basis family entry point {_label(ep)} loaded {obj!r}, which is not a subclass"
                " of fretbem.basis.Basis; it is skipped",
                RuntimeWarning,
                stacklevel=2,
            )
            continue
        families[ep.name] = obj
    return families


@functools.lru_cache(maxsize=1)
def _discover() -> dict[str, type[Basis]]:
    """Discover and load the installed families once; :func:`refresh` clears the cache."""
    return families_from_entry_points(importlib.metadata.entry_points(group=GROUP))


def available() -> dict[str, type[Basis]]:
    """Return name -> class for every installed basis family, sorted by name."""
    return dict(_discover())


def describe() -> dict[str, str]:
    """Return name -> one-line description for every installed basis family."""
    descriptions = {}
    for name, cls in _discover().items():
        lines = str(getattr(cls, "description", "") or "").strip().splitlines()
        descriptions[name] = lines[0] if lines else ""
    return descriptions


def get(family: str | type[Basis]) -> type[Basis]:
    """Return the basis class registered as ``family``; a :class:`Basis` subclass passes through.

    Raises :class:`UnknownBasisError` listing the installed names if ``family`` is not one of them.
    """
    if isinstance(family, type) and issubclass(family, Basis):
        return family
    if not isinstance(family, str):
        raise TypeError(f"family must be a name or a fretbem.basis.Basis subclass, not {family!r}")
    families = _discover()
    if family in families:
        return families[family]
    installed = ", ".join(repr(name) for name in families) or "none"
    hint = _install_hint(family)
    if hint:
        hint += " If it is installed, its plugin failed to load: see the RuntimeWarning."
    else:
        hint = (
            " Pass a Basis subclass directly, or install a package that registers it in the"
            f" {GROUP!r} entry-point group."
        )
    raise UnknownBasisError(
        f"unknown basis family {family!r}; installed families: {installed}.{hint}"
    )


def refresh() -> None:
    """Forget the discovered families, so the next call rediscovers installed packages."""
    _discover.cache_clear()
