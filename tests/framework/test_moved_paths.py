"""The flat layout's old module paths: importable for one release, warning with the new
path, the same module object; ``python -m fretbem.cli`` still runs the command line."""

from __future__ import annotations

import importlib
import subprocess
import sys
import warnings

import pytest

from fretbem.compat.moved import MOVED


@pytest.mark.parametrize(("old", "new"), sorted(MOVED.items()))
def test_an_old_path_is_the_new_module_and_says_where_it_went(old, new):
    sys.modules.pop(old, None)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        module = importlib.import_module(old)
    assert module is importlib.import_module(new)
    assert any(
        issubclass(w.category, DeprecationWarning) and new in str(w.message) for w in caught
    ), [str(w.message) for w in caught]


def test_python_m_old_cli_path_runs_the_command_line():
    done = subprocess.run(
        [sys.executable, "-m", "fretbem.cli", "--version"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr
    assert "fretbem" in done.stdout + done.stderr
    assert "Traceback" not in done.stderr
