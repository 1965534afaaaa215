"""The package's shape: few modules at the root, no import circles, layers depending downward only.

Every import counts: at module level, inside functions and for type hints only. The layer
order is the one the design page draws (docs/explanation/design.rst).
"""

from __future__ import annotations

import ast
import functools
import subprocess
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[2] / "framework" / "fretbem"

#: lowest first; a module may import its own layer or any lower one
LAYERS = (
    ("errors", "validators", "numerics", "compat"),
    ("geometry", "material"),
    ("conditions", "basis", "registry"),
    ("body",),
    ("bem", "halfplane"),
    ("contact",),
    ("solvers",),
    ("verification",),
    ("views",),
    ("results", "simulation"),
    ("fretting",),
    ("scenes", "sliding"),
    ("accuracy",),
    ("stress",),
    ("fatigue",),
    ("wear",),
    ("output",),
    ("pipeline",),
    ("studies",),
    ("app",),
    ("testing",),
)
LAYER = {name: rank for rank, names in enumerate(LAYERS) for name in names}
#: third-party packages slow to import: the only imports allowed inside functions
HEAVY = {
    "matplotlib", "pyvista", "dask", "distributed", "numba", "pandas", "pyarrow", "xarray",
    "vtk", "scipy", "tqdm", "rich", "pint", "netCDF4", "h5netcdf", "selenium", "playwright",
}  # fmt: skip


def _modules() -> dict[str, Path]:
    out = {}
    for path in PACKAGE.rglob("*.py"):
        parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        out[".".join(parts)] = path
    return out


MODULES = _modules()


@functools.cache
def _tree(path: Path) -> ast.Module:
    """A module's syntax tree, parsed once for all the tests here (they only read it)."""
    return ast.parse(path.read_text(encoding="utf-8"))


def _imports(name: str, path: Path):
    """(target module, line) for every import of a module, fretbem targets resolved to a file."""
    tree = _tree(path)
    package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[: len(package) - node.level + 1]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module or ""
            targets = [module] + [f"{module}.{a.name}" for a in node.names]
        else:
            continue
        for target in targets:
            while target and target not in MODULES and target.split(".")[0] == "fretbem":
                target = target.rpartition(".")[0]
            yield target, node.lineno


def _targets(name: str, path: Path, node: ast.AST) -> list[str]:
    """Modules one import statement loads (fretbem modules resolved to their file)."""
    if isinstance(node, ast.Import):
        return [a.name for a in node.names]
    package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
    if node.level:
        base = package[: len(package) - node.level + 1]
        module = ".".join(base + ([node.module] if node.module else []))
    else:
        module = node.module or ""
    out = []
    for alias in node.names:
        full = f"{module}.{alias.name}"
        out.append(full if full in MODULES else module)
    return out


def _graph() -> dict[str, set[str]]:
    graph = {}
    for name, path in MODULES.items():
        deps = {t for t, _ in _imports(name, path) if t in MODULES and t != name}
        # a package re-exporting its children, or a child importing its package, is no circle
        graph[name] = {
            d for d in deps if not d.startswith(name + ".") and not name.startswith(d + ".")
        }
    return graph


def _layer(module: str) -> int | None:
    parts = module.split(".")
    return LAYER.get(parts[1]) if len(parts) > 1 else None


def test_few_modules_at_the_package_root():
    root = sorted(p.stem for p in PACKAGE.glob("*.py") if p.name != "__init__.py")
    assert len(root) <= 12, root


def test_no_import_circles():
    graph, index, low, stack, on, circles = _graph(), {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            group = []
            while True:
                w = stack.pop()
                on.discard(w)
                group.append(w)
                if w == v:
                    break
            if len(group) > 1:
                circles.append(sorted(group))

    for v in graph:
        if v not in index:
            visit(v)
    assert circles == []


def test_every_folder_and_root_module_has_a_layer():
    top = {m.split(".")[1] for m in MODULES if m.count(".") >= 1}
    assert top <= set(LAYER), sorted(top - set(LAYER))


def test_layers_depend_downward_only():
    climbing = []
    for name, path in MODULES.items():
        own = _layer(name)
        for target, line in _imports(name, path):
            theirs = _layer(target) if target in MODULES else None
            if own is not None and theirs is not None and theirs > own:
                climbing.append(f"{name}:{line} -> {target}")
    assert climbing == []


def _heavy_modules() -> set[str]:
    """fretbem modules that import a heavy package when they load (numba kernels, figures)."""
    heavy = set()
    for name, path in MODULES.items():
        for node in _tree(path).body:
            if isinstance(node, ast.Import):
                roots = [a.name.split(".")[0] for a in node.names]
            elif isinstance(node, ast.ImportFrom) and not node.level:
                roots = [(node.module or "").split(".")[0]]
            else:
                continue
            if set(roots) & HEAVY - {"scipy"}:
                heavy.add(name)
    return heavy


def test_imports_inside_functions_only_for_heavy_packages():
    """Deferred imports only where loading costs: a heavy package, or a module that loads one."""
    heavy, found = _heavy_modules(), []
    for name, path in MODULES.items():
        tree = _tree(path)
        for function in ast.walk(tree):
            if not isinstance(function, (ast.FunctionDef, ast.AsyncFunctionDef)):
                continue
            for node in ast.walk(function):
                if not isinstance(node, (ast.Import, ast.ImportFrom)):
                    continue
                targets = _targets(name, path, node)
                bad = [t for t in targets if t.split(".")[0] not in HEAVY and t not in heavy]
                if bad:
                    found.append(f"{name}:{node.lineno} imports {bad} inside {function.name}")
    assert found == []


@pytest.fixture(scope="module")
def run_path_modules() -> set[str]:
    """The modules a fresh process holds after importing the run path (one process for all
    the packages checked below)."""
    code = (
        "import sys, fretbem.simulation, fretbem.scenes.builder, fretbem.contact.pairs\n"
        "print('\\n'.join(sys.modules))\n"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    modules = set(result.stdout.split())
    assert {"numpy", "fretbem.simulation"} <= modules  # the list is the process's own
    return modules


@pytest.mark.parametrize("module", ["matplotlib", "pyvista", "dask", "numba", "pandas"])
def test_heavy_packages_are_not_imported_with_the_run_path(module, run_path_modules):
    assert module not in run_path_modules, "imported"
