"""One registry for every named choice, discovered from entry-point groups.

Each group names one kind of plugin: basis families (``fretbem.bases``), body models
(``fretbem.bodies``), contact solvers (``fretbem.solvers``), contact laws
(``fretbem.laws``), contact pairings (``fretbem.pairings``) and wear laws
(``fretbem.wear_laws``); a new kind is one :class:`Group`
line in :data:`GROUPS`. fretbem's own choices are declared in its ``pyproject.toml``
exactly as a third-party package declares its own, so there is one registration path.
Discovery is lazy: the installed entry points are read (metadata only) when a group is
first asked for, and a plugin is imported only when its name is asked for (:func:`get`),
or when every plugin of a group is (:func:`available`, :func:`describe`); both are cached
until :func:`refresh`. So a run that names the ``bem`` body model does not import the
half-plane model. A plugin that fails to load gives a warning naming it and is skipped; a
duplicate name, or a built-in name claimed by another package, is an error (raised when
the group is read, before any import); an unknown name is an error listing the installed
ones that load and what to install. The model is xarray's backend registry
(``xarray/backends/plugins.py``: entry points read first, a backend loaded when used).
"""

from __future__ import annotations

import functools
import importlib
import importlib.metadata
import re
import warnings
from collections.abc import Iterable
from typing import Any, Protocol

import attrs

from fretbem.errors import ComputationError, InputError

from .basis import Basis

__all__ = [
    "GROUP",
    "GROUPS",
    "KNOWN_FAMILIES",
    "BasisRegistrationError",
    "Group",
    "PluginRegistrationError",
    "UnknownBasisError",
    "UnknownPluginError",
    "available",
    "describe",
    "entries",
    "families_from_entry_points",
    "get",
    "load_group",
    "refresh",
]

BUILTIN_DISTRIBUTION = "fretbem"


class UnknownPluginError(InputError):
    """A name that no installed distribution registers in its group."""


class UnknownBasisError(UnknownPluginError):
    """A basis family name that no installed distribution registers."""


class PluginRegistrationError(ComputationError):
    """Conflicting entry points: a duplicate name, or a built-in name claimed by another package."""


class BasisRegistrationError(PluginRegistrationError):
    """Conflicting basis-family entry points."""


@attrs.frozen
class Group:
    """One kind of plugin.

    Attributes
    ----------
    key : str
        Short name used in code and by ``fretbem plugins`` ("bases", "bodies", ...).
    entry_points : str
        The entry-point group.
    what : str
        What one plugin is, for messages ("basis family", "body model", ...).
    base : str
        ``module:Class`` that every plugin must subclass (imported when the group loads, so
        the registry depends on no higher layer).
    builtins : frozenset of str
        Names only fretbem itself may register.
    plural : str
        "installed <plural>: ..." in messages.
    known : mapping of str to str
        Name -> pip package providing it, so a missing one says what to install.
    """

    key: str
    entry_points: str
    what: str
    base: str
    builtins: frozenset = attrs.field(converter=frozenset)
    plural: str = ""
    known: dict = attrs.field(factory=dict)

    def base_class(self) -> type:
        module, _, name = self.base.partition(":")
        return getattr(importlib.import_module(module), name)


KNOWN_FAMILIES: dict[str, str] = {"lagrange2": BUILTIN_DISTRIBUTION, "nurbs": BUILTIN_DISTRIBUTION}
"""Family name -> pip package that provides it, used to say what to install."""

GROUPS: dict[str, Group] = {
    g.key: g
    for g in (
        Group("bases", "fretbem.bases", "basis family", "fretbem.basis:Basis",
              {"lagrange2", "nurbs"}, "families", KNOWN_FAMILIES),
        Group("bodies", "fretbem.bodies", "body model", "fretbem.scenes.models:BodyModel",
              {"bem", "half-plane"}, "body models"),
        Group("solvers", "fretbem.solvers", "contact solver", "fretbem.solvers.newton:Solver",
              {"newton", "lemke"}, "solvers"),
        Group("laws", "fretbem.laws", "contact law", "fretbem.contact.law:ContactLaw",
              {"coulomb"}, "laws"),
        Group("pairings", "fretbem.pairings", "contact pairing",
              "fretbem.contact.pairs:ContactPair", {"node-to-node", "node-to-segment"},
              "pairings"),
        Group("wear_laws", "fretbem.wear_laws", "wear law", "fretbem.wear.law:WearLaw",
              {"archard", "energy"}, "wear laws"),
    )
}  # fmt: skip
#: the basis families' entry-point group (kept under its first name)
GROUP = GROUPS["bases"].entry_points


class _EntryPointLike(Protocol):
    """What the registry uses of :class:`importlib.metadata.EntryPoint`."""

    name: str
    value: str
    group: str

    def load(self) -> Any: ...


def _normalize(distribution: str) -> str:
    """Normalize a distribution name as PEP 503 does (``Fretbem_X`` -> ``fretbem-x``)."""
    return re.sub(r"[-_.]+", "-", distribution).lower()


