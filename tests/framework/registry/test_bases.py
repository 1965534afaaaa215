"""Tests for the basis-family registry, fed hand-built entry points."""

from __future__ import annotations

import importlib.metadata
import os
import subprocess
import sys
import types
import warnings
from collections.abc import Iterator
from dataclasses import dataclass
from importlib.metadata import EntryPoint
from pathlib import Path
from typing import Any

import pytest

from fretbem import registry as bases
from fretbem.basis import Basis

ROOT = Path(__file__).resolve().parents[3]
PLUGIN = "fretbem_dummy_plugin"  # a module that exists only in sys.modules, see `plugin_module`


class DummyBasis(Basis):
    """A minimal family; the registry never instantiates it."""

    name = "dummy"
    description = "Dummy family for registry tests.\nA second line that describe() drops."


class OtherBasis(Basis):
    """A second minimal family."""

    name = "other"
    description = "Other dummy family."


class NotABasis:
    """A class that is not a Basis subclass."""


@dataclass(frozen=True)
class FakeEntryPoint:
    """Stand-in for an installed EntryPoint, whose ``dist`` can be set."""

    name: str
    value: str
    distribution: str | None = "fretbem-dummy"
    group: str = bases.GROUP

    @property
    def dist(self) -> types.SimpleNamespace | None:
        """Mimic ``EntryPoint.dist``, which only needs a ``name`` here."""
        if self.distribution is None:
            return None
        return types.SimpleNamespace(name=self.distribution)

    def load(self) -> Any:
        """Load through a real EntryPoint, so import failures are genuine."""
        return EntryPoint(name=self.name, value=self.value, group=self.group).load()


@pytest.fixture(autouse=True)
def plugin_module(monkeypatch: pytest.MonkeyPatch) -> Iterator[types.ModuleType]:
    """Make `PLUGIN` importable and start each test with an empty registry cache."""
    module = types.ModuleType(PLUGIN)
    module.DummyBasis = DummyBasis
    module.OtherBasis = OtherBasis
    module.NotABasis = NotABasis
    module.not_a_class = DummyBasis.__name__
    monkeypatch.setitem(sys.modules, PLUGIN, module)
    bases.refresh()
    yield module
    bases.refresh()


@pytest.fixture
def install(monkeypatch: pytest.MonkeyPatch) -> Any:
    """Return a function that fakes the installed entry points; it counts discoveries."""
    calls = []

    def install_(*entry_points: Any) -> list[str]:
        def fake_entry_points(*, group: str | None = None) -> list[Any]:
            calls.append(group)  # one call reads every group (group None)
            return [ep for ep in entry_points if group in (None, ep.group)]

        monkeypatch.setattr(importlib.metadata, "entry_points", fake_entry_points)
        return calls

    return install_


def test_real_entry_points_load_sorted_by_name() -> None:
    """Real EntryPoint objects load to their classes, keyed and sorted by name."""
    eps = [
        EntryPoint(name="other", value=f"{PLUGIN}:OtherBasis", group=bases.GROUP),
        EntryPoint(name="dummy", value=f"{PLUGIN}:DummyBasis", group=bases.GROUP),
    ]
    families = bases.families_from_entry_points(eps)
    assert families == {"dummy": DummyBasis, "other": OtherBasis}
    assert list(families) == ["dummy", "other"]


def test_broken_plugin_warns_and_is_skipped() -> None:
    """A plugin that fails to import gives a RuntimeWarning naming it and is skipped."""
    eps = [
        EntryPoint(name="broken", value="fretbem_no_such_module:Basis", group=bases.GROUP),
        EntryPoint(name="dummy", value=f"{PLUGIN}:DummyBasis", group=bases.GROUP),
    ]
    with pytest.warns(RuntimeWarning) as record:
        families = bases.families_from_entry_points(eps)
    assert families == {"dummy": DummyBasis}
    assert len(record) == 1
    message = str(record[0].message)
    assert "'broken = fretbem_no_such_module:Basis'" in message
    assert "ModuleNotFoundError" in message


