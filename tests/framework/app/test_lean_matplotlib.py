"""matplotlib in the console script's process: no property tables in docstrings and no
property lists in set() signatures, every set() as matplotlib's in what it does (each case
in a fresh interpreter: matplotlib imports once)."""

import json
import subprocess
import sys

import pytest

#: the console script's main() on `fretbem bases`, then matplotlib as the figures import it
CONSOLE = """
import inspect, json, sys
sys.argv = ["fretbem", "bases"]
from fretbem.app import cli
code = cli.main(ARGV)
import matplotlib.artist, matplotlib.figure, matplotlib.lines
from fretbem.app import lean_matplotlib
line = matplotlib.lines.Line2D

class Mine(line):  # a subclass made after the import makes its own set() too
    pass

drawn = Mine([0, 1], [0, 1])
drawn.set(lw=3.5, color="r", linestyle="--", markerfacecolor="b")
print(json.dumps({
    "code": code,
    "noted": lean_matplotlib.NOTE in line.set.__doc__,
    "table": "    linestyle: " in line.set.__doc__,
    "base_table": "zorder: float" in matplotlib.artist.Artist.set.__doc__,
    "signature": sorted(inspect.signature(line.set).parameters),
    "own_set": [c.set.__qualname__ for c in (line, Mine, matplotlib.artist.Artist)],
    "set": [drawn.get_linewidth(), drawn.get_color(), drawn.get_linestyle(),
            drawn.get_markerfacecolor()],
    "finder_left": any(type(f).__name__ == "_Finder" for f in sys.meta_path),
}))
"""


def _console(argv: str) -> dict:
    done = subprocess.run(
        [sys.executable, "-c", CONSOLE.replace("ARGV", argv)],
        capture_output=True, text=True, check=True, timeout=120,
    )  # fmt: skip
    return json.loads(done.stdout.splitlines()[-1])


def test_console_script_skips_the_tables_only():
    """main() as the console script calls it (no argv): Line2D.set's docstring has the note
    instead of its property table and its signature no property list; each class still
    has its own set(), which sets properties and aliases as in a plain session; the finder
    is gone once it has found the module."""
    console, session = _console("None"), _console('["bases"]')
    assert console["code"] == session["code"] == 0
    assert console["noted"] and not console["table"]
    assert session["table"] and not session["noted"]  # main(argv): matplotlib untouched
    assert console["signature"] == ["kwargs", "self"]
    assert {"self", "color", "linestyle", "zorder"} <= set(session["signature"])
    assert console["own_set"] == session["own_set"] == ["Line2D.set", "Mine.set", "Artist.set"]
    assert console["set"] == session["set"] == [3.5, "r", "--", "b"]
    assert console["base_table"]  # Artist's own, made with the module before the swap
    assert not console["finder_left"] and not session["finder_left"]


def test_install_after_matplotlib_changes_nothing():
    """A process that imported matplotlib first keeps its kwdoc and gets no finder."""
    import matplotlib.artist

    from fretbem.app import lean_matplotlib

    kwdoc = matplotlib.artist.kwdoc
    lean_matplotlib.install()
    try:
        assert matplotlib.artist.kwdoc is kwdoc
        assert lean_matplotlib._FINDER not in sys.meta_path
    finally:
        lean_matplotlib._remove()


@pytest.mark.parametrize("name", ["matplotlib", "matplotlib.artistic", "numpy.artist"])
def test_finder_passes_other_modules_on(name):
    """The finder answers for matplotlib.artist only."""
    from fretbem.app import lean_matplotlib

    assert lean_matplotlib._FINDER.find_spec(name, None) is None