#: id(distribution) -> (distribution, normalized name): a distribution's name is read from
#: its metadata file (an e-mail header parse, ~1 ms) once for all of its entry points, not
#: once per entry point (fretbem alone declares eleven); :func:`refresh` forgets them
_DISTRIBUTION_NAMES: dict[int, tuple[Any, str]] = {}


def _distribution_of(entry_point: _EntryPointLike) -> str | None:
    """Return the normalized name of the distribution declaring ``entry_point``, if known."""
    dist = getattr(entry_point, "dist", None)
    if dist is None:
        return None
    known = _DISTRIBUTION_NAMES.get(id(dist))
    if known is None or known[0] is not dist:  # the object is kept: its id is not reused
        known = _DISTRIBUTION_NAMES[id(dist)] = (dist, _normalize(dist.name))
    return known[1]


def _label(entry_point: _EntryPointLike) -> str:
    """Return ``'name = module:attr' (from dist)`` for messages."""
    dist = _distribution_of(entry_point) or "an unknown distribution"
    return f"'{entry_point.name} = {entry_point.value}' (from {dist})"


def _package(group: Group, name: str) -> str | None:
    package = group.known.get(name)
    if package is None and name in group.builtins:
        package = BUILTIN_DISTRIBUTION
    return package


def _install_hint(group: Group, name: str) -> str:
    """What to install for a known name that is missing, else ``""``."""
    package = _package(group, name)
    if package is None:
        return ""
    if _normalize(package) == BUILTIN_DISTRIBUTION:
        return (
            f" {name!r} is built into fretbem: install it (pip install fretbem, or"
            " pip install -e . in a checkout; PYTHONPATH alone registers no entry points)."
        )
    return f" {name!r} is provided by the {package!r} package (pip install {package})."


def _load_failure_hint(group: Group, name: str) -> str:
    """Advice for a known plugin whose import fails."""
    package = _package(group, name)
    if package is None:
        return ""
    if _normalize(package) == BUILTIN_DISTRIBUTION:
        return " The fretbem installation looks incomplete: reinstall fretbem."
    return f" Check that {package!r} and its dependencies are installed (pip install {package})."


def _errors(group: Group) -> tuple[type, type]:
    if group.key == "bases":
        return UnknownBasisError, BasisRegistrationError
    return UnknownPluginError, PluginRegistrationError


def _unique_entry_points(
    entry_points: Iterable[_EntryPointLike], group: Group
) -> list[_EntryPointLike]:
    """One entry point per name, sorted by name, raising on conflicts.

    The same (distribution, value) seen twice is collapsed; anything else sharing a name is a
    duplicate, and a built-in name declared by another distribution shadows a built-in.
    """
    conflict = _errors(group)[1]
    by_name: dict[str, dict[tuple[str | None, str], _EntryPointLike]] = {}
    for ep in entry_points:
        dist = _distribution_of(ep)  # reads the distribution's metadata file: once per entry
        if ep.name in group.builtins and dist != BUILTIN_DISTRIBUTION:
            raise conflict(
                f"entry point {_label(ep)} in group {group.entry_points!r} shadows the built-in"
                f" {group.what} {ep.name!r}, which only the {BUILTIN_DISTRIBUTION!r} distribution"
                " may register; rename it in that package's entry points"
            )
        by_name.setdefault(ep.name, {}).setdefault((dist, ep.value), ep)
    unique = []
    for name in sorted(by_name):
        matches = list(by_name[name].values())
        if len(matches) > 1:
            declared = "; ".join(_label(ep) for ep in matches)
            raise conflict(
                f"{group.what} {name!r} is registered more than once in group"
                f" {group.entry_points!r}: {declared}; uninstall or rename all but one"
            )
        unique.append(matches[0])
    return unique


def _load_one(entry_point: _EntryPointLike, group: Group) -> Any:
    """The class ``entry_point`` loads, or None after a ``RuntimeWarning`` naming it when it
    fails to import or is not a subclass of the group's base."""
    try:
        obj = entry_point.load()
    except Exception as exc:
        hint = _load_failure_hint(group, entry_point.name) if isinstance(exc, ImportError) else ""
        warnings.warn(
            f"{group.what} entry point {_label(entry_point)} failed to load and is skipped:"
            f" {type(exc).__name__}: {exc}.{hint}",
            RuntimeWarning,
            stacklevel=3,
        )
        return None
    base = group.base_class()
    if not (isinstance(obj, type) and issubclass(obj, base)) or obj is base:
        warnings.warn(
            f"{group.what} entry point {_label(entry_point)} loaded {obj!r}, which is not a"
            f" subclass of {group.base.replace(':', '.')}; it is skipped",
            RuntimeWarning,
            stacklevel=3,
        )
        return None
    return obj


def load_entry_points(entry_points: Iterable[_EntryPointLike], group: Group) -> dict[str, Any]:
    """Load ``entry_points`` of ``group`` into a name -> class dict (no caching, no discovery).

    A plugin that fails to import, or that does not load to a subclass of the group's base,
    gives a ``RuntimeWarning`` naming it and is skipped; conflicts raise before any import.
    """
    loaded: dict[str, Any] = {}
    for ep in _unique_entry_points(entry_points, group):
        obj = _load_one(ep, group)
        if obj is not None:
            loaded[ep.name] = obj
    return loaded


