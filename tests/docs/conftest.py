"""Fixtures of the documentation tests: the example plugin package, installed with pip, and
the site build, started in the background as soon as its test is collected."""

from __future__ import annotations

import importlib
import importlib.util
import shutil
import subprocess
import sys
import tempfile
import warnings
from pathlib import Path

import pytest

from fretbem import registry as bases

REPO = Path(__file__).resolve().parents[2]
DOCS = REPO / "docs"
PLUGIN = REPO / "examples" / "custom_basis"
DISTRIBUTION = "fretbem-cubic"
FAMILY = "lagrange3"


def pip(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "pip", *args],
        capture_output=True,
        text=True,
        check=False,
        timeout=600,
    )


def discovered() -> bool:
    """Whether the registry finds the example family (rediscovering installed packages)."""
    importlib.invalidate_caches()
    bases.refresh()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # a stale install fails to import
        return FAMILY in bases.available()


def _unpacked(target: Path) -> None:
    """The package and the ``.dist-info`` with the entry points of its pyproject.toml, as pip
    writes them, in ``target`` (where no wheel can be built offline)."""
    import shutil

    import tomllib

    project = tomllib.loads((PLUGIN / "pyproject.toml").read_text())["project"]
    shutil.copytree(PLUGIN / "fretbem_cubic", target / "fretbem_cubic")
    info = target / f"fretbem_cubic-{project['version']}.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(
        f"Metadata-Version: 2.1\nName: {project['name']}\nVersion: {project['version']}\n"
    )
    groups = project["entry-points"]
    (info / "entry_points.txt").write_text(
        "".join(
            f"[{group}]\n" + "".join(f"{k} = {v}\n" for k, v in entries.items())
            for group, entries in groups.items()
        )
    )


@pytest.fixture(scope="session")
def cubic_plugin(tmp_path_factory):
    """examples/custom_basis built by pip as a user installs it, into a temporary target.

    Nothing is installed into the user's environment: the package and its ``.dist-info``
    (with the entry points) go to a temporary directory put on ``sys.path`` for the session
    and removed after, so a killed test run leaves no plugin installed either.
    """
    if discovered():
        yield bases.get(FAMILY)
        return
    if pip("--version").returncode != 0:
        pytest.skip(
            "pip is not available in this Python, so the example plugin cannot be installed"
        )
    target = tmp_path_factory.mktemp("plugin-target")
    # offline (needs setuptools and wheel here); else the files pip would write by hand
    common = ("install", "--no-deps", "--target", str(target), "--no-warn-script-location")
    done = pip(*common, "--no-build-isolation", str(PLUGIN))
    if done.returncode != 0:
        _unpacked(target)
    sys.path.insert(0, str(target))
    try:
        assert discovered(), f"{DISTRIBUTION} built but {FAMILY!r} is not discovered"
        yield bases.get(FAMILY)
    finally:
        sys.path.remove(str(target))
        for name in [m for m in sys.modules if m.split(".")[0] == "fretbem_cubic"]:
            del sys.modules[name]
        importlib.invalidate_caches()
        bases.refresh()


# -- the site build ----------------------------------------------------------------------------

SITE_TEST = "test_site_builds_with_warnings_as_errors"
SITE_PACKAGES = ("sphinx_gallery", "furo", "myst_parser")  # the test skips without them
SITE_TIMEOUT = 900  # seconds the test waits for the build (it runs every gallery script)
_site_build: dict = {}


def site_build_command(folder: Path) -> list[str]:
    """``python -m sphinx -W -b html docs ...`` (the CI's docs build) into ``folder``."""
    return [sys.executable, "-m", "sphinx", "-W", "-b", "html", "-d", str(folder / "doctrees"),
            str(DOCS), str(folder / "html")]  # fmt: skip


def _start_site_build() -> None:
    folder = Path(tempfile.mkdtemp(prefix="fretbem-site-"))
    with open(folder / "stdout.txt", "w") as out, open(folder / "stderr.txt", "w") as err:
        process = subprocess.Popen(site_build_command(folder), stdout=out, stderr=err)
    _site_build.update(process=process, folder=folder)


def pytest_collection_modifyitems(session, config, items):
    """The site build's test runs last: its build runs beside the other tests meanwhile."""
    site = [item for item in items if item.name == SITE_TEST]
    items[:] = [item for item in items if item.name != SITE_TEST] + site


def pytest_collection_finish(session):
    """Start the site build (a minute or more: it runs every gallery script) when its test is
    selected, so it runs on a second core while the other tests run in this process."""
    selected = any(item.name == SITE_TEST for item in session.items)
    ready = all(importlib.util.find_spec(name) for name in SITE_PACKAGES)
    if selected and ready and not session.config.option.collectonly and not _site_build:
        _start_site_build()


def pytest_sessionfinish(session):
    """Stop a build still running (an interrupted or failed-early session); remove its files."""
    if not _site_build:
        return
    process = _site_build.pop("process")
    if process.poll() is None:
        process.kill()
        process.wait()
    shutil.rmtree(_site_build.pop("folder"), ignore_errors=True)


@pytest.fixture
def site_build():
    """The finished site build: (return code, stdout, stderr, html folder); started here if
    the session did not start it at collection."""
    for name in SITE_PACKAGES:
        pytest.importorskip(name)
    if not _site_build:
        _start_site_build()
    process = _site_build["process"]
    try:
        code = process.wait(timeout=SITE_TIMEOUT)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait()
        raise
    folder = _site_build["folder"]
    stdout, stderr = ((folder / name).read_text() for name in ("stdout.txt", "stderr.txt"))
    return code, stdout, stderr, folder / "html"
