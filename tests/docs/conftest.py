"""Fixtures of the documentation tests: the site build, started in the background as soon as
its test is collected (the example plugin package's fixture is in tests/conftest.py)."""

from __future__ import annotations

import importlib
import importlib.util
import os
import shutil
import signal
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
DOCS = REPO / "docs"


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
    _site_build.update(process=process, folder=folder, owner=os.getpid())
    if signal.getsignal(signal.SIGTERM) in (signal.SIG_DFL, None):
        signal.signal(signal.SIGTERM, _terminate)


def _stop_site_build() -> None:
    """Kill a build still running and remove its files (in the process that started it: a
    forked worker inherits the handler and this record, not the build)."""
    if not _site_build or _site_build["owner"] != os.getpid():
        return
    process, folder = _site_build["process"], _site_build["folder"]
    _site_build.clear()
    if process.poll() is None:
        process.kill()
        process.wait()
    shutil.rmtree(folder, ignore_errors=True)


def _terminate(signum, frame) -> None:
    """A test session stopped by SIGTERM stops its build too, then ends as SIGTERM would."""
    _stop_site_build()
    signal.signal(signum, signal.SIG_DFL)  # a forked worker ends as it would have
    os.kill(os.getpid(), signum)


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
    _stop_site_build()


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
