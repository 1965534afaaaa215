"""What a contact simulation needs from an elastic body: the abstract :class:`Body`.

A body model (the BEM body of :mod:`fretbem.bem.body`, a half-plane, ...) only has to
give its discretised contact face and its displacement there as an affine function of the
face tractions, its loading-block displacement and its named loads (the
:class:`ContactResponse`); the contact condensation, the solvers and the results use
nothing else. docs/how-to/new-body-model.rst shows how to add one.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Mapping
from typing import Any

import attrs
import numpy as np

from fretbem.errors import InputError

from .conditions import LoadingBlock
from .material import Material


class RigidMotionError(InputError):
    """The boundary conditions leave a rigid-body motion of a body undetermined."""


@attrs.frozen(eq=False)
class ContactFace:
    """The nodes of a body's discretised contact face (collocation points for BEM).

    Attributes
    ----------
    points, normals : ndarray, shape (n, 2)
        Node positions and unit outward normals, in the body's own node order.
    """

    points: np.ndarray
    normals: np.ndarray

    @property
    def n_nodes(self) -> int:
        """Number of face nodes."""
        return len(self.points)


@attrs.frozen(eq=False)
class ContactResponse:
    """Displacement at the face nodes, affine in the face tractions, block and loads.

    With t (n, 2) the traction vector on this body at each face node (global x, y), delta
    the loading-block displacement (2,) and beta the load amplitudes (k,) in the order of
    ``Body.load_names``::

        u = base + traction_map @ t.ravel() + block_map @ delta + load_map @ beta
        R = r_base + r_traction @ t.ravel() + r_block @ delta + r_load @ beta

    R is the force the loading block applies to the body (zeros without a block).

    Attributes
    ----------
    base : ndarray, shape (n, 2)
    traction_map : ndarray, shape (n, 2, 2n)
        Column 2 a + j: unit traction component j at node a.
    block_map : ndarray, shape (n, 2, 2)
    load_map : ndarray, shape (n, 2, k)
    r_base : ndarray, shape (2,); r_traction : (2, 2n); r_block : (2, 2); r_load : (2, k)
    contact_force : ndarray, shape (2, 2n)
        Resultant force of the face tractions per unit node traction (the integral of the
        traction field over the face, for any body model).
    has_block : bool
        Whether the body carries a loading block (its delta is then an unknown).
    """

    base: np.ndarray
    traction_map: np.ndarray
    block_map: np.ndarray
    load_map: np.ndarray
    r_base: np.ndarray
    r_traction: np.ndarray
    r_block: np.ndarray
    r_load: np.ndarray
    contact_force: np.ndarray
    has_block: bool

    @property
    def n_nodes(self) -> int:
        """Number of face nodes."""
        return len(self.base)

    def displacement(self, tractions, block=(0.0, 0.0), loads=()) -> np.ndarray:
        """u (n, 2) at the face nodes for node tractions (n, 2), block delta and loads."""
        beta = np.asarray(loads, float).reshape(-1)
        return (
            self.base
            + self.traction_map @ np.asarray(tractions, float).ravel()
            + self.block_map @ np.asarray(block, float)
            + self.load_map @ beta
        )


class Body(ABC):
    """An elastic body seen by the contact: a face, its response and its fields.

    Implementations: :class:`fretbem.bem.body.BemBody` (finite body, boundary elements)
    and the half-plane body. ``check_body`` in :mod:`fretbem.testing` checks the contract.

    Attributes
    ----------
    name : str
    material : Material
    """

    name: str
    material: Material

    @property
    @abstractmethod
    def loading_block(self) -> LoadingBlock | None:
        """The rigid block through which the load history drives the body, if any."""

    @property
    def load_names(self) -> tuple[str, ...]:
        """History-driven scalar loads the body responds to (e.g. ``("bulk",)``)."""
        return ()

    @property
    def timings(self) -> dict[str, float]:
        """Wall times (s) of the work done so far (assembly, factorisation); may be empty."""
        return {}

    @property
    @abstractmethod
    def dofs(self) -> int:
        """Number of unknowns of the discretised body (reported in the run summary)."""

    def describe(self) -> dict[str, Any]:
        """Facts for the run summary (model, basis, degree); override to add more."""
        return {"model": type(self).__name__}

    @abstractmethod
    def contact_face(self, tag: str) -> ContactFace:
        """The nodes of the face ``tag`` (raises KeyError naming the tag if unknown)."""

    @abstractmethod
    def contact_response(self, tag: str) -> ContactResponse:
        """The face's displacement response (computed once and cached by the body).

        Raises :class:`RigidMotionError` if the body is not held once its face is in
        contact (a loading block counts as holding it).
        """

    @abstractmethod
    def solution(
        self, tag: str, tractions: np.ndarray, block: np.ndarray, loads: Mapping[str, float]
    ) -> Any:
        """The body's fields for face node tractions (n, 2), block delta (2,) and loads."""