def families_from_entry_points(entry_points: Iterable[_EntryPointLike]) -> dict[str, type[Basis]]:
    """Basis families of ``entry_points`` (:func:`load_entry_points` for "bases")."""
    return load_entry_points(entry_points, GROUPS["bases"])


@functools.cache
def _installed_entry_points() -> tuple[_EntryPointLike, ...]:
    """Every installed entry point, read in one pass over the distributions' metadata (a
    pass per group cost ~6 ms each, six groups on every run); :func:`refresh` forgets it."""
    found = importlib.metadata.entry_points()
    if isinstance(found, dict):  # Python < 3.12: groups in a dict whose own methods warn
        found = [ep for group in dict.values(found) for ep in group]
    return tuple(found)


def _discovered(group: Group) -> list[_EntryPointLike]:
    """The installed entry points of ``group``."""
    return [ep for ep in _installed_entry_points() if ep.group == group.entry_points]


@functools.cache
def _named(key: str) -> dict[str, _EntryPointLike]:
    """Name -> entry point of every installed plugin of a group, sorted, conflicts raised;
    nothing imported (:func:`refresh` forgets it)."""
    group = _group(key)
    return {ep.name: ep for ep in _unique_entry_points(_discovered(group), group)}


@functools.cache
def _plugin(key: str, name: str) -> Any:
    """The class of the installed plugin ``name`` of a group, imported on first use (None,
    after one warning, when it does not load)."""
    return _load_one(_named(key)[name], _group(key))


@functools.cache
def load_group(key: str) -> dict[str, Any]:
    """Every plugin of a group imported (name -> class, sorted, those that load); cached
    until :func:`refresh`."""
    loaded = {name: _plugin(key, name) for name in _named(key)}
    return {name: cls for name, cls in loaded.items() if cls is not None}


@functools.cache
def _base_class(key: str) -> type:
    """The base class of group ``key``, imported once (a scene build asks for it about ten
    times: a class passed as a plugin is checked against it)."""
    return _group(key).base_class()


def _group(key: str) -> Group:
    if key not in GROUPS:
        raise UnknownPluginError(f"no plugin group {key!r}; the groups are {sorted(GROUPS)}")
    return GROUPS[key]


def available(group: str = "bases") -> dict[str, Any]:
    """Name -> class for every installed plugin of ``group``, sorted by name."""
    return dict(load_group(group))


def describe(group: str = "bases") -> dict[str, str]:
    """Name -> one-line description (the class's ``description`` or docstring) of a group."""
    out = {}
    for name, cls in load_group(group).items():
        text = str(getattr(cls, "description", "") or cls.__doc__ or "").strip()
        out[name] = text.splitlines()[0] if text else ""
    return out


def get(name: str | type, group: str = "bases") -> Any:
    """The class registered as ``name`` in ``group``; a class of the group passes through.

    Raises :class:`UnknownPluginError` (:class:`UnknownBasisError` for bases) listing the
    installed names if ``name`` is not one of them.
    """
    spec = _group(group)
    if isinstance(name, type) and issubclass(name, _base_class(group)):
        return name
    if not isinstance(name, str):
        base = spec.base.replace(":", ".")
        raise TypeError(f"a {spec.what} is a name or a {base} subclass, not {name!r}")
    if name in _named(group):  # only this plugin is imported
        found = _plugin(group, name)
        if found is not None:
            return found
    installed = ", ".join(repr(n) for n in load_group(group)) or "none"
    hint = _install_hint(spec, name)
    if hint:
        hint += " If it is installed, its plugin failed to load: see the RuntimeWarning."
    else:
        hint = (
            f" Pass a class directly, or install a package that registers it in the"
            f" {spec.entry_points!r} entry-point group."
        )
    unknown = _errors(spec)[0]
    raise unknown(f"unknown {spec.what} {name!r}; installed {spec.plural}: {installed}.{hint}")


def entries(group: str) -> list[dict[str, str]]:
    """Every entry point of ``group`` as name, distribution, version, object and status
    ("ok", or why it does not load), for ``fretbem plugins``; never raises for one plugin."""
    spec = _group(group)
    rows = []
    found = _discovered(spec)
    for ep in sorted(found, key=lambda e: e.name):
        dist = getattr(ep, "dist", None)
        row = {
            "name": ep.name,
            "distribution": dist.name if dist is not None else "?",
            "version": dist.version if dist is not None else "?",
            "object": ep.value,
        }
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                loaded = load_group(group)
            row["status"] = "ok" if ep.name in loaded else "does not load (see the warning)"
        except PluginRegistrationError as err:
            row["status"] = str(err)
        rows.append(row)
    return rows


def refresh() -> None:
    """Forget every discovered group, so the next call rediscovers installed packages."""
    load_group.cache_clear()
    _plugin.cache_clear()
    _named.cache_clear()
    _installed_entry_points.cache_clear()
    _DISTRIBUTION_NAMES.clear()