def test_broken_known_family_warning_says_what_to_install(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """An ImportError in a family listed in KNOWN_FAMILIES says which package to install."""
    monkeypatch.setitem(bases.KNOWN_FAMILIES, "bezier3", "fretbem-bezier")
    ep = FakeEntryPoint("bezier3", "fretbem_no_such_module:Bezier", distribution="fretbem-bezier")
    with pytest.warns(RuntimeWarning, match="pip install fretbem-bezier"):
        assert bases.families_from_entry_points([ep]) == {}


def test_broken_builtin_warning_says_reinstall_fretbem() -> None:
    """A built-in family that fails to import points at a broken fretbem installation."""
    ep = FakeEntryPoint("nurbs", "fretbem_no_such_module:NurbsBasis", distribution="fretbem")
    with pytest.warns(RuntimeWarning, match="reinstall fretbem"):
        assert bases.families_from_entry_points([ep]) == {}


@pytest.mark.parametrize(
    "value", [f"{PLUGIN}:NotABasis", f"{PLUGIN}:not_a_class", "fretbem.basis:Basis"]
)
def test_non_basis_warns_and_is_skipped(value: str) -> None:
    """An entry point that does not load to a strict Basis subclass warns and is skipped."""
    ep = EntryPoint(name="odd", value=value, group=bases.GROUP)
    with pytest.warns(RuntimeWarning, match=r"'odd = .*' .*not a subclass"):
        assert bases.families_from_entry_points([ep]) == {}


def test_duplicate_from_different_distributions_is_error() -> None:
    """The same name declared by two distributions raises, naming both."""
    eps = [
        FakeEntryPoint("dummy", f"{PLUGIN}:DummyBasis", distribution="fretbem-a"),
        FakeEntryPoint("dummy", f"{PLUGIN}:OtherBasis", distribution="fretbem-b"),
    ]
    with pytest.raises(bases.BasisRegistrationError, match="more than once") as info:
        bases.families_from_entry_points(eps)
    assert "fretbem-a" in str(info.value)
    assert "fretbem-b" in str(info.value)


def test_identical_entry_point_seen_twice_is_collapsed() -> None:
    """One distribution found twice on the path registers its family once, silently."""
    ep = FakeEntryPoint("dummy", f"{PLUGIN}:DummyBasis")
    assert bases.families_from_entry_points([ep, ep]) == {"dummy": DummyBasis}


class CountingDistribution:
    """A distribution whose ``name`` (a metadata file read in importlib) counts its reads."""

    def __init__(self, name: str) -> None:
        self._name, self.reads = name, 0

    @property
    def name(self) -> str:
        self.reads += 1
        return self._name


@dataclass(frozen=True)
class SharedDistEntryPoint(FakeEntryPoint):
    """An entry point of a given distribution object, as importlib gives every entry point
    of one distribution the same ``dist``."""

    shared: Any = None

    @property
    def dist(self) -> Any:
        return self.shared


def test_a_distribution_name_is_read_once_for_all_its_entry_points() -> None:
    """The name (importlib parses the metadata file for it) is read once per distribution
    object, names and conflicts unchanged; refresh() reads it again."""
    dist, other = CountingDistribution("Fretbem_A"), CountingDistribution("fretbem-b")
    eps = [SharedDistEntryPoint(name, f"{PLUGIN}:DummyBasis", shared=dist) for name in "xyz"]
    eps.append(SharedDistEntryPoint("w", f"{PLUGIN}:OtherBasis", shared=other))
    assert list(bases.families_from_entry_points(eps)) == ["w", "x", "y", "z"]
    assert bases.families_from_entry_points(eps[:1]) == {"x": DummyBasis}
    assert (dist.reads, other.reads) == (1, 1)
    clash = SharedDistEntryPoint("x", f"{PLUGIN}:OtherBasis", shared=other)
    with pytest.raises(bases.BasisRegistrationError, match=r"fretbem-a.*fretbem-b"):
        bases.families_from_entry_points([eps[0], clash])
    bases.refresh()
    bases.families_from_entry_points(eps)
    assert (dist.reads, other.reads) == (2, 2)


def test_conflicts_raise_before_any_plugin_is_imported() -> None:
    """A conflict is reported without importing (or warning about) any plugin."""
    eps = [
        FakeEntryPoint("dummy", "fretbem_no_such_module:A", distribution="fretbem-a"),
        FakeEntryPoint("dummy", "fretbem_no_such_module:B", distribution="fretbem-b"),
    ]
    with pytest.raises(bases.BasisRegistrationError):
        bases.families_from_entry_points(eps)


@pytest.mark.parametrize("distribution", ["fretbem-nurbs-fork", None])
def test_shadowing_a_builtin_is_error(distribution: str | None) -> None:
    """A built-in name declared by any distribution other than fretbem raises."""
    ep = FakeEntryPoint("nurbs", f"{PLUGIN}:DummyBasis", distribution=distribution)
    with pytest.raises(bases.BasisRegistrationError, match="shadows the built-in"):
        bases.families_from_entry_points([ep])


@pytest.mark.parametrize("distribution", ["fretbem", "Fretbem"])
def test_builtin_from_fretbem_is_accepted(distribution: str) -> None:
    """Built-in names declared by the fretbem distribution itself register normally."""
    ep = FakeEntryPoint("lagrange2", f"{PLUGIN}:DummyBasis", distribution=distribution)
    assert bases.families_from_entry_points([ep]) == {"lagrange2": DummyBasis}


def test_get_by_name(install: Any) -> None:
    """get() returns the class registered under a name."""
    install(FakeEntryPoint("dummy", f"{PLUGIN}:DummyBasis"))
    assert bases.get("dummy") is DummyBasis


def test_get_unknown_name_lists_installed_names(install: Any) -> None:
    """An unknown name raises UnknownBasisError (a ValueError) listing the installed names."""
    install(
        FakeEntryPoint("dummy", f"{PLUGIN}:DummyBasis"),
        FakeEntryPoint("other", f"{PLUGIN}:OtherBasis"),
    )
    with pytest.raises(ValueError, match=r"'nope'.*'dummy', 'other'") as info:
        bases.get("nope")
    assert isinstance(info.value, bases.UnknownBasisError)


def test_get_missing_builtin_says_install_fretbem(install: Any) -> None:
    """A built-in that is not registered says fretbem itself must be installed."""
    install()
    with pytest.raises(bases.UnknownBasisError, match=r"installed families: none.*pip install"):
        bases.get("nurbs")


def test_get_missing_known_family_says_pip_install(
    install: Any, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A name in KNOWN_FAMILIES that is not installed says which package to pip install."""
    monkeypatch.setitem(bases.KNOWN_FAMILIES, "bezier3", "fretbem-bezier")
    install()
    with pytest.raises(bases.UnknownBasisError, match="pip install fretbem-bezier"):
        bases.get("bezier3")


def test_get_imports_only_the_plugin_it_names(install: Any) -> None:
    """get() imports the named plugin alone: a broken or slow one beside it is not touched
    (no import, no warning) until every plugin is asked for."""
    install(
        FakeEntryPoint("dummy", f"{PLUGIN}:DummyBasis"),
        FakeEntryPoint("broken", "fretbem_no_such_module:Broken"),
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a warning here would mean 'broken' was imported
        assert bases.get("dummy") is DummyBasis
    with pytest.warns(RuntimeWarning, match="'broken = fretbem_no_such_module:Broken'"):
        assert bases.available() == {"dummy": DummyBasis}


def test_get_of_a_broken_plugin_warns_and_lists_those_that_load(install: Any) -> None:
    """Asking for a plugin that fails to import warns once, then the unknown-name error lists
    the installed plugins that load."""
    install(
        FakeEntryPoint("dummy", f"{PLUGIN}:DummyBasis"),
        FakeEntryPoint("broken", "fretbem_no_such_module:Broken"),
        FakeEntryPoint("other", f"{PLUGIN}:OtherBasis"),
    )
    with pytest.warns(RuntimeWarning, match="failed to load") as record:
        with pytest.raises(bases.UnknownBasisError, match=r"families: 'dummy', 'other'\."):
            bases.get("broken")
    assert len(record) == 1


def test_get_passes_a_class_through_without_discovery(install: Any) -> None:
    """A Basis subclass passed to get() is returned as is, without reading entry points."""
    calls = install()
    assert bases.get(DummyBasis) is DummyBasis
    assert calls == []


@pytest.mark.parametrize("family", [NotABasis, 3, None])
def test_get_rejects_other_types(family: Any) -> None:
    """get() raises TypeError for anything but a name or a Basis subclass."""
    with pytest.raises(TypeError, match="Basis"):
        bases.get(family)


def test_available_is_cached_until_refresh(install: Any) -> None:
    """Discovery runs once; refresh() makes the next call see newly installed families."""
    calls = install(FakeEntryPoint("dummy", f"{PLUGIN}:DummyBasis"))
    assert bases.available() == {"dummy": DummyBasis}
    assert bases.get("dummy") is DummyBasis
    assert len(calls) == 1
    install(FakeEntryPoint("other", f"{PLUGIN}:OtherBasis"))
    assert bases.available() == {"dummy": DummyBasis}
    bases.refresh()
    assert bases.available() == {"other": OtherBasis}
    assert len(calls) == 2


def test_available_returns_a_copy(install: Any) -> None:
    """Mutating the dict returned by available() leaves the registry unchanged."""
    install(FakeEntryPoint("dummy", f"{PLUGIN}:DummyBasis"))
    bases.available().clear()
    assert bases.available() == {"dummy": DummyBasis}


def test_describe_gives_one_line_per_family(install: Any) -> None:
    """describe() maps each name to the first line of its class's description."""
    install(
        FakeEntryPoint("other", f"{PLUGIN}:OtherBasis"),
        FakeEntryPoint("dummy", f"{PLUGIN}:DummyBasis"),
    )
    assert bases.describe() == {
        "dummy": "Dummy family for registry tests.",
        "other": "Other dummy family.",
    }


def test_lazy_import() -> None:
    """Importing fretbem (and its registry) imports no plugin, matplotlib or pyvista."""
    code = (
        "import sys, fretbem, fretbem.registry\n"
        "lazy = ['fretbem_nurbs', 'fretbem_lagrange', 'matplotlib', 'pyvista']\n"
        "loaded = [m for m in lazy if m in sys.modules]\n"
        "assert not loaded, f'imported eagerly: {loaded}'\n"
    )
    path = os.pathsep.join([str(ROOT / "framework"), str(ROOT / "plugins")])
    env = {**os.environ, "PYTHONPATH": path + os.pathsep + os.environ.get("PYTHONPATH", "")}
    result = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=False
    )
    assert result.returncode == 0, result.stderr


def _fretbem_installed() -> bool:
    """Whether the fretbem distribution (and so its entry points) is installed."""
    try:
        importlib.metadata.distribution("fretbem")
    except importlib.metadata.PackageNotFoundError:
        return False
    return True


@pytest.mark.skipif(not _fretbem_installed(), reason="fretbem is not installed (pip install -e .)")
def test_installed_builtins_are_discovered() -> None:
    """With fretbem installed, its own entry points register both built-in families."""
    families = bases.available()
    assert {"nurbs", "lagrange2"} <= families.keys()
    assert all(issubclass(cls, Basis) for cls in families.values())
