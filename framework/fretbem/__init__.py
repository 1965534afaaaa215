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
    "BemBody": "bem_body",
    "ContactPair": "contact",
    "NodeToNodePair": "contact",
    "Pairing": "contact",
    "CondensedContact": "condensation",
    "ContactLaw": "law",
    "CoulombFriction": "law",
    "ContactState": "law",
    "PairState": "law",
    "PairUnknowns": "unknowns",
    "KelvinKernel": "kernels",
    "Material": "material",
    "Solver": "solver",
    "SemiSmoothNewton": "solver",
    "IncrementResult": "solver",
    "LoadStep": "simulation",
    "Simulation": "simulation",
    "run": "simulation",
}

__all__ = ["__version__", *_EXPORTS]


def __getattr__(name: str):
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'fretbem' has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(__all__)
