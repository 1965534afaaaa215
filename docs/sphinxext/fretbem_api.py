"""Generate the API reference pages: one page per public module, grouped on an index page.

Modules are discovered by walking the ``fretbem`` package and the built-in family plugins,
so a new module gets its page without editing the docs. The groups are the package's
folders (each titled by its package docstring), in the order of the layers; nothing is kept
by hand per module. Pages are written to ``docs/api/`` when the builder starts, and autodoc
fills them from the docstrings.
"""

from __future__ import annotations

import importlib
import pkgutil
import re
from pathlib import Path

import attrs

#: packages whose modules are documented (the built-in families are plugins, see pyproject)
PACKAGES = ("fretbem", "fretbem_nurbs", "fretbem_lagrange")

#: the order of the groups on the index page: the layers of the package, lowest first
#: (a folder not listed here still gets its group, at the end: nothing is hand-kept per module)
LAYERS = (
    "numerics", "geometry", "bem", "halfplane", "contact", "solvers", "verification",
    "views", "fretting", "scenes", "sliding", "accuracy", "stress", "fatigue", "wear", "output",
    "studies", "app", "testing", "compat",
)  # fmt: skip


def _summary(name: str) -> str:
    """First line of a module's docstring (the group title of a package)."""
    doc = (importlib.import_module(name).__doc__ or name).strip().splitlines()[0]
    return doc.rstrip(".")


def groups(modules: list[str]) -> dict[str, list[str]]:
    """Group title -> modules: the package root, then one group per folder, then plugins."""

    def at_root(m: str) -> bool:
        is_package = hasattr(importlib.import_module(m), "__path__")
        return m == "fretbem" or (m.startswith("fretbem.") and m.count(".") == 1 and not is_package)

    root = [m for m in modules if at_root(m)]
    out = {"The package root: extension points and the run's vocabulary": root}
    folders = sorted(
        {m.split(".")[1] for m in modules if m.startswith("fretbem.") and m not in root},
        key=lambda f: (LAYERS.index(f) if f in LAYERS else len(LAYERS), f),
    )
    for folder in folders:
        package = f"fretbem.{folder}"
        members = [m for m in modules if m == package or m.startswith(package + ".")]
        out[f"``{package}``: {_summary(package)}"] = members
    out["Basis families (plugins)"] = [m for m in modules if m.split(".")[0] != "fretbem"]
    return out


INTRO = """\
API reference
=============

Every public module of ``fretbem`` and of the two built-in basis families, from the
docstrings. The pieces a script uses most are :class:`fretbem.body.Body`,
:class:`fretbem.contact.pairs.ContactPair`, :class:`fretbem.simulation.Simulation` with
:func:`fretbem.simulation.run`, and :class:`fretbem.basis.Basis` for a new element type.
"""


def public_modules() -> list[str]:
    """Names of every importable public module of :data:`PACKAGES` (no ``_private`` parts)."""
    names = []
    for package in PACKAGES:
        module = importlib.import_module(package)
        names.append(package)
        if hasattr(module, "__path__"):
            for info in pkgutil.walk_packages(module.__path__, f"{package}."):
                if not any(part.startswith("_") for part in info.name.split(".")):
                    names.append(info.name)
    return sorted(set(names))


def described_fields(module) -> list[str]:
    """attrs fields that their class docstring describes, safe to leave out of the listing.

    attrs records are slotted, so autodoc would list every field a second time, bare, under
    the "Attributes" table of the class docstring. A name that is also another member of
    some class or of the module is kept (``exclude-members`` applies to all of them).
    """
    classes = [
        obj
        for obj in vars(module).values()
        if isinstance(obj, type) and obj.__module__ == module.__name__
    ]
    fields, others = set(), {n for n in vars(module) if not n.startswith("_")}
    for cls in classes:
        names = {f.name for f in attrs.fields(cls)} if attrs.has(cls) else set()
        text = cls.__doc__ or ""
        fields |= {n for n in names if re.search(rf"\b{re.escape(n)}\b", text)}
        others |= {n for n in vars(cls) if n not in names}
    return sorted(fields - others)


def _page(name: str) -> str:
    module = importlib.import_module(name)
    title = f"``{name}``"
    if hasattr(module, "__path__"):
        options = "   :no-members:\n"
    else:
        excluded = described_fields(module)
        options = f"   :exclude-members: {', '.join(excluded)}\n" if excluded else ""
    return f"{title}\n{'=' * len(title)}\n\n.. automodule:: {name}\n{options}"


def _write(path: Path, text: str) -> None:
    """Write only on change, so Sphinx does not re-read unchanged pages."""
    if not path.exists() or path.read_text() != text:
        path.write_text(text)


def generate(folder: Path) -> list[str]:
    """Write ``index.rst`` and one page per module into ``folder``; returns the modules."""
    folder.mkdir(parents=True, exist_ok=True)
    modules = public_modules()
    grouped = groups(modules)
    lines = [INTRO]
    for group, members in grouped.items():
        if not members:
            continue
        lines += [f"\n{group}\n{'-' * len(group)}\n", ".. toctree::", "   :maxdepth: 1", ""]
        lines += [f"   {m}" for m in members]
    _write(folder / "index.rst", "\n".join(lines) + "\n")
    for name in modules:
        _write(folder / f"{name}.rst", _page(name))
    for stale in folder.glob("*.rst"):
        if stale.stem not in modules and stale.name != "index.rst":
            stale.unlink()
    return modules


def _indent(line: str) -> int:
    return len(line) - len(line.lstrip())


_LITERAL = re.compile(r"(``.*?``)")


def _escape_bars(line: str) -> str:
    """``|x|`` in prose is plain text in the docstrings, not a substitution: escape it."""
    parts = _LITERAL.split(line)
    return "".join(p if p.startswith("``") else p.replace("|", r"\|") for p in parts)


def plain_text_docstring(lines: list[str]) -> list[str]:
    """Read plain-text conventions of the docstrings as reStructuredText.

    The docstrings are written to be read as text: ``|x|`` means an absolute value, and a
    line ending in ``:`` directly followed by an indented formula displays that formula.
    In reStructuredText the first is a substitution and the second a definition list, so
    bars are escaped (outside inline literals and literal blocks) and such formulas
    become literal blocks.
    """
    out: list[str] = []
    literal_indent: int | None = None  # indentation of the paragraph owning a literal block
    k = 0
    while k < len(lines):
        line = lines[k]
        if literal_indent is not None:
            if line.strip() and _indent(line) <= literal_indent:
                literal_indent = None
                if out and out[-1].strip():
                    out.append("")
            else:
                out.append(line)
                k += 1
                continue
        following = lines[k + 1] if k + 1 < len(lines) else ""
        starts_block = line.rstrip().endswith(":") and not line.strip().startswith(":")
        if starts_block and following.strip() and _indent(following) > _indent(line):
            text = _escape_bars(line.rstrip())
            out += [text if text.endswith("::") else text + ":", ""]
            literal_indent = _indent(line)
        elif line.rstrip().endswith("::"):
            out.append(_escape_bars(line))
            literal_indent = _indent(line)
        else:
            out.append(_escape_bars(line))
        k += 1
    return out


def _process_docstring(app, what, name, obj, options, lines) -> None:
    lines[:] = plain_text_docstring(lines)


def _builder_inited(app) -> None:
    generate(Path(app.srcdir) / "api")


def setup(app):
    app.connect("builder-inited", _builder_inited)
    # before numpydoc's handler (priority 500), which turns numpy sections into rST
    app.connect("autodoc-process-docstring", _process_docstring, priority=400)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
