"""Old module paths of the flat layout, importable for one release.

``import fretbem.bem_body`` (say) imports :mod:`fretbem.bem.body`, warns once with the new path,
and binds the same module object under the old name, so attributes set through either path are
one and the same. The packages that took an old module's name (``fretbem.accuracy``,
``fretbem.contact``, ``fretbem.output``, ``fretbem.scenes``, ``fretbem.testing``,
``fretbem.studies.convergence``, ``fretbem.studies.sweep``) re-export its names instead.
The list is the changelog's (docs/changelog.md).
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import importlib.util
import sys
import warnings

#: old module path -> new module path
MOVED: dict[str, str] = {
    "fretbem._assembly": "fretbem.bem.assembly",
    "fretbem._blas": "fretbem.numerics.blas",
    "fretbem._compiled": "fretbem.bem.compiled_loops",
    "fretbem._newton_linear": "fretbem.solvers.newton_linear",
    "fretbem._numpy_loops": "fretbem.bem.numpy_loops",
    "fretbem._testing_contact": "fretbem.testing.contact",
    "fretbem._validators": "fretbem.validators",
    "fretbem.adaptive": "fretbem.accuracy.adaptive",
    "fretbem.adaptive_knots": "fretbem.accuracy.knots",
    "fretbem.adaptive_mesh": "fretbem.accuracy.remesh",
    "fretbem.analytical": "fretbem.verification.closed_forms",
    "fretbem.bases": "fretbem.registry",
    "fretbem.bem_body": "fretbem.bem.body",
    "fretbem.bem_layout": "fretbem.bem.layout",
    "fretbem.bem_system": "fretbem.bem.system",
    "fretbem.checks": "fretbem.verification.checks",
    "fretbem.cli": "fretbem.app.cli",
    "fretbem.condensation": "fretbem.contact.condensation",
    "fretbem.estimate": "fretbem.accuracy.estimate",
    "fretbem.integration": "fretbem.bem.integration",
    "fretbem.kernels": "fretbem.bem.kernels",
    "fretbem.law": "fretbem.contact.law",
    "fretbem.nowell_hills": "fretbem.verification.nowell_hills",
    "fretbem.plot": "fretbem.output.figures",
    "fretbem.quadrature": "fretbem.numerics.quadrature",
    "fretbem.report": "fretbem.contact.zones",
    "fretbem.resources": "fretbem.bem.resources",
    "fretbem.scene_build": "fretbem.scenes.builder",
    "fretbem.scene_file": "fretbem.scenes.file",
    "fretbem.scene_legacy": "fretbem.scenes.legacy",
    "fretbem.scene_spec": "fretbem.scenes.spec",
    "fretbem.shapes": "fretbem.geometry.shapes",
    "fretbem.solver": "fretbem.solvers.newton",
    "fretbem.studies.convergence_adaptive": "fretbem.studies.convergence.adaptive",
    "fretbem.studies.convergence_analysis": "fretbem.studies.convergence.analysis",
    "fretbem.studies.convergence_figures": "fretbem.studies.convergence.figures",
    "fretbem.studies.convergence_io": "fretbem.studies.convergence.io",
    "fretbem.studies.convergence_runs": "fretbem.studies.convergence.runs",
    "fretbem.studies.sweep_cases": "fretbem.studies.sweep.cases",
    "fretbem.studies.sweep_maps": "fretbem.studies.sweep.maps",
    "fretbem.studies.sweep_outputs": "fretbem.studies.sweep.outputs",
    "fretbem.studies.sweep_spec": "fretbem.studies.sweep.spec",
    "fretbem.studies.sweep_store": "fretbem.studies.sweep.store",
    "fretbem.unknowns": "fretbem.contact.unknowns",
    "fretbem.vtk_": "fretbem.output.vtk",
}


class _Alias(importlib.abc.Loader):
    """Loads an old path as the module at its new path."""

    def __init__(self, new: str) -> None:
        self.new = new

    def create_module(self, spec):
        warnings.warn(
            f"{spec.name} moved to {self.new}; the old path goes in the next release",
            DeprecationWarning,
            stacklevel=2,
        )
        return importlib.import_module(self.new)

    def exec_module(self, module) -> None:
        """The module at the new path is executed already."""

    def get_code(self, fullname: str):
        """The new module's code, for ``python -m <old path>`` (runpy runs it as __main__)."""
        warnings.warn(
            f"{fullname} moved to {self.new}; the old path goes in the next release",
            DeprecationWarning,
            stacklevel=2,
        )
        return importlib.util.find_spec(self.new).loader.get_code(self.new)

    def is_package(self, fullname: str) -> bool:
        """An old path names a module (runpy asks before running it)."""
        return False


class _MovedFinder(importlib.abc.MetaPathFinder):
    """Finds the old paths listed in :data:`MOVED`."""

    def find_spec(self, fullname, path=None, target=None):
        new = MOVED.get(fullname)
        if new is None:
            return None
        return importlib.machinery.ModuleSpec(fullname, _Alias(new))


def install() -> None:
    """Put the finder on ``sys.meta_path`` once."""
    if not any(isinstance(finder, _MovedFinder) for finder in sys.meta_path):
        sys.meta_path.append(_MovedFinder())
