"""fretbem: 2D elastic frictional contact by the boundary element method.

The extension points and the run entry are importable from the top level, loaded on first
use (importing fretbem imports no plugin, matplotlib or pyvista)::

    from fretbem import Basis, Body, ContactPair, Solver, Simulation
"""

from __future__ import annotations

import importlib

__version__ = "0.1.0"

#: public name -> defining module (imported lazily by __getattr__)
_EXPORTS = {
    "Basis": "basis",
    "Refinement": "basis",
    "Body": "body",
    "ContactFace": "body",
    "ContactResponse": "body",
    "BemBody": "bem.body",
    "ContactPair": "contact.pairs",
    "NodeToNodePair": "contact.pairs",
    "Pairing": "contact.pairing",
    "CondensedContact": "contact.condensation",
    "ContactLaw": "contact.law",
    "CoulombFriction": "contact.law",
    "ContactState": "contact.law",
    "PairState": "contact.law",
    "PairUnknowns": "contact.unknowns",
    "KelvinKernel": "bem.kernels",
    "Material": "material",
    "Solver": "solvers.newton",
    "SemiSmoothNewton": "solvers.newton",
    "IncrementResult": "solvers.newton",
    "LoadStep": "simulation",
    "Simulation": "simulation",
    "run": "simulation",
    "run_scene": "pipeline",
    "RunResult": "pipeline",
}

__all__ = ["__version__", *_EXPORTS]

# Old flat module paths (fretbem.bem_body, fretbem.solver, ...) import for one release,
# with a DeprecationWarning naming the new path.
from .compat import moved as _moved  # noqa: E402

_moved.install()


def __getattr__(name: str):
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'fretbem' has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(__all__)
