"""Test-session settings shared by every test folder."""

import os

# The contact Newton solves many small dense systems; on a loaded 2-core machine BLAS
# threads fight over the cores and slow each solve 10-40x. One thread is the fast choice
# for these sizes (set before numpy is first imported).
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import importlib
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

from fretbem import registry as bases


@pytest.fixture(autouse=True)
def _fresh_assembly_budget():
    """Each test starts with no numpy assembly spent, so its own runs take one path.

    The automatic choice of assembly loops counts work across a process
    (fretbem.bem.integration); without this, two runs compared bit for bit in one test could
    straddle the switch depending on which tests ran before.
    """
    from fretbem.bem import integration

    integration.LOOP_CHOICE.reset()
    yield


@pytest.fixture
def patch_run(monkeypatch):
    """Replace fretbem.simulation.run everywhere it is bound (modules import it by name)."""
    import sys

    from fretbem import simulation

    def patch(fake):
        original = simulation.run
        for name, module in list(sys.modules.items()):
            if name.startswith("fretbem") and getattr(module, "run", None) is original:
                monkeypatch.setattr(module, "run", fake)

    return patch


# -- the example plugin package (examples/custom_basis), for any test folder ---------------

REPO = Path(__file__).resolve().parents[1]
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
