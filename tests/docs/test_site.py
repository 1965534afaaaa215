"""The documentation site: API pages cover every module, docstrings read as rST, and
the whole site builds with warnings as errors (the CI's docs build)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

DOCS = Path(__file__).resolve().parents[2] / "docs"


def _extension(name: str):
    spec = importlib.util.spec_from_file_location(name, DOCS / "sphinxext" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_api_pages_cover_every_public_module(tmp_path):
    """One page per public module (new modules included), each on the index page."""
    api = _extension("fretbem_api")
    modules = api.generate(tmp_path)
    required = {
        f"fretbem.{name}"
        for name in (
            "registry basis body conditions errors contact contact.pairs solvers.newton "
            "simulation results scenes scenes.file verification.closed_forms geometry.nurbs "
            "geometry.knots geometry.boundary bem.integration bem.kernels numerics.quadrature "
            "material output.figures output.vtk testing app.cli"
        ).split()
    } | {"fretbem_nurbs.basis", "fretbem_lagrange.quadratic"}
    assert required <= set(modules)
    index = (tmp_path / "index.rst").read_text()
    for name in modules:
        assert f"   {name}\n" in index, name
        assert f".. automodule:: {name}" in (tmp_path / f"{name}.rst").read_text()


def test_plain_text_docstrings_become_rst():
    """|x| is escaped outside literals; 'text:' + indented formula becomes a literal block."""
    api = _extension("fretbem_api")
    lines = ["a ``|x|`` and |y|", "conditions:", "    F = |p|", "with p.", "code::", "", "    |z|"]
    assert api.plain_text_docstring(lines) == [
        r"a ``|x|`` and \|y\|",
        "conditions::",
        "",
        "    F = |p|",
        "",
        "with p.",
        "code::",
        "",
        "    |z|",
    ]


def test_site_builds_with_warnings_as_errors(cubic_plugin, site_build):
    """python -m sphinx -W -b html docs ... (runs every gallery script; a minute or more). The
    build starts in the background when this test is collected (tests/docs/conftest.py), and
    the test runs last."""
    code, stdout, stderr, html = site_build
    assert code == 0, stdout[-3000:] + stderr[-3000:]
    for page in ("index.html", "auto_tutorials/index.html", "api/fretbem.body.html", "cli.html"):
        assert (html / page).is_file(), page
